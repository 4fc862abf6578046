//! The `--preview` image of `ccss voxelize`: a montage of z-slices of the
//! voxel grid, written as PNG.

use crate::error::{CliError, CliResult};
use crate::io::png::png_rgb;
use crate::io::slab_bits::{bit, SlabBits};
use std::path::Path;

/// A 4 x 4 montage of z-slices (surface dark red, interior grey, outside
/// white), each slice at most 256 pixels wide.
pub fn write_preview(path: &Path, slabs: &[SlabBits], res: u32, fill: bool) -> CliResult {
    let tiles = 16u32.min(res);
    let cols = 4u32;
    let rows = tiles.div_ceil(cols);
    let step = res.div_ceil(256).max(1);
    let tw = res.div_ceil(step);
    let gap = 4u32;
    let (w, h) = (cols * (tw + gap) + gap, rows * (tw + gap) + gap);
    let mut img = vec![60u8; (w * h * 3) as usize];
    for t in 0..tiles {
        let z = ((t as u64 * 2 + 1) * res as u64 / (tiles as u64 * 2)) as u32;
        let Some(s) = slabs.iter().find(|s| z >= s.z0 && z < s.z1) else {
            continue;
        };
        let (ox, oy) = (gap + (t % cols) * (tw + gap), gap + (t / cols) * (tw + gap));
        for py in 0..tw {
            for px in 0..tw {
                let (x, y) = (px * step, res - 1 - (py * step).min(res - 1));
                let c = if bit(s, res, x, y, z, false) {
                    [150, 20, 20]
                } else if bit(s, res, x, y, z, true) {
                    if fill {
                        [170, 170, 170]
                    } else {
                        [235, 235, 235]
                    }
                } else {
                    [255, 255, 255]
                };
                let i = (((oy + py) * w + ox + px) * 3) as usize;
                img[i..i + 3].copy_from_slice(&c);
            }
        }
    }
    std::fs::write(path, png_rgb(w, h, &img)?)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}
