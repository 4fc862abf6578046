//! Issue 27: the tessellation, cell and depth bounds include rounding
//! (`ccss_core::bounds::rounding`): the same solids scaled by `2^k` and
//! `10^k` over the whole `f64` range and translated by up to 1e12 either
//! give a bound that holds at dense exact samples (zero violations; never
//! 0 or infinite) or are refused with `CoordinateRange`.
//!
//! * `tessellation_bounds_hold_or_refuse`: the cube (extraordinary
//!   vertices) and the creased cube (feature path), absolute and relative
//!   flatness: for every output polygon 16 jittered parameters of its cell
//!   are evaluated exactly and their distance to the polygon's own
//!   triangles must be at most `Stats::bound` (and eps for absolute
//!   flatness). Prints the tightness (worst distance / bound) and which
//!   cases were refused; models of moderate size and offset must not be.
//! * `cell_bounds_and_depths_include_rounding`: `cell_bound` is finite and
//!   positive at every scale it accepts and refuses beyond `2^400`; depths
//!   are unchanged by power-of-two scaling (eps scaled with the model), and
//!   refused when eps is below the rounding term.
use ccss_core::bounds::{cell_bound, depth::depths, depth::Method, rounding};
use ccss_core::mem::words_for;
use ccss_core::tessellate::{Criterion, Options, Output, PolygonCell, Scratch, Tessellation};
use ccss_core::{Error, FeatureEvaluator, Query};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, with_evaluator, XorShift};
use ccss_tests::reference::PolyMesh;
use ccss_tests::sharp::TaggedMesh;

fn cube_points(scale: f64, shift: [f64; 3]) -> Vec<[f64; 3]> {
    (0..8)
        .map(|k| {
            let c = [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64];
            core::array::from_fn(|a| (c[a] - 0.5) * scale + shift[a])
        })
        .collect()
}

const CUBE_FACES: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

fn cube(scale: f64, shift: [f64; 3]) -> PolyMesh {
    PolyMesh {
        positions: cube_points(scale, shift),
        faces: CUBE_FACES.iter().map(|f| f.to_vec()).collect(),
    }
}

/// The cube with every edge infinitely sharp (feature path).
fn creased_cube(scale: f64, shift: [f64; 3]) -> TaggedMesh {
    let mut text = String::new();
    for p in cube_points(scale, shift) {
        text += &format!("v {:e} {:e} {:e}\n", p[0], p[1], p[2]);
    }
    for f in CUBE_FACES {
        text += &format!("f {} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
    }
    for f in CUBE_FACES {
        for k in 0..4 {
            let (a, b) = (f[k], f[(k + 1) % 4]);
            if a < b {
                text += &format!("t crease 2/1/0 {a} {b} 10\n");
            }
        }
    }
    TaggedMesh::parse(&text).unwrap()
}

struct Out {
    p: Vec<f64>,
    sizes: Vec<u32>,
    tris: Vec<u32>,
    cells: Vec<PolygonCell>,
    bound: f64,
}

fn emit(mut t: Tessellation) -> Out {
    let c = t.counts();
    let mut o = Out {
        p: vec![0.0; 3 * c.vertices],
        sizes: vec![0; c.polygons],
        tris: vec![0; 3 * c.triangles],
        cells: vec![PolygonCell::default(); c.polygons],
        bound: t.stats().bound,
    };
    let mut idx = vec![0; c.polygon_indices];
    t.emit(Output {
        positions: &mut o.p,
        normals: None,
        params: None::<&mut [Query]>,
        polygon_sizes: &mut o.sizes,
        polygon_indices: &mut idx,
        triangles: Some(&mut o.tris),
        cells: Some(&mut o.cells),
    })
    .unwrap();
    o
}

fn point_triangle_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    // Relative to a (keeps the rounding of far-out coordinates small).
    let s = |x: [f64; 3]| [x[0] - a[0], x[1] - a[1], x[2] - a[2]];
    let (p, b, c) = (s(p), s(b), s(c));
    let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
    let seg = |p: [f64; 3], a: [f64; 3], b: [f64; 3]| {
        let ab = sub(b, a);
        let t = (dot(sub(p, a), ab) / dot(ab, ab).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let q = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
        dot(sub(p, q), sub(p, q)).sqrt()
    };
    let n = [
        b[1] * c[2] - b[2] * c[1],
        b[2] * c[0] - b[0] * c[2],
        b[0] * c[1] - b[1] * c[0],
    ];
    let nn = dot(n, n);
    if nn > 0.0 {
        // Barycentric test of the projection.
        let d = dot(p, n) / nn;
        let q = [p[0] - d * n[0], p[1] - d * n[1], p[2] - d * n[2]];
        let cr = |x: [f64; 3], y: [f64; 3]| {
            [
                x[1] * y[2] - x[2] * y[1],
                x[2] * y[0] - x[0] * y[2],
                x[0] * y[1] - x[1] * y[0],
            ]
        };
        let z = [0.0; 3];
        let w0 = dot(cr(sub(b, z), sub(q, z)), n);
        let w1 = dot(cr(sub(c, b), sub(q, b)), n);
        let w2 = dot(cr(sub(z, c), sub(q, c)), n);
        if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
            return d.abs() * nn.sqrt();
        }
    }
    seg(p, [0.0; 3], b)
        .min(seg(p, b, c))
        .min(seg(p, c, [0.0; 3]))
}

/// Worst distance of exact samples from their polygon's triangles.
fn worst_distance(o: &Out, eval: &dyn Fn(u32, u32, f64, f64) -> Option<[f64; 3]>) -> (f64, usize) {
    let mut rng = XorShift(0x1234_5678_9abc_def1);
    let mut worst = 0.0f64;
    let mut n = 0usize;
    let mut t0 = 0usize;
    let step = (o.sizes.len() / 1500).max(1);
    for (pi, c) in o.cells.iter().enumerate() {
        let nt = o.sizes[pi] as usize - 2;
        let tri = &o.tris[3 * t0..3 * (t0 + nt)];
        t0 += nt;
        if pi % step != 0 {
            continue;
        }
        let h = 0.5f64.powi(c.level as i32);
        for a in 0..4 {
            for b in 0..4 {
                let u = (c.i as f64 + (a as f64 + rng.unit()) / 4.0) * h;
                let v = (c.j as f64 + (b as f64 + rng.unit()) / 4.0) * h;
                let Some(s) = eval(c.face, c.sub, u.min(1.0), v.min(1.0)) else {
                    continue;
                };
                let vtx = |k: u32| {
                    let i = 3 * k as usize;
                    [o.p[i], o.p[i + 1], o.p[i + 2]]
                };
                let d = tri
                    .chunks(3)
                    .map(|t| point_triangle_distance(s, vtx(t[0]), vtx(t[1]), vtx(t[2])))
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
                n += 1;
            }
        }
    }
    (worst, n)
}

fn pow10(k: i32) -> f64 {
    format!("1e{k}").parse().unwrap()
}

/// (scale, shift, must succeed with relative flatness 0.01)
fn cases() -> Vec<(String, f64, f64, bool)> {
    let mut v = Vec::new();
    for e in [
        -1000, -600, -400, -190, -100, -20, 0, 20, 100, 190, 390, 500, 1000,
    ] {
        v.push((
            format!("2^{e}"),
            2f64.powi(e),
            0.0,
            (-190..=190).contains(&e),
        ));
    }
    for k in [-300, -200, -100, -30, 30, 100, 200, 300] {
        v.push((format!("1e{k}"), pow10(k), 0.0, k.abs() <= 30));
    }
    for k in [0, 3, 6, 9, 12, 15] {
        v.push((format!("shift 1e{k}"), 1.0, pow10(k), k <= 6));
    }
    v.push(("1e-6 at 1e6".into(), 1e-6, 1e6, false));
    v
}

#[test]
fn tessellation_bounds_hold_or_refuse() {
    let mut worst_ratio = 0.0f64;
    let mut samples = 0usize;
    let mut refused = Vec::new();
    for (name, s, t, must) in cases() {
        let shift = [t, -0.37 * t, 0.71 * t];
        for crit in [Criterion::Relative(0.01), Criterion::Absolute(1e-3 * s)] {
            let opts = Options {
                criterion: crit,
                max_level: 30,
            };
            // Smooth path.
            let r = with_evaluator(&cube(s, shift), standard_tables(), |topo, ev| {
                let mut sc = Box::new(Scratch::ZERO);
                let need = Tessellation::required_bytes(topo, ev, &opts, &mut sc)?;
                let mut mem = vec![0u64; words_for(need)];
                let o = emit(Tessellation::build(topo, ev, opts, &mut mem)?);
                let (d, n) = worst_distance(&o, &|f, sb, u, v| {
                    ev.eval(f, sb, u, v).ok().map(|e| e.p.to_array())
                });
                Ok::<_, Error>((o.bound, d, n))
            });
            let r = match r {
                Ok(x) => x,
                Err(e) => Err(e),
            };
            // Feature path.
            let tm = creased_cube(s, shift);
            let fr = with_feature_mesh(&flat(&tm), Some(standard_tables()), |fev| {
                let mut sc = Box::new(Scratch::ZERO);
                let need = Tessellation::required_bytes_feature(fev, &opts, &mut sc)?;
                let mut mem = vec![0u64; words_for(need)];
                let fev: &FeatureEvaluator = fev;
                let o = emit(Tessellation::build_feature(fev, opts, &mut mem)?);
                let (d, n) = worst_distance(&o, &|f, sb, u, v| {
                    fev.eval(f, sb, u, v).ok().map(|e| e.p.to_array())
                });
                Ok::<_, Error>((o.bound, d, n))
            });
            let fr = match fr {
                Ok(x) => x,
                Err(e) => Err(e),
            };
            for (path, r) in [("smooth", r), ("feature", fr)] {
                let what = format!("{name} {crit:?} {path}");
                match r {
                    Ok((bound, d, n)) => {
                        assert!(bound.is_finite() && bound > 0.0, "{what}: bound {bound:e}");
                        assert!(
                            d <= bound,
                            "{what}: sample {d:e} beyond the bound {bound:e}"
                        );
                        if let Criterion::Absolute(eps) = crit {
                            assert!(bound <= eps, "{what}: bound {bound:e} > eps");
                        }
                        worst_ratio = worst_ratio.max(d / bound);
                        samples += n;
                    }
                    Err(Error::CoordinateRange(_)) => {
                        assert!(
                            !(must && matches!(crit, Criterion::Relative(_))),
                            "{what}: refused"
                        );
                        refused.push(what);
                    }
                    Err(e) => panic!("{what}: {e:?}"),
                }
            }
        }
    }
    println!("tessellation: {samples} samples, worst distance / bound {worst_ratio:.3}");
    println!("refused with CoordinateRange: {refused:?}");
    assert!(samples > 100_000);
}

#[test]
fn cell_bounds_and_depths_include_rounding() {
    let d0: Vec<u32> = with_evaluator(&cube(1.0, [0.0; 3]), standard_tables(), |_, ev| {
        let mut d = vec![0u32; ev.num_slots()];
        depths(ev, 1e-4, Method::Best, &mut d).unwrap();
        d
    })
    .unwrap();
    for e in [-420, -190, -20, 0, 20, 190, 380, 420] {
        let s = 2f64.powi(e);
        with_evaluator(&cube(s, [0.0; 3]), standard_tables(), |_, ev| {
            let mut d = vec![0u32; ev.num_slots()];
            let r = depths(ev, 1e-4 * s, Method::Best, &mut d);
            let cb = cell_bound(ev, 0, 0, 3, 1, 2);
            if e.abs() > 200 {
                assert!(matches!(r, Err(Error::CoordinateRange(_))), "2^{e}: {r:?}");
                assert!(
                    matches!(cb, Err(Error::CoordinateRange(_))),
                    "2^{e}: {cb:?}"
                );
                return;
            }
            r.unwrap();
            assert_eq!(d, d0, "2^{e}");
            for (l, i, j) in [(1, 0, 0), (3, 1, 2), (6, 0, 0), (20, 5, 7)] {
                let b = cell_bound(ev, 0, 0, l, i, j).unwrap().interpolation_bound();
                assert!(b.is_finite() && b > 0.0, "2^{e} cell {l} {i} {j}: {b:e}");
                assert!(b >= rounding::ABS_TERM);
            }
        })
        .unwrap();
    }
    // Far out: eps below the rounding term is refused, not answered.
    with_evaluator(&cube(1.0, [1e12, 0.0, 0.0]), standard_tables(), |_, ev| {
        let mut d = vec![0u32; ev.num_slots()];
        let r = depths(ev, 1e-6, Method::Best, &mut d);
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
        depths(ev, 10.0, Method::Best, &mut d).unwrap();
    })
    .unwrap();
}

/// Voxelization and flooding of the cube scaled and moved: power-of-two
/// scales give the same voxels as scale 1 (the map into the grid is
/// exact), other scales and shifts the same interior up to the voxels next
/// to the surface, every run has an interior; out-of-range sizes and tiny
/// models far out are refused with `CoordinateRange` (formerly: no
/// interior, or "limit surface is not finite").
#[test]
fn voxel_classes_under_scale_and_translation() {
    use ccss_core::voxel::{Adjacency, VoxelCounts, VoxelGrid, VoxelParams, VoxelWork};
    let run = |m: &PolyMesh, adj: Adjacency| -> Result<VoxelCounts, Error> {
        with_evaluator(m, standard_tables(), |_, ev| {
            let params = VoxelParams::new([24; 3], adj);
            let mut gmem = vec![0u64; words_for(VoxelGrid::required_bytes(params.res)?)];
            let mut grid = VoxelGrid::new(params.res, &mut gmem)?;
            let mut work = Box::new(VoxelWork::ZERO);
            grid.voxelize(ev, &params, None, &mut work)?;
            let mut stack = vec![0u32; 1 << 12];
            grid.flood(ev, &mut stack, &mut work)?;
            Ok(grid.counts())
        })?
    };
    for adj in [Adjacency::Six, Adjacency::TwentySix] {
        let c0 = run(&cube(1.0, [0.0; 3]), adj).unwrap();
        assert!(c0.interior > 0);
        for e in [-190, -60, 60, 190] {
            let c = run(&cube(2f64.powi(e), [0.0; 3]), adj).unwrap();
            assert_eq!(c, c0, "2^{e} {adj:?}");
        }
        let mut ok = 0;
        for (s, t) in [
            (1e-50, 0.0),
            (1e50, 0.0),
            (1.0, 1e3),
            (1.0, 1e6),
            (1e-3, 1.0),
            (1e-6, 1e6),
            (1e-300, 0.0),
            (1e300, 0.0),
            (1e-100, 0.0),
            (1e100, 0.0),
        ] {
            let r = run(&cube(s, [t, -0.37 * t, 0.71 * t]), adj);
            let in_range =
                (1e-60..=1e60).contains(&s) && 4096.0 * f64::EPSILON * t * 23.0 / s <= 0.25;
            match r {
                Ok(c) => {
                    assert!(
                        in_range,
                        "{s:e} at {t:e} {adj:?}: {c:?} (expected a refusal)"
                    );
                    let d = c.interior.abs_diff(c0.interior);
                    assert!(
                        d * 4 <= c0.surface,
                        "{s:e} at {t:e} {adj:?}: {c:?} vs {c0:?}"
                    );
                    ok += 1;
                }
                Err(Error::CoordinateRange(_)) => {
                    assert!(!in_range, "{s:e} at {t:e} {adj:?}: refused")
                }
                Err(e) => panic!("{s:e} at {t:e} {adj:?}: {e:?}"),
            }
        }
        assert!(ok >= 5);
    }
}
