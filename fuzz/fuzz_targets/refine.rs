//! Refinement: one uniform Catmull-Clark step (`mesh::refine`) with the
//! standard rule, and the unified scheme (`refine_unified`) with fuzzed
//! parameters (header bytes 2..6: `a, b, g` near the paper's values or
//! not finite, `d` 0..=4, `p` 0..=5, the triangle rule). The refined mesh
//! has the counts `refined_counts` / `unified_counts` promise, its indices
//! are in range, and a tame mesh gives finite points; the unified size
//! query is exact.
#![no_main]
use ccss_core::mesh::refine::{refine, refine_bytes, refined_counts};
use ccss_core::unified::{refine_unified, unified_bytes, unified_counts};
use ccss_core::{Error, TriangleRule, UnifiedParams, Weights};
use ccss_fuzz::{assert_finite, topology, words, Caps, Input};
use libfuzzer_sys::fuzz_target;

const CAPS: Caps = Caps {
    faces: 32,
    corners: 128,
};

fn coefficient(b: u8) -> f64 {
    match b >> 6 {
        0 => (b & 63) as f64 / 32.0 - 0.5,
        1 => [0.0, 0.5, 1.0, -1.0][(b & 3) as usize],
        2 => [f64::NAN, f64::INFINITY, 1e300, -1e300][(b & 3) as usize],
        _ => 0.5,
    }
}

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let h = x.header;
    let mut tmem = Vec::new();
    let Some(topo) = topology(x.input(), &mut tmem) else {
        return;
    };
    let mut mem = words(refine_bytes(&topo));
    let want = refined_counts(&topo);
    match refine(&topo, &Weights::STANDARD, &mut mem) {
        Ok(r) => {
            let m = r.mesh;
            assert_eq!(m.positions.len(), 3 * want.vertices);
            assert_eq!(m.face_sizes.len(), want.faces);
            assert!(m.indices.iter().all(|&i| (i as usize) < want.vertices));
            if x.tame() {
                assert_finite("refined", m.positions);
            }
        }
        Err(e) => panic!("refine: {e:?}"),
    }
    let params = UnifiedParams {
        a: coefficient(h[2]),
        b: coefficient(h[3]),
        g: coefficient(h[4]),
        d: (h[5] & 7) as u32 % 5,
        p: (h[5] >> 3) as u32 % 6,
        triangles: if h[5] & 0x80 != 0 {
            TriangleRule::Polygon
        } else {
            TriangleRule::Split
        },
    };
    let counts = match unified_counts(&topo, &params) {
        Ok(c) => c,
        Err(Error::InvalidArgument(_)) => return,
        Err(e) => panic!("unified counts: {e:?}"),
    };
    if counts.corners > 20_000 {
        return;
    }
    let need = unified_bytes(&topo, &params).expect("counts accepted it");
    let mut umem = words(need);
    let r = refine_unified(&topo, &params, &mut umem).expect("sized block");
    let m = r.mesh;
    assert_eq!(m.positions.len(), 3 * counts.vertices);
    assert_eq!(m.face_sizes.len(), counts.faces);
    assert_eq!(m.indices.len(), counts.corners);
    assert!(m.indices.iter().all(|&i| (i as usize) < counts.vertices));
    if x.tame() && params.a.abs() < 2.0 && params.b.abs() < 2.0 && params.g.abs() < 2.0 {
        assert_finite("unified", m.positions);
    }
    if need >= 8 {
        let mut short = words(need - 8);
        match refine_unified(&topo, &params, &mut short) {
            Err(Error::BufferTooSmall { required }) => assert_eq!(required, need),
            other => panic!("short block: {:?}", other.map(|_| ())),
        }
    }
});
