//! Certified closest points against dense sampling: for every query point
//! the reported distance is the exact distance to the reported limit point
//! and never exceeds the minimum over a dense grid of exact limit points
//! (refined by Gauss-Newton from the best samples) plus `tol`.

mod query_util;

use ccss_core::query::{closest, closest_batch, Closest, ClosestOptions, QueryWork};
use ccss_core::{DVec3, Evaluator};
use ccss_tests::harness::{standard_tables, with_evaluator, XorShift};
use query_util::{centre, diagonal, grids, meshes, SlotGrid};

/// Gauss-Newton from `(u, v)` in slot `(f, s)`: the closest point nearby.
fn polish(ev: &Evaluator, f: u32, s: u32, q: DVec3, mut u: f64, mut v: f64) -> f64 {
    let mut e = ev.eval(f, s, u, v).unwrap();
    for _ in 0..30 {
        let r = e.p - q;
        let (g11, g12, g22) = (e.du.dot(e.du), e.du.dot(e.dv), e.dv.dot(e.dv));
        let (b1, b2) = (r.dot(e.du), r.dot(e.dv));
        let det = g11 * g22 - g12 * g12;
        if det <= 0.0 {
            break;
        }
        let nu = (u - (b1 * g22 - b2 * g12) / det).clamp(0.0, 1.0);
        let nv = (v - (b2 * g11 - b1 * g12) / det).clamp(0.0, 1.0);
        let ne = ev.eval(f, s, nu, nv).unwrap();
        if (ne.p - q).length() >= (e.p - q).length() {
            break;
        }
        (u, v, e) = (nu, nv, ne);
    }
    (e.p - q).length()
}

/// The sampled minimum and the refined minimum near the best samples.
fn oracle(ev: &Evaluator, gs: &[SlotGrid], q: DVec3) -> (f64, f64) {
    let mut best: Vec<(f64, u32, u32, f64, f64)> = vec![];
    for g in gs {
        let n = g.n;
        for a in 0..=n {
            for b in 0..=n {
                let d = (g.pts[a * (n + 1) + b] - q).length();
                best.push((d, g.face, g.sub, a as f64 / n as f64, b as f64 / n as f64));
            }
        }
    }
    let k = 8.min(best.len());
    best.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
    best[..k].sort_by(|a, b| a.0.total_cmp(&b.0));
    let sampled = best[0].0;
    let refined = best[..8.min(best.len())]
        .iter()
        .map(|&(_, f, s, u, v)| polish(ev, f, s, q, u, v))
        .fold(sampled, f64::min);
    (sampled, refined)
}

#[test]
fn closest_is_global_within_tol() {
    let mut work = Box::new(QueryWork::ZERO);
    let (mut count, mut worst_gap, mut better) = (0usize, f64::NEG_INFINITY, 0usize);
    let mut qtime = 0.0;
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let slots: usize = (0..ev.num_faces()).map(|f| ev.num_subfaces(f)).sum();
            let n = ((40_000.0 / slots as f64).sqrt() as usize).clamp(6, 40);
            let gs = grids(ev, n);
            let diag = diagonal(&gs);
            let c = centre(&gs);
            let mut rng = XorShift(0x5151_2727_abcd_0001 ^ name.len() as u64);
            let mut pts = vec![];
            for _ in 0..40 {
                pts.push(c + DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.8 * diag);
            }
            // Near and on the surface, at slot corners (extraordinary
            // vertices) and inside slots, on both sides.
            for f in 0..ev.num_faces().min(12) {
                for (u, v) in [(0.0, 0.0), (0.3, 0.7)] {
                    let e = ev.eval(f as u32, 0, u, v).unwrap();
                    let h = rng.signed() * 0.05 * diag;
                    pts.push(e.p + e.normal * h);
                    pts.push(e.p);
                }
            }
            pts.push(c);
            pts.push(c + DVec3::new(10.0, -7.0, 3.0) * diag);
            for (pi, &q) in pts.iter().enumerate() {
                let tol = if pi % 2 == 0 { 1e-9 * diag } else { 1e-6 * diag };
                let t0 = std::time::Instant::now();
                let r = closest(ev, q, &ClosestOptions {
        tol,
        ..Default::default()
    }, &mut work).unwrap();
                qtime += t0.elapsed().as_secs_f64();
                let e = ev.eval(r.face, r.sub, r.u, r.v).unwrap();
                assert!((e.p - r.point).length() <= 1e-12 * diag);
                assert!(((r.point - q).length() - r.dist).abs() <= 1e-12 * diag);
                assert!(r.gap <= tol, "{name} point {pi}: gap {} > tol {tol}", r.gap);
                let (sampled, refined) = oracle(ev, &gs, q);
                assert!(
                    r.dist <= sampled + tol && r.dist <= refined + tol,
                    "{name} point {pi} {q}: {} vs sampled {sampled}, refined {refined} (tol {tol:e})",
                    r.dist
                );
                worst_gap = worst_gap.max((r.dist - refined) / tol);
                if r.dist < sampled - 1e-12 * diag {
                    better += 1;
                }
                count += 1;
            }
            // The batch gives the same answers.
            let pts = &pts[..8];
            let mut out = vec![Closest::default(); pts.len()];
            let opts = ClosestOptions {
        tol: 1e-9 * diag,
        ..Default::default()
    };
            closest_batch(ev, pts, &opts, &mut work, &mut out).unwrap();
            for (q, r) in pts.iter().zip(&out) {
                assert_eq!(*r, closest(ev, *q, &opts, &mut work).unwrap());
            }
        })
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    println!(
        "{count} points: worst (dist - refined oracle) / tol = {worst_gap:.3e}; {better} strictly closer than the best sample; queries took {qtime:.2} s"
    );
    assert!(count >= 300);
}

#[test]
fn bad_closest_queries_are_errors() {
    let m = &meshes()[0].1;
    with_evaluator(m, standard_tables(), |_, ev| {
        let mut w = Box::new(QueryWork::ZERO);
        let o = ClosestOptions::default();
        assert!(closest(ev, DVec3::new(f64::NAN, 0.0, 0.0), &o, &mut w).is_err());
        for tol in [0.0, -1.0, f64::INFINITY] {
            assert!(closest(
                ev,
                DVec3::ZERO,
                &ClosestOptions {
                    tol,
                    ..Default::default()
                },
                &mut w
            )
            .is_err());
        }
        let mut out = [Closest::default(); 1];
        let e = closest_batch(ev, &[DVec3::ZERO; 2], &o, &mut w, &mut out);
        assert!(matches!(
            e,
            Err((0, ccss_core::Error::BufferTooSmall { required: 2 }))
        ));
    })
    .unwrap();
}
