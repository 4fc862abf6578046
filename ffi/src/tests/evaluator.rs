//! Tables, topology and evaluator: build, evaluation, errors, no allocation.

use super::*;

#[test]
fn build_eval_and_errors_do_not_allocate() {
    let (p, s, i) = cube();
    let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
    let mut d = Failure::invalid("x").to_detail();
    unsafe {
        assert_eq!(
            ccss_tables_required_bytes(&mut tb, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    let b = alloc_count::get();
    let probe = std::hint::black_box(vec![1u8]);
    assert!(alloc_count::get() > b, "the allocation counter counts");
    drop(probe);
    let mut tmem = block(tb);
    let mut gmem = block(gb);
    let mut bad = i;
    bad[5] = 7; // face 1 = 4 7 6 7: repeated vertex
    let mut tables = ptr::null();
    let mut topo = ptr::null();
    let mut ev = ptr::null();
    let before = alloc_count::get();
    unsafe {
        let st =
            ccss_tables_build_standard(tmem.as_mut_ptr().cast(), tb, &mut tables, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            bad.as_ptr(),
            24,
            gmem.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_REPEATED_VERTEX);
        assert_eq!((d.face, d.vertex), (1, 7));
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
    assert_eq!(alloc_count::get(), before, "tables / topology allocated");
    let mut emem = block(eb);
    let qs = [
        CcssEvaluatorQuery {
            face: 0,
            sub: 0,
            u: 0.5,
            v: 0.5,
        },
        CcssEvaluatorQuery {
            face: 1,
            sub: 0,
            u: 0.0,
            v: 0.25,
        },
    ];
    let mut res = [CcssEvaluatorResult::default(); 2];
    let mut r = CcssEvaluatorResult::default();
    let before = alloc_count::get();
    unsafe {
        let st = ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_eval(ev, 0, 0, 0.5, 0.5, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
        assert!((r.p[2] + 68.0 / 81.0).abs() < 1e-12);
        assert_eq!(
            ccss_evaluator_eval_second(ev, 0, 0, 0.5, f64::NAN, &mut r, ptr::null_mut()),
            CcssStatus::ERR_PARAMETER_OUT_OF_RANGE
        );
        let st = ccss_evaluator_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 2, &mut d);
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_evaluator_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 1, &mut d);
        assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 2));
        let mut buf = [0 as c_char; 64];
        assert!(ccss_error_detail_format(&d, buf.as_mut_ptr(), 64) > 0);
    }
    assert_eq!(alloc_count::get(), before, "evaluator / eval allocated");
    drop((tmem, gmem, emem));
}
