//! The C ABI, called through its Rust exports with fuzzed arguments: every
//! block length is exact, short, zero, above `isize::MAX` or `SIZE_MAX`,
//! or the block misaligned or NULL (header byte 2 picks per call);
//! element counts above `isize::MAX`; NULL out-params and details;
//! garbage handles. The oracle: no crash (ASan watches every access); a
//! call that does not return OK leaves its out-param as it was; garbage
//! handles are refused. The pipeline is the one a C host runs: topology,
//! evaluator, single and batch evaluations, tessellation (build, counts,
//! emit with fuzzed output lengths), voxel grid (voxelize, flood, runs).
#![no_main]
use ccss::*;
use ccss_fuzz::{words, Caps, Input, Rng};
use core::ffi::c_void;
use core::ptr;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

const CAPS: Caps = Caps {
    faces: 24,
    corners: 96,
};

/// The standard tables through the C ABI, once per process.
fn tables() -> *const CcssTables {
    static T: OnceLock<usize> = OnceLock::new();
    *T.get_or_init(|| {
        let mut bytes = 0usize;
        // SAFETY: valid out-param.
        assert_eq!(
            unsafe { ccss_tables_required_bytes(&mut bytes, ptr::null_mut()) },
            CcssStatus::OK
        );
        let mem: &'static mut [u64] = Box::leak(words(bytes).into_boxed_slice());
        let mut t: *const CcssTables = ptr::null();
        // SAFETY: a live block of `bytes` bytes.
        let st = unsafe {
            ccss_tables_build_standard(mem.as_mut_ptr().cast(), bytes, &mut t, ptr::null_mut())
        };
        assert_eq!(st, CcssStatus::OK);
        t as usize
    }) as *const CcssTables
}

/// A block argument: (pointer, length) for a block of `bytes` bytes held
/// in `mem`, mangled by `sel`.
fn block(mem: &mut Vec<u64>, bytes: usize, sel: u64) -> (*mut c_void, usize) {
    *mem = words(bytes + 8);
    let p = mem.as_mut_ptr() as *mut u8;
    match sel % 12 {
        0 if bytes >= 8 => (p.cast(), bytes - 8),
        1 => (p.cast(), 0),
        2 => (p.cast(), isize::MAX as usize + 1 + (sel as usize >> 8) % 64),
        3 => (p.cast(), usize::MAX),
        // SAFETY: inside the block (one word of slack).
        4 => (unsafe { p.add(4) }.cast(), bytes),
        5 => (ptr::null_mut(), bytes),
        _ => (p.cast(), bytes),
    }
}

/// An element count: the real one, fewer, or one whose bytes exceed
/// `isize::MAX` (never more readable elements than there are).
fn count(n: usize, elem: usize, r: &mut Rng) -> usize {
    match r.below(16) {
        0 => n.saturating_sub(1 + r.below(3) as usize),
        1 => isize::MAX as usize / elem + 1,
        2 => usize::MAX,
        _ => n,
    }
}

fn detail(d: &mut CcssErrorDetail, r: &mut Rng) -> *mut CcssErrorDetail {
    if r.below(4) == 0 {
        ptr::null_mut()
    } else {
        d
    }
}

const SENTINEL: usize = 0x5a5a_5a58;

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let mut r = x.rng();
    let h = x.header;
    // SAFETY: all-zero bytes are a valid detail (status OK, empty message).
    let mut d: CcssErrorDetail = unsafe { core::mem::zeroed() };
    let m = x.input();
    let nv = m.positions.len() / 3;
    let tables = tables();
    unsafe {
        // Garbage handles are refused.
        let mut junk = vec![0u64; 64];
        junk.iter_mut().for_each(|w| *w = r.next_u64());
        let mut n = SENTINEL;
        let st = ccss_evaluator_face_count(junk.as_ptr().cast(), &mut n, detail(&mut d, &mut r));
        assert!(
            st != CcssStatus::OK && n == SENTINEL,
            "garbage evaluator accepted"
        );
        let st = ccss_topology_vertex_count(junk.as_ptr().cast(), &mut n, ptr::null_mut());
        assert!(
            st != CcssStatus::OK && n == SENTINEL,
            "garbage topology accepted"
        );
        // Message formatting with any capacity.
        let mut msg = [0i8; 64];
        let cap = r.below(65) as usize;
        let _ = ccss_error_detail_format(&d, msg.as_mut_ptr().cast(), cap);

        // Topology.
        let mut tbytes = SENTINEL;
        let nf = count(m.face_sizes.len(), 4, &mut r);
        let st = ccss_topology_required_bytes(
            nv,
            m.face_sizes.as_ptr(),
            nf,
            &mut tbytes,
            detail(&mut d, &mut r),
        );
        if st != CcssStatus::OK {
            assert_eq!(tbytes, SENTINEL);
            return;
        }
        let mut tmem = Vec::new();
        let (tp, tl) = block(&mut tmem, tbytes, h[2] as u64);
        let mut topo: *const CcssTopology = SENTINEL as *const _;
        let ni = count(m.indices.len(), 4, &mut r);
        let st = ccss_topology_build(
            m.positions.as_ptr(),
            nv,
            m.face_sizes.as_ptr(),
            nf,
            m.indices.as_ptr(),
            ni,
            tp,
            tl,
            &mut topo,
            detail(&mut d, &mut r),
        );
        if st != CcssStatus::OK {
            assert_eq!(topo as usize, SENTINEL);
            return;
        }
        // Evaluator.
        let mut ebytes = SENTINEL;
        if ccss_evaluator_required_bytes(topo, tables, &mut ebytes, detail(&mut d, &mut r))
            != CcssStatus::OK
        {
            assert_eq!(ebytes, SENTINEL);
            return;
        }
        let mut emem = Vec::new();
        let (ep, el) = block(&mut emem, ebytes, h[2] as u64 >> 4);
        let mut ev: *const CcssEvaluator = SENTINEL as *const _;
        if ccss_evaluator_build(topo, tables, ep, el, &mut ev, detail(&mut d, &mut r))
            != CcssStatus::OK
        {
            assert_eq!(ev as usize, SENTINEL);
            return;
        }
        assert_eq!(ccss_evaluator_verify(ev, ptr::null_mut()), CcssStatus::OK);
        let mut faces = 0usize;
        assert_eq!(
            ccss_evaluator_face_count(ev, &mut faces, ptr::null_mut()),
            CcssStatus::OK
        );
        // Evaluations.
        let mut qs = [CcssEvaluatorQuery {
            face: 0,
            sub: 0,
            u: 0.0,
            v: 0.0,
        }; 8];
        for q in qs.iter_mut() {
            q.face = if r.below(16) == 0 {
                r.next_u64() as u32
            } else {
                r.below(faces as u64 + 1) as u32
            };
            q.sub = r.below(5) as u32;
            q.u = r.param();
            q.v = r.param();
            let mut out: CcssEvaluatorResult = core::mem::zeroed();
            out.p[0] = 7.0;
            let o: *mut CcssEvaluatorResult = if r.below(16) == 0 {
                ptr::null_mut()
            } else {
                &mut out
            };
            let f = [
                ccss_evaluator_eval_second,
                ccss_evaluator_eval_second_derivs,
                ccss_evaluator_eval_derivs,
            ][r.below(3) as usize];
            let st = f(ev, q.face, q.sub, q.u, q.v, o, detail(&mut d, &mut r));
            if st != CcssStatus::OK {
                assert_eq!(out.p[0], 7.0);
            }
        }
        let mut res = [core::mem::zeroed::<CcssEvaluatorResult>(); 8];
        let k = r.below(9) as usize;
        let out_len = match r.below(4) {
            0 => k.saturating_sub(1),
            1 => usize::MAX,
            _ => k,
        };
        let out_len = out_len.min(if out_len == usize::MAX { usize::MAX } else { 8 });
        let batch = if r.below(2) == 0 {
            ccss_evaluator_eval_batch
        } else {
            ccss_evaluator_eval_batch_derivs
        };
        let _ = batch(
            ev,
            qs.as_ptr(),
            k,
            (r.below(2)) as i32,
            res.as_mut_ptr(),
            out_len,
            detail(&mut d, &mut r),
        );

        // Tessellation.
        let opts = CcssTessellationOptions {
            criterion: (h[3] % 4) as u32,
            tolerance: match h[3] >> 2 & 3 {
                0 => x.max_abs * 2f64.powi(-1 - (h[4] % 8) as i32),
                1 => 2f64.powi(-1 - (h[4] % 8) as i32),
                2 => [0.0, -1.0, f64::NAN, f64::INFINITY][(h[4] % 4) as usize],
                _ => f64::MIN_POSITIVE,
            },
            uniform_level: (h[4] >> 3) as u32 % 3,
            max_level: 1 + (h[4] >> 5) as u32 % 4,
        };
        let mut sbytes = SENTINEL;
        if ccss_tessellation_required_bytes(topo, ev, &opts, &mut sbytes, detail(&mut d, &mut r))
            == CcssStatus::OK
        {
            let mut smem = Vec::new();
            let (sp, sl) = block(&mut smem, sbytes, h[5] as u64);
            let mut tess: *mut CcssTessellation = SENTINEL as *mut _;
            if ccss_tessellation_build(topo, ev, &opts, sp, sl, &mut tess, detail(&mut d, &mut r))
                == CcssStatus::OK
            {
                let mut c: CcssTessellationCountsInfo = core::mem::zeroed();
                assert_eq!(
                    ccss_tessellation_counts(tess, &mut c, ptr::null_mut()),
                    CcssStatus::OK
                );
                let mut pos = vec![0.0f64; 3 * c.vertices];
                let mut nrm = vec![0.0f64; 3 * c.vertices];
                let mut sizes = vec![0u32; c.polygons];
                let mut idx = vec![0u32; c.polygon_indices];
                let mut tris = vec![0u32; 3 * c.triangles];
                let mut len = |n: usize| match r.below(24) {
                    0 => n.saturating_sub(1),
                    1 => 0,
                    2 => isize::MAX as usize / 8 + 1,
                    _ => n,
                };
                let out = CcssTessellationOutput {
                    positions: pos.as_mut_ptr(),
                    positions_len: len(pos.len()),
                    normals: if h[6] & 1 == 0 {
                        ptr::null_mut()
                    } else {
                        nrm.as_mut_ptr()
                    },
                    normals_len: len(nrm.len()),
                    params: ptr::null_mut(),
                    params_len: 0,
                    polygon_sizes: sizes.as_mut_ptr(),
                    polygon_sizes_len: len(sizes.len()),
                    polygon_indices: idx.as_mut_ptr(),
                    polygon_indices_len: len(idx.len()),
                    triangles: if h[6] & 2 == 0 {
                        ptr::null_mut()
                    } else {
                        tris.as_mut_ptr()
                    },
                    triangles_len: len(tris.len()),
                    cells: ptr::null_mut(),
                    cells_len: 0,
                };
                if ccss_tessellation_emit(tess, &out, detail(&mut d, &mut r)) == CcssStatus::OK {
                    assert!(idx.iter().all(|&i| (i as usize) < c.vertices));
                }
            } else {
                assert_eq!(tess as usize, SENTINEL);
            }
        }

        // Voxel grid.
        let mut res3 = [
            2 + h[7] as u32 % 12,
            2 + h[8] as u32 % 12,
            2 + h[9] as u32 % 12,
        ];
        if h[10] & 0xe0 == 0xe0 {
            res3[(h[10] % 3) as usize] = [0, 1, 65537, u32::MAX][(h[10] >> 2) as usize % 4];
        }
        let (z0, z1) = if h[10] & 16 != 0 {
            (h[11] as u32 % 8, h[12] as u32 % 16)
        } else {
            (0, res3[2])
        };
        let mut gbytes = SENTINEL;
        if ccss_voxel_grid_required_bytes(
            res3.as_ptr(),
            z0,
            z1,
            &mut gbytes,
            detail(&mut d, &mut r),
        ) != CcssStatus::OK
        {
            assert_eq!(gbytes, SENTINEL);
            return;
        }
        let mut gmem = Vec::new();
        let (gp, gl) = block(&mut gmem, gbytes, h[13] as u64);
        let mut grid: *mut CcssVoxelGrid = SENTINEL as *mut _;
        if ccss_voxel_grid_build(
            res3.as_ptr(),
            z0,
            z1,
            gp,
            gl,
            &mut grid,
            detail(&mut d, &mut r),
        ) != CcssStatus::OK
        {
            assert_eq!(grid as usize, SENTINEL);
            return;
        }
        let adjacency = [6, 18, 26, 0, 7][(h[14] % 5) as usize];
        let presplit = [8, 1, 2, 4, 3, 0, 128, 8][(h[14] >> 3) as usize % 8];
        let mut vs: CcssVoxelGridVoxelizeStats = core::mem::zeroed();
        if ccss_voxel_grid_voxelize(
            ev,
            grid,
            adjacency,
            presplit,
            ptr::null(),
            &mut vs,
            detail(&mut d, &mut r),
        ) != CcssStatus::OK
        {
            return;
        }
        let mut stack = [0u32; 64];
        let sl = match r.below(8) {
            0 => 0,
            1 => isize::MAX as usize / 4 + 1,
            _ => 1 + r.below(64) as usize,
        };
        let mut fs: CcssVoxelGridFloodStats = core::mem::zeroed();
        let _ = ccss_voxel_grid_flood(
            ev,
            grid,
            stack.as_mut_ptr(),
            sl,
            &mut fs,
            detail(&mut d, &mut r),
        );
        let mut written = SENTINEL;
        let st = ccss_voxel_grid_runs(grid, ptr::null_mut(), 0, &mut written, ptr::null_mut());
        let n = if st == CcssStatus::OK { written } else { 0 };
        let mut runs = vec![core::mem::zeroed::<CcssVoxelGridRun>(); n];
        let rl = match r.below(4) {
            0 => n.saturating_sub(1),
            1 => isize::MAX as usize / 16 + 1,
            _ => n,
        };
        let mut written = SENTINEL;
        let st = ccss_voxel_grid_runs(
            grid,
            runs.as_mut_ptr(),
            rl,
            &mut written,
            detail(&mut d, &mut r),
        );
        if st != CcssStatus::OK {
            assert_eq!(written, SENTINEL);
        } else {
            assert_eq!(written, n);
        }
    }
});
