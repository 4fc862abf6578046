//! `Topology::build` on fuzzed meshes (header: module docs of the lib):
//! no panic; the size query is exact (one word less is `BufferTooSmall`
//! with the same size); a built topology's counts match the input.
#![no_main]
use ccss_core::{Error, Topology};
use ccss_fuzz::{words, Input, CAPS};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let m = x.input();
    let nv = m.positions.len() / 3;
    let need = Topology::required_bytes(nv, m.face_sizes);
    let mut mem = words(need);
    let built = Topology::build(m, &mut mem).map(|t| (t.num_vertices(), t.num_faces()));
    if let Ok((v, f)) = built {
        assert_eq!((v, f), (nv, m.face_sizes.len()));
        if need >= 8 {
            let mut short = words(need - 8);
            match Topology::build(m, &mut short) {
                Err(Error::BufferTooSmall { required }) => assert_eq!(required, need),
                other => panic!("short block: {:?}", other.map(|_| ())),
            }
        }
    }
});
