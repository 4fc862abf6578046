//! Exact volume, area and inertia (`mass_properties_with`) of the smooth
//! surface: no panic, no hang; a result is finite with finite, non-negative
//! error bounds, or a named refusal. Header bytes 2..6 pick the options,
//! capped for speed (the defaults take 2^16 area cells and corner levels to
//! 1e-15, about 50 ms for the cube under ASan): area tolerance
//! `10^-(1..=8)`, corner tolerance `10^-(1..=6)`, at most 63 + 3 per piece
//! area cells; one input in 16 has a bad tolerance (NaN, 0, negative,
//! infinite), which must be refused.
#![no_main]
use ccss_core::voxel::{mass_properties_with, MeasureOptions};
use ccss_core::Error;
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
    let h = x.header;
    let mut opts = MeasureOptions {
        area_rel_tol: 10f64.powi(-1 - (h[2] % 8) as i32),
        corner_rel_tol: 10f64.powi(-1 - (h[3] % 6) as i32),
        area_cells_min: u64::from(h[4] % 64),
        area_cells_per_piece: u64::from(h[5] % 4),
    };
    let bad = h[4] & 0xc0 == 0xc0 && h[5] & 0x30 == 0x30;
    if bad {
        let v = [f64::NAN, 0.0, -1.0, f64::INFINITY][(h[5] >> 6) as usize];
        if h[4] & 0x20 == 0 {
            opts.area_rel_tol = v;
        } else {
            opts.corner_rel_tol = v;
        }
    }
    let mut tmem = Vec::new();
    let Some(topo) = topology(x.input(), &mut tmem) else {
        return;
    };
    let mut emem = Vec::new();
    let Some(ev) = evaluator(&topo, &mut emem) else {
        return;
    };
    let r = mass_properties_with(&ev, &opts);
    if bad {
        assert!(matches!(r, Err(Error::InvalidArgument(_))), "{r:?}");
        return;
    }
    if let Ok(m) = r {
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
