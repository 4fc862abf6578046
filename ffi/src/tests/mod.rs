//! Unit tests of the C ABI, one file per object family; the helpers here
//! build the cube and the handle blocks the families share.
#![allow(clippy::undocumented_unsafe_blocks)]

pub(crate) use crate::boundary::guard;
pub(crate) use crate::status::{Failure, Msg};
pub(crate) use crate::*;
pub(crate) use ccss_core::bounds::depth::Method;
pub(crate) use ccss_core::{Error, Weights};
pub(crate) use core::ffi::{c_char, c_int};
pub(crate) use core::ptr;

mod boolean;
mod depth;
mod evaluator;
mod feature;
mod handles;
mod hardening;
mod interpolation;
mod query;
mod query_band;
mod query_index;
mod status;
mod tables;
mod tessellation;

/// Pseudo-random numbers in `[0, 1)` for the tests: xorshift64 (shifts
/// 13, 7, 17) from `seed` (not zero), the top 53 bits of each state.
pub(crate) fn unit_rng(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Counts heap allocations per thread, to prove the FFI paths allocate nothing.
pub(crate) mod alloc_count {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        pub static COUNT: Cell<usize> = const { Cell::new(0) };
    }

    pub struct Counting;

    // SAFETY: forwards to the system allocator.
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, l: Layout) -> *mut u8 {
            let _ = COUNT.try_with(|c| c.set(c.get() + 1));
            // SAFETY: same contract as ours.
            unsafe { System.alloc(l) }
        }
        unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
            // SAFETY: same contract as ours.
            unsafe { System.dealloc(p, l) }
        }
    }

    #[global_allocator]
    static A: Counting = Counting;

    pub fn get() -> usize {
        COUNT.with(|c| c.get())
    }
}

pub(crate) fn cube() -> ([f64; 24], [u32; 6], [u32; 24]) {
    (
        [
            -1., -1., -1., 1., -1., -1., 1., 1., -1., -1., 1., -1., -1., -1., 1., 1., -1., 1., 1.,
            1., 1., -1., 1., 1.,
        ],
        [4; 6],
        [
            0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
        ],
    )
}

pub(crate) fn block(bytes: usize) -> Vec<u64> {
    vec![0u64; bytes.div_ceil(8)]
}

pub(crate) fn msg(d: &CcssErrorDetail) -> String {
    let b: Vec<u8> = d
        .message
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8(b).unwrap()
}

pub(crate) fn entry(valence: u32, alpha: f64, beta: f64, gamma: f64) -> CcssWeightEntry {
    CcssWeightEntry {
        valence,
        alpha,
        beta,
        gamma,
    }
}

/// Tables (standard, or `entries`), topology and evaluator of a mesh in
/// test-owned blocks; the blocks are returned to keep them alive.
pub(crate) struct Built {
    pub(crate) tables: *const CcssTables,
    pub(crate) topo: *const CcssTopology,
    pub(crate) ev: *const CcssEvaluator,
    /// Bytes of the evaluator's block.
    pub(crate) eval_bytes: usize,
    _mem: [Vec<u64>; 3],
}

pub(crate) fn build_mesh(p: &[f64], s: &[u32], i: &[u32], entries: &[CcssWeightEntry]) -> Built {
    let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
    let mut d = Failure::invalid("x").to_detail();
    let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
    unsafe {
        assert_eq!(
            ccss_tables_required_bytes(&mut tb, ptr::null_mut()),
            CcssStatus::OK
        );
        let mut tmem = block(tb);
        let st = ccss_tables_build(
            entries.as_ptr(),
            entries.len(),
            tmem.as_mut_ptr().cast(),
            tb,
            &mut tables,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_topology_required_bytes(
            p.len() / 3,
            s.as_ptr(),
            s.len(),
            &mut gb,
            ptr::null_mut(),
        );
        assert_eq!(st, CcssStatus::OK);
        let mut gmem = block(gb);
        let st = ccss_topology_build(
            p.as_ptr(),
            p.len() / 3,
            s.as_ptr(),
            s.len(),
            i.as_ptr(),
            i.len(),
            gmem.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        // Under Miri the compact evaluator (the same results; the default
        // one runs the eigen kernel 66 times per extraordinary patch at
        // build, minutes interpreted).
        #[cfg(miri)]
        let emem = {
            let mut o = ccss_core::eval::EvaluatorOptions::COMPACT.into();
            assert_eq!(
                ccss_evaluator_options_compact(&mut o, ptr::null_mut()),
                CcssStatus::OK
            );
            let st = ccss_evaluator_required_bytes_with_options(topo, tables, &o, &mut eb, &mut d);
            assert_eq!(st, CcssStatus::OK);
            let mut emem = block(eb);
            let st = ccss_evaluator_build_with_options(
                topo,
                tables,
                &o,
                emem.as_mut_ptr().cast(),
                eb,
                &mut ev,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            emem
        };
        #[cfg(not(miri))]
        let emem = {
            let st = ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d);
            assert_eq!(st, CcssStatus::OK);
            let mut emem = block(eb);
            let st =
                ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
            assert_eq!(st, CcssStatus::OK);
            emem
        };
        Built {
            tables,
            topo,
            ev,
            eval_bytes: eb,
            _mem: [tmem, gmem, emem],
        }
    }
}
