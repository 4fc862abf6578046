//! A deterministic, structure-aware mutation fuzzer that runs inside
//! `cargo test` with no tools (the coverage-guided cargo-fuzz targets are
//! in `fuzz/`, see FUZZING.md).
//!
//! Seeds: the closed corpus shapes of `tests/data/osd` (small ones).
//! Mutations (one to three per input, SplitMix-style generator, fixed seed):
//! an index set to a random or out-of-range value, a face size changed, a
//! face dropped or duplicated, a face reversed, a coordinate set to an
//! extreme finite value (±1e308, 1e-300, 65536, 1e12 offsets), NaN or inf,
//! all coordinates scaled by 10^±k, vertices appended. Each input runs
//! `Topology::build`, `Evaluator::build`, a few evaluations, and (for meshes
//! that build) every fourth input `mass_properties` and a 12^3
//! voxelization. The oracle: no panic, every result finite or a named
//! error; per-input work is bounded by the library's own caps.
//!
//! `CCSS_FUZZ_ITERS` (default 300 in `cargo test`) sets the number of
//! inputs; `bench/fuzz.sh` runs a long campaign in release mode and prints
//! executions per second.

use ccss_core::voxel::{mass_properties, Adjacency, VoxelGrid, VoxelParams, VoxelWork};
use ccss_core::{Error, Evaluator, MeshInput, Topology};
use ccss_tests::harness::{aligned, corpus_shapes, standard_tables, XorShift};
use ccss_tests::reference::PolyMesh;

struct Input {
    p: Vec<f64>,
    s: Vec<u32>,
    i: Vec<u32>,
}

fn seeds() -> Vec<Input> {
    corpus_shapes()
        .iter()
        .map(|p| PolyMesh::from_obj(p))
        .filter(|m| m.faces.len() <= 64)
        .map(|m| Input {
            p: m.positions.iter().flat_map(|p| p.iter().copied()).collect(),
            s: m.faces.iter().map(|f| f.len() as u32).collect(),
            i: m.faces.iter().flat_map(|f| f.iter().copied()).collect(),
        })
        .collect()
}

const EXTREMES: [f64; 10] = [
    1e308,
    -1e308,
    1e-300,
    65536.0,
    1e12,
    -1e12,
    0.0,
    -0.0,
    f64::NAN,
    f64::INFINITY,
];

fn mutate(x: &mut Input, r: &mut XorShift) {
    let nv = (x.p.len() / 3).max(1) as u64;
    // Half the inputs get geometric mutations only (they still build).
    let kind = if r.next_u64().is_multiple_of(2) {
        5 + r.next_u64() % 4
    } else {
        r.next_u64() % 9
    };
    match kind {
        0 if !x.i.is_empty() => {
            let k = (r.next_u64() % x.i.len() as u64) as usize;
            x.i[k] = if r.next_u64().is_multiple_of(4) {
                u32::MAX - (r.next_u64() % 3) as u32
            } else {
                (r.next_u64() % (nv + 2)) as u32
            };
        }
        1 if !x.s.is_empty() => {
            let k = (r.next_u64() % x.s.len() as u64) as usize;
            x.s[k] = (r.next_u64() % 40) as u32;
        }
        2 if x.s.len() > 1 => {
            // Drop a face.
            let k = (r.next_u64() % x.s.len() as u64) as usize;
            let start: usize = x.s[..k].iter().map(|&n| n as usize).sum();
            let end = (start + x.s[k] as usize).min(x.i.len());
            x.i.drain(start.min(end)..end);
            x.s.remove(k);
        }
        3 if !x.s.is_empty() => {
            // Duplicate a face.
            let k = (r.next_u64() % x.s.len() as u64) as usize;
            let start: usize = x.s[..k].iter().map(|&n| n as usize).sum();
            let end = (start + x.s[k] as usize).min(x.i.len());
            let f: Vec<u32> = x.i[start.min(end)..end].to_vec();
            x.s.push(f.len() as u32);
            x.i.extend(f);
        }
        4 if !x.s.is_empty() => {
            // Reverse a face.
            let k = (r.next_u64() % x.s.len() as u64) as usize;
            let start: usize = x.s[..k].iter().map(|&n| n as usize).sum();
            let end = (start + x.s[k] as usize).min(x.i.len());
            x.i[start.min(end)..end].reverse();
        }
        5 if !x.p.is_empty() => {
            let k = (r.next_u64() % x.p.len() as u64) as usize;
            x.p[k] = EXTREMES[(r.next_u64() % EXTREMES.len() as u64) as usize];
        }
        6 => {
            let e = (r.next_u64() % 601) as i32 - 300;
            let s: f64 = format!("1e{e}").parse().unwrap();
            x.p.iter_mut().for_each(|c| *c *= s);
        }
        7 => {
            let t = EXTREMES[(r.next_u64() % 6) as usize];
            x.p.iter_mut().step_by(3).for_each(|c| *c += t);
        }
        _ => {
            for _ in 0..(1 + r.next_u64() % 3) {
                x.p.extend([r.signed(), r.signed(), r.signed()]);
            }
        }
    }
}

/// Runs one input; returns whether the evaluator built.
fn run(x: &Input, r: &mut XorShift, heavy: bool) -> bool {
    let mesh = MeshInput {
        positions: &x.p,
        face_sizes: &x.s,
        indices: &x.i,
    };
    let nv = x.p.len() / 3;
    let mut tmem = aligned(Topology::required_bytes(nv, &x.s));
    let Ok(topo) = Topology::build(mesh, &mut tmem) else {
        return false;
    };
    let tables = standard_tables();
    let Ok(bytes) = Evaluator::required_bytes(&topo, tables) else {
        return false;
    };
    let mut emem = aligned(bytes);
    let Ok(ev) = Evaluator::build(&topo, tables, &mut emem) else {
        return false;
    };
    let finite = x.p.iter().all(|c| c.is_finite());
    for _ in 0..8 {
        let f = (r.next_u64() % (ev.num_faces() as u64 + 1)) as u32;
        let s = (r.next_u64() % 5) as u32;
        match ev.eval(f, s, r.unit(), r.unit()) {
            Ok(e) => assert!(
                !finite || e.p.is_finite() || x.p.iter().any(|c| c.abs() > 1e300),
                "non-finite point from finite input"
            ),
            Err(Error::FaceOutOfRange { .. } | Error::SubFaceOutOfRange { .. }) => {}
            Err(e) => panic!("unexpected eval error {e:?}"),
        }
    }
    if heavy {
        if let Ok(m) = mass_properties(&ev) {
            assert!(
                [m.volume, m.area, m.volume_error_bound, m.area_error_bound]
                    .iter()
                    .chain(&m.centroid)
                    .chain(&m.inertia)
                    .all(|x| x.is_finite()),
                "{m:?}"
            );
        }
        let params = VoxelParams::new([12; 3], Adjacency::Six);
        let mut gmem = aligned(VoxelGrid::required_bytes(params.res).unwrap());
        let mut grid = VoxelGrid::new(params.res, &mut gmem).unwrap();
        let mut work = Box::new(VoxelWork::ZERO);
        if grid.voxelize(&ev, &params, None, &mut work).is_ok() {
            let mut stack = [0u32; 256];
            let _ = grid.flood(&ev, &mut stack, &mut work);
        }
    }
    true
}

#[test]
fn fuzz_core_builders() {
    let iters: usize = std::env::var("CCSS_FUZZ_ITERS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300);
    let seeds = seeds();
    assert!(seeds.len() > 10);
    let mut r = XorShift(0x2545_f491_4f6c_dd1d);
    let t0 = std::time::Instant::now();
    let mut built = 0usize;
    for n in 0..iters {
        let mut x = {
            let s = &seeds[(r.next_u64() % seeds.len() as u64) as usize];
            Input {
                p: s.p.clone(),
                s: s.s.clone(),
                i: s.i.clone(),
            }
        };
        for _ in 0..(1 + r.next_u64() % 3) {
            mutate(&mut x, &mut r);
        }
        if run(&x, &mut r, n % 4 == 0) {
            built += 1;
        }
    }
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "fuzz: {iters} inputs, {built} built an evaluator, {:.0} executions/s",
        iters as f64 / dt
    );
}
