//! Crease strips of `FeatureEvaluator` (`ccss_core::mesh::strip`): a quad
//! next to a straight, uniformly semi-sharp crease is cached as a row of
//! bicubic pieces across the crease instead of a quadtree. On a bumpy torus
//! with a closed crease ring (every crease vertex of valence 4: strips all
//! along it) and an open crease line (ends: trees there, strips between),
//! for sharpness from 1.25 to 9.9 with uniform and Chaikin decay:
//!
//! * positions equal the sharp reference subdivider (uniform subdivision
//!   plus exact limit masks, plain code) at the dyadic points of level 5 of
//!   every face along the creases, to 1e-12 of the diagonal;
//! * positions and first and second derivatives equal local refinement
//!   (`FeatureCache { depth: 0, .. }`, the path checked against the
//!   reference in `feature_eval.rs`) at points `2^-k` (`k` up to 40) from
//!   the crease, with the default cache and with a cache tree of depth 3
//!   (strips cut where the tree stops: nearer points refine locally);
//! * a cell inside one piece is that piece's polynomial (`CellGeom::Poly`),
//!   equal to exact evaluation over the cell.
use ccss_core::eval::{FeatureCache, Query};
use ccss_core::math::bspline::eval_points;
use ccss_core::{CellGeom, FeatureEvaluator};
use ccss_tests::feature_input::{eval_gap, flat, with_feature_caches};
use ccss_tests::harness::{standard_tables, XorShift};
use ccss_tests::sharp::{SharpRefiner, TaggedMesh};
use std::fmt::Write;

/// Around the torus.
const N: usize = 12;
/// Around the tube.
const M: usize = 8;

const NO_TREE: FeatureCache = FeatureCache {
    depth: 0,
    nodes_per_face: 0,
};

/// A cache tree of depth 3: crease strips of sharpness above 4 are cut.
const SHALLOW: FeatureCache = FeatureCache {
    depth: 3,
    nodes_per_face: 64,
};

/// Vertex `(i, j)` of the torus (`i` around, `j` around the tube).
fn vid(i: usize, j: usize) -> usize {
    (j % M) * N + i % N
}

/// A bumpy torus with a crease ring of `sharpness` at `j = 0` and a crease
/// line of `sharpness - 0.5` from `i = 2` to `i = 8` at `j = 4`.
fn torus(sharpness: f32, chaikin: bool) -> TaggedMesh {
    let mut rng = XorShift(0xc0ffee);
    let mut obj = String::new();
    for j in 0..M {
        for i in 0..N {
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / N as f64,
                std::f64::consts::TAU * j as f64 / M as f64,
            );
            let r = 1.0 + 0.15 * (rng.unit() - 0.5);
            let (x, y, z) = (
                (3.0 + r * b.cos()) * a.cos(),
                (3.0 + r * b.cos()) * a.sin(),
                r * b.sin(),
            );
            writeln!(obj, "v {x} {y} {z}").unwrap();
        }
    }
    for j in 0..M {
        for i in 0..N {
            let q = [vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)];
            writeln!(obj, "f {} {} {} {}", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1).unwrap();
        }
    }
    for i in 0..N {
        writeln!(
            obj,
            "t crease 2/1/0 {} {} {sharpness}",
            vid(i, 0),
            vid(i + 1, 0)
        )
        .unwrap();
    }
    for i in 2..8 {
        let s = sharpness - 0.5;
        writeln!(obj, "t crease 2/1/0 {} {} {s}", vid(i, 4), vid(i + 1, 4)).unwrap();
    }
    if chaikin {
        writeln!(obj, "t creasemethod 0/0/1 chaikin").unwrap();
    }
    TaggedMesh::parse(&obj).unwrap()
}

/// Faces with a side on a crease: `(face, side)`, side 0 at `v = 0`, 2 at
/// `v = 1`.
fn crease_faces() -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..N {
        out.push((i, 0)); // row j = 0: the ring at v = 0
        out.push(((M - 1) * N + i, 2)); // row M - 1: the ring at v = 1
    }
    for i in 2..8 {
        out.push((4 * N + i, 0));
        out.push((3 * N + i, 2));
    }
    out
}

/// Runs `run` with the torus's evaluator of `cache`, the one of local
/// refinement and the torus's bounding-box diagonal.
fn with_torus(
    sharpness: f32,
    chaikin: bool,
    cache: FeatureCache,
    run: impl FnOnce(&FeatureEvaluator, &FeatureEvaluator, f64),
) {
    let m = torus(sharpness, chaikin);
    let diag = m.bbox_diagonal();
    let caches = [cache, NO_TREE];
    with_feature_caches(&flat(&m), Some(standard_tables()), caches, |ev, local| {
        run(ev, local, diag)
    })
    .unwrap();
}

const CASES: [(f32, bool); 8] = [
    (1.25, false),
    (2.0, false),
    (3.5, false),
    (6.0, false),
    (9.9, false),
    (2.6, true),
    (4.3, true),
    (7.0, true),
];

#[test]
fn strips_equal_the_sharp_reference_at_dyadic_points() {
    let k = 5u32;
    let mut worst = 0.0f64;
    let mut points = 0usize;
    for (sharpness, chaikin) in CASES {
        let m = torus(sharpness, chaikin);
        let diag = m.bbox_diagonal();
        let mut r = SharpRefiner::new(&m).unwrap();
        let f = flat(&m);
        let caches = [FeatureCache::default(), NO_TREE];
        with_feature_caches(&f, Some(standard_tables()), caches, |ev, _| {
            let strips = ev.cache_counts().crease_strips;
            // At least every level-1 face along the ring (2 per face side,
            // 2 sides).
            assert!(strips >= 4 * N, "{sharpness}: {strips} strips");
            for (face, _) in crease_faces() {
                for i in 0..=(1u32 << k) {
                    for j in 0..=(1u32 << k) {
                        let want = r.dyadic_limit_point(face, 0, i, j, k);
                        let (u, v) = (i as f64 / (1u32 << k) as f64, j as f64 / (1u32 << k) as f64);
                        let got = ev.eval(face as u32, 0, u, v).unwrap().p;
                        let d = ((want[0] - got.x).powi(2)
                            + (want[1] - got.y).powi(2)
                            + (want[2] - got.z).powi(2))
                        .sqrt()
                            / diag;
                        assert!(
                            d <= 1e-12,
                            "sharpness {sharpness} chaikin {chaikin}: face {face} ({u}, {v}): {d:e}"
                        );
                        worst = worst.max(d);
                        points += 1;
                    }
                }
            }
        })
        .unwrap();
    }
    eprintln!("{points} dyadic points, max {worst:.1e} of the diagonal");
}

#[test]
fn strips_equal_local_refinement_next_to_the_crease() {
    let mut rng = XorShift(0x5791);
    let (mut worst_p, mut worst_d, mut points, mut from_strips) = (0.0f64, 0.0f64, 0usize, 0usize);
    for ((sharpness, chaikin), cache) in CASES
        .iter()
        .flat_map(|&c| [(c, FeatureCache::default()), (c, SHALLOW)])
    {
        with_torus(sharpness, chaikin, cache, |ev, local, diag| {
            for (face, side) in crease_faces() {
                for _ in 0..if cfg!(miri) { 2 } else { 60 } {
                    // Distance 2^-k from the crease side (k in 0..=40),
                    // anywhere along it (ends included).
                    let kk = (rng.next_u64() % 41) as i32;
                    let x = rng.unit() * 0.5f64.powi(kk);
                    let u = match rng.next_u64() % 8 {
                        0 => 0.0,
                        1 => 1.0,
                        _ => rng.unit(),
                    };
                    let v = if side == 0 { x } else { 1.0 - x };
                    let q = Query {
                        face: face as u32,
                        sub: 0,
                        u,
                        v,
                    };
                    let got = ev.eval_second(face as u32, 0, u, v).unwrap();
                    let want = local.eval_second(face as u32, 0, u, v).unwrap();
                    points += 1;
                    if ev.is_cached(&q) && !local.is_cached(&q) {
                        from_strips += 1;
                    }
                    let (dp, dd, which) = eval_gap(&got, &want, diag);
                    assert!(dp <= 1e-13, "{sharpness}: face {face} ({u}, {v}): {dp:e}");
                    assert!(
                        dd <= 1e-9,
                        "{sharpness}: face {face} ({u}, {v}): {which} {dd:e}"
                    );
                    worst_p = worst_p.max(dp);
                    worst_d = worst_d.max(dd);
                }
            }
        });
    }
    eprintln!(
        "{points} points, {from_strips} cached only with strips; max {worst_p:.1e} of the \
         diagonal, derivatives {worst_d:.1e}"
    );
    // Not vacuous: most points are answered by the strips.
    assert!(from_strips * 2 >= points, "{from_strips} of {points}");
}

#[test]
fn a_cell_inside_one_strip_piece_is_its_polynomial() {
    let mut rng = XorShift(0xce11);
    let (mut polys, mut from_strips, mut worst) = (0usize, 0usize, 0.0f64);
    for (sharpness, chaikin, cache) in [
        (6.0, false, FeatureCache::default()),
        (4.3, true, FeatureCache::default()),
        (6.0, false, SHALLOW),
    ] {
        with_torus(sharpness, chaikin, cache, |ev, local, diag| {
            for (face, side) in crease_faces() {
                for level in 1..=9u32 {
                    let n = 1u32 << level;
                    // Cells next to the crease, one row out, and anywhere.
                    for row in [0, 1, rng.next_u64() as u32 % n] {
                        let i = rng.next_u64() as u32 % n;
                        let j = if side == 0 { row } else { n - 1 - row };
                        let cell = ev.cell(face as u32, 0, level, i, j).unwrap();
                        let CellGeom::Poly { grid, rect } = cell else {
                            continue;
                        };
                        polys += 1;
                        // Local refinement reaches another grid (or none).
                        if local.cell(face as u32, 0, level, i, j).unwrap() != cell {
                            from_strips += 1;
                        }
                        for _ in 0..4 {
                            let (a, b) = (rng.unit(), rng.unit());
                            let s = rect[0] + a * (rect[1] - rect[0]);
                            let t = rect[2] + b * (rect[3] - rect[2]);
                            let (u, v) = ((i as f64 + a) / n as f64, (j as f64 + b) / n as f64);
                            let got = eval_points::<false>(&grid, s, t).p;
                            let want = ev.eval(face as u32, 0, u, v).unwrap().p;
                            let d = (got - want).length() / diag;
                            assert!(d <= 1e-12, "face {face} cell {level} ({i}, {j}): {d:e}");
                            worst = worst.max(d);
                        }
                    }
                }
            }
        });
    }
    eprintln!(
        "{polys} polynomial cells ({from_strips} from strips), max {worst:.1e} of the diagonal"
    );
    assert!(
        polys >= 500 && from_strips * 4 >= polys,
        "{from_strips} of {polys}"
    );
}
