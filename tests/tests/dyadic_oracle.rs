//! Exact evaluation against the independent oracle: at dyadic parameters
//! (i/2^k, j/2^k), k <= 4, the library's limit position must equal the limit
//! mask applied to the k-times uniformly subdivided mesh (reference
//! subdivider in `ccss_tests::reference`), to 1e-12 of the bounding-box
//! diagonal. Covers valences 3, 5, 6, 7, 8, 12 and MAX_VALENCE, triangles,
//! pentagons and other n-gons, and the closed untagged corpus shapes.
use ccss_core::MAX_VALENCE;
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, PolyMesh, Refiner};
use std::path::Path;

fn corpus(name: &str) -> PolyMesh {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/osd")
        .join(name);
    PolyMesh::from_obj(&p)
}

/// Checks dyadic points of the given faces (all sub-faces) at level `k`;
/// returns (max error / diagonal, number of points).
fn check_mesh(name: &str, m: &PolyMesh, faces: &[usize], k: u32) -> (f64, usize) {
    let diag = m.bbox_diagonal();
    let mut r = Refiner::new(m, None);
    let mut worst = 0.0f64;
    let mut count = 0usize;
    let n = 1u32 << k;
    with_evaluator(m, standard_tables(), |_, ev| {
        for &f in faces {
            for sub in 0..ev.num_subfaces(f) {
                for i in 0..=n {
                    for j in 0..=n {
                        let want = r.dyadic_limit_point(f, sub, i, j, k);
                        let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                        let got = ev.eval(f as u32, sub as u32, u, v).unwrap().p;
                        let d = ((got.x - want[0]).powi(2)
                            + (got.y - want[1]).powi(2)
                            + (got.z - want[2]).powi(2))
                        .sqrt();
                        worst = worst.max(d / diag);
                        count += 1;
                        assert!(
                            d <= 1e-12 * diag,
                            "{name}: face {f} sub {sub} ({u},{v}) k={k}: got {got:?} want {want:?} (err {d:e})"
                        );
                    }
                }
            }
        }
    })
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    (worst, count)
}

fn all_faces(m: &PolyMesh) -> Vec<usize> {
    (0..m.faces.len()).collect()
}

#[test]
fn pole_meshes_all_required_valences() {
    let mut report = Vec::new();
    for n in [3usize, 5, 6, 7, 8, 12, MAX_VALENCE] {
        let m = pole_mesh(n);
        // Faces around the two poles (valence n) plus a few others.
        let poles = [5 * n as u32, 5 * n as u32 + 1];
        let mut faces: Vec<usize> = (0..m.faces.len())
            .filter(|&f| m.faces[f].iter().any(|v| poles.contains(v)))
            .collect();
        faces.extend([0, m.faces.len() / 2, m.faces.len() - 1]);
        faces.sort();
        faces.dedup();
        assert!(faces
            .iter()
            .any(|&f| m.faces[f].iter().any(|&v| m.valence(v) == n)));
        let k = if n > 8 { 3 } else { 4 };
        let (w, c) = check_mesh(&format!("pole_mesh({n})"), &m, &faces, k);
        report.push(format!("n={n}: {c} points, max err/diag {w:.2e}"));
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn drums_ngon_faces_use_internal_refinement() {
    // N-gon caps (sub-faces), and side quads with two extraordinary vertices.
    for n in [3usize, 5, 6] {
        let m = drum(n);
        let (w, c) = check_mesh(&format!("drum({n})"), &m, &all_faces(&m), 3);
        eprintln!("drum({n}): {c} points, max err/diag {w:.2e}");
    }
}

#[test]
fn corpus_closed_shapes() {
    for (name, k) in [
        ("catmark_cube.obj", 4),
        ("catmark_pyramid.obj", 4),
        ("catmark_torus.obj", 3),
        ("catmark_toroidal_tet.obj", 3),
    ] {
        let m = corpus(name);
        let (w, c) = check_mesh(name, &m, &all_faces(&m), k);
        eprintln!("{name}: {c} points, max err/diag {w:.2e}");
    }
    // The larger shapes: a sample of faces (all valences 3, 4, 5 occur).
    for name in ["catmark_righthanded.obj", "catmark_lefthanded.obj"] {
        let m = corpus(name);
        let faces: Vec<usize> = (0..m.faces.len()).step_by(23).collect();
        let (w, c) = check_mesh(name, &m, &faces, 2);
        eprintln!("{name}: {c} points, max err/diag {w:.2e}");
    }
}
