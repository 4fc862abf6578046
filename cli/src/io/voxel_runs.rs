//! Writing a voxel grid as text runs: lines `z y x0 x1 class` (x1
//! exclusive; class 1 surface, 2 interior), after one `#` header line.

use crate::error::{CliError, CliResult};
use crate::io::slab_bits::{bit, SlabBits};
use std::path::Path;

/// Writes the runs of `slabs` (interior ones only with `fill`).
pub fn write_runs(path: &Path, slabs: &[SlabBits], res: u32, fill: bool) -> CliResult {
    let mut out = String::new();
    out.push_str(&format!(
        "# ccss voxel runs: res {res} {res} {res}; lines 'z y x0 x1 class' (x1 exclusive; class 1 surface, 2 interior)\n"
    ));
    for s in slabs {
        for z in s.z0..s.z1 {
            for y in 0..res {
                let mut x = 0;
                while x < res {
                    let sb = bit(s, res, x, y, z, false);
                    let ib = fill && !sb && bit(s, res, x, y, z, true);
                    if !sb && !ib {
                        x += 1;
                        continue;
                    }
                    let class = if sb { 1 } else { 2 };
                    let x0 = x;
                    while x < res {
                        let s2 = bit(s, res, x, y, z, false);
                        let i2 = fill && !s2 && bit(s, res, x, y, z, true);
                        if (class == 1 && !s2) || (class == 2 && !i2) {
                            break;
                        }
                        x += 1;
                    }
                    out.push_str(&format!("{z} {y} {x0} {x} {class}\n"));
                }
            }
        }
    }
    std::fs::write(path, out)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}
