//! The cubic frame buffer: bit planes in caller memory.
//!
//! A grid of resolution `M1 x M2 x M3` stores voxel `(i, j, k)` (x, y, z) as
//! bit `i % 64` of word `i / 64` of row `(j, k)`: rows run along x, each
//! `ceil(M1 / 64)` 64-bit words, and row `(j, k)` is row number
//! `(k - z_lo) * M2 + j`. There are three planes of one bit per voxel:
//!
//! * **surface** — black voxels written by the voxelizer;
//! * **interior** — white voxels whose centre the flood classified inside
//!   (also used by the voxelizer's certification pass as scratch);
//! * **work** — the flood's "gray" plane (outside voxels reached so far; its
//!   content after a flood is unspecified) and the voxelizer's list of voxels
//!   its certification still has to see.
//!
//! plus one bit per row (the flood's "row is dirty" set). Outside voxels are
//! those in neither the surface nor the interior plane.
//!
//! A **slab** grid holds only the z-layers `[z0, z1)` of interest plus a
//! margin of [`SLAB_MARGIN`] layers on each side (clipped to the grid), so
//! that its memory is proportional to the slab; the voxelizer then produces
//! exactly the surface voxels of those layers that the whole grid would
//! have (see [`super::rasterize`]). The full grid is the slab `[0, M3)`.

use super::{VoxelClass, VoxelTransform};
use crate::error::Error;
use crate::mem::{bytes_of, words_for};

/// Layers a slab grid keeps beyond each end of its slab.
pub const SLAB_MARGIN: u32 = 3;

/// Largest resolution per axis.
pub const MAX_RESOLUTION: u32 = 1 << 16;

/// Surface and interior voxel counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VoxelCounts {
    /// Surface (black) voxels.
    pub surface: u64,
    /// Interior voxels (after flooding).
    pub interior: u64,
}

/// What has been done to a grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridState {
    /// Cleared; nothing voxelized.
    Empty,
    /// Surface voxels written.
    Voxelized,
    /// Surface voxels written and inside/outside classified.
    Flooded,
}

/// Geometry of a grid: resolution, held layers, row length.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub res: [u32; 3],
    /// Slab of interest.
    pub z0: u32,
    pub z1: u32,
    /// Layers held in memory (slab plus margins).
    pub zlo: u32,
    pub zhi: u32,
    /// Words per row.
    pub wpr: usize,
    /// Rows held.
    pub rows: usize,
}

impl Shape {
    fn new(res: [u32; 3], z0: u32, z1: u32) -> Result<Shape, Error> {
        if res.iter().any(|&m| !(2..=MAX_RESOLUTION).contains(&m)) {
            return Err(Error::InvalidArgument(
                "voxel resolution must be in 2..=65536 per axis",
            ));
        }
        if z0 >= z1 || z1 > res[2] {
            return Err(Error::InvalidArgument(
                "slab must satisfy z0 < z1 <= resolution z",
            ));
        }
        let zlo = z0.saturating_sub(SLAB_MARGIN);
        let zhi = (z1 + SLAB_MARGIN).min(res[2]);
        let wpr = (res[0] as usize).div_ceil(64);
        let rows = (res[1] as usize)
            .checked_mul((zhi - zlo) as usize)
            .ok_or(Error::InvalidArgument("voxel grid too large"))?;
        if rows > u32::MAX as usize {
            return Err(Error::InvalidArgument("voxel grid too large"));
        }
        Ok(Shape {
            res,
            z0,
            z1,
            zlo,
            zhi,
            wpr,
            rows,
        })
    }

    /// Words of one plane, words of the row bitmap.
    fn words(&self) -> Result<(usize, usize), Error> {
        let plane = self
            .rows
            .checked_mul(self.wpr)
            .ok_or(Error::InvalidArgument("voxel grid too large"))?;
        Ok((plane, self.rows.div_ceil(64)))
    }

    fn bytes(&self) -> Result<usize, Error> {
        let (p, r) = self.words()?;
        p.checked_mul(3)
            .and_then(|x| x.checked_add(r))
            .and_then(|x| x.checked_mul(8))
            .filter(|&b| b <= isize::MAX as usize)
            .ok_or(Error::InvalidArgument("voxel grid too large"))
    }

    /// Row number of `(j, k)` if layer `k` is held.
    #[inline]
    pub fn row(&self, j: u32, k: u32) -> Option<usize> {
        if j < self.res[1] && k >= self.zlo && k < self.zhi {
            Some((k - self.zlo) as usize * self.res[1] as usize + j as usize)
        } else {
            None
        }
    }

    /// Mask of valid bits of word `w` of a row.
    #[inline]
    pub fn valid(&self, w: usize) -> u64 {
        let m1 = self.res[0] as usize;
        let lo = w * 64;
        if lo + 64 <= m1 {
            !0
        } else if lo >= m1 {
            0
        } else {
            (1u64 << (m1 - lo)) - 1
        }
    }
}

/// A voxel frame buffer of bit planes in caller memory (see module docs).
pub struct VoxelGrid<'a> {
    pub(crate) shape: Shape,
    pub(crate) surface: &'a mut [u64],
    pub(crate) interior: &'a mut [u64],
    pub(crate) work: &'a mut [u64],
    pub(crate) dirty: &'a mut [u64],
    pub(crate) transform: VoxelTransform,
    pub(crate) state: GridState,
    pub(crate) thin: bool,
}

impl<'a> VoxelGrid<'a> {
    /// Bytes of caller memory a whole grid of resolution `res` needs (three
    /// bit planes plus one bit per row; about `3 M1 M2 M3 / 8`).
    pub fn required_bytes(res: [u32; 3]) -> Result<usize, Error> {
        Shape::new(res, 0, res[2].max(1))?.bytes()
    }

    /// Bytes a slab grid for the layers `[z0, z1)` needs (the slab plus
    /// [`SLAB_MARGIN`] layers on each side).
    pub fn slab_required_bytes(res: [u32; 3], z0: u32, z1: u32) -> Result<usize, Error> {
        Shape::new(res, z0, z1)?.bytes()
    }

    /// A cleared whole grid in `mem` (at least [`VoxelGrid::required_bytes`]
    /// bytes: [`crate::mem::words_for`] words).
    pub fn new(res: [u32; 3], mem: &'a mut [u64]) -> Result<Self, Error> {
        Self::new_slab(res, 0, res[2].max(1), mem)
    }

    /// A cleared slab grid for layers `[z0, z1)` in `mem`.
    pub fn new_slab(res: [u32; 3], z0: u32, z1: u32, mem: &'a mut [u64]) -> Result<Self, Error> {
        let shape = Shape::new(res, z0, z1)?;
        let required = shape.bytes()?;
        if bytes_of(mem.len()) < required {
            return Err(Error::BufferTooSmall { required });
        }
        let (plane, rows) = shape.words()?;
        let w = &mut mem[..words_for(required)];
        let (surface, rest) = w.split_at_mut(plane);
        let (interior, rest) = rest.split_at_mut(plane);
        let (work, rest) = rest.split_at_mut(plane);
        let dirty = &mut rest[..rows];
        surface.fill(0);
        interior.fill(0);
        work.fill(0);
        dirty.fill(0);
        Ok(VoxelGrid {
            shape,
            surface,
            interior,
            work,
            dirty,
            transform: VoxelTransform::IDENTITY,
            state: GridState::Empty,
            thin: false,
        })
    }

    /// Resolution `[M1, M2, M3]`.
    pub fn resolution(&self) -> [u32; 3] {
        self.shape.res
    }

    /// The slab `[z0, z1)` this grid answers for (`[0, M3)` for a whole
    /// grid).
    pub fn slab(&self) -> (u32, u32) {
        (self.shape.z0, self.shape.z1)
    }

    /// The model-to-voxel transform of the last voxelization.
    pub fn transform(&self) -> VoxelTransform {
        self.transform
    }

    /// What has been done to the grid.
    pub fn state(&self) -> GridState {
        self.state
    }

    /// Clears all planes (state [`GridState::Empty`]).
    pub fn clear(&mut self) {
        self.surface.fill(0);
        self.interior.fill(0);
        self.work.fill(0);
        self.dirty.fill(0);
        self.state = GridState::Empty;
    }

    #[inline]
    pub(crate) fn index(&self, i: u32, j: u32, k: u32) -> Option<(usize, u64)> {
        if i >= self.shape.res[0] {
            return None;
        }
        let r = self.shape.row(j, k)?;
        Some((r * self.shape.wpr + (i / 64) as usize, 1u64 << (i % 64)))
    }

    /// Class of voxel `(i, j, k)`; voxels outside the slab (or the grid) are
    /// [`VoxelClass::Outside`].
    pub fn class(&self, i: u32, j: u32, k: u32) -> VoxelClass {
        if k < self.shape.z0 || k >= self.shape.z1 {
            return VoxelClass::Outside;
        }
        match self.index(i, j, k) {
            Some((w, b)) if self.surface[w] & b != 0 => VoxelClass::Surface,
            Some((w, b)) if self.interior[w] & b != 0 => VoxelClass::Interior,
            _ => VoxelClass::Outside,
        }
    }

    /// Rows `[r0, r1)` of the slab of interest.
    #[inline]
    pub(crate) fn slab_rows(&self) -> (usize, usize) {
        let m2 = self.shape.res[1] as usize;
        let r0 = (self.shape.z0 - self.shape.zlo) as usize * m2;
        let r1 = (self.shape.z1 - self.shape.zlo) as usize * m2;
        (r0, r1)
    }

    /// Surface and interior counts over the slab.
    pub fn counts(&self) -> VoxelCounts {
        let (r0, r1) = self.slab_rows();
        let wpr = self.shape.wpr;
        let range = r0 * wpr..r1 * wpr;
        let pop = |p: &[u64]| p[range.clone()].iter().map(|w| w.count_ones() as u64).sum();
        VoxelCounts {
            surface: pop(self.surface),
            interior: pop(self.interior),
        }
    }

    /// Word `w` of row `r` of the surface plane (`w < words_per_row`).
    #[inline]
    pub fn surface_word(&self, row: usize, w: usize) -> u64 {
        self.surface
            .get(row * self.shape.wpr + w)
            .copied()
            .unwrap_or(0)
    }

    /// Word `w` of row `r` of the interior plane.
    #[inline]
    pub fn interior_word(&self, row: usize, w: usize) -> u64 {
        self.interior
            .get(row * self.shape.wpr + w)
            .copied()
            .unwrap_or(0)
    }

    /// Words per row (`ceil(M1 / 64)`).
    pub fn words_per_row(&self) -> usize {
        self.shape.wpr
    }

    /// Row number of `(j, k)` for [`VoxelGrid::surface_word`] (None outside
    /// the slab).
    pub fn row_of(&self, j: u32, k: u32) -> Option<usize> {
        if k < self.shape.z0 || k >= self.shape.z1 {
            return None;
        }
        self.shape.row(j, k)
    }
}
