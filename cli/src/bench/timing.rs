//! The timed kernels of `ccss bench eval` and the median-of-samples loop.

use ccss_core::eval::Query;
use ccss_core::{Error, Eval, Evaluator, FeatureEvaluator};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// How the evaluator is called in the timed loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Api {
    /// `Evaluator::eval_derivs` (P, dP/du, dP/dv; no normal), one call per
    /// point: what the OpenSubdiv harness computes per point. With
    /// `--second`: `eval_second_derivs` (no normal either).
    Derivs,
    /// `Evaluator::eval` / `eval_second` (with the unit normal), one call
    /// per point.
    Point,
    /// `Evaluator::eval_batch` (with the unit normal) over chunks of 4096
    /// points.
    Batch,
}

/// Sum of the components the OpenSubdiv harness sums (P, Du, Dv), plus the
/// second derivatives when requested.
#[inline]
fn sum(e: &Eval, second: bool) -> f64 {
    let s = e.p.element_sum() + e.du.element_sum() + e.dv.element_sum();
    if second {
        s + e.duu.element_sum() + e.duv.element_sum() + e.dvv.element_sum()
    } else {
        s
    }
}

/// An evaluator the timed loops can call.
pub trait Timed {
    /// One point: with second derivatives, with the normal, or derivatives
    /// only (an evaluator without that entry point computes the normal).
    fn point<const SECOND: bool, const NORMAL: bool>(&self, q: &Query) -> Result<Eval, Error>;
    /// A batch.
    fn batch(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)>;
}

impl Timed for Evaluator<'_> {
    #[inline]
    fn point<const SECOND: bool, const NORMAL: bool>(&self, q: &Query) -> Result<Eval, Error> {
        match (SECOND, NORMAL) {
            (true, true) => self.eval_second(q.face, q.sub, q.u, q.v),
            (true, false) => self.eval_second_derivs(q.face, q.sub, q.u, q.v),
            (false, true) => self.eval(q.face, q.sub, q.u, q.v),
            (false, false) => self.eval_derivs(q.face, q.sub, q.u, q.v),
        }
    }
    fn batch(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)> {
        self.eval_batch(qs, second, out)
    }
}

impl Timed for FeatureEvaluator<'_, '_> {
    #[inline]
    fn point<const SECOND: bool, const NORMAL: bool>(&self, q: &Query) -> Result<Eval, Error> {
        if SECOND {
            self.eval_second(q.face, q.sub, q.u, q.v)
        } else {
            self.eval(q.face, q.sub, q.u, q.v)
        }
    }
    fn batch(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)> {
        for (i, (q, o)) in qs.iter().zip(out.iter_mut()).enumerate() {
            *o = if second {
                self.point::<true, true>(q)
            } else {
                self.point::<false, true>(q)
            }
            .map_err(|e| (i, e))?;
        }
        Ok(())
    }
}

fn pass_point<T: Timed, const SECOND: bool, const NORMAL: bool>(ev: &T, qs: &[Query]) -> f64 {
    let mut s = 0.0;
    for q in qs {
        let r = ev.point::<SECOND, NORMAL>(q);
        if let Ok(e) = r {
            s += sum(&e, SECOND);
        }
    }
    s
}

fn pass_batch<T: Timed>(ev: &T, qs: &[Query], second: bool, buf: &mut [Eval]) -> f64 {
    let mut s = 0.0;
    for chunk in qs.chunks(buf.len()) {
        let out = &mut buf[..chunk.len()];
        if ev.batch(chunk, second, out).is_ok() {
            for e in out.iter() {
                s += sum(e, second);
            }
        }
    }
    s
}

/// One pass over `qs`; returns the checksum.
pub fn pass<T: Timed>(ev: &T, qs: &[Query], second: bool, api: Api, buf: &mut [Eval]) -> f64 {
    let qs = black_box(qs);
    match (api, second) {
        (Api::Derivs, false) => pass_point::<T, false, false>(ev, qs),
        (Api::Derivs, true) => pass_point::<T, true, false>(ev, qs),
        (Api::Point, false) => pass_point::<T, false, true>(ev, qs),
        (Api::Point, true) => pass_point::<T, true, true>(ev, qs),
        (Api::Batch, _) => pass_batch(ev, qs, second, buf),
    }
}

/// Result of timing one class.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    /// Median over samples of nanoseconds per evaluation.
    pub ns_per_eval: f64,
    /// Checksum of one pass.
    pub checksum: f64,
}

/// Each sample repeats passes until it lasts at least this long.
const MIN_SAMPLE: Duration = Duration::from_millis(20);

/// Times `qs`: one warm-up pass (which gives the checksum), then `samples`
/// samples of whole passes; `tick` is called after each sample.
pub fn measure<T: Timed>(
    ev: &T,
    qs: &[Query],
    second: bool,
    api: Api,
    samples: usize,
    mut tick: impl FnMut(),
) -> Measured {
    let mut buf = vec![Eval::default(); 4096];
    let t0 = Instant::now();
    let checksum = pass(ev, qs, second, api, &mut buf);
    let warm = t0.elapsed().max(Duration::from_nanos(1));
    let reps = (MIN_SAMPLE.as_secs_f64() / warm.as_secs_f64())
        .ceil()
        .max(1.0) as usize;
    let mut ns: Vec<f64> = Vec::with_capacity(samples);
    for _ in 0..samples.max(1) {
        let t = Instant::now();
        for _ in 0..reps {
            black_box(pass(ev, qs, second, api, &mut buf));
        }
        ns.push(t.elapsed().as_secs_f64() * 1e9 / (reps * qs.len()) as f64);
        tick();
    }
    ns.sort_by(f64::total_cmp);
    let m = ns.len();
    let median = if m % 2 == 1 {
        ns[m / 2]
    } else {
        0.5 * (ns[m / 2 - 1] + ns[m / 2])
    };
    Measured {
        ns_per_eval: median,
        checksum,
    }
}
