//! Bicubic Bezier nets of cells: conversion from B-spline grids, rotation
//! into the slot frame, de Casteljau splitting into the four quadrants, the
//! guaranteed second-derivative bound, and positions/normals at corners.
//!
//! A [`Net`] is 16 control points in structure-of-arrays order,
//! `net[c*16 + a*4 + b]` = coordinate `c` of the point with index `a` along
//! the cell's s (slot u) and `b` along t (slot v), the same layout as
//! [`crate::math::bspline::Grid`]. Corner `q` of a cell (0: (0,0), 1: (1,0),
//! 2: (1,1), 3: (0,1)) is the net point `CORNER_POINT[q]`.

use crate::math::bspline::{basis, Grid};
use crate::math::simd::F2;
use glam::DVec3;

/// 16 Bezier control points, structure of arrays (see module docs).
pub(crate) type Net = [f64; 48];

/// Net index (a*4 + b) of each cell corner.
pub(crate) const CORNER_POINT: [usize; 4] = [0, 12, 15, 3];

/// The uniform cubic B-spline to Bezier conversion on two cubics at once (lane k of `g[i]` is point
/// i of cubic k), same operations.
#[inline(always)]
fn b2b2(g: [F2; 4]) -> [F2; 4] {
    let s = F2::splat(1.0 / 6.0);
    let t = F2::splat(1.0 / 3.0);
    let (two, four) = (F2::splat(2.0), F2::splat(4.0));
    [
        g[0].add(four.mul(g[1])).add(g[2]).mul(s),
        two.mul(g[1]).add(g[2]).mul(t),
        g[1].add(two.mul(g[2])).mul(t),
        g[1].add(four.mul(g[2])).add(g[3]).mul(s),
    ]
}

/// The Bezier net over the unit square of the bicubic B-spline grid `g`
/// (exact conversion of each cubic: `(g0 + 4 g1 + g2)/6, (2 g1 + g2)/3,
/// (g1 + 2 g2)/3, (g1 + 4 g2 + g3)/6`, first along b, then along a), seen
/// from a frame rotated by `rho`: local `(s, t)` maps to patch
/// `rot_param(rho, s, t)` (see `eval::frame::rot_param`), so
/// `out[a][b] = net[k][l]` with `(k, l) = 3 rot_param(rho, a/3, b/3)`.
#[inline]
pub(crate) fn from_grid_rotated(g: &Grid, rho: u8, out: &mut Net) {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        unsafe { from_grid_rotated_avx2(g, rho, out) };
        return;
    }
    from_grid_rotated_f2(g, rho, out)
}

/// 4 x 4 transpose of four-lane rows: `out[j]` lane `i` is `r[i]` lane `j`
/// (rows of a net into columns, or one row of four nets into one vector
/// per value).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn transpose4(r: [core::arch::x86_64::__m256d; 4]) -> [core::arch::x86_64::__m256d; 4] {
    use core::arch::x86_64::*;
    let t0 = _mm256_unpacklo_pd(r[0], r[1]);
    let t1 = _mm256_unpackhi_pd(r[0], r[1]);
    let t2 = _mm256_unpacklo_pd(r[2], r[3]);
    let t3 = _mm256_unpackhi_pd(r[2], r[3]);
    [
        _mm256_permute2f128_pd::<0x20>(t0, t2),
        _mm256_permute2f128_pd::<0x20>(t1, t3),
        _mm256_permute2f128_pd::<0x31>(t0, t2),
        _mm256_permute2f128_pd::<0x31>(t1, t3),
    ]
}

/// [`from_grid_rotated`] on four lanes: per coordinate, the rows are
/// transposed, converted along b, transposed back and converted along a
/// (the same operations per value as the two-lane path), and the rotation
/// is a transpose and/or lane reversal in registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn from_grid_rotated_avx2(g: &Grid, rho: u8, out: &mut Net) {
    use core::arch::x86_64::*;
    let k = _mm256_set1_pd;
    let b2b = |g: [__m256d; 4]| {
        let (s, t) = (k(1.0 / 6.0), k(1.0 / 3.0));
        let (two, four) = (k(2.0), k(4.0));
        let add = |x, y| _mm256_add_pd(x, y);
        let mul = |x, y| _mm256_mul_pd(x, y);
        [
            mul(add(add(g[0], mul(four, g[1])), g[2]), s),
            mul(add(mul(two, g[1]), g[2]), t),
            mul(add(g[1], mul(two, g[2])), t),
            mul(add(add(g[1], mul(four, g[2])), g[3]), s),
        ]
    };
    let tr = |r: [__m256d; 4]| transpose4(r);
    let rev = |x: __m256d| _mm256_permute4x64_pd::<0b00_01_10_11>(x);
    for c in 0..3 {
        let o = c * 16;
        // SAFETY: each load reads 4 values at o + 4 a + 4 <= 48.
        let r: [__m256d; 4] = core::array::from_fn(|a| unsafe {
            _mm256_loadu_pd(g[o + 4 * a..o + 4 * a + 4].as_ptr())
        });
        // Along b (columns as vectors), then along a (rows as vectors).
        let f = b2b(tr(b2b(tr(r))));
        let rows = match rho & 3 {
            0 => f,
            // out[a][b] = f[b][3 - a]
            1 => {
                let t = tr(f);
                [t[3], t[2], t[1], t[0]]
            }
            // out[a][b] = f[3 - a][3 - b]
            2 => [rev(f[3]), rev(f[2]), rev(f[1]), rev(f[0])],
            // out[a][b] = f[3 - b][a]
            _ => tr(f).map(rev),
        };
        for (a, v) in rows.iter().enumerate() {
            // SAFETY: 4 values at o + 4 a + 4 <= 48.
            unsafe { _mm256_storeu_pd(out[o + 4 * a..o + 4 * a + 4].as_mut_ptr(), *v) };
        }
    }
}

/// [`from_grid_rotated`] on two-lane vectors (every target).
fn from_grid_rotated_f2(g: &Grid, rho: u8, out: &mut Net) {
    let mut tmp = [0.0f64; 48];
    let dst: &mut Net = if rho & 3 == 0 { out } else { &mut tmp };
    for c in 0..3 {
        let o = c * 16;
        let row = |a: usize| [F2::ld(g, o + a * 4), F2::ld(g, o + a * 4 + 2)];
        // Along b within rows, rows (0, 1) and (2, 3) transposed into lanes.
        let mut t = [[F2::splat(0.0); 2]; 4]; // t[a][h]: lanes b = 2h, 2h + 1
        for a in (0..4).step_by(2) {
            let (x, y) = (row(a), row(a + 1));
            let r = b2b2([
                x[0].lo_lo(y[0]),
                x[0].hi_hi(y[0]),
                x[1].lo_lo(y[1]),
                x[1].hi_hi(y[1]),
            ]);
            t[a] = [r[0].lo_lo(r[1]), r[2].lo_lo(r[3])];
            t[a + 1] = [r[0].hi_hi(r[1]), r[2].hi_hi(r[3])];
        }
        // Along a, lanes b.
        for h in 0..2 {
            let r = b2b2([t[0][h], t[1][h], t[2][h], t[3][h]]);
            for (a, v) in r.iter().enumerate() {
                v.st(dst, o + a * 4 + 2 * h);
            }
        }
    }
    if rho & 3 != 0 {
        for a in 0..4 {
            for b in 0..4 {
                let (k, l) = match rho & 3 {
                    1 => (b, 3 - a),
                    2 => (3 - a, 3 - b),
                    _ => (3 - b, a),
                };
                for c in 0..3 {
                    out[c * 16 + a * 4 + b] = tmp[c * 16 + k * 4 + l];
                }
            }
        }
    }
}

/// de Casteljau halves of one cubic, two cubics at once (lane k of
/// `p[i]` is point i of cubic k): the same operations as the scalar
/// `m01 = 0.5 (p0 + p1)`, ..., `mid = 0.5 (m012 + m123)`.
#[inline(always)]
fn halves2(p: [F2; 4]) -> ([F2; 4], [F2; 4]) {
    let h = F2::splat(0.5);
    let m01 = h.mul(p[0].add(p[1]));
    let m12 = h.mul(p[1].add(p[2]));
    let m23 = h.mul(p[2].add(p[3]));
    let m012 = h.mul(m01.add(m12));
    let m123 = h.mul(m12.add(m23));
    let mid = h.mul(m012.add(m123));
    ([p[0], m01, m012, mid], [mid, m123, m23, p[3]])
}

/// Splits rows `a` and `a + 1` (each as two vectors) of one coordinate
/// along t: their lower halves go to `lo[at..at + 8]`, upper halves to
/// `hi[at..at + 8]` (row a first).
#[inline(always)]
fn split_rows(x: [F2; 2], y: [F2; 2], lo: &mut [f64], hi: &mut [f64], at: usize) {
    // Transpose: lane 0 = row x, lane 1 = row y.
    let p = [
        x[0].lo_lo(y[0]),
        x[0].hi_hi(y[0]),
        x[1].lo_lo(y[1]),
        x[1].hi_hi(y[1]),
    ];
    let (l, r) = halves2(p);
    l[0].lo_lo(l[1]).st(lo, at);
    l[2].lo_lo(l[3]).st(lo, at + 2);
    l[0].hi_hi(l[1]).st(lo, at + 4);
    l[2].hi_hi(l[3]).st(lo, at + 6);
    r[0].lo_lo(r[1]).st(hi, at);
    r[2].lo_lo(r[3]).st(hi, at + 2);
    r[0].hi_hi(r[1]).st(hi, at + 4);
    r[2].hi_hi(r[3]).st(hi, at + 6);
}

/// The nets of the four quadrants (0: s,t < 1/2; 1: s > 1/2, t < 1/2;
/// 2: s,t > 1/2; 3: s < 1/2, t > 1/2), each over its own unit square.
/// Bit-identical to splitting every cubic by de Casteljau at 1/2, first
/// along s (the columns), then along t (the rows).
///
/// Always inlined: a thin run-time switch, which the tessellation's
/// marking calls for every split node (with the voxelizer as a second
/// caller the compiler stopped inlining it, +0.1 % instructions).
#[inline(always)]
pub(crate) fn split4(n: &Net, out: &mut [Net; 4]) {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        unsafe { split4_avx2(n, out) };
        return;
    }
    split4_f2(n, out);
}

/// The split kernels, written once and instantiated twice: for an array
/// of four nets (the tessellation's, whose code stays as it was) and for
/// four separate nets (the voxelizer's stack entries).
macro_rules! split4_kernels {
    ($f2:ident, $avx2:ident, $out:ty) => {
        /// [`split4`] on two-lane vectors (every target).
        #[inline]
        fn $f2(n: &Net, out: $out) {
            let [o0, o1, o2, o3] = out;
            for c in 0..3 {
                let o = c * 16;
                // Along s, lanes b = (0, 1) and (2, 3): rows of the halves s < 1/2
                // (lo) and s > 1/2 (hi).
                let row = |a: usize| [F2::ld(n, o + a * 4), F2::ld(n, o + a * 4 + 2)];
                let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
                let mut lo = [[F2::splat(0.0); 2]; 4];
                let mut hi = [[F2::splat(0.0); 2]; 4];
                for h in 0..2 {
                    let (l, r) = halves2([r0[h], r1[h], r2[h], r3[h]]);
                    for a in 0..4 {
                        lo[a][h] = l[a];
                        hi[a][h] = r[a];
                    }
                }
                // Along t within each row, two rows at a time.
                for a in (0..4).step_by(2) {
                    let at = o + a * 4;
                    split_rows(lo[a], lo[a + 1], o0, o3, at);
                    split_rows(hi[a], hi[a + 1], o1, o2, at);
                }
            }
        }

        /// [`split4_f2`] on four-lane vectors: along s on whole rows, along t on
        /// the columns of the transposed 4 x 4 blocks (lane = row). Every value
        /// is formed by the same operations (`0.5 * (x + y)`), so the nets have
        /// the same bits (the tests compare the two).
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn $avx2(n: &Net, out: $out) {
            use core::arch::x86_64::*;
            let h = _mm256_set1_pd(0.5);
            let mid = |x: __m256d, y: __m256d| _mm256_mul_pd(h, _mm256_add_pd(x, y));
            let halves = |p: [__m256d; 4]| {
                let (m01, m12, m23) = (mid(p[0], p[1]), mid(p[1], p[2]), mid(p[2], p[3]));
                let (m012, m123) = (mid(m01, m12), mid(m12, m23));
                let c = mid(m012, m123);
                ([p[0], m01, m012, c], [c, m123, m23, p[3]])
            };
            let tr = |r: [__m256d; 4]| transpose4(r);
            let [o0, o1, o2, o3] = out;
            for c in 0..3 {
                let o = c * 16;
                // SAFETY: every load and store covers 4 values at o + 4a + 4 <= 48.
                let r: [__m256d; 4] = core::array::from_fn(|a| unsafe {
                    _mm256_loadu_pd(n[o + 4 * a..o + 4 * a + 4].as_ptr())
                });
                let (lo, hi) = halves(r);
                for (rows, dl, du) in [(lo, &mut *o0, &mut *o3), (hi, &mut *o1, &mut *o2)] {
                    let (l, u) = halves(tr(rows));
                    let (l, u) = (tr(l), tr(u));
                    for a in 0..4 {
                        let at = o + 4 * a;
                        unsafe {
                            _mm256_storeu_pd(dl[at..at + 4].as_mut_ptr(), l[a]);
                            _mm256_storeu_pd(du[at..at + 4].as_mut_ptr(), u[a]);
                        }
                    }
                }
            }
        }
    };
}

split4_kernels!(split4_f2, split4_avx2, &mut [Net; 4]);
split4_kernels!(split4_parts_f2, split4_parts_avx2, [&mut Net; 4]);

/// [`split4`] into four separate nets (same kernels, same bits).
pub(crate) fn split4_parts(n: &Net, out: [&mut Net; 4]) {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        unsafe { split4_parts_avx2(n, out) };
        return;
    }
    split4_parts_f2(n, out);
}

/// `(a, b, c)` of [`grid_second_bounds`] from a Bezier
/// net: `|S_ss| <= a`, `|S_tt| <= b`, `|S_st| <= c` over the cell, and the
/// interpolation bound `lambda_max([[a, c], [c, b]]) / 3`.
///
/// Squared lengths of the second differences are summed over x, y, z in
/// that order, then maximised (NaN entries ignored), as in the scalar
/// formula; the lanes hold neighbouring differences.
#[inline]
pub(crate) fn bound(n: &Net) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        let (a2, b2, c2) = unsafe { bound_sums_avx2(n) };
        return bound_of(a2, b2, c2);
    }
    bound_f2(n)
}

/// [`bound`] of four nets at once: the same values, bit for bit (the
/// AVX2 path takes the square roots and the division on four lanes).
#[inline]
pub(crate) fn bound4(n: &[Net; 4]) -> [f64; 4] {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        return unsafe { bound4_avx2(n) };
    }
    core::array::from_fn(|q| bound(&n[q]))
}

/// [`bound_of`] on four lanes, after the sums of [`bound_sums_avx2`]
/// (VEX-encoded square roots: no transition stall).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bound4_avx2(n: &[Net; 4]) -> [f64; 4] {
    use core::arch::x86_64::*;
    // SAFETY: same CPU features as this function.
    let s: [(f64, f64, f64); 4] = core::array::from_fn(|q| unsafe { bound_sums_avx2(&n[q]) });
    let lanes =
        |f: fn(&(f64, f64, f64)) -> f64| _mm256_set_pd(f(&s[3]), f(&s[2]), f(&s[1]), f(&s[0]));
    let (a2, b2, c2) = (lanes(|x| x.0), lanes(|x| x.1), lanes(|x| x.2));
    let k = _mm256_set1_pd;
    let a = _mm256_mul_pd(k(6.0), _mm256_sqrt_pd(a2));
    let b = _mm256_mul_pd(k(6.0), _mm256_sqrt_pd(b2));
    let c = _mm256_mul_pd(k(9.0), _mm256_sqrt_pd(c2));
    let d = _mm256_sub_pd(a, b);
    let r = _mm256_sqrt_pd(_mm256_add_pd(
        _mm256_mul_pd(_mm256_mul_pd(k(0.25), d), d),
        _mm256_mul_pd(c, c),
    ));
    let m = _mm256_add_pd(_mm256_mul_pd(k(0.5), _mm256_add_pd(a, b)), r);
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four f64.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), _mm256_div_pd(m, k(3.0))) };
    out
}

/// The bound from the largest squared second differences along s (`a2`),
/// along t (`b2`) and mixed (`c2`): `lambda_max([[a, c], [c, b]]) / 3`
/// with `a, b = 6 sqrt(a2, b2)`, `c = 9 sqrt(c2)`.
#[inline(always)]
fn bound_of(a2: f64, b2: f64, c2: f64) -> f64 {
    let a = 6.0 * libm::sqrt(a2);
    let b = 6.0 * libm::sqrt(b2);
    let c = 9.0 * libm::sqrt(c2);
    second_bound([a, b, c])
}

/// [`bound`] on two-lane vectors (every target).
#[inline]
fn bound_f2(n: &Net) -> f64 {
    let two = F2::splat(2.0);
    // sa[k][h]: along s, k = 0, 1, lanes b = 2h, 2h + 1.
    let mut sa = [[F2::splat(0.0); 2]; 2];
    // sb[a]: along t, lanes l = 0, 1.
    let mut sb = [F2::splat(0.0); 4];
    // sc[k]: mixed, lanes l = (0, 1) and (1, 2).
    let mut sc = [[F2::splat(0.0); 2]; 3];
    for c in 0..3 {
        let o = c * 16;
        let r: [[F2; 2]; 4] =
            core::array::from_fn(|a| [F2::ld(n, o + a * 4), F2::ld(n, o + a * 4 + 2)]);
        for k in 0..2 {
            for h in 0..2 {
                let d = r[k + 2][h].sub(two.mul(r[k + 1][h])).add(r[k][h]);
                sa[k][h] = if c == 0 {
                    d.mul(d)
                } else {
                    sa[k][h].add(d.mul(d))
                };
            }
        }
        for a in 0..4 {
            let [p01, p23] = r[a];
            let p12 = p01.hi_lo(p23);
            let d = p23.sub(two.mul(p12)).add(p01);
            sb[a] = if c == 0 {
                d.mul(d)
            } else {
                sb[a].add(d.mul(d))
            };
        }
        for k in 0..3 {
            let e01 = r[k + 1][0].sub(r[k][0]);
            let e23 = r[k + 1][1].sub(r[k][1]);
            let e12 = e01.hi_lo(e23);
            let d0 = e12.sub(e01);
            let d1 = e23.sub(e12);
            if c == 0 {
                sc[k] = [d0.mul(d0), d1.mul(d1)];
            } else {
                sc[k] = [sc[k][0].add(d0.mul(d0)), sc[k][1].add(d1.mul(d1))];
            }
        }
    }
    let z = F2::splat(0.0);
    let ma = sa[0][0]
        .max_into(z)
        .max_into(sa[0][1].max_into(z))
        .max_into(sa[1][0].max_into(sa[1][1].max_into(z)));
    let mb = sb[0]
        .max_into(z)
        .max_into(sb[1].max_into(z))
        .max_into(sb[2].max_into(sb[3].max_into(z)));
    let mc = sc[0][0]
        .max_into(sc[0][1].max_into(z))
        .max_into(sc[1][0].max_into(sc[1][1].max_into(z)))
        .max_into(sc[2][0].max_into(sc[2][1].max_into(z)));
    let a2 = ma.lo().max(ma.hi());
    let b2 = mb.lo().max(mb.hi());
    let c2 = mc.lo().max(mc.hi());
    bound_of(a2, b2, c2)
}

/// The squared maxima of [`bound_f2`] (`a2, b2, c2` of [`bound_of`]) on
/// four-lane vectors: one net row per vector. The same IEEE operations on
/// the same values, summed over the coordinates in the same order, and
/// maxima order-free, so the bound has the same bits (the tests compare
/// the two). The unused lane of the mixed differences is `e3 - e3`: zero
/// for finite nets, NaN otherwise, which the maxima skip as the two-lane
/// path skips NaN. The square roots are left to the caller, outside AVX
/// code (libm's SSE2 square root after 256-bit code stalls on the upper
/// register halves).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bound_sums_avx2(n: &Net) -> (f64, f64, f64) {
    use core::arch::x86_64::*;
    // SAFETY: loads read 4 values of `n` at offsets o + 4a + 4 <= 48.
    let row = |o: usize| unsafe { _mm256_loadu_pd(n[o..o + 4].as_ptr()) };
    let two = _mm256_set1_pd(2.0);
    let sq = |d: __m256d| _mm256_mul_pd(d, d);
    let zero = _mm256_setzero_pd();
    let (mut sa, mut sb, mut sc) = ([zero; 2], [zero; 2], [zero; 3]);
    for c in 0..3 {
        let o = c * 16;
        let r = [row(o), row(o + 4), row(o + 8), row(o + 12)];
        // Along s: r[k+2] - 2 r[k+1] + r[k].
        for k in 0..2 {
            let d = _mm256_add_pd(_mm256_sub_pd(r[k + 2], _mm256_mul_pd(two, r[k + 1])), r[k]);
            sa[k] = if c == 0 {
                sq(d)
            } else {
                _mm256_add_pd(sa[k], sq(d))
            };
        }
        // Along t, two rows per vector: lanes (x[b], z[b]) for b = 0, 1.
        for h in 0..2 {
            let (x, z) = (r[2 * h], r[2 * h + 1]);
            let p0 = _mm256_permute2f128_pd::<0x20>(x, z);
            let p2 = _mm256_permute2f128_pd::<0x31>(x, z);
            let p1 = _mm256_shuffle_pd::<0b0101>(p0, p2);
            let d = _mm256_add_pd(_mm256_sub_pd(p2, _mm256_mul_pd(two, p1)), p0);
            sb[h] = if c == 0 {
                sq(d)
            } else {
                _mm256_add_pd(sb[h], sq(d))
            };
        }
        // Mixed: differences along t of the differences along s.
        for k in 0..3 {
            let e = _mm256_sub_pd(r[k + 1], r[k]);
            let e_next = _mm256_permute4x64_pd::<0b11_11_10_01>(e);
            let d = _mm256_sub_pd(e_next, e);
            sc[k] = if c == 0 {
                sq(d)
            } else {
                _mm256_add_pd(sc[k], sq(d))
            };
        }
    }
    // Maxima as the two-lane path forms them: max(value, acc) from 0.
    let max4 = |v: &[__m256d]| -> f64 {
        let mut m = zero;
        for &x in v {
            m = _mm256_max_pd(x, m);
        }
        let h = _mm_max_pd(_mm256_extractf128_pd::<1>(m), _mm256_castpd256_pd128(m));
        let hi = _mm_unpackhi_pd(h, h);
        _mm_cvtsd_f64(_mm_max_pd(hi, h))
    };
    (max4(&sa), max4(&sb), max4(&sc))
}

/// Control point `idx` (`a * 4 + b`) of a net.
#[inline(always)]
pub(crate) fn point(n: &Net, idx: usize) -> DVec3 {
    DVec3::new(n[idx], n[16 + idx], n[32 + idx])
}

/// Position of corner `q` (without the frame's offset).
#[inline]
pub(crate) fn corner(n: &Net, q: usize) -> DVec3 {
    point(n, CORNER_POINT[q & 3])
}

/// Longer diagonal of the corner quad.
#[inline]
pub(crate) fn diagonal(n: &Net) -> f64 {
    let d0 = (corner(n, 2) - corner(n, 0)).length();
    let d1 = (corner(n, 3) - corner(n, 1)).length();
    d0.max(d1)
}

/// A lower bound `g` of `|S(x + h, y + h) - S(x, y)| / h` over the cell (in
/// its own coordinates), or a non-positive number: with `u` the direction
/// of the cell's main diagonal, `<S_s, u> >= min_k <3 (P[a+1][b] - P[a][b]), u>`
/// and likewise for `S_t` (derivative nets and the convex hull property),
/// and the diagonal of any sub-cell of side h is at least
/// `h (min <S_s, u> + min <S_t, u>)` long.
pub(crate) fn diagonal_rate(n: &Net) -> f64 {
    let d = corner(n, 2) - corner(n, 0);
    let l = d.length();
    if !(l > 0.0 && l.is_finite()) {
        return 0.0;
    }
    let u = d / l;
    let (mut ms, mut mt) = (f64::INFINITY, f64::INFINITY);
    for a in 0..4 {
        for b in 0..4 {
            let p = point(n, a * 4 + b);
            if a < 3 {
                ms = ms.min(3.0 * (point(n, (a + 1) * 4 + b) - p).dot(u));
            }
            if b < 3 {
                mt = mt.min(3.0 * (point(n, a * 4 + b + 1) - p).dot(u));
            }
        }
    }
    ms + mt
}

/// Unit normal `normalize(S_s x S_t)` at corner `q` from the first control
/// point differences (exact tangent directions); `None` where the net is
/// degenerate there.
#[inline]
pub(crate) fn corner_normal(n: &Net, q: usize) -> Option<DVec3> {
    // (index of the later, index of the earlier) control point along s and t.
    let (ds, dt) = match q & 3 {
        0 => ((4, 0), (1, 0)),
        1 => ((12, 8), (13, 12)),
        2 => ((15, 11), (15, 14)),
        _ => ((7, 3), (3, 2)),
    };
    let du = point(n, ds.0) - point(n, ds.1);
    let dv = point(n, dt.0) - point(n, dt.1);
    normal_of(du, dv)
}

/// `normalize(du x dv)`, or `None` when degenerate (see [`corner_normal`]).
#[inline(always)]
pub(crate) fn normal_of(du: DVec3, dv: DVec3) -> Option<DVec3> {
    let c = du.cross(dv);
    let l2 = c.length_squared();
    if nondegenerate(l2, du, dv) {
        Some(c * (1.0 / libm::sqrt(l2)))
    } else {
        None
    }
}

/// Whether `|du x dv|^2 = l2` is a usable normal length: normal and not
/// negligible against `|du|^2 |dv|^2`.
#[inline(always)]
fn nondegenerate(l2: f64, du: DVec3, dv: DVec3) -> bool {
    let scale = du.length_squared() * dv.length_squared();
    l2.is_normal() && l2 > 1e-24 * scale
}

/// Transposed de Casteljau halves of rows `x` and `y` (4 values each, as
/// two vectors): lane 0 is row `x`, lane 1 row `y`; `[p0, m01, m012, mid]`
/// and `[mid, m123, m23, p3]`.
#[inline(always)]
fn row_halves(x: [F2; 2], y: [F2; 2]) -> ([F2; 4], [F2; 4]) {
    halves2([
        x[0].lo_lo(y[0]),
        x[0].hi_hi(y[0]),
        x[1].lo_lo(y[1]),
        x[1].hi_hi(y[1]),
    ])
}

/// The five points a split of the cell creates, from its own net: centre,
/// then the midpoints of sides 0..4, each as (position without offset,
/// unit normal). Bit-identical to reading them from the quadrant nets of
/// [`split4`] as the emission does (centre: corner 2 of quadrant 0; side
/// 0: corner 1 of quadrant 0; side 1: corner 2 of quadrant 1; side 2:
/// corner 3 of quadrant 2; side 3: corner 0 of quadrant 3, positions and
/// [`corner_normal`]), computing only those control points. All five
/// positions are written to `out`, the normals of the points in `mask`
/// (bit `w` for point `w`) only; false
/// (with `out` partly written) when one of their normals is degenerate (the
/// caller then looks at the other quadrants).
pub(crate) fn node_points(n: &Net, mask: u32, out: &mut [(DVec3, DVec3); 5]) -> bool {
    // v[c][k]: value k of coordinate c; see the table below.
    #[inline(always)]
    fn coord(n: &Net, c: usize) -> [f64; 15] {
        let o = c * 16;
        let row = |a: usize| [F2::ld(n, o + a * 4), F2::ld(n, o + a * 4 + 2)];
        // Along s (the columns): rows r0, m01, m012, mid, m123, m23, r3.
        let (c0, c1, c2, c3) = (row(0), row(1), row(2), row(3));
        let (l0, u0) = halves2([c0[0], c1[0], c2[0], c3[0]]);
        let (l1, u1) = halves2([c0[1], c1[1], c2[1], c3[1]]);
        let r = |a: usize| {
            if a < 4 {
                [l0[a], l1[a]]
            } else {
                [u0[a - 3], u1[a - 3]]
            }
        };
        // Along t, rows (r0, m01), (m012, mid), (m23, r3).
        let (_, u01) = row_halves(r(0), r(1));
        let (l23, u23) = row_halves(r(2), r(3));
        let (l56, _) = row_halves(r(5), r(6));
        [
            // Centre: mid of row mid; mid of row m012; m012 of row mid.
            l23[3].hi(),
            l23[3].lo(),
            l23[2].hi(),
            // Side 0: mid[0]; m012[0]; m01 of row mid.
            l23[0].hi(),
            l23[0].lo(),
            l23[1].hi(),
            // Side 1: mid of row r3; mid of row m23; m012 of row r3.
            l56[3].hi(),
            l56[3].lo(),
            l56[2].hi(),
            // Side 2: mid[3]; m123[3]; m23 of row mid.
            u23[3].hi(),
            r(4)[1].hi(),
            u23[2].hi(),
            // Side 3: mid of row r0; mid of row m01; m123 of row r0.
            u01[0].lo(),
            u01[0].hi(),
            u01[1].lo(),
        ]
    }
    let v = [coord(n, 0), coord(n, 1), coord(n, 2)];
    let p = |k: usize| DVec3::new(v[0][k], v[1][k], v[2][k]);
    // (du, dv) as corner_normal forms them at the corner used; the
    // normals as normal_of makes them, with the square roots and
    // reciprocals two at a time (the same IEEE operations per lane).
    let mut cr = [DVec3::ZERO; 5];
    let mut l2 = [1.0f64; 6];
    for (w, o) in out.iter_mut().enumerate() {
        o.0 = p(3 * w);
        if mask & (1 << w) == 0 {
            continue;
        }
        let (du, dv) = match w {
            0 => (p(0) - p(1), p(0) - p(2)),
            1 => (p(3) - p(4), p(5) - p(3)),
            2 => (p(6) - p(7), p(6) - p(8)),
            3 => (p(10) - p(9), p(9) - p(11)),
            _ => (p(13) - p(12), p(14) - p(12)),
        };
        let c = du.cross(dv);
        let n2 = c.length_squared();
        if !nondegenerate(n2, du, dv) {
            return false;
        }
        (cr[w], l2[w]) = (c, n2);
    }
    let one = F2::splat(1.0);
    let inv = [0, 2, 4].map(|k| one.div(F2::ld(&l2, k).sqrt()));
    let inv = [
        inv[0].lo(),
        inv[0].hi(),
        inv[1].lo(),
        inv[1].hi(),
        inv[2].lo(),
    ];
    for (w, o) in out.iter_mut().enumerate() {
        if mask & (1 << w) != 0 {
            o.1 = cr[w] * inv[w];
        }
    }
    true
}

/// [`node_points`] of four nets at once: positions and normals, indexed
/// `[coordinate][point][net]`.
pub(crate) struct Points4 {
    pub pos: [[[f64; 4]; 5]; 3],
    pub nrm: [[[f64; 4]; 5]; 3],
}

impl Points4 {
    pub(crate) const ZERO: Points4 = Points4 {
        pos: [[[0.0; 4]; 5]; 3],
        nrm: [[[0.0; 4]; 5]; 3],
    };
    /// Position and normal of point `w` of net `l`.
    #[inline(always)]
    pub(crate) fn get(&self, l: usize, w: usize) -> (DVec3, DVec3) {
        let v = |a: &[[[f64; 4]; 5]; 3]| DVec3::new(a[0][w][l], a[1][w][l], a[2][w][l]);
        (v(&self.pos), v(&self.nrm))
    }
}

/// [`node_points`] of four nets (`masks[l]` for net `l`) into `out`:
/// bit `l` of the result is what `node_points` returns for net `l`, and
/// every value written for it is bit for bit the one `node_points` gives
/// (the AVX2 path runs the same scalar formulas with the nets in the four
/// lanes).
pub(crate) fn node_points4(nets: &[Net; 4], masks: [u32; 4], out: &mut Points4) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        return unsafe { node_points4_avx2(nets, masks, out) };
    }
    let mut ok = 0;
    for (l, n) in nets.iter().enumerate() {
        let mut pts = [(DVec3::ZERO, DVec3::ZERO); 5];
        if node_points(n, masks[l], &mut pts) {
            ok |= 1 << l;
            for (w, (p, nm)) in pts.iter().enumerate() {
                for c in 0..3 {
                    out.pos[c][w][l] = p[c];
                    out.nrm[c][w][l] = nm[c];
                }
            }
        }
    }
    ok
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn node_points4_avx2(nets: &[Net; 4], masks: [u32; 4], out: &mut Points4) -> u32 {
    use core::arch::x86_64::*;
    let h = _mm256_set1_pd(0.5);
    let mid = |x: __m256d, y: __m256d| _mm256_mul_pd(h, _mm256_add_pd(x, y));
    // One cubic halved: [m01, m012, mid, m123, m23].
    let cast = |p: [__m256d; 4]| {
        let (m01, m12, m23) = (mid(p[0], p[1]), mid(p[1], p[2]), mid(p[2], p[3]));
        let (m012, m123) = (mid(m01, m12), mid(m12, m23));
        [m01, m012, mid(m012, m123), m123, m23]
    };
    let tr = |r: [__m256d; 4]| transpose4(r);
    // v[c][k]: value k of coordinate c, as node_points's table.
    let v: [[__m256d; 15]; 3] = core::array::from_fn(|c| {
        let p: [[__m256d; 4]; 4] = core::array::from_fn(|a| {
            let o = c * 16 + 4 * a;
            // SAFETY: each load reads 4 values at o + 4 <= 48 of a net.
            tr(core::array::from_fn(|l| unsafe {
                _mm256_loadu_pd(nets[l][o..o + 4].as_ptr())
            }))
        });
        // Along s, column b: rows r0, m01, m012, mid, m123, m23, r3.
        let cols: [[__m256d; 5]; 4] =
            core::array::from_fn(|b| cast([p[0][b], p[1][b], p[2][b], p[3][b]]));
        let rows: [[__m256d; 4]; 7] = core::array::from_fn(|k| {
            core::array::from_fn(|b| match k {
                0 => p[0][b],
                6 => p[3][b],
                _ => cols[b][k - 1],
            })
        });
        // Along t: [m01, m012, mid, m123, m23] of the rows used.
        let (t0, t1, t2, t3) = (cast(rows[0]), cast(rows[1]), cast(rows[2]), cast(rows[3]));
        let (t5, t6) = (cast(rows[5]), cast(rows[6]));
        [
            t3[2], t2[2], t3[1], // centre
            rows[3][0], rows[2][0], t3[0], // side 0
            t6[2], t5[2], t6[1], // side 1
            rows[3][3], rows[4][3], t3[4], // side 2
            t0[2], t1[2], t0[3], // side 3
        ]
    });
    let sub = |a: usize, b: usize| -> [__m256d; 3] {
        core::array::from_fn(|c| _mm256_sub_pd(v[c][a], v[c][b]))
    };
    let dot = |x: [__m256d; 3], y: [__m256d; 3]| {
        _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(x[0], y[0]), _mm256_mul_pd(x[1], y[1])),
            _mm256_mul_pd(x[2], y[2]),
        )
    };
    let mut ok = 0xfu32;
    for w in 0..5 {
        for c in 0..3 {
            // SAFETY: the destination holds four f64.
            unsafe { _mm256_storeu_pd(out.pos[c][w].as_mut_ptr(), v[c][3 * w]) };
        }
        let need = (0..4).fold(0u32, |m, l| m | (((masks[l] >> w) & 1) << l));
        if need == 0 {
            continue;
        }
        let (du, dv) = match w {
            0 => (sub(0, 1), sub(0, 2)),
            1 => (sub(3, 4), sub(5, 3)),
            2 => (sub(6, 7), sub(6, 8)),
            3 => (sub(10, 9), sub(9, 11)),
            _ => (sub(13, 12), sub(14, 12)),
        };
        // glam's cross product, term by term.
        let cr = [
            _mm256_sub_pd(_mm256_mul_pd(du[1], dv[2]), _mm256_mul_pd(dv[1], du[2])),
            _mm256_sub_pd(_mm256_mul_pd(du[2], dv[0]), _mm256_mul_pd(dv[2], du[0])),
            _mm256_sub_pd(_mm256_mul_pd(du[0], dv[1]), _mm256_mul_pd(dv[0], du[1])),
        ];
        let l2 = dot(cr, cr);
        let scale = _mm256_mul_pd(dot(du, du), dot(dv, dv));
        // nondegenerate(): l2 >= 0 here, so is_normal is
        // MIN_POSITIVE <= l2 < inf (NaN fails every comparison).
        let good = _mm256_and_pd(
            _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GE_OQ>(l2, _mm256_set1_pd(f64::MIN_POSITIVE)),
                _mm256_cmp_pd::<_CMP_LT_OQ>(l2, _mm256_set1_pd(f64::INFINITY)),
            ),
            _mm256_cmp_pd::<_CMP_GT_OQ>(l2, _mm256_mul_pd(_mm256_set1_pd(1e-24), scale)),
        );
        ok &= !(need & !(_mm256_movemask_pd(good) as u32));
        let inv = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(l2));
        for c in 0..3 {
            let n = _mm256_mul_pd(cr[c], inv);
            // SAFETY: the destination holds four f64.
            unsafe { _mm256_storeu_pd(out.nrm[c][w].as_mut_ptr(), n) };
        }
    }
    ok
}

// ---- Scalar nets over sub-rectangles and second-difference bounds (used by
// the eigen-table constants, the cell bounds and the corner fit). ----

/// The interpolation bound `lambda_max([[a, c], [c, b]]) / 3` of a
/// polynomial cell from the bounds `[a, b, c]` of `|S_ss|`, `|S_tt|`,
/// `|S_st|` (module docs).
#[inline(always)]
pub(crate) fn second_bound([a, b, c]: [f64; 3]) -> f64 {
    let m = 0.5 * (a + b) + libm::sqrt(0.25 * (a - b) * (a - b) + c * c);
    m / 3.0
}

/// Calls `f(kind, d)` with every second difference `d` of the 4 x 4 Bezier
/// net `p(k, l)` (k along u, l along v), in a fixed order: kind 0 along u
/// (`p(k+2, l) - 2 p(k+1, l) + p(k, l)`), 1 along v, 2 mixed
/// (`p(k+1, l+1) - p(k+1, l) - p(k, l+1) + p(k, l)`).
#[inline(always)]
pub(crate) fn second_differences<T>(p: impl Fn(usize, usize) -> T, mut f: impl FnMut(usize, T))
where
    T: Copy
        + core::ops::Add<Output = T>
        + core::ops::Sub<Output = T>
        + core::ops::Mul<f64, Output = T>,
{
    for k in 0..2 {
        for l in 0..4 {
            f(0, p(k + 2, l) - p(k + 1, l) * 2.0 + p(k, l));
            f(1, p(l, k + 2) - p(l, k + 1) * 2.0 + p(l, k));
        }
    }
    for k in 0..3 {
        for l in 0..3 {
            f(2, p(k + 1, l + 1) - p(k + 1, l) - p(k, l + 1) + p(k, l));
        }
    }
}

/// The uniform B-spline basis values and derivatives at both ends of an
/// interval `[t1, t2]`, and a third of its length: what the conversion of
/// a cubic to its Bezier points over the interval needs ([`Span::cubic`]),
/// computed once per interval for every cubic converted over it.
#[derive(Clone, Copy)]
pub(crate) struct Span {
    b1: [f64; 4],
    d1: [f64; 4],
    b2: [f64; 4],
    d2: [f64; 4],
    h: f64,
}

impl Span {
    /// The span `[t1, t2]`.
    #[inline]
    pub(crate) fn new(t1: f64, t2: f64) -> Span {
        let (b1, d1, _) = basis(t1);
        let (b2, d2, _) = basis(t2);
        Span {
            b1,
            d1,
            b2,
            d2,
            h: (t2 - t1) / 3.0,
        }
    }

    /// Bezier points over the span of the cubic `sum_i g_i B_i(t)`
    /// (uniform B-spline basis): `p(t1)`, `p(t1) + h/3 p'(t1)`,
    /// `p(t2) - h/3 p'(t2)`, `p(t2)`; for scalars or points (the same
    /// operations per coordinate).
    #[inline(always)]
    pub(crate) fn cubic<T>(&self, g: [T; 4]) -> [T; 4]
    where
        T: Copy
            + core::ops::Add<Output = T>
            + core::ops::Sub<Output = T>
            + core::ops::Mul<f64, Output = T>,
    {
        let dot = |w: [f64; 4]| g[0] * w[0] + g[1] * w[1] + g[2] * w[2] + g[3] * w[3];
        let (p1, q1, p2, q2) = (dot(self.b1), dot(self.d1), dot(self.b2), dot(self.d2));
        [p1, p1 + q1 * self.h, p2 - q2 * self.h, p2]
    }
}

/// [`scalar_bezier_net`] with the spans along u and v given.
#[inline(always)]
fn scalar_net_over(g: &[f64], su: &Span, sv: &Span) -> [[f64; 4]; 4] {
    let mut rows = [[0.0f64; 4]; 4]; // rows[j][k]: u-Bezier of v-row j
    for (j, row) in rows.iter_mut().enumerate() {
        let col = |i: usize| g[i * 4 + j];
        *row = su.cubic([col(0), col(1), col(2), col(3)]);
    }
    core::array::from_fn(|k| sv.cubic([rows[0][k], rows[1][k], rows[2][k], rows[3][k]]))
}

/// Bezier net `P[k][l]` (k along u, l along v) over `[u1,u2] x [v1,v2]` of
/// the scalar bicubic B-spline with the 16 coefficients `g` (index
/// `i * 4 + j`, i along u): each cubic converted by [`Span::cubic`], first
/// along u, then along v.
pub(crate) fn scalar_bezier_net(g: &[f64], u1: f64, u2: f64, v1: f64, v2: f64) -> [[f64; 4]; 4] {
    scalar_net_over(g, &Span::new(u1, u2), &Span::new(v1, v2))
}

/// The [`Net`] over `[u1,u2] x [v1,v2]` of the bicubic B-spline whose
/// control point `i * 4 + j` (`i` along u) is `p(i * 4 + j)`: each cubic
/// converted by [`Span::cubic`], first along u, then along v, so every
/// coordinate gets the operations of [`scalar_bezier_net`] (the basis
/// values are computed once per span). Unlike [`from_grid_rotated`] (the
/// unit square by the exact `1/6`, `1/3` formula, the tessellation's
/// kernel), any sub-rectangle; the two round differently, so each user
/// keeps its own (decision: outputs stay bit for bit those of the code
/// they replace).
#[inline]
pub(crate) fn net_over_points(
    p: impl Fn(usize) -> DVec3,
    u1: f64,
    u2: f64,
    v1: f64,
    v2: f64,
) -> Net {
    let (su, sv) = (Span::new(u1, u2), Span::new(v1, v2));
    // rows[j][k]: u-Bezier point k of B-spline row j (v index j).
    let mut rows = [[DVec3::ZERO; 4]; 4];
    for (j, r) in rows.iter_mut().enumerate() {
        *r = su.cubic([p(j), p(4 + j), p(8 + j), p(12 + j)]);
    }
    let mut out = [0.0; 48];
    for k in 0..4 {
        let col = sv.cubic([rows[0][k], rows[1][k], rows[2][k], rows[3][k]]);
        for (l, q) in col.iter().enumerate() {
            out[k * 4 + l] = q.x;
            out[16 + k * 4 + l] = q.y;
            out[32 + k * 4 + l] = q.z;
        }
    }
    out
}

/// Second-derivative bounds (a, b, c) of the bicubic B-spline grid `g`
/// restricted to `[u1,u2] x [v1,v2]` (in cell coordinates).
pub(crate) fn grid_second_bounds(g: &Grid, u1: f64, u2: f64, v1: f64, v2: f64) -> [f64; 3] {
    // Bezier net P[k][l] (k along u, l along v) per coordinate.
    let net: [[[f64; 4]; 4]; 3] =
        core::array::from_fn(|c| scalar_bezier_net(&g[c * 16..c * 16 + 16], u1, u2, v1, v2));
    let p = |k: usize, l: usize| DVec3::new(net[0][k][l], net[1][k][l], net[2][k][l]);
    let mut m = [0.0f64; 3];
    second_differences(p, |kind, d| m[kind] = m[kind].max(d.length()));
    [6.0 * m[0], 6.0 * m[1], 9.0 * m[2]]
}

/// Axis-aligned box of a net (a guaranteed bound of the surface over the
/// cell, by the convex hull property). Plain comparisons (`minpd`/`maxpd`
/// semantics: the first operand if smaller/larger, else the second) on two
/// lanes per coordinate, the even and the odd points (`0, 2, .., 14` and
/// `1, 3, .., 15`, neighbours in memory), then the two lanes: the order of
/// the voxelizer's former pairwise lanes, so signed zeros and NaNs come out
/// as they did there.
#[inline(always)]
pub(crate) fn net_box(n: &Net) -> (DVec3, DVec3) {
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    for c in 0..3 {
        let mut l = F2::ld(n, c * 16);
        let mut h = l;
        for p in 1..8 {
            let x = F2::ld(n, c * 16 + 2 * p);
            l = x.min_sel(l);
            h = x.max_sel(h);
        }
        // The odd lane's result is the second operand, as before.
        lo[c] = if l.lo() < l.hi() { l.lo() } else { l.hi() };
        hi[c] = if h.lo() > h.hi() { h.lo() } else { h.hi() };
    }
    (DVec3::from_array(lo), DVec3::from_array(hi))
}

/// The signed distances `(p_i - o) . m` of the 16 control points from the
/// plane through `o` with normal `m`, folded into `(min(0, ..), max(0, ..))`
/// (NaN distances ignored). Each distance is formed as
/// `(p - o).dot(m)` forms it; the fold starts at 0 and takes a value only
/// when strictly smaller (larger), so its result does not depend on the
/// order and two lanes give the bits of the plain loop.
#[inline(always)]
pub(crate) fn plane_range(n: &Net, o: DVec3, m: DVec3) -> (f64, f64) {
    let (ox, oy, oz) = (F2::splat(o.x), F2::splat(o.y), F2::splat(o.z));
    let (mx, my, mz) = (F2::splat(m.x), F2::splat(m.y), F2::splat(m.z));
    let mut a = F2::splat(0.0);
    let mut b = F2::splat(0.0);
    for i in (0..16).step_by(2) {
        let dx = F2::ld(n, i).sub(ox);
        let dy = F2::ld(n, 16 + i).sub(oy);
        let dz = F2::ld(n, 32 + i).sub(oz);
        let d = dx.mul(mx).add(dy.mul(my)).add(dz.mul(mz));
        a = d.min_sel(a);
        b = d.max_sel(b);
    }
    let lo = if a.lo() < a.hi() { a.lo() } else { a.hi() };
    let hi = if b.lo() > b.hi() { b.lo() } else { b.hi() };
    (lo, hi)
}

/// The four corners of a net in counter-clockwise parameter order:
/// S(0,0), S(1,0), S(1,1), S(0,1).
#[inline]
pub(crate) fn corners(n: &Net) -> [DVec3; 4] {
    CORNER_POINT.map(|i| point(n, i))
}

#[cfg(test)]
mod tests {
    //! The vector kernels against the plain scalar formulas they replace
    //! (bit for bit).
    use super::*;

    /// Bezier points over [0,1] of the uniform cubic B-spline segment with
    /// control points `g`.
    fn bspline_to_bezier(g: [f64; 4]) -> [f64; 4] {
        const S: f64 = 1.0 / 6.0;
        const T: f64 = 1.0 / 3.0;
        [
            (g[0] + 4.0 * g[1] + g[2]) * S,
            (2.0 * g[1] + g[2]) * T,
            (g[1] + 2.0 * g[2]) * T,
            (g[1] + 4.0 * g[2] + g[3]) * S,
        ]
    }

    /// Bezier net over the unit square of a bicubic B-spline patch (exact
    /// conversion; same orientation as the grid).
    pub(crate) fn from_grid(g: &Grid) -> Net {
        let mut tmp = [0.0f64; 48];
        let mut out = [0.0f64; 48];
        for c in 0..3 {
            let o = c * 16;
            // Along b (v) for each a-row of the grid.
            for a in 0..4 {
                let r = bspline_to_bezier([
                    g[o + a * 4],
                    g[o + a * 4 + 1],
                    g[o + a * 4 + 2],
                    g[o + a * 4 + 3],
                ]);
                tmp[o + a * 4..o + a * 4 + 4].copy_from_slice(&r);
            }
            // Along a (u) for each b-column.
            for b in 0..4 {
                let r = bspline_to_bezier([
                    tmp[o + b],
                    tmp[o + 4 + b],
                    tmp[o + 8 + b],
                    tmp[o + 12 + b],
                ]);
                for a in 0..4 {
                    out[o + a * 4 + b] = r[a];
                }
            }
        }
        out
    }

    /// The net of `n` (in a patch frame) seen from a frame rotated by `rho`:
    /// local `(s, t)` maps to patch `rot_param(rho, s, t)` (see
    /// `eval::frame::rot_param`), so `out[a][b] = n[k][l]` with
    /// `(k, l) = 3 rot_param(rho, a/3, b/3)`.
    fn rotate(n: &Net, rho: u8) -> Net {
        if rho & 3 == 0 {
            return *n;
        }
        let mut out = [0.0f64; 48];
        for a in 0..4 {
            for b in 0..4 {
                let (k, l) = match rho & 3 {
                    1 => (b, 3 - a),
                    2 => (3 - a, 3 - b),
                    _ => (3 - b, a),
                };
                for c in 0..3 {
                    out[c * 16 + a * 4 + b] = n[c * 16 + k * 4 + l];
                }
            }
        }
        out
    }

    /// Scalar de Casteljau halves of one cubic.
    fn halves1(p: &[f64]) -> ([f64; 4], [f64; 4]) {
        let m01 = 0.5 * (p[0] + p[1]);
        let m12 = 0.5 * (p[1] + p[2]);
        let m23 = 0.5 * (p[2] + p[3]);
        let m012 = 0.5 * (m01 + m12);
        let m123 = 0.5 * (m12 + m23);
        let mid = 0.5 * (m012 + m123);
        ([p[0], m01, m012, mid], [mid, m123, m23, p[3]])
    }

    fn split4_ref(n: &Net, out: &mut [Net; 4]) {
        for c in 0..3 {
            let o = c * 16;
            let mut lo = [[0.0; 4]; 4];
            let mut hi = [[0.0; 4]; 4];
            for b in 0..4 {
                let col = [n[o + b], n[o + 4 + b], n[o + 8 + b], n[o + 12 + b]];
                let (l, h) = halves1(&col);
                for a in 0..4 {
                    lo[a][b] = l[a];
                    hi[a][b] = h[a];
                }
            }
            for a in 0..4 {
                let (l0, l1) = halves1(&lo[a]);
                let (h0, h1) = halves1(&hi[a]);
                let at = o + a * 4;
                out[0][at..at + 4].copy_from_slice(&l0);
                out[3][at..at + 4].copy_from_slice(&l1);
                out[1][at..at + 4].copy_from_slice(&h0);
                out[2][at..at + 4].copy_from_slice(&h1);
            }
        }
    }

    fn bound_ref(n: &Net) -> f64 {
        let mut sa = [[0.0f64; 4]; 2];
        let mut sb = [[0.0f64; 2]; 4];
        let mut sc = [[0.0f64; 3]; 3];
        for c in 0..3 {
            let o = c * 16;
            let r: [[f64; 4]; 4] = core::array::from_fn(|a| {
                [
                    n[o + a * 4],
                    n[o + a * 4 + 1],
                    n[o + a * 4 + 2],
                    n[o + a * 4 + 3],
                ]
            });
            for k in 0..2 {
                for b in 0..4 {
                    let d = r[k + 2][b] - 2.0 * r[k + 1][b] + r[k][b];
                    sa[k][b] += d * d;
                }
            }
            for a in 0..4 {
                for l in 0..2 {
                    let d = r[a][l + 2] - 2.0 * r[a][l + 1] + r[a][l];
                    sb[a][l] += d * d;
                }
            }
            for k in 0..3 {
                let e: [f64; 4] = core::array::from_fn(|b| r[k + 1][b] - r[k][b]);
                for l in 0..3 {
                    let d = e[l + 1] - e[l];
                    sc[k][l] += d * d;
                }
            }
        }
        let mx = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0f64, |m, x| m.max(x));
        let a = 6.0 * libm::sqrt(mx(&mut sa.iter().flatten().copied()));
        let b = 6.0 * libm::sqrt(mx(&mut sb.iter().flatten().copied()));
        let c = 9.0 * libm::sqrt(mx(&mut sc.iter().flatten().copied()));
        let m = 0.5 * (a + b) + libm::sqrt(0.25 * (a - b) * (a - b) + c * c);
        m / 3.0
    }

    /// Deterministic pseudo-random nets with mixed magnitudes.
    pub(crate) fn nets(count: usize) -> impl Iterator<Item = Net> {
        // Under Miri (about 1000x slower) a handful of nets.
        nets_all(if cfg!(miri) { count.min(3) } else { count })
    }

    /// `count` pseudo-random nets, also under Miri.
    fn nets_all(count: usize) -> impl Iterator<Item = Net> {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        (0..count).map(move |i| {
            let mut n = [0.0; 48];
            for x in n.iter_mut() {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                let e = ((s >> 3) % 40) as i32 - 20;
                *x = libm::scalbn(u, if i % 3 == 0 { e } else { 0 }) + (i % 5) as f64;
            }
            n
        })
    }

    #[test]
    fn split4_matches_scalar() {
        for n in nets(2000) {
            let (mut a, mut b) = ([[0.0; 48]; 4], [[0.0; 48]; 4]);
            split4_ref(&n, &mut b);
            let check = |a: &[Net; 4]| {
                for q in 0..4 {
                    for i in 0..48 {
                        assert_eq!(a[q][i].to_bits(), b[q][i].to_bits(), "q {q} i {i}");
                    }
                }
            };
            split4_f2(&n, &mut a);
            check(&a);
            #[cfg(target_arch = "x86_64")]
            if crate::math::simd::has_avx2() {
                // SAFETY: AVX2 checked.
                unsafe { split4_avx2(&n, &mut a) };
                check(&a);
            }
            split4(&n, &mut a);
            check(&a);
        }
    }

    #[test]
    fn node_points_match_quadrants() {
        const AT: [(usize, usize); 5] = [(0, 2), (0, 1), (1, 2), (2, 3), (3, 0)];
        for n in nets(2000) {
            let mut q = [[0.0; 48]; 4];
            split4(&n, &mut q);
            let mut p = [(DVec3::ZERO, DVec3::ZERO); 5];
            let ok = node_points(&n, 31, &mut p);
            let want: [Option<(DVec3, DVec3)>; 5] = core::array::from_fn(|w| {
                let (c, k) = AT[w];
                corner_normal(&q[c], k).map(|nn| (corner(&q[c], k), nn))
            });
            match ok {
                true => {
                    for w in 0..5 {
                        let (a, b) = want[w].unwrap();
                        assert_eq!(
                            p[w].0.to_array().map(f64::to_bits),
                            a.to_array().map(f64::to_bits)
                        );
                        assert_eq!(
                            p[w].1.to_array().map(f64::to_bits),
                            b.to_array().map(f64::to_bits)
                        );
                    }
                }
                false => assert!(want.iter().any(|w| w.is_none())),
            }
            // Without normals: all five positions, never a failure.
            let mut r = [(DVec3::ZERO, DVec3::ZERO); 5];
            assert!(node_points(&n, 0, &mut r));
            for w in 0..5 {
                let (c, k) = AT[w];
                assert_eq!(
                    r[w].0.to_array().map(f64::to_bits),
                    corner(&q[c], k).to_array().map(f64::to_bits)
                );
            }
        }
    }

    #[test]
    fn from_grid_rotated_matches_scalar() {
        for (i, g) in nets(500).enumerate() {
            let rho = (i % 4) as u8;
            let mut a = [0.0; 48];
            from_grid_rotated(&g, rho, &mut a);
            let b = rotate(&from_grid(&g), rho);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
            from_grid_rotated_f2(&g, rho, &mut a);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }

    #[test]
    fn bound_matches_scalar() {
        let mut nan = nets(1).next().unwrap();
        nan[5] = f64::NAN;
        let mut inf = nets(1).next().unwrap();
        inf[31] = f64::INFINITY;
        for n in nets(2000).chain([nan, inf]) {
            let want = bound_ref(&n);
            assert_same_bits(bound_f2(&n), want);
            #[cfg(target_arch = "x86_64")]
            if crate::math::simd::has_avx2() {
                // SAFETY: AVX2 checked.
                let (a2, b2, c2) = unsafe { bound_sums_avx2(&n) };
                assert_same_bits(bound_of(a2, b2, c2), want);
            }
            assert_same_bits(bound(&n), want);
        }
    }

    /// Bit-for-bit equal; under Miri, which picks NaN bit patterns freely
    /// (as IEEE 754 allows), any NaN matches a NaN.
    fn assert_same_bits(got: f64, want: f64) {
        if cfg!(miri) && got.is_nan() && want.is_nan() {
            return;
        }
        assert_eq!(got.to_bits(), want.to_bits());
    }

    #[test]
    fn node_points4_matches_one_by_one() {
        let mut all: Vec4Nets = [[0.0; 48]; 400];
        // Under Miri the first 16 nets (they hold the degenerate ones).
        let used = if cfg!(miri) { 16 } else { all.len() };
        for (d, n) in all.iter_mut().zip(nets_all(used)) {
            *d = n;
        }
        // Degenerate normals: a constant net, a net flat along t, NaN.
        all[5] = [1.0; 48];
        for a in 0..4 {
            for c in 0..3 {
                let o = c * 16 + 4 * a;
                let x = all[9][o];
                all[9][o..o + 4].fill(x);
            }
        }
        all[14][20] = f64::NAN;
        let mut seed = 7u32;
        let mut fails = 0;
        for c in all[..used].chunks_exact(4) {
            let four: &[Net; 4] = c.try_into().unwrap();
            let masks = core::array::from_fn(|_| {
                seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                (seed >> 8) & 31
            });
            let mut got = Points4::ZERO;
            let ok = node_points4(four, masks, &mut got);
            for l in 0..4 {
                let mut want = [(DVec3::ZERO, DVec3::ZERO); 5];
                let w_ok = node_points(&four[l], masks[l], &mut want);
                assert_eq!(ok & (1 << l) != 0, w_ok, "net {l} masks {masks:?}");
                if !w_ok {
                    fails += 1;
                    continue;
                }
                for (w, want) in want.iter().enumerate() {
                    let (p, n) = got.get(l, w);
                    assert_eq!(
                        p.to_array().map(f64::to_bits),
                        want.0.to_array().map(f64::to_bits)
                    );
                    if masks[l] & (1 << w) != 0 {
                        assert_eq!(
                            n.to_array().map(f64::to_bits),
                            want.1.to_array().map(f64::to_bits)
                        );
                    }
                }
            }
        }
        // The degenerate nets failed (with a non-empty mask), the rest not.
        assert!((1..=3).contains(&fails), "{fails} failures");
    }

    type Vec4Nets = [Net; 400];

    #[test]
    fn bound4_matches_one_by_one() {
        let mut all: [Net; 402] = [[0.0; 48]; 402];
        for (d, n) in all.iter_mut().zip(nets(402)) {
            *d = n;
        }
        all[7][5] = f64::NAN;
        all[13][31] = f64::INFINITY;
        all[22][40] = f64::NEG_INFINITY;
        for c in all.chunks_exact(4) {
            let four: &[Net; 4] = c.try_into().unwrap();
            let got = bound4(four);
            for q in 0..4 {
                assert_same_bits(got[q], bound_ref(&four[q]));
            }
        }
    }
}
