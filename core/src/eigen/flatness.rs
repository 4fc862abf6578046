//! The constants of the corner and ring-region bounds, computed with the
//! tables: per eigen column, the second differences of the Bezier nets of
//! `X_b` (the ring-region bound of a corner cell's three ring children), the
//! values at the five points a corner-cell split creates, and the terms of
//! the corner flatness `E_k` and radius `R_k` (\[CL-R ch. 7\]; the
//! per-column fits are in `corner_fit`). The bounds themselves are in
//! [`crate::bounds`]; this file only sums table constants.

use super::table::ValenceTable;
use crate::math::bspline::basis;
use crate::math::linalg::{mul2x2, pow2x2, powi};
use crate::mesh::stencil::{Row, MAX_K};
use glam::DVec3;

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

impl ValenceTable {
    /// The second differences of the Bezier nets of `X_1[c]`, `X_2[c]`,
    /// `X_3[c]`: along u, along v, mixed (24, 24 and 27 entries).
    pub(super) fn ring_diffs(&self, c: usize) -> [[f64; 27]; 3] {
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
    pub(super) fn ring_constants(&mut self, k: usize) {
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
    pub(super) fn ring_sums(&self, ghat: &[f64], k: u32, acc: &mut [[f64; 16]; 3]) {
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
    /// (the eigen expansion bound of \[CL-R ch. 7\], "m_eps"):
    /// `S(2^-k z) - L = sum_c (B^(k+j-1) ghat)_c phi_c(z')` for z in the
    /// level-j L-shaped region, `|phi_c| <= F_c` (B-spline convex hull of
    /// `X_b`), `|mu_c|^(k+j-1) <= |mu_c|^k`.
    pub fn corner_radius(&self, ghat: &[f64], k: u32) -> f64 {
        let mut t = EigenTerms::EMPTY;
        self.eigen_terms(ghat, &self.sup_phi, None, &mut t);
        t.at(k)
    }

    /// A radius around the limit point `L = ghat[0]` that holds every
    /// limit point of the corner region `[0, 2^-k]^2`: the largest distance
    /// from `L` to the region's `2n + 8` control points after `k` steps
    /// ([`ValenceTable::level_points`]). With a vertex rule of
    /// non-negative weights every subdivision step takes convex
    /// combinations (the edge and face rules always do, and the patch's
    /// ring has only quads), so the region lies in the convex hull of those
    /// points, and the hull (which holds `L`) within that distance of `L`.
    /// Widened by `1e-12` of the magnitudes for rounding and the tables'
    /// own precision; infinite with a negative weight or a non-finite
    /// value. The eigen radius ([`ValenceTable::corner_radius`]) is tight
    /// as `k` grows; at the first levels, where its constants dominate,
    /// this one is smaller (on the cube `[-1, 1]^3` at a corner limit
    /// point: eigen radius 7.14, 1.69, 0.54 at `k` = 0, 1, 2; this one
    /// 1.49, 0.80, 0.35).
    pub fn corner_hull_radius(&self, ghat: &[f64], k: u32) -> f64 {
        let (a, b, g) = self.weights;
        if !(a >= 0.0 && b >= 0.0 && g >= 0.0) || ghat.len() < 3 * self.k {
            return f64::INFINITY;
        }
        let mut pts = [DVec3::ZERO; MAX_K];
        self.level_points(ghat, k, &mut pts);
        let l = DVec3::new(ghat[0], ghat[1], ghat[2]);
        let (mut r2, mut mag) = (0.0f64, l.abs().max_element());
        for p in &pts[..self.k] {
            r2 = r2.max((*p - l).length_squared());
            mag = mag.max(p.abs().max_element());
        }
        let r = libm::sqrt(r2) * (1.0 + 1e-12) + 1e-12 * mag;
        if r.is_finite() {
            r
        } else {
            f64::INFINITY
        }
    }

    /// Guaranteed flatness `E_k` of the corner region `[0, 2^-k]^2` of the
    /// patch: there is an affine function `A` of the patch parameters with
    /// `|S - A| <= E_k` over the region, so every linear interpolant of
    /// limit points of the region is within `2 E_k` of the surface there
    /// (`eigen::corner_fit`): `E_k = sum_c |mu_c|^k |ghat_c| G_c`, a pair
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
    pub(super) fn eigen_terms(
        &self,
        ghat: &[f64],
        per: &Row,
        pairs: Option<&Row>,
        out: &mut EigenTerms,
    ) {
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
    pub(super) fn grouped<const N: usize>(
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
    /// limit point: `sum_c mu_c^k ghat_c l_c(w)`. For tests of the bound and
    /// the corner-face term of [`crate::bounds::depth::tight_depth`].
    pub fn corner_affine(&self, ghat: &[f64], k: u32, w: (f64, f64)) -> DVec3 {
        let mut a = DVec3::ZERO;
        for c in 1..self.k.min(ghat.len() / 3) {
            let [al, be] = self.flat_lin[c];
            let g = DVec3::new(ghat[3 * c], ghat[3 * c + 1], ghat[3 * c + 2]);
            a += g * (powi(self.mu[c], k) * (al * w.0 + be * w.1));
        }
        a
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
    pub(super) fn next_level(&self, p: &mut Row) -> [f64; N] {
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
    pub(super) fn at(&self, k: u32) -> [f64; N] {
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

    /// Entry `k` of [`EigenTerms::levels`], bit for bit, without the
    /// array of the levels before it.
    pub(crate) fn level(&self, k: u32) -> f64 {
        let mut p = [1.0f64; MAX_K];
        let mut b = [[1.0, 0.0], [0.0, 1.0]];
        let mut i = 0;
        loop {
            let [mut r] = self.g.next_level(&mut p);
            if let Some((m, g0, g1, f)) = self.quad {
                let a = (g0 * b[0][0] + g1 * b[0][1]).length();
                let c = (g0 * b[1][0] + g1 * b[1][1]).length();
                r += f * a.max(c);
                b = mul2x2(b, m);
            }
            if i == k {
                return r;
            }
            i += 1;
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

    /// Entry `k` of [`RingTerms::levels`], bit for bit, without the array
    /// of the levels before it.
    pub(crate) fn level(&self, k: u32) -> f64 {
        let mut p = [1.0f64; MAX_K];
        for _ in 0..k {
            self.0.next_level(&mut p);
        }
        ring_bound_of(self.0.next_level(&mut p))
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
    use crate::config::MAX_VALENCE;
    use crate::eigen::{BuildScratch, EigenTerms, TableSet};
    use crate::mesh::weights::Weights;
    use std::boxed::Box;

    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
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
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
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
