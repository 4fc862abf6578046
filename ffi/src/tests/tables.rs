//! General vertex rules: weighted tables, weight errors, the weights check.

use super::*;

#[test]
fn weighted_tables_build_eval_and_info() {
    let (p, s, i) = cube();
    let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
    let mut d = Failure::invalid("x").to_detail();
    let (a, b, g) = (0.5, 0.3, 0.2);
    let mut maxv = 0usize;
    unsafe {
        assert_eq!(ccss_max_valence(&mut maxv, ptr::null_mut()), CcssStatus::OK);
        assert_eq!(
            ccss_tables_required_bytes(&mut tb, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    let entries: Vec<CcssWeightEntry> = (3..=maxv as u32)
        .filter(|&n| n != 4)
        .map(|n| entry(n, a, b, g))
        .collect();
    let mut tmem = block(tb);
    let mut gmem = block(gb);
    let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
    let mut info = CcssTablesValenceInfo::default();
    let mut r = CcssEvaluatorResult::default();
    let before = alloc_count::get();
    unsafe {
        let st = ccss_tables_build(
            entries.as_ptr(),
            entries.len(),
            tmem.as_mut_ptr().cast(),
            tb,
            &mut tables,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_tables_valence(tables, 3, &mut info, ptr::null_mut()),
            CcssStatus::OK
        );
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            gmem.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d),
            CcssStatus::OK
        );
    }
    assert_eq!(alloc_count::get(), before, "weighted tables allocated");
    // Valence 3: the rule, 2n+8 points, and the limit mask of eq. 2.7,
    // (5 V + (12b+8g) Ebar + (2b+8g) Fbar) / (5+14b+16g).
    let den = 5.0 + 14.0 * b + 16.0 * g;
    assert_eq!((info.valence, info.num_points), (3, 14));
    assert_eq!((info.alpha, info.beta, info.gamma), (a, b, g));
    assert!((info.limit_v - 5.0 / den).abs() < 1e-13, "{info:?}");
    assert!((info.limit_e - (12.0 * b + 8.0 * g) / (3.0 * den)).abs() < 1e-13);
    assert!((info.limit_f - (2.0 * b + 8.0 * g) / (3.0 * den)).abs() < 1e-13);
    assert!((info.limit_v + 3.0 * info.limit_e + 3.0 * info.limit_f - 1.0).abs() < 1e-13);
    let w = {
        let mut w = Weights::STANDARD;
        w.set(3, a, b, g).unwrap();
        w
    };
    assert_eq!(
        info.tangent_plane_continuous,
        w.tangent_plane_continuous(3) as c_int
    );
    // x^2 - (a - 1/4) x + (1 - 2b)/16 has complex roots of modulus
    // sqrt(1/40) < lambda_2(3), which stays subdominant.
    assert_eq!(info.complex_pair, 1);
    assert!(
        (info.subdominant - Weights::lambda2(3)).abs() < 1e-12,
        "{info:?}"
    );
    unsafe {
        assert_eq!(
            ccss_tables_valence(tables, 4, &mut info, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!((info.alpha, info.beta, info.gamma), (0.5625, 0.375, 0.0625));
        assert!((info.limit_v - 16.0 / 36.0).abs() < 1e-14);
        assert!((info.limit_e - 4.0 / 36.0).abs() < 1e-14);
        assert!((info.limit_f - 1.0 / 36.0).abs() < 1e-14);
        assert_eq!((info.tangent_plane_continuous, info.complex_pair), (1, 0));
        let keep = info;
        for bad in [0u32, 2, maxv as u32 + 1, u32::MAX] {
            assert_eq!(
                ccss_tables_valence(tables, bad, &mut info, ptr::null_mut()),
                CcssStatus::ERR_UNSUPPORTED_VALENCE
            );
        }
        assert_eq!(info, keep, "written on failure");
    }
    // Evaluation uses the rule: corner v0 of the cube (face 0, u=v=0),
    // E = v1 v3 v4, F = v2 v5 v7: 5 V + (12b+8g) Ebar + (2b+8g) Fbar,
    // where Ebar = V/3 and Fbar = -V/3 (V = (-1, -1, -1)).
    let mut emem = block(eb);
    unsafe {
        let st = ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_eval(ev, 0, 0, 0.0, 0.0, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    let c = (-5.0 - (12.0 * b + 8.0 * g) / 3.0 + (2.0 * b + 8.0 * g) / 3.0) / den;
    for k in 0..3 {
        assert!((r.p[k] - c).abs() < 1e-13, "{:?} vs {c}", r.p);
    }
    // Differs from the standard corner (-1/2).
    assert!((c + 0.5).abs() > 1e-3);
    drop((tmem, gmem, emem));
}

#[test]
fn weight_errors_name_the_entry_and_write_nothing() {
    let mut tb = 0usize;
    unsafe { ccss_tables_required_bytes(&mut tb, ptr::null_mut()) };
    let mut tmem = block(tb);
    let sentinel = 0x5a5a_5a5a_5a5a_5a5au64;
    tmem.iter_mut().for_each(|x| *x = sentinel);
    let out_before = 8usize as *const CcssTables;
    let cases: [(Vec<CcssWeightEntry>, CcssStatus, u64, i64, &str); 7] = [
        (
            vec![entry(3, 0.5, 0.3, 0.2), entry(4, 0.5, 0.3, 0.2)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            1,
            4,
            "entry 1: weights for valence 4 rejected: valence 4 must keep the standard rule",
        ),
        (
            vec![entry(5, 0.5, -0.1, 0.6)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            0,
            5,
            "entry 0: weights for valence 5 rejected: a weight is negative",
        ),
        (
            vec![entry(3, 0.5, 0.3, 0.2), entry(6, 0.5, 0.3, 0.3)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            1,
            6,
            "alpha + beta + gamma is not 1",
        ),
        (
            vec![entry(3, f64::NAN, 0.3, 0.2)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            0,
            3,
            "NaN or infinite",
        ),
        (
            vec![entry(2, 0.5, 0.3, 0.2)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            0,
            2,
            "valence outside",
        ),
        (
            vec![entry(u32::MAX, 0.5, 0.3, 0.2)],
            CcssStatus::ERR_INVALID_WEIGHTS,
            0,
            u32::MAX as i64,
            "valence outside",
        ),
        (
            vec![
                entry(3, 0.5, 0.3, 0.2),
                entry(5, 0.5, 0.3, 0.2),
                entry(3, 0.5, 0.3, 0.2),
            ],
            CcssStatus::ERR_INVALID_ARGUMENT,
            2,
            3,
            "entry 2: invalid argument: valence 3 is listed twice (first in entry 0)",
        ),
    ];
    for (es, want, idx, val, text) in cases {
        let mut d = Failure::invalid("x").to_detail();
        let mut out = out_before;
        // Also with a too-small block: the entries are checked first.
        for len in [tb, 16] {
            let before = alloc_count::get();
            let st = unsafe {
                ccss_tables_build(
                    es.as_ptr(),
                    es.len(),
                    tmem.as_mut_ptr().cast(),
                    len,
                    &mut out,
                    &mut d,
                )
            };
            assert_eq!(alloc_count::get(), before, "error path allocated");
            assert_eq!(st, want, "{es:?}");
            assert_eq!(d.status, want);
            assert_eq!((d.query_index, d.value, d.vertex), (idx, val, -1), "{es:?}");
            assert!(msg(&d).contains(text), "{}", msg(&d));
        }
        assert_eq!(out, out_before, "out written on failure");
        assert!(
            tmem.iter().all(|&x| x == sentinel),
            "mem written on failure"
        );
    }
    // Pointer errors.
    let mut d = Failure::invalid("x").to_detail();
    let mut out = ptr::null();
    unsafe {
        let st = ccss_tables_build(
            ptr::null(),
            1,
            tmem.as_mut_ptr().cast(),
            tb,
            &mut out,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        assert!(msg(&d).contains("`entries`"));
        let es = [entry(3, 0.5, 0.3, 0.2)];
        let st = ccss_tables_build(
            es.as_ptr(),
            1,
            tmem.as_mut_ptr().cast(),
            tb,
            ptr::null_mut(),
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        let st = ccss_tables_build(
            es.as_ptr(),
            1,
            tmem.as_mut_ptr().cast(),
            16,
            &mut out,
            &mut d,
        );
        assert_eq!(
            (st, d.required),
            (CcssStatus::ERR_BUFFER_TOO_SMALL, tb as u64)
        );
        // No entries: the standard tables.
        let st = ccss_tables_build(
            ptr::null(),
            0,
            tmem.as_mut_ptr().cast(),
            tb,
            &mut out,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        let mut info = CcssTablesValenceInfo::default();
        assert_eq!(
            ccss_tables_valence(out, 5, &mut info, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            (info.alpha, info.beta, info.gamma),
            ccss_core::mesh::weights::standard(5)
        );
        assert!((info.limit_v - 25.0 / 50.0).abs() < 1e-14, "{info:?}");
        assert_eq!(
            ccss_tables_valence(out, 5, ptr::null_mut(), ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
        assert_eq!(
            ccss_tables_valence(ptr::null(), 5, &mut info, ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
    }
}

#[test]
fn weights_check_reports_continuity() {
    let mut d = Failure::invalid("x").to_detail();
    let mut tpc: c_int = -7;
    let mut check =
        |e: CcssWeightEntry, tpc: &mut c_int| unsafe { ccss_weight_entry_check(&e, tpc, &mut d) };
    for n in 3..=ccss_core::MAX_VALENCE as u32 {
        let (a, b, g) = ccss_core::mesh::weights::standard(n as usize);
        assert_eq!(check(entry(n, a, b, g), &mut tpc), CcssStatus::OK);
        assert_eq!(tpc, 1, "standard rule at valence {n}");
    }
    // alpha = 0.5, beta = 0.3, gamma = 0.2 at valence 3: x^2 - x/4 + 1/40
    // has complex roots of modulus sqrt(1/40) = 0.158 < lambda_2(3) = 0.41.
    assert_eq!(check(entry(3, 0.5, 0.3, 0.2), &mut tpc), CcssStatus::OK);
    assert_eq!(tpc, 1);
    // alpha close to 1: lambda_0 close to 3/4 > lambda_2(5) ~ 0.55.
    assert_eq!(check(entry(5, 0.98, 0.01, 0.01), &mut tpc), CcssStatus::OK);
    assert_eq!(tpc, 0);
    let mut w = Weights::STANDARD;
    w.set(5, 0.98, 0.01, 0.01).unwrap();
    assert!(!w.tangent_plane_continuous(5));
    tpc = -7;
    let before = alloc_count::get();
    let st = check(entry(4, 0.5, 0.3, 0.2), &mut tpc);
    assert_eq!(
        alloc_count::get(),
        before,
        "ccss_weight_entry_check allocated"
    );
    assert_eq!(st, CcssStatus::ERR_INVALID_WEIGHTS);
    assert_eq!(tpc, -7, "written on failure");
    assert_eq!((d.value, d.query_index), (4, u64::MAX));
    assert!(
        msg(&d).starts_with("weights for valence 4 rejected"),
        "{}",
        msg(&d)
    );
    unsafe {
        let e = entry(3, 0.5, 0.3, 0.2);
        assert_eq!(
            ccss_weight_entry_check(ptr::null(), &mut tpc, ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
        assert_eq!(
            ccss_weight_entry_check(&e, ptr::null_mut(), ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
    }
    assert_eq!(
        CCSS_WEIGHT_ENTRY_SUM_TOLERANCE,
        ccss_core::mesh::weights::SUM_TOLERANCE
    );
    let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(22)) };
    assert!(m.to_str().unwrap().contains("weights"));
}
