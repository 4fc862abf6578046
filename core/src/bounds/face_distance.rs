//! Guaranteed distance between a control face's bilinear map and the limit
//! surface over that face, from Bezier nets (the sharper alternative to
//! `CL-R` Lemma 1's `M / 3` used by [`crate::bounds::depth::tight_depth`]).
//!
//! Where the limit surface is one bicubic polynomial `S` over a parameter
//! square (a regular patch, or a ring region `Omega_{m,b}` of an
//! extraordinary patch, \[CL-R ch. 7\]), and `B` is any bilinear map of that
//! square, `S - B` is a bicubic polynomial: its Bezier net over the square
//! is the net of `S` minus the net of `B` degree-elevated to bicubic (whose
//! point `(a, b)` is `B(a/3, b/3)`). By the convex hull property of Bezier
//! nets (nonnegative weights summing to 1), `|S - B|` is at most the
//! largest length of that net's points, over the square and over every
//! sub-square (split by de Casteljau, which is exact). [`net_distance`]
//! takes the largest length over the four quadrant nets of one split
//! (one quadrant at a time: the bound runs on the firmware's small stack).
//!
//! The control faces that [`crate::bounds::depth`] bounds are those of the
//! 4x4 B-spline grids after uniform subdivision ([`child_grid`]: the
//! cubic B-spline refinement rule, `(P_(i-1) + 6 P_i + P_(i+1)) / 8` and
//! `(P_i + P_(i+1)) / 2`, which is Catmull-Clark on a regular grid), and
//! the bilinear map of a face is that of its four central control points.

use crate::math::bezier::{from_grid_rotated, Net};
use crate::math::bspline::Grid;
use glam::DVec3;

/// Point `(a, b)` of a grid or net (structure of arrays).
#[inline]
fn point(g: &[f64; 48], a: usize, b: usize) -> DVec3 {
    let i = a * 4 + b;
    DVec3::new(g[i], g[16 + i], g[32 + i])
}

/// The 4x4 grid of the quadrant `(qa, qb)` (0: lower half, 1: upper half,
/// along u and along v) of the central face of `g` after one uniform
/// subdivision step: along each direction the half-span `[0, 1/2]` has the
/// points `E_0, V_1, E_1, V_2` and `[1/2, 1]` the points `V_1, E_1, V_2,
/// E_2` (`V_i = (P_(i-1) + 6 P_i + P_(i+1)) / 8`, `E_i = (P_i + P_(i+1)) /
/// 2`). Tensor product: applied along u, then along v.
pub fn child_grid(g: &Grid, qa: usize, qb: usize) -> Grid {
    let rule = |p: [f64; 4], q: usize| -> [f64; 4] {
        let e = |i: usize| 0.5 * (p[i] + p[i + 1]);
        let v = |i: usize| 0.125 * (p[i - 1] + 6.0 * p[i] + p[i + 1]);
        if q == 0 {
            [e(0), v(1), e(1), v(2)]
        } else {
            [v(1), e(1), v(2), e(2)]
        }
    };
    let mut out = [0.0; 48];
    for c in 0..3 {
        let s = &g[16 * c..16 * c + 16];
        let mut t = [0.0f64; 16];
        for b in 0..4 {
            let col = rule([s[b], s[4 + b], s[8 + b], s[12 + b]], qa);
            for a in 0..4 {
                t[a * 4 + b] = col[a];
            }
        }
        for a in 0..4 {
            let row = rule([t[a * 4], t[a * 4 + 1], t[a * 4 + 2], t[a * 4 + 3]], qb);
            out[16 * c + a * 4..16 * c + a * 4 + 4].copy_from_slice(&row);
        }
    }
    out
}

/// Turns the net of `S` into the net of `S - B` over the unit square: minus
/// the bilinear map with corners `corners` (at `(0,0), (1,0), (1,1),
/// (0,1)`) degree-elevated (point `(a, b)` is `B(a/3, b/3)`).
fn subtract_bilinear(d: &mut Net, corners: [DVec3; 4]) {
    for a in 0..4 {
        for b in 0..4 {
            let (s, t) = (a as f64 / 3.0, b as f64 / 3.0);
            let bl = corners[0] * ((1.0 - s) * (1.0 - t))
                + corners[1] * (s * (1.0 - t))
                + corners[2] * (s * t)
                + corners[3] * ((1.0 - s) * t);
            let i = a * 4 + b;
            d[i] -= bl.x;
            d[16 + i] -= bl.y;
            d[32 + i] -= bl.z;
        }
    }
}

/// Largest squared length of a net's points.
fn max_len2(n: &Net) -> f64 {
    (0..16).fold(0.0f64, |m, i| {
        m.max(point(n, i / 4, i % 4).length_squared())
    })
}

/// Half `q` (0: `[0, 1/2]`, 1: `[1/2, 1]`) of a cubic's Bezier points
/// (de Casteljau at 1/2).
fn half(p: [f64; 4], q: usize) -> [f64; 4] {
    let m = 0.125 * (p[0] + 3.0 * (p[1] + p[2]) + p[3]);
    if q == 0 {
        [
            p[0],
            0.5 * (p[0] + p[1]),
            0.25 * (p[0] + 2.0 * p[1] + p[2]),
            m,
        ]
    } else {
        [
            m,
            0.25 * (p[1] + 2.0 * p[2] + p[3]),
            0.5 * (p[2] + p[3]),
            p[3],
        ]
    }
}

/// Largest squared length of the points of quadrant `(qa, qb)` of a net
/// (de Casteljau at 1/2 along s, then along t), one quadrant at a time.
fn quadrant_max_len2(n: &Net, qa: usize, qb: usize) -> f64 {
    let mut out: Net = [0.0; 48];
    for c in 0..3 {
        let s = &n[16 * c..16 * c + 16];
        let mut t = [0.0f64; 16];
        for b in 0..4 {
            let col = half([s[b], s[4 + b], s[8 + b], s[12 + b]], qa);
            for a in 0..4 {
                t[a * 4 + b] = col[a];
            }
        }
        for a in 0..4 {
            let row = half([t[a * 4], t[a * 4 + 1], t[a * 4 + 2], t[a * 4 + 3]], qb);
            out[16 * c + a * 4..16 * c + a * 4 + 4].copy_from_slice(&row);
        }
    }
    max_len2(&out)
}

/// Largest squared length over the four quadrant nets of `n`.
fn split_max_len2(n: &Net) -> f64 {
    (0..4).fold(0.0f64, |m, q| m.max(quadrant_max_len2(n, q & 1, q >> 1)))
}

/// Guaranteed `max |S - B|` over the unit square, `S` the bicubic with
/// Bezier net `net`, `B` the bilinear map with corners `corners` at `(0,0),
/// (1,0), (1,1), (0,1)` (module docs: the largest point of the quadrant
/// nets of `S - B`). Exact-arithmetic value; callers add the rounding.
#[inline(never)] // own frame: the depth bounds run on an 8 KiB stack
pub fn net_distance(net: &Net, corners: [DVec3; 4]) -> f64 {
    let mut d = *net;
    subtract_bilinear(&mut d, corners);
    libm::sqrt(split_max_len2(&d))
}

/// The Bezier net of grid `g` and the corners of its central face.
fn face_net(g: &Grid) -> (Net, [DVec3; 4]) {
    let mut net = [0.0; 48];
    from_grid_rotated(g, 0, &mut net);
    (
        net,
        [
            point(g, 1, 1),
            point(g, 2, 1),
            point(g, 2, 2),
            point(g, 1, 2),
        ],
    )
}

/// Guaranteed distance between the central control face of grid `g`
/// (bilinear map of points `(1,1), (2,1), (2,2), (1,2)`) and the bicubic of
/// `g` over that face ([`net_distance`]).
pub fn grid_face_distance(g: &Grid) -> f64 {
    let (net, corners) = face_net(g);
    net_distance(&net, corners)
}

/// Whether the central face of `g` is within `eps` of its bicubic by the
/// bound of [`grid_face_distance`] (true only if that bound is at most
/// `eps`, or the unsplit net's, which is never smaller, already is).
#[inline(never)] // own frame: the depth bounds run on an 8 KiB stack
pub fn grid_face_within(g: &Grid, eps: f64) -> bool {
    let (mut d, corners) = face_net(g);
    subtract_bilinear(&mut d, corners);
    let e2 = eps * eps;
    if max_len2(&d) <= e2 {
        return true;
    }
    (0..4).all(|q| quadrant_max_len2(&d, q & 1, q >> 1) <= e2)
}

/// Calls `f` on each of the `4^d` grids of `g` after `d` subdivision steps
/// ([`child_grid`], depth first, keeping only the path: one grid and the
/// next quadrant per depth), stopping at the first false; returns whether
/// all were true. For `d` above [`MAX_DEPTH`] nothing is visited and the
/// result is false.
pub fn all_at_depth(g: &Grid, d: usize, mut f: impl FnMut(&Grid) -> bool) -> bool {
    if d > MAX_DEPTH {
        return false;
    }
    if d == 0 {
        return f(g);
    }
    let mut path = [[0.0f64; 48]; MAX_DEPTH];
    let mut next = [0usize; MAX_DEPTH];
    path[0] = *g;
    let mut k = 0usize;
    loop {
        if next[k] == 4 {
            if k == 0 {
                return true;
            }
            k -= 1;
            continue;
        }
        let q = next[k];
        next[k] += 1;
        let child = child_grid(&path[k], q & 1, q >> 1);
        if k + 1 == d {
            if !f(&child) {
                return false;
            }
            continue;
        }
        path[k + 1] = child;
        next[k + 1] = 0;
        k += 1;
    }
}

/// A cheap bound for the central face of `g` and all its descendants: the
/// faces of `g` after `d >= 0` subdivision steps are within
/// `second_norm(g) / (6 * 4^d)` of the bicubic. Proof (`CL-R` Lemma 1,
/// split by direction): with `C_j` the u-cubic of row `j` and `l_j` the
/// chord between its points 1 and 2, a cubic B-spline minus its chord is
/// `(1-u)^3/6 D_1 + u^3/6 D_2` (`D_k` the second differences at points 1
/// and 2), so `S - B = sum_j N_j(v) (C_j - l_j) + (the v-cubic of the
/// l_j(u) minus its chord)`: at most `((1-u)^3 + u^3)/6 Mu + ((1-v)^3 +
/// v^3)/6 Mv <= (Mu + Mv)/6`, `Mu` the largest u-difference over all four
/// rows and `Mv` the largest v-difference of the two central columns
/// (the `l_j` are convex combinations of those columns' points). The same
/// with u and v swapped; the smaller is taken. A subdivision step divides
/// the differences along its direction by at least 4 (`D/4` and `(D_i +
/// D_(i+1))/8`) and averages the others with nonnegative weights, and a
/// child grid depends only on its parent, so the bound shrinks by 1/4 per
/// step.
pub fn second_norm(g: &Grid) -> f64 {
    let d = |a0: usize, b0: usize, a1: usize, b1: usize, a2: usize, b2: usize| {
        (point(g, a1, b1) * 2.0 - point(g, a0, b0) - point(g, a2, b2)).length()
    };
    let (mut u_all, mut u_mid, mut v_all, mut v_mid) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for j in 0..4 {
        for c in 1..3 {
            let du = d(c - 1, j, c, j, c + 1, j);
            let dv = d(j, c - 1, j, c, j, c + 1);
            u_all = u_all.max(du);
            v_all = v_all.max(dv);
            if j == 1 || j == 2 {
                u_mid = u_mid.max(du);
                v_mid = v_mid.max(dv);
            }
        }
    }
    (u_all + v_mid).min(v_all + u_mid)
}

/// The deepest subdivision [`all_at_depth`] walks.
pub const MAX_DEPTH: usize = 3;

/// Largest length of a grid's points (for rounding margins).
pub fn grid_magnitude(g: &Grid) -> f64 {
    (0..16).fold(0.0f64, |m, i| m.max(point(g, i / 4, i % 4).length()))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::math::bspline::eval_grid;

    fn random_grid(s: &mut u64) -> Grid {
        let mut g = [0.0; 48];
        for x in g.iter_mut() {
            *s ^= *s << 13;
            *s ^= *s >> 7;
            *s ^= *s << 17;
            *x = (*s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        }
        g
    }

    /// The child grids describe the same surface (dense comparison with the
    /// parent at the mapped parameters), and the face distance bounds the
    /// true distance between the central face's bilinear map and the
    /// surface at 33 x 33 points (never below it; reported tightness).
    #[test]
    fn child_grids_and_face_distance() {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut worst_ratio = 0.0f64;
        // Two grids under Miri (scripts/miri.sh runs this crate's tests;
        // 200 take minutes interpreted).
        let grids = if cfg!(miri) { 2 } else { 200 };
        for _ in 0..grids {
            let g = random_grid(&mut s);
            for qa in 0..2 {
                for qb in 0..2 {
                    let c = child_grid(&g, qa, qb);
                    for k in 0..=8 {
                        for l in 0..=8 {
                            let (u, v) = (k as f64 / 8.0, l as f64 / 8.0);
                            let pc = eval_grid::<false>(&c, u, v).p;
                            let pp = eval_grid::<false>(
                                &g,
                                0.5 * (u + qa as f64),
                                0.5 * (v + qb as f64),
                            )
                            .p;
                            assert!((pc - pp).length() < 1e-14, "{pc} {pp}");
                        }
                    }
                }
            }
            let bound = grid_face_distance(&g);
            let mut actual = 0.0f64;
            for k in 0..=32 {
                for l in 0..=32 {
                    let (u, v) = (k as f64 / 32.0, l as f64 / 32.0);
                    let p = eval_grid::<false>(&g, u, v).p;
                    let b = point(&g, 1, 1) * ((1.0 - u) * (1.0 - v))
                        + point(&g, 2, 1) * (u * (1.0 - v))
                        + point(&g, 2, 2) * (u * v)
                        + point(&g, 1, 2) * ((1.0 - u) * v);
                    actual = actual.max((p - b).length());
                }
            }
            assert!(actual <= bound * (1.0 + 1e-12), "{actual} > {bound}");
            let cheap = second_norm(&g) / 6.0;
            assert!(actual <= cheap * (1.0 + 1e-12), "{actual} > {cheap}");
            // Descendants at depth 2: within second_norm / (6 * 16).
            all_at_depth(&g, 2, |c| {
                let mut worst = 0.0f64;
                for k in 0..=16 {
                    for l in 0..=16 {
                        let (u, v) = (k as f64 / 16.0, l as f64 / 16.0);
                        let p = eval_grid::<false>(c, u, v).p;
                        let b = point(c, 1, 1) * ((1.0 - u) * (1.0 - v))
                            + point(c, 2, 1) * (u * (1.0 - v))
                            + point(c, 2, 2) * (u * v)
                            + point(c, 1, 2) * ((1.0 - u) * v);
                        worst = worst.max((p - b).length());
                    }
                }
                assert!(
                    worst <= cheap / 16.0 * (1.0 + 1e-12),
                    "{worst} > {}",
                    cheap / 16.0
                );
                assert!(worst <= grid_face_distance(c) * (1.0 + 1e-12));
                true
            });
            worst_ratio = worst_ratio.max(bound / actual);
        }
        std::eprintln!("face distance bound / sampled, worst: {worst_ratio:.3}");
        assert!(worst_ratio < 2.0);
    }
}
