//! Per-valence constants of the corner-cell flatness bound: how far each
//! eigen-basis function of an extraordinary patch is from a linear function
//! of the patch parameters.
//!
//! # The bound
//!
//! Near an extraordinary vertex the limit surface is its eigen expansion
//! (\[CL-R §2.4\]): on the corner cell `[0, 2^-k]^2`, with `w` in `[0, 1]^2`,
//! `S(2^-k w) = L + sum_c mu_c^k ghat_c Phi_c(w)` (columns with a real
//! eigenvalue `mu_c`; `Phi_c` is the basis function over the whole patch,
//! `Phi_c = mu_c^(m-1) X_b[c]` as a bicubic B-spline on region
//! `Omega_{m,b}`, and `Phi_c(w / 2) = mu_c Phi_c(w)`).
//!
//! For any linear `l_c(w) = alpha_c w_u + beta_c w_v`, the function
//! `A(w) = L + sum_c mu_c^k ghat_c l_c(w)` is affine in `w`, so every
//! linear interpolant `T` of `S` over a triangulation of limit points of
//! the cell reproduces it (`T[A] = A`) and
//! `|S - T[S]| = |(S - A) - T[S - A]| <= 2 max_cell |S - A|`
//! (`T[S - A]` is a convex combination of values of `S - A` in the cell).
//! With `G_c >= sup_w |Phi_c(w) - l_c(w)|`,
//! `max_cell |S - A| <= sum_c |mu_c|^k |ghat_c| G_c`.
//!
//! Two columns `c, c + 1` with the same eigenvalue (the frequencies `w` and
//! `n - w`, among them the characteristic map) are bounded together:
//! their part of `S - A` is `mu^k [ghat_c ghat_{c+1}] d(w)` with the
//! 2-vector `d = (Phi_c - l_c, Phi_{c+1} - l_{c+1})`, at most
//! `|mu|^k sigma_max([ghat_c ghat_{c+1}]) H_c` with `H_c >= sup |d|_2`
//! (the Bezier hull of the 2-vector nets, as below). For the usual
//! near-orthogonal pair of tangent coefficients that is about 0.7 of the
//! two separate terms; the smaller of the two is used.
//!
//! This replaces the radius bound (`l_c = 0`, `2 R_k`, the report's
//! "both within eps/2 of the limit point") by one that measures only how
//! far the surface bends away from a plane, and since `G_c <= F_c` (below)
//! it is never larger. For the subdominant columns (the characteristic
//! map) `G_c` is a small fraction of `F_c`, so corner cells are accepted
//! several levels earlier.
//!
//! # Computing `G_c`
//!
//! On `Omega_{m,b}` (`m >= 1`, local `(s, t)` in `[0, 1]^2`,
//! `w = 2^-m (o_b + (s, t))`, `o_1 = (1, 0)`, `o_2 = (1, 1)`, `o_3 = (0, 1)`),
//! `Phi_c - l_c = mu_c^(m-1) X_b[c](s, t) - 2^-m l_c(o_b + (s, t))`, a
//! bicubic whose Bezier net is `mu_c^(m-1) N_b - 2^-m l_c(o_b + (i, j) / 3)`
//! (`N_b` the exact Bezier net of the B-spline grid `X_b[c]`; a linear
//! function's Bezier points are its values at `(i/3, j/3)`). By the convex
//! hull property its maximum modulus is at most the largest net entry. The
//! supremum over `m` is taken term by term until the tail bound
//! `|mu_c|^(m-1) max|N| + 2^-m max|l|` (decreasing in `m`) falls below the
//! maximum so far. With `l_c = 0` this is at most `F_c = max|X_b[c]|` (Bezier
//! points are convex combinations of B-spline points), and `G_c` is the
//! smaller of that and the value for the `l_c` fitted to the net points of
//! the first levels (least squares, then Lawson's reweighting towards the
//! minimax fit; any `l_c` gives a valid bound, the fit only makes it small).

use crate::mesh::stencil::MAX_K;

/// Region offsets `o_b` (b = 1, 2, 3) in units of the region size.
const OFFSET: [(f64, f64); 3] = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];

/// Levels whose nets the least-squares fit uses.
const FIT_LEVELS: u32 = 2;

/// Most levels examined for the supremum (the tail bound is added if the
/// loop ends there).
const MAX_LEVELS: u32 = 400;

/// Bezier net over the unit square of a scalar bicubic B-spline grid
/// (index `i * 4 + j`, `i` along u), same layout.
pub(crate) fn bezier_net(g: &[f64; 16]) -> [f64; 16] {
    let n = crate::math::bezier::scalar_bezier_net(g, 0.0, 1.0, 0.0, 1.0);
    core::array::from_fn(|k| n[k / 4][k % 4])
}

/// Parameter `o_b + (i, j) / 3` of Bezier point `(i, j)` of region `b`
/// (0-based), in units of the region size.
#[inline]
fn at(b: usize, i: usize, j: usize) -> (f64, f64) {
    AT[b][i * 4 + j]
}

/// [`at`] for every point, computed at compile time.
const AT: [[(f64, f64); 16]; 3] = {
    let mut t = [[(0.0, 0.0); 16]; 3];
    let mut b = 0;
    while b < 3 {
        let mut k = 0;
        while k < 16 {
            t[b][k] = (
                OFFSET[b].0 + (k / 4) as f64 / 3.0,
                OFFSET[b].1 + (k % 4) as f64 / 3.0,
            );
            k += 1;
        }
        b += 1;
    }
    t
};

/// `sup_w |Phi - l|` bounded as in the module docs, for `l = (alpha, beta)`.
fn sup_distance(nets: &[[f64; 16]; 3], mu: f64, l: [f64; 2]) -> f64 {
    sup_norm([nets], [l], mu)
}

/// `sup_w |(Phi_1 - l_1, .., Phi_D - l_D)|_2` for `D` columns with the same
/// eigenvalue `mu`: the Euclidean norm is convex, so by the convex hull
/// property of the `D`-vector Bezier nets its maximum over a region is at
/// most the largest norm of a net point; the supremum over the levels ends
/// as in the module docs (the tail bound uses the largest norms of the
/// `Phi` and `l` parts).
fn sup_norm<const D: usize>(nets: [&[[f64; 16]; 3]; D], l: [[f64; 2]; D], mu: f64) -> f64 {
    // Squared norms are compared; one square root at the end.
    let (mut max_n2, mut max_l2) = (0.0f64, 0.0f64);
    for b in 0..3 {
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = at(b, i, j);
                let (mut n2, mut l2) = (0.0, 0.0);
                for d in 0..D {
                    let v = nets[d][b][i * 4 + j];
                    let w = l[d][0] * x + l[d][1] * y;
                    n2 += v * v;
                    l2 += w * w;
                }
                max_n2 = max_n2.max(n2);
                max_l2 = max_l2.max(l2);
            }
        }
    }
    let (max_n, max_l) = (libm::sqrt(max_n2), libm::sqrt(max_l2));
    let mut sup2 = 0.0f64;
    let (mut pm, mut h) = (1.0f64, 0.5f64); // mu^(m-1), 2^-m
    for _ in 0..MAX_LEVELS {
        let tail = libm::fabs(pm) * max_n + h * max_l;
        if tail * tail <= sup2 {
            return libm::sqrt(sup2);
        }
        for b in 0..3 {
            for i in 0..4 {
                for j in 0..4 {
                    let (x, y) = at(b, i, j);
                    let mut s2 = 0.0;
                    for d in 0..D {
                        let v = pm * nets[d][b][i * 4 + j] - h * (l[d][0] * x + l[d][1] * y);
                        s2 += v * v;
                    }
                    sup2 = sup2.max(s2);
                }
            }
        }
        pm *= mu;
        h *= 0.5;
    }
    libm::sqrt(sup2) + libm::fabs(pm) * max_n + h * max_l
}

/// Points `(x, y, f)` of the first [`FIT_LEVELS`] levels: the Bezier
/// points of `Phi` (value `f`) at their parameters `(x, y)`.
fn fit_points(nets: &[[f64; 16]; 3], mu: f64) -> [(f64, f64, f64); FIT_POINTS] {
    let mut pts = [(0.0, 0.0, 0.0); FIT_POINTS];
    let (mut pm, mut h) = (1.0f64, 0.5f64);
    let mut next = 0;
    for _ in 0..FIT_LEVELS {
        for (b, n) in nets.iter().enumerate() {
            for i in 0..4 {
                for j in 0..4 {
                    let (x, y) = at(b, i, j);
                    pts[next] = (h * x, h * y, pm * n[i * 4 + j]);
                    next += 1;
                }
            }
        }
        pm *= mu;
        h *= 0.5;
    }
    pts
}

/// Points used by the fit.
const FIT_POINTS: usize = 48 * FIT_LEVELS as usize;

/// Rounds of reweighting towards the minimax fit.
const FIT_ROUNDS: usize = 12;

/// The linear function fitted to `Phi` at the Bezier points of the first
/// [`FIT_LEVELS`] levels: least squares, then Lawson's reweighting (each
/// point's weight times its residual) towards the minimax fit; the round
/// with the smallest largest residual at those points is kept (any choice
/// gives a valid bound: [`column`] bounds the distance over the patch).
fn fit_linear(nets: &[[f64; 16]; 3], mu: f64) -> [f64; 2] {
    let pts = fit_points(nets, mu);
    let mut w = [1.0f64; FIT_POINTS];
    let mut best = ([0.0, 0.0], f64::INFINITY);
    for _ in 0..FIT_ROUNDS {
        let (mut sxx, mut sxy, mut syy, mut sx, mut sy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (&(x, y, f), &wi) in pts.iter().zip(w.iter()) {
            sxx += wi * x * x;
            sxy += wi * x * y;
            syy += wi * y * y;
            sx += wi * x * f;
            sy += wi * y * f;
        }
        let det = sxx * syy - sxy * sxy;
        if !det.is_normal() {
            break;
        }
        let l = [(sx * syy - sy * sxy) / det, (sy * sxx - sx * sxy) / det];
        let (mut total, mut worst) = (0.0, 0.0f64);
        for (&(x, y, f), wi) in pts.iter().zip(w.iter_mut()) {
            let r = libm::fabs(f - l[0] * x - l[1] * y);
            worst = worst.max(r);
            *wi *= r;
            total += *wi;
        }
        if worst < best.1 {
            best = (l, worst);
        }
        if !total.is_normal() {
            break;
        }
        for wi in w.iter_mut() {
            *wi /= total;
        }
    }
    best.0
}

/// `(G_c, l_c)` of one eigen column with real eigenvalue `mu` and level-1
/// B-spline grids `x[b]` (see the module docs). `G_c` carries a relative
/// margin for the rounding of its own computation.
pub(crate) fn column(x: [&[f64; 16]; 3], mu: f64) -> (f64, [f64; 2]) {
    let nets = [bezier_net(x[0]), bezier_net(x[1]), bezier_net(x[2])];
    let zero = sup_distance(&nets, mu, [0.0, 0.0]);
    let l = fit_linear(&nets, mu);
    let fitted = sup_distance(&nets, mu, l);
    let (g, l) = if fitted < zero {
        (fitted, l)
    } else {
        (zero, [0.0, 0.0])
    };
    (g * (1.0 + 1e-12) + 1e-15 * zero, l)
}

/// `G_c` and `l_c` for every column `c < k`; columns in the 2x2 block
/// (`skip`) and the eigenvalue-1 column get 0 (unused) and `l = 0`. For a
/// pair `(c, c + 1)` of columns with the same eigenvalue (and no third),
/// `pair[c]` is the joint bound `H_c >= sup_w |(Phi_c - l_c, Phi_{c+1} -
/// l_{c+1})|_2` (0 elsewhere): the pair's part of `S - A` at level `k` is
/// `mu^k [ghat_c ghat_{c+1}] (Phi_c - l_c, Phi_{c+1} - l_{c+1})`, at most
/// `|mu|^k sigma_max([ghat_c ghat_{c+1}]) H_c`.
pub(crate) fn columns(
    x: &[[[f64; 16]; MAX_K]; 3],
    mu: &[f64; MAX_K],
    k: usize,
    skip: Option<usize>,
    g: &mut [f64; MAX_K],
    l: &mut [[f64; 2]; MAX_K],
    pair: &mut [f64; MAX_K],
) {
    let k = k.min(MAX_K);
    let in_block = |c: usize| c == 0 || skip.is_some_and(|q| c == q || c == q + 1);
    for c in 0..k {
        pair[c] = 0.0;
        if in_block(c) {
            g[c] = 0.0;
            l[c] = [0.0; 2];
            continue;
        }
        let (gc, lc) = column([&x[0][c], &x[1][c], &x[2][c]], mu[c]);
        g[c] = gc;
        l[c] = lc;
    }
    let same = |a: usize, b: usize| b < k && mu[a].to_bits() == mu[b].to_bits();
    let mut c = 1;
    while c + 1 < k {
        if in_block(c) || in_block(c + 1) || !same(c, c + 1) {
            c += 1;
            continue;
        }
        let mut end = c + 2;
        while same(c, end) {
            end += 1;
        }
        if end == c + 2 {
            let net = |c: usize| [0, 1, 2].map(|b| bezier_net(&x[b][c]));
            let (na, nb) = (net(c), net(c + 1));
            let h = sup_norm([&na, &nb], [l[c], l[c + 1]], mu[c]);
            // Rounding: a few ulps of the net values.
            let big = [&na, &nb]
                .iter()
                .flat_map(|n| n.iter().flat_map(|r| r.iter()))
                .fold(0.0f64, |m, v| m.max(libm::fabs(*v)));
            pair[c] = h * (1.0 + 1e-12) + 1e-14 * big;
        }
        c = end;
    }
}
