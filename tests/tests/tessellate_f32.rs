//! `Tessellation::emit_f32` against `Tessellation::emit` (f64) on every
//! closed corpus shape (absolute flatness 1e-3 of the diagonal): the same
//! polygons, and every f32 vertex within the f32 vertex error of the f64
//! vertex (`vertex_error_f32` plus the f64 rounding term once more, for
//! the f64 vertex's own rounding; see `core/src/tessellate/single.rs`).
//! Zero violations; `-- --nocapture` prints the tightness (largest
//! actual error / allowed) and the errors relative to the diagonal.

use ccss_core::bounds::rounding;
use ccss_core::tessellate::{Options, Output, OutputF32, Scratch, Tessellation};
use ccss_core::Query;
use ccss_tests::harness::{aligned, corpus_shapes, standard_tables, validate, with_evaluator};
use ccss_tests::reference::PolyMesh;

#[test]
fn f32_vertices_within_the_f32_error_term() {
    let (mut worst_ratio, mut worst_rel, mut vertices, mut shapes) = (0.0f64, 0.0f64, 0usize, 0);
    let mut term_rel = 0.0f64;
    for path in corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        if validate(&m).is_err() {
            continue;
        }
        let diag = m.bbox_diagonal();
        let r = with_evaluator(&m, standard_tables(), |topo, ev| {
            let opts = Options::absolute(1e-3 * diag);
            let mut scratch = Box::new(Scratch::ZERO);
            let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
            let mut mem = aligned(need);
            let mut t = Tessellation::build(topo, ev, opts, &mut mem).unwrap();
            let c = t.counts();
            let mut pos = vec![0.0f64; 3 * c.vertices];
            let mut par = vec![Query::default(); c.vertices];
            let (mut sz, mut ix, mut tr) = (
                vec![0u32; c.polygons],
                vec![0u32; c.polygon_indices],
                vec![0u32; 3 * c.triangles],
            );
            t.emit(Output {
                positions: &mut pos,
                normals: None,
                params: Some(&mut par),
                polygon_sizes: &mut sz,
                polygon_indices: &mut ix,
                triangles: Some(&mut tr),
                cells: None,
            })
            .unwrap();
            let mut pos32 = vec![0.0f32; 3 * c.vertices];
            let mut par32 = vec![Query::default(); c.vertices];
            let (mut sz32, mut ix32, mut tr32) = (
                vec![0u32; c.polygons],
                vec![0u32; c.polygon_indices],
                vec![0u32; 3 * c.triangles],
            );
            t.emit_f32(OutputF32 {
                positions: &mut pos32,
                normals: None,
                params: Some(&mut par32),
                polygon_sizes: &mut sz32,
                polygon_indices: &mut ix32,
                triangles: Some(&mut tr32),
                cells: None,
            })
            .unwrap();
            assert_eq!((&sz, &ix, &par), (&sz32, &ix32, &par32), "{path:?}");
            assert_eq!(tr.len(), tr32.len());
            let e32 = t.vertex_error_f32().unwrap();
            let r = rounding::term(
                m.positions
                    .iter()
                    .flat_map(|p| p.iter())
                    .fold(0.0f64, |a, x| a.max(x.abs())),
            )
            .unwrap();
            let allowed = e32 + r;
            assert!(t.bound_f32().unwrap() >= t.stats().bound + e32);
            let mut local = (0.0f64, 0.0f64, allowed / diag);
            for v in 0..c.vertices {
                let d = (0..3)
                    .map(|k| (pos32[3 * v + k] as f64 - pos[3 * v + k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!(d <= allowed, "{path:?} vertex {v}: {d:e} > {allowed:e}");
                local.0 = local.0.max(d / allowed);
                local.1 = local.1.max(d / diag);
            }
            (local, c.vertices)
        })
        .unwrap();
        worst_ratio = worst_ratio.max(r.0 .0);
        worst_rel = worst_rel.max(r.0 .1);
        term_rel = term_rel.max(r.0 .2);
        vertices += r.1;
        shapes += 1;
    }
    println!(
        "f32 tessellation: {shapes} shapes, {vertices} vertices, 0 violations; \
         max |p32 - p64| / diag = {worst_rel:.3e}, f32 term / diag <= {term_rel:.3e}, \
         tightness (max actual / allowed) = {worst_ratio:.4}"
    );
    assert!(shapes >= 5);
}
