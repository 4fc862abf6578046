//! Bicubic Bezier nets of cells: conversion from B-spline grids, rotation
//! into the slot frame, de Casteljau splitting into the four quadrants, the
//! guaranteed second-derivative bound, and positions/normals at corners.
//!
//! A [`Net`] is 16 control points in structure-of-arrays order,
//! `net[c*16 + a*4 + b]` = coordinate `c` of the point with index `a` along
//! the cell's s (slot u) and `b` along t (slot v), the same layout as
//! [`crate::bspline::Grid`]. Corner `q` of a cell (0: (0,0), 1: (1,0),
//! 2: (1,1), 3: (0,1)) is the net point `CORNER[q]`.

use crate::bspline::Grid;
use glam::DVec3;

/// 16 Bezier control points, structure of arrays (see module docs).
pub(crate) type Net = [f64; 48];

/// Net index (a*4 + b) of each cell corner.
const CORNER: [usize; 4] = [0, 12, 15, 3];

/// Bezier points over [0,1] of the uniform cubic B-spline segment with
/// control points `g`.
#[inline(always)]
fn bspline_to_bezier(g: [f64; 4]) -> [f64; 4] {
    const S: f64 = 1.0 / 6.0;
    const T: f64 = 1.0 / 3.0;
    [
        (g[0] + 4.0 * g[1] + g[2]) * S,
        (2.0 * g[1] + g[2]) * T,
        (g[1] + 2.0 * g[2]) * T,
        (g[1] + 4.0 * g[2] + g[3]) * S,
    ]
}

/// Bezier net over the unit square of a bicubic B-spline patch (exact
/// conversion; same orientation as the grid).
pub(crate) fn from_grid(g: &Grid) -> Net {
    let mut tmp = [0.0f64; 48];
    let mut out = [0.0f64; 48];
    for c in 0..3 {
        let o = c * 16;
        // Along b (v) for each a-row of the grid.
        for a in 0..4 {
            let r = bspline_to_bezier([
                g[o + a * 4],
                g[o + a * 4 + 1],
                g[o + a * 4 + 2],
                g[o + a * 4 + 3],
            ]);
            tmp[o + a * 4..o + a * 4 + 4].copy_from_slice(&r);
        }
        // Along a (u) for each b-column.
        for b in 0..4 {
            let r =
                bspline_to_bezier([tmp[o + b], tmp[o + 4 + b], tmp[o + 8 + b], tmp[o + 12 + b]]);
            for a in 0..4 {
                out[o + a * 4 + b] = r[a];
            }
        }
    }
    out
}

/// The net of `n` (in a patch frame) seen from a frame rotated by `rho`:
/// local `(s, t)` maps to patch `rot_param(rho, s, t)` (see
/// `evaluator::rot_param`), so `out[a][b] = n[k][l]` with
/// `(k, l) = 3 rot_param(rho, a/3, b/3)`.
pub(crate) fn rotate(n: &Net, rho: u8) -> Net {
    if rho & 3 == 0 {
        return *n;
    }
    let mut out = [0.0f64; 48];
    for a in 0..4 {
        for b in 0..4 {
            let (k, l) = match rho & 3 {
                1 => (b, 3 - a),
                2 => (3 - a, 3 - b),
                _ => (3 - b, a),
            };
            for c in 0..3 {
                out[c * 16 + a * 4 + b] = n[c * 16 + k * 4 + l];
            }
        }
    }
    out
}

/// de Casteljau halves of one cubic.
#[inline(always)]
fn halves1(p: &[f64]) -> ([f64; 4], [f64; 4]) {
    let m01 = 0.5 * (p[0] + p[1]);
    let m12 = 0.5 * (p[1] + p[2]);
    let m23 = 0.5 * (p[2] + p[3]);
    let m012 = 0.5 * (m01 + m12);
    let m123 = 0.5 * (m12 + m23);
    let mid = 0.5 * (m012 + m123);
    ([p[0], m01, m012, mid], [mid, m123, m23, p[3]])
}

/// The nets of the four quadrants (0: s,t < 1/2; 1: s > 1/2, t < 1/2;
/// 2: s,t > 1/2; 3: s < 1/2, t > 1/2), each over its own unit square.
pub(crate) fn split4(n: &Net, out: &mut [Net; 4]) {
    for c in 0..3 {
        let o = c * 16;
        let row = |a: usize| -> [f64; 4] {
            [
                n[o + a * 4],
                n[o + a * 4 + 1],
                n[o + a * 4 + 2],
                n[o + a * 4 + 3],
            ]
        };
        let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
        // Along s (lanes b): rows of the halves s < 1/2 (lo) and s > 1/2 (hi).
        let mut m01 = [0.0; 4];
        let mut m12 = [0.0; 4];
        let mut m23 = [0.0; 4];
        for b in 0..4 {
            m01[b] = 0.5 * (r0[b] + r1[b]);
            m12[b] = 0.5 * (r1[b] + r2[b]);
            m23[b] = 0.5 * (r2[b] + r3[b]);
        }
        let mut m012 = [0.0; 4];
        let mut m123 = [0.0; 4];
        let mut mid = [0.0; 4];
        for b in 0..4 {
            m012[b] = 0.5 * (m01[b] + m12[b]);
            m123[b] = 0.5 * (m12[b] + m23[b]);
        }
        for b in 0..4 {
            mid[b] = 0.5 * (m012[b] + m123[b]);
        }
        let lo = [r0, m01, m012, mid];
        let hi = [mid, m123, m23, r3];
        // Along t within each row.
        for a in 0..4 {
            let (l0, l1) = halves1(&lo[a]);
            let (h0, h1) = halves1(&hi[a]);
            let at = o + a * 4;
            out[0][at..at + 4].copy_from_slice(&l0);
            out[3][at..at + 4].copy_from_slice(&l1);
            out[1][at..at + 4].copy_from_slice(&h0);
            out[2][at..at + 4].copy_from_slice(&h1);
        }
    }
}

/// `(a, b, c)` of [`crate::cellbound::grid_second_bounds`] from a Bezier
/// net: `|S_ss| <= a`, `|S_tt| <= b`, `|S_st| <= c` over the cell, and the
/// interpolation bound `lambda_max([[a, c], [c, b]]) / 3`.
#[inline]
pub(crate) fn bound(n: &Net) -> f64 {
    // Squared lengths of the second differences, summed over coordinates.
    let mut sa = [[0.0f64; 4]; 2]; // along s: [k][b]
    let mut sb = [[0.0f64; 2]; 4]; // along t: [a][l]
    let mut sc = [[0.0f64; 4]; 3]; // mixed: [k][l] (l < 3 used)
    for c in 0..3 {
        let o = c * 16;
        let r: [[f64; 4]; 4] = core::array::from_fn(|a| {
            [
                n[o + a * 4],
                n[o + a * 4 + 1],
                n[o + a * 4 + 2],
                n[o + a * 4 + 3],
            ]
        });
        for k in 0..2 {
            for b in 0..4 {
                let d = r[k + 2][b] - 2.0 * r[k + 1][b] + r[k][b];
                sa[k][b] += d * d;
            }
        }
        for a in 0..4 {
            for l in 0..2 {
                let d = r[a][l + 2] - 2.0 * r[a][l + 1] + r[a][l];
                sb[a][l] += d * d;
            }
        }
        for k in 0..3 {
            let mut e = [0.0f64; 4];
            for b in 0..4 {
                e[b] = r[k + 1][b] - r[k][b];
            }
            for l in 0..3 {
                let d = e[l + 1] - e[l];
                sc[k][l] += d * d;
            }
        }
    }
    let mut a2 = 0.0f64;
    for row in &sa {
        for &x in row {
            a2 = a2.max(x);
        }
    }
    let mut b2 = 0.0f64;
    for row in &sb {
        for &x in row {
            b2 = b2.max(x);
        }
    }
    let mut c2 = 0.0f64;
    for row in &sc {
        for &x in &row[..3] {
            c2 = c2.max(x);
        }
    }
    let a = 6.0 * libm::sqrt(a2);
    let b = 6.0 * libm::sqrt(b2);
    let c = 9.0 * libm::sqrt(c2);
    let m = 0.5 * (a + b) + libm::sqrt(0.25 * (a - b) * (a - b) + c * c);
    m / 3.0
}

#[inline(always)]
fn point(n: &Net, idx: usize) -> DVec3 {
    DVec3::new(n[idx], n[16 + idx], n[32 + idx])
}

/// Position of corner `q` (without the frame's offset).
#[inline]
pub(crate) fn corner(n: &Net, q: usize) -> DVec3 {
    point(n, CORNER[q & 3])
}

/// Longer diagonal of the corner quad.
#[inline]
pub(crate) fn diagonal(n: &Net) -> f64 {
    let d0 = (corner(n, 2) - corner(n, 0)).length();
    let d1 = (corner(n, 3) - corner(n, 1)).length();
    d0.max(d1)
}

/// A lower bound `g` of `|S(x + h, y + h) - S(x, y)| / h` over the cell (in
/// its own coordinates), or a non-positive number: with `u` the direction
/// of the cell's main diagonal, `<S_s, u> >= min_k <3 (P[a+1][b] - P[a][b]), u>`
/// and likewise for `S_t` (derivative nets and the convex hull property),
/// and the diagonal of any sub-cell of side h is at least
/// `h (min <S_s, u> + min <S_t, u>)` long.
pub(crate) fn diagonal_rate(n: &Net) -> f64 {
    let d = corner(n, 2) - corner(n, 0);
    let l = d.length();
    if !(l > 0.0 && l.is_finite()) {
        return 0.0;
    }
    let u = d / l;
    let (mut ms, mut mt) = (f64::INFINITY, f64::INFINITY);
    for a in 0..4 {
        for b in 0..4 {
            let p = point(n, a * 4 + b);
            if a < 3 {
                ms = ms.min(3.0 * (point(n, (a + 1) * 4 + b) - p).dot(u));
            }
            if b < 3 {
                mt = mt.min(3.0 * (point(n, a * 4 + b + 1) - p).dot(u));
            }
        }
    }
    ms + mt
}

/// Unit normal `normalize(S_s x S_t)` at corner `q` from the first control
/// point differences (exact tangent directions); `None` where the net is
/// degenerate there.
#[inline]
pub(crate) fn corner_normal(n: &Net, q: usize) -> Option<DVec3> {
    // (index of the later, index of the earlier) control point along s and t.
    let (ds, dt) = match q & 3 {
        0 => ((4, 0), (1, 0)),
        1 => ((12, 8), (13, 12)),
        2 => ((15, 11), (15, 14)),
        _ => ((7, 3), (3, 2)),
    };
    let du = point(n, ds.0) - point(n, ds.1);
    let dv = point(n, dt.0) - point(n, dt.1);
    let c = du.cross(dv);
    let l2 = c.length_squared();
    let scale = du.length_squared() * dv.length_squared();
    if l2.is_normal() && l2 > 1e-24 * scale {
        Some(c * (1.0 / libm::sqrt(l2)))
    } else {
        None
    }
}
