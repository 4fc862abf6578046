//! Per-valence eigen tables and the exact evaluation kernel of an
//! extraordinary patch (Stam 1998; Cheng & Lai report ch. 2, eqs. 2.4-2.7).
//!
//! For valence `n` the local subdivision matrix `A` (K x K, K = 2n+8, see
//! [`crate::mesh::stencil`]) is diagonalised as `A = R B L`, `L R = I`, where `B` is
//! diagonal except for one optional 2x2 block (the frequency-0 pair
//! lambda_0, lambda_1 when it is complex, possible with general weights).
//! The eigenvalues are known in closed form (report §2.4):
//!
//! * `1, 1/8, 1/16, 1/32, 1/64`;
//! * `lambda_{2w}, lambda_{2w+1} = (c + 5 +- sqrt((c+1)(c+9)))/16`, `c = cos(2 pi w/n)`, `w = 1..n/2`;
//! * `lambda_{0,1}`: the roots of `x^2 - (alpha - 1/4) x + (1 - 2 beta)/16`.
//!
//! Each eigenspace is computed as the null space of `A - lambda I` (right) and
//! of its transpose (left) by Gauss-Jordan elimination with full pivoting,
//! then normalised so that `L R = I`; the build checks `R B L = A` to 1e-10.
//!
//! Evaluation at (u, v) in region Omega_{m,b} (report §2.1) uses the 16
//! control points of the regular sub-patch
//! `G_{m,b} = X_b B^{m-1} L G`, `X_b = P_b A_bar R`, then the bicubic
//! B-spline. The limit-point term (eigenvalue 1) is added separately so that
//! derivatives near the extraordinary vertex keep full relative precision.

use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::math::bspline::{basis, eval_grid, Grid};
use crate::math::linalg::{invert_small, mul2x2, null_space, pow2x2, powi};
use crate::math::Eval;
use crate::mesh::stencil::{Mat, Row, Stencils, MAX_K};
use crate::mesh::weights::Weights;
use glam::DVec3;

/// The eigen data of one valence. About `8 * (2 MAX_K^2 + 78 MAX_K)` bytes
/// (50 KiB for `MAX_VALENCE = 16`), whatever the valence.
#[derive(Clone)]
pub struct ValenceTable {
    n: usize,
    k: usize,
    weights: (f64, f64, f64),
    /// Eigenvalue of each column (for the 2x2 block: its spectral radius).
    mu: Row,
    /// Start column and matrix of the 2x2 block, if any.
    quad: Option<(usize, [[f64; 2]; 2])>,
    /// Left eigenvectors (rows), normalised so that `L R = I`.
    left: Mat,
    /// Right eigenvectors (columns), `R = L^-1`.
    right: Mat,
    /// `X_b = P_b A_bar R` (b = 1, 2, 3), stored by eigen column: `x[b-1][c]`
    /// is column `c` (16 grid points, index `i*4 + j`, i along u, j along v).
    x: [[[f64; 16]; MAX_K]; 3],
    /// Subdominant columns `[sub0, sub1)`.
    sub: (usize, usize),
    /// Weights over eigen columns of the limit tangents at the EV.
    tan_u: Row,
    tan_v: Row,
    /// Subdivision-depth constants (report ch. 3).
    rates: crate::eigen::rates::Rates,
    /// `F_c = max_{b,i} |X_b[i][c]|`: bound of eigen-basis function c over
    /// the first-level L-shaped region (B-spline convex hull).
    sup_phi: Row,
    /// `sup_{p >= 0} ||B_q^p||_inf` of the 2x2 block (1 without one).
    quad_growth: f64,
    /// `G_c >= sup |Phi_c - l_c|` over the patch, the distance of eigen-basis
    /// function c from the linear function `l_c` ([`crate::eigen::corner_fit`];
    /// 0 for column 0 and the 2x2 block, which the flatness bound treats
    /// as the radius bound does).
    flat_phi: Row,
    /// The linear functions `l_c = (alpha_c, beta_c)` of `flat_phi`.
    flat_lin: [[f64; 2]; MAX_K],
    /// At the first column `c` of a pair of columns with the same
    /// eigenvalue: the joint bound `H_c` of both distances
    /// ([`crate::eigen::corner_fit`]); 0 elsewhere.
    flat_pair: Row,
    /// Ring-region bound constants: per column `c`, over the Bezier nets of
    /// `X_1[c]`, `X_2[c]`, `X_3[c]`, the largest second difference along
    /// u (`ring_sd[0]`), along v (`[1]`) and mixed (`[2]`), absolute
    /// values ([`ValenceTable::ring_terms`]).
    ring_sd: [Row; 3],
    /// At the first column `c` of a pair of real columns with the same
    /// eigenvalue: the joint constants `max_e |(D_c[e], D_c+1[e])|` of the
    /// three kinds of difference (0 elsewhere).
    ring_pair: [Row; 3],
    /// Ring-point functionals: per column `c`, value and u, v derivatives
    /// of the bicubic B-splines `X_b[c]` at the five points a split of a
    /// corner cell creates ([`RING_POINTS`]), index `3 w + (0, 1, 2)`
    /// (the 16th entry unused).
    ring_pts: [[f64; 16]; MAX_K],
}

/// Where the five points created by splitting the corner cell
/// `[0, 2^-k]^2` lie (patch frame; centre, then the midpoints of sides
/// 0..4 of the cell): `(b, s, t)` = sub-patch `Omega_{k+1, b}` at its
/// local parameters `(s, t)`. Side 0 is `v = 0`, side 1 `u = 2^-k`,
/// side 2 `v = 2^-k`, side 3 `u = 0`.
pub(crate) const RING_POINTS: [(usize, f64, f64); 5] = [
    (2, 0.0, 0.0),
    (1, 0.0, 0.0),
    (1, 1.0, 1.0),
    (3, 1.0, 1.0),
    (3, 0.0, 0.0),
];

/// Scratch memory for [`ValenceTable::build_into`] (about 66 KiB for
/// `MAX_VALENCE = 16`); callers may keep one in static memory.
pub struct BuildScratch {
    st: Stencils,
    q: Mat,
    r: Mat,
    l: Mat,
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
enum Factor {
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
fn factors(n: usize, a: f64, b: f64, out: &mut heapless::Vec<Factor, { MAX_VALENCE + 8 }>) {
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

/// `acc += w * col` on 16 values (SSE2 on x86_64).
#[inline(always)]
fn axpy16(acc: &mut [f64; 16], w: f64, col: &[f64; 16]) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::*;
        // SAFETY: SSE2 is part of the x86_64 baseline; the unaligned loads and
        // stores stay inside the two 16-element arrays.
        unsafe {
            let wv = _mm_set1_pd(w);
            for i in (0..16).step_by(2) {
                let a = _mm_loadu_pd(acc.as_ptr().add(i));
                let x = _mm_loadu_pd(col.as_ptr().add(i));
                _mm_storeu_pd(acc.as_mut_ptr().add(i), _mm_add_pd(a, _mm_mul_pd(wv, x)));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    for i in 0..16 {
        acc[i] += w * col[i];
    }
}

impl ValenceTable {
    /// An empty table, to be filled by [`ValenceTable::build_into`].
    pub const ZERO: ValenceTable = ValenceTable {
        n: 0,
        k: 0,
        weights: (0.0, 0.0, 0.0),
        mu: [0.0; MAX_K],
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
    /// eigenvector of eigenvalue 1, report eq. 2.7).
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

    /// The second differences of the Bezier nets of `X_1[c]`, `X_2[c]`,
    /// `X_3[c]`: along u, along v, mixed (24, 24 and 27 entries).
    fn ring_diffs(&self, c: usize) -> [[f64; 27]; 3] {
        let mut d = [[0.0f64; 27]; 3];
        let mut n = [0usize; 3];
        for x in &self.x {
            let p = crate::math::bezier::scalar_bezier_net(&x[c], 0.0, 1.0, 0.0, 1.0);
            crate::math::bezier::second_differences(
                |k, l| p[k][l],
                |kind, v| {
                    d[kind][n[kind]] = v;
                    n[kind] += 1;
                },
            );
        }
        d
    }

    /// Fills `ring_sd`, `ring_pair` and `ring_pts` for the first `k`
    /// columns.
    fn ring_constants(&mut self, k: usize) {
        let q0 = self.quad.map_or(usize::MAX, |(q, _)| q);
        self.ring_pair = [[0.0; MAX_K]; 3];
        for c in 0..k {
            let d = self.ring_diffs(c);
            for (r, e) in self.ring_sd.iter_mut().zip(&d) {
                r[c] = e.iter().fold(0.0f64, |m, v| m.max(libm::fabs(*v)));
            }
            // A pair of real columns with one eigenvalue: the joint
            // constant (max over entries of the 2-vector length).
            let pair_start = c >= 1
                && c + 1 < k
                && c != q0
                && c != q0.wrapping_add(1)
                && c + 1 != q0
                && self.mu[c].to_bits() == self.mu[c + 1].to_bits()
                && !(c > 1 && self.ring_pair.iter().any(|h| h[c - 1] > 0.0));
            if pair_start {
                let e = self.ring_diffs(c + 1);
                for ((h, a), b) in self.ring_pair.iter_mut().zip(&d).zip(&e) {
                    h[c] = a
                        .iter()
                        .zip(b)
                        .fold(0.0f64, |m, (x, y)| m.max(libm::sqrt(x * x + y * y)));
                }
            }
            for (w, &(b, s, t)) in RING_POINTS.iter().enumerate() {
                let (bs, ds, _) = basis(s);
                let (bt, dt, _) = basis(t);
                let g = &self.x[b - 1][c];
                let (mut p, mut pu, mut pv) = (0.0, 0.0, 0.0);
                for i in 0..4 {
                    for j in 0..4 {
                        let v = g[i * 4 + j];
                        p += bs[i] * bt[j] * v;
                        pu += ds[i] * bt[j] * v;
                        pv += bs[i] * dt[j] * v;
                    }
                }
                self.ring_pts[c][3 * w..3 * w + 3].copy_from_slice(&[p, pu, pv]);
            }
        }
    }

    /// The terms of the ring-region bound of a patch with eigen projection
    /// `ghat` ([`RingTerms`]): at level `k` they bound the largest second
    /// differences (along u, along v, mixed) of the Bezier nets of the three
    /// sub-patches `Omega_{k+1, b}`. Those nets are
    /// `sum_c mu_c^k ghat_c Bez(X_b[c])`, and a difference of the sum is at
    /// most `sum_c |mu_c|^k |ghat_c| ring_sd[.][c]` (triangle inequality);
    /// for a pair of columns with one eigenvalue the pair's two terms are
    /// replaced by `|mu|^k sigma_max([ghat_c ghat_c+1]) ring_pair[.][c]`
    /// where smaller (Cauchy-Schwarz per entry). `None` for a table with a
    /// 2x2 block, whose terms this does not cover.
    pub(crate) fn ring_terms(&self, ghat: &[f64]) -> Option<RingTerms> {
        if self.quad.is_some() {
            return None;
        }
        let [a, b, c] = &self.ring_sd;
        let [pa, pb, pc] = &self.ring_pair;
        Some(RingTerms(self.grouped(ghat, [a, b, c], Some([pa, pb, pc]))))
    }

    /// The five points a split of the corner cell `[0, 2^-k]^2` creates
    /// ([`RING_POINTS`]), each as (position minus the limit point, and the
    /// u and v derivatives of its sub-patch there, which are positive
    /// multiples of the patch's): `sum_c mu_c^k ghat_c f_c` over the columns
    /// `c >= 1` for each functional `f` of `ring_pts`. False (nothing
    /// written) for a table with a 2x2 block.
    pub(crate) fn ring_points(&self, ghat: &[f64], k: u32, out: &mut [[DVec3; 3]; 5]) -> bool {
        if self.quad.is_some() {
            return false;
        }
        let mut acc = [[0.0f64; 16]; 3];
        #[cfg(target_arch = "x86_64")]
        if crate::math::simd::has_avx2() {
            // SAFETY: the CPU runs AVX2 (checked just above).
            unsafe { self.ring_sums_avx2(ghat, k, &mut acc) };
        } else {
            self.ring_sums(ghat, k, &mut acc);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.ring_sums(ghat, k, &mut acc);
        for (w, o) in out.iter_mut().enumerate() {
            for (q, v) in o.iter_mut().enumerate() {
                let i = 3 * w + q;
                *v = DVec3::new(acc[0][i], acc[1][i], acc[2][i]);
            }
        }
        true
    }

    /// The sums of [`ValenceTable::ring_points`]: `acc[coordinate][f] =
    /// sum_c mu_c^k ghat_c[coordinate] ring_pts[c][f]` over columns `c >= 1`
    /// in order (plain multiplies and adds: the same bits on every path).
    fn ring_sums(&self, ghat: &[f64], k: u32, acc: &mut [[f64; 16]; 3]) {
        let kk = self.k.min(ghat.len() / 3);
        for c in 1..kk {
            let w = powi(self.mu[c], k);
            let t = &self.ring_pts[c];
            for (co, a) in acc.iter_mut().enumerate() {
                let g = ghat[3 * c + co] * w;
                for (x, y) in a.iter_mut().zip(t) {
                    *x += g * y;
                }
            }
        }
    }

    /// [`ValenceTable::ring_sums`] on four lanes, the sums kept in
    /// registers (the same operations in the same order, so the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn ring_sums_avx2(&self, ghat: &[f64], k: u32, acc: &mut [[f64; 16]; 3]) {
        use core::arch::x86_64::*;
        let kk = self.k.min(ghat.len() / 3);
        let mut a = [[_mm256_setzero_pd(); 4]; 3];
        for c in 1..kk {
            let w = powi(self.mu[c], k);
            let t = &self.ring_pts[c];
            // SAFETY: 4 values at 4 i + 4 <= 16 of the row.
            let tv: [__m256d; 4] =
                core::array::from_fn(|i| unsafe { _mm256_loadu_pd(t[4 * i..4 * i + 4].as_ptr()) });
            for (co, ac) in a.iter_mut().enumerate() {
                let g = _mm256_set1_pd(ghat[3 * c + co] * w);
                for (x, y) in ac.iter_mut().zip(&tv) {
                    *x = _mm256_add_pd(*x, _mm256_mul_pd(g, *y));
                }
            }
        }
        for (ac, out) in a.iter().zip(acc.iter_mut()) {
            for (i, x) in ac.iter().enumerate() {
                // SAFETY: 4 values at 4 i + 4 <= 16 of the row.
                unsafe { _mm256_storeu_pd(out[4 * i..4 * i + 4].as_mut_ptr(), *x) };
            }
        }
    }

    /// Guaranteed radius `R_k` such that every limit point of the corner
    /// region `[0, 2^-k]^2` of the patch is within `R_k` of the limit point
    /// (the eigen expansion bound of report §7, "m_eps"):
    /// `S(2^-k z) - L = sum_c (B^(k+j-1) ghat)_c phi_c(z')` for z in the
    /// level-j L-shaped region, `|phi_c| <= F_c` (B-spline convex hull of
    /// `X_b`), `|mu_c|^(k+j-1) <= |mu_c|^k`.
    pub fn corner_radius(&self, ghat: &[f64], k: u32) -> f64 {
        let mut t = EigenTerms::EMPTY;
        self.eigen_terms(ghat, &self.sup_phi, None, &mut t);
        t.at(k)
    }

    /// Guaranteed flatness `E_k` of the corner region `[0, 2^-k]^2` of the
    /// patch: there is an affine function `A` of the patch parameters with
    /// `|S - A| <= E_k` over the region, so every linear interpolant of
    /// limit points of the region is within `2 E_k` of the surface there
    /// ([`crate::eigen::corner_fit`]): `E_k = sum_c |mu_c|^k |ghat_c| G_c`, a pair
    /// of columns with one eigenvalue replaced by its joint term where that
    /// is smaller, the 2x2 block (if any) bounded as in
    /// [`ValenceTable::corner_radius`].
    /// Never larger than `corner_radius(ghat, k)`, and for the
    /// characteristic-map columns a small fraction of it.
    pub fn corner_flatness(&self, ghat: &[f64], k: u32) -> f64 {
        let mut t = EigenTerms::EMPTY;
        self.flatness_terms(ghat, &mut t);
        t.at(k)
    }

    /// The terms of [`ValenceTable::corner_flatness`] for one patch, for
    /// the bounds of many levels: one weight per distinct eigenvalue
    /// modulus (`sum G_c |ghat_c|` over its columns) and the 2x2 block.
    pub(crate) fn flatness_terms(&self, ghat: &[f64], out: &mut EigenTerms) {
        self.eigen_terms(ghat, &self.flat_phi, Some(&self.flat_pair), out);
    }

    /// `sum_c |mu_c|^k |ghat_c| per[c]` over the columns `c >= 1` with a
    /// real eigenvalue, grouped by modulus ([`ValenceTable::grouped`]),
    /// plus the 2x2 block's term `(F_q0 + F_q1) growth max_i |(B^k ghat)_i|`
    /// (bounded by `sup_phi` whatever `per` is), as terms to evaluate at
    /// any `k`. With `pairs`, the two terms of a pair `(c, c + 1)` with
    /// `pairs[c] = H > 0` are replaced by `H sigma_max([ghat_c ghat_{c+1}])`
    /// where that is smaller (see [`crate::eigen::corner_fit::columns`]).
    fn eigen_terms(&self, ghat: &[f64], per: &Row, pairs: Option<&Row>, out: &mut EigenTerms) {
        let gv = |c: usize| DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
        out.g = self.grouped(ghat, [per], pairs.map(|p| [p]));
        out.quad = self.quad.map(|(q0, m)| {
            let f = (self.sup_phi[q0] + self.sup_phi[q0 + 1]) * self.quad_growth;
            (m, gv(q0), gv(q0 + 1), f)
        });
    }

    /// For `N` weight rows at once: `sum_c |mu_c|^k |ghat_c| per[i][c]` over
    /// the columns `c >= 1` with a real eigenvalue (the 2x2 block's columns
    /// skipped), grouped by modulus (columns of equal modulus are next to
    /// each other). With `pairs`, a pair `(c, c + 1)` with some
    /// `pairs[i][c] = H_i > 0` counts once, each row's two terms replaced
    /// by `H_i sigma_max([ghat_c ghat_{c+1}])` where that is smaller.
    fn grouped<const N: usize>(
        &self,
        ghat: &[f64],
        per: [&Row; N],
        pairs: Option<[&Row; N]>,
    ) -> Grouped<N> {
        let gv = |c: usize| DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
        let q0 = self.quad.map_or(usize::MAX, |(q, _)| q);
        let mut out = Grouped::<N>::EMPTY;
        let k = self.k.min(ghat.len() / 3);
        let mut c = 1;
        while c < k {
            if c == q0 || c == q0.wrapping_add(1) {
                c += 1;
                continue;
            }
            let a = gv(c);
            let mut w: [f64; N] = core::array::from_fn(|i| per[i][c] * a.length());
            let mut step = 1;
            if let Some(h) = pairs.filter(|h| h.iter().any(|h| h[c] > 0.0)) {
                // The pair (c, c + 1): one joint term `H sigma_max`, where
                // smaller.
                let b = gv(c + 1);
                let (aa, bb, ab) = (a.dot(a), b.dot(b), a.dot(b));
                let lam = 0.5 * (aa + bb) + libm::sqrt(0.25 * (aa - bb) * (aa - bb) + ab * ab);
                for (i, wi) in w.iter_mut().enumerate() {
                    *wi = (*wi + per[i][c + 1] * b.length()).min(h[i][c] * libm::sqrt(lam));
                }
                step = 2;
            }
            let m = libm::fabs(self.mu[c]);
            if out.n > 0 && out.mu[out.n - 1].to_bits() == m.to_bits() {
                for (x, y) in out.w[out.n - 1].iter_mut().zip(w) {
                    *x += y;
                }
            } else {
                out.mu[out.n] = m;
                out.w[out.n] = w;
                out.n += 1;
            }
            c += step;
        }
        out
    }

    /// The affine function of [`ValenceTable::corner_flatness`] at `w` in
    /// `[0, 1]^2` (corner-cell coordinates, `w = 2^k (u, v)`), without the
    /// limit point: `sum_c mu_c^k ghat_c l_c(w)`. For tests of the bound.
    pub fn corner_affine(&self, ghat: &[f64], k: u32, w: (f64, f64)) -> DVec3 {
        let mut a = DVec3::ZERO;
        for c in 1..self.k.min(ghat.len() / 3) {
            let [al, be] = self.flat_lin[c];
            let g = DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
            a += g * (powi(self.mu[c], k) * (al * w.0 + be * w.1));
        }
        a
    }

    /// Control points of the extraordinary sub-patch after `i` subdivision
    /// steps, `A^i G = R B^i ghat`, in label order (`out.len() >= 2n+8`).
    pub fn level_points(&self, ghat: &[f64], i: u32, out: &mut [DVec3]) {
        let mut c = [[0.0f64; MAX_K]; 3];
        self.coefficients(ghat, i + 1, &mut c);
        let k = self.k.min(out.len());
        for (r, o) in out.iter_mut().enumerate().take(k) {
            let row = &self.right[r];
            let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
            for j in 0..self.k {
                x += row[j] * c[0][j];
                y += row[j] * c[1][j];
                z += row[j] * c[2][j];
            }
            *o = DVec3::new(x, y, z);
        }
    }

    /// The coefficients of the complex pair (frequency 0, a 2x2 block `b`
    /// of `B`, columns `q0, q0 + 1`) at power `e`: `b^e` applied to the
    /// pair's two `ghat` rows (overwrites those two columns of `out`).
    #[inline]
    fn quad_coefficients(&self, ghat: &[f64], e: u32, k: usize, out: &mut [[f64; MAX_K]; 3]) {
        let gv = |c: usize| DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
        if let Some((q0, b)) = self.quad {
            if q0 + 1 < k {
                let p = pow2x2(b, e);
                let (g0, g1) = (gv(q0), gv(q0 + 1));
                let a = g0 * p[0][0] + g1 * p[0][1];
                let bb = g0 * p[1][0] + g1 * p[1][1];
                for (c, (x, y)) in [(a.x, bb.x), (a.y, bb.y), (a.z, bb.z)].iter().enumerate() {
                    out[c][q0] = *x;
                    out[c][q0 + 1] = *y;
                }
            }
        }
    }

    /// Eigen coefficients at level `m` (>= 1), `B^(m-1) ghat`, as three
    /// coordinate arrays.
    #[inline]
    fn coefficients(&self, ghat: &[f64], m: u32, out: &mut [[f64; MAX_K]; 3]) {
        let e = m - 1;
        let k = self.k.min(ghat.len() / 3);
        for c in 0..k {
            let w = powi(self.mu[c], e);
            out[0][c] = ghat[3 * c] * w;
            out[1][c] = ghat[3 * c + 1] * w;
            out[2][c] = ghat[3 * c + 2] * w;
        }
        self.quad_coefficients(ghat, e, k, out);
    }

    /// The control grid of sub-patch (m, b) (`m >= 1`, `b` in 1..=3),
    /// including (`with_limit`) or excluding the eigenvalue-1 term.
    pub fn sub_patch(&self, ghat: &[f64], m: u32, b: usize, with_limit: bool, out: &mut Grid) {
        let mut c = [[0.0f64; MAX_K]; 3];
        self.coefficients(ghat, m, &mut c);
        if !with_limit {
            c[0][0] = 0.0;
            c[1][0] = 0.0;
            c[2][0] = 0.0;
        }
        let x = &self.x[b.clamp(1, 3) - 1];
        let k = self.k;
        for (co, cc) in c.iter().enumerate() {
            let mut acc = [0.0f64; 16];
            for (col, &w) in x[..k].iter().zip(cc[..k].iter()) {
                axpy16(&mut acc, w, col);
            }
            out[co * 16..co * 16 + 16].copy_from_slice(&acc);
        }
    }

    /// The three control grids of sub-patches `(m, 1)`, `(m, 2)`, `(m, 3)`
    /// at once: bit for bit what three calls of [`ValenceTable::sub_patch`]
    /// give, with the eigen coefficients computed once (the powers of the
    /// eigenvalues two columns at a time, by the same binary powering) and
    /// the eigenvalue-1 column skipped when it is excluded (its weight is
    /// zero and the table entries are finite, so the sums do not change).
    pub(crate) fn sub_patches3(&self, ghat: &[f64], m: u32, with_limit: bool, out: &mut [Grid; 3]) {
        use crate::math::simd::F2;
        let mut c = [[0.0f64; MAX_K]; 3];
        let e = m - 1;
        let k = self.k.min(ghat.len() / 3);
        // powi(mu[c], e) for columns c, c + 1 in the two lanes.
        let mut c0 = 0;
        while c0 < k {
            let c1 = (c0 + 1).min(MAX_K - 1);
            let (mut r, mut x, mut ee) = (F2::splat(1.0), F2::ld2(self.mu[c0], self.mu[c1]), e);
            while ee > 0 {
                if ee & 1 == 1 {
                    r = r.mul(x);
                }
                x = x.mul(x);
                ee >>= 1;
            }
            for (j, w) in [(c0, r.lo()), (c0 + 1, r.hi())] {
                if j < k {
                    c[0][j] = ghat[3 * j] * w;
                    c[1][j] = ghat[3 * j + 1] * w;
                    c[2][j] = ghat[3 * j + 2] * w;
                }
            }
            c0 += 2;
        }
        self.quad_coefficients(ghat, e, k, &mut c);
        let first = if with_limit { 0 } else { 1 };
        #[cfg(target_arch = "x86_64")]
        if crate::math::simd::has_avx2() {
            // SAFETY: the CPU runs AVX2 (checked just above).
            unsafe { self.combine_avx2(&c, first, out) };
            return;
        }
        let kk = self.k;
        for (x, g) in self.x.iter().zip(out.iter_mut()) {
            for (co, cc) in c.iter().enumerate() {
                let z = F2::splat(0.0);
                let mut acc = [z; 8];
                for (col, &w) in x[first..kk].iter().zip(cc[first..kk].iter()) {
                    let wv = F2::splat(w);
                    for (i, a) in acc.iter_mut().enumerate() {
                        *a = a.add(wv.mul(F2::ld(col, 2 * i)));
                    }
                }
                for (i, a) in acc.iter().enumerate() {
                    a.st(g, co * 16 + 2 * i);
                }
            }
        }
    }

    /// The grid sums of [`ValenceTable::sub_patches3`] on four lanes: for
    /// each region, coordinate and grid value, `sum_col w_col * x_col` over
    /// columns `first..k` in order, one multiply and one add per term (the
    /// same operations as the two-lane loop, so the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn combine_avx2(&self, c: &[[f64; MAX_K]; 3], first: usize, out: &mut [Grid; 3]) {
        use core::arch::x86_64::*;
        let kk = self.k;
        for (x, g) in self.x.iter().zip(out.iter_mut()) {
            for (co, cc) in c.iter().enumerate() {
                let mut acc = [_mm256_setzero_pd(); 4];
                for (col, &w) in x[first..kk].iter().zip(cc[first..kk].iter()) {
                    let wv = _mm256_set1_pd(w);
                    for (i, a) in acc.iter_mut().enumerate() {
                        // SAFETY: 4 values at 4 i + 4 <= 16 of a column.
                        let v = unsafe { _mm256_loadu_pd(col[4 * i..4 * i + 4].as_ptr()) };
                        *a = _mm256_add_pd(*a, _mm256_mul_pd(wv, v));
                    }
                }
                for (i, a) in acc.iter().enumerate() {
                    let at = co * 16 + 4 * i;
                    // SAFETY: 4 values at at + 4 <= 48 of the grid.
                    unsafe { _mm256_storeu_pd(g[at..at + 4].as_mut_ptr(), *a) };
                }
            }
        }
    }

    /// Limit position, tangents and normal at the extraordinary vertex.
    ///
    /// `du`, `dv` are the limit directions of the parametric derivatives along
    /// the two patch edges: `du = lim_{m->inf} dS/du(2^-m, 0) / (2 lambda)^(m-1)`
    /// (lambda = subdominant eigenvalue), likewise `dv` along `u = 0`. Their
    /// cross product is the limit normal. Second derivatives are reported as 0.
    pub fn eval_at_ev(&self, ghat: &[f64]) -> Eval {
        let mut du = DVec3::ZERO;
        let mut dv = DVec3::ZERO;
        let gv = |c: usize| DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
        for c in self.sub.0..self.sub.1.min(ghat.len() / 3) {
            du += gv(c) * self.tan_u[c];
            dv += gv(c) * self.tan_v[c];
        }
        Eval {
            p: gv(0),
            du,
            dv,
            normal: du.cross(dv).normalize_or_zero(),
            ..Eval::default()
        }
    }

    /// Evaluates the patch at (u, v) in `[0, 1]^2` from its eigen projection
    /// `ghat` (see [`ValenceTable::project`]); the EV is at (0,0).
    /// `cache`, when given, holds the six sub-patch grids of levels 1
    /// and 2 (grid `(m-1)*3 + b-1` at `cache[48*grid..]`, made by
    /// [`ValenceTable::sub_patch`] with the limit term) and short-cuts those
    /// levels.
    #[inline]
    pub fn eval_projected<const SECOND: bool>(
        &self,
        ghat: &[f64],
        cache: Option<&[f64]>,
        u: f64,
        v: f64,
    ) -> Eval {
        self.eval_projected_with::<SECOND, true>(ghat, cache, u, v)
    }

    /// [`ValenceTable::eval_projected`]; the normal is computed only when
    /// `NORMAL` (otherwise it is left zero, except at the EV itself).
    #[inline]
    pub(crate) fn eval_projected_with<const SECOND: bool, const NORMAL: bool>(
        &self,
        ghat: &[f64],
        cache: Option<&[f64]>,
        u: f64,
        v: f64,
    ) -> Eval {
        let t = if u > v { u } else { v };
        if t <= 0.0 {
            return self.eval_at_ev(ghat);
        }
        let (_, e) = libm::frexp(t);
        let m = (1 - e).max(1);
        let ub = libm::scalbn(u, m);
        let vb = libm::scalbn(v, m);
        let (b, uu, vv) = if ub >= 1.0 {
            if vb >= 1.0 {
                (2, ub - 1.0, vb - 1.0)
            } else {
                (1, ub - 1.0, vb)
            }
        } else {
            (3, ub, vb - 1.0)
        };
        let mut e = match cache {
            Some(cg) if m <= 2 && cg.len() >= 6 * 48 => {
                let i = ((m as usize - 1) * 3 + b - 1) * 48;
                match <&Grid>::try_from(&cg[i..i + 48]) {
                    Ok(g) => eval_grid::<SECOND>(g, uu, vv),
                    Err(_) => Eval::default(),
                }
            }
            _ => {
                let mut g = [0.0; 48];
                self.sub_patch(ghat, m as u32, b, false, &mut g);
                let mut e = eval_grid::<SECOND>(&g, uu, vv);
                e.p += DVec3::new(ghat[0], ghat[1], ghat[2]);
                e
            }
        };
        let s1 = libm::scalbn(1.0, m);
        if m < 1000 {
            e.du *= s1;
            e.dv *= s1;
            if SECOND {
                let s2 = s1 * s1;
                e.duu *= s2;
                e.duv *= s2;
                e.dvv *= s2;
            }
        } else {
            let sc = |x: DVec3, k: i32| {
                DVec3::new(
                    libm::scalbn(x.x, k),
                    libm::scalbn(x.y, k),
                    libm::scalbn(x.z, k),
                )
            };
            e.du = sc(e.du, m);
            e.dv = sc(e.dv, m);
            if SECOND {
                e.duu = sc(e.duu, 2 * m);
                e.duv = sc(e.duv, 2 * m);
                e.dvv = sc(e.dvv, 2 * m);
            }
        }
        if !NORMAL {
            return e;
        }
        let n = e.du.cross(e.dv);
        let l2 = n.length_squared();
        e.normal = if l2.is_normal() {
            n / libm::sqrt(l2)
        } else {
            // Deep near the EV the derivatives underflow (they scale like
            // (2 lambda)^m); the normal has converged to the limit normal.
            self.eval_at_ev(ghat).normal
        };
        e
    }

    /// Patch-level evaluation from the 2n+8 control points in label order
    /// (see [`crate::mesh::stencil`]); projects on every call, so prefer
    /// [`ValenceTable::project`] + [`ValenceTable::eval_projected`] for many
    /// points on one patch.
    pub fn eval_patch(
        &self,
        points: &[DVec3],
        u: f64,
        v: f64,
        second: bool,
    ) -> Result<Eval, Error> {
        if points.len() < self.k {
            return Err(Error::BufferTooSmall { required: self.k });
        }
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(Error::ParameterOutOfRange);
        }
        let mut g = [0.0; 3 * MAX_K];
        self.project(points, &mut g);
        let g = &g[..3 * self.k];
        Ok(if second {
            self.eval_projected::<true>(g, None, u, v)
        } else {
            self.eval_projected::<false>(g, None, u, v)
        })
    }
}

/// Tables for every valence `3..=MAX_VALENCE` (about 50 KiB each for
/// `MAX_VALENCE = 16`, 14 tables: 694 KiB).
pub struct TableSet {
    tables: [ValenceTable; MAX_VALENCE - 2],
    weights: Weights,
}

impl TableSet {
    /// An empty set; fill it with [`TableSet::build_into`].
    pub const ZERO: TableSet = TableSet {
        tables: [const { ValenceTable::ZERO }; MAX_VALENCE - 2],
        weights: Weights::STANDARD,
    };

    /// Builds all valences for vertex rule `w`.
    pub fn build_into(&mut self, w: &Weights, scratch: &mut BuildScratch) -> Result<(), Error> {
        self.weights = *w;
        for n in 3..=MAX_VALENCE {
            self.tables[n - 3].build_into(n, w, scratch)?;
        }
        Ok(())
    }

    /// The table of valence `n`, if built.
    #[inline]
    pub fn get(&self, n: usize) -> Option<&ValenceTable> {
        if (3..=MAX_VALENCE).contains(&n) {
            let t = &self.tables[n - 3];
            if t.n == n {
                return Some(t);
            }
        }
        None
    }

    /// The vertex rule the tables were built for.
    pub fn weights(&self) -> &Weights {
        &self.weights
    }
}

/// `N` sums `sum_g mu_g^k w_g[i]`, one weight row per distinct eigenvalue
/// modulus `mu_g` ([`ValenceTable::grouped`]).
#[derive(Clone, Copy)]
pub(crate) struct Grouped<const N: usize> {
    n: usize,
    mu: Row,
    w: [[f64; N]; MAX_K],
}

impl<const N: usize> Grouped<N> {
    /// No terms (sums of 0).
    const EMPTY: Self = Grouped {
        n: 0,
        mu: [0.0; MAX_K],
        w: [[0.0; N]; MAX_K],
    };

    /// The sums at the level whose powers `mu_g^k` are `p[g]`, and the
    /// powers advanced to the next level (one multiplication each).
    #[inline]
    fn next_level(&self, p: &mut Row) -> [f64; N] {
        let mut d = [0.0f64; N];
        for ((pg, m), w) in p[..self.n].iter_mut().zip(&self.mu).zip(&self.w) {
            for (x, y) in d.iter_mut().zip(w) {
                *x += *pg * y;
            }
            *pg *= m;
        }
        d
    }

    /// The sums at level `k` (binary powering).
    fn at(&self, k: u32) -> [f64; N] {
        let mut d = [0.0f64; N];
        for (m, w) in self.mu[..self.n].iter().zip(&self.w[..self.n]) {
            let pk = powi(*m, k);
            for (x, y) in d.iter_mut().zip(w) {
                *x += pk * y;
            }
        }
        d
    }
}

/// The terms of a patch's corner bounds (flatness `E_k`, radius `R_k`;
/// [`ValenceTable::flatness_terms`], [`ValenceTable::corner_radius`]):
/// `sum_g mu_g^k w_g` + the 2x2 block's term, one weight `w_g` per
/// distinct eigenvalue modulus `mu_g`.
#[derive(Clone, Copy)]
pub(crate) struct EigenTerms {
    g: Grouped<1>,
    /// The 2x2 block, its two `ghat` rows and `(F_q0 + F_q1) growth`.
    quad: Option<([[f64; 2]; 2], DVec3, DVec3, f64)>,
}

impl EigenTerms {
    /// No terms (a bound of 0).
    pub(crate) const EMPTY: EigenTerms = EigenTerms {
        g: Grouped::EMPTY,
        quad: None,
    };

    /// [`EigenTerms::at`] for `k = 0..out.len()` at once, the powers
    /// `mu^k` and `B^k` by one multiplication per level (so equal to `at`
    /// up to a few ulps, not bit for bit).
    pub(crate) fn levels(&self, out: &mut [f64]) {
        let mut p = [1.0f64; MAX_K];
        let mut b = [[1.0, 0.0], [0.0, 1.0]];
        for e in out.iter_mut() {
            let [mut r] = self.g.next_level(&mut p);
            if let Some((m, g0, g1, f)) = self.quad {
                let a = (g0 * b[0][0] + g1 * b[0][1]).length();
                let c = (g0 * b[1][0] + g1 * b[1][1]).length();
                r += f * a.max(c);
                b = mul2x2(b, m);
            }
            *e = r;
        }
    }

    /// The bound of the corner region `[0, 2^-k]^2`.
    pub(crate) fn at(&self, k: u32) -> f64 {
        let [mut r] = self.g.at(k);
        if let Some((m, g0, g1, f)) = self.quad {
            let p = pow2x2(m, k);
            let a = (g0 * p[0][0] + g1 * p[0][1]).length();
            let b = (g0 * p[1][0] + g1 * p[1][1]).length();
            r += f * a.max(b);
        }
        r
    }
}

/// The terms of a patch's ring-region bound ([`ValenceTable::ring_terms`]):
/// per distinct eigenvalue modulus, the weights of the three kinds of
/// second difference (along u, along v, mixed).
#[derive(Clone, Copy)]
pub(crate) struct RingTerms(Grouped<3>);

impl RingTerms {
    /// The ring bound at levels `k = 0..out.len()` (powers by one
    /// multiplication per level: equal to [`RingTerms::at`] up to a few
    /// ulps, which the bound's margin covers).
    pub(crate) fn levels(&self, out: &mut [f64]) {
        let mut p = [1.0f64; MAX_K];
        for e in out.iter_mut() {
            *e = ring_bound_of(self.0.next_level(&mut p));
        }
    }

    /// The ring bound at level `k`.
    pub(crate) fn at(&self, k: u32) -> f64 {
        ring_bound_of(self.0.at(k))
    }
}

/// The bound `lambda_max([[a, c], [c, b]]) / 3` of [`crate::bounds::cell`]
/// from the largest lengths of a Bezier net's second differences along u,
/// along v and mixed (`d`): `a, b = 6 d[0], 6 d[1]`, `c = 9 d[2]`, with a
/// relative margin of `1e-12` for the rounding of the table constants and
/// the sums.
pub(crate) fn ring_bound_of(d: [f64; 3]) -> f64 {
    crate::math::bezier::second_bound([6.0 * d[0], 6.0 * d[1], 9.0 * d[2]]) * (1.0 + 1e-12)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::boxed::Box;

    #[test]
    fn sub_patches3_matches_sub_patch() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Weights::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        for n in 3..=MAX_VALENCE {
            let tab = ts.get(n).unwrap();
            let k = 2 * n + 8;
            let mut ghat = [0.0; 3 * MAX_K];
            for x in ghat.iter_mut().take(3 * k) {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                *x = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            }
            for m in 1..32 {
                for lim in [false, true] {
                    let mut three = [[0.0; 48]; 3];
                    tab.sub_patches3(&ghat[..3 * k], m, lim, &mut three);
                    for b in 1..=3 {
                        let mut one = [0.0; 48];
                        tab.sub_patch(&ghat[..3 * k], m, b, lim, &mut one);
                        assert_eq!(one.map(f64::to_bits), three[b - 1].map(f64::to_bits));
                    }
                }
            }
        }
    }
    /// `EigenTerms::levels` (one multiplication per level) against
    /// `EigenTerms::at` (binary powering) for random projections at every
    /// valence, for the standard rules and for weights whose tables have a
    /// 2x2 block (a complex pair): equal to 1e-14 relative.
    #[test]
    fn levels_match_at() {
        let mut complex = Weights::STANDARD;
        for n in (3..=MAX_VALENCE).filter(|&n| n != 4) {
            complex.set(n, 0.5, 0.3, 0.2).unwrap();
        }
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        for (w, want_quads) in [(Weights::STANDARD, false), (complex, true)] {
            let mut ts = Box::new(TableSet::ZERO);
            ts.build_into(&w, &mut Box::new(BuildScratch::ZERO))
                .unwrap();
            let mut worst = 0.0f64;
            let mut quads = 0;
            for n in 3..=MAX_VALENCE {
                let tab = ts.get(n).unwrap();
                let k = 2 * n + 8;
                for _ in 0..20 {
                    let mut ghat = [0.0; 3 * MAX_K];
                    for x in ghat.iter_mut().take(3 * k) {
                        s ^= s << 13;
                        s ^= s >> 7;
                        s ^= s << 17;
                        *x = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    }
                    let mut t = EigenTerms::EMPTY;
                    tab.flatness_terms(&ghat[..3 * k], &mut t);
                    quads += t.quad.is_some() as usize;
                    let mut all = [0.0; 31];
                    t.levels(&mut all);
                    for (lv, &v) in all.iter().enumerate() {
                        let want = t.at(lv as u32);
                        assert!(want > 0.0, "valence {n} level {lv}");
                        worst = worst.max((v - want).abs() / want);
                    }
                }
            }
            assert_eq!(quads > 0, want_quads);
            assert!(worst <= 1e-14, "worst relative difference {worst:e}");
        }
    }
}
