//! The ccss demo on a Cortex-M4F (QEMU `mps2-an386`): runs
//! `ccss_embedded_demo::run` with static pools and the eigen tables baked
//! into flash (`ccss-core` feature `baked-tables`; feature `runtime-tables`
//! builds them into RAM instead), prints its report lines over
//! semihosting, then the measured stack of each phase (stack painting)
//! and exits with the status of the run. Feature `smooth-only` runs only
//! the smooth solid's steps (`Parts::SMOOTH`: build, evaluation, depths,
//! tessellation), with pools sized for them.
#![no_std]
#![no_main]

mod stack;
mod ticks;

use ccss_core::voxel::{VoxelRun, VoxelWork};
use ccss_core::TableSet;
use ccss_embedded_demo::{line, run, Parts, Pools, Report, Sum, Value};
use core::fmt::Write;
use core::ptr::addr_of_mut;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};

/// Which steps of the demo run.
#[cfg(not(feature = "smooth-only"))]
const PARTS: Parts = Parts::ALL;
#[cfg(feature = "smooth-only")]
const PARTS: Parts = Parts::SMOOTH;

// Pool sizes: the exact bytes of the demo's size queries (the `info`
// lines of `cargo run --release -p ccss-embedded-demo --example host`,
// with this crate's CCSS_* settings, the tessellation's with its Scratch
// of CCSS_TESS_MAX_LEVEL=10, 20,768 bytes). A pool too small ends the run
// with `BufferTooSmall`.

/// Topology (264 bytes) and compact evaluator (22,728).
const KEPT: usize = 264 + 22_728;
/// Builder memory (words): what the topology and the evaluator keep, then
/// the largest later phase: the evaluator build's own memory (8,784),
/// the tessellation (33,848 with `Keep::LEAST`) or the feature mesh and
/// evaluator (7,328 + 38,880 at cache depth 2).
#[cfg(not(feature = "smooth-only"))]
const WORDS: usize = (KEPT + 7_328 + 38_880) / 8;
#[cfg(feature = "smooth-only")]
const WORDS: usize = (KEPT + 33_848) / 8;
/// Tessellation positions (3 x 354 vertices).
const REALS: usize = 3 * 354;
/// Depths (13), the streamed polygon and its triangles (14), flood stack
/// (voxels).
#[cfg(not(feature = "smooth-only"))]
const INTS: usize = 6 * 1024;
#[cfg(feature = "smooth-only")]
const INTS: usize = 14;
/// Voxel runs of one slab.
#[cfg(not(feature = "smooth-only"))]
const RUNS: usize = 256;
#[cfg(feature = "smooth-only")]
const RUNS: usize = 0;

static mut WORDS_POOL: [u64; WORDS] = [0; WORDS];
static mut REALS_POOL: [f64; REALS] = [0.0; REALS];
static mut INTS_POOL: [u32; INTS] = [0; INTS];
static mut RUNS_POOL: [VoxelRun; RUNS] = [VoxelRun {
    x0: 0,
    x1: 0,
    y: 0,
    z: 0,
    class: 0,
}; RUNS];
#[cfg(not(feature = "smooth-only"))]
static mut VOXEL_WORK: VoxelWork = VoxelWork::ZERO;

/// The voxelizer's work area, if the voxel step runs.
fn voxel_work() -> Option<&'static mut VoxelWork> {
    #[cfg(not(feature = "smooth-only"))]
    {
        // SAFETY: called once, from `main`; nothing else refers to it.
        Some(unsafe { &mut *addr_of_mut!(VOXEL_WORK) })
    }
    #[cfg(feature = "smooth-only")]
    {
        None
    }
}

#[cfg(feature = "runtime-tables")]
static mut TABLES: TableSet = TableSet::ZERO;
#[cfg(feature = "runtime-tables")]
static mut BUILD_SCRATCH: ccss_core::BuildScratch = ccss_core::BuildScratch::ZERO;

/// The tables: built into RAM at start, or the ones in flash.
fn tables() -> &'static TableSet {
    #[cfg(feature = "runtime-tables")]
    {
        // SAFETY: called once, before anything else touches these statics;
        // nothing else refers to them.
        let (t, s) = unsafe {
            (
                &mut *addr_of_mut!(TABLES),
                &mut *addr_of_mut!(BUILD_SCRATCH),
            )
        };
        if let Err(e) = t.build_into(&Default::default(), s) {
            fail(format_args!("table build: {e}"));
        }
        t
    }
    #[cfg(not(feature = "runtime-tables"))]
    {
        &ccss_core::eigen::BAKED_TABLES
    }
}

/// Report lines to the semihosting console; stack per phase.
struct Console {
    out: hio::HostStream,
    phases: Phases,
}

/// Stack high-water marks per phase, printed after the report.
struct Phases {
    names: [&'static str; 10],
    bytes: [usize; 10],
    /// QEMU instructions of the phase (see `ticks`).
    ins: [u64; 10],
    len: usize,
    /// Instruction count when the last phase ended.
    last: u64,
}

impl Report for Console {
    fn sum(&mut self, key: &str, s: Sum) {
        let _ = line(&mut self.out, key, Value::Sum(s));
    }
    fn int(&mut self, key: &str, x: u64) {
        let _ = line(&mut self.out, key, Value::Int(x));
    }
    fn phase(&mut self, name: &str) {
        let now = ticks::instructions();
        let used = stack::high_water();
        let p = &mut self.phases;
        if p.len < p.names.len() {
            p.names[p.len] = phase_name(name);
            p.bytes[p.len] = used;
            p.ins[p.len] = now - p.last;
            p.len += 1;
        }
        stack::paint();
        // Leave out the painting.
        p.last = ticks::instructions();
    }
}

fn phase_name(name: &str) -> &'static str {
    for n in [
        "tables",
        "build",
        "eval",
        "eval_f64",
        "eval_f32",
        "feature",
        "depth",
        "tess_mark",
        "tess_emit",
        "voxel",
    ] {
        if n == name {
            return n;
        }
    }
    "?"
}

fn fail(msg: core::fmt::Arguments) -> ! {
    if let Ok(mut o) = hio::hstdout() {
        let _ = writeln!(o, "firmware: error: {msg}");
    }
    halt(debug::EXIT_FAILURE)
}

/// Ends the QEMU run with `status`.
fn halt(status: debug::ExitStatus) -> ! {
    debug::exit(status);
    loop {
        cortex_m::asm::wfi();
    }
}

#[entry]
fn main() -> ! {
    stack::paint();
    // SAFETY: taken once, here.
    ticks::start(unsafe { cortex_m::Peripherals::steal() }.SYST);
    let Ok(out) = hio::hstdout() else {
        halt(debug::EXIT_FAILURE)
    };
    let mut console = Console {
        out,
        phases: Phases {
            names: [""; 10],
            bytes: [0; 10],
            ins: [0; 10],
            len: 0,
            last: 0,
        },
    };
    let tables = tables();
    console.phase("tables");
    // SAFETY: `main` runs once and is the only user of the pools.
    let mut pools = unsafe {
        Pools {
            words: &mut *addr_of_mut!(WORDS_POOL),
            reals: &mut *addr_of_mut!(REALS_POOL),
            ints: &mut *addr_of_mut!(INTS_POOL),
            runs: &mut *addr_of_mut!(RUNS_POOL),
            voxel_work: voxel_work(),
            tess_scratch: None,
        }
    };
    if let Err(e) = run(tables, &mut pools, PARTS, &mut console) {
        fail(format_args!("{e}"));
    }
    let p = &console.phases;
    for i in 0..p.len {
        let _ = writeln!(console.out, "stack {} {}", p.names[i], p.bytes[i]);
        let _ = writeln!(console.out, "ins {} {}", p.names[i], p.ins[i]);
    }
    let _ = writeln!(console.out, "done");
    halt(debug::EXIT_SUCCESS)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    fail(format_args!("panic: {info}"))
}
