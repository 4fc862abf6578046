//! The (bi)linear interpolation operator `L` of a level: values at the old
//! vertices to values at every new vertex, optionally with the length
//! renormalisation of the rounding factor `b`.
//!
//! `L` is used twice per level:
//!
//! * on positions it *is* the linear subdivision (MS eqs. (1)–(2), Fig. 8);
//! * on the push-back vectors `D(V_i)` it gives `D` at the new vertices,
//!   eqs. (6) and (15)–(17), renormalised by eqs. (18)–(21).
//!
//! Edge points: linear along the edge. Split triangles: barycentric.
//! Polygons (including quads): the centroid value is the average of the
//! corner values — for `D` this is eq. (17), `D(F) = 1/#F Σ D(V_k)` — and
//! each sector `[v_k, mid_k, centroid, mid_{k-1}]` is bilinear; for a quad
//! the union of the four sectors is exactly the bilinear interpolant.
//!
//! **Renormalisation** (eqs. (18)–(21) generalised to every new vertex): the
//! lengths `|D(V_k)|` are interpolated by the same `L`, and
//! `D := l D` with `l = b L(|D|) / |L(D)| + 1 - b`.
//! *Zero-length vectors* (MS leaves `|D(E)| = 0` open): when
//! `|L(D)| <= 1e-12 L(|D|)` the interpolated vectors cancel and have no
//! direction; `L(D)` is then used unscaled (`l = 1`). The result's length is
//! bounded by `|1 - b| |L(D)| + |b| L(|D|)` in every case.

use super::layout::Numbering;
use crate::config::MAX_VALENCE;
use crate::mesh::topology::Topology;
use glam::DVec3;

/// Relative length below which an interpolated push-back vector counts as
/// zero (no direction to renormalise).
pub const ZERO_LENGTH: f64 = 1e-12;

/// The renormalised interpolated vector: `lin` is `L(D)`, `len` is `L(|D|)`,
/// `b` the rounding factor (eqs. (18)–(21)).
#[inline]
pub fn renormalize(lin: DVec3, len: f64, b: f64) -> DVec3 {
    if b == 0.0 {
        return lin;
    }
    let n = lin.length();
    if n > ZERO_LENGTH * len && n > 0.0 {
        lin * ((1.0 - b) + b * len / n)
    } else {
        lin
    }
}

/// A value with its (interpolated) length; the length is ignored unless
/// renormalising.
#[derive(Clone, Copy, Default)]
struct Val {
    v: DVec3,
    l: f64,
}

impl Val {
    #[inline]
    fn mix2(a: Val, b: Val, s: f64) -> Val {
        Val {
            v: a.v * (1.0 - s) + b.v * s,
            l: a.l * (1.0 - s) + b.l * s,
        }
    }
    #[inline]
    fn bilinear(c: [Val; 4], s: f64, t: f64) -> Val {
        let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
        Val {
            v: c[0].v * w[0] + c[1].v * w[1] + c[2].v * w[2] + c[3].v * w[3],
            l: c[0].l * w[0] + c[1].l * w[1] + c[2].l * w[2] + c[3].l * w[3],
        }
    }
}

/// Adds `L(value)` to `out[r]` for every new vertex `r >= V` (edge and face
/// points); old vertices are left to the caller. `value(v)` gives the vector
/// at old vertex `v` and (used only with `RENORM`) its length; with `RENORM`
/// the lengths are interpolated too and the result renormalised with `b`.
pub(crate) fn add_interpolated<const RENORM: bool>(
    t: &Topology,
    num: &Numbering,
    value: &impl Fn(usize) -> (DVec3, f64),
    b: f64,
    out: &mut [DVec3],
) {
    interpolate::<RENORM, false>(t, num, value, b, out, |_| true);
}

/// Sets `out[r] = L(value)` for the new vertices of the faces `wanted`
/// accepts (their edge points and interior points); other new vertices are
/// left alone. No renormalisation (used for the linear subdivision).
pub(crate) fn set_interpolated(
    t: &Topology,
    num: &Numbering,
    value: &impl Fn(usize) -> (DVec3, f64),
    out: &mut [DVec3],
    wanted: impl Fn(usize) -> bool,
) {
    interpolate::<false, true>(t, num, value, 0.0, out, wanted);
}

/// Adds (`ASSIGN = false`: every edge once, from the face of its first
/// half-edge) or assigns (`ASSIGN = true`: every edge of every wanted face)
/// the interpolated values.
fn interpolate<const RENORM: bool, const ASSIGN: bool>(
    t: &Topology,
    num: &Numbering,
    value: &impl Fn(usize) -> (DVec3, f64),
    b: f64,
    out: &mut [DVec3],
    wanted: impl Fn(usize) -> bool,
) {
    let sh = num.shape;
    let d = sh.d;
    let inv = 1.0 / d as f64;
    let val = |v: usize| -> Val {
        let (x, l) = value(v);
        Val { v: x, l }
    };
    let put = |out: &mut [DVec3], r: usize, x: Val| {
        let y = if RENORM {
            renormalize(x.v, x.l, b)
        } else {
            x.v
        };
        if ASSIGN {
            out[r] = y;
        } else {
            out[r] += y;
        }
    };
    let mut corner = [Val::default(); MAX_VALENCE];
    for f in 0..t.num_faces() {
        if !wanted(f) {
            continue;
        }
        let n = t.face_size(f);
        let base = num.interior_start[f] as usize;
        let fs = t.face_half_edge(f);
        let vs = t.face_vertices(f);
        for (k, &v) in vs.iter().enumerate() {
            corner[k] = val(v as usize);
        }
        // Edge points, eq. (2) / (6) / (15): each edge from the face of its
        // first half-edge.
        for k in 0..n {
            let h = fs + k;
            let (a, c) = (corner[k], corner[if k + 1 == n { 0 } else { k + 1 }]);
            if h < t.twin(h) {
                let first = num.edge_point(t, h, 1);
                for q in 1..d {
                    put(out, first + q - 1, Val::mix2(a, c, q as f64 * inv));
                }
            } else if ASSIGN {
                for q in 1..d {
                    put(
                        out,
                        num.edge_point(t, h, q),
                        Val::mix2(a, c, q as f64 * inv),
                    );
                }
            }
        }
        if sh.is_split_tri(n) {
            let mut r = base;
            for j in 1..d.saturating_sub(1) {
                for i in 1..d - j {
                    let (s, tt) = (i as f64 * inv, j as f64 * inv);
                    let w0 = 1.0 - s - tt;
                    let x = Val {
                        v: corner[0].v * w0 + corner[1].v * s + corner[2].v * tt,
                        l: corner[0].l * w0 + corner[1].l * s + corner[2].l * tt,
                    };
                    put(out, r, x);
                    r += 1;
                }
            }
            continue;
        }
        // Eq. (17): the centroid value is the corner average.
        let mut c = Val::default();
        for x in &corner[..n] {
            c.v += x.v;
            c.l += x.l;
        }
        c.v /= n as f64;
        c.l /= n as f64;
        let m = sh.m;
        let (mut r, jmax) = if sh.odd {
            (base, m)
        } else {
            put(out, base, c);
            (base + 1, m - 1)
        };
        if jmax == 0 {
            continue; // d = 2: the centroid is the only interior point
        }
        let step = 2.0 * inv;
        for k in 0..n {
            let kn = if k + 1 == n { 0 } else { k + 1 };
            let kp = if k == 0 { n - 1 } else { k - 1 };
            let quad = [
                corner[k],
                Val::mix2(corner[k], corner[kn], 0.5),
                c,
                Val::mix2(corner[kp], corner[k], 0.5),
            ];
            for j in 1..=jmax {
                for i in 1..=m {
                    put(
                        out,
                        r,
                        Val::bilinear(quad, i as f64 * step, j as f64 * step),
                    );
                    r += 1;
                }
            }
        }
    }
}
