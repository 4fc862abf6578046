//! Certified ray queries against a brute-force oracle: dense grids of exact
//! limit points per slot, triangulated and ray-cast, every triangle hit
//! refined by Newton's method on the exact evaluation (`query_util`).
//!
//! For thousands of rays over closed meshes with extraordinary vertices of
//! valences 3 to 9 and n-gons (random rays, rays aimed at slot corners and
//! edge midpoints, i.e. at extraordinary vertices and cell boundaries, and
//! axis-parallel rays through the centre), at tolerances 1e-9 and 1e-6 of
//! the diagonal:
//!
//! * zero missed crossings: every oracle crossing has a hit within `tol`;
//! * every hit is the exact limit point at its parameters and lies within
//!   `tol` of the ray;
//! * the first hit is the smallest of all hits;
//! * inside/outside agrees with the oracle's crossing parity.

mod query_util;

use ccss_core::query::{inside, ray_all, ray_first, Hit, HitKind, QueryWork, Ray, RayOptions};
use ccss_core::DVec3;
use ccss_tests::harness::{standard_tables, with_evaluator, XorShift};
use query_util::{centre, crossings, diagonal, grids, meshes};

#[test]
fn rays_miss_no_crossing() {
    let mut work = Box::new(QueryWork::ZERO);
    let mut total = (0usize, 0usize, 0usize, 0usize); // rays, oracle crossings, hits, tangent hits
    let mut worst_ratio = 0.0f64;
    let mut unmatched_transversal = 0usize;
    let mut not_real = 0usize;
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let slots: usize = (0..ev.num_faces()).map(|f| ev.num_subfaces(f)).sum();
            let n = ((60_000.0 / slots as f64).sqrt() as usize).clamp(6, 48);
            let gs = grids(ev, n);
            let diag = diagonal(&gs);
            let c = centre(&gs);
            let mut rng = XorShift(0x9e37_79b9_7f4a_7c15 ^ name.len() as u64);
            let mut rays = vec![];
            let rnd = |rng: &mut XorShift| DVec3::new(rng.signed(), rng.signed(), rng.signed());
            for _ in 0..200 {
                let o = c + rnd(&mut rng).normalize() * diag;
                let target = c + rnd(&mut rng) * 0.5 * diag;
                rays.push(Ray { origin: o, dir: (target - o) * (0.5 + rng.unit()) });
            }
            // Through slot corners (extraordinary vertices among them) and
            // edge midpoints (cell boundaries).
            for f in 0..ev.num_faces() {
                for s in 0..ev.num_subfaces(f) {
                    for (u, v) in [(0.0, 0.0), (0.5, 0.0), (0.5, 0.5)] {
                        if rays.len() > 600 {
                            break;
                        }
                        let p = ev.eval(f as u32, s as u32, u, v).unwrap().p;
                        let o = c + rnd(&mut rng).normalize() * diag;
                        rays.push(Ray { origin: o, dir: p - o });
                    }
                }
            }
            for a in 0..3 {
                let mut d = DVec3::ZERO;
                d[a] = 1.0;
                rays.push(Ray { origin: c - d * diag, dir: d });
            }
            for (ri, ray) in rays.iter().enumerate() {
                let tol = if ri % 2 == 0 { 1e-9 * diag } else { 1e-6 * diag };
                let opts = RayOptions {
        tol,
        t_min: 0.0,
        ..Default::default()
    };
                let oracle = crossings(ev, &gs, ray.origin, ray.dir, diag);
                let need = match ray_all(ev, ray, &opts, &mut work, &mut []) {
                    Ok(0) => 0,
                    Err(ccss_core::Error::BufferTooSmall { required }) => required,
                    e => panic!("{name} ray {ri}: {e:?}"),
                };
                let mut hits = vec![Hit::ZERO; need];
                let nh = ray_all(ev, ray, &opts, &mut work, &mut hits).unwrap();
                assert_eq!(nh, need, "size query is exact");
                let dl = ray.dir.length();
                // Soundness of every hit.
                for h in &hits {
                    let e = ev.eval(h.face, h.sub, h.u, h.v).unwrap();
                    assert!((e.p - h.point).length() <= 1e-12 * diag);
                    let r = h.point - ray.origin;
                    let along = r.dot(ray.dir) / dl;
                    let off = (r - along * ray.dir / dl).length();
                    assert!(off <= tol, "{name} ray {ri}: hit {off} off the ray (tol {tol})");
                    assert!((along / dl - h.t).abs() * dl <= 1e-12 * diag);
                    if h.kind == HitKind::Tangent {
                        total.3 += 1;
                    } else {
                        if !oracle.iter().any(|x| (x.t - h.t).abs() * dl <= tol) {
                            unmatched_transversal += 1;
                        }
                        // A transversal hit is a real crossing: Newton from
                        // it converges to one within tol.
                        let x = query_util::refine(ev, h.face, h.sub, ray.origin, ray.dir, h.u, h.v, h.t, diag);
                        let ok = x.is_some_and(|x| (x.t - h.t).abs() * dl <= tol);
                        if !ok {
                            if not_real < 8 { println!("{name} ray {ri}: {h:?} -> {x:?} tol {tol:e}"); }
                            not_real += 1;
                        }
                    }
                }
                for w in hits.windows(2) {
                    assert!(w[0].t <= w[1].t);
                }
                // Completeness.
                for x in &oracle {
                    let best = hits
                        .iter()
                        .map(|h| (h.t - x.t).abs() * dl)
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        best <= tol,
                        "{name} ray {ri}: missed crossing t {} at ({}, {}, {}, {}), cos {:.3e}; nearest hit {best:e}, tol {tol:e}; hits {hits:?}",
                        x.t, x.face, x.sub, x.u, x.v, x.cos
                    );
                    worst_ratio = worst_ratio.max(best / tol);
                }
                // First hit.
                let first = ray_first(ev, ray, &opts, &mut work).unwrap();
                match (first, hits.first()) {
                    (None, None) => {}
                    (Some(f), Some(h)) => assert!(
                        (f.t - h.t).abs() * dl <= tol,
                        "{name} ray {ri}: first {} vs {}",
                        f.t,
                        h.t
                    ),
                    (a, b) => panic!("{name} ray {ri}: first {a:?} vs all {b:?}"),
                }
                total.0 += 1;
                total.1 += oracle.len();
                total.2 += hits.len();
            }
        })
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    println!(
        "{} rays, {} oracle crossings, {} hits ({} tangent, {} transversal without an oracle crossing, {not_real} of them not refined to a crossing); worst |t - t*| / tol = {worst_ratio:.3e}",
        total.0, total.1, total.2, total.3, unmatched_transversal
    );
    assert!(total.0 >= 2000 && total.1 >= 2000);
    assert!(
        not_real * 100 <= total.2,
        "{not_real} transversal hits Newton cannot refine"
    );
}

#[test]
fn inside_matches_oracle_parity() {
    let mut work = Box::new(QueryWork::ZERO);
    let (mut checked, mut ins) = (0usize, 0usize);
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let gs = grids(ev, 16);
            let diag = diagonal(&gs);
            let c = centre(&gs);
            let mut rng = XorShift(0x1234_5678_9abc_def1);
            for _ in 0..60 {
                let p = c + DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.4 * diag;
                // Oracle parity along two directions; skip when they differ
                // (the point is near the surface or a ray grazes).
                let par = |d: DVec3| crossings(ev, &gs, p, d, diag).len() % 2 == 1;
                let (a, b) = (
                    par(DVec3::new(0.3, 0.5, 0.8)),
                    par(DVec3::new(-0.7, 0.2, -0.4)),
                );
                if a != b {
                    continue;
                }
                let got = inside(ev, p, 1e-9 * diag, &mut work).unwrap();
                assert_eq!(got, a, "{name}: point {p}");
                checked += 1;
                ins += got as usize;
            }
        })
        .unwrap();
    }
    println!("{checked} points checked, {ins} inside");
    assert!(checked >= 300 && ins >= 50);
}

#[test]
fn bad_rays_are_errors() {
    let m = &meshes()[0].1;
    with_evaluator(m, standard_tables(), |_, ev| {
        let mut w = Box::new(QueryWork::ZERO);
        let o = RayOptions::default();
        let bad = [
            Ray {
                origin: DVec3::ZERO,
                dir: DVec3::ZERO,
            },
            Ray {
                origin: DVec3::new(f64::NAN, 0.0, 0.0),
                dir: DVec3::X,
            },
            Ray {
                origin: DVec3::ZERO,
                dir: DVec3::new(0.0, f64::INFINITY, 0.0),
            },
        ];
        for r in bad {
            assert!(ray_first(ev, &r, &o, &mut w).is_err());
        }
        let r = Ray {
            origin: DVec3::new(0.1, 0.2, -5.0),
            dir: DVec3::Z,
        };
        for tol in [0.0, -1.0, f64::NAN] {
            assert!(ray_first(
                ev,
                &r,
                &RayOptions {
                    tol,
                    t_min: 0.0,
                    ..Default::default()
                },
                &mut w
            )
            .is_err());
        }
        // On the surface: inside/outside is undecided.
        let p = ev.eval(0, 0, 0.3, 0.4).unwrap().p;
        assert!(inside(ev, p, 1e-9, &mut w).is_err());
    })
    .unwrap();
}
