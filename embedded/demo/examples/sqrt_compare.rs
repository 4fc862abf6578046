//! Host side of the `f32` square-root comparison (BENCHMARKS.md
//! "Firmware"; the Cortex-M4F side is `embedded/firmware/examples/sqrt_bench.rs`):
//! `libm::sqrtf` (what `Evaluator::eval_f32` uses off hard-float ARM),
//! `micromath`'s `F32Ext::sqrt` and the host FPU (`f32::sqrt`): the largest
//! error in ulps against the correctly rounded root (`f64` root rounded to
//! `f32`) over every `f32` in `[1, 4)` (both exponent parities: 2^24
//! inputs) and 2^20 spread over `[2^-100, 2^100)`, and ns per call (best
//! of 5 passes over 2^24 inputs). A benchmark:
//!
//!   cargo run --release -p ccss-embedded-demo --example sqrt_compare

use micromath::F32Ext;
use std::hint::black_box;
use std::time::Instant;

fn input(k: u32) -> f32 {
    if k < 1 << 24 {
        f32::from_bits(1.0f32.to_bits() + k)
    } else {
        let j = k - (1 << 24);
        let e = 27 + (j % 200);
        f32::from_bits((e << 23) | (j.wrapping_mul(2_654_435_761) >> 9))
    }
}

const INPUTS: u32 = (1 << 24) + (1 << 20);

/// A square root under test.
type Sqrt = fn(f32) -> f32;

fn main() {
    let cases: [(&str, Sqrt); 3] = [
        ("libm::sqrtf", libm::sqrtf),
        ("micromath", |x| F32Ext::sqrt(x)),
        ("f32::sqrt (host FPU)", f32::sqrt),
    ];
    for (name, f) in cases {
        let mut worst = 0u32;
        let mut worst_rel = 0.0f64;
        for k in 0..INPUTS {
            let x = input(k);
            let exact = (x as f64).sqrt() as f32;
            let y = f(x);
            worst = worst.max(y.to_bits().abs_diff(exact.to_bits()));
            worst_rel = worst_rel.max(((y as f64) - (x as f64).sqrt()).abs() / (x as f64).sqrt());
        }
        let mut best = f64::MAX;
        for _ in 0..5 {
            let s = Instant::now();
            let mut acc = 0.0f32;
            for k in 0..1u32 << 24 {
                acc += f(black_box(input(k)));
            }
            black_box(acc);
            best = best.min(s.elapsed().as_secs_f64());
        }
        println!(
            "sqrt {name}: max error {worst} ulp ({worst_rel:.2e} relative), {:.2} ns per call",
            best * 1e9 / (1u64 << 24) as f64
        );
    }
}
