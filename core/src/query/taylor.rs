//! Local models of a polynomial cell, shared by the queries: position and
//! first derivatives of a Bezier net at a point, and the guaranteed bounds
//! `|S_ss| <= a`, `|S_tt| <= b`, `|S_st| <= c` over the cell (second
//! differences of the net and the convex hull property, as
//! [`crate::bounds::cell`] uses them, \[CL-R ch. 7\]).

use super::cell::Cell;
use super::krawczyk::bernstein;
use crate::math::bezier::{point, second_differences};
use glam::DVec3;

/// Quadratic Bernstein basis at `s`.
#[inline]
fn bernstein2(s: f64) -> [f64; 3] {
    let r = 1.0 - s;
    [r * r, 2.0 * s * r, s * s]
}

/// `S`, `S_s`, `S_t` of the cell's net (with its offset) at cell
/// coordinates `(s, t)`.
pub(crate) fn net_eval(c: &Cell, s: f64, t: f64) -> (DVec3, DVec3, DVec3) {
    let (bs, bt) = (bernstein(s), bernstein(t));
    let (ds, dt) = (bernstein2(s), bernstein2(t));
    let p = |a: usize, b: usize| point(&c.net, a * 4 + b);
    let (mut x, mut xs, mut xt) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for a in 0..4 {
        for b in 0..4 {
            x += p(a, b) * (bs[a] * bt[b]);
            if a < 3 {
                xs += (p(a + 1, b) - p(a, b)) * (3.0 * ds[a] * bt[b]);
            }
            if b < 3 {
                xt += (p(a, b + 1) - p(a, b)) * (3.0 * bs[a] * dt[b]);
            }
        }
    }
    (x + c.off, xs, xt)
}

/// `[a, b, c]`: bounds of `|S_ss|`, `|S_tt|`, `|S_st|` over the cell (cell
/// coordinates).
pub(crate) fn second_bounds(c: &Cell) -> [f64; 3] {
    let mut m = [0.0f64; 3];
    second_differences(
        |k, l| point(&c.net, k * 4 + l),
        |kind, d: DVec3| m[kind] = m[kind].max(d.length()),
    );
    [6.0 * m[0], 6.0 * m[1], 9.0 * m[2]]
}

/// Distance from `q` to the parallelogram `o + a e1 + b e2`,
/// `(a, b) in [0, 1]^2`.
pub(crate) fn parallelogram_distance(q: DVec3, o: DVec3, e1: DVec3, e2: DVec3) -> f64 {
    let r = q - o;
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (b1, b2) = (r.dot(e1), r.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if det > 1e-300 {
        let a = (b1 * g22 - b2 * g12) / det;
        let b = (b2 * g11 - b1 * g12) / det;
        if (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b) {
            return (r - a * e1 - b * e2).length();
        }
    }
    let seg = |p: DVec3, e: DVec3| {
        let l2 = e.length_squared();
        let x = if l2 > 0.0 {
            ((q - p).dot(e) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (q - p - x * e).length()
    };
    seg(o, e1)
        .min(seg(o, e2))
        .min(seg(o + e1, e2))
        .min(seg(o + e2, e1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallelogram_distance_cases() {
        let (o, e1, e2) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let d = |q: DVec3| parallelogram_distance(q, o, e1, e2);
        assert!((d(DVec3::new(0.5, 0.5, 2.0)) - 2.0).abs() < 1e-15);
        assert!((d(DVec3::new(2.0, 0.5, 0.0)) - 1.0).abs() < 1e-15);
        assert!((d(DVec3::new(2.0, 2.0, 0.0)) - 2f64.sqrt()).abs() < 1e-15);
        // Degenerate (a segment).
        let s = parallelogram_distance(DVec3::new(0.5, 1.0, 0.0), o, e1, DVec3::ZERO);
        assert!((s - 1.0).abs() < 1e-15);
    }
}
