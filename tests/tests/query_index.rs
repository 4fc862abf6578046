//! The slot index (`SlotIndex`, `Indexed`) against the walks over every
//! slot, which `query_ray`, `query_closest`, `query_slice` and
//! `query_feature` check against brute-force oracles:
//!
//! * every slot's box holds dense exact limit points of the slot (the
//!   soundness the skipping rests on), on smooth and feature meshes;
//! * all hits of a ray, inside/outside and slice contours are bit for bit
//!   those of the unindexed walk (the index keeps the slot order there);
//! * the first hit and the closest point, which the index visits nearest
//!   box first, agree within the tolerance (the same crossing / distance);
//! * size queries are exact, a short slice is `BufferTooSmall` with the
//!   length and nothing written, an index of another surface is refused.

mod query_util;

use ccss_core::query::{
    band_layer, closest, inside, ray_all, ray_first, slice_band, slice_write, ClosestOptions,
    Contour, Hit, IndexNode, Indexed, PlaneStack, QuerySurface, QueryWork, Ray, RayOptions,
    SliceOptions, SliceSegment, SliceStats, SlotIndex,
};
use ccss_core::{DVec3, Error, FeatureEvaluator};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, with_evaluator, workspace_root, XorShift};
use ccss_tests::sharp::TaggedMesh;
use query_util::{centre, diagonal, grids, meshes};

fn index_of<S: QuerySurface + ?Sized>(surf: &S) -> Vec<IndexNode> {
    let n = SlotIndex::required_len(surf);
    let mut nodes = vec![IndexNode::default(); n];
    SlotIndex::build(surf, &mut nodes).unwrap();
    nodes
}

/// Every slot's box holds a 33 x 33 grid of its exact limit points.
fn boxes_hold<S: QuerySurface + ?Sized>(
    name: &str,
    surf: &S,
    eval: impl Fn(u32, u32, f64, f64) -> DVec3,
) -> usize {
    let mut nodes = index_of(surf);
    let ix = SlotIndex::build(surf, &mut nodes).unwrap();
    let mut checked = 0;
    for k in 0..ix.slots() {
        let (lo, hi, face, sub) = ix.slot_box(k);
        for a in 0..=32 {
            for b in 0..=32 {
                let p = eval(face, sub, a as f64 / 32.0, b as f64 / 32.0);
                assert!(
                    p.cmpge(lo).all() && p.cmple(hi).all(),
                    "{name}: slot {k} ({face}, {sub}) at ({a}, {b})/32: {p} outside {lo}..{hi}"
                );
                checked += 1;
            }
        }
    }
    checked
}

#[test]
fn index_boxes_hold_their_slots() {
    let mut checked = 0;
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            checked += boxes_hold(&name, ev, |f, s, u, v| ev.eval(f, s, u, v).unwrap().p);
        })
        .unwrap();
    }
    for name in FEATURE {
        let m = load(name);
        with_feature_mesh(&flat(&m), Some(standard_tables()), |fe| {
            checked += boxes_hold(name, fe, |f, s, u, v| fe.eval(f, s, u, v).unwrap().p);
        })
        .unwrap();
    }
    println!("{checked} exact points inside their slot boxes");
    assert!(checked > 600_000);
}

const FEATURE: [&str; 3] = [
    "catmark_cube_creases1",
    "catmark_torus_creases0",
    "catmark_hole_test2",
];

fn load(name: &str) -> TaggedMesh {
    let path = workspace_root().join(format!("tests/data/osd/{name}.obj"));
    TaggedMesh::from_obj(&path).unwrap()
}

/// Rays from outside aimed into the middle, plus axis rays through the
/// centre.
fn rays(c: DVec3, diag: f64, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = XorShift(seed);
    let mut v: Vec<Ray> = (0..n)
        .map(|_| {
            let o = c + DVec3::new(rng.signed(), rng.signed(), rng.signed()).normalize() * diag;
            let t = c + DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.3 * diag;
            Ray {
                origin: o,
                dir: t - o,
            }
        })
        .collect();
    for d in [DVec3::X, DVec3::Y, DVec3::Z] {
        v.push(Ray {
            origin: c - d * diag,
            dir: d,
        });
    }
    v
}

/// Rays, inside and closest points through the index and without it.
fn same_answers<S: QuerySurface + ?Sized>(
    name: &str,
    surf: &S,
    c: DVec3,
    diag: f64,
    solid: bool,
) -> (usize, usize) {
    let mut nodes = index_of(surf);
    let ix = SlotIndex::build(surf, &mut nodes).unwrap();
    let isurf = Indexed::new(surf, &ix).unwrap();
    let mut w = Box::new(QueryWork::ZERO);
    let tol = 1e-9 * diag;
    let ro = RayOptions {
        tol,
        ..Default::default()
    };
    let (mut hits, mut points) = (0, 0);
    for (i, r) in rays(c, diag, 60, 0x5107_1dec).iter().enumerate() {
        let mut a = [Hit::ZERO; 16];
        let mut b = [Hit::ZERO; 16];
        let na = ray_all(surf, r, &ro, &mut w, &mut a).unwrap();
        let nb = ray_all(&isurf, r, &ro, &mut w, &mut b).unwrap();
        assert_eq!(a[..na], b[..nb], "{name}: all hits of ray {i}");
        hits += na;
        let fa = ray_first(surf, r, &ro, &mut w).unwrap();
        let fb = ray_first(&isurf, r, &ro, &mut w).unwrap();
        match (fa, fb) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                let dl = r.dir.length();
                assert!(
                    (x.t - y.t).abs() * dl <= tol,
                    "{name}: first hit of ray {i}: {} / {}",
                    x.t,
                    y.t
                );
                assert!((x.t - a[0].t).abs() * dl <= tol);
            }
            _ => panic!("{name}: first hit of ray {i}: {fa:?} / {fb:?}"),
        }
    }
    let mut rng = XorShift(0x0c10_5e57);
    let co = ClosestOptions {
        tol,
        ..Default::default()
    };
    for i in 0..40 {
        let s = if i % 2 == 0 { 0.4 } else { 1.5 };
        let q = c + DVec3::new(rng.signed(), rng.signed(), rng.signed()) * s * diag;
        let x = closest(surf, q, &co, &mut w).unwrap();
        let y = closest(&isurf, q, &co, &mut w).unwrap();
        assert!(
            (x.dist - y.dist).abs() <= tol,
            "{name}: closest to {q}: {} / {}",
            x.dist,
            y.dist
        );
        if solid {
            assert_eq!(
                inside(surf, q, tol, &mut w).unwrap(),
                inside(&isurf, q, tol, &mut w).unwrap(),
                "{name}: inside {q}"
            );
        }
        points += 1;
    }
    (hits, points)
}

/// All layers of a stack through `slice_band`: per layer its points and
/// contours.
type Layers = Vec<(Vec<[f64; 2]>, Vec<Contour>)>;

fn stack_of<S: QuerySurface + ?Sized>(surf: &S, stack: &PlaneStack, n: usize, eps: f64) -> Layers {
    let o = SliceOptions {
        eps,
        ..Default::default()
    };
    let mut w = Box::new(QueryWork::ZERO);
    let mut out = vec![];
    let mut first = 0;
    while first < n {
        let k = (n - first).min(16);
        let mut stats = vec![SliceStats::default(); k];
        let need = match slice_band(surf, stack, first, &o, &mut w, &mut [], &mut stats) {
            Err(Error::BufferTooSmall { required }) => required,
            Ok(0) => 0,
            r => panic!("size query: {r:?}"),
        };
        let mut segs = vec![SliceSegment::default(); need];
        slice_band(surf, stack, first, &o, &mut w, &mut segs, &mut stats).unwrap();
        for i in 0..k {
            let st = stats[i];
            let mut pts = vec![[0.0; 2]; st.points];
            let mut cs = vec![Contour::default(); st.contours];
            slice_write(band_layer(&mut segs, &stats, i), &mut pts, &mut cs).unwrap();
            out.push((pts, cs));
        }
        first += k;
    }
    out
}

fn same_slices<S: QuerySurface + ?Sized>(name: &str, surf: &S, lo: DVec3, hi: DVec3) -> usize {
    let mut nodes = index_of(surf);
    let ix = SlotIndex::build(surf, &mut nodes).unwrap();
    let isurf = Indexed::new(surf, &ix).unwrap();
    let n = 40;
    let dz = (hi.z - lo.z) / n as f64;
    // Past both ends too: layers that meet no slot.
    let stack = PlaneStack::z(lo.z - 2.5 * dz, dz);
    let eps = 1e-3 * (hi - lo).length();
    let a = stack_of(surf, &stack, n + 5, eps);
    let b = stack_of(&isurf, &stack, n + 5, eps);
    assert!(a == b, "{name}: indexed contours differ");
    a.iter().map(|l| l.0.len()).sum()
}

#[test]
fn index_gives_the_walks_answers() {
    let (mut hits, mut points, mut slice_points) = (0, 0, 0);
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let gs = grids(ev, 8);
            let (c, diag) = (centre(&gs), diagonal(&gs));
            let (h, p) = same_answers(&name, ev, c, diag, true);
            hits += h;
            points += p;
            let lo = gs.iter().fold(DVec3::INFINITY, |a, g| a.min(g.lo));
            let hi = gs.iter().fold(DVec3::NEG_INFINITY, |a, g| a.max(g.hi));
            slice_points += same_slices(&name, ev, lo, hi);
        })
        .unwrap();
    }
    for name in FEATURE {
        let m = load(name);
        with_feature_mesh(&flat(&m), Some(standard_tables()), |fe| {
            let (lo, hi) = feature_box(fe);
            let solid = name != "catmark_hole_test2"; // open: holes
            let (h, p) = same_answers(name, fe, 0.5 * (lo + hi), (hi - lo).length(), solid);
            hits += h;
            points += p;
            if solid {
                slice_points += same_slices(name, fe, lo, hi);
            }
        })
        .unwrap();
    }
    println!("{hits} hits, {points} closest points, {slice_points} slice points: the same");
    assert!(hits > 500 && points > 300 && slice_points > 10_000);
}

/// The box of a feature surface's exact points on a 9 x 9 grid per slot.
fn feature_box(fe: &FeatureEvaluator) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for f in 0..fe.num_faces() {
        for s in 0..fe.num_subfaces(f) {
            for a in 0..=8 {
                for b in 0..=8 {
                    // Hole faces have no surface.
                    if let Ok(e) = fe.eval(f as u32, s as u32, a as f64 / 8.0, b as f64 / 8.0) {
                        lo = lo.min(e.p);
                        hi = hi.max(e.p);
                    }
                }
            }
        }
    }
    (lo, hi)
}

#[test]
fn index_sizes_and_misuse() {
    let ms = meshes();
    with_evaluator(&ms[0].1, standard_tables(), |_, cube| {
        with_evaluator(&ms[1].1, standard_tables(), |_, rh| {
            let n = SlotIndex::required_len(cube);
            // Slots plus twice the power of two above them.
            let slots: usize = (0..cube.num_faces()).map(|f| cube.num_subfaces(f)).sum();
            assert_eq!(n, slots + 2 * slots.next_power_of_two());
            let mut short = vec![IndexNode::default(); n - 1];
            short[0].a = 7;
            assert_eq!(
                SlotIndex::build(cube, &mut short).err(),
                Some(Error::BufferTooSmall { required: n })
            );
            assert!(short[0].a == 7 && short[1..] == vec![IndexNode::default(); n - 2][..]);
            let mut nodes = vec![IndexNode::default(); n + 3];
            let ix = SlotIndex::build(cube, &mut nodes).unwrap();
            assert_eq!(ix.slots(), slots);
            assert!(matches!(
                Indexed::new(rh, &ix).err(),
                Some(Error::InvalidArgument(_))
            ));
        })
        .unwrap();
    })
    .unwrap();
}
