//! The hard interpolation conditions (\[CL-R eq. 4.1\]): each Type I vertex
//! of `Q` is fixed by its 1-ring so that its limit point is the vertex of
//! `P` it stands for.
//!
//! The limit point of a vertex of valence `N` is (\[CL-R eq. 2.7\])
//! `(5 V + (12b + 8g) avg(E) + (2b + 8g) avg(F)) / (5 + 14b + 16g)` with
//! `(a, b, g)` the vertex rule of valence `N`. On a once-subdivided mesh the
//! ring `E`, `F` of a Type I vertex holds only Type II vertices, so solving
//! for `V` expresses every Type I vertex through the unknowns:
//! `V = (P - a1 sum E - a2 sum F) / a0`. Interpolation therefore holds
//! exactly (to rounding) whatever the Type II vertices are.

use crate::mesh::topology::Topology;
use crate::mesh::weights::Weights;
use glam::DVec3;

/// `(a0, a1, a2)`: limit point = `a0 V + a1 sum(E) + a2 sum(F)` for a
/// vertex of valence `n` under rule `w`.
pub fn limit_coefficients(w: &Weights, n: usize) -> (f64, f64, f64) {
    let (_, b, g) = w.get(n);
    let d = 5.0 + 14.0 * b + 16.0 * g;
    let nf = n as f64;
    (
        5.0 / d,
        (12.0 * b + 8.0 * g) / (nf * d),
        (2.0 * b + 8.0 * g) / (nf * d),
    )
}

#[inline]
pub(crate) fn get3(v: &[f64], i: usize) -> DVec3 {
    DVec3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2])
}

#[inline]
pub(crate) fn add3(v: &mut [f64], i: usize, p: DVec3) {
    v[3 * i] += p.x;
    v[3 * i + 1] += p.y;
    v[3 * i + 2] += p.z;
}

#[inline]
pub(crate) fn set3(v: &mut [f64], i: usize, p: DVec3) {
    v[3 * i] = p.x;
    v[3 * i + 1] = p.y;
    v[3 * i + 2] = p.z;
}

/// Calls `f(e, f)` for each sector of vertex `v` of `g`: its edge
/// neighbour and its face-diagonal vertex.
#[inline]
pub(crate) fn for_ring(g: &Topology, v: usize, mut f: impl FnMut(usize, usize)) {
    let start = g.vertex_half_edge(v);
    let mut h = start;
    loop {
        f(g.dest(h), g.dest(g.next(h)));
        h = g.rotate_ccw(h);
        if h == start {
            break;
        }
    }
}

/// The Type I vertices from the Type II ones (\[CL-R eq. 4.1\]).
///
/// `coef` holds `(1/a0, a1/a0, a2/a0)` per Type I vertex, `target` the
/// points of `P` (or zeros for the homogeneous part). Entries `0..n` of `q`
/// are overwritten; the rest are read.
pub(crate) fn fill_type1(g: &Topology, coef: &[f64], target: Option<&[f64]>, q: &mut [f64]) {
    let n1 = coef.len() / 3;
    for i in 0..n1 {
        let (inv, ce, cf) = (coef[3 * i], coef[3 * i + 1], coef[3 * i + 2]);
        let mut s = match target {
            Some(t) => get3(t, i) * inv,
            None => DVec3::ZERO,
        };
        for_ring(g, i, |e, f| {
            s -= get3(q, e) * ce + get3(q, f) * cf;
        });
        set3(q, i, s);
    }
}

/// The transpose of [`fill_type1`]'s linear part: moves the entries of the
/// Type I vertices of `y` onto their rings and zeroes them.
pub(crate) fn fold_type1(g: &Topology, coef: &[f64], y: &mut [f64]) {
    let n1 = coef.len() / 3;
    for i in 0..n1 {
        let (ce, cf) = (coef[3 * i + 1], coef[3 * i + 2]);
        let c = get3(y, i);
        for_ring(g, i, |e, f| {
            add3(y, e, -c * ce);
            add3(y, f, -c * cf);
        });
        set3(y, i, DVec3::ZERO);
    }
}
