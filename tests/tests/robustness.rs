//! No input makes the core panic: random garbage meshes are accepted or
//! rejected with an error, and evaluation at extreme parameters (0, 1,
//! subnormals, points a hair away from an extraordinary vertex) returns
//! finite values.
use ccss_core::{Evaluator, MeshInput, Topology};
use ccss_tests::harness::{aligned, standard_tables, with_evaluator, XorShift};
use ccss_tests::reference::{drum, pole_mesh};

#[test]
fn garbage_meshes_never_panic() {
    let mut r = XorShift(0x1234_5678);
    let mut accepted = 0;
    for round in 0..3000 {
        let nv = (r.next_u64() % 12) as usize;
        let nf = (r.next_u64() % 10) as usize;
        let mut p: Vec<f64> = (0..3 * nv)
            .map(|_| (r.next_u64() % 1000) as f64 / 100.0)
            .collect();
        if round % 7 == 0 && !p.is_empty() {
            p[0] = f64::NAN;
        }
        let sizes: Vec<u32> = (0..nf).map(|_| (r.next_u64() % 6) as u32).collect();
        let total: u32 = sizes.iter().sum();
        let extra = if round % 5 == 0 { 1 } else { 0 };
        let idx: Vec<u32> = (0..total + extra)
            .map(|_| (r.next_u64() % (nv as u64 + 2)) as u32)
            .collect();
        let mesh = MeshInput {
            positions: &p,
            face_sizes: &sizes,
            indices: &idx,
        };
        let need = Topology::required_bytes(nv, &sizes);
        let mut mem = aligned(need + 8);
        if let Ok(t) = Topology::build(mesh, &mut mem) {
            accepted += 1;
            let tables = standard_tables();
            if let Ok(n) = Evaluator::required_bytes(&t, tables) {
                let mut em = aligned(n);
                if let Ok(ev) = Evaluator::build(&t, tables, &mut em) {
                    let _ = ev.eval(0, 0, 0.5, 0.5);
                }
            }
        }
    }
    // Random soups are almost never closed manifolds; the point is no panic.
    eprintln!("{accepted} of 3000 random meshes accepted");
}

#[test]
fn extreme_parameters_give_finite_results() {
    let ps = [
        0.0,
        1.0,
        0.5,
        f64::MIN_POSITIVE,
        5e-324,
        1e-300,
        1e-17,
        1.0 - 1e-16,
        0.25,
        0.75,
    ];
    for m in [pole_mesh(3), pole_mesh(5), pole_mesh(16), drum(7)] {
        with_evaluator(&m, standard_tables(), |_, ev| {
            for f in 0..m.faces.len() {
                for sub in 0..ev.num_subfaces(f) {
                    for &u in &ps {
                        for &v in &ps {
                            let e = ev.eval_second(f as u32, sub as u32, u, v).unwrap();
                            assert!(e.p.is_finite(), "face {f} sub {sub} ({u:e},{v:e}): {e:?}");
                            assert!(e.normal.is_finite() && e.du.is_finite() && e.dv.is_finite());
                            assert!(
                                (e.normal.length() - 1.0).abs() < 1e-9,
                                "unit normal at ({u:e},{v:e}): {e:?}"
                            );
                        }
                    }
                }
            }
        })
        .unwrap();
    }
}
