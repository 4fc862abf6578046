//! Hostile input for the feature path: random polygon soups (repeated,
//! non-manifold, misoriented, isolated and degenerate pieces), random tags
//! and options, random queries. `FeatureMesh::build`,
//! `FeatureEvaluator::build` and `eval` must return `Ok` or a clear `Err`:
//! never panic, never loop, and every `Ok` evaluation is finite.
use ccss_core::eval::Query;
use ccss_core::mem::words_for;
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::{FeatureEvaluator, MeshInput};
use ccss_tests::harness::XorShift;

fn pick(r: &mut XorShift, n: usize) -> usize {
    (r.next_u64() % n as u64) as usize
}

#[test]
fn random_meshes_and_tags_never_panic() {
    let mut r = XorShift(0x1234_5678_9abc_def1);
    let (mut built, mut refused, mut evals, mut eval_errors) = (0, 0, 0usize, 0usize);
    let mut kinds = std::collections::BTreeMap::new();
    for case in 0..600 {
        let nv = 4 + pick(&mut r, 12);
        let positions: Vec<f64> = (0..3 * nv).map(|_| r.signed() * 2.0).collect();
        let nf = 1 + pick(&mut r, 10);
        let mut sizes = Vec::new();
        let mut idx = Vec::new();
        for _ in 0..nf {
            let n = 3 + pick(&mut r, 3);
            sizes.push(n as u32);
            // Mostly distinct vertices; sometimes a repeat or a bad index.
            let mut face: Vec<u32> = Vec::new();
            while face.len() < n {
                let v = pick(&mut r, nv) as u32;
                if !face.contains(&v) || pick(&mut r, 400) == 0 {
                    face.push(v);
                }
            }
            if pick(&mut r, 400) == 0 {
                face[0] = nv as u32 + 3;
            }
            idx.extend(face);
        }
        let nc = pick(&mut r, 6);
        // Mostly real edges (consecutive corners of a face), sometimes not.
        let mut cv: Vec<u32> = Vec::new();
        for _ in 0..nc {
            let f = pick(&mut r, nf);
            let start: usize = sizes[..f].iter().map(|&s| s as usize).sum();
            let n = sizes[f] as usize;
            let k = pick(&mut r, n);
            cv.push(idx[start + k]);
            cv.push(if pick(&mut r, 30) == 0 {
                idx[pick(&mut r, idx.len())]
            } else {
                idx[start + (k + 1) % n]
            });
        }
        let cs: Vec<f32> = (0..nc)
            .map(|_| [0.0, 0.5, 1.0, 2.5, 7.9, 10.0, 12.0][pick(&mut r, 7)])
            .collect();
        let nk = pick(&mut r, 3);
        let kv: Vec<u32> = (0..nk).map(|_| pick(&mut r, nv + 1) as u32).collect();
        let ks: Vec<f32> = (0..nk).map(|_| [0.3, 2.0, 10.0][pick(&mut r, 3)]).collect();
        let holes: Vec<u32> = (0..pick(&mut r, 2))
            .map(|_| pick(&mut r, nf + 1) as u32)
            .collect();
        let options = FeatureOptions {
            boundary: [Boundary::None, Boundary::EdgeOnly, Boundary::EdgeAndCorner]
                [pick(&mut r, 3)],
            creasing: [Creasing::Uniform, Creasing::Chaikin][pick(&mut r, 2)],
            smooth_triangles: pick(&mut r, 2) == 0,
        };
        let mesh = MeshInput {
            positions: &positions,
            face_sizes: &sizes,
            indices: &idx,
        };
        let tags = FeatureInput {
            crease_vertices: &cv,
            crease_sharpness: &cs,
            corner_vertices: &kv,
            corner_sharpness: &ks,
            holes: &holes,
            options,
        };
        let Ok(need) = FeatureMesh::required_bytes(&mesh) else {
            refused += 1;
            continue;
        };
        let mut mem = vec![0u64; words_for(need)];
        let fm = match FeatureMesh::build(&mesh, &tags, &mut mem) {
            Ok(fm) => fm,
            Err(e) => {
                assert!(!e.to_string().is_empty());
                refused += 1;
                continue;
            }
        };
        let tables = (case % 2 == 0).then(ccss_tests::harness::standard_tables);
        let mut emem = vec![0u64; words_for(FeatureEvaluator::required_bytes(&fm, tables))];
        let ev = FeatureEvaluator::build(&fm, tables, &mut emem)
            .unwrap_or_else(|e| panic!("case {case}: {e}"));
        built += 1;
        for _ in 0..40 {
            let extra = usize::from(pick(&mut r, 20) == 0);
            let f = pick(&mut r, nf + extra) as u32;
            let sub = if pick(&mut r, 20) == 0 {
                pick(&mut r, 6) as u32
            } else {
                let n = sizes.get(f as usize).copied().unwrap_or(4);
                if n == 4 {
                    0
                } else {
                    pick(&mut r, n as usize) as u32
                }
            };
            let edges = [0.0, 1.0, 0.5];
            let mut coord = || {
                if pick(&mut r, 3) == 0 {
                    edges[pick(&mut r, 3)]
                } else {
                    r.unit()
                }
            };
            let (u, v) = (coord(), coord());
            let q = Query { face: f, sub, u, v };
            match ev.eval_second(q.face, q.sub, q.u, q.v) {
                Ok(e) => {
                    assert!(
                        e.p.is_finite() && e.du.is_finite() && e.dv.is_finite(),
                        "case {case}: {q:?} gave {e:?}"
                    );
                    evals += 1;
                }
                Err(e) => {
                    let kind = format!("{e:?}");
                    let kind = kind.split([' ', '(']).next().unwrap_or("").to_string();
                    assert!(
                        !e.to_string().contains("internal"),
                        "case {case}: {q:?}: {e}"
                    );
                    *kinds.entry(kind).or_insert(0usize) += 1;
                    eval_errors += 1
                }
            }
        }
    }
    eprintln!(
        "built {built}, refused {refused}; {evals} evaluations, {eval_errors} refused queries: {kinds:?}"
    );
    assert!(built > 300, "only {built} meshes built");
}
