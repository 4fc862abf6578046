//! The fixed-size work memory of the voxel algorithms: an explicit stack of
//! cells (no machine recursion) and the small lists the certification and
//! the ray test use.

use super::cells::{Cell, HullCell, Net};
use glam::DVec3;

/// Deepest subdivision below a pre-split cell. Cells at this depth are
/// leaves whatever the tests say (counted as `guard_hits`).
pub const MAX_DEPTH: u32 = 48;

/// Stack entries: a depth-first walk that pushes four children per split
/// needs at most `3 * MAX_DEPTH + 4`.
pub(crate) const STACK_CAP: usize = 3 * MAX_DEPTH as usize + 8;

/// Voxels a certification subtree remembers (see [`super::rasterize`]).
pub(crate) const LOCAL_CAP: usize = 64;

/// `Entry::corner` of a polynomial cell.
pub(crate) const POLY: u32 = u32::MAX;

/// `Entry::corner` of a feature hull cell: the net holds its corners
/// (values 0..12), box (12..18) and index `(i, j)` (18, 19); `level` is
/// its level in the sub-face.
pub(crate) const HULL: u32 = u32::MAX - 1;

/// One pending cell: a Bezier net, or (`corner != POLY`) the corner cell of
/// that level (the net is then unused). A struct rather than an enum so that
/// children can be split directly into their stack slots.
#[derive(Clone, Copy)]
pub(crate) struct Entry {
    pub net: Net,
    /// Eq. (2) voxels of the net's corners (set by the voxelizer's first
    /// walk for polynomial cells; unused elsewhere).
    pub vox: [[i32; 3]; 4],
    pub corner: u32,
    /// Depth below the pre-split root.
    pub depth: u32,
    /// Parameter level of the cell in its patch (cell size `2^-level`).
    pub level: u32,
    /// 0: first walk; 1: certification refinement; 2: a certification root.
    pub mode: u8,
}

impl Entry {
    #[inline(always)]
    pub fn new(cell: Cell, depth: u32, level: u32, mode: u8) -> Entry {
        match cell {
            Cell::Poly(net) => Entry {
                net,
                vox: [[0; 3]; 4],
                corner: POLY,
                depth,
                level,
                mode,
            },
            Cell::Corner(l) => Entry {
                net: [0.0; 48],
                vox: [[0; 3]; 4],
                corner: l,
                depth,
                level,
                mode,
            },
            Cell::Hull(h) => {
                let mut net = [0.0; 48];
                for (k, c) in h.corners.iter().enumerate() {
                    net[3 * k..3 * k + 3].copy_from_slice(&c.to_array());
                }
                net[12..15].copy_from_slice(&h.lo.to_array());
                net[15..18].copy_from_slice(&h.hi.to_array());
                net[18] = h.i as f64;
                net[19] = h.j as f64;
                Entry {
                    net,
                    vox: [[0; 3]; 4],
                    corner: HULL,
                    depth,
                    level: h.level,
                    mode,
                }
            }
        }
    }

    /// The hull cell of a [`HULL`] entry.
    #[inline]
    pub fn hull(&self) -> HullCell {
        let n = &self.net;
        let v = |k: usize| DVec3::new(n[k], n[k + 1], n[k + 2]);
        HullCell {
            level: self.level,
            i: n[18] as u32,
            j: n[19] as u32,
            corners: [v(0), v(3), v(6), v(9)],
            lo: v(12),
            hi: v(15),
        }
    }
    #[inline(always)]
    pub fn cell(&self) -> Cell {
        if self.corner == POLY {
            Cell::Poly(self.net)
        } else if self.corner == HULL {
            Cell::Hull(self.hull())
        } else {
            Cell::Corner(self.corner)
        }
    }
}

const EMPTY: Entry = Entry {
    net: [0.0; 48],
    vox: [[0; 3]; 4],
    corner: 0,
    depth: 0,
    level: 0,
    mode: 0,
};

/// Fixed-size scratch memory of the voxelizer, the flood's inside/outside
/// test and the bounding-box fit (about 60 KiB). Nothing in it survives a
/// call; one `VoxelWork` can serve any number of grids, one call at a time.
/// Build it with [`VoxelWork::ZERO`] (e.g. in a `static` or a `Box`).
pub struct VoxelWork {
    pub(crate) stack: [Entry; STACK_CAP],
    pub(crate) len: usize,
    pub(crate) local: [[u32; 3]; LOCAL_CAP],
    pub(crate) nlocal: usize,
}

impl VoxelWork {
    /// An empty work area.
    pub const ZERO: VoxelWork = VoxelWork {
        stack: [EMPTY; STACK_CAP],
        len: 0,
        local: [[0; 3]; LOCAL_CAP],
        nlocal: 0,
    };

    #[inline]
    pub(crate) fn push(&mut self, e: Entry) -> bool {
        if self.len < STACK_CAP {
            self.stack[self.len] = e;
            self.len += 1;
            true
        } else {
            false
        }
    }

    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            None
        } else {
            self.len -= 1;
            Some(self.stack[self.len])
        }
    }

    #[inline]
    pub(crate) fn local_has(&self, v: [u32; 3]) -> bool {
        self.local[..self.nlocal].contains(&v)
    }

    #[inline]
    pub(crate) fn local_add(&mut self, v: [u32; 3]) {
        if self.nlocal < LOCAL_CAP && !self.local_has(v) {
            self.local[self.nlocal] = v;
            self.nlocal += 1;
        }
    }
}
