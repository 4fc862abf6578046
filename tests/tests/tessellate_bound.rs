//! Adaptive tessellation, the error bound:
//!
//! 1. Dense exact samples: for every output polygon (a dyadic parameter
//!    cell, `Output::cells`) a jittered grid of parameters in the cell is
//!    evaluated exactly, and the distance of each limit point to the
//!    polygon's own triangles (an upper bound of its distance to the output
//!    mesh) must be at most eps. At least 10^6 samples per model and
//!    tolerance; zero violations. Tightness = max distance / eps.
//! 2. Every accepted cell, re-checked with `bounds::cell_bound` (the
//!    cellbound.rs bound, computed independently of the tessellator's top
//!    down nets): `interpolation_bound() <= eps` (absolute), resp. `<= R *`
//!    the cell's corner-quad diagonal or, for corner cells, `<= R *` the
//!    slot's (relative); and `tessellate::marking_bound` (the top-down value
//!    the marking uses) agrees with it to 1e-9 on every accepted cell.
//! 3. `Stats::bound` is at most eps and at least the largest cell bound.
mod tessellate_util;

use ccss_core::bounds::CellKind;
use ccss_core::tessellate::{self, Criterion, Options};
use ccss_core::Evaluator;
use ccss_tests::harness::{standard_tables, with_evaluator, XorShift};
use ccss_tests::reference::{drum, pole_mesh, PolyMesh};
use tessellate_util::*;

const MIN_SAMPLES: usize = 1_000_000;

fn corner_diag(ev: &Evaluator, face: u32, sub: u32, level: u32, i: u32, j: u32) -> f64 {
    let h = 0.5f64.powi(level as i32);
    let at = |di: u32, dj: u32| {
        ev.eval(face, sub, (i + di) as f64 * h, (j + dj) as f64 * h)
            .unwrap()
            .p
    };
    let (a, b, c, d) = (at(0, 0), at(1, 0), at(1, 1), at(0, 1));
    (c - a).length().max((d - b).length())
}

/// (samples, max distance / tol, cells checked)
fn check(name: &str, m: &PolyMesh, crit: Criterion) -> (usize, f64, usize) {
    let what = format!("{name} {crit:?}");
    with_evaluator(m, standard_tables(), |topo, ev| {
        let t = tessellate(topo, ev, Options { criterion: crit, max_level: 30 })
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        // 2. Every cell against cellbound.rs.
        let mut max_official = 0.0f64;
        for c in &t.cells {
            let cb = ccss_core::bounds::cell_bound(ev, c.face, c.sub, c.level, c.i, c.j).unwrap();
            assert_ne!(cb.kind, CellKind::Split, "{what}: accepted a split cell {c:?}");
            let b = cb.interpolation_bound();
            let td = tessellate::marking_bound(ev, c.face, c.sub, c.level, c.i, c.j).unwrap();
            assert!((td - b).abs() <= 1e-9 * b.max(1e-300), "{what}: {c:?}: top-down bound {td:e} vs cell_bound {b:e}");
            max_official = max_official.max(b);
            match crit {
                Criterion::Absolute(eps) => {
                    assert!(b <= eps * (1.0 + 1e-12), "{what}: {c:?} bound {b:e} > eps {eps:e}")
                }
                Criterion::Relative(r) => {
                    let d = corner_diag(ev, c.face, c.sub, c.level, c.i, c.j);
                    let ok = b <= r * d * (1.0 + 1e-9)
                        || (cb.kind == CellKind::Corner
                            && b <= r * corner_diag(ev, c.face, c.sub, 0, 0, 0) * (1.0 + 1e-9));
                    assert!(ok, "{what}: {c:?} bound {b:e} > R * diagonal {d:e}");
                }
                Criterion::Uniform(_) => {}
            }
        }
        assert!(t.stats.bound >= max_official * (1.0 - 1e-9), "{what}: stats bound {} < {max_official}", t.stats.bound);
        let tol = match crit {
            Criterion::Absolute(eps) => {
                assert!(t.stats.bound <= eps, "{what}: stats bound");
                eps
            }
            _ => t.stats.bound,
        };
        // 1. Dense samples, in parallel over polygons.
        let polys = t.polygons();
        let mut tri_start = Vec::with_capacity(polys.len());
        let mut acc = 0usize;
        for p in &polys {
            tri_start.push(acc);
            acc += p.len() - 2;
        }
        let k = ((MIN_SAMPLES as f64 / polys.len() as f64).sqrt().ceil() as usize).max(2);
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(8);
        let chunk = polys.len().div_ceil(threads);
        let results: Vec<(usize, f64)> = std::thread::scope(|sc| {
            let hs: Vec<_> = (0..threads)
                .map(|th| {
                    let (t, tri_start, polys) = (&t, &tri_start, &polys);
                    let what = &what;
                    sc.spawn(move || {
                        let mut rng = XorShift(0x9E3779B97F4A7C15 ^ (th as u64 + 1).wrapping_mul(0xD1B54A32D192ED03));
                        let (mut n, mut worst) = (0usize, 0.0f64);
                        let lo = th * chunk;
                        let hi = ((th + 1) * chunk).min(polys.len());
                        for p in lo..hi {
                            let c = t.cells[p];
                            let h = 0.5f64.powi(c.level as i32);
                            let tris = &t.tris[3 * tri_start[p]..3 * (tri_start[p] + polys[p].len() - 2)];
                            for a in 0..k {
                                for b in 0..k {
                                    let u = (c.i as f64 + (a as f64 + rng.unit()) / k as f64) * h;
                                    let v = (c.j as f64 + (b as f64 + rng.unit()) / k as f64) * h;
                                    let s = ev.eval_derivs(c.face, c.sub, u.min(1.0), v.min(1.0)).unwrap().p.to_array();
                                    let d = tris
                                        .chunks(3)
                                        .map(|tr| point_triangle_distance(s, t.p(tr[0]), t.p(tr[1]), t.p(tr[2])))
                                        .fold(f64::INFINITY, f64::min);
                                    assert!(d <= tol * (1.0 + 1e-9) + 1e-14, "{what}: sample ({u}, {v}) of polygon {p} {c:?} is {d:e} from its triangles (tolerance {tol:e})");
                                    worst = worst.max(d);
                                    n += 1;
                                }
                            }
                        }
                        (n, worst)
                    })
                })
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let n: usize = results.iter().map(|r| r.0).sum();
        let worst = results.iter().map(|r| r.1).fold(0.0, f64::max);
        assert!(n >= MIN_SAMPLES, "{what}: only {n} samples");
        (n, worst / tol, t.cells.len())
    })
    .unwrap()
}

#[test]
fn dense_samples_within_the_guaranteed_bound() {
    let shapes: Vec<(&str, PolyMesh)> = vec![
        ("cube", corpus("catmark_cube.obj")),
        ("pyramid", corpus("catmark_pyramid.obj")),
        ("toroidal_tet", corpus("catmark_toroidal_tet.obj")),
        ("torus", corpus("catmark_torus.obj")),
        ("righthanded", corpus("catmark_righthanded.obj")),
        ("pole_mesh(7)", pole_mesh(7)),
        ("drum(5)", drum(5)),
    ];
    let mut total = 0usize;
    for (name, m) in &shapes {
        let diag = m.bbox_diagonal();
        // Two absolute tolerances on three shapes, one on the others;
        // relative flatness on three.
        let crits: Vec<Criterion> = match *name {
            "cube" | "toroidal_tet" | "righthanded" => {
                vec![
                    Criterion::Absolute(0.01 * diag),
                    Criterion::Absolute(0.001 * diag),
                ]
            }
            _ => vec![Criterion::Absolute(0.003 * diag)],
        };
        let rel = matches!(*name, "righthanded" | "pole_mesh(7)" | "torus");
        for crit in crits
            .into_iter()
            .chain(rel.then_some(Criterion::Relative(0.1)))
        {
            let (n, tight, cells) = check(name, m, crit);
            total += n;
            eprintln!("{name} {crit:?}: {cells} polygons, {n} samples, 0 violations, max distance / tolerance {tight:.4}");
        }
    }
    eprintln!("total: {total} samples, 0 violations");
}
