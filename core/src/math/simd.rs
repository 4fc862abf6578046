//! A two-lane f64 vector for the Bezier-net kernels of the tessellation,
//! the eigenvalue powers of the tables and the jump-free parameter steps of
//! the evaluator (ring region, split quadrant): SSE2 on x86_64 (part of the
//! baseline, no run-time detection), plain pairs elsewhere. Every operation
//! is the IEEE operation of each lane, so results are bit-identical to the
//! scalar formulas written in the same order (Rust never contracts to FMA).
//!
//! [`has_avx2`] tells (once, by CPUID) whether the four-lane kernels some
//! modules keep beside their two-lane ones may run; those kernels do the
//! same IEEE operations per value, so both paths give the same bits.

#[cfg(target_arch = "x86_64")]
mod imp {
    use core::arch::x86_64::*;

    /// Two f64 lanes.
    #[derive(Clone, Copy)]
    #[repr(transparent)]
    pub(crate) struct F2(__m128d);

    // SAFETY (all blocks below): SSE2 is part of the x86_64 baseline; loads
    // and stores go through bounds-checked sub-slices of length 2.
    impl F2 {
        #[inline(always)]
        pub fn splat(x: f64) -> F2 {
            F2(unsafe { _mm_set1_pd(x) })
        }
        /// Lanes `(a, b)`.
        #[inline(always)]
        pub fn ld2(a: f64, b: f64) -> F2 {
            F2(unsafe { _mm_set_pd(b, a) })
        }
        /// Lanes `s[i], s[i + 1]`.
        #[inline(always)]
        pub fn ld(s: &[f64], i: usize) -> F2 {
            let s = &s[i..i + 2];
            F2(unsafe { _mm_loadu_pd(s.as_ptr()) })
        }
        /// Writes the lanes to `s[i], s[i + 1]`.
        #[inline(always)]
        pub fn st(self, s: &mut [f64], i: usize) {
            let s = &mut s[i..i + 2];
            unsafe { _mm_storeu_pd(s.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        pub fn add(self, o: F2) -> F2 {
            F2(unsafe { _mm_add_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn sub(self, o: F2) -> F2 {
            F2(unsafe { _mm_sub_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn mul(self, o: F2) -> F2 {
            F2(unsafe { _mm_mul_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn div(self, o: F2) -> F2 {
            F2(unsafe { _mm_div_pd(self.0, o.0) })
        }
        /// Lane-wise IEEE square root (as `libm::sqrt`).
        #[inline(always)]
        pub fn sqrt(self) -> F2 {
            F2(unsafe { _mm_sqrt_pd(self.0) })
        }
        /// Lane-wise maximum of `self` and `acc`, ignoring NaN lanes of
        /// `self` (as `f64::max(acc, self)` does when `acc` is not NaN).
        #[inline(always)]
        pub fn max_into(self, acc: F2) -> F2 {
            // MAXPD returns the second operand when either is NaN.
            F2(unsafe { _mm_max_pd(self.0, acc.0) })
        }
        /// `self < acc ? self : acc` lane-wise (MINPD: the second operand
        /// on ties and NaNs), the same in both implementations.
        #[inline(always)]
        pub fn min_sel(self, acc: F2) -> F2 {
            F2(unsafe { _mm_min_pd(self.0, acc.0) })
        }
        /// `self > acc ? self : acc` lane-wise (MAXPD), the same in both
        /// implementations (unlike [`F2::max_into`]'s fallback).
        #[inline(always)]
        pub fn max_sel(self, acc: F2) -> F2 {
            F2(unsafe { _mm_max_pd(self.0, acc.0) })
        }
        /// `self - (c >= at ? d : +0.0)` lane-wise, by a compare mask
        /// (CMPPD, ANDPD, SUBPD) instead of a branch: where the compare
        /// is random from call to call, LLVM lowers the `select` of an f64
        /// to a jump, which then mispredicts (BENCHMARKS.md). The same
        /// bits as the branch: `x - 0.0` is `x`, signed zeros included.
        #[inline(always)]
        pub fn minus_where_ge(self, c: F2, at: F2, d: F2) -> F2 {
            F2(unsafe { _mm_sub_pd(self.0, _mm_and_pd(_mm_cmpge_pd(c.0, at.0), d.0)) })
        }
        /// (self.0, o.0)
        #[inline(always)]
        pub fn lo_lo(self, o: F2) -> F2 {
            F2(unsafe { _mm_unpacklo_pd(self.0, o.0) })
        }
        /// (self.1, o.1)
        #[inline(always)]
        pub fn hi_hi(self, o: F2) -> F2 {
            F2(unsafe { _mm_unpackhi_pd(self.0, o.0) })
        }
        /// (self.1, o.0)
        #[inline(always)]
        pub fn hi_lo(self, o: F2) -> F2 {
            F2(unsafe { _mm_shuffle_pd::<0b01>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn lo(self) -> f64 {
            unsafe { _mm_cvtsd_f64(self.0) }
        }
        #[inline(always)]
        pub fn hi(self) -> f64 {
            unsafe { _mm_cvtsd_f64(_mm_unpackhi_pd(self.0, self.0)) }
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    /// Two f64 lanes.
    #[derive(Clone, Copy)]
    pub(crate) struct F2([f64; 2]);

    impl F2 {
        #[inline(always)]
        pub fn splat(x: f64) -> F2 {
            F2([x, x])
        }
        #[inline(always)]
        pub fn ld2(a: f64, b: f64) -> F2 {
            F2([a, b])
        }
        #[inline(always)]
        pub fn ld(s: &[f64], i: usize) -> F2 {
            F2([s[i], s[i + 1]])
        }
        #[inline(always)]
        pub fn st(self, s: &mut [f64], i: usize) {
            s[i] = self.0[0];
            s[i + 1] = self.0[1];
        }
        #[inline(always)]
        pub fn add(self, o: F2) -> F2 {
            F2([self.0[0] + o.0[0], self.0[1] + o.0[1]])
        }
        #[inline(always)]
        pub fn sub(self, o: F2) -> F2 {
            F2([self.0[0] - o.0[0], self.0[1] - o.0[1]])
        }
        #[inline(always)]
        pub fn mul(self, o: F2) -> F2 {
            F2([self.0[0] * o.0[0], self.0[1] * o.0[1]])
        }
        #[inline(always)]
        pub fn div(self, o: F2) -> F2 {
            F2([self.0[0] / o.0[0], self.0[1] / o.0[1]])
        }
        /// Lane-wise IEEE square root.
        #[inline(always)]
        pub fn sqrt(self) -> F2 {
            F2([libm::sqrt(self.0[0]), libm::sqrt(self.0[1])])
        }
        #[inline(always)]
        pub fn max_into(self, acc: F2) -> F2 {
            F2([acc.0[0].max(self.0[0]), acc.0[1].max(self.0[1])])
        }
        #[inline(always)]
        pub fn min_sel(self, acc: F2) -> F2 {
            let m = |x: f64, a: f64| if x < a { x } else { a };
            F2([m(self.0[0], acc.0[0]), m(self.0[1], acc.0[1])])
        }
        #[inline(always)]
        pub fn max_sel(self, acc: F2) -> F2 {
            let m = |x: f64, a: f64| if x > a { x } else { a };
            F2([m(self.0[0], acc.0[0]), m(self.0[1], acc.0[1])])
        }
        /// `self - (c >= at ? d : +0.0)` lane-wise.
        #[inline(always)]
        pub fn minus_where_ge(self, c: F2, at: F2, d: F2) -> F2 {
            let m = |x: f64, c: f64, a: f64, d: f64| x - if c >= a { d } else { 0.0 };
            F2([
                m(self.0[0], c.0[0], at.0[0], d.0[0]),
                m(self.0[1], c.0[1], at.0[1], d.0[1]),
            ])
        }
        #[inline(always)]
        pub fn lo_lo(self, o: F2) -> F2 {
            F2([self.0[0], o.0[0]])
        }
        #[inline(always)]
        pub fn hi_hi(self, o: F2) -> F2 {
            F2([self.0[1], o.0[1]])
        }
        #[inline(always)]
        pub fn hi_lo(self, o: F2) -> F2 {
            F2([self.0[1], o.0[0]])
        }
        #[inline(always)]
        pub fn lo(self) -> f64 {
            self.0[0]
        }
        #[inline(always)]
        pub fn hi(self) -> f64 {
            self.0[1]
        }
    }
}

pub(crate) use imp::F2;

/// Whether this CPU (and OS) runs AVX2 code: CPUID leaf 1 (AVX, OSXSAVE),
/// XCR0 (the OS saves the YMM state) and leaf 7 (AVX2). Asked once, then
/// remembered.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn has_avx2() -> bool {
    use core::sync::atomic::{AtomicU8, Ordering};
    // 0: not asked yet, 1: no, 2: yes.
    static KNOWN: AtomicU8 = AtomicU8::new(0);
    match KNOWN.load(Ordering::Relaxed) {
        0 => {
            let yes = detect_avx2();
            KNOWN.store(if yes { 2 } else { 1 }, Ordering::Relaxed);
            yes
        }
        k => k == 2,
    }
}

#[cfg(target_arch = "x86_64")]
#[cold]
fn detect_avx2() -> bool {
    // Miri cannot run CPUID (inline assembly): there the AVX2 path is taken
    // only when the build enables AVX2 (`-C target-feature=+avx2`).
    if cfg!(miri) {
        return cfg!(target_feature = "avx2");
    }
    use core::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
    #[target_feature(enable = "xsave")]
    unsafe fn xcr0() -> u64 {
        unsafe { _xgetbv(0) }
    }
    // SAFETY: CPUID exists on every x86_64 CPU; XGETBV is only executed
    // when CPUID reports OSXSAVE (the OS enabled it).
    unsafe {
        if __cpuid(0).eax < 7 {
            return false;
        }
        let l1 = __cpuid(1).ecx;
        let (osxsave, avx) = (l1 & (1 << 27) != 0, l1 & (1 << 28) != 0);
        if !(osxsave && avx) || xcr0() & 0b110 != 0b110 {
            return false;
        }
        __cpuid_count(7, 0).ebx & (1 << 5) != 0
    }
}

/// Asks the CPU to start loading every cache line of the `len` bytes from
/// `start` (x86_64: `prefetcht0`, one per line; a hint only: it never
/// faults, reads nothing into the program and changes no value), so a read
/// whose address is known early overlaps other misses instead of following
/// them. Elsewhere, and under Miri, nothing.
#[inline(always)]
pub(crate) fn prefetch<T>(start: *const T, len: usize) {
    #[cfg(all(target_arch = "x86_64", not(miri)))]
    {
        use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = start.cast::<i8>();
        let mut at = 0;
        while at < len {
            // SAFETY: SSE is part of the x86_64 baseline; a prefetch does
            // not dereference its address (any address is allowed).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(at)) };
            at += 64;
        }
        if len > 0 {
            // SAFETY: as above (the line of the last byte).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(len - 1)) };
        }
    }
    #[cfg(not(all(target_arch = "x86_64", not(miri))))]
    let _ = (start, len);
}

#[cfg(test)]
mod tests {
    use super::F2;

    /// [`F2::minus_where_ge`] is the branch it replaces, `x - (c >= at ?
    /// d : 0.0)`, bit for bit in both lanes: at and around the thresholds
    /// the evaluator uses (1/2, 1), signed zeros, NaN and infinite
    /// operands, subnormals.
    #[test]
    fn minus_where_ge_is_the_branch_bit_for_bit() {
        let vals = [
            0.0,
            -0.0,
            5e-324,
            0.25,
            0.49999999999999994,
            0.5,
            0.5000000000000001,
            0.75,
            0.9999999999999999,
            1.0,
            1.0000000000000002,
            2.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        let mut n = 0;
        for &x in &vals {
            for &c in &vals {
                for at in [0.5, 1.0] {
                    for d in [1.0, -0.0, 0.5] {
                        let want = x - if c >= at { d } else { 0.0 };
                        let lanes = F2::ld2(x, -x).minus_where_ge(
                            F2::ld2(c, c),
                            F2::splat(at),
                            F2::splat(d),
                        );
                        let want_hi = -x - if c >= at { d } else { 0.0 };
                        assert!(same(lanes.lo(), want), "{x} {c} {at} {d}");
                        assert!(same(lanes.hi(), want_hi), "-{x} {c} {at} {d}");
                        n += 1;
                    }
                }
            }
        }
        assert_eq!(n, 16 * 16 * 2 * 3);
    }
}
