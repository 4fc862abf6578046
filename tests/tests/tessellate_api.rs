//! Adaptive tessellation, API properties:
//!
//! * relative flatness is invariant under similarity transforms: scaling,
//!   rotating and translating the input gives the same polygons (identical
//!   index lists and parameters) and the transformed vertices;
//! * the per-slot path (`mark_slot`, e.g. in parallel, then `build_marked`)
//!   emits exactly what `build` does;
//! * size queries are exact: `build` succeeds with `required_bytes` and
//!   fails with `BufferTooSmall { required }` (the same number) one word
//!   short; emission buffers one element short fail likewise;
//! * uniform tessellations have slots x 4^L polygons; the uniform depth of a
//!   tolerance is at least the adaptive depth and its cells all pass;
//! * the optional outputs (normals, params, triangles, cells) do not change
//!   the others, in any combination;
//! * errors: bad options, a topology that is not the evaluator's, a
//!   tolerance that needs more than `max_level` levels.
mod tessellate_util;

use ccss_core::tessellate::{
    mark_slot, uniform_depth, Criterion, Options, Output, Scratch, SlotMark, Tessellation,
};
use ccss_core::Error;
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, PolyMesh};
use tessellate_util::*;

fn transformed(m: &PolyMesh, scale: f64, angle: f64, shift: [f64; 3]) -> PolyMesh {
    // Rotation about the axis (1, 2, 2)/3 by `angle`.
    let (x, y, z) = (1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0);
    let (c, s) = (angle.cos(), angle.sin());
    let t = 1.0 - c;
    let r = [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ];
    let positions = m
        .positions
        .iter()
        .map(|p| {
            let q: [f64; 3] = core::array::from_fn(|i| {
                scale * (r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]) + shift[i]
            });
            q
        })
        .collect();
    PolyMesh {
        positions,
        faces: m.faces.clone(),
    }
}

fn run(m: &PolyMesh, opts: Options) -> Tess {
    with_evaluator(m, standard_tables(), |topo, ev| {
        tessellate(topo, ev, opts).unwrap()
    })
    .unwrap()
}

#[test]
fn relative_flatness_is_similarity_invariant() {
    for (name, m) in [
        ("cube", corpus("catmark_cube.obj")),
        ("toroidal_tet", corpus("catmark_toroidal_tet.obj")),
        ("righthanded", corpus("catmark_righthanded.obj")),
        ("drum(5)", drum(5)),
    ] {
        for r in [0.2, 0.05] {
            let a = run(&m, Options::relative(r));
            for (scale, angle, shift) in [
                (1000.0, 0.0, [0.0; 3]),
                (3.7e-3, 0.9, [1.0, -2.0, 0.5]),
                (17.25, 2.3, [-40.0, 3.0, 8.0]),
            ] {
                let mt = transformed(&m, scale, angle, shift);
                let b = run(&mt, Options::relative(r));
                let what = format!("{name} R={r} scale {scale} angle {angle}");
                assert_eq!(a.counts, b.counts, "{what}: counts");
                assert_eq!(a.sizes, b.sizes, "{what}: polygon sizes");
                assert_eq!(a.idx, b.idx, "{what}: polygon indices");
                assert_eq!(a.cells, b.cells, "{what}: cells");
                assert_eq!(a.stats.max_level, b.stats.max_level, "{what}");
                // The bounds include a rounding term proportional to the
                // coordinates' magnitude (bounds::rounding), which a shift
                // changes: up to 3e-6 of these ratios (righthanded at scale
                // 3.7e-3 moved by 500 times its size).
                assert!(
                    (a.stats.max_ratio - b.stats.max_ratio).abs() <= 1e-4 * a.stats.max_ratio,
                    "{what}: ratio"
                );
                let t = transformed(
                    &PolyMesh {
                        positions: a.pos.chunks(3).map(|p| [p[0], p[1], p[2]]).collect(),
                        faces: vec![],
                    },
                    scale,
                    angle,
                    shift,
                );
                let diag = mt.bbox_diagonal();
                for (v, p) in t.positions.iter().enumerate() {
                    let d = norm(sub(*p, b.p(v as u32)));
                    assert!(d <= 1e-12 * diag, "{what}: vertex {v} off by {d:e}");
                }
            }
            eprintln!(
                "{name} R={r}: {} polygons, identical under 3 similarity transforms",
                a.counts.polygons
            );
        }
    }
}

#[test]
fn per_slot_marking_gives_the_same_tessellation() {
    for m in [corpus("catmark_righthanded.obj"), pole_mesh(5), drum(6)] {
        let diag = m.bbox_diagonal();
        for opts in [
            Options::absolute(2e-3 * diag),
            Options::relative(0.1),
            Options::uniform(2),
        ] {
            with_evaluator(&m, standard_tables(), |topo, ev| {
                let a = tessellate(topo, ev, opts).unwrap();
                // Slots marked in reverse order, each into its own buffer
                // (grown on BufferTooSmall), as a parallel host would.
                let mut scratch = Box::new(Scratch::ZERO);
                let mut marks = vec![SlotMark::default(); ev.num_slots()];
                let mut trees = vec![Vec::new(); ev.num_slots()];
                for s in (0..ev.num_slots()).rev() {
                    let mut buf = vec![0u32; 1];
                    let mk = loop {
                        match mark_slot(ev, &opts, s, Some(&mut buf), &mut scratch) {
                            Ok(mk) => break mk,
                            Err(Error::BufferTooSmall { required }) => buf.resize(required, 0),
                            Err(e) => panic!("{e}"),
                        }
                    };
                    let count = mark_slot(ev, &opts, s, None, &mut scratch).unwrap();
                    assert_eq!(mk, count, "count-only marking differs");
                    buf.truncate(mk.nodes as usize);
                    marks[s] = mk;
                    trees[s] = buf;
                }
                let flat: Vec<u32> = trees.concat();
                let need = Tessellation::required_bytes_marked(topo, &marks).unwrap();
                assert_eq!(
                    need,
                    Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap()
                );
                let mut mem = aligned(need);
                let mut t =
                    Tessellation::build_marked(topo, ev, opts, &marks, &flat, &mut mem).unwrap();
                assert_eq!(t.counts(), a.counts);
                for (s, tree) in trees.iter().enumerate() {
                    assert_eq!(t.slot_tree(s).unwrap(), &tree[..]);
                }
                let c = t.counts();
                let (mut pos, mut sizes, mut idx) = (
                    vec![0.0; 3 * c.vertices],
                    vec![0; c.polygons],
                    vec![0; c.polygon_indices],
                );
                t.emit(Output {
                    positions: &mut pos,
                    normals: None,
                    params: None,
                    polygon_sizes: &mut sizes,
                    polygon_indices: &mut idx,
                    triangles: None,
                    cells: None,
                })
                .unwrap();
                assert_eq!((pos, sizes, idx), (a.pos, a.sizes, a.idx));
                // Corrupt trees are rejected, not followed.
                let mut bad = flat.clone();
                if let Some(x) = bad.iter_mut().find(|x| **x != 0) {
                    *x += 4 * 1000;
                }
                let mut mem2 = aligned(need);
                assert!(matches!(
                    Tessellation::build_marked(topo, ev, opts, &marks, &bad, &mut mem2),
                    Err(Error::InvalidArgument(_))
                ));
            })
            .unwrap();
        }
    }
}

#[test]
fn sizes_are_exact_and_errors_are_reported() {
    let m = corpus("catmark_pyramid.obj");
    let other = corpus("catmark_cube.obj");
    with_evaluator(&m, standard_tables(), |topo, ev| {
        let opts = Options::absolute(1e-3);
        let mut scratch = Box::new(Scratch::ZERO);
        let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
        let mut mem = aligned(need);
        let words = &mut mem;
        assert_eq!(
            Tessellation::build(topo, ev, opts, &mut words[..need / 8 - 1]).err(),
            Some(Error::BufferTooSmall { required: need })
        );
        assert!(matches!(
            Tessellation::build(topo, ev, opts, &mut words[..8]),
            Err(Error::BufferTooSmall { .. })
        ));
        let mut t = Tessellation::build(topo, ev, opts, &mut words[..need / 8]).unwrap();
        let c = t.counts();
        let mut pos = vec![0.0; 3 * c.vertices];
        let mut sizes = vec![0; c.polygons];
        let mut idx = vec![0; c.polygon_indices - 1];
        let r = t.emit(Output {
            positions: &mut pos,
            normals: None,
            params: None,
            polygon_sizes: &mut sizes,
            polygon_indices: &mut idx,
            triangles: None,
            cells: None,
        });
        assert_eq!(
            r,
            Err(Error::BufferTooSmall {
                required: c.polygon_indices
            })
        );
        // Options.
        for bad in [
            Options::absolute(0.0),
            Options::absolute(f64::NAN),
            Options::relative(-1.0),
            Options::relative(f64::INFINITY),
            Options {
                criterion: Criterion::Uniform(5),
                max_level: 4,
            },
            Options {
                criterion: Criterion::Absolute(1.0),
                max_level: 31,
            },
        ] {
            assert!(
                matches!(
                    Tessellation::required_bytes(topo, ev, &bad, &mut scratch),
                    Err(Error::InvalidArgument(_))
                ),
                "{bad:?}"
            );
        }
        // Too fine for the level cap.
        let deep = Options {
            criterion: Criterion::Absolute(1e-9),
            max_level: 6,
        };
        assert!(matches!(
            Tessellation::required_bytes(topo, ev, &deep, &mut scratch),
            Err(Error::InvalidArgument(msg)) if msg.contains("max_level")
        ));
        // A topology that is not the evaluator's.
        with_evaluator(&other, standard_tables(), |topo2, _| {
            assert!(matches!(
                Tessellation::required_bytes(topo2, ev, &opts, &mut scratch),
                Err(Error::InvalidArgument(_))
            ));
        })
        .unwrap();
        assert!(mark_slot(ev, &opts, ev.num_slots(), None, &mut scratch).is_err());
    })
    .unwrap();
}

/// The optional outputs (normals, params, triangles, cells) change
/// nothing else: every combination emits the same positions, polygons and
/// (when asked) triangles as the full emission, also when emitted again
/// from the same plan (the emission may take different internal paths,
/// e.g. four plain quads at once when no cells are wanted, and records the
/// quads' cuts only when triangles are wanted).
#[test]
fn optional_outputs_do_not_change_the_rest() {
    for (name, opts) in [
        ("catmark_torus.obj", Options::absolute(1e-3)),
        ("catmark_righthanded.obj", Options::relative(0.05)),
        ("catmark_righthanded.obj", Options::absolute(0.01)),
        ("catmark_cube.obj", Options::absolute(1e-3)),
    ] {
        let m = corpus(name);
        with_evaluator(&m, standard_tables(), |topo, ev| {
            let full = tessellate(topo, ev, opts).unwrap();
            let mut scratch = Box::new(Scratch::ZERO);
            let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
            let mut mem = aligned(need);
            let mut t = Tessellation::build(topo, ev, opts, &mut mem).unwrap();
            let c = t.counts();
            for mask in 0..16u32 {
                let mut pos = vec![0.0; 3 * c.vertices];
                let mut nrm = vec![0.0; 3 * c.vertices];
                let mut params = vec![Default::default(); c.vertices];
                let mut sizes = vec![0; c.polygons];
                let mut idx = vec![0; c.polygon_indices];
                let mut tris = vec![0; 3 * c.triangles];
                let mut cells = vec![Default::default(); c.polygons];
                t.emit(Output {
                    positions: &mut pos,
                    normals: (mask & 1 != 0).then_some(&mut nrm[..]),
                    params: (mask & 2 != 0).then_some(&mut params[..]),
                    polygon_sizes: &mut sizes,
                    polygon_indices: &mut idx,
                    triangles: (mask & 4 != 0).then_some(&mut tris[..]),
                    cells: (mask & 8 != 0).then_some(&mut cells[..]),
                })
                .unwrap();
                let what = format!("{name} outputs {mask:04b}");
                assert_eq!(pos, full.pos, "{what}: positions");
                assert_eq!(sizes, full.sizes, "{what}: sizes");
                assert_eq!(idx, full.idx, "{what}: indices");
                if mask & 1 != 0 {
                    assert_eq!(nrm, full.nrm, "{what}: normals");
                }
                if mask & 2 != 0 {
                    assert_eq!(params, full.params, "{what}: params");
                }
                if mask & 4 != 0 {
                    assert_eq!(tris, full.tris, "{what}: triangles");
                }
                if mask & 8 != 0 {
                    assert_eq!(cells, full.cells, "{what}: cells");
                }
            }
        })
        .unwrap();
    }
}

#[test]
fn uniform_tessellations_and_depths() {
    for m in [
        corpus("catmark_cube.obj"),
        corpus("catmark_pyramid.obj"),
        pole_mesh(7),
    ] {
        let diag = m.bbox_diagonal();
        with_evaluator(&m, standard_tables(), |topo, ev| {
            for l in 0..4u32 {
                let t = tessellate(topo, ev, Options::uniform(l)).unwrap();
                assert_eq!(t.counts.polygons, ev.num_slots() << (2 * l));
                assert!(t.cells.iter().all(|c| c.level == l));
            }
            let mut scratch = Box::new(Scratch::ZERO);
            for crit in [Criterion::Absolute(0.01 * diag), Criterion::Relative(0.2)] {
                let a = tessellate(
                    topo,
                    ev,
                    Options {
                        criterion: crit,
                        max_level: 30,
                    },
                )
                .unwrap();
                let l = uniform_depth(ev, crit, 0, 30, &mut scratch)
                    .unwrap()
                    .unwrap();
                assert!(
                    l >= a.stats.max_level,
                    "{crit:?}: uniform {l} < adaptive {}",
                    a.stats.max_level
                );
                eprintln!(
                    "{crit:?}: adaptive {} polygons (depth {}), uniform depth {l}: A/U = {:.5}",
                    a.counts.polygons,
                    a.stats.max_level,
                    a.counts.polygons as f64 / (ev.num_slots() as f64 * 4f64.powi(l as i32))
                );
            }
        })
        .unwrap();
    }
}

/// A tree made elsewhere that is deeper than `MAX_LEVEL` (a chain of
/// internal nodes in one corner of a slot, on two slot sides) is an error
/// of `build_marked`, not a panic or a wrong numbering.
#[test]
fn too_deep_marked_trees_are_rejected() {
    let m = corpus("catmark_cube.obj");
    with_evaluator(&m, standard_tables(), |topo, ev| {
        let opts = Options::absolute(1e-3);
        for depth in [30u32, 31] {
            // Internal nodes at levels 0..depth: node 0, then quadrant 0 of
            // each children group (local index 4 g + 1) splits again.
            let n = 1 + 4 * depth as usize;
            let mut tree = vec![0u32; n];
            tree[0] = 1;
            for g in 0..depth as usize - 1 {
                tree[4 * g + 1] = 4 * (g as u32 + 1) + 1;
            }
            let mut marks = vec![
                SlotMark {
                    nodes: 1,
                    leaves: 1,
                    ..Default::default()
                };
                ev.num_slots()
            ];
            marks[0] = SlotMark {
                nodes: n as u32,
                leaves: 3 * depth + 1,
                // The root touches four sides, every other node two.
                side_mids: 2 * depth + 2,
                max_level: depth,
                ..Default::default()
            };
            let mut flat = tree.clone();
            flat.extend(std::iter::repeat_n(0u32, ev.num_slots() - 1));
            let need = Tessellation::required_bytes_marked(topo, &marks).unwrap();
            let mut mem = aligned(need);
            let r = Tessellation::build_marked(topo, ev, opts, &marks, &flat, &mut mem);
            if depth <= 30 {
                // Leaves at level 30 are allowed: the numbering goes through.
                let t = r.unwrap();
                assert_eq!(t.counts().polygons, 3 * depth as usize + ev.num_slots());
            } else {
                assert!(
                    matches!(r, Err(Error::InvalidArgument(_))),
                    "depth {depth}: {:?}",
                    r.err()
                );
            }
        }
    })
    .unwrap();
}
