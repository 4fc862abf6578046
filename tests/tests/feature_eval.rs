//! Exact evaluation of meshes with boundaries, creases, corners and holes
//! (`ccss_core::FeatureEvaluator`) against the sharp reference subdivider
//! (`ccss_tests::sharp`, itself checked against OpenSubdiv in
//! `sharp_reference.rs`): at dyadic points of every sub-face of the corpus
//! shapes, positions equal uniform subdivision plus exact limit masks to
//! 1e-12 of the bounding-box diagonal. On closed smooth meshes it also
//! equals the eigen-table evaluator (positions and derivatives).
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{
    corpus_shapes as corpus, standard_tables, with_evaluator, workspace_root as root, XorShift,
};
use ccss_tests::reference::PolyMesh;
use ccss_tests::sharp::{SharpRefiner, TaggedMesh};

fn dist(a: [f64; 3], b: ccss_core::DVec3) -> f64 {
    ((a[0] - b.x).powi(2) + (a[1] - b.y).powi(2) + (a[2] - b.z).powi(2)).sqrt()
}

#[test]
fn dyadic_points_equal_the_sharp_reference_on_the_corpus() {
    let mut shapes = 0;
    let mut points = 0usize;
    let mut refused = Vec::new();
    let mut worst_all = 0.0f64;
    for path in corpus() {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let m = TaggedMesh::from_obj(&path).unwrap();
        let Ok(mut r) = SharpRefiner::new(&m) else {
            refused.push(name);
            continue;
        };
        let corners: usize = m.faces.iter().map(|f| f.len()).sum();
        // Level of the dyadic grid: finer on small shapes.
        // Very high valence or many-faced edges: every local step is
        // expensive on both sides (O(size^2) scans), so sample fewer faces.
        let l0 = r.level(0);
        let heavy =
            l0.vert_faces.iter().any(|f| f.len() > 32) || l0.edge_faces.iter().any(|f| f.len() > 4);
        let k: u32 = if heavy {
            1
        } else if corners <= 400 {
            3
        } else {
            2
        };
        let stride = if heavy {
            m.faces.len().div_ceil(6)
        } else if corners > 4000 {
            7
        } else {
            1
        };
        let diag = m.bbox_diagonal();
        let f = flat(&m);
        let level0 = r.level(0).clone();
        let res = with_feature_mesh(&f, Some(standard_tables()), |ev| {
            let mut worst = 0.0f64;
            let mut n = 0usize;
            let (mut t_ref, mut t_lib) = (0.0f64, 0.0f64);
            for face in (0..m.faces.len()).step_by(stride) {
                if level0.hole[face] {
                    let e = ev.eval(face as u32, 0, 0.5, 0.5).unwrap_err();
                    assert_eq!(e, ccss_core::Error::HoleFace { face: face as u32 });
                    continue;
                }
                let subs = if m.faces[face].len() == 4 {
                    1
                } else {
                    m.faces[face].len()
                };
                for sub in 0..subs {
                    for i in 0..=(1u32 << k) {
                        for j in 0..=(1u32 << k) {
                            let t0 = std::time::Instant::now();
                            let want = r.dyadic_limit_point(face, sub, i, j, k);
                            t_ref += t0.elapsed().as_secs_f64();
                            let t0 = std::time::Instant::now();
                            let (u, v) =
                                (i as f64 / (1u32 << k) as f64, j as f64 / (1u32 << k) as f64);
                            let got = match ev.eval(face as u32, sub as u32, u, v) {
                                Ok(g) => g,
                                Err(e @ ccss_core::Error::NeighbourhoodTooLarge { .. }) => {
                                    return Err(e)
                                }
                                Err(e) => panic!("{name} face {face}.{sub} ({u},{v}): {e}"),
                            };
                            t_lib += t0.elapsed().as_secs_f64();
                            let d = dist(want, got.p) / diag;
                            assert!(
                                d <= 1e-12,
                                "{name}: face {face}.{sub} at ({u}, {v}): {:?} vs reference {want:?} ({d:e} of the diagonal)",
                                got.p
                            );
                            worst = worst.max(d);
                            n += 1;
                        }
                    }
                }
            }
            eprintln!("  {name}: reference {t_ref:.2} s, library {t_lib:.3} s");
            Ok((worst, n))
        });
        match res.and_then(|r| r) {
            Ok((worst, n)) => {
                eprintln!("{name}: {n} dyadic points (k = {k}), max {worst:.1e} of the diagonal");
                worst_all = worst_all.max(worst);
                points += n;
                shapes += 1;
            }
            Err(e) => refused.push(format!("{name}: {e}")),
        }
    }
    eprintln!(
        "{shapes} shapes, {points} points, max {worst_all:.1e}; refused {}: {refused:?}",
        refused.len()
    );
    assert!(shapes >= 83, "only {shapes} shapes evaluated");
}

#[test]
fn smooth_closed_meshes_match_the_eigen_evaluator() {
    let tables = standard_tables();
    for name in [
        "catmark_torus",
        "catmark_pyramid",
        "catmark_toroidal_tet",
        "catmark_cube",
    ] {
        let path = root().join(format!("tests/data/osd/{name}.obj"));
        let pm = PolyMesh::from_obj(&path);
        let tm = TaggedMesh::from_obj(&path).unwrap();
        assert!(tm.creases.is_empty() && tm.corners.is_empty());
        let f = flat(&tm);
        let diag = tm.bbox_diagonal();
        // PolyMesh renumbers vertices by first use; both keep face order and
        // each face's corner order, so (face, sub, u, v) names the same point.
        with_evaluator(&pm, tables, |_, ev| {
            with_feature_mesh(&f, Some(standard_tables()), |fe| {
                let mut rng = XorShift(0x9e3779b97f4a7c15);
                for face in 0..tm.faces.len() {
                    let subs = if tm.faces[face].len() == 4 {
                        1
                    } else {
                        tm.faces[face].len()
                    };
                    for sub in 0..subs {
                        for _ in 0..6 {
                            let (u, v) = (rng.unit(), rng.unit());
                            let a = ev.eval(face as u32, sub as u32, u, v).unwrap();
                            let b = fe.eval(face as u32, sub as u32, u, v).unwrap();
                            assert!(
                                (a.p - b.p).length() <= 1e-12 * diag,
                                "{name} {face}.{sub} ({u},{v}): {:?} vs {:?}",
                                a.p,
                                b.p
                            );
                            let scale = a.du.length().max(a.dv.length()).max(1e-300);
                            assert!(
                                (a.du - b.du).length() <= 1e-9 * scale
                                    && (a.dv - b.dv).length() <= 1e-9 * scale,
                                "{name} {face}.{sub} ({u},{v}): derivatives {:?} {:?} vs {:?} {:?}",
                                a.du,
                                a.dv,
                                b.du,
                                b.dv
                            );
                        }
                    }
                }
            })
            .unwrap()
        })
        .unwrap();
    }
}

/// First and second derivatives against central differences of the
/// (exact) positions (evaluator without eigen tables: every irregular
/// piece by local refinement), at random points of every face of the corpus shapes
/// with creases, corners, boundaries or holes. Points within 1e-3 of a face
/// edge are skipped: differences across a sharp edge or a patch boundary of
/// a refined piece are not smooth there.
#[test]
fn derivatives_match_finite_differences_on_the_corpus() {
    let mut checked = 0usize;
    for path in corpus() {
        let m = TaggedMesh::from_obj(&path).unwrap();
        if m.creases.is_empty() && m.corners.is_empty() && m.holes.is_empty() {
            let closed = SharpRefiner::new(&m)
                .map(|mut r| r.level(0).edge_faces.iter().all(|f| f.len() == 2))
                .unwrap_or(false);
            if closed {
                continue; // smooth closed meshes: compared with the eigen evaluator
            }
        }
        let f = flat(&m);
        let diag = m.bbox_diagonal();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let res = with_feature_mesh(&f, None, |ev| {
            let mut rng = XorShift(0x2545f4914f6cdd1d);
            let mut n = 0;
            let faces = m.faces.len();
            for face in (0..faces).step_by(faces.div_ceil(40)) {
                let subs = if m.faces[face].len() == 4 {
                    1
                } else {
                    m.faces[face].len()
                };
                for sub in 0..subs {
                    let (u, v) = (0.001 + 0.998 * rng.unit(), 0.001 + 0.998 * rng.unit());
                    let q = |u: f64, v: f64| ev.eval_second(face as u32, sub as u32, u, v);
                    let Ok(e) = q(u, v) else { continue }; // holes
                    let h = 1e-6;
                    let pu = (q(u + h, v).unwrap().p - q(u - h, v).unwrap().p) / (2.0 * h);
                    let pv = (q(u, v + h).unwrap().p - q(u, v - h).unwrap().p) / (2.0 * h);
                    let duu = (q(u + h, v).unwrap().du - q(u - h, v).unwrap().du) / (2.0 * h);
                    let dvv = (q(u, v + h).unwrap().dv - q(u, v - h).unwrap().dv) / (2.0 * h);
                    let scale = e.du.length().max(e.dv.length()).max(1e-3 * diag);
                    assert!(
                        (pu - e.du).length() <= 1e-6 * scale
                            && (pv - e.dv).length() <= 1e-6 * scale,
                        "{name} {face}.{sub} ({u},{v}): du {:?} vs {pu:?}, dv {:?} vs {pv:?}",
                        e.du,
                        e.dv
                    );
                    let s2 = e.duu.length().max(e.dvv.length()).max(scale);
                    assert!(
                        (duu - e.duu).length() <= 1e-5 * s2 && (dvv - e.dvv).length() <= 1e-5 * s2,
                        "{name} {face}.{sub} ({u},{v}): duu {:?} vs {duu:?}, dvv {:?} vs {dvv:?}",
                        e.duu,
                        e.dvv
                    );
                    n += 1;
                }
            }
            n
        });
        if let Ok(n) = res {
            checked += n;
        }
    }
    eprintln!("derivatives checked at {checked} points");
    assert!(checked > 1000, "only {checked} points");
}
