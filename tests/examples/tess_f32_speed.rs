//! Host speed of the tessellation's emission in f64 (`Tessellation::emit`)
//! and with f32 vertices (`Tessellation::emit_f32`) on the closed corpus
//! shapes, absolute flatness 1e-4 of the diagonal: best of 5 wall times of
//! each (the marking is done once, before). A benchmark, not a test:
//!
//!   cargo run --release -p ccss-tests --example tess_f32_speed [-- emit|emit_f32]
//!
//! With an argument only that emission runs (once per shape), for
//! instruction counts under `valgrind --tool=callgrind`.

use ccss_core::tessellate::{Options, Output, OutputF32, Scratch, Tessellation};
use ccss_tests::harness::{aligned, corpus_shapes, standard_tables, validate, with_evaluator};
use ccss_tests::reference::PolyMesh;
use std::time::Instant;

fn main() {
    let only = std::env::args().nth(1);
    let reps = if only.is_some() { 1 } else { 5 };
    let (mut t64, mut t32, mut verts) = (0.0f64, 0.0f64, 0usize);
    for path in corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        if validate(&m).is_err() {
            continue;
        }
        let diag = m.bbox_diagonal();
        with_evaluator(&m, standard_tables(), |topo, ev| {
            let opts = Options::absolute(1e-4 * diag);
            let mut scratch = Box::new(Scratch::ZERO);
            let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch).unwrap();
            let mut mem = aligned(need);
            let mut t = Tessellation::build(topo, ev, opts, &mut mem).unwrap();
            let c = t.counts();
            verts += c.vertices;
            let mut pos = vec![0.0f64; 3 * c.vertices];
            let mut pos32 = vec![0.0f32; 3 * c.vertices];
            let (mut sz, mut ix, mut tr) = (
                vec![0u32; c.polygons],
                vec![0u32; c.polygon_indices],
                vec![0u32; 3 * c.triangles],
            );
            let (mut b64, mut b32) = (f64::MAX, f64::MAX);
            for _ in 0..reps {
                if only.as_deref() != Some("emit_f32") {
                    let s = Instant::now();
                    t.emit(Output {
                        positions: &mut pos,
                        normals: None,
                        params: None,
                        polygon_sizes: &mut sz,
                        polygon_indices: &mut ix,
                        triangles: Some(&mut tr),
                        cells: None,
                    })
                    .unwrap();
                    b64 = b64.min(s.elapsed().as_secs_f64());
                }
                if only.as_deref() != Some("emit") {
                    let s = Instant::now();
                    t.emit_f32(OutputF32 {
                        positions: &mut pos32,
                        normals: None,
                        params: None,
                        polygon_sizes: &mut sz,
                        polygon_indices: &mut ix,
                        triangles: Some(&mut tr),
                        cells: None,
                    })
                    .unwrap();
                    b32 = b32.min(s.elapsed().as_secs_f64());
                }
            }
            t64 += b64;
            t32 += b32;
        })
        .unwrap();
    }
    if only.is_none() {
        println!(
            "emission of {verts} vertices (corpus, 1e-4 of the diagonal): emit (f64) {:.2} ms, \
             emit_f32 {:.2} ms ({:.0} ns / {:.0} ns per vertex)",
            t64 * 1e3,
            t32 * 1e3,
            t64 * 1e9 / verts as f64,
            t32 * 1e9 / verts as f64
        );
    }
}
