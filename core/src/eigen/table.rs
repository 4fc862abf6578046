//! Per-valence eigen tables and the exact evaluation kernel of an
//! extraordinary patch (\[Stam98\]; \[CL-R ch. 2, eqs. 2.4-2.7\]).
//!
//! For valence `n` the local subdivision matrix `A` (K x K, K = 2n+8, see
//! [`crate::mesh::stencil`]) is diagonalised as `A = R B L`, `L R = I`, where `B` is
//! diagonal except for one optional 2x2 block (the frequency-0 pair
//! lambda_0, lambda_1 when it is complex, possible with general weights).
//! The eigenvalues are known in closed form (\[CL-R §2.4\]):
//!
//! * `1, 1/8, 1/16, 1/32, 1/64`;
//! * `lambda_{2w}, lambda_{2w+1} = (c + 5 +- sqrt((c+1)(c+9)))/16`, `c = cos(2 pi w/n)`, `w = 1..n/2`;
//! * `lambda_{0,1}`: the roots of `x^2 - (alpha - 1/4) x + (1 - 2 beta)/16`.
//!
//! Each eigenspace is computed as the null space of `A - lambda I` (right) and
//! of its transpose (left) by Gauss-Jordan elimination with full pivoting,
//! then normalised so that `L R = I`; the build checks `R B L = A` to 1e-10.
//!
//! Evaluation at (u, v) in region Omega_{m,b} (\[CL-R §2.1\]) uses the 16
//! control points of the regular sub-patch
//! `G_{m,b} = X_b B^{m-1} L G`, `X_b = P_b A_bar R`, then the bicubic
//! B-spline. The limit-point term (eigenvalue 1) is added separately so that
//! derivatives near the extraordinary vertex keep full relative precision.

use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::math::bspline::basis;
use crate::math::linalg::{invert_small, null_space};
use crate::mesh::stencil::{Mat, Row, Stencils, MAX_K};
use crate::mesh::weights::Weights;
use glam::DVec3;

/// The eigen data of one valence. About `8 * (2 MAX_K^2 + 110 MAX_K)` bytes
/// (60 KiB for `MAX_VALENCE = 16`), whatever the valence.
#[derive(Clone)]
pub struct ValenceTable {
    pub(super) n: usize,
    pub(super) k: usize,
    pub(super) weights: (f64, f64, f64),
    /// Eigenvalue of each column (for the 2x2 block: its spectral radius).
    pub(super) mu: Row,
    /// `mu_pow[e][c] = powi(mu[c], e)` for `e < POW_LEVELS`: the eigenvalue
    /// powers of the evaluation kernel at levels `m = e + 1 <= POW_LEVELS`
    /// by one load ([`crate::eigen::kernel`]), the same bits as
    /// [`crate::math::linalg::powi`].
    pub(super) mu_pow: [Row; POW_LEVELS],
    /// Start column and matrix of the 2x2 block, if any.
    pub(super) quad: Option<(usize, [[f64; 2]; 2])>,
    /// Left eigenvectors (rows), normalised so that `L R = I`.
    pub(super) left: Mat,
    /// Right eigenvectors (columns), `R = L^-1`.
    pub(super) right: Mat,
    /// `X_b = P_b A_bar R` (b = 1, 2, 3), stored by eigen column: `x[b-1][c]`
    /// is column `c` (16 grid points, index `i*4 + j`, i along u, j along v).
    pub(super) x: [[[f64; 16]; MAX_K]; 3],
    /// Subdominant columns `[sub0, sub1)`.
    pub(super) sub: (usize, usize),
    /// Weights over eigen columns of the limit tangents at the EV.
    pub(super) tan_u: Row,
    pub(super) tan_v: Row,
    /// Subdivision-depth constants (\[CL-R ch. 3\]).
    pub(super) rates: crate::eigen::rates::Rates,
    /// `F_c = max_{b,i} |X_b[i][c]|`: bound of eigen-basis function c over
    /// the first-level L-shaped region (B-spline convex hull).
    pub(super) sup_phi: Row,
    /// `sup_{p >= 0} ||B_q^p||_inf` of the 2x2 block (1 without one).
    pub(super) quad_growth: f64,
    /// `G_c >= sup |Phi_c - l_c|` over the patch, the distance of eigen-basis
    /// function c from the linear function `l_c` ([`crate::eigen::corner_fit`];
    /// 0 for column 0 and the 2x2 block, which the flatness bound treats
    /// as the radius bound does).
    pub(super) flat_phi: Row,
    /// The linear functions `l_c = (alpha_c, beta_c)` of `flat_phi`.
    pub(super) flat_lin: [[f64; 2]; MAX_K],
    /// At the first column `c` of a pair of columns with the same
    /// eigenvalue: the joint bound `H_c` of both distances
    /// ([`crate::eigen::corner_fit`]); 0 elsewhere.
    pub(super) flat_pair: Row,
    /// Ring-region bound constants: per column `c`, over the Bezier nets of
    /// `X_1[c]`, `X_2[c]`, `X_3[c]`, the largest second difference along
    /// u (`ring_sd[0]`), along v (`[1]`) and mixed (`[2]`), absolute
    /// values ([`ValenceTable::ring_terms`]).
    pub(super) ring_sd: [Row; 3],
    /// At the first column `c` of a pair of real columns with the same
    /// eigenvalue: the joint constants `max_e |(D_c[e], D_c+1[e])|` of the
    /// three kinds of difference (0 elsewhere).
    pub(super) ring_pair: [Row; 3],
    /// Ring-point functionals: per column `c`, value and u, v derivatives
    /// of the bicubic B-splines `X_b[c]` at the five points a split of a
    /// corner cell creates ([`RING_POINTS`]), index `3 w + (0, 1, 2)`
    /// (the 16th entry unused).
    pub(super) ring_pts: [[f64; 16]; MAX_K],
}

/// Levels `m = 1..=POW_LEVELS` whose eigenvalue powers a table keeps
/// ([`ValenceTable::mu_pow`]): every point farther than `2^-32` from the
/// extraordinary vertex.
pub(super) const POW_LEVELS: usize = 32;

/// Scratch memory for [`ValenceTable::build_into`] (about 66 KiB for
/// `MAX_VALENCE = 16`); callers may keep one in static memory.
pub struct BuildScratch {
    pub(super) st: Stencils,
    pub(super) q: Mat,
    pub(super) r: Mat,
    pub(super) l: Mat,
}

impl BuildScratch {
    /// Fills the local subdivision matrix `A` of valence `n` for rule `w`
    /// (label order of [`crate::mesh::stencil`]) and returns it; the leading
    /// `(2n+8) x (2n+8)` block is meaningful. For checks and tools.
    pub fn subdivision_matrix(&mut self, n: usize, w: &Weights) -> &Mat {
        let n = n.clamp(3, MAX_VALENCE);
        self.st.fill(n, w.get(n), w.get(4));
        &self.st.a
    }

    /// A zeroed scratch.
    pub const ZERO: BuildScratch = BuildScratch {
        st: Stencils::ZERO,
        q: [[0.0; MAX_K]; MAX_K],
        r: [[0.0; MAX_K]; MAX_K],
        l: [[0.0; MAX_K]; MAX_K],
    };
}

/// One eigenvalue factor: a real root or a real quadratic `x^2 - t x + d`.
#[derive(Clone, Copy, Debug)]
pub(super) enum Factor {
    Real(f64),
    Quad(f64, f64),
}

impl Factor {
    fn radius(&self) -> f64 {
        match *self {
            Factor::Real(x) => x.abs(),
            Factor::Quad(_, d) => libm::sqrt(d.abs()),
        }
    }
}

/// The distinct eigenvalue factors of valence `n` with EV weights `(a, b, _)`,
/// sorted by decreasing modulus.
pub(super) fn factors(
    n: usize,
    a: f64,
    b: f64,
    out: &mut heapless::Vec<Factor, { MAX_VALENCE + 8 }>,
) {
    out.clear();
    let push = |x: f64, out: &mut heapless::Vec<Factor, { MAX_VALENCE + 8 }>| {
        let dup = out.iter().any(|f| match f {
            Factor::Real(y) => (x - y).abs() < 1e-9,
            _ => false,
        });
        if !dup {
            let _ = out.push(Factor::Real(x));
        }
    };
    for x in [1.0, 0.125, 0.0625, 0.03125, 0.015625] {
        push(x, out);
    }
    for w in 1..=n / 2 {
        let c = libm::cos(2.0 * core::f64::consts::PI * w as f64 / n as f64);
        let s = libm::sqrt(((c + 1.0) * (c + 9.0)).max(0.0));
        push((c + 5.0 + s) / 16.0, out);
        push((c + 5.0 - s) / 16.0, out);
    }
    let t = a - 0.25;
    let d = (1.0 - 2.0 * b) / 16.0;
    let disc = t * t - 4.0 * d;
    if disc >= 0.0 {
        let s = libm::sqrt(disc);
        push((t + s) / 2.0, out);
        push((t - s) / 2.0, out);
    } else {
        let _ = out.push(Factor::Quad(t, d));
    }
    // Insertion sort by decreasing modulus (stable, tiny).
    let len = out.len();
    for i in 1..len {
        let mut j = i;
        while j > 0 && out[j - 1].radius() < out[j].radius() {
            out.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// `acc += w * col` on 16 values: one multiply and one add per value, in
/// the order of the scalar loop (the optimiser vectorises it; written
/// without intrinsics so that sanitizer builds see plain loads and stores).
#[inline(always)]
pub(super) fn axpy16(acc: &mut [f64; 16], w: f64, col: &[f64; 16]) {
    for (a, &x) in acc.iter_mut().zip(col.iter()) {
        *a += w * x;
    }
}

impl ValenceTable {
    /// An empty table, to be filled by [`ValenceTable::build_into`].
    pub const ZERO: ValenceTable = ValenceTable {
        n: 0,
        k: 0,
        weights: (0.0, 0.0, 0.0),
        mu: [0.0; MAX_K],
        mu_pow: [[0.0; MAX_K]; POW_LEVELS],
        quad: None,
        left: [[0.0; MAX_K]; MAX_K],
        right: [[0.0; MAX_K]; MAX_K],
        x: [[[0.0; 16]; MAX_K]; 3],
        sub: (0, 0),
        tan_u: [0.0; MAX_K],
        tan_v: [0.0; MAX_K],
        sup_phi: [0.0; MAX_K],
        quad_growth: 1.0,
        flat_phi: [0.0; MAX_K],
        flat_lin: [[0.0; 2]; MAX_K],
        flat_pair: [0.0; MAX_K],
        ring_sd: [[0.0; MAX_K]; 3],
        ring_pair: [[0.0; MAX_K]; 3],
        ring_pts: [[0.0; 16]; MAX_K],
        rates: crate::eigen::rates::Rates {
            n: 0,
            r1: 0.0,
            r2: 0.0,
            c_new: 0.0,
            c_lemma10: 0.0,
            r_old: 0.0,
            c_old: 0.0,
        },
    };

    /// Builds the table of valence `n` (3..=MAX_VALENCE) for vertex rule `w`
    /// into `self`, using `scratch`. No heap, libm only.
    pub fn build_into(
        &mut self,
        n: usize,
        w: &Weights,
        scratch: &mut BuildScratch,
    ) -> Result<(), Error> {
        if !(3..=MAX_VALENCE).contains(&n) {
            return Err(Error::UnsupportedValence {
                vertex: u32::MAX,
                valence: n as u32,
            });
        }
        let fail = Error::TableBuildFailed { valence: n as u32 };
        let ev = w.get(n);
        scratch.st.fill(n, ev, w.get(4));
        let k = scratch.st.k;
        let a = &scratch.st.a;
        let mut fs = heapless::Vec::new();
        factors(n, ev.0, ev.1, &mut fs);

        let mut scale = 0.0f64;
        for row in a.iter().take(k) {
            for v in row.iter().take(k) {
                scale = scale.max(v.abs());
            }
        }
        let tol = 1e-8 * scale.max(1.0);
        // Null spaces of each factor, right (columns of r) and left (columns of l).
        let mut col = 0usize;
        let mut groups: heapless::Vec<(usize, usize, Factor), { MAX_VALENCE + 8 }> =
            heapless::Vec::new();
        for f in fs.iter() {
            let q = &mut scratch.q;
            for i in 0..k {
                for j in 0..k {
                    q[i][j] = match *f {
                        Factor::Real(x) => a[i][j] - if i == j { x } else { 0.0 },
                        Factor::Quad(t, d) => {
                            let mut s = 0.0;
                            for (l, arow) in a.iter().enumerate().take(k) {
                                s += a[i][l] * arow[j];
                            }
                            s - t * a[i][j] + if i == j { d } else { 0.0 }
                        }
                    };
                }
            }
            if col >= k {
                return Err(fail);
            }
            let mut qt = [[0.0; MAX_K]; MAX_K];
            for (i, row) in q.iter().enumerate().take(k) {
                for (j, &v) in row.iter().enumerate().take(k) {
                    qt[j][i] = v;
                }
            }
            let dim = null_space(q, k, tol, &mut scratch.r, col);
            let dim_l = null_space(&mut qt, k, tol, &mut scratch.l, col);
            if dim != dim_l || dim == 0 || dim > 8 || col + dim > k {
                return Err(fail);
            }
            let _ = groups.push((col, dim, *f));
            col += dim;
        }
        if col != k {
            return Err(fail);
        }
        // Normalise each group: L_g := (L_g^T R_g)^-1 L_g^T.
        *self = ValenceTable::ZERO;
        self.n = n;
        self.k = k;
        self.weights = ev;
        for &(c0, g, f) in groups.iter() {
            let mut nm = [[0.0; 8]; 8];
            for (i, row) in nm.iter_mut().enumerate().take(g) {
                for (j, v) in row.iter_mut().enumerate().take(g) {
                    let mut s = 0.0;
                    for t in 0..k {
                        s += scratch.l[t][c0 + i] * scratch.r[t][c0 + j];
                    }
                    *v = s;
                }
            }
            if !invert_small(&mut nm, g) {
                return Err(fail);
            }
            for i in 0..g {
                for t in 0..k {
                    let mut s = 0.0;
                    for j in 0..g {
                        s += nm[i][j] * scratch.l[t][c0 + j];
                    }
                    self.left[c0 + i][t] = s;
                }
            }
            match f {
                Factor::Real(x) => {
                    for i in 0..g {
                        self.mu[c0 + i] = x;
                    }
                }
                Factor::Quad(..) => {
                    if g != 2 {
                        return Err(fail);
                    }
                    // B = L_g A R_g.
                    let mut bm = [[0.0; 2]; 2];
                    for (i, brow) in bm.iter_mut().enumerate() {
                        for (j, bv) in brow.iter_mut().enumerate() {
                            let mut s = 0.0;
                            for t in 0..k {
                                let mut ar = 0.0;
                                for l in 0..k {
                                    ar += a[t][l] * scratch.r[l][c0 + j];
                                }
                                s += self.left[c0 + i][t] * ar;
                            }
                            *bv = s;
                        }
                    }
                    self.quad = Some((c0, bm));
                    let r = f.radius();
                    self.mu[c0] = r;
                    self.mu[c0 + 1] = r;
                }
            }
        }
        // Normalise the eigenvalue-1 column to all ones (then Ghat_0 is the limit point).
        let c = scratch.r[0][0];
        if c.abs() < 1e-12 || (self.mu[0] - 1.0).abs() > 1e-12 {
            return Err(fail);
        }
        for i in 0..k {
            scratch.r[i][0] /= c;
            self.left[0][i] *= c;
        }
        // Check R B L = A.
        for i in 0..k {
            for j in 0..k {
                let mut s = 0.0;
                for c in 0..k {
                    let bl = self.b_times_left(c, j);
                    s += scratch.r[i][c] * bl;
                }
                if (s - a[i][j]).abs() > 1e-10 {
                    return Err(fail);
                }
            }
        }
        self.right = scratch.r;
        // X_b = P_b A_bar R.
        for b in 0..3 {
            for r in 0..16 {
                let row = (r % 4) * 4 + r / 4;
                for c in 0..k {
                    let mut s = 0.0;
                    for t in 0..k {
                        s += scratch.st.pick[b][r][t] * scratch.r[t][c];
                    }
                    self.x[b][c][row] = s;
                }
            }
        }
        // Subdominant columns: the largest modulus below 1.
        let s0 = 1;
        let lam = self.mu[s0];
        let mut s1 = s0;
        while s1 < k && (self.mu[s1] - lam).abs() < 1e-9 {
            s1 += 1;
        }
        self.sub = (s0, s1);
        // Limit tangents: derivative of the subdominant part at the start of
        // Omega_{1,1} (u = 1/2, v = 0) along u and of Omega_{1,3} along v,
        // times 2 (the chain-rule factor of the first level).
        let (b0, d0, _) = basis(0.0);
        for c in s0..s1 {
            let mut tu = 0.0;
            let mut tv = 0.0;
            for j in 0..4 {
                for i in 0..4 {
                    tu += d0[i] * b0[j] * self.x[0][c][i * 4 + j];
                    tv += b0[i] * d0[j] * self.x[2][c][i * 4 + j];
                }
            }
            self.tan_u[c] = 2.0 * tu;
            self.tan_v[c] = 2.0 * tv;
        }
        for c in 0..k {
            let mut s = 0.0f64;
            for b in 0..3 {
                for v in self.x[b][c].iter() {
                    s = s.max(libm::fabs(*v));
                }
            }
            self.sup_phi[c] = s;
        }
        for (e, row) in self.mu_pow.iter_mut().enumerate() {
            for (p, &m) in row.iter_mut().zip(self.mu.iter()).take(k) {
                *p = crate::math::linalg::powi(m, e as u32);
            }
        }
        self.ring_constants(k);
        crate::eigen::corner_fit::columns(
            &self.x,
            &self.mu,
            k,
            self.quad.map(|(q, _)| q),
            &mut self.flat_phi,
            &mut self.flat_lin,
            &mut self.flat_pair,
        );
        self.quad_growth = 1.0;
        if let Some((_, m)) = self.quad {
            let mut p = m;
            for _ in 0..10_000 {
                let norm = (libm::fabs(p[0][0]) + libm::fabs(p[0][1]))
                    .max(libm::fabs(p[1][0]) + libm::fabs(p[1][1]));
                self.quad_growth = self.quad_growth.max(norm);
                if norm < 1e-6 {
                    break;
                }
                p = [
                    [
                        p[0][0] * m[0][0] + p[0][1] * m[1][0],
                        p[0][0] * m[0][1] + p[0][1] * m[1][1],
                    ],
                    [
                        p[1][0] * m[0][0] + p[1][1] * m[1][0],
                        p[1][0] * m[0][1] + p[1][1] * m[1][1],
                    ],
                ];
            }
        }
        let standard = ev == crate::mesh::weights::standard(n);
        self.rates = crate::eigen::rates::rates(n, &scratch.st.a, standard)?;
        Ok(())
    }

    /// Subdivision-depth constants of this valence (see [`crate::bounds::depth`]).
    pub fn rates(&self) -> &crate::eigen::rates::Rates {
        &self.rates
    }

    /// `(B L)[c][j]`: row `c` of the left eigenvectors times the eigenvalue
    /// block (for checks: `L A = B L`).
    pub fn b_times_left(&self, c: usize, j: usize) -> f64 {
        if let Some((q0, m)) = self.quad {
            if c == q0 || c == q0 + 1 {
                let i = c - q0;
                return m[i][0] * self.left[q0][j] + m[i][1] * self.left[q0 + 1][j];
            }
        }
        self.mu[c] * self.left[c][j]
    }

    /// Valence.
    pub fn valence(&self) -> usize {
        self.n
    }
    /// Number of control points, `2n + 8`.
    pub fn num_points(&self) -> usize {
        self.k
    }
    /// Vertex-rule weights the table was built for.
    pub fn weights(&self) -> (f64, f64, f64) {
        self.weights
    }
    /// Eigenvalue (modulus for the complex pair) of each eigen column, in
    /// decreasing order; `eigenvalues()[0] == 1`.
    pub fn eigenvalues(&self) -> &[f64] {
        &self.mu[..self.k]
    }
    /// The subdominant eigenvalue (largest modulus below 1).
    pub fn subdominant(&self) -> f64 {
        self.mu[self.sub.0]
    }
    /// Row `c` of the left eigenvector matrix `L` (length 2n+8).
    pub fn left_row(&self, c: usize) -> &[f64] {
        &self.left[c.min(MAX_K - 1)][..self.k]
    }
    /// Whether the eigenvalue block contains a complex pair (general weights
    /// with `16 alpha^2 - 8 alpha + 8 beta - 3 < 0`).
    pub fn has_complex_pair(&self) -> bool {
        self.quad.is_some()
    }
    /// Whether the rule is tangent-plane continuous at this valence (see
    /// [`Weights::tangent_plane_continuous`]).
    pub fn tangent_plane_continuous(&self) -> bool {
        let mut w = Weights::STANDARD;
        if w.set(self.n, self.weights.0, self.weights.1, self.weights.2)
            .is_err()
        {
            return self.n == 4;
        }
        w.tangent_plane_continuous(self.n)
    }

    /// Weights of the limit point over the 2n+8 control points (the left
    /// eigenvector of eigenvalue 1, \[CL-R eq. 2.7\]).
    pub fn limit_weights(&self) -> &[f64] {
        &self.left[0][..self.k]
    }

    /// Projects control points (label order, see [`crate::mesh::stencil`]) onto the
    /// eigen basis: `ghat = L G`, written as x y z per eigen column.
    /// `points.len()` must be at least `2n + 8` and `ghat.len()` `3(2n + 8)`.
    pub fn project(&self, points: &[DVec3], ghat: &mut [f64]) {
        let k = self.k.min(points.len()).min(ghat.len() / 3);
        for c in 0..k {
            let row = &self.left[c];
            let mut s = DVec3::ZERO;
            for j in 0..k {
                s += points[j] * row[j];
            }
            ghat[3 * c] = s.x;
            ghat[3 * c + 1] = s.y;
            ghat[3 * c + 2] = s.z;
        }
    }
}
