//! Writing a voxel grid as binvox: the header (dim, translate, scale) and
//! the voxels in binvox order (x slowest, then z, then y fastest), run-length
//! coded as (value, count <= 255) byte pairs.

use crate::error::{CliError, CliResult};
use crate::io::slab_bits::SlabBits;
use ccss_core::voxel::VoxelTransform;
use std::io::Write;
use std::path::Path;

/// Writes the binvox file (x slowest, then z, then y; RLE pairs).
pub fn write_binvox(
    path: &Path,
    slabs: &[SlabBits],
    res: u32,
    t: &VoxelTransform,
    fill: bool,
) -> CliResult {
    let n = res as usize;
    // Transpose into binvox order: bit index x*n*n + z*n + y.
    let mut bits = vec![0u64; (n * n * n).div_ceil(64)];
    for s in slabs {
        for z in s.z0..s.z1 {
            for y in 0..res {
                let r = ((z - s.z0) * res + y) as usize * s.wpr;
                for w in 0..s.wpr {
                    let mut word = s.surface[r + w] | if fill { s.interior[r + w] } else { 0 };
                    while word != 0 {
                        let x = w * 64 + word.trailing_zeros() as usize;
                        word &= word - 1;
                        let i = x * n * n + z as usize * n + y as usize;
                        bits[i / 64] |= 1u64 << (i % 64);
                    }
                }
            }
        }
    }
    let scale = n as f64 / t.scale;
    let tr = t.offset.map(|o| (-0.5 - o) / t.scale);
    let mut out = Vec::new();
    let _ = write!(
        out,
        "#binvox 1\ndim {n} {n} {n}\ntranslate {} {} {}\nscale {}\ndata\n",
        tr[0], tr[1], tr[2], scale
    );
    // RLE pairs (value, count <= 255); run ends found a word at a time.
    let total = n * n * n;
    let mut i = 0usize;
    while i < total {
        let v = bits[i / 64] >> (i % 64) & 1;
        let mut j = i;
        while j < total {
            let (w, b) = (j / 64, j % 64);
            // Ones where the bit differs from v (padding past `total` is 0).
            let differ = if v == 1 { !bits[w] } else { bits[w] } >> b;
            if differ != 0 {
                j += differ.trailing_zeros() as usize;
                break;
            }
            j = (w + 1) * 64;
        }
        let mut len = j.min(total) - i;
        i += len;
        while len > 0 {
            let c = len.min(255);
            out.push(v as u8);
            out.push(c as u8);
            len -= c;
        }
    }
    std::fs::write(path, out)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}
