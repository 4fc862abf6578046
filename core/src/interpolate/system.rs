//! The least-squares similarity system (\[CL-R eqs. 4.5, 4.6\]), applied
//! without assembling it (the matrix-free path; [`super::assembled`] holds
//! the same matrix in blocks).
//!
//! Each sampled derivative gives the row `S_d(Q) x S_d(G) = 0`, three
//! scalar equations of which two are independent. With `g = S_d(G)` (scaled
//! per derivative kind by its RMS over `G`) and `q = S_d(Q) = sum_k w_k
//! Q_{l_k}`, the squared residual is `|q x g|^2 = q . (|g|^2 q - (g . q) g)`.
//! These rows alone are also met by shrinking or reversing `q`; an
//! optional parallel term `mu ((q - S g_true) . g)^2`
//! ([`super::InterpolationOptions::parallel_weight`], default 0) pulls the
//! component along `g` towards `G`'s derivative scaled per axis by `S`, the
//! report's initial-guess scaling (\[CL-R §4\]: extent of `P`'s bounding
//! box over that of the limit points of `G`'s Type I vertices). It keeps the
//! problem linear; measured on 8 meshes it cuts iterations (192 -> 55 on
//! `catmark_lefthanded` at `mu = 0.1`) but does not reduce folds there (810
//! -> 1737), so it is off by default.
//! The normal matrix is `A = sum (w w^T) (x) (|g|^2 I - (1 - mu) g g^T)`: the
//! redundant third equation costs nothing, and rows weigh with `|g|^2`, so a
//! vanishing derivative of `G` (a flat spot's second derivative) drops out
//! instead of imposing a random direction.
//!
//! Storage: per face of `G` its labels, per valence the weight rows, per
//! (face, sample, kind) the vector `g`: the normal matrix of the Type II
//! unknowns is `T^T A T` with `T` the substitution of \[CL-R eq. 4.1\]
//! ([`super::ring`]), applied face by face in `O(faces)` per product.

use super::blocks::Matrix;
use super::interpolator::{drow, nzrow, wrow, Interpolator, NS};
use super::ring::{add3, for_ring, get3};
use super::samples::ROWS;
use super::solver::NormalSystem;
use crate::config::MAX_VALENCE;
use crate::mesh::stencil::MAX_K;
use glam::DVec3;

/// Largest number of distinct unknowns one row touches after the Type I
/// substitution: every label replaced by its ring.
const MAX_ROW: usize = MAX_K * (1 + 2 * MAX_VALENCE);

impl Interpolator<'_> {
    /// The similarity residual `sum |q x g|^2` (\[CL-R eq. 4.5\]) of the
    /// control points `q` (all vertices); with `y`, also writes the product
    /// with the normal matrix of the solved functional
    /// `sum |q x g|^2 + mu ((q - S g) . g)^2` (full numbering; `S` the
    /// per-axis scale of [`Interpolator`]).
    ///
    /// With `affine`, `y` is the gradient half of the full functional,
    /// `A q - c` with the parallel term's target `c`; without, the linear
    /// part `A q` only.
    pub(crate) fn similarity(&self, q: &[f64], mut y: Option<&mut [f64]>, affine: bool) -> f64 {
        if let Some(y) = y.as_deref_mut() {
            y.fill(0.0);
        }
        let mut total = 0.0;
        let mu = self.opts.parallel_weight;
        let mut pts = [DVec3::ZERO; MAX_K];
        let mut acc = [DVec3::ZERO; MAX_K];
        let kinds = self.opts.derivatives;
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = 2 * n + 8;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            for (p, &l) in pts.iter_mut().zip(lab) {
                *p = get3(q, l as usize);
            }
            acc[..k].fill(DVec3::ZERO);
            for s in 0..NS {
                for d in 1..ROWS {
                    if kinds & (1 << d) == 0 {
                        continue;
                    }
                    let g = get3(&self.dirs[drow(f, s, 0)..], d);
                    let g2 = g.length_squared();
                    if g2 == 0.0 {
                        continue;
                    }
                    let w = &self.weights[wrow(n, s, d)..][..MAX_K];
                    let z = &self.nonzero[nzrow(n, s, d)..][..MAX_K + 1];
                    let nz = &z[1..1 + z[0] as usize];
                    let mut qv = DVec3::ZERO;
                    for &j in nz {
                        let j = j as usize;
                        qv += pts[j] * w[j];
                    }
                    let gq = g.dot(qv);
                    total += qv.length_squared() * g2 - gq * gq;
                    // |g|^2 q - (g.q) g + mu (g.q) g, minus mu |g|^2 g.
                    let mut r = qv * g2 - g * ((1.0 - mu) * gq);
                    if affine {
                        r -= g * (mu * self.rms[d] * g.dot(g * self.scale));
                    }
                    if y.is_some() {
                        for &j in nz {
                            let j = j as usize;
                            acc[j] += r * w[j];
                        }
                    }
                }
            }
            if let Some(y) = y.as_deref_mut() {
                for (a, &l) in acc[..k].iter().zip(lab) {
                    add3(y, l as usize, *a);
                }
            }
        }
        total
    }

    /// `ap = T^T A T p` for a vector `p` of Type II unknowns (Type I entries
    /// ignored); `tmp` is scratch of the same length.
    pub(crate) fn apply_normal(&self, p: &[f64], tmp: &mut [f64], ap: &mut [f64]) {
        tmp.copy_from_slice(p);
        super::ring::fill_type1(&self.g, self.coef, None, tmp);
        self.similarity(tmp, Some(&mut *ap), false);
        self.anchor_terms(tmp, Some(&mut *ap), false);
        self.orient_terms(tmp, Some(&mut *ap), false);
        super::ring::fold_type1(&self.g, self.coef, ap);
    }

    /// Adds the anchor rows' product ([`super::folds`]) to `ap`, which
    /// holds the assembled product (Type I entries zero).
    fn apply_anchors(&self, p: &[f64], tmp: &mut [f64], ap: &mut [f64]) {
        if !self.anchored && !self.oriented {
            return;
        }
        tmp.copy_from_slice(p);
        super::ring::fill_type1(&self.g, self.coef, None, tmp);
        self.anchor_terms(tmp, Some(&mut *ap), false);
        self.orient_terms(tmp, Some(&mut *ap), false);
        super::ring::fold_type1(&self.g, self.coef, ap);
    }

    /// The inverses of the 3x3 diagonal blocks of `T^T A T` (row-major, 9
    /// per vertex; zero for Type I vertices) into `out`, anchor rows
    /// ([`super::folds`]) included unless there are extra requirements
    /// (their projection is factored in the metric of the build).
    pub(crate) fn build_preconditioner(&self, out: &mut [f64]) {
        out.fill(0.0);
        // Scatter array of the row coefficients of one sample row.
        let mut touched = [0u32; MAX_ROW];
        let kinds = self.opts.derivatives;
        let mu = self.opts.parallel_weight;
        // A sparse row over the unknowns: (vertex, coefficient), merged by
        // a linear scan within the row (rows are short: a few dozen).
        let mut vals = [0.0f64; MAX_ROW];
        let with_anchors = self.rows.count() == 0;
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = 2 * n + 8;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            for s in 0..NS {
                for d in 1..ROWS {
                    let anchor = if with_anchors && d <= 2 {
                        self.anchor[f]
                    } else {
                        0.0
                    };
                    let g = if kinds & (1 << d) == 0 {
                        DVec3::ZERO
                    } else {
                        get3(&self.dirs[drow(f, s, 0)..], d)
                    };
                    let g2 = g.length_squared();
                    if g2 == 0.0 && anchor == 0.0 {
                        continue;
                    }
                    let o = wrow(n, s, d);
                    let w = &self.weights[o..o + k];
                    let mut len = 0usize;
                    let mut push = |v: usize, c: f64, len: &mut usize| {
                        if c == 0.0 {
                            return;
                        }
                        for t in 0..*len {
                            if touched[t] as usize == v {
                                vals[t] += c;
                                return;
                            }
                        }
                        if *len < MAX_ROW {
                            touched[*len] = v as u32;
                            vals[*len] = c;
                            *len += 1;
                        }
                    };
                    for (&l, &wj) in lab.iter().zip(w) {
                        let l = l as usize;
                        if l >= self.n1 {
                            push(l, wj, &mut len);
                        } else {
                            let (ce, cf) = (self.coef[3 * l + 1], self.coef[3 * l + 2]);
                            for_ring(&self.g, l, |e, fv| {
                                push(e, -wj * ce, &mut len);
                                push(fv, -wj * cf, &mut len);
                            });
                        }
                    }
                    for t in 0..len {
                        let c2 = vals[t] * vals[t];
                        let b = &mut out[9 * touched[t] as usize..][..9];
                        for r in 0..3 {
                            for c in 0..3 {
                                let id = if r == c { g2 + anchor } else { 0.0 };
                                b[3 * r + c] += c2 * (id - (1.0 - mu) * g[r] * g[c]);
                            }
                        }
                    }
                }
            }
        }
        if with_anchors {
            let mut vecs = [DVec3::ZERO; MAX_ROW];
            self.orient_blocks(out, &mut touched, &mut vecs);
        }
        for v in 0..self.m {
            let b = &mut out[9 * v..9 * v + 9];
            invert3(b);
        }
    }

    /// The block-Jacobi blocks of [`Interpolator::build_preconditioner`]
    /// from the assembled matrix: its diagonal blocks (the similarity part,
    /// assembled once) plus the orientation rows' blocks, inverted. Used
    /// for the fold rounds instead of the face-by-face pass over every
    /// sample row (same blocks up to rounding order; not with anchor rows,
    /// which the matrix does not hold).
    pub(crate) fn preconditioner_from_matrix(&self, mat: &Matrix, out: &mut [f64]) {
        out[..9 * self.n1].fill(0.0);
        for r in 0..self.m - self.n1 {
            let a = &mat.vals[6 * mat.start[r] as usize..][..6];
            out[9 * (self.n1 + r)..][..9]
                .copy_from_slice(&[a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5]]);
        }
        if self.rows.count() == 0 {
            let mut touched = [0u32; MAX_ROW];
            let mut vecs = [DVec3::ZERO; MAX_ROW];
            self.orient_blocks(out, &mut touched, &mut vecs);
        }
        for b in out[9 * self.n1..9 * self.m].chunks_exact_mut(9) {
            invert3(b);
        }
    }

    /// `z -= M^-1 u`.
    pub(crate) fn precondition_sub(&self, u: &[f64], z: &mut [f64]) {
        match self.opts.preconditioner {
            super::options::Preconditioner::None => {
                for (z, u) in z.iter_mut().zip(u) {
                    *z -= u;
                }
            }
            _ => {
                for v in 0..self.m {
                    let b = &self.precond[9 * v..9 * v + 9];
                    let x = get3(u, v);
                    z[3 * v] -= b[0] * x.x + b[1] * x.y + b[2] * x.z;
                    z[3 * v + 1] -= b[3] * x.x + b[4] * x.y + b[5] * x.z;
                    z[3 * v + 2] -= b[6] * x.x + b[7] * x.y + b[8] * x.z;
                }
            }
        }
        z[..3 * self.n1].fill(0.0);
    }

    /// `z = M^-1 r` (block Jacobi or identity), Type I entries zero.
    pub(crate) fn precondition_block(&self, r: &[f64], z: &mut [f64]) {
        match self.opts.preconditioner {
            super::options::Preconditioner::None => z.copy_from_slice(r),
            _ => {
                for v in 0..self.m {
                    let b = &self.precond[9 * v..9 * v + 9];
                    let x = get3(r, v);
                    z[3 * v] = b[0] * x.x + b[1] * x.y + b[2] * x.z;
                    z[3 * v + 1] = b[3] * x.x + b[4] * x.y + b[5] * x.z;
                    z[3 * v + 2] = b[6] * x.x + b[7] * x.y + b[8] * x.z;
                }
            }
        }
        z[..3 * self.n1].fill(0.0);
    }
}

/// Inverts a symmetric 3x3 block in place; a block that is (numerically)
/// singular becomes the inverse of its trace times the identity, or zero.
pub(crate) fn invert3(b: &mut [f64]) {
    let (a, bb, c, d, e, f, g, h, i) = (b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8]);
    let co0 = e * i - f * h;
    let co1 = f * g - d * i;
    let co2 = d * h - e * g;
    let det = a * co0 + bb * co1 + c * co2;
    let tr = a + e + i;
    if tr > 0.0 && det > 1e-12 * tr * tr * tr {
        let inv = 1.0 / det;
        b[0] = co0 * inv;
        b[1] = (c * h - bb * i) * inv;
        b[2] = (bb * f - c * e) * inv;
        b[3] = co1 * inv;
        b[4] = (a * i - c * g) * inv;
        b[5] = (c * d - a * f) * inv;
        b[6] = co2 * inv;
        b[7] = (bb * g - a * h) * inv;
        b[8] = (a * e - bb * d) * inv;
    } else {
        let s = if tr > 0.0 { 3.0 / tr } else { 0.0 };
        b.fill(0.0);
        b[0] = s;
        b[4] = s;
        b[8] = s;
    }
}

impl NormalSystem for Interpolator<'_> {
    fn apply(&self, p: &[f64], tmp: &mut [f64], ap: &mut [f64]) {
        match &self.matrix {
            Some(mat) => {
                mat.apply(self.n1, p, ap);
                self.apply_anchors(p, tmp, ap);
            }
            None => self.apply_normal(p, tmp, ap),
        }
    }
    fn precondition(&self, r: &[f64], z: &mut [f64], tmp: &mut [f64], small: &mut [f64]) {
        let rows = &self.rows;
        let k = rows.count();
        if k == 0 && !self.anchored && !self.oriented {
            if let (Some(mat), super::options::Preconditioner::SymmetricGaussSeidel) =
                (&self.matrix, self.opts.preconditioner)
            {
                mat.sgs(self.n1, self.precond, r, z);
                return;
            }
        }
        self.precondition_block(r, z);
        self.project(z, tmp, small);
    }
    fn project(&self, v: &mut [f64], tmp: &mut [f64], small: &mut [f64]) {
        let rows = &self.rows;
        let k = rows.count();
        if k == 0 {
            return;
        }
        // v -= M^-1 E^T (E M^-1 E^T)^+ E v: the M-orthogonal projection.
        for (c, t) in small.iter_mut().enumerate().take(k) {
            *t = rows.row_dot(c, v);
        }
        super::requirements::solve_rows(rows.ldl, &mut small[..k]);
        tmp.fill(0.0);
        for (c, &t) in small.iter().enumerate().take(k) {
            rows.add_row(c, t, tmp);
        }
        self.precondition_sub(tmp, v);
    }
    fn limits(&self) -> (f64, u32, f64) {
        if self.loose {
            let tol = (self.opts.tolerance * super::orient::ROUND_TOLERANCE).min(1e-2);
            (tol, self.opts.max_iterations, 0.0)
        } else {
            // The first solve has first_residual 0 (relative only); the
            // one after the fold rounds starts near its solution, and
            // stops at the first solve's absolute accuracy at the latest.
            let tol = self.opts.tolerance;
            (tol, self.opts.max_iterations, tol * self.first_residual)
        }
    }
}
