//! Small dense linear algebra on fixed-size arrays (no heap): Gauss-Jordan
//! elimination with full pivoting for null spaces and inverses.

use crate::config::MAX_K;

/// A dense row of weights over the labels of a patch.
pub type Row = [f64; MAX_K];

/// A dense K x K matrix (row-major, only the leading K x K part is used).
pub type Mat = [[f64; MAX_K]; MAX_K];

/// Null space of the leading `k x k` block of `m` (destroyed), by Gauss-Jordan
/// elimination with full pivoting. Pivots below `tol` count as zero. The
/// null vectors are written as columns `col0..col0+dim` of `out`; returns the
/// dimension.
pub fn null_space(m: &mut Mat, k: usize, tol: f64, out: &mut Mat, col0: usize) -> usize {
    let mut perm = [0usize; MAX_K];
    for (i, p) in perm.iter_mut().enumerate().take(k) {
        *p = i;
    }
    let mut rank = 0;
    while rank < k {
        // Full pivot search.
        let (mut bi, mut bj, mut best) = (rank, rank, 0.0f64);
        for (i, row) in m.iter().enumerate().take(k).skip(rank) {
            for (j, &v) in row.iter().enumerate().take(k).skip(rank) {
                if v.abs() > best {
                    best = v.abs();
                    bi = i;
                    bj = j;
                }
            }
        }
        if best <= tol {
            break;
        }
        m.swap(rank, bi);
        if bj != rank {
            for row in m.iter_mut().take(k) {
                row.swap(rank, bj);
            }
            perm.swap(rank, bj);
        }
        let p = m[rank][rank];
        for j in 0..k {
            m[rank][j] /= p;
        }
        let prow = m[rank];
        for (i, row) in m.iter_mut().enumerate().take(k) {
            if i != rank {
                let f = row[rank];
                if f != 0.0 {
                    for j in rank..k {
                        row[j] -= f * prow[j];
                    }
                }
            }
        }
        rank += 1;
    }
    let dim = k - rank;
    for d in 0..dim {
        let fc = rank + d; // free column (permuted index)
        let c = col0 + d;
        if c >= MAX_K {
            break;
        }
        for row in out.iter_mut().take(k) {
            row[c] = 0.0;
        }
        out[perm[fc]][c] = 1.0;
        for i in 0..rank {
            out[perm[i]][c] = -m[i][fc];
        }
    }
    dim
}

/// Inverts the leading `g x g` block of `m` in place (g <= MAX_K) by
/// Gauss-Jordan with partial pivoting. Returns false when singular.
pub fn invert_small(m: &mut [[f64; 8]; 8], g: usize) -> bool {
    let mut inv = [[0.0; 8]; 8];
    for (i, row) in inv.iter_mut().enumerate().take(g) {
        row[i] = 1.0;
    }
    for c in 0..g {
        let mut p = c;
        for r in c + 1..g {
            if m[r][c].abs() > m[p][c].abs() {
                p = r;
            }
        }
        if m[p][c].abs() < 1e-300 {
            return false;
        }
        m.swap(c, p);
        inv.swap(c, p);
        let d = m[c][c];
        for j in 0..g {
            m[c][j] /= d;
            inv[c][j] /= d;
        }
        for r in 0..g {
            if r != c {
                let f = m[r][c];
                for j in 0..g {
                    m[r][j] -= f * m[c][j];
                    inv[r][j] -= f * inv[c][j];
                }
            }
        }
    }
    *m = inv;
    true
}

/// `x^e` for integer `e >= 0` by binary powering (no libm needed).
#[inline]
pub fn powi(mut x: f64, mut e: u32) -> f64 {
    let mut r = 1.0;
    while e > 0 {
        if e & 1 == 1 {
            r *= x;
        }
        x *= x;
        e >>= 1;
    }
    r
}

/// 2x2 matrix product `a b`.
#[inline]
pub fn mul2x2(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [
        [
            a[0][0] * b[0][0] + a[0][1] * b[1][0],
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
        ],
        [
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1],
        ],
    ]
}

/// 2x2 matrix power by binary powering.
#[inline]
pub fn pow2x2(m: [[f64; 2]; 2], mut e: u32) -> [[f64; 2]; 2] {
    let mul = mul2x2;
    let mut r = [[1.0, 0.0], [0.0, 1.0]];
    let mut x = m;
    while e > 0 {
        if e & 1 == 1 {
            r = mul(r, x);
        }
        x = mul(x, x);
        e >>= 1;
    }
    r
}
