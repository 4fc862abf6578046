//! The 2n+8 control-point labels of one face of the subdivided mesh `G`, as
//! vertex indices (label order of [`crate::mesh::stencil`], \[Stam98\]).
//!
//! Every face of `G` (one Catmull-Clark step of `P`) is a quad with at most
//! one extraordinary vertex, so each is one patch whose control points are
//! vertices of `G` itself: the similarity rows of \[CL-R eq. 4.5\] are
//! linear combinations of these vertices with per-valence weights.

use crate::mesh::stencil::{outer, MAX_K};
use crate::mesh::topology::Topology;

/// The corner of quad `q` holding its extraordinary vertex (0 when all four
/// are regular), that vertex's valence, and the number of extraordinary
/// corners (at most 1 on a once-subdivided mesh).
pub fn patch_corner(t: &Topology, q: usize) -> (usize, usize, usize) {
    let vs = t.face_vertices(q);
    let mut corner = 0;
    let mut count = 0;
    for (k, &v) in vs.iter().enumerate() {
        if t.valence(v as usize) != 4 {
            if count == 0 {
                corner = k;
            }
            count += 1;
        }
    }
    (corner, t.valence(vs[corner] as usize), count)
}

/// Writes the vertex indices of the 2n+8 control points of quad `q` whose
/// corner `r` (valence `n`) is the label-0 vertex.
pub fn patch_labels(t: &Topology, q: usize, r: usize, n: usize, out: &mut [u32; MAX_K]) {
    let id = |v: usize| v as u32;
    let h0 = t.face_half_edge(q) + r;
    out[0] = id(t.origin(h0));
    let mut s = h0;
    for i in 0..n {
        out[1 + 2 * i] = id(t.dest(s));
        out[2 + 2 * i] = id(t.dest(t.next(s)));
        s = t.rotate_ccw(s);
    }
    let b = t.next(h0);
    let tb = t.twin(b);
    let g1 = t.next(tb);
    let o = |k: usize| outer(n, k);
    out[o(1)] = id(t.dest(g1));
    out[o(2)] = id(t.dest(t.next(g1)));
    out[o(0)] = id(t.origin(t.prev(t.twin(g1))));
    let d = t.twin(t.prev(tb));
    out[o(3)] = id(t.dest(t.next(d)));
    let c = t.twin(t.next(b));
    let c1 = t.next(c);
    out[o(4)] = id(t.dest(c1));
    out[o(5)] = id(t.dest(t.next(c1)));
    let e6 = t.twin(t.prev(c));
    out[o(6)] = id(t.dest(t.next(e6)));
}
