//! The demo on the host: the x86-64 reference of the firmware's lines
//! (eigen tables built at run time, pools on the heap). Prints the report
//! lines, then `info` lines with the exact caller-buffer sizes (not
//! compared). `scripts/firmware.sh` runs it; with `--smooth` it runs
//! only the smooth solid's steps (`Parts::SMOOTH`, the firmware feature
//! `smooth-only`).
use ccss_core::tessellate::Scratch;
use ccss_core::voxel::{VoxelRun, VoxelWork};
use ccss_core::{BuildScratch, TableSet};
use ccss_embedded_demo::{line, run, Parts, Pools, Report, Sum, Value};

struct Lines;

impl Report for Lines {
    fn sum(&mut self, key: &str, s: Sum) {
        let mut o = String::new();
        line(&mut o, key, Value::Sum(s)).unwrap();
        print!("{o}");
    }
    fn int(&mut self, key: &str, x: u64) {
        let mut o = String::new();
        line(&mut o, key, Value::Int(x)).unwrap();
        print!("{o}");
    }
    fn info(&mut self, key: &str, x: u64) {
        println!("info {key} {x}");
    }
}

fn main() {
    let parts = if std::env::args().any(|a| a == "--smooth") {
        Parts::SMOOTH
    } else {
        Parts::ALL
    };
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
        .expect("tables");
    let mut words = vec![0u64; 1 << 20];
    let mut reals = vec![0f64; 1 << 20];
    let mut ints = vec![0u32; 1 << 20];
    let mut runs = vec![VoxelRun::default(); 1 << 12];
    let mut work = Box::new(VoxelWork::ZERO);
    let mut scratch = Box::new(Scratch::ZERO);
    let mut pools = Pools {
        words: &mut words,
        reals: &mut reals,
        ints: &mut ints,
        runs: &mut runs,
        voxel_work: Some(&mut work),
        tess_scratch: Some(&mut scratch),
    };
    run(&tables, &mut pools, parts, &mut Lines).expect("demo run");
    host_speed(&tables);
}

/// ns per point of `eval` (f64) and `eval_f32` on the demo's pyramid,
/// over the demo grid repeated (the host figures of BENCHMARKS.md).
fn host_speed(tables: &TableSet) {
    use ccss_core::mem::words_for;
    use ccss_core::{Evaluator, MeshInput, Topology};
    use ccss_embedded_demo::meshes::*;
    use std::hint::black_box;
    use std::time::Instant;
    let m = MeshInput {
        positions: &PYRAMID_POSITIONS,
        face_sizes: &PYRAMID_SIZES,
        indices: &PYRAMID_INDICES,
    };
    let mut tm = vec![0u64; words_for(Topology::required_bytes(5, m.face_sizes))];
    let topo = Topology::build(m, &mut tm).unwrap();
    let mut em = vec![0u64; words_for(Evaluator::required_bytes(&topo, tables).unwrap())];
    let ev = Evaluator::build(&topo, tables, &mut em).unwrap();
    let mut pts = Vec::new();
    for f in 0..ev.num_faces() {
        for s in 0..ev.num_subfaces(f) {
            for i in 0..64 {
                for j in 0..64 {
                    pts.push((f as u32, s as u32, i as f64 / 63.0, j as f64 / 63.0));
                }
            }
        }
    }
    for round in 0..2 {
        let t = Instant::now();
        for &(f, s, u, v) in &pts {
            black_box(ev.eval(f, s, u, v).unwrap());
        }
        let a = t.elapsed().as_nanos() as f64 / pts.len() as f64;
        let t = Instant::now();
        for &(f, s, u, v) in &pts {
            black_box(ev.eval_f32(f, s, u as f32, v as f32).unwrap());
        }
        let b = t.elapsed().as_nanos() as f64 / pts.len() as f64;
        if round == 1 {
            println!(
                "info host_ns_per_point eval_f64 {a:.1} eval_f32 {b:.1} ({} points)",
                pts.len()
            );
        }
    }
}
