//! Writes the baked eigen tables `core/src/eigen/baked_tables.bin`: the
//! standard-rule tables of valences 3..=8 (`BAKED_MAX_VALENCE`) built now,
//! as little-endian words (`ccss_core::eigen::bake`).
//!
//! `cargo run -p ccss-core --example bake_tables -- core/src/eigen/baked_tables.bin`
//! (the default `CCSS_MAX_VALENCE`, 16, covers them);
//! `tests/tests/baked_tables.rs` checks that the committed file is what
//! this writes.
use ccss_core::eigen::bake::{bake_words, BAKED_MAX_VALENCE};
use ccss_core::{BuildScratch, TableSet};

fn main() {
    let path = std::env::args().nth(1).expect("usage: bake_tables OUT.bin");
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
        .expect("table build");
    let mut bytes = Vec::new();
    bake_words(&tables, BAKED_MAX_VALENCE, |w| {
        bytes.extend_from_slice(&w.to_le_bytes())
    });
    std::fs::write(&path, &bytes).expect("write");
    eprintln!("{path}: {} bytes", bytes.len());
}
