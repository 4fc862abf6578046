//! The assembled normal matrix of \[CL-R eq. 4.6\] as compressed rows of
//! symmetric 3x3 blocks (upper triangle) over the Type II unknowns: its
//! product and the symmetric Gauss-Seidel sweep. Built by
//! [`super::assembled`].

use super::ring::{add3, get3, set3};
use glam::DVec3;

/// The assembled normal matrix over the unknowns `n1..m`.
pub(crate) struct Matrix<'a> {
    /// Row starts (`m - n1 + 1`), indices into `cols`.
    pub(crate) start: &'a [u32],
    /// Column (vertex of `G`) of each block of the upper triangle, sorted
    /// within a row: the diagonal block first.
    pub(crate) cols: &'a [u32],
    /// Symmetric 3x3 blocks, 6 values each: `xx, xy, xz, yy, yz, zz`.
    pub(crate) vals: &'a [f64],
}

impl Matrix<'_> {
    /// `ap = S p` over the unknowns `n1..`; Type I entries of `ap` zero,
    /// those of `p` ignored. Each stored block serves its row and, for
    /// off-diagonal blocks, its transpose's row.
    pub(crate) fn apply(&self, n1: usize, p: &[f64], ap: &mut [f64]) {
        ap.fill(0.0);
        let rows = self.start.len() - 1;
        for r in 0..rows {
            let v = n1 + r;
            let (b0, b1) = (self.start[r] as usize, self.start[r + 1] as usize);
            let pv = get3(p, v);
            let mut s = sym3(&self.vals[6 * b0..6 * b0 + 6], pv);
            // Slices of fixed length, so that the loop body indexes
            // without bounds checks.
            let cols = &self.cols[b0 + 1..b1];
            let vals = &self.vals[6 * (b0 + 1)..6 * b1];
            for (&c, a) in cols.iter().zip(vals.chunks_exact(6)) {
                let c = 3 * c as usize;
                let x = &p[c..c + 3];
                s += sym3(a, DVec3::new(x[0], x[1], x[2]));
                let t = sym3(a, pv);
                let y = &mut ap[c..c + 3];
                y[0] += t.x;
                y[1] += t.y;
                y[2] += t.z;
            }
            add3(ap, v, s);
        }
    }

    /// `z = M^-1 r` for the symmetric Gauss-Seidel splitting `M = (D + L)
    /// D^-1 (D + U)` (`L = U^T`; `dinv`: the inverse diagonal blocks per
    /// vertex); Type I entries zero. The forward sweep runs by columns of
    /// the stored upper triangle, the backward one by its rows.
    pub(crate) fn sgs(&self, n1: usize, dinv: &[f64], r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
        z[..3 * n1].fill(0.0);
        let rows = self.start.len() - 1;
        // Forward: (D + L) y = r; z_j -= A_ij y_i once y_i is known.
        for i in 0..rows {
            let v = n1 + i;
            let y = mul3(&dinv[9 * v..9 * v + 9], get3(z, v));
            set3(z, v, y);
            for b in self.start[i] as usize + 1..self.start[i + 1] as usize {
                add3(
                    z,
                    self.cols[b] as usize,
                    -sym3(&self.vals[6 * b..6 * b + 6], y),
                );
            }
        }
        // Backward: (D + U) z = D y, i.e. z_i = y_i - D_i^-1 U_i z.
        for i in (0..rows).rev() {
            let v = n1 + i;
            let mut s = DVec3::ZERO;
            for b in self.start[i] as usize + 1..self.start[i + 1] as usize {
                s += sym3(&self.vals[6 * b..6 * b + 6], get3(z, self.cols[b] as usize));
            }
            let y = get3(z, v) - mul3(&dinv[9 * v..9 * v + 9], s);
            set3(z, v, y);
        }
    }
}

#[inline]
fn sym3(a: &[f64], x: DVec3) -> DVec3 {
    DVec3::new(
        a[0] * x.x + a[1] * x.y + a[2] * x.z,
        a[1] * x.x + a[3] * x.y + a[4] * x.z,
        a[2] * x.x + a[4] * x.y + a[5] * x.z,
    )
}

#[inline]
fn mul3(b: &[f64], x: DVec3) -> DVec3 {
    DVec3::new(
        b[0] * x.x + b[1] * x.y + b[2] * x.z,
        b[3] * x.x + b[4] * x.y + b[5] * x.z,
        b[6] * x.x + b[7] * x.y + b[8] * x.z,
    )
}
