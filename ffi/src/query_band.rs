//! C ABI of the band slicer (ccss-core's `query::slice_band`): up to
//! `CCSS_QUERY_MAX_BAND` layers of a family of parallel planes in one walk
//! of the cells, each layer's contours exactly those of
//! `ccss_query_slice_layer` on that layer's plane.
//!
//! Layer `k` of a family is the plane `normal . p = offset + k * step`;
//! a band is the layers `first .. first + count`. Per band: the scratch
//! size (`ccss_query_slice_band_required_bytes`), the walk
//! (`ccss_query_slice_band`, one `ccss_query_slice_layer_stats` per
//! layer), then each layer's contours (`ccss_query_slice_band_write`).
//! Every function on a `ccss_evaluator` has a twin
//! `ccss_query_feature_<verb>` on a `ccss_feature_evaluator` (closed solids
//! only: NOT_CLOSED_SOLID); `ccss_query_slice_band_write` serves both.
//! Rounding, coordinate range and work budget as in `query.rs`: one band
//! is one walk, with the cell budget of one layer's walk
//! (`ERR_WORK_LIMIT_EXCEEDED` past it: use a smaller band).

use crate::boundary::{check_len, check_ptr, guard, put, try_handle, try_handle_mut, try_slice};
use crate::evaluator::CcssEvaluator;
use crate::feature::CcssFeatureEvaluator;
use crate::query::{
    scratch_segments, write_layer, CcssQuery, CcssQueryContour, CcssQuerySliceLayerStats,
};
use crate::query_index::on_surface;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::query::{self, PlaneStack, QuerySurface, SliceOptions, SliceSegment, SliceStats};
use ccss_core::DVec3;
use core::ffi::c_void;
use core::mem::size_of;

/// Most layers of one band (`ccss_query_slice_band`'s `count`).
pub const CCSS_QUERY_MAX_BAND: usize = 64;

const _: () = assert!(CCSS_QUERY_MAX_BAND == query::MAX_BAND);

/// Reads the plane family (normal: three doubles), checks the band and eps.
///
/// # Safety
/// `normal` NULL or three readable doubles.
unsafe fn stack_of(
    normal: *const f64,
    offset: f64,
    step: f64,
    count: usize,
    eps: f64,
) -> Result<(PlaneStack, SliceOptions), Failure> {
    // SAFETY: forwarded caller promise.
    let n = unsafe { try_slice(normal, 3, "normal") }?;
    let stack = PlaneStack {
        normal: DVec3::new(n[0], n[1], n[2]),
        offset,
        step,
    };
    stack.layer(0).frame()?;
    if count == 0 || count > CCSS_QUERY_MAX_BAND {
        return Err(Failure::invalid(
            "count must be 1 to 64 (CCSS_QUERY_MAX_BAND)",
        ));
    }
    if !(eps > 0.0 && eps.is_finite()) {
        return Err(Failure::invalid("eps must be positive and finite"));
    }
    Ok((
        stack,
        SliceOptions {
            eps,
            ..Default::default()
        },
    ))
}

/// `ccss_query_slice_band_required_bytes` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_slice_band_required_bytes`.
#[allow(clippy::too_many_arguments)] // the export's parameters
unsafe fn band_required_bytes_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    out: *mut usize,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let (stack, opts) = unsafe { stack_of(normal, offset, step, count, eps) }?;
    check_ptr(out as *const usize, "out")?;
    let mut stats = [SliceStats::default(); CCSS_QUERY_MAX_BAND];
    let n = match query::slice_band(
        surf,
        &stack,
        first,
        &opts,
        &mut w.work,
        &mut [],
        &mut stats[..count],
    ) {
        Ok(n) => n,
        Err(ccss_core::Error::BufferTooSmall { required }) => required,
        Err(err) => return Err(err.into()),
    };
    let bytes = n
        .checked_mul(size_of::<SliceSegment>())
        .ok_or(Failure::invalid("slice too large"))?;
    // SAFETY: checked above.
    unsafe { put(out, "out", bytes) }
}

/// Writes to `*out` the scratch bytes `ccss_query_slice_band` needs for
/// the layers `first .. first + count` (1 to `CCSS_QUERY_MAX_BAND`) of the
/// planes `normal . p = offset + k * step` (the normal is normalised;
/// offsets are signed distances along it) at Hausdorff bound `eps`. (It
/// walks the cells once, as the band does.)
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (zero normal, count,
/// step or offsets not finite, eps).
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `out`, `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_band_required_bytes(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            band_required_bytes_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            normal,
            offset,
            step,
            first,
            count,
            eps,
            out
        )
    })
}

/// As `ccss_query_slice_band_required_bytes`, on the limit surface of a
/// feature evaluator (creases, corners, semi-sharp edges, boundaries,
/// holes). A surface that bounds no solid is NOT_CLOSED_SOLID (the detail
/// names the edge, face or vertex).
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere
/// during the call; `normal` three readable doubles; `out`, `detail` NULL
/// or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_slice_band_required_bytes(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            band_required_bytes_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            normal,
            offset,
            step,
            first,
            count,
            eps,
            out
        )
    })
}

/// `ccss_query_slice_band` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_slice_band`.
#[allow(clippy::too_many_arguments)] // the export's parameters
unsafe fn band_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let (stack, opts) = unsafe { stack_of(normal, offset, step, count, eps) }?;
    check_ptr(out as *const CcssQuerySliceLayerStats, "out")?;
    check_len::<CcssQuerySliceLayerStats>(count, "count too large")?;
    // SAFETY: forwarded caller promise.
    let segs = unsafe { scratch_segments(scratch, scratch_len) }?;
    // The statistics go to `out` only once every layer is chained.
    let mut stats = [SliceStats::default(); CCSS_QUERY_MAX_BAND];
    match query::slice_band(
        surf,
        &stack,
        first,
        &opts,
        &mut w.work,
        segs,
        &mut stats[..count],
    ) {
        Ok(_) => {}
        Err(ccss_core::Error::BufferTooSmall { required }) => {
            return Err(Failure::too_small(required * size_of::<SliceSegment>()))
        }
        Err(err) => return Err(err.into()),
    }
    for (i, st) in stats[..count].iter().enumerate() {
        // SAFETY: `out` holds `count` writable entries (caller promise;
        // pointer and length checked).
        unsafe {
            *out.add(i) = CcssQuerySliceLayerStats {
                points: st.points as u64,
                contours: st.contours as u64,
                segments: st.segments as u64,
                unresolved: st.unresolved as u64,
            }
        };
    }
    Ok(())
}

/// Slices the solid bounded by `ev` with the layers `first .. first +
/// count` (1 to `CCSS_QUERY_MAX_BAND`) of the planes
/// `normal . p = offset + k * step` in one walk of the cells, within
/// Hausdorff distance `eps`, chaining every layer's section into closed
/// contours in `scratch` (`scratch_len` bytes, 8-byte aligned, at least
/// `ccss_query_slice_band_required_bytes`). `out[i]` receives layer
/// `first + i`'s numbers: exactly those `ccss_query_slice_layer` gives for
/// the plane offset `offset + (first + i) * step` (the same contours);
/// `ccss_query_slice_band_write` writes them.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// scratch bytes), INVALID_ARGUMENT (zero normal, count, step or offsets
/// not finite, eps; a contour that does not close: shift the planes).
/// On failure `out` is not written (the scratch is).
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `scratch` NULL (with
/// `scratch_len` 0) or `scratch_len` writable bytes; `out` NULL or `count`
/// writable entries; `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_band(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            band_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            normal,
            offset,
            step,
            first,
            count,
            eps,
            scratch,
            scratch_len,
            out
        )
    })
}

/// As `ccss_query_slice_band`, on the limit surface of a feature evaluator
/// (creases, corners, semi-sharp edges, boundaries, holes). A surface that
/// bounds no solid is NOT_CLOSED_SOLID (the detail names the edge, face or
/// vertex).
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere
/// during the call; `normal` three readable doubles; `scratch` NULL (with
/// `scratch_len` 0) or `scratch_len` writable bytes; `out` NULL or `count`
/// writable entries; `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_slice_band(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    step: f64,
    first: usize,
    count: usize,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            band_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            normal,
            offset,
            step,
            first,
            count,
            eps,
            scratch,
            scratch_len,
            out
        )
    })
}

/// Writes the contours of layer `first + layer` of a band
/// (`ccss_query_slice_band` filled `scratch`, `stats` = its `count`
/// entries; `layer < count`) as `ccss_query_slice_write` writes a layer:
/// points as (x, y) pairs of the plane's frame into `out_points` (capacity
/// `out_points_len` points), contours into `out_contours` (capacity
/// `out_contours_len`). A short array is BUFFER_TOO_SMALL with the exact
/// count (points first), nothing written.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL, INVALID_ARGUMENT
/// (`layer` not below `count`; scratch and stats do not match).
///
/// # Safety
/// `scratch` the block `ccss_query_slice_band` filled (unmodified, except
/// by this function), with `scratch_len` bytes; `stats` `count` readable
/// entries; `out_points` NULL (with 0) or `2 out_points_len` writable
/// doubles; `out_contours` NULL (with 0) or `out_contours_len` writable
/// contours, not overlapping the others; `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_band_write(
    scratch: *mut c_void,
    scratch_len: usize,
    stats: *const CcssQuerySliceLayerStats,
    count: usize,
    layer: usize,
    out_points: *mut f64,
    out_points_len: usize,
    out_contours: *mut CcssQueryContour,
    out_contours_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let st = unsafe { try_slice(stats, count, "stats") }?;
        if layer >= count {
            return Err(Failure::invalid("layer must be below count"));
        }
        // SAFETY: forwarded caller promise.
        let all = unsafe { scratch_segments(scratch, scratch_len) }?;
        let mismatch = || Failure::invalid("stats do not match the scratch");
        let start = st[..layer]
            .iter()
            .try_fold(0u64, |a, s| a.checked_add(s.segments))
            .ok_or_else(mismatch)?;
        let end = start.checked_add(st[layer].segments).ok_or_else(mismatch)?;
        if end > all.len() as u64 {
            return Err(mismatch());
        }
        // SAFETY: forwarded caller promises.
        unsafe {
            write_layer(
                &mut all[start as usize..end as usize],
                out_points,
                out_points_len,
                out_contours,
                out_contours_len,
            )
        }
    })
}
