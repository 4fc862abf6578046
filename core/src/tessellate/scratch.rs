//! The explicit traversal state (no recursion), in caller memory.
//!
//! Every pass walks a slot's quadtree depth first with one [`Level`] per
//! tree level: the node being expanded there, the four children it made
//! (kinds, Bezier nets and offsets, computed in place, never copied), which
//! child comes next, and the per-pass extras (same-level neighbours, corner
//! vertex indices, children bounds).

use super::cells::Kind;
use super::MAX_LEVEL;
use crate::math::bezier::Net;

/// Levels of the cursor: 0..=MAX_LEVEL.
pub(crate) const LEVELS: usize = MAX_LEVEL as usize + 1;

/// "No node / no vertex".
pub(crate) const NONE: u32 = u32::MAX;

/// The expansion of one internal node (plain data: any bit pattern is
/// valid).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct Level {
    /// Children bounds (marking).
    pub bounds: [f64; 4],
    /// Children offsets.
    pub offs: [[f64; 3]; 4],
    /// Children nets.
    pub nets: [Net; 4],
    /// Children kinds.
    pub kinds: [Kind; 4],
    /// The node (local index), its first child, level and cell indices.
    pub node: u32,
    pub first: u32,
    pub level: u32,
    pub i: u32,
    pub j: u32,
    /// Next child to visit (4: done).
    pub q: u32,
    /// Bit q: child q is internal (marking).
    pub internal: u32,
    /// Same-level neighbours across sides 0..4, or [`NONE`].
    pub nb: [u32; 4],
    /// First child of each neighbour (0: none or a leaf).
    pub nbc: [u32; 4],
    /// First child of each of the node's children (0 for leaves).
    pub own: [u32; 4],
    /// Vertex indices of the corners (0,0), (1,0), (1,1), (0,1).
    pub corner: [u32; 4],
    /// Corner vertex indices of each child (polygon pass).
    pub cc: [[u32; 4]; 4],
}

impl Level {
    /// Starts the walk of node `node` (first child `first`) at cell
    /// (`level`, `i`, `j`): next child 0, no internal child yet.
    #[inline(always)]
    pub fn start(&mut self, node: u32, first: u32, level: u32, i: u32, j: u32) {
        (self.node, self.first, self.level, self.i, self.j) = (node, first, level, i, j);
        (self.q, self.internal) = (0, 0);
    }
}

const ZERO_LEVEL: Level = Level {
    bounds: [0.0; 4],
    offs: [[0.0; 3]; 4],
    nets: [[0.0; 48]; 4],
    kinds: [Kind {
        tag: 0,
        patch: 0,
        rho: 0,
        k: 0,
    }; 4],
    node: 0,
    first: 0,
    level: 0,
    i: 0,
    j: 0,
    q: 0,
    internal: 0,
    nb: [0; 4],
    nbc: [0; 4],
    own: [0; 4],
    corner: [0; 4],
    cc: [[0; 4]; 4],
};

/// Scratch memory of one traversal (about 58 KiB). Give each thread its
/// own when marking slots in parallel ([`super::mark_slot`]).
#[repr(C)]
pub struct Scratch {
    pub(crate) levels: [Level; LEVELS],
}

impl Scratch {
    /// A zeroed scratch (put it on the heap or in static memory: it is
    /// large).
    pub const ZERO: Scratch = Scratch {
        levels: [ZERO_LEVEL; LEVELS],
    };

    /// Bytes of a scratch.
    pub const BYTES: usize = core::mem::size_of::<Scratch>();

    /// Views `mem` (at least [`Scratch::BYTES`] bytes of words) as a
    /// scratch.
    pub(crate) fn from_words(mem: &mut [u64]) -> Option<&mut Scratch> {
        if mem.len().saturating_mul(8) < Self::BYTES {
            return None;
        }
        // SAFETY: `Scratch` is `repr(C)` of f64 and u32 fields only
        // (alignment 8, every bit pattern valid); `mem` is aligned, large
        // enough and exclusively borrowed for the returned lifetime.
        Some(unsafe { &mut *(mem.as_mut_ptr() as *mut Scratch) })
    }
}

/// Level `l` (read) and level `l + 1` (write) at once.
#[inline]
pub(crate) fn pair(levels: &mut [Level; LEVELS], l: usize) -> (&Level, &mut Level) {
    let (a, b) = levels.split_at_mut(l + 1);
    (&a[l], &mut b[0])
}

/// The next child to visit in a depth-first walk over `levels`: the next
/// quadrant of the node at level `*l` (advancing its cursor), climbing to
/// the parent once all four are done; `None` when the walk is over.
#[inline(always)]
pub(crate) fn next_child(levels: &mut [Level; LEVELS], l: &mut usize) -> Option<usize> {
    loop {
        let cur = &mut levels[*l];
        if cur.q < 4 {
            cur.q += 1;
            return Some(cur.q as usize - 1);
        }
        if *l == 0 {
            return None;
        }
        *l -= 1;
    }
}
