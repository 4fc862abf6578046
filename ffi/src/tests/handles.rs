//! Issue 27: garbage and foreign handles on the query, feature-evaluator,
//! tessellation (smooth and feature) and interpolation entries give
//! INVALID_HANDLE naming the argument and the expected type; the integrity
//! check of tables and evaluator blocks (`ccss_tables_verify`,
//! `ccss_evaluator_verify`) finds a flipped byte and passes untouched blocks.

use super::*;
use crate::interpolation::{
    ccss_interpolation_counts, ccss_interpolation_required_bytes, ccss_interpolation_solve,
};

/// Zeroed and patterned junk, big enough for any handle header.
fn junk_blocks() -> Vec<Vec<u64>> {
    [0u64, u64::MAX, 0x0123_4567_89ab_cdef]
        .iter()
        .map(|&f| vec![f; 1 << 14])
        .collect()
}

fn invalid(st: CcssStatus, d: &CcssErrorDetail, arg: &str, ty: &str) {
    assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE, "{}", msg(d));
    let m = msg(d);
    assert!(
        m.contains(&format!("`{arg}`")) && m.contains(&format!("{ty} handle")),
        "{m}"
    );
    assert_eq!(d.status, CcssStatus::ERR_INVALID_HANDLE);
}

/// A topology of the cube in a test block (interpolation takes one).
fn cube_topology(mem: &mut Vec<u64>) -> *const CcssTopology {
    let (p, s, i) = cube();
    let mut n = 0usize;
    let mut topo = ptr::null();
    unsafe {
        let st = ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut n, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        *mem = block(n);
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            mem.as_mut_ptr().cast(),
            n,
            &mut topo,
            ptr::null_mut(),
        );
        assert_eq!(st, CcssStatus::OK);
    }
    topo
}

#[test]
fn query_handles_garbage_and_foreign() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let pt = [0.0f64; 3];
    let mut inside = 0 as c_int;
    let ray = CcssQueryRay::default();
    let mut hit = CcssQueryHit::default();
    let mut found = 0 as c_int;
    let mut junk = junk_blocks();
    unsafe {
        // A real query block for the evaluator-argument checks.
        let mut n = 0usize;
        assert_eq!(ccss_query_required_bytes(&mut n, &mut d), CcssStatus::OK);
        let mut qm = block(n);
        let mut q = ptr::null_mut();
        assert_eq!(
            ccss_query_build(qm.as_mut_ptr().cast(), n, &mut q, &mut d),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_query_inside(b.ev, q, pt.as_ptr(), 1e-9, &mut inside, &mut d),
            CcssStatus::OK,
            "{}",
            msg(&d)
        );
        for j in junk.iter_mut() {
            let gq = j.as_mut_ptr() as *mut CcssQuery;
            let st = ccss_query_inside(b.ev, gq, pt.as_ptr(), 1e-9, &mut inside, &mut d);
            invalid(st, &d, "q", "ccss_query");
            let st = ccss_query_ray_first(b.ev, gq, &ray, 1, 1e-9, &mut hit, &mut found, &mut d);
            invalid(st, &d, "q", "ccss_query");
            // Junk as the evaluator, with a real query.
            let ge = j.as_ptr() as *const CcssEvaluator;
            let st = ccss_query_inside(ge, q, pt.as_ptr(), 1e-9, &mut inside, &mut d);
            invalid(st, &d, "ev", "ccss_evaluator");
        }
        // Foreign: the evaluator as the query, the query as the evaluator.
        let st = ccss_query_inside(
            b.ev,
            b.ev as *mut CcssQuery,
            pt.as_ptr(),
            1e-9,
            &mut inside,
            &mut d,
        );
        invalid(st, &d, "q", "ccss_query");
        let st = ccss_query_inside(
            q as *const CcssEvaluator,
            q,
            pt.as_ptr(),
            1e-9,
            &mut inside,
            &mut d,
        );
        invalid(st, &d, "ev", "ccss_evaluator");
        // An overwritten header, then restored.
        let off = <CcssQuery as crate::boundary::Handle>::MAGIC_OFFSET;
        let hdr = (q as *mut u8).add(off) as *mut u64;
        let saved = hdr.read();
        hdr.write(!saved);
        let st = ccss_query_inside(b.ev, q, pt.as_ptr(), 1e-9, &mut inside, &mut d);
        invalid(st, &d, "q", "ccss_query");
        hdr.write(saved);
        assert_eq!(
            ccss_query_inside(b.ev, q, pt.as_ptr(), 1e-9, &mut inside, &mut d),
            CcssStatus::OK
        );
    }
}

#[test]
fn feature_handles_garbage_and_foreign_name_the_feature_evaluator() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let junk = junk_blocks();
    let mut foreign: Vec<*const CcssFeatureEvaluator> = junk
        .iter()
        .map(|j| j.as_ptr() as *const CcssFeatureEvaluator)
        .collect();
    // Handles of other types.
    foreign.push(b.ev as *const CcssFeatureEvaluator);
    foreign.push(b.tables as *const CcssFeatureEvaluator);
    let mut r = CcssEvaluatorResult::default();
    let mut n = 0usize;
    let mut depth = 0u32;
    let mut mp = CcssMassProperties::default();
    let opts = CcssTessellationOptions {
        criterion: 0,
        tolerance: 1e-3,
        uniform_level: 0,
        max_level: 0,
    };
    unsafe {
        for &fe in &foreign {
            let st = ccss_feature_evaluator_face_count(fe, &mut n, &mut d);
            invalid(st, &d, "fe", "ccss_feature_evaluator");
            let st = ccss_feature_evaluator_eval(fe, 0, 0, 0.5, 0.5, &mut r, &mut d);
            invalid(st, &d, "fe", "ccss_feature_evaluator");
            let st = ccss_feature_evaluator_depth(fe, 0, 0, 1e-3, &mut depth, &mut d);
            invalid(st, &d, "ev", "ccss_feature_evaluator");
            let st = ccss_mass_properties_compute_feature(fe, &mut mp, &mut d);
            invalid(st, &d, "ev", "ccss_feature_evaluator");
            let st = ccss_voxel_grid_voxelize_feature(
                fe,
                ptr::null_mut(),
                6,
                8,
                ptr::null(),
                ptr::null_mut(),
                &mut d,
            );
            invalid(st, &d, "ev", "ccss_feature_evaluator");
            // The tessellation of a feature evaluator.
            let st = ccss_tessellation_feature_required_bytes(fe, &opts, &mut n, &mut d);
            invalid(st, &d, "fe", "ccss_feature_evaluator");
            let mut mem = block(4096);
            let mut t = ptr::null_mut();
            let st = ccss_tessellation_feature_build(
                fe,
                &opts,
                mem.as_mut_ptr().cast(),
                4096,
                &mut t,
                &mut d,
            );
            invalid(st, &d, "fe", "ccss_feature_evaluator");
            assert!(t.is_null());
        }
        // Garbage and foreign tessellation handles.
        let mut c = CcssTessellationCountsInfo::default();
        for j in &junk {
            let st =
                ccss_tessellation_counts(j.as_ptr() as *const CcssTessellation, &mut c, &mut d);
            invalid(st, &d, "tess", "ccss_tessellation");
        }
        let st = ccss_tessellation_counts(b.ev as *const CcssTessellation, &mut c, &mut d);
        invalid(st, &d, "tess", "ccss_tessellation");
    }
}

#[test]
fn interpolation_handles_garbage_and_foreign() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut tmem = Vec::new();
    let topo = cube_topology(&mut tmem);
    let mut d = Failure::invalid("x").to_detail();
    let (mut nv, mut nf) = (0usize, 0usize);
    unsafe {
        assert_eq!(
            ccss_interpolation_counts(topo, &mut nv, &mut nf, &mut d),
            CcssStatus::OK
        );
        let mut pos = vec![0.0f64; 3 * nv];
        let mut idx = vec![0u32; 4 * nf];
        let mut mem = block(1 << 16);
        let solve = |t: *const CcssTopology,
                     tb: *const CcssTables,
                     mem: &mut Vec<u64>,
                     pos: &mut Vec<f64>,
                     idx: &mut Vec<u32>,
                     d: &mut CcssErrorDetail| {
            ccss_interpolation_solve(
                t,
                tb,
                ptr::null(),
                ptr::null(),
                0,
                mem.as_mut_ptr().cast(),
                mem.len() * 8,
                pos.as_mut_ptr(),
                pos.len(),
                idx.as_mut_ptr(),
                idx.len(),
                ptr::null_mut(),
                d,
            )
        };
        let junk = junk_blocks();
        let mut bad_topo: Vec<*const CcssTopology> = junk
            .iter()
            .map(|j| j.as_ptr() as *const CcssTopology)
            .collect();
        bad_topo.push(b.ev as *const CcssTopology);
        bad_topo.push(b.tables as *const CcssTopology);
        for &t in &bad_topo {
            let st = ccss_interpolation_counts(t, &mut nv, &mut nf, &mut d);
            invalid(st, &d, "topology", "ccss_topology");
            let mut n = 0usize;
            let st = ccss_interpolation_required_bytes(t, ptr::null(), 0, &mut n, &mut d);
            invalid(st, &d, "topology", "ccss_topology");
            let st = solve(t, b.tables, &mut mem, &mut pos, &mut idx, &mut d);
            invalid(st, &d, "topology", "ccss_topology");
        }
        let mut bad_tables: Vec<*const CcssTables> = junk
            .iter()
            .map(|j| j.as_ptr() as *const CcssTables)
            .collect();
        bad_tables.push(b.ev as *const CcssTables);
        bad_tables.push(topo as *const CcssTables);
        for &tb in &bad_tables {
            let st = solve(topo, tb, &mut mem, &mut pos, &mut idx, &mut d);
            invalid(st, &d, "tables", "ccss_tables");
        }
    }
}

/// Byte offsets of the evaluator block's core arena (after the handle
/// header) and its end, from the size query.
fn arena_of(b: &Built) -> (usize, usize) {
    let head = crate::boundary::round8(core::mem::size_of::<CcssEvaluator>());
    (head, b.eval_bytes)
}

#[test]
fn integrity_check_finds_flipped_bytes() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    unsafe {
        assert_eq!(ccss_evaluator_verify(b.ev, &mut d), CcssStatus::OK);
        assert_eq!(ccss_tables_verify(b.tables, &mut d), CcssStatus::OK);
        // Every 7th byte of the evaluator's arena, one at a time.
        let (from, to) = arena_of(&b);
        let base = b.ev as *mut u8;
        let mut tried = 0;
        let mut at = from;
        while at < to {
            let x = base.add(at);
            let saved = x.read();
            x.write(saved ^ 0x10);
            let st = ccss_evaluator_verify(b.ev, &mut d);
            assert_eq!(st, CcssStatus::ERR_CORRUPTED, "byte {at}: {}", msg(&d));
            assert!(
                msg(&d).contains("ccss_evaluator block changed"),
                "{}",
                msg(&d)
            );
            x.write(saved);
            tried += 1;
            at += 7;
        }
        assert!(tried > 100, "{tried}");
        assert_eq!(ccss_evaluator_verify(b.ev, &mut d), CcssStatus::OK);
        // The tables: bytes of words that evaluation reads (found by their
        // values: words of the valence-5 table as the core lists them).
        let set = &(&*b.tables).set;
        let mut words = Vec::new();
        set.get(5).unwrap().for_each_word(|w| words.push(w));
        let tbase = b.tables as *mut u8;
        let mut tb = 0usize;
        ccss_tables_required_bytes(&mut tb, &mut d);
        let table_words = core::slice::from_raw_parts(tbase as *const u64, tb / 8);
        let mut flipped = 0;
        for w in words.iter().step_by(97) {
            if *w == 0 || f64::from_bits(*w).abs() < 1e-300 {
                continue;
            }
            let Some(k) = table_words.iter().position(|x| x == w) else {
                continue;
            };
            let x = tbase.add(8 * k + 3);
            let saved = x.read();
            x.write(saved ^ 0x01);
            assert_eq!(
                ccss_tables_verify(b.tables, &mut d),
                CcssStatus::ERR_CORRUPTED
            );
            assert!(msg(&d).contains("ccss_tables block changed"), "{}", msg(&d));
            // The evaluator built from them reports it too.
            assert_eq!(
                ccss_evaluator_verify(b.ev, &mut d),
                CcssStatus::ERR_CORRUPTED
            );
            x.write(saved);
            flipped += 1;
        }
        assert!(flipped > 10, "{flipped}");
        assert_eq!(ccss_tables_verify(b.tables, &mut d), CcssStatus::OK);
        assert_eq!(ccss_evaluator_verify(b.ev, &mut d), CcssStatus::OK);
        // Garbage handles: INVALID_HANDLE, not CORRUPTED.
        let junk = vec![0u64; 1 << 12];
        let st = ccss_evaluator_verify(junk.as_ptr() as *const CcssEvaluator, &mut d);
        invalid(st, &d, "ev", "ccss_evaluator");
        let st = ccss_tables_verify(junk.as_ptr() as *const CcssTables, &mut d);
        invalid(st, &d, "tables", "ccss_tables");
    }
}
