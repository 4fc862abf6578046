//! The eigen tables baked into `core/src/eigen/baked_tables.bin` (and into
//! the `static` `ccss_core::eigen::BAKED_TABLES`, feature `baked-tables`)
//! against the runtime builder:
//!
//! * the committed file is, byte for byte, what the builder and
//!   `ccss_core::eigen::bake::bake_words` make now (else: rerun
//!   `cargo run -p ccss-core --example bake_tables -- core/src/eigen/baked_tables.bin`);
//! * the compile-time static holds, word for word, the meaningful part of
//!   every runtime table of valences 3..=8, and no table above 8;
//! * evaluators built on either give bit-identical points, derivatives and
//!   normals on every closed corpus shape of valences <= 8.

use ccss_core::eigen::bake::{bake_words, BAKED_MAX_VALENCE};
use ccss_core::eigen::BAKED_TABLES;
use ccss_core::{TableSet, ValenceTable, MAX_VALENCE};
use ccss_tests::harness::{
    corpus_shapes, standard_tables, validate, with_evaluator, workspace_root,
};
use ccss_tests::reference::PolyMesh;

fn words(t: &ValenceTable) -> Vec<u64> {
    let mut v = Vec::new();
    t.for_each_word(|w| v.push(w));
    v
}

#[test]
fn committed_file_is_what_the_builder_makes() {
    let path = workspace_root().join("core/src/eigen/baked_tables.bin");
    let file = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut now = Vec::new();
    bake_words(standard_tables(), BAKED_MAX_VALENCE, |w| {
        now.extend_from_slice(&w.to_le_bytes())
    });
    assert_eq!(file.len(), now.len(), "baked file size");
    let first = file.iter().zip(&now).position(|(a, b)| a != b);
    assert_eq!(
        first, None,
        "baked_tables.bin differs from the builder at byte {first:?}: rerun the bake_tables example"
    );
}

#[test]
fn static_tables_equal_runtime_tables_bit_for_bit() {
    let runtime = standard_tables();
    let top = BAKED_MAX_VALENCE.min(MAX_VALENCE);
    for n in 3..=top {
        let baked = BAKED_TABLES.get(n).expect("baked valence");
        let built = runtime.get(n).unwrap();
        assert_eq!(baked.valence(), n);
        let (a, b) = (words(baked), words(built));
        assert_eq!(
            a.len(),
            2 * (2 * n + 8) * (2 * n + 8) + (78 + 32) * (2 * n + 8) + 21
        );
        assert_eq!(a, b, "valence {n}: baked and built tables differ");
    }
    for n in top + 1..=MAX_VALENCE {
        assert!(BAKED_TABLES.get(n).is_none(), "valence {n} baked");
    }
    assert_eq!(*BAKED_TABLES.weights(), *runtime.weights());
}

#[test]
fn evaluators_on_baked_and_runtime_tables_agree_bit_for_bit() {
    let mut shapes = 0;
    for path in corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        if validate(&m).is_err() {
            continue; // open or otherwise outside the eigen evaluator
        }
        let mut val = vec![0usize; m.positions.len()];
        for f in &m.faces {
            for &v in f {
                val[v as usize] += 1;
            }
        }
        if val.iter().any(|&n| n > 8) {
            continue;
        }
        let eval_all = |tables: &TableSet| {
            with_evaluator(&m, tables, |_, ev| {
                let mut out = Vec::new();
                for f in 0..ev.num_faces() {
                    for s in 0..ev.num_subfaces(f) {
                        for (u, v) in [
                            (0.0, 0.0),
                            (0.3, 0.7),
                            (0.5, 0.5),
                            (1.0, 0.25),
                            (0.01, 0.002),
                        ] {
                            let e = ev.eval_second(f as u32, s as u32, u, v).unwrap();
                            for p in [e.p, e.du, e.dv, e.duu, e.duv, e.dvv, e.normal] {
                                out.extend(p.to_array().map(f64::to_bits));
                            }
                        }
                    }
                }
                out
            })
            .unwrap()
        };
        let a = eval_all(&BAKED_TABLES);
        let b = eval_all(standard_tables());
        assert_eq!(a, b, "{}: evaluations differ", path.display());
        shapes += 1;
    }
    assert!(
        shapes >= 5,
        "only {shapes} closed corpus shapes of valences <= 8"
    );
    eprintln!("{shapes} shapes evaluated bit-identically on baked and runtime tables");
}
