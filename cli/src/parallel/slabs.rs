//! Voxelization of the z-slabs of a grid on all cores: each slab is
//! voxelized (and optionally classified) in its own slab grid, which gives
//! exactly the voxels of the whole grid (see `ccss_core::voxel::rasterize`).

use crate::mem::words;
use crate::progress::Progress;
use ccss_core::voxel::{RasterStats, Surface, VoxelGrid, VoxelParams, VoxelTransform, VoxelWork};
use rayon::prelude::*;

/// Voxelizes (and, with `flood`, classifies) the z-slabs `cuts` in
/// parallel; `each` is called on every finished slab grid (in slab order
/// per thread) and its results are collected; `progress` counts the
/// finished slabs.
pub fn run_slabs<S: Surface + Sync + ?Sized, R: Send>(
    ev: &S,
    params: &VoxelParams,
    t: VoxelTransform,
    cuts: &[u32],
    flood: bool,
    progress: Option<&Progress>,
    each: impl Fn(&VoxelGrid, RasterStats) -> R + Sync,
) -> Result<Vec<R>, ccss_core::Error> {
    cuts.par_windows(2)
        .map(|w| {
            let (z0, z1) = (w[0], w[1]);
            let need = VoxelGrid::slab_required_bytes(params.res, z0, z1)?;
            let mut mem = words(need);
            let mut grid = VoxelGrid::new_slab(params.res, z0, z1, &mut mem)?;
            let mut work = Box::new(VoxelWork::ZERO);
            let st = grid.voxelize(ev, params, Some(t), &mut work)?;
            if flood {
                let rows = params.res[1] as usize * (z1 - z0) as usize;
                let mut stack = vec![0u32; rows.clamp(1, 1 << 20)];
                grid.flood(ev, &mut stack, &mut work)?;
            }
            if let Some(p) = progress {
                p.inc();
            }
            Ok(each(&grid, st))
        })
        .collect()
}

/// Slab boundaries for `threads` workers: about four slabs per thread, at
/// least 8 layers each.
pub fn cuts(m3: u32, threads: usize) -> Vec<u32> {
    let n = ((threads * 4) as u32).clamp(1, (m3 / 8).max(1));
    (0..=n)
        .map(|i| (m3 as u64 * i as u64 / n as u64) as u32)
        .collect()
}
