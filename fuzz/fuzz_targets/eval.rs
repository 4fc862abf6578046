//! Evaluation: single points (f64, second derivatives, f32), batches, with
//! fuzzed (face, sub, u, v): in-range queries of a tame mesh give finite
//! points; out-of-range ones a named error; a batch agrees with single
//! evaluations bit for bit.
#![no_main]
use ccss_core::{Error, Query};
use ccss_fuzz::{assert_finite, evaluator, topology, Input, CAPS};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
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
    let mut r = x.rng();
    let nf = ev.num_faces() as u64;
    let mut qs = [Query::default(); 8];
    for q in qs.iter_mut() {
        let face = if r.below(16) == 0 {
            r.next_u64() as u32
        } else {
            r.below(nf + 1) as u32
        };
        let sub = r.below(6) as u32;
        let (u, v) = (r.param(), r.param());
        *q = Query { face, sub, u, v };
        let inside = (face as u64) < nf
            && (sub as usize) < ev.num_subfaces(face as usize)
            && (0.0..=1.0).contains(&u)
            && (0.0..=1.0).contains(&v);
        let one = ev.eval_second(face, sub, u, v);
        match one {
            Ok(e) => {
                assert!(inside, "accepted {q:?}");
                if x.tame() {
                    assert_finite("p", &e.p.to_array());
                }
                let f = ev.eval_f32(face, sub, u as f32, v as f32);
                assert!(f.is_ok() || u as f32 > 1.0 || v as f32 > 1.0);
            }
            Err(Error::FaceOutOfRange { .. } | Error::SubFaceOutOfRange { .. }) => {
                assert!(!inside)
            }
            Err(Error::ParameterOutOfRange) => assert!(!inside),
            Err(e) => panic!("{q:?}: {e:?}"),
        }
    }
    let mut out = [ccss_core::Eval::default(); 8];
    if ev.eval_batch(&qs, true, &mut out).is_ok() {
        for (q, o) in qs.iter().zip(&out) {
            let e = ev
                .eval_second(q.face, q.sub, q.u, q.v)
                .expect("batch accepted it");
            assert_eq!(
                e.p.to_array().map(f64::to_bits),
                o.p.to_array().map(f64::to_bits)
            );
        }
    }
});
