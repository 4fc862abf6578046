//! `ccss bench tables [--weights W.tsv] [--reps R]`: single-threaded timing
//! of the eigen table construction (`ValenceTable::build_into`) per valence.
//!
//! Output (stdout), one line each, first for the standard rule, then (with
//! `--weights`) for the rule of the file:
//!
//! ```text
//! ccss tables n=3 us=41.2 weights=standard
//! ...
//! ccss tables n=16 us=2210.5 weights=standard
//! ccss tables total_us=9876.5 weights=standard
//! ccss tables n=3 us=45.0 weights=custom
//! ...
//! ```
//!
//! `us` is the median over `--reps` builds (after one untimed build, which
//! also checks that the table can be built) of one valence's table, in
//! microseconds, into a preallocated table and scratch (no allocation is
//! timed); `total_us` is the sum of the medians, i.e. the cost of a whole
//! `TableSet`. In the `weights=custom` pass valences the file does not list
//! use the standard rule.

use crate::error::{CliError, CliResult};
use crate::io::weights_file::WeightsArg;
use crate::stdout;
use ccss_core::{BuildScratch, ValenceTable, Weights, MAX_VALENCE};
use std::hint::black_box;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Time the construction of the eigen table of each valence 3..=max (ValenceTable::build_into, \
single-threaded, into preallocated memory) and print 'ccss tables n=N us=XX.X \
weights=standard' per valence, the median of --reps builds in microseconds, then 'ccss \
tables total_us=XX.X weights=standard' (the sum: one whole table set). With --weights W.tsv \
(the format of 'ccss eval --help') the same lines follow for that rule, with \
weights=custom (valences the file does not list use the standard rule).";

/// Arguments of `ccss bench tables`.
#[derive(clap::Args, Debug)]
pub struct BenchTablesArgs {
    /// Timed builds per valence (the median is reported).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub reps: u32,
    #[command(flatten)]
    pub weights: WeightsArg,
}

/// Median of `xs` (not empty).
fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(f64::total_cmp);
    let m = xs.len();
    if m % 2 == 1 {
        xs[m / 2]
    } else {
        0.5 * (xs[m / 2 - 1] + xs[m / 2])
    }
}

/// Times every valence for rule `w` and prints its lines.
fn pass(w: &Weights, label: &str, reps: usize) -> CliResult {
    // ~29 KiB and ~66 KiB: on the heap, allocated once.
    let mut table = Box::new(ValenceTable::ZERO);
    let mut scratch = Box::new(BuildScratch::ZERO);
    let mut us = vec![0.0f64; reps];
    let mut total = 0.0;
    for n in 3..=MAX_VALENCE {
        table.build_into(n, w, &mut scratch).map_err(|e| {
            CliError::failure(format!("cannot build the eigen table of valence {n}: {e}"))
        })?;
        for x in us.iter_mut() {
            let t = Instant::now();
            let r = table.build_into(black_box(n), black_box(w), &mut scratch);
            *x = t.elapsed().as_secs_f64() * 1e6;
            let _ = black_box((r, &table));
        }
        let med = median(&mut us);
        total += med;
        stdout::line(&format!("ccss tables n={n} us={med:.1} weights={label}"))?;
    }
    stdout::line(&format!("ccss tables total_us={total:.1} weights={label}"))
}

/// Runs the verb.
pub fn run(a: &BenchTablesArgs) -> CliResult {
    let custom = match a.weights.weights {
        Some(_) => Some(a.weights.load()?),
        None => None,
    };
    let reps = a.reps as usize;
    pass(&Weights::STANDARD, "standard", reps)?;
    if let Some(w) = custom {
        pass(&w, "custom", reps)?;
    }
    Ok(())
}
