//! Reads the compile-time configuration of `ccss-core`.
//!
//! `CCSS_MAX_VALENCE` (default 16, range 5..=64) sets the largest vertex
//! valence the fixed-size eigen tables support.
use std::{env, fs, path::Path};

fn main() {
    println!("cargo:rerun-if-env-changed=CCSS_MAX_VALENCE");
    let max: usize = match env::var("CCSS_MAX_VALENCE") {
        Ok(s) => s
            .trim()
            .parse()
            .expect("CCSS_MAX_VALENCE must be an integer"),
        Err(_) => 16,
    };
    assert!(
        (5..=64).contains(&max),
        "CCSS_MAX_VALENCE must be in 5..=64, got {max}"
    );
    let out = Path::new(&env::var("OUT_DIR").unwrap()).join("config.rs");
    fs::write(
        out,
        format!(
            "/// Largest supported vertex valence (and face size after one refinement step).\n\
             /// Set at build time with the environment variable `CCSS_MAX_VALENCE` (default 16).\n\
             pub const MAX_VALENCE: usize = {max};\n"
        ),
    )
    .unwrap();
}
