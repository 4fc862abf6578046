//! Builds the library's evaluator for a [`PolyMesh`] in test-owned memory.

use crate::reference::PolyMesh;
use ccss_core::{BuildScratch, Error, Evaluator, MeshInput, TableSet, Topology, Weights};
use std::sync::OnceLock;

/// Standard-rule tables for all valences, built once per test process.
pub fn standard_tables() -> &'static TableSet {
    static T: OnceLock<&'static TableSet> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = Box::new(TableSet::ZERO);
        let mut s = Box::new(BuildScratch::ZERO);
        t.build_into(&Weights::STANDARD, &mut s)
            .expect("standard tables");
        Box::leak(t)
    })
}

/// 8-byte aligned zeroed memory of at least `bytes` bytes.
pub fn aligned(bytes: usize) -> Vec<u64> {
    vec![0u64; bytes.div_ceil(8)]
}

/// Flat arrays of a mesh: positions, face sizes, indices.
pub fn flatten(m: &PolyMesh) -> (Vec<f64>, Vec<u32>, Vec<u32>) {
    let p = m.positions.iter().flat_map(|p| p.iter().copied()).collect();
    let s = m.faces.iter().map(|f| f.len() as u32).collect();
    let i = m.faces.iter().flat_map(|f| f.iter().copied()).collect();
    (p, s, i)
}

/// Validates `m` (topology only).
pub fn validate(m: &PolyMesh) -> Result<(), Error> {
    let (p, s, i) = flatten(m);
    let mut mem = aligned(Topology::required_bytes(p.len() / 3, &s));
    Topology::build(
        MeshInput {
            positions: &p,
            face_sizes: &s,
            indices: &i,
        },
        &mut mem,
    )
    .map(|_| ())
}

/// Runs `f` with the library's topology and evaluator of `m`.
pub fn with_evaluator<R>(
    m: &PolyMesh,
    tables: &TableSet,
    f: impl FnOnce(&Topology, &Evaluator) -> R,
) -> Result<R, Error> {
    let (p, s, i) = flatten(m);
    let mut tmem = aligned(Topology::required_bytes(p.len() / 3, &s));
    let topo = Topology::build(
        MeshInput {
            positions: &p,
            face_sizes: &s,
            indices: &i,
        },
        &mut tmem,
    )?;
    let mut emem = aligned(Evaluator::required_bytes(&topo, tables)?);
    let ev = Evaluator::build(&topo, tables, &mut emem)?;
    Ok(f(&topo, &ev))
}

/// The workspace root (parent of the `tests` crate).
pub fn workspace_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests crate lives inside the workspace")
        .to_path_buf()
}

/// `<target dir>/sub`, honouring a (possibly relative) `CARGO_TARGET_DIR`:
/// where tests that build things outside cargo keep their files.
pub fn target_subdir(sub: &str) -> std::path::PathBuf {
    let root = workspace_root();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let target = if target.is_absolute() {
        target
    } else {
        root.join(target)
    };
    target.join(sub)
}

/// Marsaglia's xorshift64 (shifts 13, 7, 17): reproducible test inputs
/// without a dependency. The seed must not be 0.
pub struct XorShift(pub u64);

impl XorShift {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1) (the top 53 bits).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    pub fn signed(&mut self) -> f64 {
        self.unit() * 2.0 - 1.0
    }
}

/// The OpenSubdiv corpus shapes bundled in `tests/data/osd`, sorted.
pub fn corpus_shapes() -> Vec<std::path::PathBuf> {
    let dir = workspace_root().join("tests/data/osd");
    let mut v: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    v.sort();
    v
}

/// Builds the OpenSubdiv harnesses (`bench/osd/build.sh`, Debian
/// `libosd-dev`) into `<target>/osd-peer` and returns the path of the one
/// named `exe`; `None` (with a note) when OpenSubdiv is missing, unless
/// `CCSS_REQUIRE_OSD=1` (set by `.ci/run`), which makes that a failure.
pub fn osd_harness(exe: &str) -> Option<std::path::PathBuf> {
    let out = target_subdir("osd-peer");
    let st = std::process::Command::new("sh")
        .arg(workspace_root().join("bench/osd/build.sh"))
        .arg(&out)
        .output()
        .ok()?;
    if !st.status.success() {
        let msg = String::from_utf8_lossy(&st.stderr).to_string();
        if std::env::var("CCSS_REQUIRE_OSD").as_deref() == Ok("1") {
            panic!("OpenSubdiv harness does not build: {msg}");
        }
        eprintln!("NOTE: OpenSubdiv not available, peer check skipped: {msg}");
        return None;
    }
    Some(out.join(exe))
}
