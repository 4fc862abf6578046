//! The voxels of one slab of a grid, copied out of the core's grid as the
//! writers (binvox, runs, preview) read them: surface and interior words per
//! (y, z) row.

use ccss_core::voxel::VoxelGrid;

/// The bits of one slab needed by the writers.
pub struct SlabBits {
    /// First layer of the slab.
    pub z0: u32,
    /// One past its last layer.
    pub z1: u32,
    /// 64-bit words per row (x in bit `x % 64` of word `x / 64`).
    pub wpr: usize,
    /// Rows (y fastest) of the slab: surface and interior words.
    pub surface: Vec<u64>,
    /// Interior words, laid out as `surface`.
    pub interior: Vec<u64>,
}

/// Copies the rows of the slab grid `g`.
pub fn slab_bits(g: &VoxelGrid) -> SlabBits {
    let (z0, z1) = g.slab();
    let m2 = g.resolution()[1];
    let wpr = g.words_per_row();
    let mut surface = Vec::with_capacity((z1 - z0) as usize * m2 as usize * wpr);
    let mut interior = Vec::with_capacity(surface.capacity());
    for z in z0..z1 {
        for y in 0..m2 {
            let r = g.row_of(y, z).unwrap_or(usize::MAX);
            for w in 0..wpr {
                surface.push(g.surface_word(r, w));
                interior.push(g.interior_word(r, w));
            }
        }
    }
    SlabBits {
        z0,
        z1,
        wpr,
        surface,
        interior,
    }
}

/// Bit `x` of row `(y, z)` of the selected planes.
#[inline]
pub fn bit(s: &SlabBits, m2: u32, x: u32, y: u32, z: u32, fill: bool) -> bool {
    let r = ((z - s.z0) * m2 + y) as usize * s.wpr + (x / 64) as usize;
    let m = 1u64 << (x % 64);
    s.surface[r] & m != 0 || (fill && s.interior[r] & m != 0)
}
