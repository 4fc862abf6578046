//! Single-precision square root for [`crate::eval::Evaluator::eval_f32`]'s
//! normal: the FPU's `vsqrt.f32` on hard-float ARM (a Cortex-M4F), else
//! `libm::sqrtf`. Both are correctly rounded (IEEE 754), so the results
//! agree bit for bit; `micromath`'s approximation was measured and not
//! taken (BENCHMARKS.md "Firmware": `embedded/firmware/examples/sqrt_bench.rs`
//! under QEMU, 73 instructions per call for `libm::sqrtf`, 7 for this
//! `vsqrt.f32` sequence, 10 for `micromath` with errors up to 719,629 ulps).

/// `sqrt(x)`, correctly rounded.
#[inline]
pub(crate) fn sqrt_f32(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        let r: u32;
        // Through core registers and a saved `s0`: rustc's `sreg` operands
        // need a `vfp2` target feature the thumbv7em-none-eabihf target
        // does not name. Every eabihf target has a VFP with `vsqrt.f32`.
        // SAFETY: `s0` is saved and restored; the asm touches only the
        // stack slot it pushes and pops.
        unsafe {
            core::arch::asm!(
                "vpush {{s0}}",
                "vmov s0, {x}",
                "vsqrt.f32 s0, s0",
                "vmov {r}, s0",
                "vpop {{s0}}",
                r = lateout(reg) r,
                x = in(reg) x.to_bits(),
                options(pure, nomem),
            );
        }
        f32::from_bits(r)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}
