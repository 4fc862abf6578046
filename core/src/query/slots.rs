//! The data of the slot index (`index.rs` builds it and walks it): per
//! slot a box, then a complete binary tree of boxes, in one caller slice.
//! Apart from `index.rs` so that the cell trait (`cell.rs`) can name it
//! without a circle of imports.

use glam::DVec3;

/// One box of a [`SlotIndex`] (`#[repr(C)]`, 56 bytes): `lo..hi`, and two
/// words whose meaning depends on where the node is (the slot's face and
/// sub-face for the per-slot boxes; the slot number for a tree leaf,
/// `u32::MAX` for padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IndexNode {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
    /// First word.
    pub a: u32,
    /// Second word.
    pub b: u32,
}

impl Default for IndexNode {
    /// An empty box (meets nothing).
    fn default() -> Self {
        IndexNode {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            a: u32::MAX,
            b: 0,
        }
    }
}

/// The slot boxes and their tree, borrowed from the caller's slice
/// (built by `SlotIndex::build`, see `index.rs`).
#[derive(Clone, Copy, Debug)]
pub struct SlotIndex<'a> {
    pub(crate) nodes: &'a [IndexNode],
    pub(crate) slots: usize,
    pub(crate) leaves: usize,
    pub(crate) magnitude: f64,
}

impl SlotIndex<'_> {
    /// Number of slots indexed.
    pub fn slots(&self) -> usize {
        self.slots
    }

    /// The box of slot number `k` (slot order: faces, then sub-faces) and
    /// its `(face, sub)`.
    pub fn slot_box(&self, k: usize) -> (DVec3, DVec3, u32, u32) {
        let s = &self.nodes[k];
        (DVec3::from_array(s.lo), DVec3::from_array(s.hi), s.a, s.b)
    }

    /// Node `k` of the tree (1 is the root; leaves from `leaves` on).
    pub(crate) fn tree(&self, k: usize) -> &IndexNode {
        &self.nodes[self.slots + k]
    }
}
