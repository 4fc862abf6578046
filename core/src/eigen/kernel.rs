//! The exact evaluation kernel of an extraordinary patch (\[Stam98\],
//! \[CL-R §2.1\]): region `Omega_{m,b}`, the sub-patch grid
//! `G_{m,b} = X_b B^(m-1) L G`, the bicubic B-spline on it, and the limit
//! term (eigenvalue 1) kept separate for precision near the vertex.

use super::table::{axpy16, ValenceTable};
use crate::error::Error;
use crate::math::bspline::{eval_grid, eval_grid_with, Grid};
use crate::math::linalg::{pow2x2, powi};
use crate::math::simd::F2;
use crate::math::Eval;
use crate::mesh::stencil::MAX_K;
use glam::DVec3;

impl ValenceTable {
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
    pub(super) fn quad_coefficients(
        &self,
        ghat: &[f64],
        e: u32,
        k: usize,
        out: &mut [[f64; MAX_K]; 3],
    ) {
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
    /// coordinate arrays (the powers from [`ValenceTable::mu_pow`] below
    /// its last level, by [`powi`] beyond).
    #[inline]
    pub(super) fn coefficients(&self, ghat: &[f64], m: u32, out: &mut [[f64; MAX_K]; 3]) {
        let e = m - 1;
        let k = self.k.min(ghat.len() / 3);
        let pw = self.mu_pow.get(e as usize);
        for c in 0..k {
            // The stored power is `powi`'s, bit for bit.
            let w = match pw {
                Some(row) => row[c],
                None => powi(self.mu[c], e),
            };
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

    /// The level-1 grid of region `b` of eigen component `c` alone:
    /// [`ValenceTable::sub_patch`] at `m = 1` of a `ghat` that is zero but
    /// for component `c` (the same values: `ghat_c` times column `c` of
    /// the region's table), without the `k` columns of zeros. Components
    /// of a complex pair go through `sub_patch` (the pair's 2x2 block).
    pub(crate) fn component_grid(&self, ghat: &[f64], c: usize, b: usize, out: &mut Grid) {
        let in_pair = matches!(self.quad, Some((q0, _)) if c == q0 || c == q0 + 1);
        if in_pair || c >= self.k.min(MAX_K) || 3 * c + 3 > ghat.len() {
            let mut one = [0.0f64; 3 * MAX_K];
            let k = self.k.min(MAX_K).min(ghat.len() / 3);
            if c < k {
                one[3 * c..3 * c + 3].copy_from_slice(&ghat[3 * c..3 * c + 3]);
            }
            self.sub_patch(&one[..3 * k], 1, b, false, out);
            return;
        }
        let col = &self.x[b.clamp(1, 3) - 1][c];
        for a in 0..3 {
            let w = ghat[3 * c + a];
            for (o, &x) in out[16 * a..16 * a + 16].iter_mut().zip(col.iter()) {
                *o = w * x;
            }
        }
    }

    /// The grid of sub-patch `(m, b)` without the eigenvalue-1 term, the
    /// kernel of every evaluation beyond the cached levels 1 and 2: bit for bit
    /// [`ValenceTable::sub_patch`] with `with_limit = false`. Where the CPU
    /// has AVX2, the table has no 2x2 block and `m <= POW_LEVELS`, it runs
    /// on four lanes with the same multiplies and adds in the same order:
    /// the powers `mu_c^(m-1)` loaded from [`ValenceTable::mu_pow`] (made
    /// by [`powi`]), the weights `ghat_c mu_c^(m-1)`, then per grid value
    /// `sum_{c >= 1} w_c x_c` from zero, each table column loaded once for
    /// the three coordinates; column 0, whose weight is zero there, is
    /// skipped, which leaves the sums unchanged.
    #[inline]
    pub(crate) fn deep_grid(&self, ghat: &[f64], m: u32, b: usize, out: &mut Grid) {
        #[cfg(target_arch = "x86_64")]
        if crate::math::simd::has_avx2()
            && self.quad.is_none()
            && (1..=super::table::POW_LEVELS as u32).contains(&m)
            && ghat.len() >= 3 * self.k
        {
            // SAFETY: the CPU runs AVX2 (checked just above).
            unsafe { self.deep_grid_avx2(ghat, m, b, out) };
            return;
        }
        self.sub_patch(ghat, m, b, false, out);
    }

    /// [`ValenceTable::deep_grid`] on four lanes (`ghat.len() >= 3k`,
    /// `1 <= m <= POW_LEVELS`, no 2x2 block).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn deep_grid_avx2(&self, ghat: &[f64], m: u32, b: usize, out: &mut Grid) {
        use core::arch::x86_64::*;
        let k = self.k.min(MAX_K).min(ghat.len() / 3);
        let pw = &self.mu_pow[(m as usize - 1).min(super::table::POW_LEVELS - 1)];
        let xs = self.x[b.clamp(1, 3) - 1].as_ptr();
        let op = out.as_mut_ptr();
        let gp = ghat.as_ptr();
        // Two halves of the 16 grid values (6 accumulators, so that they,
        // the column and the weights stay in the 16 registers).
        for h in [0usize, 8] {
            let z = _mm256_setzero_pd();
            let (mut x0, mut x1, mut y0, mut y1, mut z0, mut z1) = (z, z, z, z, z, z);
            for j in 1..k {
                // SAFETY: column j < k <= MAX_K of the table, values
                // h..h + 8 of its 16; ghat has 3k values.
                let (v0, v1, gx, gy, gz) = unsafe {
                    let col = (*xs.add(j)).as_ptr().add(h);
                    (
                        _mm256_loadu_pd(col),
                        _mm256_loadu_pd(col.add(4)),
                        *gp.add(3 * j),
                        *gp.add(3 * j + 1),
                        *gp.add(3 * j + 2),
                    )
                };
                let p = pw[j];
                let w = _mm256_set1_pd(gx * p);
                x0 = _mm256_add_pd(x0, _mm256_mul_pd(w, v0));
                x1 = _mm256_add_pd(x1, _mm256_mul_pd(w, v1));
                let w = _mm256_set1_pd(gy * p);
                y0 = _mm256_add_pd(y0, _mm256_mul_pd(w, v0));
                y1 = _mm256_add_pd(y1, _mm256_mul_pd(w, v1));
                let w = _mm256_set1_pd(gz * p);
                z0 = _mm256_add_pd(z0, _mm256_mul_pd(w, v0));
                z1 = _mm256_add_pd(z1, _mm256_mul_pd(w, v1));
            }
            // SAFETY: values h..h + 8 of each coordinate's 16 in the grid
            // of 48.
            unsafe {
                _mm256_storeu_pd(op.add(h), x0);
                _mm256_storeu_pd(op.add(h + 4), x1);
                _mm256_storeu_pd(op.add(16 + h), y0);
                _mm256_storeu_pd(op.add(16 + h + 4), y1);
                _mm256_storeu_pd(op.add(32 + h), z0);
                _mm256_storeu_pd(op.add(32 + h + 4), z1);
            }
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
        self.eval_projected_at::<SECOND, NORMAL>(ghat, cache.ok_or(false), &[], u, v)
    }

    /// [`ValenceTable::eval_projected_with`], where the levels 1 and 2 come
    /// from the six sub-patch grids stored beside the projection, or, when
    /// they are not stored (`None`), from the same grids made per query by
    /// [`ValenceTable::sub_patch`] with the limit term: bit for bit the
    /// stored case (the grid is the one the stored one was made as).
    /// `deep` holds the grids of levels `3..3 + deep.len() / 144` (three
    /// regions of 48 values per level, made by
    /// [`ValenceTable::deep_grid`]: without the limit term) and short-cuts
    /// those levels, bit for bit what the kernel gives per query.
    #[inline]
    pub(crate) fn eval_projected_impl<const SECOND: bool, const NORMAL: bool>(
        &self,
        ghat: &[f64],
        grids: Option<&[f64]>,
        deep: &[f64],
        u: f64,
        v: f64,
    ) -> Eval {
        self.eval_projected_at::<SECOND, NORMAL>(ghat, grids.ok_or(true), deep, u, v)
    }

    /// [`ValenceTable::eval_projected_impl`], always inlined (the
    /// evaluator's single-point path: its result then stays in registers
    /// for the rotation and the caller's store instead of going through a
    /// frame; callgrind, BENCHMARKS.md).
    #[inline(always)]
    pub(crate) fn eval_projected_inlined<const SECOND: bool, const NORMAL: bool>(
        &self,
        ghat: &[f64],
        grids: Option<&[f64]>,
        deep: &[f64],
        u: f64,
        v: f64,
    ) -> Eval {
        self.eval_projected_body::<SECOND, NORMAL, false>(ghat, grids.ok_or(true), deep, u, v)
    }

    /// [`ValenceTable::eval_projected_impl`] compiled with AVX2, its
    /// bicubics on four-lane vectors (the same bits): one call out of the
    /// AVX2 evaluation paths of [`crate::Evaluator`] (inlined there it
    /// made the C ABI's per-point path slower on meshes of extraordinary
    /// patches only, measured).
    /// Elsewhere than x86_64 it is [`ValenceTable::eval_projected_impl`].
    ///
    /// # Safety
    /// The CPU runs AVX2 ([`crate::math::simd::has_avx2`]).
    #[cfg_attr(target_arch = "x86_64", target_feature(enable = "avx2"))]
    #[inline(never)]
    pub(crate) unsafe fn eval_projected_avx2<const SECOND: bool, const NORMAL: bool>(
        &self,
        ghat: &[f64],
        grids: Option<&[f64]>,
        deep: &[f64],
        u: f64,
        v: f64,
    ) -> Eval {
        self.eval_projected_body::<SECOND, NORMAL, true>(ghat, grids.ok_or(true), deep, u, v)
    }

    /// The body of both: `cache` is the stored grids, or whether levels 1
    /// and 2 make them per query (`Err(true)`) or evaluate them as the
    /// deeper levels do (`Err(false)`); `deep` the stored grids of levels
    /// 3 and beyond (see [`ValenceTable::eval_projected_impl`]).
    #[inline]
    fn eval_projected_at<const SECOND: bool, const NORMAL: bool>(
        &self,
        ghat: &[f64],
        cache: Result<&[f64], bool>,
        deep: &[f64],
        u: f64,
        v: f64,
    ) -> Eval {
        self.eval_projected_body::<SECOND, NORMAL, false>(ghat, cache, deep, u, v)
    }

    /// The body of [`ValenceTable::eval_projected_at`] and
    /// [`ValenceTable::eval_projected_inlined`].
    #[inline(always)]
    fn eval_projected_body<const SECOND: bool, const NORMAL: bool, const WIDE: bool>(
        &self,
        ghat: &[f64],
        cache: Result<&[f64], bool>,
        deep: &[f64],
        u: f64,
        v: f64,
    ) -> Eval {
        let Some((m, b, uu, vv)) = ring_region(u, v) else {
            return self.eval_at_ev(ghat);
        };
        let mut e = match cache {
            Ok(cg) if m <= 2 && cg.len() >= 6 * 48 => {
                let i = ((m as usize - 1) * 3 + b - 1) * 48;
                match <&Grid>::try_from(&cg[i..i + 48]) {
                    Ok(g) => eval_grid_with::<SECOND, WIDE>(g, uu, vv),
                    Err(_) => Eval::default(),
                }
            }
            Err(true) if m <= 2 => self.eval_made_grid::<SECOND>(ghat, m, b, true, uu, vv),
            _ => {
                // A stored grid of level m >= 3 (the kernel's, bit for
                // bit), else the kernel.
                let stored = if m >= 3 {
                    let i = (m as usize - 3) * 144 + (b - 1) * 48;
                    deep.get(i..i + 48).and_then(|d| <&Grid>::try_from(d).ok())
                } else {
                    None
                };
                let mut e = match stored {
                    Some(d) => eval_grid_with::<SECOND, WIDE>(d, uu, vv),
                    None => self.eval_made_grid::<SECOND>(ghat, m, b, false, uu, vv),
                };
                e.p += DVec3::new(ghat[0], ghat[1], ghat[2]);
                e
            }
        };
        let s1 = scale2(1.0, m);
        if m < 1000 {
            e.scale_derivatives::<SECOND>(s1);
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

    /// The grids that [`ValenceTable::eval_projected_at`] makes per query
    /// (not stored): with `sub` the level-1/2 grid of
    /// [`ValenceTable::sub_patch`] (with the limit term), else the
    /// kernel's [`ValenceTable::deep_grid`], evaluated at `(uu, vv)`. A
    /// frame of its own, so that the stored-grid paths do not clear its
    /// 384-byte grid per query.
    #[inline(never)]
    fn eval_made_grid<const SECOND: bool>(
        &self,
        ghat: &[f64],
        m: i32,
        b: usize,
        sub: bool,
        uu: f64,
        vv: f64,
    ) -> Eval {
        let mut g = [0.0; 48];
        if sub {
            self.sub_patch(ghat, m as u32, b, true, &mut g);
        } else {
            self.deep_grid(ghat, m as u32, b, &mut g);
        }
        eval_grid::<SECOND>(&g, uu, vv)
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

/// Where the point `(u, v)` of an extraordinary patch (the vertex at the
/// origin) lies: the level `m >= 1` of the ring `Omega_m` that holds it,
/// its region `b` there (1: `u` side, 2: diagonal, 3: `v` side) and its
/// parameters in that region's sub-patch; `None` at the vertex itself
/// (`max(u, v) <= 0`) \[Stam98 sec. 4\].
#[inline(always)]
pub(crate) fn ring_region(u: f64, v: f64) -> Option<(i32, usize, f64, f64)> {
    let t = if u > v { u } else { v };
    if t <= 0.0 {
        return None;
    }
    let m = corner_level(t);
    let (ub, vb) = (scale2(u, m), scale2(v, m));
    // Branch-free (the region is random from point to point): one of
    // `ub`, `vb` is at least 1; region 1 when only `ub` is, 2 when both
    // are, 3 when only `vb` is; the parameter that is at least 1 loses
    // 1 (`x - 0.0` is `x` bit for bit, signed zeros included), by a
    // compare mask: `ub - cu as u8 as f64` compiled to a jump.
    let (cu, cv) = (ub >= 1.0, vb >= 1.0);
    let b = 3 - 2 * cu as usize + (cu & cv) as usize;
    let w = F2::ld2(ub, vb);
    let one = F2::splat(1.0);
    let r = w.minus_where_ge(w, one, one);
    Some((m, b, r.lo(), r.hi()))
}

/// The level `m >= 1` of the corner region whose ring holds a point with
/// `max(u, v) = t` (`0 < t <= 1`): `max(1 - e, 1)` for `t = f 2^e`,
/// `f` in `[1/2, 1)` (`libm::frexp`), read from the exponent bits for a
/// normal `t` (the same value; `libm::frexp` for a subnormal one).
#[inline(always)]
fn corner_level(t: f64) -> i32 {
    let biased = ((t.to_bits() >> 52) & 0x7ff) as i32;
    let e = if biased == 0 {
        libm::frexp(t).1
    } else {
        biased - 1022
    };
    (1 - e).max(1)
}

/// `x 2^m`, as `libm::scalbn(x, m)` bit for bit: for `0 <= m <= 1023`
/// one multiplication by the power of two (exact where the result is
/// representable, as here: `|x 2^m| < 2` for the parameters of
/// [`corner_level`], and scaling up leaves no bits to round), else
/// `libm::scalbn`.
#[inline(always)]
fn scale2(x: f64, m: i32) -> f64 {
    if (0..=1023).contains(&m) {
        x * f64::from_bits(((1023 + m) as u64) << 52)
    } else {
        libm::scalbn(x, m)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use crate::eigen::{BuildScratch, TableSet};
    use crate::mesh::stencil::MAX_K;
    use crate::test_rng::XorShift;
    use std::boxed::Box;

    /// [`super::ValenceTable::component_grid`] gives the values of
    /// `sub_patch` at level 1 on a one-hot `ghat` (the way the measure's
    /// corner constants were computed before), for every valence,
    /// component and region.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn component_grid_is_one_hot_sub_patch() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
        for n in 3..=crate::config::MAX_VALENCE {
            let tab = ts.get(n).unwrap();
            let k = tab.num_points();
            let mut ghat = [0.0; 3 * MAX_K];
            for g in ghat.iter_mut() {
                *g = rng.unit() - 0.5;
            }
            for c in 1..k {
                for b in 1..=3 {
                    let mut one = [0.0; 3 * MAX_K];
                    one[3 * c..3 * c + 3].copy_from_slice(&ghat[3 * c..3 * c + 3]);
                    let (mut want, mut got) = ([0.0; 48], [1.0; 48]);
                    tab.sub_patch(&one[..3 * k], 1, b, false, &mut want);
                    tab.component_grid(&ghat[..3 * k], c, b, &mut got);
                    assert_eq!(want, got, "n {n} c {c} b {b}");
                }
            }
        }
    }

    /// The stored eigenvalue powers are `powi`'s bit for bit, and the
    /// evaluation kernel's grid (four lanes where the CPU has AVX2) is bit
    /// for bit the plain [`super::ValenceTable::sub_patch`] without the
    /// limit term, for every valence, region and level 1..=64 and at deep
    /// levels, on pseudo-random projections.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn deep_grid_is_sub_patch_bit_for_bit() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
        let mut rnd = || rng.unit() - 0.5;
        let mut checked = 0;
        for n in 3..=crate::config::MAX_VALENCE {
            let tab = ts.get(n).unwrap();
            let mut ghat = [0.0; 3 * MAX_K];
            for g in ghat.iter_mut() {
                *g = rnd();
            }
            let ghat = &ghat[..3 * tab.num_points()];
            // The stored powers are powi's (so sub_patch is unchanged).
            for (e, row) in tab.mu_pow.iter().enumerate() {
                for c in 0..tab.num_points() {
                    let want = crate::math::linalg::powi(tab.mu[c], e as u32);
                    assert_eq!(row[c].to_bits(), want.to_bits(), "n {n} e {e} c {c}");
                }
            }
            for m in (1..=64).chain([100, 500, 1000, 1070]) {
                for b in 1..=3 {
                    let (mut want, mut got) = ([0.0; 48], [0.0; 48]);
                    tab.sub_patch(ghat, m, b, false, &mut want);
                    tab.deep_grid(ghat, m, b, &mut got);
                    for (w, g) in want.iter().zip(got.iter()) {
                        assert_eq!(w.to_bits(), g.to_bits(), "n {n} m {m} b {b}");
                    }
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, (crate::config::MAX_VALENCE - 2) * 68 * 3);
    }

    /// An evaluation that reads the stored deep grids (levels
    /// `3..3 + count`, made by [`super::ValenceTable::deep_grid`] as the
    /// evaluator's build does) is bit for bit the one that runs the kernel
    /// per query, for every valence, at points of every level 1..=40 in
    /// each of the three regions (and on their borders), with and without
    /// second derivatives; both against the plain `sub_patch` grid plus
    /// the limit term, so that a wrong level or region index fails.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn stored_deep_grids_are_the_kernel_bit_for_bit() {
        use crate::math::bspline::eval_grid;
        use std::vec::Vec;
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
        let mut rnd = || rng.unit();
        let count = 24usize; // levels 3..=26
        let bits = |e: &crate::math::Eval| {
            [e.p, e.du, e.dv, e.duu, e.duv, e.dvv, e.normal].map(|a| a.to_array().map(f64::to_bits))
        };
        let mut checked = 0;
        for n in 3..=crate::config::MAX_VALENCE {
            let tab = ts.get(n).unwrap();
            let mut ghat = [0.0; 3 * MAX_K];
            for g in ghat.iter_mut() {
                *g = rnd() - 0.5;
            }
            let ghat = &ghat[..3 * tab.num_points()];
            let mut deep = Vec::new();
            for m in 3..3 + count as u32 {
                for b in 1..=3 {
                    let mut g = [0.0; 48];
                    tab.deep_grid(ghat, m, b, &mut g);
                    deep.extend_from_slice(&g);
                }
            }
            for m in 1..=40i32 {
                let h = libm::scalbn(1.0, -m); // level m: max(u, v) in [h, 2h)
                for (a, c) in [(1.5, 0.5), (1.5, 1.5), (0.5, 1.5), (1.0, 0.0), (rnd(), 1.0)] {
                    let (u, v) = (a * h, c * h);
                    let plain = tab.eval_projected_impl::<true, true>(ghat, None, &[], u, v);
                    let got = tab.eval_projected_impl::<true, true>(ghat, None, &deep, u, v);
                    assert_eq!(bits(&got), bits(&plain), "n {n} m {m} at ({u}, {v})");
                    let plain = tab.eval_projected_impl::<false, true>(ghat, None, &[], u, v);
                    let got = tab.eval_projected_impl::<false, true>(ghat, None, &deep, u, v);
                    assert_eq!(bits(&got), bits(&plain), "n {n} m {m} first");
                    // The level and region the kernel took: the plain grid.
                    if (3..3 + count as i32).contains(&m) && a < 2.0 && c < 2.0 {
                        let (ub, vb) = (libm::scalbn(u, m), libm::scalbn(v, m));
                        let (b, uu, vv) = if ub >= 1.0 {
                            if vb >= 1.0 {
                                (2, ub - 1.0, vb - 1.0)
                            } else {
                                (1, ub - 1.0, vb)
                            }
                        } else {
                            (3, ub, vb - 1.0)
                        };
                        let mut g = [0.0; 48];
                        tab.sub_patch(ghat, m as u32, b, false, &mut g);
                        let mut want = eval_grid::<true>(&g, uu, vv);
                        want.p += glam::DVec3::new(ghat[0], ghat[1], ghat[2]);
                        assert_eq!(
                            got.p.to_array().map(f64::to_bits),
                            want.p.to_array().map(f64::to_bits),
                            "n {n} m {m} b {b}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= (crate::config::MAX_VALENCE - 2) * 24 * 4);
    }

    /// The level search of `eval_projected_at` by exponent bits
    /// ([`super::corner_level`], [`super::scale2`]) is `libm::frexp` /
    /// `libm::scalbn` bit for bit: at every power of two from 1 down to
    /// the smallest subnormal, its neighbours, and a million random
    /// parameters spread over all exponents (`u`, `v` below `t`; 2,000
    /// under Miri).
    #[test]
    fn level_search_is_frexp_scalbn() {
        let level = |t: f64| (1 - libm::frexp(t).1).max(1);
        let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
        let mut rnd = || rng.next_u64();
        let mut ts = std::vec::Vec::new();
        for k in 0..=1074 {
            let p = libm::scalbn(1.0, -k);
            ts.extend([
                p,
                f64::from_bits(p.to_bits() + 1),
                f64::from_bits(p.to_bits() - 1),
            ]);
        }
        // Fewer under Miri (scripts/miri.sh runs this crate's tests).
        let draws = if cfg!(miri) { 2_000 } else { 1_000_000 };
        for _ in 0..draws {
            // Random mantissa, exponent 2^0 .. 2^-1074.
            let r = rnd();
            let f = 0.5 + (r >> 11) as f64 / (1u64 << 54) as f64;
            ts.push(libm::scalbn(f, -((r % 1076) as i32)));
        }
        let mut checked = 0;
        for t in ts {
            if !(t > 0.0 && t <= 1.0) {
                continue;
            }
            let m = super::corner_level(t);
            assert_eq!(m, level(t), "t {t:e}");
            let w = f64::from_bits(rnd() >> 12 | 0x3ff0_0000_0000_0000) - 1.0; // [0, 1)
            for x in [t, w * t, 0.0, 1.0] {
                assert_eq!(
                    super::scale2(x, m).to_bits(),
                    libm::scalbn(x, m).to_bits(),
                    "x {x:e} m {m}"
                );
            }
            checked += 1;
        }
        assert!(checked > draws);
    }
}
