//! Exact volume, area and inertia (`mass_properties`) of the smooth
//! surface: no panic, no hang; a result is finite with finite, non-negative
//! error bounds, or a named refusal.
#![no_main]
use ccss_core::voxel::mass_properties;
use ccss_fuzz::{assert_finite, evaluator, topology, Caps, Input};
use libfuzzer_sys::fuzz_target;

const CAPS: Caps = Caps {
    faces: 8,
    corners: 32,
};

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
    if let Ok(m) = mass_properties(&ev) {
        assert_finite("volume, area", &[m.volume, m.area]);
        assert_finite("centroid", &m.centroid);
        assert_finite("inertia", &m.inertia);
        let b = [
            m.volume_error_bound,
            m.area_error_bound,
            m.centroid_error_bound,
        ];
        assert_finite("bounds", &b);
        assert!(b.iter().all(|&e| e >= 0.0), "{m:?}");
    }
});
