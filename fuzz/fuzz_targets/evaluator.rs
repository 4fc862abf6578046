//! Eigen tables and the evaluator build. Header byte 2 picks a valence
//! (3..=MAX_VALENCE) and bytes 3..6 a vertex rule (`alpha, beta, gamma`
//! near the standard one, or far off, or not finite): one `ValenceTable`
//! build must succeed or fail with a named error, never panic. Then the
//! smooth evaluator of the mesh with the standard tables: the size query
//! is exact and every patch evaluates to finite numbers at its centre.
#![no_main]
use ccss_core::eigen::ValenceTable;
use ccss_core::{BuildScratch, Error, Evaluator, Weights, MAX_VALENCE};
use ccss_fuzz::{assert_finite, tables, topology, words, Input, CAPS};
use libfuzzer_sys::fuzz_target;
use std::cell::RefCell;

thread_local! {
    static WORK: RefCell<(Box<ValenceTable>, Box<BuildScratch>)> =
        RefCell::new((Box::new(ValenceTable::ZERO), Box::new(BuildScratch::ZERO)));
}

fn weight(b: u8, standard: f64) -> f64 {
    match b >> 5 {
        0 => standard,
        1 => standard * (1.0 + (b & 31) as f64 / 64.0),
        2 => standard * (1.0 - (b & 31) as f64 / 64.0),
        3 => (b & 31) as f64 - 16.0,
        4 => f64::NAN,
        5 => 1e300,
        6 => -standard,
        _ => 0.0,
    }
}

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let h = x.header;
    if h[2] & 1 == 1 {
        let n = 3 + (h[2] as usize >> 1) % (MAX_VALENCE - 2);
        let (a, b, g) = ccss_core::mesh::weights::standard(n);
        let mut w = Weights::STANDARD;
        if w.set(n, weight(h[3], a), weight(h[4], b), weight(h[5], g))
            .is_ok()
        {
            WORK.with(|c| {
                let (t, s) = &mut *c.borrow_mut();
                match t.build_into(n, &w, s) {
                    Ok(()) => assert_finite("eigenvalues", t.eigenvalues()),
                    Err(Error::TableBuildFailed { .. }) => {}
                    Err(e) => panic!("table build: {e:?}"),
                }
            });
        }
    }
    let mut tmem = Vec::new();
    let Some(topo) = topology(x.input(), &mut tmem) else {
        return;
    };
    let t = tables();
    let Ok(need) = Evaluator::required_bytes(&topo, t) else {
        return;
    };
    let mut emem = words(need);
    let Ok(ev) = Evaluator::build(&topo, t, &mut emem) else {
        return;
    };
    for f in 0..ev.num_faces() {
        for s in 0..ev.num_subfaces(f) {
            let e = ev.eval(f as u32, s as u32, 0.5, 0.5).expect("in range");
            if x.tame() {
                assert_finite("centre", &e.p.to_array());
            }
        }
    }
    let mut short = words(need - 8);
    match Evaluator::build(&topo, t, &mut short) {
        Err(Error::BufferTooSmall { required }) => assert_eq!(required, need),
        other => panic!("short block: {:?}", other.map(|_| ())),
    }
});
