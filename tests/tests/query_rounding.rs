//! Certified queries under translation and scale (issue 27): the stated
//! tolerances hold for the computed outputs, rounding included, or the
//! call refuses with `CoordinateRange`.
//!
//! The same solid (the cube's limit surface, extraordinary vertices of
//! valence 3) is shifted by `1e0..1e12` and scaled by `1e-200..1e200`;
//! rays (all hits), closest points and a slice are computed on the moved
//! solid and compared, after undoing the move, with the same queries on
//! the unmoved one. Every difference must be within the sum of the two
//! stated tolerances plus the rounding of the move itself (each control
//! point moves by at most half an ulp of its coordinates, and the limit
//! surface, an affine combination of them, by at most `sqrt(3)` times that).
//! The worst difference / bound ratio per move is printed (`--nocapture`).
//!
//! * `queries_under_translation`: tolerance `1e-6`, shifts `1e0..1e12`;
//! * `queries_under_scale`: tolerance `1e-6 s`, scales `1e-200..1e200`
//!   (outside `2^-200..2^200` refused);
//! * `query_budgets`: every query stops with `WorkLimitExceeded` at its
//!   budget, promptly, and succeeds with the default one; a ray lying in a
//!   planar part of a surface (the adversarial case) is stopped.

use ccss_core::query::{
    closest, inside, ray_all, slice_layer, slice_segment_count, slice_write, ClosestOptions,
    Contour, Plane, QuerySurface, QueryWork, Ray, RayOptions, SliceOptions, SliceSegment,
};
use ccss_core::{DVec3, Error, Evaluator};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::PolyMesh;
use ccss_tests::sharp::TaggedMesh;
use std::time::Instant;

fn cube(scale: f64, shift: [f64; 3]) -> PolyMesh {
    let mut positions = Vec::new();
    for k in 0..8 {
        let c = [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64];
        positions.push([
            (c[0] - 0.5) * scale + shift[0],
            (c[1] - 0.5) * scale + shift[1],
            (c[2] - 0.5) * scale + shift[2],
        ]);
    }
    let faces = vec![
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
    ];
    PolyMesh { positions, faces }
}

fn pow10(k: i32) -> f64 {
    format!("1e{k}").parse().unwrap()
}

/// Rays (origin, direction) around the unit cube's limit surface (inside
/// radius ~0.3): from a sphere of radius 2 towards points near the centre.
fn rays() -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::new();
    for i in 0..24 {
        let a = 2.399_963 * i as f64;
        let z = 1.0 - (2 * i + 1) as f64 / 24.0;
        let r = (1.0 - z * z).sqrt();
        let o = 2.0 * DVec3::new(r * a.cos(), r * a.sin(), z);
        let target = DVec3::new(0.05 * a.sin(), -0.07 * a.cos(), 0.03 * z);
        out.push((o, target - o));
    }
    out
}

/// Query points for the closest-point comparison (outside and inside).
fn points() -> Vec<DVec3> {
    (0..16)
        .map(|i| {
            let a = 1.7 * i as f64;
            let r = if i % 2 == 0 { 0.9 } else { 0.12 };
            DVec3::new(r * a.cos(), r * (1.3 * a).sin(), 0.4 * (0.7 * a).cos())
        })
        .collect()
}

/// Distance, gap and `(face, sub, u, v)` of a closest point.
type ClosestRow = (f64, f64, u32, u32, f64, f64);

/// The outputs of every query on one solid; each kind `Err` at its first
/// refusal.
struct Outputs {
    /// Per ray: the hits' `t` and points.
    hits: Result<Vec<Vec<(f64, DVec3)>>, Error>,
    /// Per point: distance, gap, `(face, sub, u, v)`.
    closest: Result<Vec<ClosestRow>, Error>,
    /// Slice at `z = 0.1` (unmoved units): contours as point lists.
    slice: Result<Vec<Vec<[f64; 2]>>, Error>,
    /// Inside/outside of the query points.
    inside: Result<Vec<bool>, Error>,
}

/// Runs the queries on the solid moved by `x -> s x + shift`, tolerances
/// `tol` (rays, closest, inside) and `eps` (slice) in moved units.
fn run<S: QuerySurface + ?Sized>(ev: &S, s: f64, shift: DVec3, tol: f64, eps: f64) -> Outputs {
    let mut w = Box::new(QueryWork::ZERO);
    let ropts = RayOptions {
        tol,
        ..Default::default()
    };
    let hits = rays()
        .into_iter()
        .map(|(o, d)| {
            let ray = Ray {
                origin: s * o + shift,
                dir: s * d,
            };
            let mut out = vec![ccss_core::query::Hit::ZERO; 16];
            let n = ray_all(ev, &ray, &ropts, &mut w, &mut out)?;
            Ok(out[..n].iter().map(|h| (h.t, h.point)).collect())
        })
        .collect();
    let copts = ClosestOptions {
        tol,
        ..Default::default()
    };
    let cl = points()
        .into_iter()
        .map(|q| {
            let c = closest(ev, s * q + shift, &copts, &mut w)?;
            Ok((c.dist, c.gap, c.face, c.sub, c.u, c.v))
        })
        .collect();
    let ins = points()
        .into_iter()
        .map(|q| inside(ev, s * q + shift, tol, &mut w))
        .collect();
    let plane = Plane::z(s * 0.1 + shift.z);
    let so = SliceOptions {
        eps,
        ..Default::default()
    };
    let slice = (|| {
        let ns = slice_segment_count(ev, &plane, &so, &mut w)?;
        let mut segs = vec![SliceSegment::default(); ns];
        let st = slice_layer(ev, &plane, &so, &mut w, &mut segs)?;
        let mut pts = vec![[0.0; 2]; st.points];
        let mut cs = vec![Contour::default(); st.contours];
        slice_write(&mut segs[..st.segments], &mut pts, &mut cs)?;
        Ok(cs
            .iter()
            .map(|c| pts[c.start as usize..(c.start + c.len) as usize].to_vec())
            .collect())
    })();
    Outputs {
        hits,
        closest: cl,
        slice,
        inside: ins,
    }
}

/// Distance from `p` to the closed polylines `cs`.
fn to_polylines(p: [f64; 2], cs: &[Vec<[f64; 2]>]) -> f64 {
    let mut best = f64::INFINITY;
    for c in cs {
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let l2 = ab[0] * ab[0] + ab[1] * ab[1];
            let w = if l2 > 0.0 {
                (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (dx, dy) = (p[0] - a[0] - w * ab[0], p[1] - a[1] - w * ab[1]);
            best = best.min((dx * dx + dy * dy).sqrt());
        }
    }
    best
}

/// One query kind's result against the unmoved one: the worst difference
/// / bound ratio, or the refusal (which must be `CoordinateRange`).
type Verdict = Result<f64, String>;

fn refusal(e: &Error) -> Verdict {
    assert!(matches!(e, Error::CoordinateRange(_)), "{e:?}");
    Err(e.to_string())
}

/// Compares the moved outputs with the unmoved ones (the unmoved ones must
/// all be accepted): rays, closest, slice, inside. Panics on a violation.
#[allow(clippy::too_many_arguments)]
fn compare(
    label: &str,
    eval0: &dyn Fn(u32, u32, f64, f64) -> DVec3,
    o0: &Outputs,
    (tol0, eps0): (f64, f64),
    o: &Outputs,
    s: f64,
    shift: DVec3,
    (tol, eps): (f64, f64),
) -> [Verdict; 4] {
    let moved = move_rounding(s, shift);
    // Undo the move: x -> (x - shift) / s; bounds in unmoved units.
    let back = |p: DVec3| (p - shift) / s;
    let (tu, eu, mu) = (tol / s, eps / s, moved / s);
    let rays_v = match (&o.hits, &o0.hits) {
        (Err(e), _) => refusal(e),
        (Ok(hs), Ok(hs0)) => {
            let mut worst = 0.0f64;
            for (i, (h, h0)) in hs.iter().zip(hs0).enumerate() {
                assert_eq!(h.len(), h0.len(), "{label}: ray {i} hit count");
                let (_, d) = rays()[i];
                for ((t, p), (t0, p0)) in h.iter().zip(h0) {
                    // `t` is in units of `s d`: the same parameter as `t0`.
                    let dt = (t - t0).abs() * d.length();
                    let b = tu + tol0 + mu;
                    assert!(dt <= b, "{label}: ray {i} |dt| {dt:e} > {b:e}");
                    let dp = (back(*p) - *p0).length();
                    assert!(dp <= 2.0 * b, "{label}: ray {i} point {dp:e}");
                    worst = worst.max(dt / b);
                }
            }
            Ok(worst)
        }
        (_, Err(e)) => panic!("unmoved rays: {e:?}"),
    };
    let closest_v = match (&o.closest, &o0.closest) {
        (Err(e), _) => refusal(e),
        (Ok(cs), Ok(cs0)) => {
            let mut worst = 0.0f64;
            for (k, (c, c0)) in cs.iter().zip(cs0).enumerate() {
                let (dist, gap) = (c.0 / s, c.1 / s);
                assert!(c.1 <= tol * (1.0 + 1e-12), "{label}: gap {} > tol", c.1);
                let b = gap + c0.1 + mu;
                let dd = (dist - c0.0).abs();
                assert!(dd <= b, "{label}: closest {k} |d dist| {dd:e} > {b:e}");
                // The moved run's parameters, evaluated on the unmoved
                // solid, are within the gaps of the minimum.
                let d_at = (eval0(c.2, c.3, c.4, c.5) - points()[k]).length();
                assert!(d_at <= c0.0 + b, "{label}: closest {k} point {d_at:e}");
                worst = worst.max(dd / b);
            }
            Ok(worst)
        }
        (_, Err(e)) => panic!("unmoved closest: {e:?}"),
    };
    let slice_v = match (&o.slice, &o0.slice) {
        (Err(e), _) => refusal(e),
        (Ok(sl), Ok(sl0)) => {
            let moved2: Vec<Vec<[f64; 2]>> = sl
                .iter()
                .map(|c| {
                    c.iter()
                        .map(|p| [(p[0] - shift.x) / s, (p[1] - shift.y) / s])
                        .collect()
                })
                .collect();
            let b = eu + eps0 + mu;
            let mut worst = 0.0f64;
            for (a, bset) in [(&moved2, sl0), (sl0, &moved2)] {
                for c in a.iter() {
                    for p in c {
                        let d = to_polylines(*p, bset);
                        assert!(d <= b, "{label}: slice point {d:e} > {b:e}");
                        worst = worst.max(d / b);
                    }
                }
            }
            Ok(worst)
        }
        (_, Err(e)) => panic!("unmoved slice: {e:?}"),
    };
    let inside_v = match (&o.inside, &o0.inside) {
        (Err(e), _) => refusal(e),
        (Ok(i), Ok(i0)) => {
            assert_eq!(i, i0, "{label}: inside");
            Ok(0.0)
        }
        (_, Err(e)) => panic!("unmoved inside: {e:?}"),
    };
    [rays_v, closest_v, slice_v, inside_v]
}

/// Half an ulp of the largest moved coordinate, times `sqrt(3)` (the move's
/// own rounding, in moved units), doubled for the query data.
fn move_rounding(s: f64, shift: DVec3) -> f64 {
    let m = (0.5 * s).abs() + shift.abs().max_element() + 2.0 * s.abs();
    2.0 * 3f64.sqrt() * f64::EPSILON * m
}

/// The unmoved smooth evaluator as a point function.
fn ev_fn<'a>(ev: &'a Evaluator<'a>) -> impl Fn(u32, u32, f64, f64) -> DVec3 + 'a {
    move |f, s, u, v| ev.eval(f, s, u, v).unwrap().p
}

/// Each query kind is accepted where its tolerance is certifiable and
/// refused where it is not: the term is `4096 eps M`, `M` = the shift plus
/// the model and query data (a factor 2 of slack on this estimate of `M`
/// either way); rays, closest and slice need `tol >= 4 r`, inside `64 r`.
fn expect_refusals(label: &str, v: &[Verdict; 4], shift: f64, (tol, eps): (f64, f64)) {
    let r = 4096.0 * f64::EPSILON * (shift + 2.5 * tol / 1e-6);
    for (i, x) in v.iter().enumerate() {
        let limit = if i == 3 { 64.0 } else { 4.0 };
        let t = if i == 2 { eps } else { tol };
        if limit * r * 2.0 <= t {
            assert!(x.is_ok(), "{label}: kind {i} refused");
        }
        if limit * r * 0.5 > t {
            assert!(x.is_err(), "{label}: kind {i} accepted");
        }
    }
}

fn show(label: &str, v: &[Verdict; 4]) {
    let f = |x: &Verdict| match x {
        Ok(r) => format!("{r:.2e}"),
        Err(_) => "refused".to_string(),
    };
    println!(
        "{label}: worst difference / bound: rays {}, closest {}, slice {}, inside {}",
        f(&v[0]),
        f(&v[1]),
        f(&v[2]),
        if v[3].is_ok() { "same" } else { "refused" }
    );
    if let Some(Err(e)) = v.iter().find(|x| x.is_err()) {
        println!("  ({e})");
    }
}

#[test]
fn queries_under_translation() {
    let tols = (1e-6, 1e-3);
    let base = cube(1.0, [0.0; 3]);
    with_evaluator(&base, standard_tables(), |_, ev0| {
        let o0 = run(ev0, 1.0, DVec3::ZERO, tols.0, tols.1);
        assert!(o0.hits.as_ref().unwrap().iter().all(|h| h.len() == 2));
        assert!(!o0.slice.as_ref().unwrap().is_empty());
        for k in 0..=12 {
            let t = pow10(k);
            let shift = DVec3::new(t, -t, 0.5 * t);
            let m = cube(1.0, shift.to_array());
            let v = with_evaluator(&m, standard_tables(), |_, ev| {
                let o = run(ev, 1.0, shift, tols.0, tols.1);
                compare(
                    &format!("shift 1e{k}"),
                    &ev_fn(ev0),
                    &o0,
                    tols,
                    &o,
                    1.0,
                    shift,
                    tols,
                )
            })
            .unwrap();
            show(&format!("shift 1e{k}"), &v);
            expect_refusals(&format!("shift 1e{k}"), &v, t, tols);
        }
        // Coarser tolerances reach further: 1e-2 up to a shift ~2.7e9.
        let tols = (1e-2, 1e-2);
        let o0 = run(ev0, 1.0, DVec3::ZERO, tols.0, tols.1);
        for k in [6, 8] {
            let t = pow10(k);
            let shift = DVec3::new(t, -t, 0.5 * t);
            let m = cube(1.0, shift.to_array());
            with_evaluator(&m, standard_tables(), |_, ev| {
                let o = run(ev, 1.0, shift, tols.0, tols.1);
                let v = compare("", &ev_fn(ev0), &o0, tols, &o, 1.0, shift, tols);
                show(&format!("shift 1e{k}, tol 1e-2"), &v);
                assert!(v[..3].iter().all(|x| x.is_ok()));
            })
            .unwrap();
        }
    })
    .unwrap();
}

#[test]
fn queries_under_scale() {
    let tols = (1e-6, 1e-3);
    let base = cube(1.0, [0.0; 3]);
    with_evaluator(&base, standard_tables(), |_, ev0| {
        let o0 = run(ev0, 1.0, DVec3::ZERO, tols.0, tols.1);
        for k in [
            -200, -100, -61, -60, -59, -30, -10, 10, 30, 59, 60, 61, 100, 200,
        ] {
            let s = pow10(k);
            let m = cube(s, [0.0; 3]);
            let v = with_evaluator(&m, standard_tables(), |_, ev| {
                let o = run(ev, s, DVec3::ZERO, tols.0 * s, tols.1 * s);
                let st = (tols.0 * s, tols.1 * s);
                compare(
                    &format!("scale 1e{k}"),
                    &ev_fn(ev0),
                    &o0,
                    tols,
                    &o,
                    s,
                    DVec3::ZERO,
                    st,
                )
            })
            .unwrap();
            show(&format!("scale 1e{k}"), &v);
            // Certified range 2^-200..2^200 (6.2e-61..1.6e60); the cube's
            // control points are at 0.5 s, the rays' origins at 2 s (1e+-60
            // may go either way).
            for x in &v {
                if (-59..=59).contains(&k) {
                    assert!(x.is_ok(), "scale 1e{k}: {x:?}");
                } else if !(-60..=60).contains(&k) {
                    assert!(x.is_err(), "scale 1e{k}: {x:?}");
                }
            }
        }
        // A tolerance the coordinates cannot certify: refused, not a wrong
        // answer (unit cube, tolerance below 4 x 4096 eps).
        let mut w = Box::new(QueryWork::ZERO);
        let r = closest(
            ev0,
            DVec3::new(1.0, 0.0, 0.0),
            &ClosestOptions {
                tol: 1e-13,
                ..Default::default()
            },
            &mut w,
        );
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
        // A query point far out: its rounding counts too.
        let r = closest(
            ev0,
            DVec3::new(1e12, 0.0, 0.0),
            &ClosestOptions {
                tol: 1e-6,
                ..Default::default()
            },
            &mut w,
        );
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
    })
    .unwrap();
}

/// A slab `[-2, 2] x [-2, 2] x [0, 1]` cut into 4 x 4 x 1 cells: the limit
/// surface's top is exactly the plane `z = 1`... away from the border
/// (its inner B-spline patches have coplanar control points).
fn slab() -> PolyMesh {
    let n = 4usize;
    let mut positions = Vec::new();
    for z in 0..2 {
        for j in 0..=n {
            for i in 0..=n {
                positions.push([i as f64 - 2.0, j as f64 - 2.0, z as f64]);
            }
        }
    }
    let id = |i: usize, j: usize, z: usize| (z * (n + 1) * (n + 1) + j * (n + 1) + i) as u32;
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            faces.push(vec![
                id(i, j, 0),
                id(i, j + 1, 0),
                id(i + 1, j + 1, 0),
                id(i + 1, j, 0),
            ]);
            faces.push(vec![
                id(i, j, 1),
                id(i + 1, j, 1),
                id(i + 1, j + 1, 1),
                id(i, j + 1, 1),
            ]);
        }
    }
    for k in 0..n {
        faces.push(vec![
            id(k, 0, 0),
            id(k + 1, 0, 0),
            id(k + 1, 0, 1),
            id(k, 0, 1),
        ]);
        faces.push(vec![
            id(k + 1, n, 0),
            id(k, n, 0),
            id(k, n, 1),
            id(k + 1, n, 1),
        ]);
        faces.push(vec![
            id(0, k + 1, 0),
            id(0, k, 0),
            id(0, k, 1),
            id(0, k + 1, 1),
        ]);
        faces.push(vec![
            id(n, k, 0),
            id(n, k + 1, 0),
            id(n, k + 1, 1),
            id(n, k, 1),
        ]);
    }
    PolyMesh { positions, faces }
}

#[test]
fn query_budgets() {
    let mut w = Box::new(QueryWork::ZERO);
    with_evaluator(&slab(), standard_tables(), |_, ev| {
        // The top is planar at z = 1 over the middle patches.
        let e = ev.eval(0, 0, 0.5, 0.5).unwrap();
        println!("slab sample {:?}", e.p);
        let ray = Ray {
            origin: DVec3::new(-0.7, 0.1, 1.0),
            dir: DVec3::new(1.0, 0.05, 0.0),
        };
        // Adversarial: the ray lies in the planar top. Default budget:
        // stopped (budget or the hit cap), promptly.
        let t0 = Instant::now();
        let mut out = vec![ccss_core::query::Hit::ZERO; 8];
        let r = ray_all(ev, &ray, &RayOptions::default(), &mut w, &mut out);
        let secs = t0.elapsed().as_secs_f64();
        println!("ray in a planar part, default budget: {r:?} in {secs:.2} s");
        assert!(r.is_err(), "{r:?}");
        assert!(secs < 120.0);
        // With a budget of 10^4 cells: WorkLimitExceeded naming it.
        for limit in [1_000u64, 10_000, 100_000] {
            let t0 = Instant::now();
            let r = ray_all(
                ev,
                &ray,
                &RayOptions {
                    max_cells: limit,
                    ..Default::default()
                },
                &mut w,
                &mut out,
            );
            println!(
                "ray in a planar part, budget {limit}: {r:?} in {:.3} s",
                t0.elapsed().as_secs_f64()
            );
            match r {
                Err(Error::WorkLimitExceeded { limit: l, .. }) => assert_eq!(l, limit),
                Err(Error::InvalidArgument(m)) => assert!(m.contains("MAX_HITS"), "{m}"),
                other => panic!("{other:?}"),
            }
        }
        // Closest point and slice: a small budget stops them, the default
        // does not.
        let q = DVec3::new(0.3, -0.2, 2.0);
        let c = closest(ev, q, &ClosestOptions::default(), &mut w).unwrap();
        assert!((c.dist - 1.0).abs() <= c.gap + 1e-12, "{c:?}");
        let r = closest(
            ev,
            q,
            &ClosestOptions {
                max_cells: 5,
                ..Default::default()
            },
            &mut w,
        );
        assert!(
            matches!(r, Err(Error::WorkLimitExceeded { limit: 5, .. })),
            "{r:?}"
        );
        let plane = Plane::z(0.5);
        let so = SliceOptions::default();
        assert!(slice_segment_count(ev, &plane, &so, &mut w).unwrap() > 0);
        let r = slice_segment_count(
            ev,
            &plane,
            &SliceOptions {
                max_cells: 20,
                ..so
            },
            &mut w,
        );
        assert!(
            matches!(r, Err(Error::WorkLimitExceeded { limit: 20, .. })),
            "{r:?}"
        );
        // Throughput: a slice far finer than needed (eps 1e-10 on a model
        // of size 4) stopped by a budget of 2^18 cells; the time per cell
        // bounds what the default 2^22 costs.
        let t0 = Instant::now();
        let r = slice_segment_count(
            ev,
            &plane,
            &SliceOptions {
                eps: 1e-10,
                max_cells: 1 << 18,
            },
            &mut w,
        );
        let secs = t0.elapsed().as_secs_f64();
        println!(
            "slice at eps 1e-10, budget 2^18 cells: {r:?} in {secs:.2} s ({:.2} us per cell)",
            secs * 1e6 / (1u64 << 18) as f64
        );
        assert!(
            matches!(r, Err(Error::WorkLimitExceeded { limit, .. }) if limit == 1 << 18),
            "{r:?}"
        );
        assert!(secs < 60.0);
    })
    .unwrap();
}

/// The cube with every edge infinitely sharp (feature path: planar faces,
/// hull cells at the corners).
fn creased_cube(scale: f64, shift: [f64; 3]) -> TaggedMesh {
    let m = cube(scale, shift);
    let mut text = String::new();
    for p in &m.positions {
        text += &format!("v {:e} {:e} {:e}\n", p[0], p[1], p[2]);
    }
    for f in &m.faces {
        text += &format!("f {} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
    }
    for f in &m.faces {
        for k in 0..4 {
            let (a, b) = (f[k], f[(k + 1) % 4]);
            if a < b {
                text += &format!("t crease 2/1/0 {a} {b} 10\n");
            }
        }
    }
    TaggedMesh::parse(&text).unwrap()
}

/// The same comparisons on a feature mesh (`FeatureEvaluator`): shifts
/// 1e0..1e6 and scales 1e-30..1e30 (powers of ten) and 2^-100, 2^100.
#[test]
fn feature_queries_under_translation_and_scale() {
    let tols = (1e-6, 1e-3);
    let f0 = flat(&creased_cube(1.0, [0.0; 3]));
    with_feature_mesh(&f0, Some(standard_tables()), |fe0| {
        let o0 = run(fe0, 1.0, DVec3::ZERO, tols.0, tols.1);
        assert!(o0.hits.as_ref().unwrap().iter().all(|h| h.len() == 2));
        let eval0 = |f, s, u, v| fe0.eval(f, s, u, v).unwrap().p;
        let mut cases: Vec<(String, f64, DVec3)> = Vec::new();
        for k in [0, 2, 4, 6] {
            let t = pow10(k);
            cases.push((
                format!("feature shift 1e{k}"),
                1.0,
                DVec3::new(t, -t, 0.5 * t),
            ));
        }
        for k in [-30, -10, 10, 30] {
            cases.push((format!("feature scale 1e{k}"), pow10(k), DVec3::ZERO));
        }
        for e in [-100, 100] {
            cases.push((format!("feature scale 2^{e}"), 2f64.powi(e), DVec3::ZERO));
        }
        for (label, s, shift) in cases {
            let f = flat(&creased_cube(s, shift.to_array()));
            let v = with_feature_mesh(&f, Some(standard_tables()), |fe| {
                let st = (tols.0 * s, tols.1 * s);
                let o = run(fe, s, shift, st.0, st.1);
                compare(&label, &eval0, &o0, tols, &o, s, shift, st)
            })
            .unwrap();
            show(&label, &v);
            expect_refusals(&label, &v, shift.x, (tols.0 * s, tols.1 * s));
        }
    })
    .unwrap();
}

/// Headroom of the default budget: the smallest power-of-two budget each
/// query on corpus shapes needs (tolerance `1e-9` of the diagonal, slices
/// `1e-4`), against `MAX_CELLS`.
#[test]
fn default_budget_headroom() {
    let dir = ccss_tests::harness::workspace_root().join("tests/data/osd");
    let mut worst = [0u64; 3];
    for name in [
        "catmark_cube",
        "catmark_torus",
        "catmark_pyramid",
        "catmark_toroidal_tet",
        "catmark_righthanded",
        "catmark_helmet",
        "catmark_rook",
    ] {
        let m = PolyMesh::from_obj(&dir.join(format!("{name}.obj")));
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &m.positions {
            lo = lo.min(DVec3::from_array(*p));
            hi = hi.max(DVec3::from_array(*p));
        }
        let (c, diag) = (0.5 * (lo + hi), (hi - lo).length());
        let r = with_evaluator(&m, standard_tables(), |_, ev| {
            let mut w = Box::new(QueryWork::ZERO);
            let need = |f: &mut dyn FnMut(u64) -> Result<(), Error>| -> u64 {
                for k in 4..=22 {
                    match f(1 << k) {
                        Err(Error::WorkLimitExceeded { .. }) => continue,
                        Ok(()) => return 1 << k,
                        Err(e) => panic!("{name}: {e}"),
                    }
                }
                panic!("{name}: default budget exceeded");
            };
            let mut out = [0u64; 3];
            for i in 0..12 {
                let a = 2.399_963 * i as f64;
                let z = 1.0 - (2 * i + 1) as f64 / 12.0;
                let s = (1.0 - z * z).sqrt();
                let dir = DVec3::new(s * a.cos(), s * a.sin(), z);
                let o = c + diag * dir;
                let n = need(&mut |b| {
                    let mut hits = [ccss_core::query::Hit::ZERO; 64];
                    let opts = RayOptions {
                        tol: 1e-9 * diag,
                        max_cells: b,
                        ..Default::default()
                    };
                    ray_all(
                        ev,
                        &Ray {
                            origin: o,
                            dir: c - o + 0.05 * diag * dir.cross(DVec3::Z),
                        },
                        &opts,
                        &mut w,
                        &mut hits,
                    )
                    .map(|_| ())
                });
                out[0] = out[0].max(n);
                let q = c + 0.3 * diag * dir;
                let n = need(&mut |b| {
                    let opts = ClosestOptions {
                        tol: 1e-9 * diag,
                        max_cells: b,
                    };
                    closest(ev, q, &opts, &mut w).map(|_| ())
                });
                out[1] = out[1].max(n);
            }
            for k in 1..4 {
                let plane = Plane::z(lo.z + (hi.z - lo.z) * k as f64 / 4.0 + 1e-3 * diag);
                let n = need(&mut |b| {
                    let so = SliceOptions {
                        eps: 1e-4 * diag,
                        max_cells: b,
                    };
                    slice_segment_count(ev, &plane, &so, &mut w).map(|_| ())
                });
                out[2] = out[2].max(n);
            }
            out
        });
        let Ok(out) = r else {
            println!("{name}: not a closed smooth mesh, skipped");
            continue;
        };
        println!(
            "{name}: budget needed (power of two): rays {}, closest {}, slice {}",
            out[0], out[1], out[2]
        );
        for k in 0..3 {
            worst[k] = worst[k].max(out[k]);
        }
    }
    println!(
        "worst: rays {}, closest {}, slice {}; default {}",
        worst[0],
        worst[1],
        worst[2],
        ccss_core::query::MAX_CELLS
    );
    assert!(worst.iter().all(|&w| w * 16 <= ccss_core::query::MAX_CELLS));
}
