//! Adaptive tessellation of the smooth surface. Header byte 2 picks the
//! criterion (absolute or relative tolerance `2^-(1..=8)` of the size,
//! uniform level 0..=2, or a bad tolerance: 0, negative, NaN, inf) and
//! byte 3 `max_level` (0..=4, so at most 4^4 leaves per slot). The size
//! query is exact; a built tessellation emits into exactly sized buffers,
//! polygons index emitted vertices, and a tame mesh gives finite
//! positions; a buffer one word short is `BufferTooSmall`.
#![no_main]
use ccss_core::eval::Query;
use ccss_core::tessellate::{Criterion, Options, Output, Scratch, Tessellation};
use ccss_core::Error;
use ccss_fuzz::{assert_finite, evaluator, topology, words, Caps, Input};
use libfuzzer_sys::fuzz_target;
use std::cell::RefCell;

thread_local! {
    static SCRATCH: RefCell<Box<Scratch>> = RefCell::new(Box::new(Scratch::ZERO));
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
    let tol = 2f64.powi(-1 - (h[2] as i32 >> 3) % 8) * x.max_abs.max(1e-300);
    let criterion = match h[2] & 7 {
        0 | 1 => Criterion::Absolute(tol),
        2 | 3 => Criterion::Relative(2f64.powi(-1 - (h[2] as i32 >> 3) % 8)),
        4 | 5 => Criterion::Uniform((h[2] as u32 >> 3) % 3),
        6 => Criterion::Absolute([0.0, -1.0, f64::NAN, f64::INFINITY][(h[2] as usize >> 3) % 4]),
        _ => Criterion::Relative(f64::MIN_POSITIVE),
    };
    let opts = Options {
        criterion,
        max_level: h[3] as u32 % 5,
    };
    let mut tmem = Vec::new();
    let Some(topo) = topology(x.input(), &mut tmem) else {
        return;
    };
    let mut emem = Vec::new();
    let Some(ev) = evaluator(&topo, &mut emem) else {
        return;
    };
    let need =
        SCRATCH.with(|s| Tessellation::required_bytes(&topo, &ev, &opts, &mut s.borrow_mut()));
    let need = match need {
        Ok(n) => n,
        Err(Error::InvalidArgument(_) | Error::CoordinateRange(_)) => return,
        Err(e) => panic!("{e:?}"),
    };
    let mut mem = words(need);
    let mut t = Tessellation::build(&topo, &ev, opts, &mut mem).expect("size query accepted it");
    let c = t.counts();
    let mut pos = vec![0.0; 3 * c.vertices];
    let mut nrm = vec![0.0; 3 * c.vertices];
    let mut params = vec![Query::default(); c.vertices];
    let mut sizes = vec![0; c.polygons];
    let mut idx = vec![0; c.polygon_indices];
    let mut tris = vec![0; 3 * c.triangles];
    t.emit(Output {
        positions: &mut pos,
        normals: Some(&mut nrm),
        params: Some(&mut params),
        polygon_sizes: &mut sizes,
        polygon_indices: &mut idx,
        triangles: Some(&mut tris),
        cells: None,
    })
    .expect("exact buffers");
    assert!(idx.iter().chain(&tris).all(|&i| (i as usize) < c.vertices));
    assert_eq!(
        sizes.iter().map(|&s| s as usize).sum::<usize>(),
        c.polygon_indices
    );
    if x.tame() {
        assert_finite("positions", &pos);
    }
    if need >= 8 {
        let mut short = words(need - 8);
        match Tessellation::build(&topo, &ev, opts, &mut short) {
            Err(Error::BufferTooSmall { required }) => assert_eq!(required, need),
            other => panic!("short block: {:?}", other.map(|_| ())),
        }
    }
});
