//! Voxelization, flooding and runs. Header bytes 2..5 pick the resolution
//! (2..=10 per axis; byte 2 bit 7 gives 0 or 65537, which must be refused)
//! and byte 5 the adjacency (6, 18, 26) and pre-split (1, 2, 4, 8, or a
//! bad 3 / 0; small ones mostly, for speed). No panic; the run count is what `write_runs` writes, a
//! buffer one run short is `BufferTooSmall`; any voxel has a class.
#![no_main]
use ccss_core::voxel::{Adjacency, VoxelClass, VoxelGrid, VoxelParams, VoxelRun, VoxelWork};
use ccss_core::Error;
use ccss_fuzz::{evaluator, topology, words, Caps, Input};
use libfuzzer_sys::fuzz_target;
use std::cell::RefCell;

thread_local! {
    static WORK: RefCell<Box<VoxelWork>> = RefCell::new(Box::new(VoxelWork::ZERO));
}

const CAPS: Caps = Caps {
    faces: 24,
    corners: 96,
};

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let h = x.header;
    let mut res = [
        2 + h[2] as u32 % 9,
        2 + h[3] as u32 % 9,
        2 + h[4] as u32 % 9,
    ];
    if h[2] & 0x80 != 0 && h[3] & 1 == 1 {
        res[(h[4] % 3) as usize] = [0, 1, 65537][(h[3] as usize >> 1) % 3];
    }
    let adjacency =
        [Adjacency::Six, Adjacency::Eighteen, Adjacency::TwentySix][(h[5] % 3) as usize];
    let presplit = [1, 2, 1, 4, 8, 2, 3, 0][(h[5] as usize >> 2) % 8];
    let params = VoxelParams {
        res,
        adjacency,
        presplit,
    };
    let Ok(gbytes) = VoxelGrid::required_bytes(res) else {
        return;
    };
    let mut tmem = Vec::new();
    let Some(topo) = topology(x.input(), &mut tmem) else {
        return;
    };
    let mut emem = Vec::new();
    let Some(ev) = evaluator(&topo, &mut emem) else {
        return;
    };
    let mut gmem = words(gbytes);
    let mut grid = VoxelGrid::new(res, &mut gmem).expect("sized block");
    WORK.with(|w| {
        let work = &mut **w.borrow_mut();
        if grid.voxelize(&ev, &params, None, work).is_err() {
            return;
        }
        let mut stack = [0u32; 64];
        let stack_len = 3 + (h[6] as usize % 62);
        match grid.flood(&ev, &mut stack[..stack_len], work) {
            Ok(_) | Err(Error::NotClosedSolid(_) | Error::BufferTooSmall { .. }) => {}
            Err(Error::InvalidArgument(_) | Error::CoordinateRange(_)) => {}
            Err(e) => panic!("flood: {e:?}"),
        }
        let n = grid.run_count();
        let mut runs = vec![VoxelRun::default(); n];
        assert_eq!(grid.write_runs(&mut runs), Ok(n));
        if n > 0 {
            assert!(matches!(
                grid.write_runs(&mut runs[..n - 1]),
                Err(Error::BufferTooSmall { .. })
            ));
        }
        let (i, j, k) = (
            h[7] as u32 % res[0],
            h[8] as u32 % res[1],
            h[9] as u32 % res[2],
        );
        let _: VoxelClass = grid.class(i, j, k);
    });
});
