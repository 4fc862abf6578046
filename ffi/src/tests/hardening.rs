//! Issue 27: handles carry a magic word (garbage, foreign or overwritten
//! handles are INVALID_HANDLE), lengths above `isize::MAX` are refused, new
//! statuses keep their values.

use super::*;

#[test]
fn new_status_values_are_appended() {
    for (st, v, want) in [
        (CcssStatus::ERR_WORK_LIMIT_EXCEEDED, 29, "work limit"),
        (CcssStatus::ERR_COORDINATE_RANGE, 30, "certifiable range"),
        (CcssStatus::ERR_INVALID_HANDLE, 31, "invalid handle"),
        (CcssStatus::ERR_CORRUPTED, 32, "integrity"),
        (CcssStatus::ERR_OVERLAP, 33, "overlaps"),
    ] {
        assert_eq!(st as c_int, v);
        let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(v)) };
        assert!(m.to_str().unwrap().contains(want), "{m:?}");
    }
    let f = Failure::from(Error::WorkLimitExceeded {
        limit: 77,
        what: "cells",
    });
    assert_eq!(
        (f.status, f.required),
        (CcssStatus::ERR_WORK_LIMIT_EXCEEDED, 77)
    );
    let f = Failure::from(Error::CoordinateRange("x"));
    assert_eq!(f.status, CcssStatus::ERR_COORDINATE_RANGE);
}

#[test]
fn garbage_foreign_and_overwritten_handles_are_refused() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    unsafe {
        assert_eq!(
            ccss_evaluator_face_count(b.ev, &mut n, &mut d),
            CcssStatus::OK
        );
        assert_eq!(n, 6);
        // Garbage: zeroed and patterned memory.
        for fill in [0u64, u64::MAX, 0x0123_4567_89ab_cdef] {
            let junk = vec![fill; 4096];
            let ev = junk.as_ptr() as *const CcssEvaluator;
            let st = ccss_evaluator_face_count(ev, &mut n, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE);
            assert!(msg(&d).contains("ccss_evaluator"), "{}", msg(&d));
            let mut out = CcssEvaluatorResult::default();
            let r = ccss_evaluator_eval(ev, 0, 0, 0.5, 0.5, &mut out, &mut d);
            assert_eq!(r, CcssStatus::ERR_INVALID_HANDLE);
            let g = junk.as_ptr() as *const CcssVoxelGrid;
            let (mut a, mut c) = (0u64, 0u64);
            let st = ccss_voxel_grid_counts(g, &mut a, &mut c, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE);
        }
        // A handle of another type: the tables as an evaluator.
        let st = ccss_evaluator_face_count(b.tables as *const CcssEvaluator, &mut n, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE);
        // An overwritten header (as after free and reuse).
        let off = <CcssEvaluator as crate::boundary::Handle>::MAGIC_OFFSET;
        let hdr = (b.ev as *mut u8).add(off) as *mut u64;
        let saved = hdr.read();
        hdr.write(0xdead_beef);
        let st = ccss_evaluator_face_count(b.ev, &mut n, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE);
        hdr.write(saved);
        assert_eq!(
            ccss_evaluator_face_count(b.ev, &mut n, &mut d),
            CcssStatus::OK
        );
    }
}

#[test]
fn lengths_above_isize_max_are_refused() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let mut mem = block(1 << 12);
    let big = isize::MAX as usize + 1;
    unsafe {
        for len in [big, usize::MAX] {
            let mut t = ptr::null();
            let st = ccss_tables_build_standard(mem.as_mut_ptr().cast(), len, &mut t, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "{}", msg(&d));
            let mut n = 0usize;
            let st = ccss_topology_required_bytes(8, s.as_ptr(), len, &mut n, &mut d);
            assert_ne!(st, CcssStatus::OK);
            let mut topo = ptr::null();
            let st = ccss_topology_build(
                p.as_ptr(),
                len,
                s.as_ptr(),
                s.len(),
                i.as_ptr(),
                i.len(),
                mem.as_mut_ptr().cast(),
                mem.len() * 8,
                &mut topo,
                &mut d,
            );
            assert_ne!(st, CcssStatus::OK);
            let mut e = ptr::null();
            let st = ccss_evaluator_build(
                ptr::null(),
                b.tables,
                mem.as_mut_ptr().cast(),
                len,
                &mut e,
                &mut d,
            );
            assert_ne!(st, CcssStatus::OK);
            let q = [CcssEvaluatorQuery::default()];
            let mut r = [CcssEvaluatorResult::default()];
            let st = ccss_evaluator_eval_batch(b.ev, q.as_ptr(), len, 0, r.as_mut_ptr(), 1, &mut d);
            assert_ne!(st, CcssStatus::OK);
        }
    }
}

#[test]
fn voxel_runs_into_the_grid_block_is_an_overlap() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let res = [16u32; 3];
    let mut n = 0usize;
    unsafe {
        assert_eq!(
            ccss_voxel_grid_required_bytes(res.as_ptr(), 0, 16, &mut n, &mut d),
            CcssStatus::OK
        );
        let mut mem = block(n);
        let mut g = ptr::null_mut();
        let st = ccss_voxel_grid_build(
            res.as_ptr(),
            0,
            16,
            mem.as_mut_ptr().cast(),
            n,
            &mut g,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_voxel_grid_voxelize(b.ev, g, 6, 8, ptr::null(), ptr::null_mut(), &mut d);
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        let mut written = 0usize;
        // Room for every run, but inside the grid's own block (its tail).
        let cap = 512usize;
        assert!(n > cap * 16);
        let runs = (mem.as_mut_ptr() as *mut u8).add(n - cap * 16) as *mut CcssVoxelGridRun;
        let st = ccss_voxel_grid_runs(g, runs, cap, &mut written, &mut d);
        assert_eq!(st, CcssStatus::ERR_OVERLAP, "{}", msg(&d));
        let mut out = vec![CcssVoxelGridRun::default(); 4096];
        let st = ccss_voxel_grid_runs(g, out.as_mut_ptr(), out.len(), &mut written, &mut d);
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        assert!(written > 0);
    }
}
