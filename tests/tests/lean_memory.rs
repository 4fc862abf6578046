//! The memory-saving choices give the same results bit for bit:
//! `Evaluator::build_with` with every [`EvaluatorOptions`] (without the
//! level-1/2 sub-patch grids and / or the corner bounds, recomputed per
//! query) against the default build, and `Tessellation::build_with`
//! without the saved corner-cell expansions (`Keep::LEAST`, redone at
//! emission) against the default, on the closed corpus shapes: positions,
//! derivatives and normals (f64 and f32) at random points, points next to
//! the extraordinary vertices and slot corners; subdivision depths; the
//! whole tessellation output (positions, polygons, triangles) at two
//! absolute tolerances; the cell bounds. Each size query is exact: the
//! build fits in `required_bytes` and not in 8 bytes less. And
//! `Evaluator::build_split` (the build's own memory in a block of its
//! own, garbage-filled) gives the same evaluator, and
//! `Tessellation::emit_stream` (one polygon at a time through a buffer of
//! `stream_len` values) hands out exactly what `emit` writes.

use ccss_core::bounds::cell_bound;
use ccss_core::bounds::depth::{depths, Method};
use ccss_core::mem::words_for;
use ccss_core::tessellate::{Keep, Options, Output, Scratch, Tessellation};
use ccss_core::{Error, Eval, Evaluator, EvaluatorOptions, MeshInput, Topology};
use ccss_tests::harness::{corpus_shapes, flatten, standard_tables, validate, XorShift};
use ccss_tests::reference::PolyMesh;

const ALL_OPTIONS: [EvaluatorOptions; 5] = [
    EvaluatorOptions::FULL,
    EvaluatorOptions {
        subpatch_grids: false,
        corner_bounds: true,
        deep_levels: ccss_core::eval::MAX_DEEP_LEVEL,
    },
    EvaluatorOptions {
        subpatch_grids: true,
        corner_bounds: false,
        deep_levels: 0,
    },
    EvaluatorOptions {
        subpatch_grids: true,
        corner_bounds: true,
        deep_levels: 5,
    },
    EvaluatorOptions::COMPACT,
];

fn bits(e: &Eval) -> [[u64; 3]; 7] {
    [e.p, e.du, e.dv, e.duu, e.duv, e.dvv, e.normal].map(|a| a.to_array().map(f64::to_bits))
}

/// Builds the evaluator of `topo` with `opts` in exactly its required
/// memory, after checking that 8 bytes less is refused with that size.
fn with_ev<R>(topo: &Topology, opts: EvaluatorOptions, f: impl FnOnce(&Evaluator) -> R) -> R {
    let t = standard_tables();
    let need = Evaluator::required_bytes_with(topo, t, opts).unwrap();
    assert_eq!(need % 8, 0);
    let mut short = vec![0u64; need / 8 - 1];
    assert!(matches!(
        Evaluator::build_with(topo, t, opts, &mut short),
        Err(Error::BufferTooSmall { required }) if required == need
    ));
    // The build's own memory apart (`build_split`), both blocks full of
    // garbage, each refused when 8 bytes short: the same evaluator.
    let lv = Evaluator::build_scratch_bytes(topo);
    let kept = need - lv;
    let mut scratch = vec![u64::MAX; lv / 8];
    let mut mem = vec![0x7ff8_dead_beef_0001u64; kept / 8];
    if lv > 0 {
        assert!(matches!(
            Evaluator::build_split(topo, t, opts, &mut mem, &mut scratch[1..]),
            Err(Error::BufferTooSmall { required }) if required == lv
        ));
    }
    assert!(matches!(
        Evaluator::build_split(topo, t, opts, &mut mem[1..], &mut scratch),
        Err(Error::BufferTooSmall { required }) if required == kept
    ));
    let split = Evaluator::build_split(topo, t, opts, &mut mem, &mut scratch).unwrap();
    let mut one = vec![0u64; words_for(need)];
    let ev = Evaluator::build_with(topo, t, opts, &mut one).unwrap();
    assert_eq!(ev.options(), opts);
    for f in 0..ev.num_faces() {
        for s in 0..ev.num_subfaces(f) {
            for (u, v) in [(0.0, 0.0), (0.3, 0.7), (1e-3, 2e-3), (0.6, 0.1)] {
                let (a, b) = (
                    ev.eval_second(f as u32, s as u32, u, v),
                    split.eval_second(f as u32, s as u32, u, v),
                );
                assert_eq!(bits(&a.unwrap()), bits(&b.unwrap()), "build_split");
            }
        }
    }
    f(&ev)
}

/// Everything the tessellation of `ev` at `eps` outputs, built with
/// `keep` in exactly its required memory (and refused in 8 bytes less).
fn tess_output(topo: &Topology, ev: &Evaluator, eps: f64, keep: Keep) -> Vec<u64> {
    let opts = Options::absolute(eps);
    let mut sc = Box::new(Scratch::ZERO);
    let need = Tessellation::required_bytes_with(topo, ev, &opts, keep, &mut sc).unwrap();
    let mut short = vec![0u64; need / 8 - 1];
    assert!(matches!(
        Tessellation::build_with(topo, ev, opts, keep, &mut short),
        Err(Error::BufferTooSmall { required }) if required == need
    ));
    let mut mem = vec![0u64; words_for(need)];
    let mut t = Tessellation::build_with(topo, ev, opts, keep, &mut mem).unwrap();
    let c = t.counts();
    let mut pos = vec![0.0; 3 * c.vertices];
    let mut sizes = vec![0u32; c.polygons];
    let mut ids = vec![0u32; c.polygon_indices];
    let mut tris = vec![0u32; 3 * c.triangles];
    t.emit(Output {
        positions: &mut pos,
        normals: None,
        params: None,
        polygon_sizes: &mut sizes,
        polygon_indices: &mut ids,
        triangles: Some(&mut tris),
        cells: None,
    })
    .unwrap();
    // The streamed emission: the same positions, polygons and triangles
    // in the same order, through a buffer of one polygon.
    let need = t.stream_len().unwrap();
    let largest = sizes.iter().copied().max().unwrap() as usize;
    assert_eq!(need, 4 * largest - 6, "stream_len of the largest polygon");
    let mut pos2 = vec![0.0; 3 * c.vertices];
    let (mut calls, mut sizes2, mut ids2, mut tris2) = (0, vec![], vec![], vec![]);
    let mut short = vec![0u32; need - 1];
    assert_eq!(
        t.emit_stream(&mut pos2, &mut short, &mut |_, _, _| calls += 1),
        Err(Error::BufferTooSmall { required: need })
    );
    assert_eq!(calls, 0, "nothing handed out before a size error");
    let mut buf = vec![0u32; need];
    t.emit_stream(&mut pos2, &mut buf, &mut |all, p, tr| {
        assert_eq!(all.len(), 3 * c.vertices);
        assert_eq!(tr.len(), 3 * (p.len() - 2));
        sizes2.push(p.len() as u32);
        ids2.extend_from_slice(p);
        tris2.extend_from_slice(tr);
    })
    .unwrap();
    assert!(pos2
        .iter()
        .zip(&pos)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!(
        (sizes2, ids2, tris2),
        (sizes.clone(), ids.clone(), tris.clone())
    );
    let mut out: Vec<u64> = pos.iter().map(|x| x.to_bits()).collect();
    out.extend(sizes.iter().chain(&ids).chain(&tris).map(|&x| x as u64));
    out.push(t.stats().bound.to_bits());
    out
}

#[test]
fn lean_evaluator_and_tessellation_are_bit_for_bit() {
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let (mut shapes, mut points, mut tess) = (0, 0usize, 0);
    let (mut full_bytes, mut compact_bytes) = (0usize, 0usize);
    for path in corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        if validate(&m).is_err() {
            continue;
        }
        let (p, s, i) = flatten(&m);
        let mut tm = vec![0u64; words_for(Topology::required_bytes(p.len() / 3, &s))];
        let topo = Topology::build(
            MeshInput {
                positions: &p,
                face_sizes: &s,
                indices: &i,
            },
            &mut tm,
        )
        .unwrap();
        let (lo, hi) = p
            .chunks(3)
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), q| {
                (
                    core::array::from_fn(|k| lo[k].min(q[k])),
                    core::array::from_fn(|k| hi[k].max(q[k])),
                )
            });
        let diag = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        // The reference: default build.
        let (pts, want_eval, want_depth, want_cells, want_tess) =
            with_ev(&topo, EvaluatorOptions::default(), |ev| {
                let mut pts = vec![];
                for f in 0..ev.num_faces() {
                    for sub in 0..ev.num_subfaces(f) {
                        for (u, v) in [(0.0, 0.0), (1.0, 1.0), (0.5, 0.25), (1e-9, 3e-9)] {
                            pts.push((f as u32, sub as u32, u, v));
                        }
                        for _ in 0..12 {
                            let sc = 0.5f64.powi((rng.next_u64() % 5) as i32);
                            pts.push((f as u32, sub as u32, sc * rng.unit(), sc * rng.unit()));
                        }
                        // Next to the corners: the levels whose grids
                        // `deep_levels` keeps, and beyond.
                        for _ in 0..6 {
                            let sc = 0.5f64.powi((rng.next_u64() % 40) as i32);
                            pts.push((f as u32, sub as u32, sc * rng.unit(), sc * rng.unit()));
                        }
                    }
                }
                let evals: Vec<_> = pts
                    .iter()
                    .map(|&(f, s, u, v)| {
                        let a = ev.eval_second(f, s, u, v).unwrap();
                        let b = ev.eval(f, s, u, v).unwrap();
                        let c = ev.eval_f32(f, s, u as f32, v as f32).unwrap();
                        (bits(&a), bits(&b), [c.p, c.du, c.dv, c.normal])
                    })
                    .collect();
                let mut d = vec![0u32; ev.num_slots()];
                depths(ev, 1e-3 * diag, Method::Best, &mut d).unwrap();
                let cells = cell_bounds(ev);
                let t: Vec<_> = [0.05, 0.005]
                    .map(|e| tess_output(&topo, ev, e * diag, Keep::ALL))
                    .into();
                (pts, evals, d, cells, t)
            });
        full_bytes += Evaluator::required_bytes(&topo, standard_tables()).unwrap();
        compact_bytes +=
            Evaluator::required_bytes_with(&topo, standard_tables(), EvaluatorOptions::COMPACT)
                .unwrap();
        for opts in ALL_OPTIONS {
            with_ev(&topo, opts, |ev| {
                for (k, &(f, s, u, v)) in pts.iter().enumerate() {
                    let a = ev.eval_second(f, s, u, v).unwrap();
                    let b = ev.eval(f, s, u, v).unwrap();
                    let c = ev.eval_f32(f, s, u as f32, v as f32).unwrap();
                    let got = (bits(&a), bits(&b), [c.p, c.du, c.dv, c.normal]);
                    assert_eq!(got, want_eval[k], "{path:?} {opts:?} at {:?}", pts[k]);
                }
                points += pts.len();
                let mut d = vec![0u32; ev.num_slots()];
                depths(ev, 1e-3 * diag, Method::Best, &mut d).unwrap();
                assert_eq!(d, want_depth, "{path:?} {opts:?} depths");
                assert_eq!(cell_bounds(ev), want_cells, "{path:?} {opts:?} cell bounds");
                for (e, want) in [0.05, 0.005].iter().zip(&want_tess) {
                    for keep in [Keep::ALL, Keep::LEAST] {
                        let got = tess_output(&topo, ev, e * diag, keep);
                        assert!(got == *want, "{path:?} {opts:?} {keep:?} tessellation {e}");
                        tess += 1;
                    }
                }
            });
        }
        shapes += 1;
    }
    assert!(shapes >= 20, "closed corpus shapes: {shapes}");
    println!(
        "{shapes} shapes, {points} points and {tess} tessellations bit for bit; evaluator \
         bytes {full_bytes} (default) vs {compact_bytes} (compact)"
    );
}

/// The cell bounds of a few dyadic cells of every slot, as bits.
fn cell_bounds(ev: &Evaluator) -> Vec<u64> {
    let mut out = vec![];
    for f in 0..ev.num_faces() {
        for sub in 0..ev.num_subfaces(f) {
            for (level, i, j) in [
                (0, 0, 0),
                (1, 0, 0),
                (2, 1, 0),
                (3, 0, 0),
                (3, 2, 3),
                (6, 0, 1),
            ] {
                let b = cell_bound(ev, f as u32, sub as u32, level, i, j).unwrap();
                out.extend([b.flatness, b.radius, b.rounding].map(f64::to_bits));
                out.extend(b.second.map(f64::to_bits));
            }
        }
    }
    out
}
