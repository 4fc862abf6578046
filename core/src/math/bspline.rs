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

/// Evaluates a bicubic B-spline patch: position and derivatives with respect
/// to the patch's own (u, v); second derivatives only when `SECOND`.
#[inline(always)]
pub fn eval_grid<const SECOND: bool>(g: &Grid, u: f64, v: f64) -> Eval {
    let wu = basis(u);
    let wv = basis(v);
    let (cols, _) = g.as_chunks::<4>();
    let x = coord::<SECOND>(&cols[0..4], &wu, &wv);
    let y = coord::<SECOND>(&cols[4..8], &wu, &wv);
    let z = coord::<SECOND>(&cols[8..12], &wu, &wv);
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
