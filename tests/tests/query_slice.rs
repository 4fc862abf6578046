//! Planar slices against the exact section curve, sampled independently:
//! on many parameter lines `u = const` and `v = const` of every slot the
//! roots of `n . S - h` are bracketed by sign changes of exact evaluations
//! and bisected. Checks, on closed meshes with extraordinary vertices
//! (valences 3 to 9, n-gons) and a genus-3 plate:
//!
//! * every exact section sample is within `eps` of the polylines and every
//!   polyline point (vertices and points along the edges) within `eps`
//!   (plus the sampling's own spacing) of the samples: Hausdorff `<= eps`;
//! * vertices are exact limit points on the plane;
//! * outer contours run counter-clockwise, holes clockwise (the plate has
//!   one outer contour and three holes at mid-height, the torus one and
//!   one), size queries are exact;
//! * the sum of the section areas over many layers matches the exact
//!   volume (`voxel::mass_properties`) within the slices' bound plus the
//!   quadrature's.

mod query_util;

use ccss_core::query::{
    band_layer, slice_band, slice_layer, slice_segment_count, slice_write, Contour, Plane,
    PlaneStack, QueryWork, SliceOptions, SliceSegment, SliceStats, MAX_BAND,
};
use ccss_core::{DVec3, Error, Evaluator};
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::shapes::pretzel;
use query_util::{centre, diagonal, grids, meshes};

/// One layer through the public API with exact buffers (and the size
/// errors of one-short buffers checked).
fn layer(
    ev: &Evaluator,
    plane: &Plane,
    eps: f64,
    w: &mut QueryWork,
) -> (Vec<[f64; 2]>, Vec<Contour>) {
    let o = SliceOptions {
        eps,
        ..Default::default()
    };
    let ns = slice_segment_count(ev, plane, &o, w).unwrap();
    let mut segs = vec![SliceSegment::default(); ns];
    let st = slice_layer(ev, plane, &o, w, &mut segs).unwrap();
    assert_eq!(st.segments, ns);
    assert_eq!(st.unresolved, 0);
    let mut pts = vec![[0.0; 2]; st.points];
    let mut cs = vec![Contour::default(); st.contours];
    if st.points > 0 {
        let mut short = vec![[7.0; 2]; st.points - 1];
        let e = slice_write(&mut segs, &mut short, &mut cs);
        assert_eq!(
            e,
            Err(Error::BufferTooSmall {
                required: st.points
            })
        );
        assert!(short.iter().all(|p| *p == [7.0; 2]), "nothing written");
        let e = slice_write(&mut segs, &mut pts, &mut cs[..st.contours - 1]);
        assert_eq!(
            e,
            Err(Error::BufferTooSmall {
                required: st.contours
            })
        );
    }
    let (np, nc) = slice_write(&mut segs, &mut pts, &mut cs).unwrap();
    assert_eq!((np, nc), (st.points, st.contours));
    (pts, cs)
}

/// Layers `first .. first + count` of `stack` through [`slice_band`]
/// (size query by an empty scratch, then exact buffers).
fn band(
    ev: &Evaluator,
    stack: &PlaneStack,
    first: usize,
    count: usize,
    eps: f64,
    w: &mut QueryWork,
) -> Vec<(SliceStats, Vec<[f64; 2]>, Vec<Contour>)> {
    let o = SliceOptions {
        eps,
        ..SliceOptions::default()
    };
    let mut stats = vec![SliceStats::default(); count];
    let need = match slice_band(ev, stack, first, &o, w, &mut [], &mut stats) {
        Err(Error::BufferTooSmall { required }) => required,
        Ok(0) => 0,
        r => panic!("size query: {r:?}"),
    };
    let mut segs = vec![SliceSegment::default(); need];
    if need > 0 {
        let e = slice_band(ev, stack, first, &o, w, &mut segs[..need - 1], &mut stats);
        assert_eq!(e, Err(Error::BufferTooSmall { required: need }));
    }
    assert_eq!(
        slice_band(ev, stack, first, &o, w, &mut segs, &mut stats),
        Ok(need)
    );
    assert_eq!(stats.iter().map(|s| s.segments).sum::<usize>(), need);
    (0..count)
        .map(|i| {
            let st = stats[i];
            let mut pts = vec![[0.0; 2]; st.points];
            let mut cs = vec![Contour::default(); st.contours];
            let r = slice_write(band_layer(&mut segs, &stats, i), &mut pts, &mut cs).unwrap();
            assert_eq!(r, (st.points, st.contours));
            (st, pts, cs)
        })
        .collect()
}

/// Exact section samples on `m` lines per direction per slot (3D points).
fn samples(ev: &Evaluator, n: DVec3, h: f64, m: usize) -> Vec<DVec3> {
    let mut out = vec![];
    let g = |f: u32, s: u32, u: f64, v: f64| n.dot(ev.eval(f, s, u, v).unwrap().p) - h;
    for f in 0..ev.num_faces() as u32 {
        for s in 0..ev.num_subfaces(f as usize) as u32 {
            for dir in 0..2 {
                for i in 0..=m {
                    let a = i as f64 / m as f64;
                    let at = |x: f64| if dir == 0 { (a, x) } else { (x, a) };
                    let k = 64;
                    let mut prev = {
                        let (u, v) = at(0.0);
                        g(f, s, u, v)
                    };
                    for j in 1..=k {
                        let x = j as f64 / k as f64;
                        let (u, v) = at(x);
                        let cur = g(f, s, u, v);
                        if (prev < 0.0) != (cur < 0.0) {
                            let (mut lo, mut hi) = ((j - 1) as f64 / k as f64, x);
                            for _ in 0..60 {
                                let mid = 0.5 * (lo + hi);
                                let (u, v) = at(mid);
                                if (g(f, s, u, v) < 0.0) == (prev < 0.0) {
                                    lo = mid;
                                } else {
                                    hi = mid;
                                }
                            }
                            let (u, v) = at(0.5 * (lo + hi));
                            out.push(ev.eval(f, s, u, v).unwrap().p);
                        }
                        prev = cur;
                    }
                }
            }
        }
    }
    out
}

fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (x, y) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
    (x * x + y * y).sqrt()
}

fn edges(pts: &[[f64; 2]], cs: &[Contour]) -> Vec<([f64; 2], [f64; 2])> {
    let mut e = vec![];
    for c in cs {
        let (s, l) = (c.start as usize, c.len as usize);
        for k in 0..l {
            e.push((pts[s + k], pts[s + (k + 1) % l]));
        }
    }
    e
}

fn signed_area(pts: &[[f64; 2]], c: &Contour) -> f64 {
    let (s, l) = (c.start as usize, c.len as usize);
    (0..l)
        .map(|k| {
            let (p, q) = (pts[s + k], pts[s + (k + 1) % l]);
            p[0] * q[1] - p[1] * q[0]
        })
        .sum::<f64>()
        * 0.5
}

#[test]
fn slices_within_eps_of_exact_section() {
    let mut w = Box::new(QueryWork::ZERO);
    let mut worst = (0.0f64, 0.0f64);
    let mut layers = 0;
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let gs = grids(ev, 8);
            let diag = diagonal(&gs);
            let c = centre(&gs);
            // Sampling spacing: the largest diameter of a 1/m parameter square.
            let mlines = 96;
            let fine = grids(ev, mlines);
            let mut spacing = 0.0f64;
            for g in &fine {
                let n1 = g.n + 1;
                for a in 0..g.n {
                    for b in 0..g.n {
                        let p = |i: usize, j: usize| g.pts[i * n1 + j];
                        spacing = spacing.max((p(a, b) - p(a + 1, b + 1)).length());
                        spacing = spacing.max((p(a + 1, b) - p(a, b + 1)).length());
                    }
                }
            }
            for (k, normal) in [DVec3::Z, DVec3::new(0.3, -0.2, 0.9), DVec3::X].iter().enumerate() {
                let nn = normal.normalize();
                let h = nn.dot(c) + 0.123 * diag * (k as f64 - 1.0);
                let plane = Plane { normal: *normal, offset: h };
                let eps = 3e-3 * diag;
                let (pts, cs) = layer(ev, &plane, eps, &mut w);
                let (_, e1, e2) = plane.frame().unwrap();
                let ex: Vec<[f64; 2]> = samples(ev, nn, h, mlines)
                    .iter()
                    .map(|p| [p.dot(e1), p.dot(e2)])
                    .collect();
                assert_eq!(ex.is_empty(), cs.is_empty(), "{name} plane {k}");
                if cs.is_empty() {
                    continue;
                }
                let es = edges(&pts, &cs);
                // Exact -> polylines.
                for p in &ex {
                    let d = es.iter().map(|&(a, b)| seg_dist(*p, a, b)).fold(f64::INFINITY, f64::min);
                    assert!(d <= eps, "{name} plane {k}: exact point {p:?} {d:e} from the polylines (eps {eps:e})");
                    worst.0 = worst.0.max(d / eps);
                }
                // Polylines -> exact (vertices and 8 points per edge).
                for &(a, b) in &es {
                    for i in 0..8 {
                        let t = i as f64 / 8.0;
                        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                        let d = ex
                            .iter()
                            .map(|q| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt())
                            .fold(f64::INFINITY, f64::min);
                        assert!(d <= eps + spacing, "{name} plane {k}: polyline point {d:e} from the section (eps {eps:e}, spacing {spacing:e})");
                        worst.1 = worst.1.max((d - spacing).max(0.0) / eps);
                    }
                }
                // Orientation: the solid's area is positive.
                let total: f64 = cs.iter().map(|c| signed_area(&pts, c)).sum();
                assert!(total > 0.0, "{name} plane {k}: area {total}");
                for c in &cs {
                    assert_eq!(c.outer, signed_area(&pts, c) > 0.0);
                }
                layers += 1;
            }
        })
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    assert!(layers >= 15);
    println!(
        "{layers} layers: worst exact->polyline {:.3} eps, polyline->exact {:.3} eps (beyond the sampling spacing)",
        worst.0, worst.1
    );
}

#[test]
fn holes_and_volume() {
    let mut w = Box::new(QueryWork::ZERO);
    // Genus-3 plate at mid-height: one outer contour, three holes inside it.
    let plate = pretzel(3);
    with_evaluator(&plate, standard_tables(), |_, ev| {
        let (pts, cs) = layer(ev, &Plane::z(0.5), 1e-3, &mut w);
        let outer: Vec<_> = cs.iter().filter(|c| c.outer).collect();
        let holes: Vec<_> = cs.iter().filter(|c| !c.outer).collect();
        assert_eq!((outer.len(), holes.len()), (1, 3), "{cs:?}");
        for h in &holes {
            assert!(signed_area(&pts, h) < 0.0);
            assert!(signed_area(&pts, h).abs() < signed_area(&pts, outer[0]));
        }
        // Sum of section areas over z times dz vs the exact volume.
        let mp = ccss_core::voxel::mass_properties(ev).unwrap();
        let (z0, z1) = (-0.2, 1.2);
        let k = 28;
        let dz = (z1 - z0) / k as f64;
        let eps = 1e-2;
        let (mut vol, mut bound) = (0.0, 0.0);
        // All layers in one band walk.
        let stack = PlaneStack::z(z0 + 0.5 * dz, dz);
        for (st, pts, cs) in band(ev, &stack, 0, k, eps, &mut w) {
            assert_eq!(st.unresolved, 0);
            let a: f64 = cs.iter().map(|c| signed_area(&pts, c)).sum();
            let per: f64 = edges(&pts, &cs)
                .iter()
                .map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt())
                .sum();
            vol += a * dz;
            bound += per * eps * dz;
        }
        let diff = (vol - mp.volume).abs();
        println!(
            "plate: sum of areas {vol:.6} vs exact volume {:.6}: diff {diff:.2e}, slice bound {bound:.2e}",
            mp.volume
        );
        // Midpoint quadrature adds O(dz^2); allow it on top of the bound.
        assert!(diff <= bound + 2e-3 * mp.volume, "{diff} > {bound}");
    })
    .unwrap();
    // Torus through its middle: one outer, one hole.
    let root = ccss_tests::harness::workspace_root().join("tests/data/osd/catmark_torus.obj");
    let torus = ccss_tests::reference::PolyMesh::from_obj(&root);
    with_evaluator(&torus, standard_tables(), |_, ev| {
        let gs = grids(ev, 4);
        let c = centre(&gs);
        // The torus' axis: try the three axes, one gives the ring section.
        let mut found = false;
        for n in [DVec3::X, DVec3::Y, DVec3::Z] {
            let (_, cs) = layer(
                ev,
                &Plane {
                    normal: n,
                    offset: n.dot(c),
                },
                1e-3,
                &mut w,
            );
            let o = cs.iter().filter(|c| c.outer).count();
            if cs.len() == 2 && o == 1 {
                found = true;
            }
        }
        assert!(found);
    })
    .unwrap();
}

#[test]
fn bad_slices_are_errors() {
    let m = &meshes()[0].1;
    with_evaluator(m, standard_tables(), |_, ev| {
        let mut w = Box::new(QueryWork::ZERO);
        let p = Plane::z(0.0);
        for eps in [0.0, -1.0, f64::NAN] {
            assert!(slice_segment_count(
                ev,
                &p,
                &SliceOptions {
                    eps,
                    ..Default::default()
                },
                &mut w
            )
            .is_err());
        }
        let bad = Plane {
            normal: DVec3::ZERO,
            offset: 0.0,
        };
        assert!(slice_segment_count(ev, &bad, &SliceOptions::default(), &mut w).is_err());
        let n = slice_segment_count(ev, &p, &SliceOptions::default(), &mut w).unwrap();
        let mut segs = vec![SliceSegment::default(); n - 1];
        let e = slice_layer(ev, &p, &SliceOptions::default(), &mut w, &mut segs);
        assert_eq!(e, Err(Error::BufferTooSmall { required: n }));
    })
    .unwrap();
}

/// The band slicer against one walk per layer: on every test mesh, stacks
/// of 150 layers (tilted and axis normals, heights rising and falling)
/// from one side of the solid to the other, cut into bands of 64 and of
/// 23 layers, give each layer the same statistics, points (bit for bit)
/// and contours as `slice_layer` on
/// `stack.layer(k)`; bad bands are errors.
#[test]
fn bands_equal_single_layers() {
    let mut w = Box::new(QueryWork::ZERO);
    let mut compared = 0;
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let gs = grids(ev, 8);
            let diag = diagonal(&gs);
            let c = centre(&gs);
            // Rising and falling heights (the walk skips the layers
            // outside a cell's range by a search in either order).
            for (normal, sign) in [
                (DVec3::Z, 1.0),
                (DVec3::new(0.3, -0.2, 0.9), 1.0),
                (DVec3::new(0.3, -0.2, 0.9), -1.0),
            ] {
                let nn = normal.normalize();
                let total = 150;
                let step = sign * 1.2 * diag / total as f64;
                let stack = PlaneStack {
                    normal,
                    offset: nn.dot(c) - sign * 0.6 * diag,
                    step,
                };
                let eps = 2e-3 * diag;
                for bsize in [MAX_BAND, 23] {
                    let mut first = 0;
                    while first < total {
                        let count = bsize.min(total - first);
                        let got = band(ev, &stack, first, count, eps, &mut w);
                        for (i, (st, pts, cs)) in got.into_iter().enumerate() {
                            let plane = stack.layer(first + i);
                            let o = SliceOptions {
                                eps,
                                ..SliceOptions::default()
                            };
                            let ns = slice_segment_count(ev, &plane, &o, &mut w).unwrap();
                            let mut segs = vec![SliceSegment::default(); ns];
                            let one = slice_layer(ev, &plane, &o, &mut w, &mut segs).unwrap();
                            assert_eq!(st, one, "{name} layer {}", first + i);
                            let mut p1 = vec![[0.0; 2]; one.points];
                            let mut c1 = vec![Contour::default(); one.contours];
                            slice_write(&mut segs, &mut p1, &mut c1).unwrap();
                            assert_eq!(pts, p1, "{name} layer {}", first + i);
                            assert_eq!(cs, c1, "{name} layer {}", first + i);
                            compared += !cs.is_empty() as usize;
                        }
                        first += count;
                    }
                }
            }
        })
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    assert!(compared > 1000, "{compared}");
    // Bad bands.
    with_evaluator(&meshes()[0].1, standard_tables(), |_, ev| {
        let o = SliceOptions::default();
        let s = PlaneStack::z(0.0, 0.1);
        for n in [0, MAX_BAND + 1] {
            let mut stats = vec![SliceStats::default(); n];
            assert!(slice_band(ev, &s, 0, &o, &mut w, &mut [], &mut stats).is_err());
        }
        let mut stats = vec![SliceStats::default(); 4];
        let bad = PlaneStack::z(0.0, f64::NAN);
        assert!(slice_band(ev, &bad, 0, &o, &mut w, &mut [], &mut stats).is_err());
        let bad = SliceOptions {
            eps: 0.0,
            ..SliceOptions::default()
        };
        assert!(slice_band(ev, &s, 0, &bad, &mut w, &mut [], &mut stats).is_err());
    })
    .unwrap();
}

/// Planes just above a nearly horizontal stretch of `catmark_righthanded`
/// at a fine eps: there two cells' roots on a shared side differed by
/// 1e-11 (rounding over a nearly tangent side) and chaining failed with
/// "slice contour did not close" (found by a 1000-layer stack at eps 1e-5
/// of the diagonal, layer 217). Now the contours close and stay within
/// eps of exact section samples.
#[test]
fn nearly_tangent_sides_still_chain() {
    let mut w = Box::new(QueryWork::ZERO);
    let root = ccss_tests::harness::workspace_root().join("tests/data/osd/catmark_righthanded.obj");
    let hand = ccss_tests::reference::PolyMesh::from_obj(&root);
    with_evaluator(&hand, standard_tables(), |_, ev| {
        let eps = 7.9e-6;
        for h in [-0.005645635, -0.00564565] {
            let plane = Plane::z(h);
            let (pts, cs) = layer(ev, &plane, eps, &mut w);
            assert!(!cs.is_empty());
            let es = edges(&pts, &cs);
            let mut worst = 0.0f64;
            for p in samples(ev, DVec3::Z, h, 24) {
                let q = [p.x, p.y];
                let d = es
                    .iter()
                    .map(|&(a, b)| seg_dist(q, a, b))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d <= eps,
                    "z {h}: exact point {q:?} {d:e} from the polylines"
                );
                worst = worst.max(d / eps);
            }
            let total: f64 = cs.iter().map(|c| signed_area(&pts, c)).sum();
            assert!(total > 0.0);
            println!(
                "z {h}: {} contours, {} points, worst exact->polyline {worst:.3} eps",
                cs.len(),
                pts.len()
            );
        }
    })
    .unwrap();
}

/// At a coarse eps (5 % of the diagonal) every layer of a righthanded
/// stack chains into closed contours within eps of the exact section:
/// corner balls made small by their control-point hull at the first
/// levels are not nodes (such a ball can hold several arcs; with them as
/// nodes layer 9 of this stack failed to close).
#[test]
fn coarse_eps_stacks_close() {
    let mut w = Box::new(QueryWork::ZERO);
    let root = ccss_tests::harness::workspace_root().join("tests/data/osd/catmark_righthanded.obj");
    let hand = ccss_tests::reference::PolyMesh::from_obj(&root);
    with_evaluator(&hand, standard_tables(), |_, ev| {
        let gs = grids(ev, 8);
        let (lo, hi) = gs
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), g| {
                (l.min(g.lo), h.max(g.hi))
            });
        let eps = 0.05 * diagonal(&gs);
        let n = 40;
        let dz = (hi.z - lo.z) / n as f64;
        let stack = PlaneStack::z(lo.z + 0.5 * dz, dz);
        let (mut contours, mut worst) = (0, 0.0f64);
        for (k, (st, pts, cs)) in band(ev, &stack, 0, n, eps, &mut w).into_iter().enumerate() {
            assert_eq!(st.unresolved, 0);
            contours += cs.len();
            let h = stack.layer(k).offset;
            let es = edges(&pts, &cs);
            for p in samples(ev, DVec3::Z, h, 8) {
                let d = es
                    .iter()
                    .map(|&(a, b)| seg_dist([p.x, p.y], a, b))
                    .fold(f64::INFINITY, f64::min);
                assert!(d <= eps, "layer {k}: exact point {d:e} from the polylines");
                worst = worst.max(d / eps);
            }
        }
        println!("{contours} contours, worst exact->polyline {worst:.3} eps");
        assert!(contours >= n / 2);
    })
    .unwrap();
}
