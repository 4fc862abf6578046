//! The Cortex-M4F firmware (`embedded/firmware`) against the same
//! computation on this machine: `scripts/firmware.sh` builds the firmware,
//! runs it in QEMU (`mps2-an386`) and compares its report lines with the
//! reference lines this test computes here with `ccss_embedded_demo::run`
//! (integers exactly, f64 checksums to 1e-12 relative), then checks the
//! script's last line (`checks=ok`).
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target: without
//! QEMU the test is skipped with a note, unless `CCSS_REQUIRE_QEMU=1`
//! (`.ci/run` installs QEMU and sets it), which makes a missing QEMU a
//! failure.

use ccss_core::tessellate::Scratch;
use ccss_core::voxel::{VoxelRun, VoxelWork};
use ccss_core::{BuildScratch, TableSet};
use ccss_embedded_demo::{line, run, Parts, Pools, Report, Sum, Value};
use std::path::Path;
use std::process::Command;

struct Lines(String);

impl Report for Lines {
    fn sum(&mut self, key: &str, s: Sum) {
        line(&mut self.0, key, Value::Sum(s)).unwrap();
    }
    fn int(&mut self, key: &str, x: u64) {
        line(&mut self.0, key, Value::Int(x)).unwrap();
    }
}

/// The reference lines, with run-time tables and pools on the heap.
fn host_lines(parts: Parts) -> String {
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
        .unwrap();
    let mut words = vec![0u64; 1 << 18];
    let mut reals = vec![0f64; 1 << 16];
    let mut ints = vec![0u32; 1 << 16];
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
    let mut out = Lines(String::new());
    run(&tables, &mut pools, parts, &mut out).unwrap();
    out.0
}

fn qemu_present() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs `scripts/firmware.sh` on the reference lines of `parts` with the
/// extra script arguments `args` and checks its last line.
fn firmware_matches_host(parts: Parts, name: &str, args: &[&str]) {
    if !qemu_present() {
        if std::env::var("CCSS_REQUIRE_QEMU").as_deref() == Ok("1") {
            panic!("qemu-system-arm not found but CCSS_REQUIRE_QEMU=1");
        }
        eprintln!(
            "firmware test SKIPPED: qemu-system-arm not found (Debian: apt-get install \
             qemu-system-arm; CCSS_REQUIRE_QEMU=1 makes this a failure)"
        );
        return;
    }
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let expect = tmp.join(format!("firmware-host-{name}.txt"));
    std::fs::write(&expect, host_lines(parts)).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new("bash")
        .arg(root.join("scripts/firmware.sh"))
        .args(args)
        .arg("--expect")
        .arg(&expect)
        .arg("--target-dir")
        .arg(tmp.join(format!("firmware-{name}")))
        .arg("--timeout")
        .arg("300")
        .env("CARGO", env!("CARGO"))
        .output()
        .expect("bash scripts/firmware.sh");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stdout}");
    eprintln!("{stderr}");
    let last = stdout.lines().last().unwrap_or("");
    assert!(
        out.status.success(),
        "scripts/firmware.sh {args:?} failed: {last}\n{stderr}"
    );
    assert!(
        last.starts_with("firmware: ") && last.ends_with("checks=ok"),
        "last line: {last}"
    );
}

/// The whole demo (eigen tables of valences 3..=8 baked).
#[test]
fn firmware_in_qemu_matches_host() {
    firmware_matches_host(Parts::ALL, "all", &[]);
}

/// The evaluate-and-tessellate firmware (`--smooth`: feature
/// `smooth-only`, only the pyramid's tables 3 and 4 baked).
#[test]
fn smooth_firmware_in_qemu_matches_host() {
    firmware_matches_host(Parts::SMOOTH, "smooth", &["--smooth"]);
}
