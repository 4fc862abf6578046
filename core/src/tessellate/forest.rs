//! The marked quadtrees of all slots (read-only view) and the quadrant
//! tables every traversal shares.
//!
//! Node `x` of slot `s` is `nodes[slot_node[s] + x]`: the local index of
//! its first child (children are four consecutive nodes in quadrant order
//! 0: (0,0), 1: (1,0), 2: (1,1), 3: (0,1)), or 0 for a leaf; the root is
//! local node 0. Internal nodes are numbered by their children group: the
//! record of the node whose first child is `c` is
//! `(slot_node[s] - s) / 4 + (c - 1) / 4` (each slot has `1 + 4 I_s` nodes,
//! so the groups of all slots are consecutive).
//!
//! Sides: 0 bottom (v = 0), 1 right (u = 1), 2 top (v = 1), 3 left (u = 0).

use super::carrier::Topo;

/// Read-only view of the marked trees.
#[derive(Clone, Copy)]
pub(crate) struct Forest<'t> {
    pub topo: Topo<'t>,
    pub slot_node: &'t [u32],
    pub nodes: &'t [u32],
}

impl Forest<'_> {
    #[inline]
    pub fn num_slots(&self) -> usize {
        self.slot_node.len() - 1
    }
    /// The node entries of slot `s` (indexed by local node).
    #[inline]
    pub fn tree(&self, s: usize) -> &[u32] {
        &self.nodes[self.slot_node[s] as usize..self.slot_node[s + 1] as usize]
    }
    /// Record index of the internal node whose first child is `c`.
    #[inline]
    pub fn rec(&self, s: usize, c: u32) -> usize {
        rec_at((self.slot_node[s] as usize - s) / 4, c)
    }
}

/// Record index of the internal node whose first child is `c`, in a slot
/// whose root's record is `rbase` ([`Forest::rec`]`(s, 1)`): the passes
/// keep `rbase` per slot and index records with this.
#[inline(always)]
pub(crate) fn rec_at(rbase: usize, c: u32) -> usize {
    rbase + (c as usize - 1) / 4
}

/// Is the node whose first child is `c` (0 for a leaf) a *bottom node*:
/// internal, with four leaf children? `tree` is its slot's node entries
/// ([`Forest::tree`]).
#[inline]
pub(crate) fn is_bottom(tree: &[u32], c: u32) -> bool {
    c != 0
        && tree
            .get(c as usize..c as usize + 4)
            .is_some_and(|k| k == [0; 4])
}

/// Does quadrant `q` touch side `side` of its parent? (Side k is touched
/// by quadrants k and k + 1 mod 4.)
#[inline]
pub(crate) fn touches(q: usize, side: usize) -> bool {
    q.wrapping_sub(side) & 3 < 2
}

/// The quadrant across side `side` of quadrant `q` (sibling, or the
/// neighbour parent's child): across a vertical side (1, 3) `q ^ 1`
/// (0 <-> 1, 2 <-> 3), across a horizontal one `q ^ 3` (0 <-> 3, 1 <-> 2).
#[inline]
pub(crate) const fn mirror(q: usize, side: usize) -> usize {
    (q ^ if side & 1 == 1 { 1 } else { 3 }) & 3
}

/// The two children touching side `side`, by increasing coordinate along it.
#[inline]
pub(crate) const fn along(side: usize) -> [usize; 2] {
    [[0, 1], [1, 2], [3, 2], [0, 3]][side & 3]
}

/// Opposite side.
#[inline]
pub(crate) fn opposite(side: usize) -> usize {
    (side + 2) & 3
}

/// Does side `side` of cell (level, i, j) lie on the slot boundary?
#[inline]
pub(crate) fn on_boundary(level: u32, i: u32, j: u32, side: usize) -> bool {
    let last = (1u32 << level) - 1;
    match side & 3 {
        0 => j == 0,
        1 => i == last,
        2 => j == last,
        _ => i == 0,
    }
}

/// Index along side `side` of cell (i, j).
#[inline]
pub(crate) fn along_index(i: u32, j: u32, side: usize) -> u32 {
    if side & 1 == 0 {
        i
    } else {
        j
    }
}

/// Is the counter-clockwise walk of side `side` in increasing coordinate?
#[inline]
pub(crate) fn increasing(side: usize) -> bool {
    side & 3 < 2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quadrant `q`'s cell (x, y) in its parent.
    fn xy(q: usize) -> (u32, u32) {
        [(0, 0), (1, 0), (1, 1), (0, 1)][q]
    }

    #[test]
    fn touches_and_mirror_follow_the_quadrant_layout() {
        for q in 0..4 {
            let (x, y) = xy(q);
            // Sides 0 bottom (y = 0), 1 right (x = 1), 2 top, 3 left.
            let on = [y == 0, x == 1, y == 1, x == 0];
            for side in 0..4 {
                assert_eq!(touches(q, side), on[side], "q {q} side {side}");
                let want = if side & 1 == 1 {
                    (1 - x, y)
                } else {
                    (x, 1 - y)
                };
                assert_eq!(xy(mirror(q, side)), want, "q {q} side {side}");
            }
        }
    }
}
