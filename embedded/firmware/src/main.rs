//! The ccss demo on a Cortex-M4F (QEMU `mps2-an386`): runs
//! `ccss_embedded_demo::run` with static pools and the eigen tables baked
//! into flash (`ccss-core` feature `baked-tables`; feature `runtime-tables`
//! builds them into RAM instead), prints its report lines over
//! semihosting, then the measured stack of each phase (stack painting)
//! and exits with the status of the run.
#![no_std]
#![no_main]

mod stack;
mod ticks;

use ccss_core::voxel::{VoxelRun, VoxelWork};
use ccss_core::TableSet;
use ccss_embedded_demo::{line, run, Pools, Report, Sum, Value};
use core::fmt::Write;
use core::ptr::addr_of_mut;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};

/// Builder memory (words): the largest phase of the demo (topology and
/// evaluator plus the tessellation), with some room.
const WORDS: usize = 24 * 1024;
/// Tessellation positions.
const REALS: usize = 1536;
/// Depths, polygons, triangles, flood stack.
const INTS: usize = 6 * 1024;
/// Voxel runs of one slab.
const RUNS: usize = 256;

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
static mut VOXEL_WORK: VoxelWork = VoxelWork::ZERO;

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
        "tessellate",
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
            voxel_work: &mut *addr_of_mut!(VOXEL_WORK),
            tess_scratch: None,
        }
    };
    if let Err(e) = run(tables, &mut pools, &mut console) {
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
