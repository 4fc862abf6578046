//! The voxel set as runs along x: for each row `(y, z)` of the slab (z
//! outer, y inner), the maximal runs of surface voxels and of interior
//! voxels, in increasing x. Outside voxels are not listed.

use super::grid::VoxelGrid;
use super::VoxelClass;
use crate::error::Error;

/// One run: voxels `x0 .. x1` (exclusive) of row `(y, z)`, all of class
/// `class` (1 surface, 2 interior: [`VoxelClass`] as u32).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct VoxelRun {
    /// First voxel.
    pub x0: u32,
    /// One past the last voxel.
    pub x1: u32,
    /// Row y.
    pub y: u32,
    /// Row z.
    pub z: u32,
    /// 1 = surface, 2 = interior.
    pub class: u32,
}

impl VoxelGrid<'_> {
    /// Calls `f` with every run of the slab, in order.
    fn for_each_run(&self, mut f: impl FnMut(VoxelRun)) {
        let (r0, r1) = self.slab_rows();
        let m2 = self.shape.res[1] as usize;
        let wpr = self.shape.wpr;
        for r in r0..r1 {
            let y = ((r - r0) % m2) as u32;
            let z = self.shape.z0 + ((r - r0) / m2) as u32;
            // Merge the two planes' runs in x order.
            let row_s = &self.surface[r * wpr..(r + 1) * wpr];
            let row_i = &self.interior[r * wpr..(r + 1) * wpr];
            let mut x = 0usize;
            let m1 = self.shape.res[0] as usize;
            while x < m1 {
                let w = x / 64;
                let b = x % 64;
                let s = row_s[w] >> b;
                let i = row_i[w] >> b;
                if s & 1 == 0 && i & 1 == 0 {
                    // Skip to the next set bit of either plane.
                    let any = s | i;
                    if any == 0 {
                        x = (w + 1) * 64;
                    } else {
                        x += any.trailing_zeros() as usize;
                    }
                    continue;
                }
                let (plane, class) = if s & 1 != 0 {
                    (row_s, VoxelClass::Surface)
                } else {
                    (row_i, VoxelClass::Interior)
                };
                let start = x;
                loop {
                    let w = x / 64;
                    let b = x % 64;
                    let ones = (!(plane[w] >> b)).trailing_zeros() as usize;
                    let ones = ones.min(64 - b);
                    x += ones;
                    if ones < 64 - b || x >= m1 {
                        break;
                    }
                }
                let x1 = x.min(m1);
                f(VoxelRun {
                    x0: start as u32,
                    x1: x1 as u32,
                    y,
                    z,
                    class: class as u32,
                });
                x = x1;
            }
        }
    }

    /// Number of runs [`VoxelGrid::write_runs`] writes.
    pub fn run_count(&self) -> usize {
        let mut n = 0usize;
        self.for_each_run(|_| n += 1);
        n
    }

    /// Writes the runs of the slab into `out` and returns their number.
    /// Errors: `BufferTooSmall { required }` (runs) if `out` is too short;
    /// nothing is written then.
    pub fn write_runs(&self, out: &mut [VoxelRun]) -> Result<usize, Error> {
        let required = self.run_count();
        if out.len() < required {
            return Err(Error::BufferTooSmall { required });
        }
        let mut n = 0usize;
        self.for_each_run(|r| {
            out[n] = r;
            n += 1;
        });
        Ok(n)
    }
}
