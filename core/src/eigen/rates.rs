//! Per-valence subdivision-depth rates (\[CL-R ch. 3\]), computed with the
//! eigen tables: the matrix technique's `r_1 = ||A Lambda A^+||_inf`,
//! `r_2 = ||A Lambda^2 A^+||_inf` (pseudo-inverse via
//! `(A^T A + P_null)^-1 A^T`) and Theorem 11's constant, and the old
//! technique's Lemma 2 rate and Lemma 5 constant. The depth formulas that
//! use them are in [`crate::bounds::depth`].

use crate::config::MAX_K;
use crate::error::Error;
use crate::math::linalg::{null_space, Mat};
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
