//! The bits of a node record shared by the tessellation passes (the bottom
//! file of `tessellate/`: it imports nothing, the passes import it).
//!
//! A record entry (and a slot-corner entry) is a vertex index in the
//! [`INDEX`] bits plus two flags, [`OWN`] and [`DIAG`]; [`AT`] names the
//! children's net corners that fall on a node's centre and side midpoints.

/// Flag on a record or slot-corner entry: this node (slot) created the
/// vertex, and writes it at emission. Indices stay below 2^30.
pub(crate) const OWN: u32 = 1 << 31;

/// Flag on a record entry, set by the emission of a polynomial bottom
/// node (all four children leaves) when triangles are wanted (else stale
/// and unread): on entry 0, "the cuts are known"; on
/// entry `1 + q`, child `q`'s quad is cut along its corners 1-3 (else 0-2),
/// the choice [`super::triangulate::quad`] makes, taken from the points
/// of the node's own net so that the polygon pass need not read them back.
pub(crate) const DIAG: u32 = 1 << 30;

/// Mask of the index bits of a record or slot-corner entry.
pub(crate) const INDEX: u32 = !(OWN | DIAG);

/// (child, net corner) pairs that have the centre (index 0) or the
/// midpoint of side k (index 1 + k) as a corner.
pub(crate) const AT: [[(usize, usize); 4]; 5] = [
    [(0, 2), (1, 3), (2, 0), (3, 1)],
    [(0, 1), (1, 0), (0, 1), (1, 0)],
    [(1, 2), (2, 1), (1, 2), (2, 1)],
    [(2, 3), (3, 2), (2, 3), (3, 2)],
    [(3, 0), (0, 3), (3, 0), (0, 3)],
];
