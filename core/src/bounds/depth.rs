//! Subdivision depth for a tolerance (Cheng & Lai report ch. 3).
//!
//! "Depth" = number of uniform Catmull-Clark steps after which the control
//! mesh of a patch lies within `eps` of its limit surface:
//! `max ||L(u,v) - S(u,v)|| <= eps`, L the bilinear maps of the refined
//! control faces. All bounds use the second-order norm `M`, the largest
//! Euclidean norm of the second-order forward differences (SOFDs) of the
//! patch's control points.
//!
//! * Regular patch, Lemma 1: distance <= M/3, and M shrinks by 1/4 per step,
//!   so `depth = ceil(log4(M / (3 eps)))`.
//! * Extraordinary patch, old technique (Theorem 6): distance after k steps
//!   <= `c_n r^k M`, with Lemma 2's rate r (2/3, 18/25, 3/4 + (8n-46)/(4n^2))
//!   and Lemma 5's constant c_n (1, 5/7, 4n/(n^2-8n+46), n^2/(2(n^2-8n+46)),
//!   the last from the geometric series; the report prints a 4 there, see
//!   DIGEST §3.7). Standard weights only.
//! * Extraordinary patch, matrix technique (Theorem 11): with the group-I SOFD
//!   matrix `A` (2n x (2n+1)) and the 1-ring subdivision matrix `Lambda`,
//!   `r_i = ||A Lambda^i A^+||_inf`; `M_{2j} <= r_2^j M`, `M_{2j+1} <= r_1 r_2^j M`,
//!   and the distance at level i is <= `C_n M_i` where `C_n` is the supremum
//!   over m of the bound (3.17). The report takes `C_n` as the m -> infinity
//!   limit `(1 + r_1)/(min(n,8)(1 - r_2))` (Lemma 10), which fails for n = 8
//!   (DIGEST §3.5); we take the true supremum, so the bound holds for all n.
//!   `depth = min(2l, 2k+1)`, the smallest even / odd level meeting eps.
//!
//! `M` here is the maximum over group I (`2V - E_i - E_(i+2)`,
//! `2E_(i+1) - F_i - F_(i+1)`) and over every row/column SOFD of the 4x4 grid
//! that exists around the patch (which contains group II), so it is never
//! smaller than the report's M.

use crate::error::Error;
use crate::math::linalg::null_space;
use crate::mesh::stencil::{label_at, Mat, MAX_K};
use glam::DVec3;

/// Which bound to use for extraordinary patches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Method {
    /// Theorem 6 (Lemmas 2-5); standard weights only.
    Old = 0,
    /// Theorem 11 (matrix technique).
    New = 1,
    /// The smaller valid depth of all methods.
    Best = 2,
    /// Measured norms: the second-order norms of the exactly subdivided
    /// control points at each level (`A^i G` for the extraordinary part, the
    /// regular sub-patches `G_{m,b}` with Lemma 1's rate), with Theorem 11's
    /// constant for the extraordinary part (the report: "the same bound
    /// applies at any level i with M_i in place of M_0"). Never larger than
    /// `New` (it replaces the estimate `M_i <= r_i M_0` by the true `M_i`).
    Tight = 3,
}

/// Per-valence constants of both techniques.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rates {
    /// Valence.
    pub n: usize,
    /// `r_1 = ||A Lambda A^+||_inf`.
    pub r1: f64,
    /// `r_2 = ||A Lambda^2 A^+||_inf`.
    pub r2: f64,
    /// Supremum over m of the bound (3.17) per unit M (Theorem 11's constant).
    pub c_new: f64,
    /// The report's Lemma 10 constant `(1 + r1) / (min(n,8) (1 - r2))`.
    pub c_lemma10: f64,
    /// Lemma 2 rate of the old technique (0 when not applicable).
    pub r_old: f64,
    /// Lemma 5 constant of the old technique (0 when not applicable).
    pub c_old: f64,
}

/// Rate `r` of Lemma 2 and constant `c_n` of Lemma 5 (standard weights).
pub fn old_constants(n: usize) -> (f64, f64) {
    let nf = n as f64;
    let q = nf * nf - 8.0 * nf + 46.0;
    let r = match n {
        3 => 2.0 / 3.0,
        4 => 0.25,
        5 => 18.0 / 25.0,
        _ => 0.75 + (8.0 * nf - 46.0) / (4.0 * nf * nf),
    };
    let c = match n {
        3 => 1.0,
        4 => 1.0 / 3.0,
        5 => 5.0 / 7.0,
        6..=8 => 4.0 * nf / q,
        _ => nf * nf / (2.0 * q),
    };
    (r, c)
}

/// Computes [`Rates`] for valence `n` from `lambda`, the (2n+1) x (2n+1)
/// 1-ring subdivision matrix in label order (the top-left block of
/// [`crate::eigen::BuildScratch::subdivision_matrix`]). `standard` enables the old
/// technique's constants. No heap: about 4 K x K scratch matrices on the stack.
pub fn rates(n: usize, lambda: &Mat, standard: bool) -> Result<Rates, Error> {
    let fail = Error::TableBuildFailed { valence: n as u32 };
    let m = 2 * n + 1; // columns of A
    let rows = 2 * n;
    if m > MAX_K {
        return Err(fail);
    }
    // A: group-I SOFDs.
    let mut a = [[0.0f64; MAX_K]; MAX_K];
    for i in 0..n {
        a[i][0] += 2.0;
        a[i][1 + 2 * i] -= 1.0;
        a[i][1 + 2 * ((i + 2) % n)] -= 1.0;
        a[n + i][1 + 2 * ((i + 1) % n)] += 2.0;
        a[n + i][2 + 2 * i] -= 1.0;
        a[n + i][2 + 2 * ((i + 1) % n)] -= 1.0;
    }
    // Null space of A (pad to square with zero rows), orthonormalised.
    let mut sq = a;
    let mut nul = [[0.0f64; MAX_K]; MAX_K];
    let dim = null_space(&mut sq, m, 1e-10, &mut nul, 0);
    for c in 0..dim {
        for p in 0..c {
            let d: f64 = (0..m).map(|i| nul[i][c] * nul[i][p]).sum();
            for i in 0..m {
                nul[i][c] -= d * nul[i][p];
            }
        }
        let norm = libm::sqrt((0..m).map(|i| nul[i][c] * nul[i][c]).sum());
        if norm < 1e-12 {
            return Err(fail);
        }
        for i in 0..m {
            nul[i][c] /= norm;
        }
    }
    // A^+ = (A^T A + P)^-1 A^T, P the projector onto null(A).
    let mut g = [[0.0f64; MAX_K]; MAX_K];
    for i in 0..m {
        for j in 0..m {
            let mut s = 0.0;
            for r in 0..rows {
                s += a[r][i] * a[r][j];
            }
            for c in 0..dim {
                s += nul[i][c] * nul[j][c];
            }
            g[i][j] = s;
        }
    }
    let mut pinv = [[0.0f64; MAX_K]; MAX_K]; // m x rows
    solve_into(&mut g, m, &a, rows, &mut pinv).ok_or(fail)?;
    // r_i = ||A Lambda^i A^+||_inf for i = 1, 2.
    let mut cur = pinv; // Lambda^0 A^+
    let mut r = [0.0f64; 2];
    for ri in r.iter_mut() {
        let mut next = [[0.0f64; MAX_K]; MAX_K];
        for i in 0..m {
            for j in 0..rows {
                let mut s = 0.0;
                for t in 0..m {
                    s += lambda[i][t] * cur[t][j];
                }
                next[i][j] = s;
            }
        }
        cur = next;
        let mut norm = 0.0f64;
        for row in a.iter().take(rows) {
            let mut sum = 0.0;
            for j in 0..rows {
                let mut s = 0.0;
                for t in 0..m {
                    s += row[t] * cur[t][j];
                }
                sum += libm::fabs(s);
            }
            norm = norm.max(sum);
        }
        *ri = norm;
    }
    let (r1, r2) = (r[0], r[1]);
    let c = 1.0 / (n.min(8) as f64);
    let mut out = Rates {
        n,
        r1,
        r2,
        ..Rates::default()
    };
    if r2 < 1.0 {
        out.c_lemma10 = c * (1.0 + r1) / (1.0 - r2);
        // Supremum over m of (3.17): m = 2j and m = 2j + 1; the limit is c_lemma10.
        let mut sup = out.c_lemma10;
        let mut p = 1.0; // r2^j
        for j in 0..2000 {
            let geo = (1.0 - p) / (1.0 - r2);
            if j >= 1 {
                let geo1 = (1.0 - p / r2) / (1.0 - r2);
                sup = sup.max(c * (geo + r1 * geo1) + r1 * (p / r2) / 4.0 + p / 3.0);
            }
            sup = sup.max(c * (geo + r1 * geo) + p / 4.0 + r1 * p / 3.0);
            p *= r2;
            if p < 1e-300 {
                break;
            }
        }
        out.c_new = sup;
    }
    if standard {
        let (ro, co) = old_constants(n);
        out.r_old = ro;
        out.c_old = co;
    }
    Ok(out)
}

/// Solves `g X = A^T` (g is m x m, A is rows x m) into `x` (m x rows) by
/// Gauss-Jordan with partial pivoting.
fn solve_into(g: &mut Mat, m: usize, a: &Mat, rows: usize, x: &mut Mat) -> Option<()> {
    for i in 0..m {
        for j in 0..rows {
            x[i][j] = a[j][i];
        }
    }
    for c in 0..m {
        let mut p = c;
        for r in c + 1..m {
            if libm::fabs(g[r][c]) > libm::fabs(g[p][c]) {
                p = r;
            }
        }
        if libm::fabs(g[p][c]) < 1e-14 {
            return None;
        }
        g.swap(c, p);
        x.swap(c, p);
        let d = g[c][c];
        for j in 0..m {
            g[c][j] /= d;
        }
        for j in 0..rows {
            x[c][j] /= d;
        }
        for r in 0..m {
            if r != c {
                let f = g[r][c];
                if f != 0.0 {
                    for j in 0..m {
                        g[r][j] -= f * g[c][j];
                    }
                    for j in 0..rows {
                        x[r][j] -= f * x[c][j];
                    }
                }
            }
        }
    }
    Some(())
}

/// Second-order norm `M` of a patch from its 2n+8 control points in label
/// order (see module docs for which SOFDs count).
pub fn second_order_norm(n: usize, g: &[DVec3]) -> f64 {
    let mut m = 0.0f64;
    if n != 4 {
        for i in 0..n {
            let a = g[0] * 2.0 - g[1 + 2 * i] - g[1 + 2 * ((i + 2) % n)];
            let b = g[1 + 2 * ((i + 1) % n)] * 2.0 - g[2 + 2 * i] - g[2 + 2 * ((i + 1) % n)];
            m = m.max(a.length()).max(b.length());
        }
    }
    let at = |x: i32, y: i32| label_at(n, x, y).map(|l| g[l]);
    for y in -1..=2 {
        for x in 0..=1 {
            if let (Some(a), Some(b), Some(c)) = (at(x - 1, y), at(x, y), at(x + 1, y)) {
                m = m.max((b * 2.0 - a - c).length());
            }
        }
    }
    for x in -1..=2 {
        for y in 0..=1 {
            if let (Some(a), Some(b), Some(c)) = (at(x, y - 1), at(x, y), at(x, y + 1)) {
                m = m.max((b * 2.0 - a - c).length());
            }
        }
    }
    m
}

/// Smallest integer `d >= 0` with `c * q^d * m <= eps` (q in (0,1)); None if
/// no such d below 10_000 (q >= 1 or not finite).
fn levels(c: f64, q: f64, m: f64, eps: f64) -> Option<u32> {
    if !(q.is_finite() && q > 0.0 && q < 1.0 && c.is_finite() && m.is_finite()) {
        return None;
    }
    let mut bound = c * m;
    for d in 0..10_000u32 {
        if bound <= eps {
            return Some(d);
        }
        bound *= q;
    }
    None
}

/// Depth of a regular patch (Lemma 1) with second-order norm `m`.
pub fn regular_depth(m: f64, eps: f64) -> u32 {
    levels(1.0 / 3.0, 0.25, m, eps).unwrap_or(u32::MAX)
}

/// Depth of an extraordinary patch with norm `m` by Theorem 6, if applicable.
pub fn old_depth(r: &Rates, m: f64, eps: f64) -> Option<u32> {
    if r.r_old == 0.0 {
        return None;
    }
    levels(r.c_old, r.r_old, m, eps)
}

/// Depth of an extraordinary patch with norm `m` by Theorem 11:
/// `min(2l, 2k+1)`.
pub fn new_depth(r: &Rates, m: f64, eps: f64) -> Option<u32> {
    if r.c_new == 0.0 {
        return None;
    }
    let l = levels(r.c_new, r.r2, m, eps)?;
    let k = levels(r.c_new * r.r1, r.r2, m, eps)?;
    Some((2 * l).min(2 * k + 1))
}

/// Depth by `method` (Best = the smaller valid one).
pub fn ev_depth(r: &Rates, m: f64, eps: f64, method: Method) -> Option<u32> {
    match method {
        Method::Old => old_depth(r, m, eps),
        Method::New => new_depth(r, m, eps),
        Method::Tight => new_depth(r, m, eps),
        Method::Best => match (old_depth(r, m, eps), new_depth(r, m, eps)) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        },
    }
}

/// Second-order norm of a regular 4x4 grid (structure of arrays, see
/// [`crate::math::bspline::Grid`]): the 16 row and column SOFDs (Lemma 1's M).
pub fn grid_norm(g: &crate::math::bspline::Grid) -> f64 {
    let p = |i: usize, j: usize| DVec3::new(g[i * 4 + j], g[16 + i * 4 + j], g[32 + i * 4 + j]);
    let mut m = 0.0f64;
    for a in 0..4 {
        for b in 1..3 {
            m = m.max((p(b, a) * 2.0 - p(b - 1, a) - p(b + 1, a)).length());
            m = m.max((p(a, b) * 2.0 - p(a, b - 1) - p(a, b + 1)).length());
        }
    }
    m
}

/// [`Method::Tight`] depth of an extraordinary patch from its eigen
/// projection `ghat` (see [`crate::eigen::ValenceTable::project`]): the smallest
/// level `i` at which `C_n M(A^i G) <= eps` and every regular sub-patch
/// `G_{m,b}` (m <= i) satisfies `M(G_{m,b}) / (3 * 4^(i-m)) <= eps`.
/// None when the constants are unavailable or no level up to 200 suffices.
pub fn tight_depth(tab: &crate::eigen::ValenceTable, ghat: &[f64], eps: f64) -> Option<u32> {
    let c = tab.rates().c_new;
    if !(c > 0.0 && c.is_finite()) {
        return None;
    }
    let n = tab.valence();
    let k = 2 * n + 8;
    let mut pts = [DVec3::ZERO; MAX_K];
    let mut reg = 0.0f64; // max over m <= i of M(G_{m,b}) * 4^m
    let mut four_i = 1.0f64;
    for i in 0..=200u32 {
        if i >= 1 {
            four_i *= 4.0;
            for b in 1..=3 {
                let mut g = [0.0; 48];
                tab.sub_patch(ghat, i, b, true, &mut g);
                reg = reg.max(grid_norm(&g) * four_i);
            }
        }
        tab.level_points(ghat, i, &mut pts[..k]);
        let mi = second_order_norm(n, &pts[..k]);
        if c * mi <= eps && reg / (3.0 * four_i) <= eps {
            return Some(i);
        }
    }
    None
}
