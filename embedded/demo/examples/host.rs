//! The demo on the host: the x86-64 reference of the firmware's lines
//! (eigen tables built at run time, pools on the heap). Prints the report
//! lines, then `info` lines with the exact caller-buffer sizes (not
//! compared). `scripts/firmware.sh` runs it.
use ccss_core::tessellate::Scratch;
use ccss_core::voxel::{VoxelRun, VoxelWork};
use ccss_core::{BuildScratch, TableSet};
use ccss_embedded_demo::{line, run, Pools, Report, Sum, Value};

struct Lines;

impl Report for Lines {
    fn sum(&mut self, key: &str, s: Sum) {
        let mut o = String::new();
        line(&mut o, key, Value::Sum(s)).unwrap();
        print!("{o}");
    }
    fn int(&mut self, key: &str, x: u64) {
        let mut o = String::new();
        line(&mut o, key, Value::Int(x)).unwrap();
        print!("{o}");
    }
    fn info(&mut self, key: &str, x: u64) {
        println!("info {key} {x}");
    }
}

fn main() {
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
        .expect("tables");
    let mut words = vec![0u64; 1 << 20];
    let mut reals = vec![0f64; 1 << 20];
    let mut ints = vec![0u32; 1 << 20];
    let mut runs = vec![VoxelRun::default(); 1 << 12];
    let mut work = Box::new(VoxelWork::ZERO);
    let mut scratch = Box::new(Scratch::ZERO);
    let mut pools = Pools {
        words: &mut words,
        reals: &mut reals,
        ints: &mut ints,
        runs: &mut runs,
        voxel_work: &mut work,
        tess_scratch: Some(&mut scratch),
    };
    run(&tables, &mut pools, &mut Lines).expect("demo run");
}
