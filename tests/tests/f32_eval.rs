//! `Evaluator::eval_f32` against `Evaluator::eval` (f64) on every closed
//! corpus shape: dense random points per slot, the slot corners and points
//! next to the extraordinary vertices (where the f64 eigen expansion
//! takes over). Errors are relative to the diagonal of the control-point
//! box: position max and RMS, derivatives relative to their f64 size,
//! normals as angles. Issue #29's target: positions within 1e-5 of the
//! diagonal. `cargo test --test f32_eval -- --nocapture` prints the figures.

use ccss_tests::harness::{corpus_shapes, standard_tables, validate, with_evaluator, XorShift};
use ccss_tests::reference::PolyMesh;

#[test]
fn f32_evaluation_within_1e5_of_the_diagonal() {
    let mut rng = XorShift(0x2545_f491_4f6c_dd1d);
    let (mut worst_p, mut sum2, mut count) = (0.0f64, 0.0f64, 0usize);
    let (mut worst_d, mut worst_n) = (0.0f64, 0.0f64);
    let mut shapes = 0;
    for path in corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        if validate(&m).is_err() {
            continue;
        }
        let diag = m.bbox_diagonal();
        let r = with_evaluator(&m, standard_tables(), |_, ev| {
            let mut local = (0.0f64, 0.0f64, 0usize, 0.0f64, 0.0f64);
            for f in 0..ev.num_faces() {
                for s in 0..ev.num_subfaces(f) {
                    let mut pts: Vec<(f32, f32)> = vec![
                        (0.0, 0.0),
                        (1.0, 0.0),
                        (0.0, 1.0),
                        (1.0, 1.0),
                        (0.5, 0.5),
                        (0.2, 0.1),
                        (0.01, 0.003),
                        (1e-5, 2e-5),
                        (0.25, 0.1),
                        (0.249, 0.0),
                    ];
                    for _ in 0..40 {
                        pts.push((rng.unit() as f32, rng.unit() as f32));
                    }
                    for (u, v) in pts {
                        let a = ev.eval_f32(f as u32, s as u32, u, v).unwrap();
                        let b = ev.eval(f as u32, s as u32, u as f64, v as f64).unwrap();
                        let d = |x: [f32; 3], y: ccss_core::DVec3| {
                            ((x[0] as f64 - y.x).powi(2)
                                + (x[1] as f64 - y.y).powi(2)
                                + (x[2] as f64 - y.z).powi(2))
                            .sqrt()
                        };
                        let ep = d(a.p, b.p) / diag;
                        local.0 = local.0.max(ep);
                        local.1 += ep * ep;
                        local.2 += 1;
                        for (x, y) in [(a.du, b.du), (a.dv, b.dv)] {
                            let size = y.length().max(1e-300);
                            if size > 1e-6 * diag {
                                local.3 = local.3.max(d(x, y) / size);
                            }
                        }
                        local.4 = local.4.max(d(a.normal, b.normal));
                    }
                }
            }
            local
        })
        .unwrap();
        worst_p = worst_p.max(r.0);
        sum2 += r.1;
        count += r.2;
        worst_d = worst_d.max(r.3);
        worst_n = worst_n.max(r.4);
        shapes += 1;
    }
    let rms = (sum2 / count as f64).sqrt();
    eprintln!(
        "f32 vs f64 over {shapes} shapes, {count} points: position max {worst_p:.3e}, RMS {rms:.3e} \
         of the diagonal; derivatives max {worst_d:.3e} relative; normals max {worst_n:.3e}"
    );
    assert!(shapes >= 10, "only {shapes} closed corpus shapes");
    assert!(
        worst_p <= 1e-5,
        "position error {worst_p:e} of the diagonal"
    );
    assert!(worst_d <= 1e-4, "derivative error {worst_d:e}");
    assert!(worst_n <= 1e-4, "normal error {worst_n:e}");
}
