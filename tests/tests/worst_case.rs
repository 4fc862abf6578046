//! The worst-case rows of `docs/WORST_CASE.md` not backed elsewhere
//! (issue 27): each entry point reaches its cap or budget on an adversarial
//! input and stops with the documented error, with a bounded count of work
//! (times printed with `--nocapture` are only a generous sanity bound).
//!
//! * `tessellation_nodes_follow_the_level_budget`: `Uniform(L)` marks
//!   exactly `S (4^(L+1) - 1) / 3` nodes (the formula's worst case); an
//!   absolute tolerance far below what `max_level` can reach stops at the
//!   level cap with at most that many nodes tested; accepted tessellations
//!   stay below the formula at their deepest level.
//! * `feature_eval_next_to_irregular_corners_is_bounded`: parameters
//!   `5e-324` from the corners of every sub-face of creased, cornered and
//!   semi-sharp corpus shapes (the most local refinement steps an `f64`
//!   allows, `eval::MAX_STEPS`) evaluate to finite points.

use ccss_core::tessellate::{Criterion, Options, Scratch, Tessellation, MAX_NODES};
use ccss_core::Error;
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, with_evaluator, workspace_root};
use ccss_tests::reference::PolyMesh;
use ccss_tests::sharp::TaggedMesh;
use std::time::Instant;

#[test]
fn tessellation_nodes_follow_the_level_budget() {
    let dir = workspace_root().join("tests/data/osd");
    let m = PolyMesh::from_obj(&dir.join("catmark_torus.obj"));
    with_evaluator(&m, standard_tables(), |topo, ev| {
        let s = ev.num_slots();
        let mut scratch = Box::new(Scratch::ZERO);
        let formula = |l: u32| s * ((1usize << (2 * (l + 1))) - 1) / 3;
        for l in 0..=5u32 {
            let opts = Options::uniform(l);
            let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
            let mut mem = vec![0u64; ccss_core::mem::words_for(need)];
            let t = Tessellation::build(topo, ev, opts, &mut mem).unwrap();
            assert_eq!(t.stats().nodes, formula(l), "uniform {l}");
        }
        // A tolerance no level up to L reaches: stopped at the level cap,
        // promptly, for the size query and the build alike.
        for l in [4u32, 6, 8] {
            let opts = Options {
                criterion: Criterion::Absolute(1e-11),
                max_level: l,
            };
            let t0 = Instant::now();
            let r = Tessellation::required_bytes(topo, ev, &opts, &mut scratch);
            let secs = t0.elapsed().as_secs_f64();
            println!(
                "torus ({s} slots), eps 1e-11, max_level {l}: {r:?} in {secs:.3} s (cap {} nodes)",
                formula(l)
            );
            assert!(matches!(r, Err(Error::InvalidArgument(m)) if m.contains("max_level")));
            assert!(secs < 60.0);
        }
        // Accepted tessellations: nodes below the formula at their depth.
        for eps in [1e-2, 1e-3, 1e-4] {
            let opts = Options::absolute(eps);
            let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
            let mut mem = vec![0u64; ccss_core::mem::words_for(need)];
            let t = Tessellation::build(topo, ev, opts, &mut mem).unwrap();
            let st = t.stats();
            println!(
                "torus eps {eps:e}: {} nodes, deepest level {}, formula {}",
                st.nodes,
                st.max_level,
                formula(st.max_level)
            );
            assert!(st.nodes <= formula(st.max_level));
            assert!((st.nodes as u64) < MAX_NODES);
        }
    })
    .unwrap();
}

#[test]
fn feature_eval_next_to_irregular_corners_is_bounded() {
    let dir = workspace_root().join("tests/data/osd");
    let tiny = 5e-324;
    let near = [tiny, 1.0 - f64::EPSILON / 2.0];
    let mut worst = (0.0f64, String::new());
    let mut n = 0usize;
    for name in [
        "catmark_cube_creases2",
        "catmark_cube_corner4",
        "catmark_cubes_semisharp",
        "catmark_pyramid_creases2",
        "catmark_dart_edgecorner",
    ] {
        let m = TaggedMesh::from_obj(&dir.join(format!("{name}.obj"))).unwrap();
        let f = flat(&m);
        with_feature_mesh(&f, Some(standard_tables()), |fe| {
            for face in 0..fe.num_faces() {
                for sub in 0..fe.num_subfaces(face) {
                    for u in near {
                        for v in near {
                            let t0 = Instant::now();
                            let r = fe.eval(face as u32, sub as u32, u, v);
                            let dt = t0.elapsed().as_secs_f64();
                            match r {
                                Ok(e) => assert!(e.p.is_finite(), "{name} {face} {sub}"),
                                Err(Error::HoleFace { .. }) => {}
                                Err(e) => panic!("{name} {face} {sub} ({u:e}, {v:e}): {e}"),
                            }
                            n += 1;
                            if dt > worst.0 {
                                worst = (dt, format!("{name} face {face} sub {sub}"));
                            }
                        }
                    }
                }
            }
        })
        .unwrap();
    }
    println!(
        "{n} evaluations 5e-324 from sub-face corners: slowest {:.2} ms ({})",
        worst.0 * 1e3,
        worst.1
    );
    assert!(n > 100);
    assert!(worst.0 < 5.0);
}
