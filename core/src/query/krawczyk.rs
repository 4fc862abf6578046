//! Certified zeros of a planar bicubic map `F: [0,1]^2 -> R^2` given by its
//! Bezier net (two coordinates of 16 control points), by the Krawczyk
//! operator (R. Krawczyk 1969; R. E. Moore, *Interval Analysis*):
//!
//! `K(X) = c - Y F(c) + (I - Y J(X)) (X - c)`, with `c` the centre of the
//! box `X`, `Y` the inverse of the midpoint of `J(X)` and `J(X)` an interval
//! matrix holding the Jacobian over `X`. Every zero of `F` in `X` lies in
//! `K(X)`; so `K(X) ∩ X = ∅` proves that `X` holds no zero, and iterating
//! `X <- K(X) ∩ X` narrows a box that holds every zero of `X`.
//!
//! `J` is taken over the whole cell once: the derivative nets
//! `3 (P[a+1][b] - P[a][b])` and `3 (P[a][b+1] - P[a][b])` hold `F_s`
//! and `F_t` in their convex hulls. When `rho = || |I - Y J| ||_inf < 1`
//! the map `x -> x - Y F(x)` is a contraction on the cell, so the cell
//! holds **at most one** zero (and `F`'s Jacobian, hence the crossing's
//! orientation, keeps its sign there).

/// What [`solve`] found in the cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Solve {
    /// No zero in the cell (proven).
    Empty,
    /// At most one zero in the cell, and every zero of the cell lies in the
    /// box `[s0, s1] x [t0, t1]` (no wider than the target).
    Narrowed { s0: f64, s1: f64, t0: f64, t1: f64 },
    /// Nothing proven: split the cell.
    Unknown,
}

/// Cubic Bernstein basis at `s`.
#[inline]
pub(crate) fn bernstein(s: f64) -> [f64; 4] {
    let r = 1.0 - s;
    [r * r * r, 3.0 * s * r * r, 3.0 * s * s * r, s * s * s]
}

/// `F(s, t)` of the two-coordinate net `f` (`f[c][a*4 + b]`).
#[inline]
pub(crate) fn eval2(f: &[[f64; 16]; 2], s: f64, t: f64) -> [f64; 2] {
    let (bs, bt) = (bernstein(s), bernstein(t));
    let mut out = [0.0; 2];
    for (c, o) in out.iter_mut().enumerate() {
        let mut acc = 0.0;
        for a in 0..4 {
            let mut row = 0.0;
            for b in 0..4 {
                row += bt[b] * f[c][a * 4 + b];
            }
            acc += bs[a] * row;
        }
        *o = acc;
    }
    out
}

/// Interval hull `[lo, hi]` of `F_s` (`d = 0`) or `F_t` (`d = 1`) for
/// coordinate `c` over the cell.
fn derivative_hull(f: &[[f64; 16]; 2], c: usize, d: usize) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for a in 0..4 {
        for b in 0..4 {
            let (na, nb) = if d == 0 { (a + 1, b) } else { (a, b + 1) };
            if na > 3 || nb > 3 {
                continue;
            }
            let v = 3.0 * (f[c][na * 4 + nb] - f[c][a * 4 + b]);
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (lo, hi)
}

/// Product of the number `y` and the interval `[lo, hi]`.
#[inline]
fn scale(y: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
    if y >= 0.0 {
        (y * lo, y * hi)
    } else {
        (y * hi, y * lo)
    }
}

/// The zeros of `f` in the cell `[0, 1]^2` (see module docs): narrows the
/// box until both sides are at most `width`; `err` bounds the rounding
/// error of one evaluation of `F` and the distance of the net from the
/// exact one (absolute, per value: the derivative hull is widened by
/// `6 err`).
pub(crate) fn solve(f: &[[f64; 16]; 2], width: f64, err: f64) -> Solve {
    let mut j = [[(0.0, 0.0); 2]; 2];
    for (c, row) in j.iter_mut().enumerate() {
        for (d, e) in row.iter_mut().enumerate() {
            let h = derivative_hull(f, c, d);
            // A net moved by `err` per value moves its derivative net by
            // `6 err` (two differences, times 3).
            *e = (h.0 - 6.0 * err, h.1 + 6.0 * err);
        }
    }
    let m = |e: (f64, f64)| 0.5 * (e.0 + e.1);
    let (a, b, c, d) = (m(j[0][0]), m(j[0][1]), m(j[1][0]), m(j[1][1]));
    let det = a * d - b * c;
    let norm = a.abs().max(b.abs()).max(c.abs()).max(d.abs());
    if det.abs() <= 1e-12 * norm * norm || !det.is_finite() {
        return Solve::Unknown;
    }
    let y = [[d / det, -b / det], [-c / det, a / det]];
    // |I - Y J| entrywise (interval magnitude) and its row sums.
    let mut mag = [[0.0f64; 2]; 2];
    for i in 0..2 {
        for k in 0..2 {
            let (p, q) = (scale(y[i][0], j[0][k]), scale(y[i][1], j[1][k]));
            let (lo, hi) = (p.0 + q.0, p.1 + q.1);
            let id = if i == k { 1.0 } else { 0.0 };
            // Rounding of the products: a relative margin.
            let slack = 1e-14 * (lo.abs() + hi.abs());
            mag[i][k] = (id - lo).abs().max((hi - id).abs()) + slack;
        }
    }
    let rho = (mag[0][0] + mag[0][1]).max(mag[1][0] + mag[1][1]);
    // Rounding of Y F(c) from the rounding of F(c).
    let yerr = [
        (y[0][0].abs() + y[0][1].abs()) * err,
        (y[1][0].abs() + y[1][1].abs()) * err,
    ];
    let (mut s0, mut s1, mut t0, mut t1) = (0.0f64, 1.0f64, 0.0f64, 1.0f64);
    for _ in 0..200 {
        let (cs, ct) = (0.5 * (s0 + s1), 0.5 * (t0 + t1));
        let (rs, rt) = (0.5 * (s1 - s0), 0.5 * (t1 - t0));
        let fc = eval2(f, cs, ct);
        if !(fc[0].is_finite() && fc[1].is_finite()) {
            return Solve::Unknown;
        }
        let ns = cs - (y[0][0] * fc[0] + y[0][1] * fc[1]);
        let nt = ct - (y[1][0] * fc[0] + y[1][1] * fc[1]);
        let es = mag[0][0] * rs + mag[0][1] * rt + yerr[0] + 4.0 * f64::EPSILON * ns.abs();
        let et = mag[1][0] * rs + mag[1][1] * rt + yerr[1] + 4.0 * f64::EPSILON * nt.abs();
        let (a0, a1) = ((ns - es).max(s0), (ns + es).min(s1));
        let (b0, b1) = ((nt - et).max(t0), (nt + et).min(t1));
        if a0 > a1 || b0 > b1 {
            return Solve::Empty;
        }
        if rho >= 1.0 {
            // Exclusion only: no uniqueness, no narrowing claimed.
            return Solve::Unknown;
        }
        if a1 - a0 <= width && b1 - b0 <= width {
            return Solve::Narrowed {
                s0: a0,
                s1: a1,
                t0: b0,
                t1: b1,
            };
        }
        // Stalled (rounding or rho near 1): let the caller split.
        if (a1 - a0) > 0.999 * (s1 - s0) && (b1 - b0) > 0.999 * (t1 - t0) {
            return Solve::Unknown;
        }
        (s0, s1, t0, t1) = (a0, a1, b0, b1);
    }
    Solve::Unknown
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Net of the bilinear-like map `F(s, t) = (s - s*, t - t*) + small
    /// cubic terms`, degree-elevated to a bicubic net.
    fn net(f: impl Fn(f64, f64) -> [f64; 2]) -> [[f64; 16]; 2] {
        // Interpolate at the 4 x 4 grid and convert: F here is at most
        // bicubic, so sample the polynomial's control points by solving the
        // Bernstein system on the Chebyshev-free grid a/3.
        let inv = [
            [1.0, 0.0, 0.0, 0.0],
            [-5.0 / 6.0, 3.0, -1.5, 1.0 / 3.0],
            [1.0 / 3.0, -1.5, 3.0, -5.0 / 6.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let mut vals = [[[0.0; 4]; 4]; 2];
        for a in 0..4 {
            for b in 0..4 {
                let v = f(a as f64 / 3.0, b as f64 / 3.0);
                vals[0][a][b] = v[0];
                vals[1][a][b] = v[1];
            }
        }
        let mut out = [[0.0; 16]; 2];
        for c in 0..2 {
            for a in 0..4 {
                for b in 0..4 {
                    let mut acc = 0.0;
                    for k in 0..4 {
                        for l in 0..4 {
                            acc += inv[a][k] * inv[b][l] * vals[c][k][l];
                        }
                    }
                    out[c][a * 4 + b] = acc;
                }
            }
        }
        out
    }

    #[test]
    fn finds_and_excludes() {
        let f = |s0: f64, t0: f64| {
            net(move |s, t| [s - s0 + 0.1 * t * t * s, t - t0 + 0.05 * s * s * s - 0.02])
        };
        // The interpolation is exact: eval2 reproduces F.
        let g = f(0.3, 0.6);
        let v = eval2(&g, 0.2, 0.7);
        assert!((v[0] - (0.2 - 0.3 + 0.1 * 0.49 * 0.2)).abs() < 1e-14);
        match solve(&g, 1e-12, 1e-16) {
            Solve::Narrowed { s0, s1, t0, t1 } => {
                let r = eval2(&g, 0.5 * (s0 + s1), 0.5 * (t0 + t1));
                assert!(r[0].abs() < 1e-11 && r[1].abs() < 1e-11, "{r:?}");
                assert!(s1 - s0 <= 1e-12 && t1 - t0 <= 1e-12);
            }
            o => panic!("{o:?}"),
        }
        assert_eq!(solve(&f(3.0, 0.5), 1e-12, 1e-16), Solve::Empty);
        assert_eq!(solve(&f(0.5, -2.0), 1e-12, 1e-16), Solve::Empty);
        // A fold (det changes sign): nothing proven.
        let fold = net(|s, t| [(s - 0.5) * (s - 0.5) - 0.01, t - 0.5]);
        assert_eq!(solve(&fold, 1e-12, 1e-16), Solve::Unknown);
    }
}
