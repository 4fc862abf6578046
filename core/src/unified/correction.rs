//! The Catmull-Clark correction (MS eqs. (11)–(13), §3.3).
//!
//! After a smoothing pass, an old vertex `V_i` with `N_i = #⊕(V_i) != 4`
//! edges gets
//!
//! `C_i = (N_i - 4)/N_i (V̄_i - V_i)`   (eq. (12)),
//!
//! `V̄_i` being its position before the pass and `V_i` the smoothed one, and
//! moves by `g C_i` (eq. (13)); for `d = 2`, `g = 1` after simple averaging
//! (9) this is exactly the Catmull-Clark vertex rule (10).
//!
//! **General `d`** (MS gives the weight tables only as a figure): the
//! correction is spread over the new vertices near `V_i` with the
//! piecewise-bilinear weight `w(s, t) = (1 - 2s)(1 - 2t)` on `0 <= s, t <=
//! 1/2` of every face around `V_i` (`s, t` in units of the face's edges, from
//! `V_i`), zero elsewhere: the bilinear interpolant of Fig. 10's step-1
//! table (1 at the extraordinary vertex, 0 at every other vertex of a binary
//! step), sampled at the new vertices as MS §3.3 suggests for `d` other than
//! a power of two. For `d = 2` only `V_i` moves, as in eq. (13).
//!
//! **Where it applies**: at old vertices whose faces all use the polygon
//! layout (the Catmull-Clark correction is a quad-mesh notion; around split
//! triangles the regular valence is 6, not 4, so such vertices are left
//! alone). New vertices (including `n`-gon centroids, which Catmull-Clark
//! leaves at the centroid anyway) are not corrected. With `p > 3` the
//! correction follows every smoothing pass, `V̄_i` being the position before
//! that pass.
//!
//! **Edges of non-quads** (our extension): simple averaging (9) reproduces
//! the Catmull-Clark edge rule only next to quads. For an edge `V_0 V_1` of
//! a polygon face with centroid `c` in which `V_0` is preceded by `a` and
//! `V_1` followed by `b`, Catmull-Clark minus simple averaging at the edge
//! point is `(c - q)/8` with `q = (a + V_0 + V_1 + b)/4` (zero for a quad).
//! The first pass adds `g` times the sum of these terms over the edge's two
//! faces, spread with the bilinear hat `(1 - |2s - 1|)(1 - 2t)` (`s` along
//! the edge, `t` into either face), so that `g = 1`, `d = 2` is exactly
//! Catmull-Clark on every polygon mesh (the paper states it for quads).

use super::layout::Numbering;
use crate::mesh::topology::Topology;
use glam::DVec3;

/// `(N - 4)/N` if old vertex `v` takes the correction, else `None`.
fn factor(t: &Topology, num: &Numbering, v: usize) -> Option<f64> {
    let n = t.valence(v);
    if n == 0 || n == 4 {
        return None;
    }
    if num.shape.split_tris {
        let start = t.vertex_half_edge(v);
        let mut h = start;
        loop {
            if t.face_size(t.face_of(h)) == 3 {
                return None;
            }
            h = t.rotate_ccw(h);
            if h == start {
                break;
            }
        }
    }
    Some((n as f64 - 4.0) / n as f64)
}

/// Applies `g C_i` (spread as described in the module docs) to `x`.
/// `before[v]` is the position of old vertex `v` before the pass; `c` is
/// scratch with one entry per old vertex (all `C_i` are formed before any is
/// applied: Jacobi).
pub(crate) fn apply(
    t: &Topology,
    num: &Numbering,
    g: f64,
    before: &[DVec3],
    x: &mut [DVec3],
    c: &mut [DVec3],
) {
    let nv = t.num_vertices();
    for v in 0..nv {
        c[v] = match factor(t, num, v) {
            Some(w) => (before[v] - x[v]) * w,
            None => DVec3::ZERO,
        };
    }
    let d = num.shape.d;
    let inv = 1.0 / d as f64;
    for v in 0..nv {
        if c[v] == DVec3::ZERO {
            continue;
        }
        let cv = c[v] * g;
        x[v] += cv;
        if d <= 2 {
            continue;
        }
        // Each outgoing half-edge h covers its face's points with i >= 1
        // (s along h), j >= 0; the points with i = 0 lie on the previous
        // edge and are covered by the next face around v.
        let start = t.vertex_half_edge(v);
        let mut h = start;
        loop {
            let f = t.face_of(h);
            let k = h - t.face_half_edge(f);
            let n = t.face_size(f);
            let mut i = 1;
            while 2 * i < d {
                let wi = 1.0 - 2.0 * i as f64 * inv;
                let mut j = 0;
                while 2 * j < d {
                    let w = wi * (1.0 - 2.0 * j as f64 * inv);
                    if let Some(r) = num.poly_point(t, f, n, k, i, j) {
                        x[r] += cv * w;
                    }
                    j += 1;
                }
                i += 1;
            }
            h = t.rotate_ccw(h);
            if h == start {
                break;
            }
        }
    }
}

/// The edge terms of non-quad polygon faces (module docs), first pass only.
pub(crate) fn apply_edges(t: &Topology, num: &Numbering, g: f64, x: &mut [DVec3]) {
    let sh = num.shape;
    let d = sh.d;
    let inv = 1.0 / d as f64;
    // (c - q)/8 for the face of half-edge h, zero for quads and split
    // triangles.
    let term = |h: usize| -> DVec3 {
        let f = t.face_of(h);
        let n = t.face_size(f);
        if n == 4 || sh.is_split_tri(n) {
            return DVec3::ZERO;
        }
        let mut c = DVec3::ZERO;
        for &v in t.face_vertices(f) {
            c += t.position(v as usize);
        }
        c /= n as f64;
        let a = t.position(t.origin(t.prev(h)));
        let b = t.position(t.dest(t.next(h)));
        let q = (a + t.position(t.origin(h)) + t.position(t.dest(h)) + b) * 0.25;
        (c - q) * 0.125
    };
    for h in 0..t.num_half_edges() {
        let tw = t.twin(h);
        if h > tw {
            continue;
        }
        let k = (term(h) + term(tw)) * g;
        if k == DVec3::ZERO {
            continue;
        }
        for side in [h, tw] {
            let f = t.face_of(side);
            let n = t.face_size(f);
            let c = side - t.face_half_edge(f);
            let mut j = 0;
            while 2 * j < d {
                // The edge itself (j = 0) is visited from h only.
                if j > 0 || side == h {
                    let wj = 1.0 - 2.0 * j as f64 * inv;
                    for i in 1..d {
                        let wi = 1.0 - (2.0 * i as f64 * inv - 1.0).abs();
                        if let Some(r) = num.poly_point(t, f, n, c, i, j) {
                            x[r] += k * (wi * wj);
                        }
                    }
                }
                j += 1;
            }
        }
    }
}
