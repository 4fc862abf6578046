//! General vertex weights (alpha_n, beta_n, gamma_n), issue #3: standard
//! weights reproduce the standard tables bit for bit; three non-standard
//! weight sets match uniform subdivision with the same rule plus the general
//! limit mask (2.7) at dyadic points; eigenvalues equal the closed forms; the
//! eigen decomposition reconstructs the subdivision matrix to 1e-12.
use ccss_core::{BuildScratch, Error, TableSet, Weights, WeightsProblem, MAX_VALENCE};
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, standard_weights, PolyMesh, Refiner};
use std::path::Path;

/// The three non-standard rules of the test (valence 4 stays standard).
fn rule(set: usize, n: usize) -> (f64, f64, f64) {
    if n == 4 {
        return standard_weights(4);
    }
    match set {
        // One rule for every valence (complex frequency-0 pair).
        0 => (0.5, 0.3, 0.2),
        // Per-valence rule.
        1 => {
            let a = (0.3 + 0.04 * n as f64).min(0.8);
            (a, (1.0 - a) * 0.7, 1.0 - a - (1.0 - a) * 0.7)
        }
        // Heavier centre weight, no face term for odd valences.
        _ => {
            if n % 2 == 1 {
                (0.7, 0.3, 0.0)
            } else {
                (0.65, 0.25, 0.1)
            }
        }
    }
}

fn weights(set: usize) -> Weights {
    let mut w = Weights::STANDARD;
    for n in 3..=MAX_VALENCE {
        if n != 4 {
            let (a, b, g) = rule(set, n);
            w.set(n, a, b, g).unwrap();
        }
    }
    w
}

fn tables(w: &Weights) -> Box<TableSet> {
    let mut t = Box::new(TableSet::ZERO);
    t.build_into(w, &mut Box::new(BuildScratch::ZERO)).unwrap();
    t
}

#[test]
fn weights_are_validated() {
    let mut w = Weights::STANDARD;
    let e = |n, p| {
        Err(Error::InvalidWeights {
            valence: n,
            problem: p,
        })
    };
    assert_eq!(
        w.set(5, f64::NAN, 0.5, 0.5),
        e(5, WeightsProblem::NonFinite)
    );
    assert_eq!(w.set(5, 0.5, 0.6, -0.1), e(5, WeightsProblem::Negative));
    assert_eq!(w.set(5, 0.5, 0.3, 0.3), e(5, WeightsProblem::SumNotOne));
    assert_eq!(
        w.set(4, 0.5, 0.3, 0.2),
        e(4, WeightsProblem::RegularValence)
    );
    assert_eq!(
        w.set(2, 0.5, 0.3, 0.2),
        e(2, WeightsProblem::ValenceOutOfRange)
    );
    assert_eq!(w, Weights::STANDARD, "nothing changes on error");
    assert!(
        w.set(4, 9.0 / 16.0, 3.0 / 8.0, 1.0 / 16.0).is_ok(),
        "standard n = 4 is fine"
    );
    // Tangent-plane continuity is reported, not enforced.
    for n in 3..=MAX_VALENCE {
        assert!(
            Weights::STANDARD.tangent_plane_continuous(n),
            "standard n={n}"
        );
    }
    w.set(3, 0.95, 0.05, 0.0).unwrap();
    let (l0, _, _, _) = w.frequency0_eigenvalues(3);
    assert!(l0 > Weights::lambda2(3));
    assert!(!w.tangent_plane_continuous(3));
}

#[test]
fn standard_weights_reproduce_standard_tables_bit_for_bit() {
    let mut w = Weights::STANDARD;
    for n in 3..=MAX_VALENCE {
        let (a, b, g) = standard_weights(n);
        w.set(n, a, b, g).unwrap();
    }
    let t = tables(&w);
    let s = standard_tables();
    for n in 3..=MAX_VALENCE {
        let (x, y) = (t.get(n).unwrap(), s.get(n).unwrap());
        assert_eq!(x.eigenvalues(), y.eigenvalues());
        assert_eq!(x.limit_weights(), y.limit_weights());
        for c in 0..2 * n + 8 {
            assert_eq!(x.left_row(c), y.left_row(c));
        }
    }
    let m = pole_mesh(5);
    let a: Vec<_> = with_evaluator(&m, &t, |_, ev| {
        (0..m.faces.len())
            .map(|f| ev.eval(f as u32, 0, 0.3, 0.1).unwrap())
            .collect::<Vec<_>>()
    })
    .unwrap();
    let b: Vec<_> = with_evaluator(&m, s, |_, ev| {
        (0..m.faces.len())
            .map(|f| ev.eval(f as u32, 0, 0.3, 0.1).unwrap())
            .collect::<Vec<_>>()
    })
    .unwrap();
    assert_eq!(a, b);
}

#[test]
fn eigenvalues_limit_weights_and_reconstruction() {
    let mut scratch = Box::new(BuildScratch::ZERO);
    for set in 0..3 {
        let w = weights(set);
        let t = tables(&w);
        for n in 3..=MAX_VALENCE {
            let tab = t.get(n).unwrap();
            let k = 2 * n + 8;
            let (a, b, g) = w.get(n);
            // Closed forms ([CL-R §2.4]).
            let mut want: Vec<f64> = vec![1.0, 0.125, 0.0625, 0.03125, 0.015625];
            for om in 1..=n / 2 {
                let c = (2.0 * std::f64::consts::PI * om as f64 / n as f64).cos();
                let s = ((c + 1.0) * (c + 9.0)).sqrt();
                want.push((c + 5.0 + s) / 16.0);
                want.push((c + 5.0 - s) / 16.0);
            }
            let (r0, i0, r1, i1) = w.frequency0_eigenvalues(n);
            want.push((r0 * r0 + i0 * i0).sqrt());
            want.push((r1 * r1 + i1 * i1).sqrt());
            assert_eq!(tab.has_complex_pair(), i0 != 0.0);
            for &ev in tab.eigenvalues() {
                assert!(
                    want.iter().any(|x| (x - ev).abs() < 1e-12),
                    "set {set} n={n}: {ev} not a closed-form value"
                );
            }
            for x in &want {
                assert!(
                    tab.eigenvalues().iter().any(|ev| (x - ev).abs() < 1e-12),
                    "set {set} n={n}: {x} missing"
                );
            }
            // Limit point (2.7).
            let d = 5.0 + 14.0 * b + 16.0 * g;
            let lw = tab.limit_weights();
            assert!((lw[0] - 5.0 / d).abs() < 1e-12);
            for i in 0..n {
                assert!((lw[1 + 2 * i] - (12.0 * b + 8.0 * g) / (n as f64 * d)).abs() < 1e-12);
                assert!((lw[2 + 2 * i] - (2.0 * b + 8.0 * g) / (n as f64 * d)).abs() < 1e-12);
            }
            let _ = a;
            // A = L^-1 (B L): invert L independently (Gauss-Jordan, partial pivoting).
            let amat = *scratch.subdivision_matrix(n, &w);
            let l: Vec<Vec<f64>> = (0..k).map(|c| tab.left_row(c).to_vec()).collect();
            let bl: Vec<Vec<f64>> = (0..k)
                .map(|c| (0..k).map(|j| tab.b_times_left(c, j)).collect())
                .collect();
            let linv = invert(&l);
            let mut worst = 0.0f64;
            for i in 0..k {
                for j in 0..k {
                    let s: f64 = (0..k).map(|c| linv[i][c] * bl[c][j]).sum();
                    worst = worst.max((s - amat[i][j]).abs());
                }
            }
            assert!(
                worst < 1e-12,
                "set {set} n={n}: reconstruction error {worst:e}"
            );
        }
    }
}

fn invert(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let k = m.len();
    let mut a: Vec<Vec<f64>> = m.to_vec();
    let mut inv: Vec<Vec<f64>> = (0..k)
        .map(|i| (0..k).map(|j| (i == j) as u8 as f64).collect())
        .collect();
    for c in 0..k {
        let p = (c..k)
            .max_by(|&x, &y| a[x][c].abs().partial_cmp(&a[y][c].abs()).unwrap())
            .unwrap();
        a.swap(c, p);
        inv.swap(c, p);
        let d = a[c][c];
        for j in 0..k {
            a[c][j] /= d;
            inv[c][j] /= d;
        }
        for r in 0..k {
            if r != c {
                let f = a[r][c];
                for j in 0..k {
                    a[r][j] -= f * a[c][j];
                    inv[r][j] -= f * inv[c][j];
                }
            }
        }
    }
    inv
}

fn check_dyadic(set: usize, name: &str, m: &PolyMesh, faces: &[usize], k: u32) -> f64 {
    let w = weights(set);
    let t = tables(&w);
    let wf = move |n: usize| rule(set, n);
    let mut r = Refiner::new(m, Some(&wf));
    let diag = m.bbox_diagonal();
    let n = 1u32 << k;
    let mut worst = 0.0f64;
    with_evaluator(m, &t, |_, ev| {
        for &f in faces {
            for sub in 0..ev.num_subfaces(f) {
                for i in 0..=n {
                    for j in 0..=n {
                        let want = r.dyadic_limit_point(f, sub, i, j, k);
                        let got = ev
                            .eval(
                                f as u32,
                                sub as u32,
                                i as f64 / n as f64,
                                j as f64 / n as f64,
                            )
                            .unwrap()
                            .p;
                        let d = ((got.x - want[0]).powi(2)
                            + (got.y - want[1]).powi(2)
                            + (got.z - want[2]).powi(2))
                        .sqrt();
                        worst = worst.max(d / diag);
                        assert!(
                            d <= 1e-12 * diag,
                            "set {set} {name}: face {f} sub {sub} ({i},{j})/2^{k}: err {d:e}"
                        );
                    }
                }
            }
        }
    })
    .unwrap();
    worst
}

#[test]
fn dyadic_points_match_weighted_subdivision() {
    for set in 0..3 {
        let mut report = Vec::new();
        for n in [3usize, 5, 6, 7, 8, 12] {
            let m = pole_mesh(n);
            let poles = [5 * n as u32, 5 * n as u32 + 1];
            let faces: Vec<usize> = (0..m.faces.len())
                .filter(|&f| m.faces[f].iter().any(|v| poles.contains(v)))
                .collect();
            let w = check_dyadic(
                set,
                &format!("pole_mesh({n})"),
                &m,
                &faces,
                if n > 8 { 3 } else { 4 },
            );
            report.push(format!("n={n} {w:.1e}"));
        }
        let d = drum(5);
        let w = check_dyadic(
            set,
            "drum(5)",
            &d,
            &(0..d.faces.len()).collect::<Vec<_>>(),
            3,
        );
        report.push(format!("drum(5) {w:.1e}"));
        let cube = PolyMesh::from_obj(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd/catmark_cube.obj"),
        );
        let w = check_dyadic(set, "cube", &cube, &(0..6).collect::<Vec<_>>(), 4);
        report.push(format!("cube {w:.1e}"));
        eprintln!("weights set {set}: max err/diag {}", report.join(", "));
    }
}

#[test]
fn tangent_plane_at_ev_with_general_weights() {
    let w = weights(0);
    let t = tables(&w);
    for n in [3usize, 5, 7] {
        let m = pole_mesh(n);
        let pole = 5 * n as u32;
        with_evaluator(&m, &t, |_, ev| {
            for (f, face) in m.faces.iter().enumerate() {
                let Some(k) = face.iter().position(|&v| v == pole) else {
                    continue;
                };
                let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k];
                let at = ev.eval(f as u32, 0, c.0, c.1).unwrap();
                let e = 1e-150;
                let near = ev
                    .eval(
                        f as u32,
                        0,
                        if c.0 == 0.0 { e } else { 1.0 - e },
                        if c.1 == 0.0 { e } else { 1.0 - e },
                    )
                    .unwrap();
                assert!(
                    (at.normal - near.normal).length() < 1e-9,
                    "n={n}: {:?} vs {:?}",
                    at.normal,
                    near.normal
                );
            }
        })
        .unwrap();
    }
}
