//! Subdivision depth through the ABI.

use super::*;

const METHODS: [(u32, Method); 4] = [
    (CcssDepthMethod::DEPTH_OLD as u32, Method::Old),
    (CcssDepthMethod::DEPTH_NEW as u32, Method::New),
    (CcssDepthMethod::DEPTH_BEST as u32, Method::Best),
    (CcssDepthMethod::DEPTH_TIGHT as u32, Method::Tight),
];

#[test]
fn depths_match_core_and_do_not_allocate() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    // SAFETY: a live handle built above.
    let core_ev = unsafe { &(*b.ev).ev };
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    let mut start = 0usize;
    let mut got = [0u32; 6];
    let mut want = [0u32; 6];
    let before = alloc_count::get();
    unsafe {
        assert_eq!(
            ccss_evaluator_slot_count(b.ev, &mut n, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(n, 6);
        for f in 0..6u32 {
            assert_eq!(
                ccss_evaluator_slot_start(b.ev, f, &mut start, ptr::null_mut()),
                CcssStatus::OK
            );
            assert_eq!(start, f as usize);
        }
        for eps in [0.1, 0.01, 1e-3, 1e-6] {
            for (m, cm) in METHODS {
                let st = ccss_depth_compute(b.ev, eps, m, got.as_mut_ptr(), 6, &mut d);
                assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
                ccss_core::bounds::depth::depths(core_ev, eps, cm, &mut want).unwrap();
                assert_eq!(got, want, "eps {eps} method {m}");
            }
        }
    }
    assert_eq!(alloc_count::get(), before, "depth paths allocated");
    // Cube: all faces alike; smaller eps, deeper; TIGHT <= NEW, BEST <= all.
    let depth = |eps: f64, m: u32| {
        let mut o = [0u32; 6];
        let st = unsafe { ccss_depth_compute(b.ev, eps, m, o.as_mut_ptr(), 6, ptr::null_mut()) };
        assert_eq!(st, CcssStatus::OK);
        assert!(o.iter().all(|&x| x == o[0]), "{o:?}");
        o[0]
    };
    for eps in [0.01, 1e-4] {
        let [old, new, best, tight] = [0, 1, 2, 3].map(|m| depth(eps, m));
        assert!(tight <= new && best <= old && best <= new && best <= tight);
        assert!(best > 0 && best < 40, "{best}");
    }
    assert!(depth(1e-4, 2) > depth(0.01, 2));
}

#[test]
fn depth_errors_write_nothing() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut d = Failure::invalid("x").to_detail();
    let sentinel = 0xdead_beef_u32;
    let mut out = [sentinel; 8];
    // Each call, failing or not, allocates nothing (the checks of the
    // messages below do).
    let call = |eps: f64, m: u32, o: *mut u32, len: usize, d: &mut CcssErrorDetail| {
        let before = alloc_count::get();
        let st = unsafe { ccss_depth_compute(b.ev, eps, m, o, len, d) };
        assert_eq!(alloc_count::get(), before, "ccss_depth_compute allocated");
        st
    };
    let o = out.as_mut_ptr();
    for eps in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let st = call(eps, 2, o, 8, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "eps {eps}");
        assert!(
            msg(&d).contains("eps must be positive and finite"),
            "{}",
            msg(&d)
        );
    }
    for m in [4u32, 99, u32::MAX] {
        let st = call(0.01, m, o, 8, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "method {m}");
        assert!(msg(&d).contains("ccss_depth_method"), "{}", msg(&d));
    }
    let st = call(0.01, 2, o, 5, &mut d);
    assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 6));
    assert_eq!(d.status, CcssStatus::ERR_BUFFER_TOO_SMALL);
    let st = call(0.01, 2, ptr::null_mut(), 0, &mut d);
    assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 6));
    let st = call(0.01, 2, ptr::null_mut(), 6, &mut d);
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
    assert!(msg(&d).contains("`out`"));
    let mis = (out.as_mut_ptr() as *mut u8).wrapping_add(1) as *mut u32;
    assert_eq!(call(0.01, 2, mis, 6, &mut d), CcssStatus::ERR_MISALIGNED);
    assert!(out.iter().all(|&x| x == sentinel), "written on failure");
    unsafe {
        let st = ccss_depth_compute(ptr::null(), 0.01, 2, o, 8, &mut d);
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        let mut n = 7usize;
        assert_eq!(
            ccss_evaluator_slot_count(ptr::null(), &mut n, ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
        assert_eq!(
            ccss_evaluator_slot_count(b.ev, ptr::null_mut(), ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
        for f in [6u32, u32::MAX] {
            assert_eq!(
                ccss_evaluator_slot_start(b.ev, f, &mut n, ptr::null_mut()),
                CcssStatus::ERR_FACE_OUT_OF_RANGE
            );
        }
        assert_eq!(n, 7, "written on failure");
    }
    // Enough room is enough: a larger buffer keeps its tail.
    assert_eq!(call(0.01, 2, o, 8, &mut d), CcssStatus::OK);
    assert_eq!(out[6..], [sentinel; 2]);
}

#[test]
fn depth_slots_of_triangles_and_general_weights() {
    // Tetrahedron: 4 triangles, 3 sub-faces each.
    let p = [1., 1., 1., 1., -1., -1., -1., 1., -1., -1., -1., 1.];
    let s = [3u32; 4];
    let i = [0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2];
    let b = build_mesh(&p, &s, &i, &[]);
    let mut n = 0usize;
    unsafe {
        assert_eq!(
            ccss_evaluator_slot_count(b.ev, &mut n, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(n, 12);
        for f in 0..4u32 {
            assert_eq!(
                ccss_evaluator_slot_start(b.ev, f, &mut n, ptr::null_mut()),
                CcssStatus::OK
            );
            assert_eq!(n, 3 * f as usize);
        }
        let mut o = [0u32; 12];
        let st = ccss_depth_compute(b.ev, 0.01, 2, o.as_mut_ptr(), 12, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        // All sub-faces alike (the tetrahedron's symmetry).
        assert!(o.iter().all(|&x| x == o[0] && x > 0), "{o:?}");
    }
    // A general rule at valence 3: the old technique does not apply.
    let (p, s, i) = cube();
    let w = build_mesh(&p, &s, &i, &[entry(3, 0.5, 0.3, 0.2)]);
    let mut d = Failure::invalid("x").to_detail();
    let mut o = [7u32; 6];
    unsafe {
        let st = ccss_depth_compute(w.ev, 0.01, 0, o.as_mut_ptr(), 6, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        assert!(msg(&d).contains("standard weights"), "{}", msg(&d));
        assert_eq!(o, [7; 6]);
        for m in [1, 2, 3] {
            let st = ccss_depth_compute(w.ev, 0.01, m, o.as_mut_ptr(), 6, &mut d);
            assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
            assert!(o.iter().all(|&x| x > 0 && x < 100), "{o:?}");
        }
        let mut r = CcssDepthRatesInfo::default();
        assert_eq!(
            ccss_depth_rates(w.tables, 3, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!((r.valence, r.r_old, r.c_old), (3, 0.0, 0.0));
        assert!(r.r2 > 0.0 && r.r2 < 1.0 && r.c_new > 0.0, "{r:?}");
        // Valence 5 keeps the standard rule there.
        assert_eq!(
            ccss_depth_rates(w.tables, 5, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!((r.r_old, r.c_old), (18.0 / 25.0, 5.0 / 7.0));
    }
}

#[test]
fn depth_rates_are_the_tables_rates() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let mut maxv = 0usize;
    let mut r = CcssDepthRatesInfo::default();
    let before = alloc_count::get();
    unsafe {
        assert_eq!(ccss_max_valence(&mut maxv, ptr::null_mut()), CcssStatus::OK);
        // SAFETY: a live handle.
        let set = &(*b.tables).inner.set;
        for n in 3..=maxv as u32 {
            assert_eq!(
                ccss_depth_rates(b.tables, n, &mut r, ptr::null_mut()),
                CcssStatus::OK
            );
            let want = set.get(n as usize).unwrap().rates();
            assert_eq!(r, CcssDepthRatesInfo::from(want), "n={n}");
            assert_eq!(r.valence, n);
        }
        // Report Table 2, n = 5 (and Lemma 2's rate).
        assert_eq!(
            ccss_depth_rates(b.tables, 5, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
        assert!(
            (r.r1 - 0.72).abs() < 5e-5 && (r.r2 - 0.4016).abs() < 5e-5,
            "{r:?}"
        );
        assert_eq!(r.r_old, 18.0 / 25.0);
        let keep = r;
        for bad in [0u32, 2, maxv as u32 + 1, u32::MAX] {
            assert_eq!(
                ccss_depth_rates(b.tables, bad, &mut r, ptr::null_mut()),
                CcssStatus::ERR_UNSUPPORTED_VALENCE
            );
        }
        assert_eq!(r, keep, "written on failure");
        assert_eq!(
            ccss_depth_rates(ptr::null(), 5, &mut r, ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
        assert_eq!(
            ccss_depth_rates(b.tables, 5, ptr::null_mut(), ptr::null_mut()),
            CcssStatus::ERR_NULL_POINTER
        );
    }
    assert_eq!(alloc_count::get(), before, "ccss_depth_rates allocated");
}

#[test]
fn depth_method_values_are_stable() {
    for (v, m) in METHODS {
        assert_eq!(CcssDepthMethod::from_raw(v).map(|x| x.core()), Some(m));
    }
    assert_eq!(CcssDepthMethod::from_raw(4), None);
    assert_eq!(
        [0, 1, 2, 3].map(|v: u32| CcssDepthMethod::from_raw(v).unwrap() as u32),
        [0, 1, 2, 3]
    );
}
