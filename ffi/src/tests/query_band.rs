//! The band slicer's C ABI: every layer of a band equals the per-layer
//! slice through the C ABI (statistics, points and contours bit for bit),
//! on the smooth and the feature evaluator; exact size errors with nothing
//! written; the checks of every argument.

use super::feature::{all_edges_sharp_cube, defaults, grid, make, Tags};
use super::*;
use core::ffi::c_void;

type BandBytes<E> = unsafe extern "C" fn(
    *const E,
    *mut CcssQuery,
    *const f64,
    f64,
    f64,
    usize,
    usize,
    f64,
    *mut usize,
    *mut CcssErrorDetail,
) -> CcssStatus;
type Band<E> = unsafe extern "C" fn(
    *const E,
    *mut CcssQuery,
    *const f64,
    f64,
    f64,
    usize,
    usize,
    f64,
    *mut c_void,
    usize,
    *mut CcssQuerySliceLayerStats,
    *mut CcssErrorDetail,
) -> CcssStatus;
type LayerBytes<E> = unsafe extern "C" fn(
    *const E,
    *mut CcssQuery,
    *const f64,
    f64,
    f64,
    *mut usize,
    *mut CcssErrorDetail,
) -> CcssStatus;
type Layer<E> = unsafe extern "C" fn(
    *const E,
    *mut CcssQuery,
    *const f64,
    f64,
    f64,
    *mut c_void,
    usize,
    *mut CcssQuerySliceLayerStats,
    *mut CcssErrorDetail,
) -> CcssStatus;

/// The four slice functions of one evaluator kind.
struct Fns<E> {
    band_bytes: BandBytes<E>,
    band: Band<E>,
    layer_bytes: LayerBytes<E>,
    layer: Layer<E>,
}

/// A query area in a test-owned block.
pub(super) fn query() -> (Vec<u64>, *mut CcssQuery) {
    let mut n = 0usize;
    let mut q = ptr::null_mut();
    unsafe {
        assert_eq!(
            ccss_query_required_bytes(&mut n, ptr::null_mut()),
            CcssStatus::OK
        );
        let mut mem = block(n);
        let st = ccss_query_build(mem.as_mut_ptr().cast(), n, &mut q, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        (mem, q)
    }
}

/// One layer written by `ccss_query_slice_write` or `_band_write`.
type Written = (Vec<f64>, Vec<CcssQueryContour>);

/// The band `first .. first + count` of `offset + k step` (normal `nrm`)
/// against `ccss_query_slice_layer` on each of its planes; returns the
/// band's statistics and the scratch (for the argument checks).
#[allow(clippy::too_many_arguments)]
unsafe fn band_equals_layers<E>(
    f: &Fns<E>,
    ev: *const E,
    q: *mut CcssQuery,
    nrm: [f64; 3],
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
) -> (Vec<CcssQuerySliceLayerStats>, Vec<u64>, usize) {
    let mut d = Failure::invalid("x").to_detail();
    let mut bytes = 0usize;
    let st = unsafe {
        (f.band_bytes)(
            ev,
            q,
            nrm.as_ptr(),
            offset,
            step,
            first,
            count,
            eps,
            &mut bytes,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
    assert!(bytes > 0);
    let mut scratch = block(bytes);
    let sentinel = CcssQuerySliceLayerStats {
        points: 77,
        ..Default::default()
    };
    let mut stats = vec![sentinel; count];
    // One byte short: the exact size, nothing written.
    let st = unsafe {
        (f.band)(
            ev,
            q,
            nrm.as_ptr(),
            offset,
            step,
            first,
            count,
            eps,
            scratch.as_mut_ptr().cast(),
            bytes - 1,
            stats.as_mut_ptr(),
            &mut d,
        )
    };
    assert_eq!(
        (st, d.required as usize),
        (CcssStatus::ERR_BUFFER_TOO_SMALL, bytes)
    );
    assert!(stats.iter().all(|s| *s == sentinel), "nothing written");
    let st = unsafe {
        (f.band)(
            ev,
            q,
            nrm.as_ptr(),
            offset,
            step,
            first,
            count,
            eps,
            scratch.as_mut_ptr().cast(),
            bytes,
            stats.as_mut_ptr(),
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
    let total: u64 = stats.iter().map(|s| s.segments).sum();
    assert_eq!(total as usize * size_of_segment(), bytes);
    for (i, bs) in stats.iter().enumerate() {
        // The same layer alone.
        let h = offset + (first + i) as f64 * step;
        let mut lb = 0usize;
        let st = unsafe { (f.layer_bytes)(ev, q, nrm.as_ptr(), h, eps, &mut lb, &mut d) };
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        let mut ls_scratch = block(lb.max(8));
        let mut ls = CcssQuerySliceLayerStats::default();
        let st = unsafe {
            (f.layer)(
                ev,
                q,
                nrm.as_ptr(),
                h,
                eps,
                ls_scratch.as_mut_ptr().cast(),
                lb,
                &mut ls,
                &mut d,
            )
        };
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        assert_eq!(*bs, ls, "layer {i} (h = {h})");
        let alone = unsafe { write_alone(&mut ls_scratch, lb, &ls) };
        let banded = unsafe { write_banded(&mut scratch, bytes, &stats, i) };
        assert_eq!(alone.1, banded.1, "contours of layer {i}");
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&alone.0), bits(&banded.0), "points of layer {i}");
    }
    (stats, scratch, bytes)
}

fn size_of_segment() -> usize {
    core::mem::size_of::<ccss_core::query::SliceSegment>()
}

unsafe fn write_alone(scratch: &mut [u64], bytes: usize, ls: &CcssQuerySliceLayerStats) -> Written {
    let mut d = Failure::invalid("x").to_detail();
    let (np, nc) = (ls.points as usize, ls.contours as usize);
    let mut pts = vec![0.0; 2 * np];
    let mut cs = vec![CcssQueryContour::default(); nc];
    let st = unsafe {
        ccss_query_slice_write(
            scratch.as_mut_ptr().cast(),
            bytes,
            ls,
            pts.as_mut_ptr(),
            np,
            cs.as_mut_ptr(),
            nc,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
    (pts, cs)
}

/// Layer `i` of the band; a short points array first (the exact count,
/// nothing written).
unsafe fn write_banded(
    scratch: &mut [u64],
    bytes: usize,
    stats: &[CcssQuerySliceLayerStats],
    i: usize,
) -> Written {
    let mut d = Failure::invalid("x").to_detail();
    let (np, nc) = (stats[i].points as usize, stats[i].contours as usize);
    let mut pts = vec![9.0; 2 * np];
    let mut cs = vec![CcssQueryContour::default(); nc];
    let sp: *mut c_void = scratch.as_mut_ptr().cast();
    let write = |pts: &mut Vec<f64>, np_cap: usize, cs: &mut Vec<CcssQueryContour>, d| unsafe {
        ccss_query_slice_band_write(
            sp,
            bytes,
            stats.as_ptr(),
            stats.len(),
            i,
            pts.as_mut_ptr(),
            np_cap,
            cs.as_mut_ptr(),
            nc,
            d,
        )
    };
    if np > 0 {
        let st = write(&mut pts, np - 1, &mut cs, &mut d);
        assert_eq!(
            (st, d.required as usize),
            (CcssStatus::ERR_BUFFER_TOO_SMALL, np)
        );
        assert!(pts.iter().all(|&x| x == 9.0), "nothing written");
    }
    let st = write(&mut pts, np, &mut cs, &mut d);
    assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
    (pts, cs)
}

const SMOOTH: Fns<CcssEvaluator> = Fns {
    band_bytes: ccss_query_slice_band_required_bytes,
    band: ccss_query_slice_band,
    layer_bytes: ccss_query_slice_required_bytes,
    layer: ccss_query_slice_layer,
};

const FEATURE: Fns<CcssFeatureEvaluator> = Fns {
    band_bytes: ccss_query_feature_slice_band_required_bytes,
    band: ccss_query_feature_slice_band,
    layer_bytes: ccss_query_feature_slice_required_bytes,
    layer: ccss_query_feature_slice_layer,
};

#[test]
fn bands_equal_layers_through_the_c_abi() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let (_qm, q) = query();
    unsafe {
        // The smooth cube (limit surface within |z| < 0.84): layers
        // z = -0.9 .. 0.9, the outer two empty; a tilted family from
        // layer 3 on.
        let (st, ..) = band_equals_layers(&SMOOTH, b.ev, q, [0., 0., 1.], -0.9, 0.2, 0, 10, 1e-3);
        assert_eq!((st[0].segments, st[9].segments), (0, 0));
        assert!(st[1..9].iter().all(|s| s.contours == 1), "{st:?}");
        let (st, ..) = band_equals_layers(&SMOOTH, b.ev, q, [1., 2., 3.], -0.7, 0.1, 3, 7, 1e-4);
        assert!(st.iter().all(|s| s.contours == 1), "{st:?}");
        // The fully creased cube [-1, 1]^3 (feature evaluator).
        let (fp, fs, fi, ft) = all_edges_sharp_cube();
        let Ok((fe, _fm)) = make(&fp, &fs, &fi, &ft, &defaults()) else {
            panic!("build failed")
        };
        let (st, ..) = band_equals_layers(&FEATURE, fe, q, [0., 0., 1.], -0.75, 0.25, 0, 7, 1e-6);
        assert!(st.iter().all(|s| s.contours == 1), "{st:?}");
        // A band of the full width.
        let (st, ..) = band_equals_layers(
            &FEATURE,
            fe,
            q,
            [0., 1., 0.],
            -0.99,
            0.03,
            0,
            CCSS_QUERY_MAX_BAND,
            1e-6,
        );
        assert!(st.iter().all(|s| s.contours == 1), "{st:?}");
    }
}

#[test]
fn band_arguments_are_checked() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let (_qm, q) = query();
    let mut d = Failure::invalid("x").to_detail();
    let nz = [0.0, 0.0, 1.0];
    unsafe {
        let (stats, mut scratch, bytes) =
            band_equals_layers(&SMOOTH, b.ev, q, nz, -0.5, 0.25, 0, 5, 1e-3);
        let sp: *mut c_void = scratch.as_mut_ptr().cast();
        let mut out = [CcssQuerySliceLayerStats::default(); 6];
        let mut n = 0usize;
        let band = |ev, q, nrm: &[f64; 3], step, count, eps, sc, sl, out, d| {
            ccss_query_slice_band(
                ev,
                q,
                nrm.as_ptr(),
                -0.5,
                step,
                0,
                count,
                eps,
                sc,
                sl,
                out,
                d,
            )
        };
        let bytes_of = |nrm: &[f64; 3], step, count, eps, out, d| {
            ccss_query_slice_band_required_bytes(
                b.ev,
                q,
                nrm.as_ptr(),
                -0.5,
                step,
                0,
                count,
                eps,
                out,
                d,
            )
        };
        let o = out.as_mut_ptr();
        let inv = CcssStatus::ERR_INVALID_ARGUMENT;
        // Band size: 0 and 65 layers, eps, normal, step.
        for (nrm, step, count, eps) in [
            (nz, 0.25, 0, 1e-3),
            (nz, 0.25, CCSS_QUERY_MAX_BAND + 1, 1e-3),
            (nz, 0.25, 5, 0.0),
            (nz, 0.25, 5, f64::NAN),
            ([0.0; 3], 0.25, 5, 1e-3),
            (nz, f64::INFINITY, 5, 1e-3),
        ] {
            let st = bytes_of(&nrm, step, count, eps, &mut n, &mut d);
            assert_eq!(st, inv, "{nrm:?} {step} {count} {eps}");
            let st = band(b.ev, q, &nrm, step, count, eps, sp, bytes, o, &mut d);
            assert_eq!(st, inv, "{nrm:?} {step} {count} {eps}: {}", msg(&d));
        }
        assert!(out
            .iter()
            .all(|s| *s == CcssQuerySliceLayerStats::default()));
        // NULL handles, NULL and misaligned outputs and scratch.
        let null = CcssStatus::ERR_NULL_POINTER;
        let st = band(ptr::null(), q, &nz, 0.25, 5, 1e-3, sp, bytes, o, &mut d);
        assert_eq!(st, null);
        let st = band(
            b.ev,
            ptr::null_mut(),
            &nz,
            0.25,
            5,
            1e-3,
            sp,
            bytes,
            o,
            &mut d,
        );
        assert_eq!(st, null);
        let st = band(
            b.ev,
            q,
            &nz,
            0.25,
            5,
            1e-3,
            sp,
            bytes,
            ptr::null_mut(),
            &mut d,
        );
        assert_eq!(st, null);
        let st = band(
            b.ev,
            q,
            &nz,
            0.25,
            5,
            1e-3,
            ptr::null_mut(),
            bytes,
            o,
            &mut d,
        );
        assert_eq!(st, null);
        let st = bytes_of(&nz, 0.25, 5, 1e-3, ptr::null_mut(), &mut d);
        assert_eq!(st, null);
        let st = ccss_query_slice_band_required_bytes(
            b.ev,
            q,
            ptr::null(),
            -0.5,
            0.25,
            0,
            5,
            1e-3,
            &mut n,
            &mut d,
        );
        assert_eq!(st, null);
        let mis = CcssStatus::ERR_MISALIGNED;
        let sp4 = sp.cast::<u8>().add(4).cast();
        let st = band(b.ev, q, &nz, 0.25, 5, 1e-3, sp4, bytes - 8, o, &mut d);
        assert_eq!(st, mis);
        let o4 = o.cast::<u8>().add(4).cast();
        let st = band(b.ev, q, &nz, 0.25, 5, 1e-3, sp, bytes, o4, &mut d);
        assert_eq!(st, mis);
        assert!(out
            .iter()
            .all(|s| *s == CcssQuerySliceLayerStats::default()));
        // The size query with a NULL scratch: BUFFER_TOO_SMALL, exact.
        let st = band(b.ev, q, &nz, 0.25, 5, 1e-3, ptr::null_mut(), 0, o, &mut d);
        assert_eq!(
            (st, d.required as usize),
            (CcssStatus::ERR_BUFFER_TOO_SMALL, bytes)
        );
        // The writer: layer out of range, stats that do not match.
        let mut xy = [0.0; 2];
        let mut cs = [CcssQueryContour::default(); 1];
        let mut write = |stats: *const CcssQuerySliceLayerStats, count, layer, d| {
            ccss_query_slice_band_write(
                sp,
                bytes,
                stats,
                count,
                layer,
                xy.as_mut_ptr(),
                0,
                cs.as_mut_ptr(),
                0,
                d,
            )
        };
        assert_eq!(write(stats.as_ptr(), 5, 5, &mut d), inv);
        assert_eq!(write(stats.as_ptr(), 0, 0, &mut d), inv);
        assert_eq!(write(ptr::null(), 5, 0, &mut d), null);
        let mut more = stats.clone();
        more[4].segments += 1;
        assert_eq!(write(more.as_ptr(), 5, 4, &mut d), inv);
        assert!(msg(&d).contains("do not match"), "{}", msg(&d));
        more[4].segments = u64::MAX;
        more[3].segments = u64::MAX;
        assert_eq!(write(more.as_ptr(), 5, 4, &mut d), inv);
        assert_eq!(
            write(stats.as_ptr(), 5, 2, &mut d),
            CcssStatus::ERR_BUFFER_TOO_SMALL
        );
        assert_eq!(d.required, stats[2].points);
        // An open feature mesh bounds no solid.
        let (gp, gs, gi) = grid(true);
        let Ok((open, _om)) = make(&gp, &gs, &gi, &Tags::default(), &defaults()) else {
            panic!("build failed")
        };
        let st = ccss_query_feature_slice_band_required_bytes(
            open,
            q,
            nz.as_ptr(),
            0.1,
            0.1,
            0,
            4,
            1e-3,
            &mut n,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NOT_CLOSED_SOLID);
        let st = ccss_query_feature_slice_band(
            open,
            q,
            nz.as_ptr(),
            0.1,
            0.1,
            0,
            4,
            1e-3,
            sp,
            bytes,
            o,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NOT_CLOSED_SOLID);
    }
}
