//! Similarity-based interpolation (`CL-R` ch. 4) against independent
//! oracles: the reference subdivider and limit masks of
//! `tests/src/reference.rs` for the interpolation conditions, the library's
//! exact evaluator on `Q` and `G` for similarity and folds.

use ccss_core::interpolate::{
    derivative, FoldRemoval, InterpolationOptions, Interpolator, Preconditioner, Prescribed,
    Requirement, SolveStats,
};
use ccss_core::{BuildScratch, DVec3, Error, MeshInput, TableSet, Topology, Weights};
use ccss_tests::harness::{aligned, flatten, standard_tables, with_evaluator, workspace_root};
use ccss_tests::reference::{self, PolyMesh};

struct Run {
    g: PolyMesh,
    q: PolyMesh,
    naive: PolyMesh,
    stats: SolveStats,
}

fn mesh_of(positions: &[f64], like: &PolyMesh) -> PolyMesh {
    PolyMesh {
        positions: positions.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        faces: like.faces.clone(),
    }
}

/// The solve of `ccss interpolate` (assembled normal matrix).
fn interpolate(p: &PolyMesh, tables: &TableSet, opts: InterpolationOptions) -> Result<Run, Error> {
    interpolate_with(p, tables, opts, &[])
}

fn interpolate_with(
    p: &PolyMesh,
    tables: &TableSet,
    opts: InterpolationOptions,
    reqs: &[Requirement],
) -> Result<Run, Error> {
    interpolate_path(p, tables, opts, reqs, true)
}

/// `assemble`: multiply with the assembled normal matrix, else face by
/// face (the matrix-free path, the oracle of the assembled one).
fn interpolate_path(
    p: &PolyMesh,
    tables: &TableSet,
    opts: InterpolationOptions,
    reqs: &[Requirement],
    assemble: bool,
) -> Result<Run, Error> {
    let (pos, sizes, idx) = flatten(p);
    let mut tmem = aligned(Topology::required_bytes(pos.len() / 3, &sizes));
    let topo = Topology::build(
        MeshInput {
            positions: &pos,
            face_sizes: &sizes,
            indices: &idx,
        },
        &mut tmem,
    )?;
    let need = Interpolator::required_bytes(&topo, reqs);
    assert!(matches!(
        Interpolator::build(&topo, tables, opts, reqs, &mut aligned(need - 8)),
        Err(Error::BufferTooSmall { required }) if required == need
    ));
    let mut mem = aligned(need);
    // Both blocks outlive the interpolator (its lifetime).
    let (mut short, mut mat);
    let mut it = Interpolator::build(&topo, tables, opts, reqs, &mut mem)?;
    if assemble {
        let need = it.assembled_bytes();
        short = aligned(need - 8);
        assert!(matches!(
            it.assemble(&mut short),
            Err(Error::BufferTooSmall { required }) if required == need
        ));
        mat = aligned(need);
        it.assemble(&mut mat)?;
    }
    let m = it.num_vertices();
    assert_eq!(m, Interpolator::num_vertices_for(&topo));
    let gt = it.subdivided();
    let faces: Vec<Vec<u32>> = gt
        .face_sizes()
        .iter()
        .scan(0usize, |o, &s| {
            let f = gt.indices()[*o..*o + s as usize].to_vec();
            *o += s as usize;
            Some(f)
        })
        .collect();
    let g = PolyMesh {
        positions: gt
            .positions()
            .chunks(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        faces,
    };
    let mut naive = vec![0.0; 3 * m];
    it.naive_into(&mut naive)?;
    let mut out = vec![0.0; 3 * m];
    assert!(matches!(
        it.solve(&mut out[..3 * m - 1], &mut |_, _| {}),
        Err(Error::BufferTooSmall { required }) if required == 3 * m
    ));
    let stats = it.solve(&mut out, &mut |_, _| {})?;
    Ok(Run {
        q: mesh_of(&out, &g),
        naive: mesh_of(&naive, &g),
        g,
        stats,
    })
}

fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(&workspace_root().join(format!("tests/data/osd/{name}.obj")))
}

/// Test meshes: name and mesh (closed, valences 3..=6, n-gons).
fn meshes() -> Vec<(String, PolyMesh)> {
    let mut v = vec![
        ("cube".to_string(), corpus("catmark_cube")),
        ("pyramid".to_string(), corpus("catmark_pyramid")),
        ("toroidal_tet".to_string(), corpus("catmark_toroidal_tet")),
        ("torus".to_string(), corpus("catmark_torus")),
        ("drum5".to_string(), reference::drum(5)),
        ("pole7".to_string(), reference::pole_mesh(7)),
        ("torus_8x6".to_string(), reference::torus(8, 6, 2.0, 0.7)),
    ];
    v.push(("lefthanded".to_string(), corpus("catmark_lefthanded")));
    v
}

/// The reference subdivider's G equals the interpolator's G corner by corner
/// (vertex points and face points share numbers; edge points are compared
/// through the faces).
fn check_g(p: &PolyMesh, g: &PolyMesh, diag: f64) {
    let r = reference::catmull_clark(p);
    assert_eq!(r.faces.len(), g.faces.len());
    for (fr, fg) in r.faces.iter().zip(&g.faces) {
        for (&a, &b) in fr.iter().zip(fg) {
            let (x, y) = (r.positions[a as usize], g.positions[b as usize]);
            let d = (0..3).map(|k| (x[k] - y[k]).abs()).fold(0.0, f64::max);
            assert!(d <= 1e-13 * diag, "G differs from the reference by {d}");
        }
    }
}

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// Largest distance between the limit points of Q's Type I vertices (the
/// reference limit mask) and P's vertices, relative to P's diagonal.
fn interpolation_error(p: &PolyMesh, q: &PolyMesh, w: Option<&reference::Weights>) -> f64 {
    let diag = p.bbox_diagonal();
    (0..p.positions.len())
        .map(|i| {
            let l = match w {
                None => reference::limit_position(q, i as u32),
                Some(w) => reference::limit_position_weighted(q, i as u32, w),
            };
            (v3(l) - v3(p.positions[i])).length() / diag
        })
        .fold(0.0, f64::max)
}

/// Independent similarity measures through the library evaluator on Q and G
/// at `k x k` points of every face: (sum of |dQ x dG|^2 over du, dv, duu, dvv
/// with each kind scaled by its RMS over G, RMS angle in degrees between
/// the first derivatives, number of points with n_Q . n_G <= 0).
fn similarity(q: &PolyMesh, g: &PolyMesh, tables: &TableSet, k: usize) -> (f64, f64, usize) {
    similarity_on(q, g, tables, k, &|_| true)
}

/// Faces of G with two extraordinary corners (the solver leaves them
/// unsampled).
fn single_patch(g: &PolyMesh, f: u32) -> bool {
    g.faces[f as usize]
        .iter()
        .filter(|&&v| g.valence(v) != 4)
        .count()
        <= 1
}

/// [`similarity`] over the faces `keep` accepts (RMS scales over those).
fn similarity_on(
    q: &PolyMesh,
    g: &PolyMesh,
    tables: &TableSet,
    k: usize,
    keep: &dyn Fn(u32) -> bool,
) -> (f64, f64, usize) {
    let pts: Vec<(u32, f64, f64)> = (0..g.faces.len() as u32)
        .filter(|&f| keep(f))
        .flat_map(|f| {
            (0..k).flat_map(move |i| {
                (0..k).map(move |j| (f, i as f64 / (k - 1) as f64, j as f64 / (k - 1) as f64))
            })
        })
        .collect();
    let eval_all = |m: &PolyMesh| {
        with_evaluator(m, tables, |_, ev| {
            pts.iter()
                .map(|&(f, u, v)| ev.eval_second(f, 0, u, v).expect("eval"))
                .collect::<Vec<_>>()
        })
        .expect("evaluator")
    };
    let (eq, eg) = (eval_all(q), eval_all(g));
    let kinds = |e: &ccss_core::Eval| [e.du, e.dv, e.duu, e.dvv];
    // One scale for du and dv, one for duu and dvv (as the solver).
    let mut rms = [0.0; 4];
    for e in &eg {
        for (c, d) in kinds(e).iter().enumerate() {
            rms[c / 2 * 2] += d.length_squared() / (2 * eg.len()) as f64;
        }
    }
    rms[1] = rms[0];
    rms[3] = rms[2];
    let (mut obj, mut ang2, mut nang, mut folds) = (0.0, 0.0, 0usize, 0usize);
    for (a, b) in eq.iter().zip(&eg) {
        for (c, (x, y)) in kinds(a).iter().zip(kinds(b)).enumerate() {
            if rms[c] > 0.0 {
                obj += x.cross(y).length_squared() / rms[c];
            }
            if c < 2 && x.length() > 0.0 && y.length() > 0.0 {
                let t = x.angle_between(y).to_degrees();
                ang2 += t * t;
                nang += 1;
            }
        }
        if a.normal.dot(b.normal) <= 0.0 {
            folds += 1;
        }
    }
    (obj, (ang2 / nang as f64).sqrt(), folds)
}

#[test]
fn limit_points_of_type1_vertices_are_the_input_vertices() {
    let tables = standard_tables();
    for (name, p) in meshes() {
        let run = interpolate(&p, tables, InterpolationOptions::default()).expect(&name);
        check_g(&p, &run.g, p.bbox_diagonal());
        let e = interpolation_error(&p, &run.q, None);
        let en = interpolation_error(&p, &run.naive, None);
        let eg = interpolation_error(&p, &run.g, None);
        println!("{name}: interpolation error {e:.2e} (naive {en:.2e}; G itself {eg:.2e})");
        assert!(e <= 1e-12 && en <= 1e-12, "{name}: {e} / {en}");
        assert!(
            eg > 1e-4,
            "{name}: G already interpolates ({eg}), test is vacuous"
        );
    }
}

#[test]
fn solution_is_more_similar_than_naive_and_has_no_folds() {
    let tables = standard_tables();
    // catmark_lefthanded (a thin stepped plate) is left out here: it needs
    // fold rounds, checked with its timing in `folds_dense_check`.
    for (name, p) in meshes().into_iter().filter(|(n, _)| n != "lefthanded") {
        let run = interpolate(&p, tables, InterpolationOptions::default()).expect(&name);
        let s = run.stats;
        // Converged, and the (4.5) residual went down.
        assert!(s.objective < s.naive_objective, "{name}: {s:?}");
        assert!(
            s.final_residual <= 1e-6 * s.initial_residual,
            "{name}: {s:?}"
        );
        // Independent measure at the 9 samples and on a denser 5x5 grid.
        let (oq, aq, fq) = similarity(&run.q, &run.g, tables, 3);
        let (on, an, _) = similarity(&run.naive, &run.g, tables, 3);
        let (oq5, _, fq5) = similarity(&run.q, &run.g, tables, 5);
        let (on5, _, _) = similarity(&run.naive, &run.g, tables, 5);
        println!(
            "{name}: {} iterations; residual (4.5) at samples {oq:.3e} vs naive {on:.3e} \
             (ratio {:.3}); 5x5 grid ratio {:.3}; RMS angle {aq:.2} deg vs naive {an:.2}; folds {fq}/{fq5}",
            s.iterations,
            oq / on,
            oq5 / on5
        );
        // The solver's objective and the evaluator's agree (same samples:
        // the faces of G that are single patches).
        let two_ev = (0..run.g.faces.len() as u32)
            .filter(|&f| !single_patch(&run.g, f))
            .count();
        let keep = |f: u32| single_patch(&run.g, f);
        let (os, _, _) = similarity_on(&run.q, &run.g, tables, 3, &keep);
        let (ons, _, _) = similarity_on(&run.naive, &run.g, tables, 3, &keep);
        println!(
            "{name}: {two_ev} of {} faces of G unsampled (two extraordinary corners)",
            run.g.faces.len()
        );
        assert!(
            (ons - s.naive_objective).abs() <= 1e-9 * ons,
            "{name}: evaluator naive objective {ons} vs solver {}",
            s.naive_objective
        );
        assert!(
            (os - s.objective).abs() <= 1e-9 * ons,
            "{name}: evaluator objective {os} vs solver {}",
            s.objective
        );
        assert!(oq < 0.9 * on, "{name}: not measurably better: {oq} vs {on}");
        assert!(oq5 < on5, "{name}: worse between samples: {oq5} vs {on5}");
        assert_eq!(fq + fq5, 0, "{name}: folds");
    }
}

#[test]
fn general_weights_go_through_the_same_tables() {
    let mut w = Weights::STANDARD;
    w.set(3, 0.45, 0.4, 0.15).unwrap();
    w.set(5, 0.5, 0.35, 0.15).unwrap();
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&w, &mut Box::new(BuildScratch::ZERO))
        .unwrap();
    let rule = move |n: usize| w.get(n);
    for (name, p) in [
        ("cube", corpus("catmark_cube")),
        ("pole5", reference::pole_mesh(5)),
        ("drum5", reference::drum(5)),
    ] {
        let run = interpolate(&p, &tables, InterpolationOptions::default()).unwrap();
        let r = reference::catmull_clark_weighted(&p, &rule);
        for (fr, fg) in r.faces.iter().zip(&run.g.faces) {
            for (&a, &b) in fr.iter().zip(fg) {
                let d = (v3(r.positions[a as usize]) - v3(run.g.positions[b as usize])).length();
                assert!(d <= 1e-13 * p.bbox_diagonal(), "{name}: weighted G differs");
            }
        }
        let e = interpolation_error(&p, &run.q, Some(&rule));
        let e_std = interpolation_error(&p, &run.q, None);
        println!(
            "{name}: weighted interpolation error {e:.2e} (standard mask would give {e_std:.2e})"
        );
        assert!(e <= 1e-12, "{name}: {e}");
        assert!(e_std > 1e-6, "{name}: weights had no effect");
        let (oq, _, fq) = similarity(&run.q, &run.g, &tables, 3);
        let (on, _, _) = similarity(&run.naive, &run.g, &tables, 3);
        assert!(oq < 0.9 * on && fq == 0, "{name}: {oq} vs {on}, folds {fq}");
    }
}

#[test]
fn solvers_agree_and_options_are_checked() {
    let tables = standard_tables();
    let p = reference::pole_mesh(5);
    let base = InterpolationOptions {
        tolerance: 1e-10,
        ..Default::default()
    };
    let a = interpolate(&p, tables, base).unwrap();
    let b = interpolate(
        &p,
        tables,
        InterpolationOptions {
            preconditioner: Preconditioner::None,
            ..base
        },
    )
    .unwrap();
    println!("block Jacobi {:?}\nplain CG {:?}", a.stats, b.stats);
    let d =
        a.q.positions
            .iter()
            .zip(&b.q.positions)
            .map(|(x, y)| (v3(*x) - v3(*y)).length())
            .fold(0.0, f64::max);
    assert!(d <= 1e-6 * p.bbox_diagonal(), "solutions differ by {d}");
    assert!((a.stats.objective - b.stats.objective).abs() <= 1e-9 * a.stats.naive_objective);
    // Iteration limit: a clear error.
    let e = interpolate(
        &p,
        tables,
        InterpolationOptions {
            max_iterations: 2,
            ..base
        },
    );
    assert!(
        matches!(e, Err(Error::NotConverged { iterations: 2 })),
        "{:?}",
        e.err()
    );
    for bad in [0.0, -1.0, f64::NAN, 1.0] {
        let e = interpolate(
            &p,
            tables,
            InterpolationOptions {
                tolerance: bad,
                ..base
            },
        );
        assert!(matches!(e, Err(Error::InvalidArgument(_))));
    }
    let e = interpolate(
        &p,
        tables,
        InterpolationOptions {
            derivatives: 0,
            ..base
        },
    );
    assert!(matches!(e, Err(Error::InvalidArgument(_))));
    // Only first derivatives also works.
    let f = interpolate(
        &p,
        tables,
        InterpolationOptions {
            derivatives: derivative::FIRST,
            ..base
        },
    )
    .unwrap();
    assert!(f.stats.objective < f.stats.naive_objective);
}

/// The assembled normal matrix against the matrix-free products (the old
/// path): at a tight tolerance both solves reach the same minimiser, with
/// either preconditioner; at the default tolerance they agree to the
/// accuracy the stopping rule allows. Meshes with valences 3..7, n-gons
/// (unsampled faces of G) and the hand.
#[test]
fn assembled_matrix_agrees_with_the_matrix_free_products() {
    let tables = standard_tables();
    let mut shapes = meshes();
    shapes.push(("pole3".to_string(), reference::pole_mesh(3)));
    // Genus 2, 1182 vertices (bench/data/gen_polycube.py, refined twice).
    shapes.push((
        "genus2_polycube".to_string(),
        PolyMesh::from_obj(&workspace_root().join("bench/data/genus2_polycube.obj")),
    ));
    for (name, p) in shapes {
        let diag = p.bbox_diagonal();
        let differ = |a: &Run, b: &Run| {
            a.q.positions
                .iter()
                .zip(&b.q.positions)
                .map(|(x, y)| (v3(*x) - v3(*y)).length())
                .fold(0.0, f64::max)
                / diag
        };
        for tol in [1e-11, 1e-6] {
            // Without fold rounds: the orientation rows are added by the
            // same matrix-free code on both paths, and the rounds' loose
            // solves make the comparison depend on where a round stops
            // (measured with the rounds on the hand at 1e-11: 14,424
            // iterations on both paths, solutions within 1.2e-9 of the
            // diagonal, objectives within 5e-11 of the naive one).
            let opts = InterpolationOptions {
                tolerance: tol,
                preconditioner: Preconditioner::BlockJacobi,
                fold_rounds: 0,
                ..Default::default()
            };
            let old = interpolate_path(&p, tables, opts, &[], false).expect(&name);
            let bj = interpolate_path(&p, tables, opts, &[], true).expect(&name);
            let sgs = interpolate_path(
                &p,
                tables,
                InterpolationOptions {
                    preconditioner: Preconditioner::SymmetricGaussSeidel,
                    ..opts
                },
                &[],
                true,
            )
            .expect(&name);
            let (d_bj, d_sgs) = (differ(&old, &bj), differ(&old, &sgs));
            let obj = |r: &Run| r.stats.objective;
            let rel = |r: &Run| (obj(r) - obj(&old)).abs() / old.stats.naive_objective;
            println!(
                "{name} tol {tol:e}: iterations matrix-free {} / assembled {} / SGS {}; \
                 max |Q - Q_old| / diag {d_bj:.1e} / SGS {d_sgs:.1e}; objective {:.6e} \
                 (assembled {:.1e}, SGS {:.1e} relative to naive)",
                old.stats.iterations,
                bj.stats.iterations,
                sgs.stats.iterations,
                obj(&old),
                rel(&bj),
                rel(&sgs)
            );
            for r in [&bj, &sgs] {
                let e = interpolation_error(&p, &r.q, None);
                assert!(e <= 1e-12, "{name}: interpolation error {e}");
            }
            if tol < 1e-9 {
                assert!(d_bj <= 1e-7 && d_sgs <= 1e-7, "{name}: {d_bj} {d_sgs}");
                assert!(rel(&bj) <= 1e-12 && rel(&sgs) <= 1e-12, "{name}");
            } else {
                // The stopping rule bounds the residual, not the distance:
                // the objectives agree to the reported 7 digits.
                assert!(rel(&bj) <= 1e-7 && rel(&sgs) <= 1e-7, "{name}");
            }
        }
    }
}

#[test]
fn degenerate_input_is_an_error() {
    let mut p = corpus("catmark_cube");
    for x in &mut p.positions {
        *x = [1.0, 2.0, 3.0];
    }
    let e = interpolate(&p, standard_tables(), InterpolationOptions::default());
    assert!(matches!(e, Err(Error::InvalidArgument(m)) if m.contains("degenerate")));
    let mut p = corpus("catmark_cube");
    p.positions[3][1] = f64::NAN;
    let e = interpolate(&p, standard_tables(), InterpolationOptions::default());
    assert!(matches!(e, Err(Error::NonFiniteCoordinate { vertex: 3 })));
}

#[test]
#[ignore]
/// Measurement, not a check: `MU=0.1 KINDS=6 cargo test --release -p
/// ccss-tests --test interpolate sweep -- --ignored --nocapture` (`KINDS`:
/// bits of `derivative`, default first | second).
fn sweep_parallel_weight() {
    let tables = standard_tables();
    let mu: f64 = std::env::var("MU").map_or(0.0, |m| m.parse().expect("MU"));
    let kinds: u8 = std::env::var("KINDS").map_or(derivative::FIRST | derivative::SECOND, |m| {
        m.parse().expect("KINDS")
    });
    for (name, p) in meshes() {
        let run = interpolate(
            &p,
            tables,
            InterpolationOptions {
                parallel_weight: mu,
                derivatives: kinds,
                fold_rounds: std::env::var("ROUNDS").map_or(8, |m| m.parse().expect("ROUNDS")),
                fold_weight: std::env::var("FW").map_or(0.01, |m| m.parse().expect("FW")),
                ..Default::default()
            },
        )
        .unwrap();
        let (oq, aq, fq) = similarity(&run.q, &run.g, tables, 3);
        let (on, an, _) = similarity(&run.naive, &run.g, tables, 3);
        let (_, _, f9) = similarity(&run.q, &run.g, tables, 9);
        println!(
            "SWEEP mu={mu} kinds={kinds} {name}: it {} ratio {:.3} angle {aq:.2} (naive {an:.2}) folds {fq} (9x9: {f9}) rounds {} anchored {}",
            run.stats.iterations,
            oq / on,
            run.stats.fold_rounds,
            run.stats.anchored_faces
        );
    }
}

/// Folds on a 9 x 9 grid of every face of `G` (81 points per face against
/// the solver's 7 x 7 orientation rows and fold count), faces
/// with two extraordinary corners included (the library evaluator handles
/// them through sub-faces): none on any of the 8 meshes, `catmark_lefthanded`
/// included, whose solve without fold rounds (`fold_rounds = 0`) has 8,232;
/// on the hand also none on a 17 x 17 grid (between the 9 x 9 points). The
/// (4.5) residual stays well below the naive one and interpolation exact.
#[test]
fn folds_dense_check() {
    let tables = standard_tables();
    let mut total_before = 0;
    for (name, p) in meshes() {
        let t = std::time::Instant::now();
        let run = interpolate(&p, tables, InterpolationOptions::default()).expect(&name);
        let secs = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let plain = interpolate(
            &p,
            tables,
            InterpolationOptions {
                fold_rounds: 0,
                ..Default::default()
            },
        )
        .expect(&name);
        let secs0 = t.elapsed().as_secs_f64();
        let (oq, aq, fq) = similarity(&run.q, &run.g, tables, 9);
        let (o0, a0, f0) = similarity(&plain.q, &run.g, tables, 9);
        let (on, an, fnv) = similarity(&run.naive, &run.g, tables, 9);
        let (oq3, _, _) = similarity(&run.q, &run.g, tables, 3);
        let (on3, _, _) = similarity(&run.naive, &run.g, tables, 3);
        let s = run.stats;
        println!(
            "{name}: folds {fq} of {} points (without fold rounds {f0}, naive {fnv}); \
             (4.5) ratio to naive {:.3} at the samples, {:.3} on the 9x9 grid (without fold \
             rounds {:.3}); RMS angle {aq:.2} deg (without {a0:.2}, naive {an:.2}); \
             {} rounds, {} orientation rows, {} iterations (without {}), {:.2} s (without {:.2} s)",
            81 * run.g.faces.len(),
            oq3 / on3,
            oq / on,
            o0 / on,
            s.fold_rounds,
            s.orientation_rows,
            s.iterations,
            plain.stats.iterations,
            secs,
            secs0
        );
        total_before += f0;
        // The faces the solver leaves unsampled (two extraordinary
        // corners): their own (4.5) ratio and folds.
        let two_ev = |f: u32| !single_patch(&run.g, f);
        if (0..run.g.faces.len() as u32).any(two_ev) {
            let (ot, _, ft) = similarity_on(&run.q, &run.g, tables, 9, &two_ev);
            let (ont, _, _) = similarity_on(&run.naive, &run.g, tables, 9, &two_ev);
            println!(
                "{name}: unsampled faces (two extraordinary corners): (4.5) ratio {:.3}, folds {ft}",
                ot / ont
            );
        }
        assert_eq!(fq, 0, "{name}: folds");
        assert_eq!(s.folds, 0, "{name}: solver reports folds");
        if name == "lefthanded" {
            let f17 = folds_per_face(&run.q, &run.g, tables, 17)
                .iter()
                .sum::<usize>();
            println!(
                "{name}: folds {f17} of {} points at 17 x 17",
                289 * run.g.faces.len()
            );
            assert_eq!(f17, 0, "{name}: folds between the 9 x 9 points");
        }
        assert!(oq3 < 0.5 * on3, "{name}: {oq3} vs naive {on3}");
        let e = interpolation_error(&p, &run.q, None);
        assert!(e <= 1e-12, "{name}: interpolation error {e}");
    }
    // The check can fail: without the rounds the hand folds.
    assert!(total_before > 0, "no mesh folds without the fold rounds");
}

/// The solver's fold count (`SolveStats::folds`) equals an independent
/// count through the library evaluator (`eval_second` normals of `Q` and
/// `G`) at the same points of the faces the solver samples: on the default
/// grid (7 x 7, the orientation grid, from the tabulated derivative
/// weights) and on a 5 x 5 grid (patch evaluation point by point). One
/// fold round on `catmark_lefthanded` leaves folds to count.
#[test]
fn fold_count_matches_the_evaluator() {
    let tables = standard_tables();
    let p = corpus("catmark_lefthanded");
    for grid in [7u32, 5] {
        let run = interpolate(
            &p,
            tables,
            InterpolationOptions {
                fold_rounds: 1,
                fold_grid: grid,
                ..Default::default()
            },
        )
        .unwrap();
        let per = folds_per_face(&run.q, &run.g, tables, grid as usize);
        let expected: usize = per
            .iter()
            .enumerate()
            .filter(|&(f, _)| single_patch(&run.g, f as u32))
            .map(|(_, &c)| c)
            .sum();
        println!(
            "grid {grid}: solver {} folds, evaluator {expected}",
            run.stats.folds
        );
        assert!(expected > 0, "grid {grid}: nothing to count");
        assert_eq!(run.stats.folds as usize, expected, "grid {grid}");
    }
}

#[test]
fn extra_requirements_are_met_and_conflicts_are_named() {
    let tables = standard_tables();
    let p = reference::pole_mesh(7);
    let diag = p.bbox_diagonal();
    let base = interpolate(&p, tables, InterpolationOptions::default()).unwrap();
    // Requirements relative to G's limit surface: moved points, tilted
    // normals, on regular and extraordinary patches.
    let g_eval = |f: u32, u: f64, v: f64| {
        with_evaluator(&base.g, tables, |_, ev| ev.eval(f, 0, u, v).unwrap()).unwrap()
    };
    let ev_face = (0..base.g.faces.len() as u32)
        .find(|&f| {
            base.g.faces[f as usize]
                .iter()
                .any(|&v| base.g.valence(v) == 7)
        })
        .unwrap();
    let mut reqs = Vec::new();
    for (f, u, v) in [(3u32, 0.3, 0.7), (ev_face, 0.25, 0.1), (100, 0.5, 0.5)] {
        let e = g_eval(f, u, v);
        let t = e.p + e.normal * (0.02 * diag);
        reqs.push(Requirement {
            face: f,
            u,
            v,
            what: Prescribed::Position(t.to_array()),
        });
    }
    for (f, u, v) in [(40u32, 0.5, 0.5), (ev_face, 0.6, 0.3), (150, 0.0, 1.0)] {
        let e = g_eval(f, u, v);
        let n = (e.normal + e.du.normalize() * 0.2).normalize();
        reqs.push(Requirement {
            face: f,
            u,
            v,
            what: Prescribed::Normal(n.to_array()),
        });
    }
    let run = interpolate_with(&p, tables, InterpolationOptions::default(), &reqs).unwrap();
    let q_evals: Vec<_> = with_evaluator(&run.q, tables, |_, ev| {
        reqs.iter()
            .map(|r| ev.eval(r.face, 0, r.u, r.v).unwrap())
            .collect()
    })
    .unwrap();
    let (mut worst_p, mut worst_n) = (0.0f64, 0.0f64);
    for (r, e) in reqs.iter().zip(&q_evals) {
        match r.what {
            Prescribed::Position(t) => worst_p = worst_p.max((e.p - v3(t)).length() / diag),
            Prescribed::Normal(n) => {
                worst_n = worst_n.max(e.normal.cross(v3(n).normalize()).length())
            }
        }
    }
    let e = interpolation_error(&p, &run.q, None);
    println!(
        "requirements: position error {worst_p:.2e} of the diagonal, normal sine {worst_n:.2e}; \
         interpolation {e:.2e}; {} iterations; (4.5) residual {:.3e} (without requirements {:.3e})",
        run.stats.iterations, run.stats.objective, base.stats.objective
    );
    assert!(worst_p <= 1e-10 && worst_n <= 1e-10 && e <= 1e-12);
    let (_, _, folds) = similarity(&run.q, &run.g, tables, 3);
    assert_eq!(folds, 0);

    // Conflicts.
    let opts = InterpolationOptions::default();
    let pos = |f: u32, u: f64, v: f64, t: [f64; 3]| Requirement {
        face: f,
        u,
        v,
        what: Prescribed::Position(t),
    };
    let a = pos(3, 0.3, 0.7, [0.1, 0.2, 0.3]);
    let b = pos(3, 0.3, 0.7, [0.1, 0.2, 0.4]);
    let e = interpolate_with(&p, tables, opts, &[a, b]).err();
    assert_eq!(e, Some(Error::ConflictingRequirement { requirement: 1 }));
    // The same requirement twice is redundant, not a conflict.
    assert!(interpolate_with(&p, tables, opts, &[a, a]).is_ok());
    // Corner 0 of a face of G is a Type I vertex: its limit is P's vertex.
    let v0 = base.g.faces[3][0] as usize;
    let moved = [
        p.positions[v0][0] + 0.01 * diag,
        p.positions[v0][1],
        p.positions[v0][2],
    ];
    let e = interpolate_with(&p, tables, opts, &[pos(3, 0.0, 0.0, moved)]).err();
    assert_eq!(e, Some(Error::ConflictingRequirement { requirement: 0 }));
    assert!(interpolate_with(&p, tables, opts, &[pos(3, 0.0, 0.0, p.positions[v0])]).is_ok());
    // Two different normals at one point: linearly consistent (both
    // tangents along their cross product) but no surface has them.
    let nrm = |n: [f64; 3]| Requirement {
        face: 40,
        u: 0.5,
        v: 0.5,
        what: Prescribed::Normal(n),
    };
    let e = interpolate_with(
        &p,
        tables,
        opts,
        &[nrm([0.0, 0.0, 1.0]), nrm([1.0, 0.0, 0.0])],
    )
    .err();
    assert!(
        matches!(e, Some(Error::ConflictingRequirement { .. })),
        "{e:?}"
    );
    // Bad requirement values and places.
    let e = interpolate_with(&p, tables, opts, &[pos(3, 0.5, 0.5, [f64::NAN, 0.0, 0.0])]).err();
    assert_eq!(e, Some(Error::ConflictingRequirement { requirement: 0 }));
    let e = interpolate_with(&p, tables, opts, &[pos(100_000, 0.5, 0.5, [0.0; 3])]).err();
    assert_eq!(e, Some(Error::FaceOutOfRange { face: 100_000 }));
    let e = interpolate_with(&p, tables, opts, &[pos(3, 1.5, 0.5, [0.0; 3])]).err();
    assert_eq!(e, Some(Error::ParameterOutOfRange));
}

/// Options from the environment (measurements): `ROUNDS`, `FW` (first
/// weight), `MODE` (`anchors` or `orientation`).
fn env_options() -> InterpolationOptions {
    let d = InterpolationOptions::default();
    InterpolationOptions {
        fold_rounds: std::env::var("ROUNDS").map_or(d.fold_rounds, |m| m.parse().expect("ROUNDS")),
        fold_weight: std::env::var("FW").map_or(d.fold_weight, |m| m.parse().expect("FW")),
        fold_margin: std::env::var("MARGIN").map_or(d.fold_margin, |m| m.parse().expect("MARGIN")),
        fold_removal: match std::env::var("MODE").as_deref() {
            Ok("anchors") => FoldRemoval::Anchors,
            Ok("orientation") => FoldRemoval::Orientation,
            _ => d.fold_removal,
        },
        ..d
    }
}

/// Per face of `G`: points of a `k x k` grid where `n_Q . n_G <= 0`.
fn folds_per_face(q: &PolyMesh, g: &PolyMesh, tables: &TableSet, k: usize) -> Vec<usize> {
    let normals = |m: &PolyMesh| {
        with_evaluator(m, tables, |_, ev| {
            let mut out = Vec::new();
            for f in 0..g.faces.len() as u32 {
                for i in 0..k {
                    for j in 0..k {
                        let (u, v) = (i as f64 / (k - 1) as f64, j as f64 / (k - 1) as f64);
                        out.push(ev.eval_second(f, 0, u, v).expect("eval").normal);
                    }
                }
            }
            out
        })
        .expect("evaluator")
    };
    let (nq, ng) = (normals(q), normals(g));
    let mut per = vec![0; g.faces.len()];
    for (i, (a, b)) in nq.iter().zip(&ng).enumerate() {
        if a.dot(*b) <= 0.0 {
            per[i / (k * k)] += 1;
        }
    }
    per
}

/// One face of `G` in [`folds_where`]: (folded points, face, Type I corner,
/// its valence, face of `P`, largest dihedral angle, smallest corner cos,
/// gap over the local edge).
type FaceRow = (usize, usize, u32, usize, usize, f64, f64, f64);

/// Newell normal of a polygon of `P`.
fn face_normal(p: &PolyMesh, f: &[u32]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, &a) in f.iter().enumerate() {
        let b = f[(i + 1) % f.len()];
        n += v3(p.positions[a as usize]).cross(v3(p.positions[b as usize]));
    }
    n
}

/// Diagnosis, not a check: where the hand's remaining folds are
/// (`cargo test --release -p ccss-tests --test interpolate folds_where --
/// --ignored --nocapture`). Per face of `G` with a folded point of the
/// 9 x 9 grid: its Type I corner (valence), the face of `P` it lies in,
/// that face's largest dihedral angle to its neighbours, its corner
/// normals against its Newell normal (a folded or twisted `P` face), and
/// the gap `|P_v - limit_G(v)|` over the mean edge length at `v`.
#[test]
#[ignore]
fn folds_where() {
    let tables = standard_tables();
    let p = corpus("catmark_lefthanded");
    let opts = env_options();
    let t = std::time::Instant::now();
    let run = interpolate(&p, tables, opts).unwrap();
    let secs = t.elapsed().as_secs_f64();
    let per = folds_per_face(&run.q, &run.g, tables, 9);
    let (oq, aq, _) = similarity(&run.q, &run.g, tables, 3);
    let (on, an, _) = similarity(&run.naive, &run.g, tables, 3);
    println!(
        "{opts:?}\n{:?}\nsolve {secs:.2} s (test build, load {}); ratio {:.3}, RMS angle {aq:.2} (naive {an:.2}); interpolation error {:.2e}",
        run.stats,
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim(),
        oq / on,
        interpolation_error(&p, &run.q, None)
    );
    let n1 = p.positions.len() as u32;
    let nf = p.faces.len() as u32;
    let ne = run.g.positions.len() as u32 - n1 - nf;
    // Edges of P -> faces.
    let mut edge_faces = std::collections::HashMap::<(u32, u32), Vec<usize>>::new();
    for (fi, f) in p.faces.iter().enumerate() {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            edge_faces.entry((a.min(b), a.max(b))).or_default().push(fi);
        }
    }
    let dihedral = |fi: usize| {
        let f = &p.faces[fi];
        let n = face_normal(&p, f).normalize();
        let mut worst: f64 = 0.0;
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            for &o in &edge_faces[&(a.min(b), a.max(b))] {
                if o != fi {
                    let m = face_normal(&p, &p.faces[o]).normalize();
                    worst = worst.max(n.dot(m).clamp(-1.0, 1.0).acos().to_degrees());
                }
            }
        }
        worst
    };
    let twist = |fi: usize| {
        let f = &p.faces[fi];
        let n = face_normal(&p, f).normalize();
        let mut worst: f64 = 1.0;
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            let c = f[(i + f.len() - 1) % f.len()];
            let pa = v3(p.positions[a as usize]);
            let cn = (v3(p.positions[b as usize]) - pa)
                .cross(v3(p.positions[c as usize]) - pa)
                .normalize();
            worst = worst.min(cn.dot(n));
        }
        worst
    };
    let gap = |v: u32| {
        let l = v3(reference::limit_position(&run.g, v));
        let pv = v3(p.positions[v as usize]);
        let mut len = 0.0;
        let mut cnt = 0.0;
        for f in &p.faces {
            for (i, &a) in f.iter().enumerate() {
                if a == v {
                    len += (v3(p.positions[f[(i + 1) % f.len()] as usize]) - pv).length();
                    cnt += 1.0;
                }
            }
        }
        (pv - l).length() / (len / cnt)
    };
    let mut rows = Vec::new();
    for (gf, &c) in per.iter().enumerate() {
        let quad = &run.g.faces[gf];
        let v = quad[0];
        assert!(v < n1);
        let pf = (quad[2] - n1 - ne) as usize;
        rows.push((c, gf, v, p.valence(v), pf, dihedral(pf), twist(pf), gap(v)));
    }
    let (fold, clean): (Vec<_>, Vec<_>) = rows.iter().partition(|r| r.0 > 0);
    let stats = |set: &[&FaceRow], name: &str| {
        let n = set.len() as f64;
        let mean = |f: &dyn Fn(&FaceRow) -> f64| set.iter().map(|r| f(r)).sum::<f64>() / n;
        let ev = set.iter().filter(|r| r.3 != 4).count();
        println!(
            "{name}: {} faces of G; mean dihedral of P's face {:.1} deg, mean min corner cos {:.3}, \
             twisted (corner cos < 0.5) {}, mean gap/edge {:.3}, extraordinary corner {ev}",
            set.len(),
            mean(&|r| r.5),
            mean(&|r| r.6),
            set.iter().filter(|r| r.6 < 0.5).count(),
            mean(&|r| r.7),
        );
    };
    stats(&fold, "folded");
    stats(&clean, "not folded");
    let mut pfaces: Vec<usize> = fold.iter().map(|r| r.4).collect();
    pfaces.sort_unstable();
    pfaces.dedup();
    println!(
        "folded points {} on {} faces of G in {} faces of P",
        fold.iter().map(|r| r.0).sum::<usize>(),
        fold.len(),
        pfaces.len()
    );
    let mut top = fold.clone();
    top.sort_by_key(|r| std::cmp::Reverse(r.0));
    for r in top.iter().take(25) {
        println!(
            "G face {:5} folds {:2}/81  P vertex {:4} (valence {})  P face {:4}  dihedral {:6.1}  corner cos {:6.3}  gap/edge {:.2}  at {:?}",
            r.1, r.0, r.2, r.3, r.4, r.5, r.6, r.7, p.positions[r.2 as usize]
        );
    }
}
