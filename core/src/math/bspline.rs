//! Uniform cubic B-spline basis and bicubic patch evaluation.
//!
//! Basis on t in `[0, 1]`: `(1-t)^3/6`, `(3t^3 - 6t^2 + 4)/6`,
//! `(-3t^3 + 3t^2 + 3t + 1)/6`, `t^3/6`. A patch has a 4x4 control grid and
//! covers its middle square.
//!
//! The evaluation kernel works on a [`Grid`]: the 16 control points in
//! structure-of-arrays order, `g[c*16 + i*4 + j]` = coordinate `c` of the
//! point with index `i` along u and `j` along v. That layout lets the
//! compiler vectorise the inner loops.

use crate::math::Eval;
use glam::DVec3;

/// 16 control points, structure of arrays: `g[c*16 + i*4 + j]`.
pub type Grid = [f64; 48];

/// Basis values and first and second derivatives at `t`.
#[inline(always)]
pub fn basis(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    let b = [
        s * s * s * (1.0 / 6.0),
        (3.0 * t3 - 6.0 * t2 + 4.0) * (1.0 / 6.0),
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) * (1.0 / 6.0),
        t3 * (1.0 / 6.0),
    ];
    let d = [
        -0.5 * s * s,
        1.5 * t2 - 2.0 * t,
        -1.5 * t2 + t + 0.5,
        0.5 * t2,
    ];
    let dd = [s, 3.0 * t - 2.0, -3.0 * t + 1.0, t];
    (b, d, dd)
}

#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// Per coordinate, the column sums `r = sum_i bu[i] col_i` (and with the
/// derivative weights) followed by dot products with the v weights.
/// Returns `[p, du, dv, duu, duv, dvv]` for one coordinate.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn coord<const SECOND: bool>(
    cols: &[[f64; 4]],
    w: &([f64; 4], [f64; 4], [f64; 4]),
    wv: &([f64; 4], [f64; 4], [f64; 4]),
) -> [f64; 6] {
    let (bu, du, duu) = w;
    let (bv, dv, dvv) = wv;
    let mut r = [0.0f64; 4];
    let mut ru = [0.0f64; 4];
    let mut ruu = [0.0f64; 4];
    for i in 0..4 {
        let col = &cols[i];
        axpy4(&mut r, bu[i], col);
        axpy4(&mut ru, du[i], col);
        if SECOND {
            axpy4(&mut ruu, duu[i], col);
        }
    }
    let mut o = [dot4(bv, &r), dot4(bv, &ru), dot4(dv, &r), 0.0, 0.0, 0.0];
    if SECOND {
        o[3] = dot4(bv, &ruu);
        o[4] = dot4(dv, &ru);
        o[5] = dot4(dvv, &r);
    }
    o
}

#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn axpy4(acc: &mut [f64; 4], a: f64, x: &[f64; 4]) {
    for k in 0..4 {
        acc[k] += a * x[k];
    }
}

/// SSE2 version of `coord` (SSE2 is part of the x86_64 baseline): each
/// column is two 2-lane vectors.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn coord<const SECOND: bool>(
    cols: &[[f64; 4]],
    w: &([f64; 4], [f64; 4], [f64; 4]),
    wv: &([f64; 4], [f64; 4], [f64; 4]),
) -> [f64; 6] {
    use core::arch::x86_64::*;
    // SAFETY: SSE2 is part of the x86_64 baseline, so these intrinsics are
    // always available; no pointer is dereferenced.
    unsafe {
        let (bu, du, duu) = w;
        let (bv, dv, dvv) = wv;
        let ld = |x: &[f64; 4]| -> (__m128d, __m128d) {
            (_mm_set_pd(x[1], x[0]), _mm_set_pd(x[3], x[2]))
        };
        let z = _mm_setzero_pd();
        let (mut r0, mut r1, mut u0, mut u1, mut s0, mut s1) = (z, z, z, z, z, z);
        for i in 0..4 {
            let (c0, c1) = ld(&cols[i]);
            let b = _mm_set1_pd(bu[i]);
            let d = _mm_set1_pd(du[i]);
            r0 = _mm_add_pd(r0, _mm_mul_pd(b, c0));
            r1 = _mm_add_pd(r1, _mm_mul_pd(b, c1));
            u0 = _mm_add_pd(u0, _mm_mul_pd(d, c0));
            u1 = _mm_add_pd(u1, _mm_mul_pd(d, c1));
            if SECOND {
                let e = _mm_set1_pd(duu[i]);
                s0 = _mm_add_pd(s0, _mm_mul_pd(e, c0));
                s1 = _mm_add_pd(s1, _mm_mul_pd(e, c1));
            }
        }
        let dot = |w: &[f64; 4], a: __m128d, b: __m128d| -> f64 {
            let (w0, w1) = ld(w);
            let s = _mm_add_pd(_mm_mul_pd(w0, a), _mm_mul_pd(w1, b));
            let h = _mm_unpackhi_pd(s, s);
            _mm_cvtsd_f64(_mm_add_sd(s, h))
        };
        let mut o = [
            dot(bv, r0, r1),
            dot(bv, u0, u1),
            dot(dv, r0, r1),
            0.0,
            0.0,
            0.0,
        ];
        if SECOND {
            o[3] = dot(bv, s0, s1);
            o[4] = dot(dv, u0, u1);
            o[5] = dot(dvv, r0, r1);
        }
        o
    }
}

/// [`coord`] with each column one four-lane AVX vector: the same IEEE
/// operations on the same values in the same order per lane (the two-lane
/// version's halves are this one's low and high lanes, and its dot
/// product adds the low and high halves first, as this one does), so the
/// same bits. Only inlined into functions compiled with AVX2 (see
/// [`eval_grid_with`]).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn coord4<const SECOND: bool>(
    cols: &[[f64; 4]],
    w: &([f64; 4], [f64; 4], [f64; 4]),
    wv: &([f64; 4], [f64; 4], [f64; 4]),
) -> [f64; 6] {
    use core::arch::x86_64::*;
    // SAFETY: the callers run only where the CPU has AVX2 (`eval_grid_with`'s
    // contract with `WIDE`); every load reads a whole `[f64; 4]`.
    unsafe {
        let (bu, du, duu) = w;
        let (bv, dv, dvv) = wv;
        let z = _mm256_setzero_pd();
        let (mut r, mut ru, mut rs) = (z, z, z);
        for i in 0..4 {
            let c = _mm256_loadu_pd(cols[i].as_ptr());
            r = _mm256_add_pd(r, _mm256_mul_pd(_mm256_set1_pd(bu[i]), c));
            ru = _mm256_add_pd(ru, _mm256_mul_pd(_mm256_set1_pd(du[i]), c));
            if SECOND {
                rs = _mm256_add_pd(rs, _mm256_mul_pd(_mm256_set1_pd(duu[i]), c));
            }
        }
        // A function, not a closure: `inline(always)` keeps it in the
        // AVX2 caller (a closure left out of line is compiled without
        // AVX2 and takes its vectors through memory: 4x slower, measured).
        #[inline(always)]
        unsafe fn dot(w: &[f64; 4], a: __m256d) -> f64 {
            // SAFETY: as `coord4`'s (AVX2 callers; a whole `[f64; 4]`).
            unsafe {
                let p = _mm256_mul_pd(_mm256_loadu_pd(w.as_ptr()), a);
                let s = _mm_add_pd(_mm256_castpd256_pd128(p), _mm256_extractf128_pd::<1>(p));
                let h = _mm_unpackhi_pd(s, s);
                _mm_cvtsd_f64(_mm_add_sd(s, h))
            }
        }
        let mut o = [dot(bv, r), dot(bv, ru), dot(dv, r), 0.0, 0.0, 0.0];
        if SECOND {
            o[3] = dot(bv, rs);
            o[4] = dot(dv, ru);
            o[5] = dot(dvv, r);
        }
        o
    }
}

/// [`coord4`] with `WIDE` on x86_64, else [`coord`].
#[inline(always)]
fn coord_with<const SECOND: bool, const WIDE: bool>(
    cols: &[[f64; 4]],
    w: &([f64; 4], [f64; 4], [f64; 4]),
    wv: &([f64; 4], [f64; 4], [f64; 4]),
) -> [f64; 6] {
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        return coord4::<SECOND>(cols, w, wv);
    }
    coord::<SECOND>(cols, w, wv)
}

/// Evaluates a bicubic B-spline patch: position and derivatives with respect
/// to the patch's own (u, v); second derivatives only when `SECOND`.
#[inline(always)]
pub fn eval_grid<const SECOND: bool>(g: &Grid, u: f64, v: f64) -> Eval {
    eval_grid_with::<SECOND, false>(g, u, v)
}

/// [`eval_grid`] (`WIDE` false), or the same with four-lane vectors
/// (`WIDE` true; the same bits): for the bodies of functions compiled
/// with `#[target_feature(enable = "avx2")]`, whose callers checked
/// [`crate::math::simd::has_avx2`] (inlined anywhere else each intrinsic
/// would be a call). Elsewhere than x86_64 `WIDE` changes nothing.
#[inline(always)]
pub(crate) fn eval_grid_with<const SECOND: bool, const WIDE: bool>(
    g: &Grid,
    u: f64,
    v: f64,
) -> Eval {
    let wu = basis(u);
    let wv = basis(v);
    let (cols, _) = g.as_chunks::<4>();
    let x = coord_with::<SECOND, WIDE>(&cols[0..4], &wu, &wv);
    let y = coord_with::<SECOND, WIDE>(&cols[4..8], &wu, &wv);
    let z = coord_with::<SECOND, WIDE>(&cols[8..12], &wu, &wv);
    let v3 = |k: usize| DVec3::new(x[k], y[k], z[k]);
    Eval {
        p: v3(0),
        du: v3(1),
        dv: v3(2),
        duu: v3(3),
        duv: v3(4),
        dvv: v3(5),
        normal: DVec3::ZERO,
    }
}

/// Converts 16 points given row by row (`points[j*4 + i]`, i along u, j
/// along v) to a [`Grid`].
pub fn grid_from_points(points: &[DVec3; 16]) -> Grid {
    let mut g = [0.0; 48];
    for j in 0..4 {
        for i in 0..4 {
            let p = points[j * 4 + i];
            g[i * 4 + j] = p.x;
            g[16 + i * 4 + j] = p.y;
            g[32 + i * 4 + j] = p.z;
        }
    }
    g
}

/// Evaluates a patch given as 16 points row by row (`points[j*4 + i]`).
pub fn eval_points<const SECOND: bool>(points: &[DVec3; 16], u: f64, v: f64) -> Eval {
    eval_grid::<SECOND>(&grid_from_points(points), u, v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// The four-lane bicubic is the two-lane one bit for bit: random
    /// grids (magnitudes from 1e-300 to 1e300, signed zeros) at random
    /// and boundary parameters, with and without second derivatives.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn wide_bicubic_is_the_narrow_one_bit_for_bit() {
        if !crate::math::simd::has_avx2() {
            return; // nothing to compare on this CPU
        }
        #[target_feature(enable = "avx2")]
        fn wide(g: &Grid, u: f64, v: f64) -> (Eval, Eval) {
            (
                eval_grid_with::<false, true>(g, u, v),
                eval_grid_with::<true, true>(g, u, v),
            )
        }
        let bits = |e: &Eval| {
            [e.p, e.du, e.dv, e.duu, e.duv, e.dvv].map(|x| x.to_array().map(f64::to_bits))
        };
        let mut rng = XorShift(11);
        for k in 0..20_000 {
            let scale = [1.0, 1e-300, 1e300, 3.7][k % 4];
            let g: Grid = core::array::from_fn(|i| {
                if (k + i) % 17 == 0 {
                    -0.0
                } else {
                    (rng.unit() - 0.5) * scale
                }
            });
            let at = |rng: &mut XorShift| match k % 5 {
                0 => 0.0,
                1 => 1.0,
                _ => rng.unit(),
            };
            let (u, v) = (at(&mut rng), at(&mut rng));
            // SAFETY: the CPU runs AVX2 (checked above).
            let (w1, w2) = unsafe { wide(&g, u, v) };
            assert_eq!(bits(&w1), bits(&eval_grid::<false>(&g, u, v)), "k {k}");
            assert_eq!(bits(&w2), bits(&eval_grid::<true>(&g, u, v)), "k {k}");
        }
    }
}
