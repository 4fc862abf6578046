//! Square root in `f32` on the Cortex-M4F (QEMU `mps2-an386`,
//! `-icount shift=0`): `libm::sqrtf` (what `Evaluator::eval_f32` uses for
//! the normal), `micromath`'s `F32Ext::sqrt` and the FPU's `vsqrt.f32`.
//! For each: the largest error in ulps against the correctly rounded root
//! (`libm::sqrt` in `f64` rounded to `f32`, exact for square roots) over
//! every 16th `f32` in `[1, 4)` (both exponent parities, 2^20 inputs) and
//! 2^16 inputs spread over `[2^-100, 2^100)`, and instructions per call
//! (a loop of 2^16 calls, minus the same loop without the call).
//!
//!   cd embedded/firmware && cargo build --release --example sqrt_bench
//!   qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
//!     -icount shift=0 -semihosting-config enable=on,target=native \
//!     -kernel target/thumbv7em-none-eabihf/release/examples/sqrt_bench
#![no_std]
#![no_main]

#[path = "../src/ticks.rs"]
mod ticks;

use core::fmt::Write;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use micromath::F32Ext;

/// The FPU's square root (correctly rounded, IEEE 754).
#[inline(always)]
fn vsqrt(x: f32) -> f32 {
    let r: u32;
    // Through core registers and a saved s0: rustc's `sreg` operands need
    // a `vfp2` target feature this target does not name.
    // SAFETY: s0 is saved and restored; only the stack slot is touched.
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

fn libm_sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

fn micromath_sqrt(x: f32) -> f32 {
    F32Ext::sqrt(x)
}

fn fpu_sqrt(x: f32) -> f32 {
    vsqrt(x)
}

/// Distance in ulps of two positive finite `f32`.
fn ulps(a: f32, b: f32) -> u32 {
    a.to_bits().abs_diff(b.to_bits())
}

/// The inputs: every 16th `f32` in `[1, 4)`, then 2^16 spread over
/// `2^-100 .. 2^100` (exponent and mantissa from a counter).
fn input(k: u32) -> f32 {
    if k < 1 << 20 {
        f32::from_bits(1.0f32.to_bits() + 16 * k)
    } else {
        let j = k - (1 << 20);
        let e = 27 + (j % 200);
        f32::from_bits((e << 23) | ((j.wrapping_mul(2_654_435_761)) >> 9))
    }
}

const INPUTS: u32 = (1 << 20) + (1 << 16);
const CALLS: u32 = 1 << 16;

#[inline(never)]
fn max_ulps(f: fn(f32) -> f32) -> u32 {
    let mut worst = 0;
    for k in 0..INPUTS {
        let x = input(k);
        let exact = libm::sqrt(x as f64) as f32;
        worst = worst.max(ulps(f(x), exact));
    }
    worst
}

/// Instructions of `CALLS` calls through `f` on varied inputs (the sum
/// keeps the calls alive).
#[inline(never)]
fn count(f: fn(f32) -> f32) -> (u64, f32) {
    let t0 = ticks::instructions();
    let mut s = 0.0f32;
    let mut x = 1.0f32;
    for _ in 0..CALLS {
        s += f(x);
        x += 0.5;
    }
    (ticks::instructions() - t0, s)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

#[entry]
fn main() -> ! {
    let cp = cortex_m::Peripherals::take().unwrap();
    ticks::start(cp.SYST);
    let mut out = hio::hstdout().unwrap();
    // The first reading after start can precede the counter's first reload.
    count(|x| x);
    let (base, _) = count(|x| x);
    for (name, f) in [
        ("libm::sqrtf", libm_sqrt as fn(f32) -> f32),
        ("micromath", micromath_sqrt),
        ("vsqrt.f32", fpu_sqrt),
    ] {
        let (ins, s) = count(f);
        let per = ins.saturating_sub(base) as f64 / CALLS as f64;
        writeln!(out, "raw {name}: {ins} vs empty loop {base}").ok();
        let worst = max_ulps(f);
        writeln!(
            out,
            "sqrt {name}: {per:.1} instructions per call, max error {worst} ulp (checksum {s})"
        )
        .ok();
    }
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}
