//! Certified queries on meshes with features (creases, corners,
//! semi-sharp edges, boundaries, holes) through the `FeatureEvaluator`,
//! against an independent oracle: per slot a grid of exact limit points of
//! the reference subdivider (`tests/src/sharp.rs`, OpenSubdiv's rules with
//! exact limit masks at dyadic parameters), triangulated and ray-cast;
//! every triangle hit is refined by Newton's method on exact evaluation
//! (kept only when it converges to `|S - ray| < 1e-12 diag` inside the
//! slot). On closed and open corpus shapes, at tolerances 1e-9 and 1e-6 of
//! the diagonal:
//!
//! * rays: zero missed crossings (every oracle crossing has a hit within
//!   `tol`), every hit the exact limit point at its parameters and within
//!   `tol` of the ray, rays aimed at slot corners (corners, crease and
//!   boundary vertices) and at edge midpoints (creases) included;
//! * closest points: never farther than the reference grid's nearest
//!   point plus `tol`, nor than Gauss-Newton minima near it plus `tol`;
//! * closed shapes: inside/outside agrees with the oracle's parity and the
//!   slices are closed, within `eps` of exact section samples (Hausdorff);
//! * open shapes: inside/outside and slices are `NotClosedSolid`.

use ccss_core::query::{
    closest, inside, ray_all, slice_layer, slice_segment_count, slice_write, ClosestOptions,
    Contour, Hit, HitKind, Plane, QueryWork, Ray, RayOptions, SliceOptions, SliceSegment,
};
use ccss_core::{DVec3, Error, FeatureEvaluator};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, workspace_root, XorShift};
use ccss_tests::sharp::{SharpRefiner, TaggedMesh};

/// Shapes: (name, closed solid?).
const SHAPES: [(&str, bool); 7] = [
    ("catmark_cube_creases1", true),
    ("catmark_cube_corner3", true),
    ("catmark_torus_creases0", true),
    ("catmark_pyramid_creases1", true),
    ("catmark_edgecorner", false),
    ("catmark_hole_test1", false),
    ("catmark_tent_creases0", false),
];

/// One slot's reference grid: `(n + 1)^2` points, row-major in u.
struct SlotGrid {
    face: u32,
    sub: u32,
    n: usize,
    pts: Vec<DVec3>,
    lo: DVec3,
    hi: DVec3,
}

/// Reference limit points at the dyadic grid of level `k` of every slot
/// that is not a hole.
fn grids(m: &TaggedMesh, fe: &FeatureEvaluator, k: u32) -> Vec<SlotGrid> {
    let mut r = SharpRefiner::new(m).unwrap();
    let n = 1usize << k;
    let mut out = vec![];
    for f in 0..fe.num_faces() {
        if m.holes.contains(&(f as u32)) {
            continue;
        }
        for s in 0..fe.num_subfaces(f) {
            let mut pts = Vec::with_capacity((n + 1) * (n + 1));
            for a in 0..=n {
                for b in 0..=n {
                    let p = r.dyadic_limit_point(f, s, a as u32, b as u32, k);
                    pts.push(DVec3::from_array(p));
                }
            }
            let lo = pts.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
            let hi = pts.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
            let mg = DVec3::splat(0.1 * (hi - lo).length());
            out.push(SlotGrid {
                face: f as u32,
                sub: s as u32,
                n,
                pts,
                lo: lo - mg,
                hi: hi + mg,
            });
        }
    }
    out
}

fn ray_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        if d[a].abs() < 1e-300 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return false;
            }
            continue;
        }
        let (x, y) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        t0 = t0.max(x.min(y));
        t1 = t1.min(x.max(y));
    }
    t0 <= t1
}

/// Moller-Trumbore with a small barycentric slack: `(t, b1, b2)`.
fn ray_tri(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if u < -1e-6 || v < -1e-6 || u + v > 1.0 + 1e-6 {
        return None;
    }
    Some((e2.dot(q) * inv, u, v))
}

/// Newton on `S(u, v) - o - t d = 0` in slot `(f, s)`: the crossing's
/// `(t, u, v)` when it converges inside the slot.
#[allow(clippy::too_many_arguments)]
fn newton(
    fe: &FeatureEvaluator,
    f: u32,
    s: u32,
    o: DVec3,
    d: DVec3,
    mut u: f64,
    mut v: f64,
    mut t: f64,
    scale: f64,
) -> Option<(f64, f64, f64)> {
    for _ in 0..40 {
        let e = fe.eval(f, s, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)).ok()?;
        let g = e.p - o - t * d;
        let inside = |x: f64| (-1e-7..=1.0 + 1e-7).contains(&x);
        if g.length() < 1e-12 * scale && inside(u) && inside(v) {
            return Some((t, u, v));
        }
        let (c0, c1, c2) = (e.du, e.dv, -d);
        let det = c0.dot(c1.cross(c2));
        if det.abs() < 1e-300 {
            return None;
        }
        u += -g.dot(c1.cross(c2)) / det;
        v += -c0.dot(g.cross(c2)) / det;
        t += -c0.dot(c1.cross(g)) / det;
        if !(-0.05..=1.05).contains(&u) || !(-0.05..=1.05).contains(&v) {
            return None;
        }
    }
    None
}

/// The oracle's crossings (ray parameters) with `t >= 0`.
fn crossings(fe: &FeatureEvaluator, gs: &[SlotGrid], o: DVec3, d: DVec3, diag: f64) -> Vec<f64> {
    let mut out: Vec<f64> = vec![];
    for g in gs.iter().filter(|g| ray_box(o, d, g.lo, g.hi)) {
        let n = g.n;
        let p = |a: usize, b: usize| g.pts[a * (n + 1) + b];
        for a in 0..n {
            for b in 0..n {
                let (p00, p10, p11, p01) = (p(a, b), p(a + 1, b), p(a + 1, b + 1), p(a, b + 1));
                for (tri, map) in [
                    ([p00, p10, p11], [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]),
                    ([p00, p11, p01], [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0)]),
                ] {
                    let Some((t, b1, b2)) = ray_tri(o, d, tri[0], tri[1], tri[2]) else {
                        continue;
                    };
                    let w0 = 1.0 - b1 - b2;
                    let cu = w0 * map[0].0 + b1 * map[1].0 + b2 * map[2].0;
                    let cv = w0 * map[0].1 + b1 * map[1].1 + b2 * map[2].1;
                    let (u, v) = ((a as f64 + cu) / n as f64, (b as f64 + cv) / n as f64);
                    if let Some((t, _, _)) = newton(fe, g.face, g.sub, o, d, u, v, t, diag) {
                        if t >= 0.0
                            && !out
                                .iter()
                                .any(|x| ((x - t) * d.length()).abs() < 1e-10 * diag)
                        {
                            out.push(t);
                        }
                    }
                }
            }
        }
    }
    out.sort_by(|a, b| a.total_cmp(b));
    out
}

fn bbox(gs: &[SlotGrid]) -> (DVec3, DVec3) {
    let pts = gs.iter().flat_map(|g| g.pts.iter());
    let lo = pts.clone().fold(DVec3::INFINITY, |a, &p| a.min(p));
    let hi = pts.fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
    (lo, hi)
}

fn load(name: &str) -> TaggedMesh {
    let path = workspace_root().join(format!("tests/data/osd/{name}.obj"));
    TaggedMesh::from_obj(&path).unwrap()
}

#[test]
fn feature_rays_miss_no_crossing() {
    let mut work = Box::new(QueryWork::ZERO);
    let (mut rays_n, mut oracle_n, mut hits_n, mut tangent_n) = (0usize, 0usize, 0usize, 0usize);
    let mut worst = 0.0f64;
    for (name, closed) in SHAPES {
        let m = load(name);
        with_feature_mesh(&flat(&m), Some(standard_tables()), |fe| {
            let gs = grids(&m, fe, 4);
            let (lo, hi) = bbox(&gs);
            let (diag, c) = ((hi - lo).length(), 0.5 * (lo + hi));
            let mut rng = XorShift(0x5eed_0000 ^ name.len() as u64);
            let rnd = |rng: &mut XorShift| DVec3::new(rng.signed(), rng.signed(), rng.signed());
            let mut rays = vec![];
            for _ in 0..200 {
                let o = c + rnd(&mut rng).normalize() * diag;
                let target = c + rnd(&mut rng) * 0.5 * diag;
                rays.push(Ray { origin: o, dir: target - o });
            }
            // Through slot corners (corners, crease ends, boundary
            // vertices) and edge midpoints (creases, boundaries).
            for g in &gs {
                for (a, b) in [(0, 0), (g.n / 2, 0), (g.n / 2, g.n / 2)] {
                    if rays.len() < 420 {
                        let p = g.pts[a * (g.n + 1) + b];
                        let o = c + rnd(&mut rng).normalize() * diag;
                        rays.push(Ray { origin: o, dir: p - o });
                    }
                }
            }
            for (ri, ray) in rays.iter().enumerate() {
                let tol = if ri % 2 == 0 { 1e-9 * diag } else { 1e-6 * diag };
                let opts = RayOptions {
        tol,
        t_min: 0.0,
        ..Default::default()
    };
                let oracle = crossings(fe, &gs, ray.origin, ray.dir, diag);
                let need = match ray_all(fe, ray, &opts, &mut work, &mut []) {
                    Ok(0) => 0,
                    Err(Error::BufferTooSmall { required }) => required,
                    e => panic!("{name} ray {ri}: {e:?}"),
                };
                let mut hits = vec![Hit::ZERO; need];
                assert_eq!(ray_all(fe, ray, &opts, &mut work, &mut hits).unwrap(), need);
                let dl = ray.dir.length();
                for h in &hits {
                    let e = fe.eval(h.face, h.sub, h.u, h.v).unwrap();
                    assert!((e.p - h.point).length() <= 1e-12 * diag, "{name}: hit point");
                    let r = h.point - ray.origin;
                    let along = r.dot(ray.dir) / dl;
                    let off = (r - along * ray.dir / dl).length();
                    assert!(off <= tol, "{name} ray {ri}: hit {off:e} off the ray (tol {tol:e})");
                    tangent_n += (h.kind == HitKind::Tangent) as usize;
                }
                for &t in &oracle {
                    let best = hits.iter().map(|h| (h.t - t).abs() * dl).fold(f64::INFINITY, f64::min);
                    assert!(best <= tol, "{name} ray {ri}: missed crossing t {t}; nearest {best:e}, tol {tol:e}; hits {hits:?}");
                    worst = worst.max(best / tol);
                }
                rays_n += 1;
                oracle_n += oracle.len();
                hits_n += hits.len();
            }
            // Inside/outside: parity on closed shapes, refused on open ones.
            for _ in 0..20 {
                let p = c + rnd(&mut rng) * 0.4 * diag;
                let r = inside(fe, p, 1e-9 * diag, &mut work);
                if !closed {
                    assert!(matches!(r, Err(Error::NotClosedSolid(_))), "{name}: {r:?}");
                    continue;
                }
                let par = |d: DVec3| crossings(fe, &gs, p, d, diag).len() % 2 == 1;
                let (a, b) = (par(DVec3::new(0.3, 0.5, 0.8)), par(DVec3::new(-0.7, 0.2, -0.4)));
                if a == b {
                    assert_eq!(r.unwrap(), a, "{name}: inside {p}");
                }
            }
        })
        .unwrap();
    }
    println!(
        "{rays_n} rays, {oracle_n} oracle crossings, {hits_n} hits ({tangent_n} tangent); worst |t - t*| / tol = {worst:.3e}"
    );
    assert!(rays_n >= 1500 && oracle_n >= 1000);
}

/// Gauss-Newton from `(u, v)`: a local minimum of `|S - q|` nearby.
fn polish(fe: &FeatureEvaluator, f: u32, s: u32, q: DVec3, mut u: f64, mut v: f64) -> f64 {
    let mut e = fe.eval(f, s, u, v).unwrap();
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
        let ne = fe.eval(f, s, nu, nv).unwrap();
        if (ne.p - q).length() >= (e.p - q).length() {
            break;
        }
        (u, v, e) = (nu, nv, ne);
    }
    (e.p - q).length()
}

#[test]
fn feature_closest_is_global_within_tol() {
    let mut work = Box::new(QueryWork::ZERO);
    let (mut n, mut worst_gap) = (0usize, 0.0f64);
    for (name, _) in SHAPES {
        let m = load(name);
        with_feature_mesh(&flat(&m), Some(standard_tables()), |fe| {
            let gs = grids(&m, fe, 4);
            let (lo, hi) = bbox(&gs);
            let (diag, c) = ((hi - lo).length(), 0.5 * (lo + hi));
            let mut rng = XorShift(0xc105_e570 ^ name.len() as u64);
            for qi in 0..40 {
                let q = c + DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.7 * diag;
                let tol = if qi % 2 == 0 {
                    1e-9 * diag
                } else {
                    1e-6 * diag
                };
                let r = closest(
                    fe,
                    q,
                    &ClosestOptions {
                        tol,
                        ..Default::default()
                    },
                    &mut work,
                )
                .unwrap();
                let e = fe.eval(r.face, r.sub, r.u, r.v).unwrap();
                assert!((e.p - r.point).length() <= 1e-12 * diag);
                assert!(((r.point - q).length() - r.dist).abs() <= 1e-12 * diag);
                assert!(r.gap <= tol, "{name}: gap {} tol {tol}", r.gap);
                // Reference samples and local minima near the best ones.
                let mut best: Vec<(f64, u32, u32, f64, f64)> = vec![];
                for g in &gs {
                    for a in 0..=g.n {
                        for b in 0..=g.n {
                            let d = (g.pts[a * (g.n + 1) + b] - q).length();
                            best.push((
                                d,
                                g.face,
                                g.sub,
                                a as f64 / g.n as f64,
                                b as f64 / g.n as f64,
                            ));
                        }
                    }
                }
                best.sort_by(|a, b| a.0.total_cmp(&b.0));
                let sampled = best[0].0;
                let refined = best[..12]
                    .iter()
                    .map(|&(_, f, s, u, v)| polish(fe, f, s, q, u, v))
                    .fold(sampled, f64::min);
                assert!(
                    r.dist <= sampled + tol,
                    "{name}: {} vs sampled {sampled}",
                    r.dist
                );
                assert!(
                    r.dist <= refined + tol,
                    "{name}: {} vs refined {refined} (tol {tol:e})",
                    r.dist
                );
                worst_gap = worst_gap.max((r.dist - refined) / tol);
                n += 1;
            }
        })
        .unwrap();
    }
    println!("{n} closest points; worst (dist - refined oracle) / tol = {worst_gap:.3e}");
    assert!(n >= 200);
}

/// Exact section samples of `n . S = h` on `m` parameter lines per
/// direction of every slot (bisected sign changes of exact evaluations).
fn section_samples(
    fe: &FeatureEvaluator,
    gs: &[SlotGrid],
    n: DVec3,
    h: f64,
    m: usize,
) -> Vec<DVec3> {
    let mut out = vec![];
    let g = |f: u32, s: u32, u: f64, v: f64| n.dot(fe.eval(f, s, u, v).unwrap().p) - h;
    for sg in gs {
        let (f, s) = (sg.face, sg.sub);
        for dir in 0..2 {
            for i in 0..=m {
                let a = i as f64 / m as f64;
                let at = |x: f64| if dir == 0 { (a, x) } else { (x, a) };
                let k = 64;
                for j in 0..k {
                    let (x0, x1) = (j as f64 / k as f64, (j + 1) as f64 / k as f64);
                    let (u0, v0) = at(x0);
                    let (u1, v1) = at(x1);
                    let (g0, g1) = (g(f, s, u0, v0), g(f, s, u1, v1));
                    if (g0 < 0.0) == (g1 < 0.0) {
                        continue;
                    }
                    let (mut lo, mut hi) = (x0, x1);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        let (u, v) = at(mid);
                        if (g(f, s, u, v) < 0.0) == (g0 < 0.0) {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    let (u, v) = at(0.5 * (lo + hi));
                    out.push(fe.eval(f, s, u, v).unwrap().p);
                }
            }
        }
    }
    out
}

fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let w = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p[0] - a[0] - w * dx).powi(2) + (p[1] - a[1] - w * dy).powi(2)).sqrt()
}

#[test]
fn feature_slices_within_eps() {
    let mut work = Box::new(QueryWork::ZERO);
    let (mut layers, mut worst) = (0usize, 0.0f64);
    for (name, closed) in SHAPES {
        let m = load(name);
        with_feature_mesh(&flat(&m), Some(standard_tables()), |fe| {
            let gs = grids(&m, fe, 2);
            let (lo, hi) = bbox(&gs);
            let diag = (hi - lo).length();
            for (li, frac) in [0.23, 0.5, 0.71].into_iter().enumerate() {
                let nrm = [DVec3::Z, DVec3::new(0.3, -0.2, 1.0).normalize()][li % 2];
                let h = nrm.dot(lo + (hi - lo) * frac);
                let plane = Plane {
                    normal: nrm,
                    offset: h,
                };
                let eps = [1e-3, 1e-4][li % 2] * diag;
                let o = SliceOptions {
                    eps,
                    ..Default::default()
                };
                let r = slice_segment_count(fe, &plane, &o, &mut work);
                if !closed {
                    assert!(matches!(r, Err(Error::NotClosedSolid(_))), "{name}: {r:?}");
                    continue;
                }
                let ns = r.unwrap();
                let mut segs = vec![SliceSegment::default(); ns];
                let st = slice_layer(fe, &plane, &o, &mut work, &mut segs).unwrap();
                assert_eq!(st.unresolved, 0, "{name}");
                let mut pts = vec![[0.0; 2]; st.points];
                let mut cs = vec![Contour::default(); st.contours];
                slice_write(&mut segs, &mut pts, &mut cs).unwrap();
                let (_, e1, e2) = plane.frame().unwrap();
                let samples = section_samples(fe, &gs, nrm, h, 24);
                assert!(!samples.is_empty(), "{name}: empty section");
                let edges: Vec<([f64; 2], [f64; 2])> = cs
                    .iter()
                    .flat_map(|c| {
                        let (s, l) = (c.start as usize, c.len as usize);
                        (0..l).map(move |k| (s + k, s + (k + 1) % l))
                    })
                    .map(|(a, b)| (pts[a], pts[b]))
                    .collect();
                // Samples to polylines.
                for q in &samples {
                    let q2 = [q.dot(e1), q.dot(e2)];
                    let d = edges
                        .iter()
                        .map(|(a, b)| seg_dist(q2, *a, *b))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        d <= eps,
                        "{name} layer {li}: sample {d:e} from the polylines (eps {eps:e})"
                    );
                    worst = worst.max(d / eps);
                }
                // Polylines to samples: vertices and edge midpoints within
                // eps plus the sampling's spacing (a slot's size over the
                // number of sample lines).
                let spacing = gs
                    .iter()
                    .map(|g| (g.hi - g.lo).length() / 1.2)
                    .fold(0.0, f64::max)
                    / 24.0;
                let s2: Vec<[f64; 2]> = samples.iter().map(|q| [q.dot(e1), q.dot(e2)]).collect();
                for (a, b) in &edges {
                    for p in [*a, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]] {
                        let d = s2
                            .iter()
                            .map(|q| seg_dist(p, *q, *q))
                            .fold(f64::INFINITY, f64::min);
                        assert!(
                            d <= eps + spacing,
                            "{name} layer {li}: polyline point {d:e} from the samples"
                        );
                    }
                }
                layers += 1;
            }
        })
        .unwrap();
    }
    println!("{layers} feature layers; worst sample-to-polyline distance / eps = {worst:.3e}");
    assert!(layers >= 10);
}
