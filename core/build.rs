//! Reads the compile-time configuration of `ccss-core` (environment
//! variables; the defaults are the host configuration):
//!
//! * `CCSS_MAX_VALENCE` (default 16, range 5..=64): the largest vertex
//!   valence the fixed-size eigen tables support.
//! * `CCSS_TABLE_VALENCES` (default every valence `3..=CCSS_MAX_VALENCE`):
//!   the valences a `TableSet` holds, as a list of valences and ranges
//!   (`3,4` or `3-8`). A firmware that knows the valences of its meshes
//!   keeps only those tables (in flash with `baked-tables`, or in RAM).
//! * `CCSS_TESS_MAX_LEVEL` (default 30, range 4..=30): the deepest quadtree
//!   level of the adaptive tessellation; its fixed traversal `Scratch`
//!   holds one level record per level (about 1.9 KiB each).
use std::{env, fs, path::Path};

fn number(name: &str, default: usize, range: std::ops::RangeInclusive<usize>) -> usize {
    println!("cargo:rerun-if-env-changed={name}");
    let v = match env::var(name) {
        Ok(s) => s
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("{name} must be an integer, got {s:?}")),
        Err(_) => default,
    };
    assert!(
        range.contains(&v),
        "{name} must be in {}..={}, got {v}",
        range.start(),
        range.end()
    );
    v
}

/// The valences of `CCSS_TABLE_VALENCES`, ascending, without repeats.
fn table_valences(max: usize) -> Vec<usize> {
    println!("cargo:rerun-if-env-changed=CCSS_TABLE_VALENCES");
    let Ok(list) = env::var("CCSS_TABLE_VALENCES") else {
        return (3..=max).collect();
    };
    let mut on = vec![false; max + 1];
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let bad = || panic!("CCSS_TABLE_VALENCES: {item:?} is not a valence or a range a-b");
        let (a, b) = match item.split_once('-') {
            Some((a, b)) => (
                a.trim().parse().unwrap_or_else(|_| bad()),
                b.trim().parse().unwrap_or_else(|_| bad()),
            ),
            None => {
                let a: usize = item.parse().unwrap_or_else(|_| bad());
                (a, a)
            }
        };
        assert!(
            3 <= a && a <= b && b <= max,
            "CCSS_TABLE_VALENCES: {item:?} is outside 3..={max} (CCSS_MAX_VALENCE)"
        );
        on[a..=b].fill(true);
    }
    let v: Vec<usize> = (3..=max).filter(|&n| on[n]).collect();
    assert!(!v.is_empty(), "CCSS_TABLE_VALENCES lists no valence");
    v
}

fn main() {
    let max = number("CCSS_MAX_VALENCE", 16, 5..=64);
    let valences = table_valences(max);
    let level = number("CCSS_TESS_MAX_LEVEL", 30, 4..=30);
    let mut slot = vec![usize::MAX; max + 1];
    for (i, &n) in valences.iter().enumerate() {
        slot[n] = i;
    }
    let list = |v: &[usize]| {
        v.iter()
            .map(|x| {
                if *x == usize::MAX {
                    "usize::MAX".to_string()
                } else {
                    x.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let out = Path::new(&env::var("OUT_DIR").unwrap()).join("config.rs");
    fs::write(
        out,
        format!(
            "/// Largest supported vertex valence (and face size after one refinement step).\n\
             /// Set at build time with the environment variable `CCSS_MAX_VALENCE` (default 16).\n\
             pub const MAX_VALENCE: usize = {max};\n\
             /// The valences whose eigen tables a `TableSet` holds, ascending. Set at build\n\
             /// time with `CCSS_TABLE_VALENCES` (default every valence `3..=MAX_VALENCE`).\n\
             pub const TABLE_VALENCES: [usize; {count}] = [{vals}];\n\
             /// Per valence `0..=MAX_VALENCE`: its index in [`TABLE_VALENCES`], or\n\
             /// `usize::MAX` for a valence without a table.\n\
             pub const TABLE_SLOT: [usize; {slots}] = [{slot}];\n\
             /// Deepest level of the adaptive tessellation's quadtree. Set at build time with\n\
             /// `CCSS_TESS_MAX_LEVEL` (default 30).\n\
             pub const TESS_MAX_LEVEL: u32 = {level};\n",
            count = valences.len(),
            vals = list(&valences),
            slots = max + 1,
            slot = list(&slot),
        ),
    )
    .unwrap();
}
