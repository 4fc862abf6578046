//! The cache tree of `FeatureEvaluator` (`FeatureCache`): points answered
//! from the deep tree equal the local refinement that answers them without
//! it (`FeatureCache { depth: 0, .. }`: every level-1 face that is not a
//! B-spline refined at each query, the path `feature_eval.rs` checks
//! against the sharp reference), at points drawn towards the corners of
//! every sub-face, with distances `2^-k` for `k` up to 30; and the size
//! query is exact and the node budget holds.
use ccss_core::eval::{FeatureCache, Query};
use ccss_core::mem::words_for;
use ccss_core::mesh::features::FeatureMesh;
use ccss_core::{Error, FeatureEvaluator, MeshInput};
use ccss_tests::feature_input::{eval_gap, flat, with_feature_caches};
use ccss_tests::harness::{standard_tables, workspace_root, XorShift};
use ccss_tests::sharp::TaggedMesh;

/// Shapes with boundaries, creases (infinitely sharp and semi-sharp,
/// uniform and Chaikin), corners, darts, holes, valence 2 and extraordinary
/// vertices.
const SHAPES: [&str; 12] = [
    "catmark_edgecorner",
    "catmark_edgeonly",
    "catmark_dart_edgeonly",
    "catmark_dart_edgecorner",
    "catmark_cube_creases1",
    "catmark_cube_corner4",
    "catmark_chaikin1",
    "catmark_hole_test1",
    "catmark_val2_interior",
    "catmark_xord_boundary",
    "catmark_pyramid_creases1",
    "catmark_tent_creases1",
];

const NO_TREE: FeatureCache = FeatureCache {
    depth: 0,
    nodes_per_face: 0,
};

fn tagged(name: &str) -> TaggedMesh {
    let path = workspace_root().join(format!("tests/data/osd/{name}.obj"));
    TaggedMesh::from_obj(&path).unwrap()
}

#[test]
fn tree_equals_local_refinement_near_special_vertices() {
    let mut rng = XorShift(24);
    let (mut total, mut from_tree) = (0usize, 0usize);
    let (mut worst_p, mut worst_d) = (0.0f64, 0.0f64);
    for name in SHAPES {
        let m = tagged(name);
        let diag = m.bbox_diagonal();
        let f = flat(&m);
        let caches = [FeatureCache::default(), NO_TREE];
        with_feature_caches(&f, Some(standard_tables()), caches, |tree, local| {
            for face in 0..tree.num_faces() {
                for sub in 0..tree.num_subfaces(face) {
                    for corner in 0..4 {
                        for _ in 0..6 {
                            // Distance 2^-k (k in 0..30) from the corner.
                            let k = (rng.next_u64() % 31) as i32;
                            let r = 0.5f64.powi(k);
                            let a = rng.unit() * r;
                            let b = rng.unit() * r;
                            let (u, v) = match corner {
                                0 => (a, b),
                                1 => (1.0 - a, b),
                                2 => (1.0 - a, 1.0 - b),
                                _ => (a, 1.0 - b),
                            };
                            let q = Query {
                                face: face as u32,
                                sub: sub as u32,
                                u,
                                v,
                            };
                            if tree.check(&q).is_err() {
                                continue;
                            }
                            let (fa, sa) = (face as u32, sub as u32);
                            let got = tree.eval_second(fa, sa, u, v).unwrap();
                            let want = local.eval_second(fa, sa, u, v).unwrap();
                            total += 1;
                            if tree.is_cached(&q) && !local.is_cached(&q) {
                                from_tree += 1;
                            }
                            let (dp, dd, which) = eval_gap(&got, &want, diag);
                            assert!(
                                dp <= 1e-12,
                                "{name} face {face}.{sub} ({u}, {v}): {dp:e} of the diagonal"
                            );
                            assert!(
                                dd <= 1e-9,
                                "{name} face {face}.{sub} ({u}, {v}): {which} {dd:e} apart"
                            );
                            worst_p = worst_p.max(dp);
                            worst_d = worst_d.max(dd);
                        }
                    }
                }
            }
        })
        .unwrap();
    }
    eprintln!(
        "{total} points, {from_tree} from the tree only; max {worst_p:.1e} of the diagonal, \
         derivatives {worst_d:.1e}"
    );
    // Not vacuous: many points are answered by the tree where the plain
    // evaluator refines locally.
    assert!(from_tree * 10 >= total, "{from_tree} of {total}");
}

#[test]
fn size_query_is_exact_and_the_node_budget_holds() {
    for name in [
        "catmark_cube_creases1",
        "catmark_dart_edgeonly",
        "catmark_chaikin1",
    ] {
        let m = tagged(name);
        let f = flat(&m);
        let mesh = MeshInput {
            positions: &f.p,
            face_sizes: &f.sizes,
            indices: &f.idx,
        };
        let tags = ccss_core::mesh::features::FeatureInput {
            crease_vertices: &f.cv,
            crease_sharpness: &f.cs,
            corner_vertices: &f.kv,
            corner_sharpness: &f.ks,
            holes: &f.holes,
            options: f.opts,
        };
        let mut mem = vec![0u64; words_for(FeatureMesh::required_bytes(&mesh).unwrap())];
        let fm = FeatureMesh::build(&mesh, &tags, &mut mem).unwrap();
        let tables = Some(standard_tables());
        let mut last = 0;
        for depth in [0, 2, 6, 12, 16] {
            for budget in [4, 64] {
                let c = FeatureCache {
                    depth,
                    nodes_per_face: budget,
                };
                let need = FeatureEvaluator::required_bytes_with(&fm, tables, c);
                assert_eq!(need % 8, 0);
                let mut short = vec![0u64; need / 8 - 1];
                match FeatureEvaluator::build_with(&fm, tables, c, &mut short) {
                    Err(Error::BufferTooSmall { required }) => assert_eq!(required, need),
                    other => panic!("{name}: {other:?}"),
                }
                let mut exact = vec![0u64; need / 8];
                let ev = FeatureEvaluator::build_with(&fm, tables, c, &mut exact).unwrap();
                let counts = ev.cache_counts();
                assert!(counts.nodes <= counts.split_faces * budget as usize);
                if budget == 64 {
                    assert!(need >= last, "{name}: depth {depth} needs less than before");
                    last = need;
                }
                eprintln!("{name}: depth {depth}, budget {budget}: {need} bytes, {counts:?}");
            }
        }
        // Depths above the maximum count as the maximum.
        let deep = |depth| {
            FeatureEvaluator::required_bytes_with(
                &fm,
                tables,
                FeatureCache {
                    depth,
                    nodes_per_face: 64,
                },
            )
        };
        assert_eq!(deep(40), deep(ccss_core::eval::MAX_CACHE_DEPTH));
    }
}
