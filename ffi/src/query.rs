//! C ABI of the certified queries (ccss-core's `query` module): ray
//! intersection, inside/outside, closest points, planar slices.
//!
//! Every query on a `ccss_evaluator` has a twin `ccss_query_feature_<verb>`
//! on a `ccss_feature_evaluator` (creases, corners, boundaries, holes; rays
//! and closest points on open meshes too, inside/outside and slices only on
//! closed solids: NOT_CLOSED_SOLID); `ccss_query_slice_write` serves both.
//! Many layers of a plane family in one walk: `query_band.rs`.
//!
//! A `ccss_query` is the fixed work area of the queries (about 100 KiB) at
//! the start of a caller block of `ccss_query_required_bytes` bytes. It does
//! not refer to any evaluator between calls; one `ccss_query` serves any
//! number of calls, but not two threads at once (give each thread its own).
//!
//! Tolerances hold for the computed outputs, rounding included; a tolerance
//! below 4 times the rounding term of the coordinates (64 times for
//! inside/outside), or coordinates outside `2^-200..2^200`, is
//! `ERR_COORDINATE_RANGE`. Each query visits at most the core's default
//! budget of `2^22` cells (`MAX_CELLS`; `docs/WORST_CASE.md`), beyond which
//! it is `ERR_WORK_LIMIT_EXCEEDED` with the limit in `detail.value`.
//!
//! Typical use:
//!
//! ```c
//! size_t n; ccss_query_required_bytes(&n, &detail);
//! void *qm = malloc(n); ccss_query *q; ccss_query_build(qm, n, &q, &detail);
//! ccss_query_ray ray = {{0, 0, -5}, {0, 0, 1}};
//! ccss_query_hit hit; int found;
//! ccss_query_ray_first(ev, q, &ray, 1, 1e-9, &hit, &found, &detail);
//! ```

use crate::boundary::{
    check_len, check_ptr, guard, put, round8, try_block, try_handle, try_handle_mut, try_ref,
    try_slice,
};
use crate::evaluator::CcssEvaluator;
use crate::feature::CcssFeatureEvaluator;
use crate::query_index::on_surface;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::query::{
    self, Contour, Hit, HitKind, Plane, QuerySurface, QueryWork, Ray, RayOptions, SliceOptions,
    SliceSegment,
};
use ccss_core::DVec3;
use core::ffi::{c_int, c_void};
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// A ray `origin + t * dir` (`dir` finite and non-zero, need not be unit).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssQueryRay {
    /// Start point.
    pub origin: [f64; 3],
    /// Direction.
    pub dir: [f64; 3],
}

/// One hit of a ray with the limit surface: `point` is the exact limit
/// point at `(face, sub, u, v)`, within `tol` of the ray at parameter `t`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssQueryHit {
    /// Ray parameter.
    pub t: f64,
    /// Base face.
    pub face: u32,
    /// Sub-face.
    pub sub: u32,
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// Limit point.
    pub point: [f64; 3],
    /// Unit normal (zero where degenerate).
    pub normal: [f64; 3],
    /// 1: a transversal crossing (at most one in its cell, orientation
    /// fixed); 0: the surface comes within `tol` of the ray (tangent, or
    /// through an extraordinary vertex).
    pub transversal: c_int,
}

impl From<Hit> for CcssQueryHit {
    fn from(h: Hit) -> Self {
        CcssQueryHit {
            t: h.t,
            face: h.face,
            sub: h.sub,
            u: h.u,
            v: h.v,
            point: h.point.to_array(),
            normal: h.normal.to_array(),
            transversal: (h.kind == HitKind::Transversal) as c_int,
        }
    }
}

/// The closest limit point to a query point.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssQueryClosestInfo {
    /// Distance to `point` (at most the true minimum plus `gap`).
    pub dist: f64,
    /// Base face.
    pub face: u32,
    /// Sub-face.
    pub sub: u32,
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// The limit point.
    pub point: [f64; 3],
    /// Certified bound: `dist <= minimum + gap` (`gap <= tol`, except where
    /// a corner ball at the deepest level stayed wider).
    pub gap: f64,
}

/// One closed contour of a slice: points `start .. start + len` of the
/// points array (x, y pairs), the last joined to the first.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssQueryContour {
    /// First point.
    pub start: u32,
    /// Number of points.
    pub len: u32,
    /// 1: outer boundary (counter-clockwise seen from +normal); 0: hole
    /// (clockwise).
    pub outer: c_int,
}

/// What `ccss_query_slice_layer` wrote.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssQuerySliceLayerStats {
    /// Points written.
    pub points: u64,
    /// Contours written.
    pub contours: u64,
    /// Section segments found.
    pub segments: u64,
    /// Cells below eps where the plane is tangent to the surface (their
    /// section is left out).
    pub unresolved: u64,
}

/// The work area of the queries (opaque; lives at the start of its block).
pub struct CcssQuery {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// The slot index attached by `ccss_query_set_index` (NULL: none).
    pub(crate) index: *const crate::query_index::CcssQueryIndex,
    pub(crate) work: QueryWork,
}

impl crate::boundary::Handle for CcssQuery {
    const MAGIC: u64 = crate::boundary::magic(b"ccssQRY2");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssQuery, magic);
    const NAME: &'static str = "ccss_query";
}

const QUERY_HEAD: usize = round8(size_of::<CcssQuery>());

const _: () = {
    assert!(align_of::<CcssQuery>() <= 8);
    assert!(!needs_drop::<CcssQuery>());
    assert!(align_of::<SliceSegment>() <= 8);
};

static ZERO_WORK: QueryWork = QueryWork::ZERO;

/// Writes to `*out` the bytes `ccss_query_build` needs.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_required_bytes(
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", QUERY_HEAD) }
    })
}

/// Initialises the work area in `mem` (`mem_len` bytes, 8-byte aligned, at
/// least `ccss_query_required_bytes`) and writes the handle (which equals
/// `mem`) to `*out`. Nothing to destroy: free `mem` when done.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// bytes). On failure `*out` is not written.
///
/// # Safety
/// `mem` NULL or `mem_len` writable bytes not otherwise in use; `out`,
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_build(
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssQuery,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const *mut CcssQuery, "out")?;
        let base = try_block(mem, mem_len, QUERY_HEAD)?;
        // SAFETY: `base` is 8-aligned with at least QUERY_HEAD writable
        // bytes; the work area is copied from a static zero value.
        unsafe {
            let h = base as *mut CcssQuery;
            ptr::copy_nonoverlapping(&ZERO_WORK, ptr::addr_of_mut!((*h).work), 1);
            ptr::addr_of_mut!((*h).index).write(ptr::null());
            ptr::addr_of_mut!((*h).magic).write(<CcssQuery as crate::boundary::Handle>::MAGIC);
            *out = h;
        }
        Ok(())
    })
}

fn ray_of(r: &CcssQueryRay) -> Ray {
    Ray {
        origin: DVec3::from_array(r.origin),
        dir: DVec3::from_array(r.dir),
    }
}

/// Checks one ray (finite, non-zero direction).
fn check_ray(r: &CcssQueryRay) -> Result<(), ccss_core::Error> {
    let ray = ray_of(r);
    if !(ray.origin.is_finite() && ray.dir.is_finite()) {
        return Err(ccss_core::Error::InvalidArgument(
            "ray origin or direction not finite",
        ));
    }
    if ray.dir.length_squared() == 0.0 {
        return Err(ccss_core::Error::InvalidArgument("ray direction is zero"));
    }
    Ok(())
}

fn tol_ok(tol: f64) -> Result<(), Failure> {
    if tol > 0.0 && tol.is_finite() {
        Ok(())
    } else {
        Err(Failure::invalid("tol must be positive and finite"))
    }
}

/// `ccss_query_ray_first` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_ray_first`.
unsafe fn ray_first_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    rays: *const CcssQueryRay,
    n_rays: usize,
    tol: f64,
    out: *mut CcssQueryHit,
    out_found: *mut c_int,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let rs = unsafe { try_slice(rays, n_rays, "rays") }?;
    tol_ok(tol)?;
    if n_rays > 0 {
        check_ptr(out as *const CcssQueryHit, "out")?;
        check_ptr(out_found as *const c_int, "out_found")?;
        check_len::<CcssQueryHit>(n_rays, "n_rays too large")?;
    }
    for (i, r) in rs.iter().enumerate() {
        check_ray(r).map_err(|err| {
            let mut f = Failure::from(err);
            f.query_index = Some(i as u64);
            f
        })?;
    }
    let opts = RayOptions {
        tol,
        t_min: 0.0,
        ..Default::default()
    };
    for (i, r) in rs.iter().enumerate() {
        let h = query::ray_first(surf, &ray_of(r), &opts, &mut w.work).map_err(|err| {
            let mut f = Failure::from(err);
            f.query_index = Some(i as u64);
            f
        })?;
        // SAFETY: `out` and `out_found` hold n_rays entries (checked).
        unsafe {
            *out_found.add(i) = h.is_some() as c_int;
            if let Some(h) = h {
                *out.add(i) = h.into();
            }
        }
    }
    Ok(())
}

/// The first hit (smallest `t >= 0`) of each of `n_rays` rays with the limit
/// surface of `ev`, certified: no crossing missed, the hit within `tol`
/// (model units) of the exact crossing. `out[i]` is written and
/// `out_found[i]` set to 1 for a hit, `out_found[i] = 0` for a miss.
///
/// Every ray is checked before any is cast (a bad one: INVALID_ARGUMENT
/// with `detail.query_index`); a ray that fails while cast (it runs along
/// the surface) stops the batch with its index, the entries before it
/// written.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT.
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `rays` NULL (with `n_rays` 0) or `n_rays` readable rays; `out`
/// and `out_found` NULL (with `n_rays` 0) or `n_rays` writable entries;
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_ray_first(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    rays: *const CcssQueryRay,
    n_rays: usize,
    tol: f64,
    out: *mut CcssQueryHit,
    out_found: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            ray_first_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            rays,
            n_rays,
            tol,
            out,
            out_found
        )
    })
}

/// As `ccss_query_ray_first`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). Open meshes are fine.
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `rays` NULL (with `n_rays` 0) or `n_rays` readable rays; `out`
/// and `out_found` NULL (with `n_rays` 0) or `n_rays` writable entries;
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_ray_first(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    rays: *const CcssQueryRay,
    n_rays: usize,
    tol: f64,
    out: *mut CcssQueryHit,
    out_found: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            ray_first_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            rays,
            n_rays,
            tol,
            out,
            out_found
        )
    })
}

/// `ccss_query_ray_all` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_ray_all`.
unsafe fn ray_all_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    ray: *const CcssQueryRay,
    tol: f64,
    out: *mut CcssQueryHit,
    out_len: usize,
    out_count: *mut usize,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promises.
    let (w, r) = unsafe { (try_handle_mut(q, "q")?, try_ref(ray, "ray")?) };
    check_ptr(out_count as *const usize, "out_count")?;
    tol_ok(tol)?;
    check_ray(r)?;
    if out_len > 0 {
        check_ptr(out as *const CcssQueryHit, "out")?;
        check_len::<CcssQueryHit>(out_len, "out_len too large")?;
    }
    let opts = RayOptions {
        tol,
        t_min: 0.0,
        ..Default::default()
    };
    let n = match query::ray_all(surf, &ray_of(r), &opts, &mut w.work, &mut []) {
        Ok(n) => n,
        Err(ccss_core::Error::BufferTooSmall { required }) => required,
        Err(err) => return Err(err.into()),
    };
    if n > out_len {
        return Err(Failure::too_small(n));
    }
    for (i, h) in w.work.last_hits()[..n].iter().enumerate() {
        // SAFETY: `out` holds out_len >= n entries (checked).
        unsafe { *out.add(i) = (*h).into() };
    }
    // SAFETY: checked above.
    unsafe { put(out_count, "out_count", n) }
}

/// Every hit of one ray (`t >= 0`), sorted by `t`, into `out` (capacity
/// `out_len`); `*out_count` = their number. `out_len` smaller than that
/// (0 is the size query) is BUFFER_TOO_SMALL with the count in
/// `detail.required`, nothing written.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL, INVALID_ARGUMENT.
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `ray` readable; `out` NULL (with `out_len` 0) or `out_len`
/// writable hits; `out_count`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_ray_all(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    ray: *const CcssQueryRay,
    tol: f64,
    out: *mut CcssQueryHit,
    out_len: usize,
    out_count: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            ray_all_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            ray,
            tol,
            out,
            out_len,
            out_count
        )
    })
}

/// As `ccss_query_ray_all`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). Open meshes are fine.
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `ray` readable; `out` NULL (with `out_len` 0) or `out_len`
/// writable hits; `out_count`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_ray_all(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    ray: *const CcssQueryRay,
    tol: f64,
    out: *mut CcssQueryHit,
    out_len: usize,
    out_count: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            ray_all_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            ray,
            tol,
            out,
            out_len,
            out_count
        )
    })
}

/// `ccss_query_inside` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_inside`.
unsafe fn inside_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    p: *const f64,
    tol: f64,
    out: *mut c_int,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let pt = unsafe { try_slice(p, 3, "p") }?;
    check_ptr(out as *const c_int, "out")?;
    tol_ok(tol)?;
    let r = query::inside(surf, DVec3::new(pt[0], pt[1], pt[2]), tol, &mut w.work)?;
    // SAFETY: checked above.
    unsafe { put(out, "out", r as c_int) }
}

/// Whether the point `p` (three doubles) lies inside the closed solid
/// bounded by the limit surface of `ev`: `*out` = 1 inside, 0 outside. A
/// point within `tol` of the surface is INVALID_ARGUMENT.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT.
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `p` three readable doubles; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_inside(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    p: *const f64,
    tol: f64,
    out: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            inside_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            p,
            tol,
            out
        )
    })
}

/// As `ccss_query_inside`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). A surface that bounds
/// no solid is NOT_CLOSED_SOLID (the detail names the edge, face or vertex).
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `p` three readable doubles; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_inside(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    p: *const f64,
    tol: f64,
    out: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            inside_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            p,
            tol,
            out
        )
    })
}

/// `ccss_query_closest` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_closest`.
unsafe fn closest_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    points: *const f64,
    n_points: usize,
    tol: f64,
    out: *mut CcssQueryClosestInfo,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    let n3 = n_points
        .checked_mul(3)
        .ok_or(Failure::invalid("n_points too large"))?;
    // SAFETY: forwarded caller promise.
    let ps = unsafe { try_slice(points, n3, "points") }?;
    tol_ok(tol)?;
    if n_points > 0 {
        check_ptr(out as *const CcssQueryClosestInfo, "out")?;
        check_len::<CcssQueryClosestInfo>(n_points, "n_points too large")?;
    }
    for (i, c) in ps.chunks_exact(3).enumerate() {
        if !c.iter().all(|x| x.is_finite()) {
            let mut f = Failure::invalid("query point not finite");
            f.query_index = Some(i as u64);
            return Err(f);
        }
    }
    let opts = query::ClosestOptions {
        tol,
        ..Default::default()
    };
    for (i, c) in ps.chunks_exact(3).enumerate() {
        let r = query::closest(surf, DVec3::new(c[0], c[1], c[2]), &opts, &mut w.work).map_err(
            |err| {
                let mut f = Failure::from(err);
                f.query_index = Some(i as u64);
                f
            },
        )?;
        // SAFETY: `out` holds n_points entries (checked).
        unsafe {
            *out.add(i) = CcssQueryClosestInfo {
                dist: r.dist,
                face: r.face,
                sub: r.sub,
                u: r.u,
                v: r.v,
                point: r.point.to_array(),
                gap: r.gap,
            }
        };
    }
    Ok(())
}

/// The closest limit point of `ev` to each of `n_points` points (x, y, z
/// triples in `points`), certified to `tol` (model units): `out[i]`.
/// Every point is checked first (finite); the batch then runs in order.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (`detail.query_index`).
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `points` NULL (with `n_points` 0) or `3 n_points` readable
/// doubles; `out` NULL (with `n_points` 0) or `n_points` writable entries;
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_closest(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    points: *const f64,
    n_points: usize,
    tol: f64,
    out: *mut CcssQueryClosestInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            closest_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            points,
            n_points,
            tol,
            out
        )
    })
}

/// As `ccss_query_closest`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). Open meshes are fine.
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `points` NULL (with `n_points` 0) or `3 n_points` readable
/// doubles; `out` NULL (with `n_points` 0) or `n_points` writable entries;
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_closest(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    points: *const f64,
    n_points: usize,
    tol: f64,
    out: *mut CcssQueryClosestInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            closest_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            points,
            n_points,
            tol,
            out
        )
    })
}

/// Reads a plane (normal: three doubles) and the options.
///
/// # Safety
/// `normal` NULL or three readable doubles.
unsafe fn plane_of(
    normal: *const f64,
    offset: f64,
    eps: f64,
) -> Result<(Plane, SliceOptions), Failure> {
    // SAFETY: forwarded caller promise.
    let n = unsafe { try_slice(normal, 3, "normal") }?;
    let plane = Plane {
        normal: DVec3::new(n[0], n[1], n[2]),
        offset,
    };
    plane.frame()?;
    if !(eps > 0.0 && eps.is_finite()) {
        return Err(Failure::invalid("eps must be positive and finite"));
    }
    Ok((
        plane,
        SliceOptions {
            eps,
            ..Default::default()
        },
    ))
}

/// `ccss_query_slice_required_bytes` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_slice_required_bytes`.
unsafe fn slice_required_bytes_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    out: *mut usize,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let (plane, opts) = unsafe { plane_of(normal, offset, eps) }?;
    check_ptr(out as *const usize, "out")?;
    let n = query::slice_segment_count(surf, &plane, &opts, &mut w.work)?;
    let bytes = n
        .checked_mul(size_of::<SliceSegment>())
        .ok_or(Failure::invalid("slice too large"))?;
    // SAFETY: checked above.
    unsafe { put(out, "out", bytes) }
}

/// Writes to `*out` the scratch bytes `ccss_query_slice_layer` needs for
/// the section of `ev` by the plane `normal . p = offset` (the normal is
/// normalised; `offset` is the signed distance along it) at Hausdorff bound
/// `eps`. (It walks the cells once, as the slice does.)
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (zero normal, eps).
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `out`, `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_required_bytes(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            slice_required_bytes_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            normal,
            offset,
            eps,
            out
        )
    })
}

/// As `ccss_query_slice_required_bytes`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). A surface that bounds
/// no solid is NOT_CLOSED_SOLID (the detail names the edge, face or vertex).
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `out`, `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_slice_required_bytes(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            slice_required_bytes_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            normal,
            offset,
            eps,
            out
        )
    })
}

/// `ccss_query_slice_layer` on any surface the queries accept.
///
/// # Safety
/// As `ccss_query_slice_layer`.
#[allow(clippy::too_many_arguments)] // the export's parameters
unsafe fn slice_layer_on<S: QuerySurface + ?Sized>(
    surf: &S,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle_mut(q, "q")? };
    // SAFETY: forwarded caller promise.
    let (plane, opts) = unsafe { plane_of(normal, offset, eps) }?;
    check_ptr(out as *const CcssQuerySliceLayerStats, "out")?;
    // SAFETY: forwarded caller promise.
    let segs = unsafe { scratch_segments(scratch, scratch_len) }?;
    let st = match query::slice_layer(surf, &plane, &opts, &mut w.work, segs) {
        Ok(st) => st,
        Err(ccss_core::Error::BufferTooSmall { required }) => {
            return Err(Failure::too_small(required * size_of::<SliceSegment>()))
        }
        Err(err) => return Err(err.into()),
    };
    let stats = CcssQuerySliceLayerStats {
        points: st.points as u64,
        contours: st.contours as u64,
        segments: st.segments as u64,
        unresolved: st.unresolved as u64,
    };
    // SAFETY: checked above.
    unsafe { put(out, "out", stats) }
}

/// Slices the solid bounded by `ev` with the plane `normal . p = offset`
/// within Hausdorff distance `eps` of the exact section, chaining the
/// section into closed contours in `scratch` (`scratch_len` bytes, 8-byte
/// aligned, at least `ccss_query_slice_required_bytes`). `*out` receives
/// the exact numbers of points and contours `ccss_query_slice_write` will
/// write (and the scratch entries used).
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// scratch bytes), INVALID_ARGUMENT (zero normal, eps; a contour that does
/// not close: shift the plane).
///
/// # Safety
/// `ev` a live evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `scratch` NULL (with
/// `scratch_len` 0) or `scratch_len` writable bytes; `out`, `detail` NULL
/// or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_layer(
    ev: *const CcssEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            slice_layer_on,
            unsafe { &try_handle(ev, "ev")?.ev },
            ev,
            q,
            normal,
            offset,
            eps,
            scratch,
            scratch_len,
            out
        )
    })
}

/// As `ccss_query_slice_layer`, on the limit surface of a feature evaluator (creases,
/// corners, semi-sharp edges, boundaries, holes). A surface that bounds
/// no solid is NOT_CLOSED_SOLID (the detail names the edge, face or vertex).
///
/// # Safety
/// `ev` a live feature evaluator, `q` a live query area not used elsewhere during
/// the call; `normal` three readable doubles; `scratch` NULL (with
/// `scratch_len` 0) or `scratch_len` writable bytes; `out`, `detail` NULL
/// or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_slice_layer(
    ev: *const CcssFeatureEvaluator,
    q: *mut CcssQuery,
    normal: *const f64,
    offset: f64,
    eps: f64,
    scratch: *mut c_void,
    scratch_len: usize,
    out: *mut CcssQuerySliceLayerStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        on_surface!(
            slice_layer_on,
            unsafe { try_handle(ev, "ev")?.evaluator() },
            ev,
            q,
            normal,
            offset,
            eps,
            scratch,
            scratch_len,
            out
        )
    })
}

/// The scratch block as segments.
///
/// # Safety
/// `scratch` NULL (with `scratch_len` 0) or `scratch_len` writable bytes.
pub(crate) unsafe fn scratch_segments<'a>(
    scratch: *mut c_void,
    scratch_len: usize,
) -> Result<&'a mut [SliceSegment], Failure> {
    if scratch.is_null() {
        if scratch_len != 0 {
            return Err(Failure::null("scratch"));
        }
        return Ok(&mut []);
    }
    if (scratch as usize) % 8 != 0 {
        return Err(Failure::misaligned());
    }
    if scratch_len > isize::MAX as usize {
        return Err(Failure::invalid("scratch_len too large"));
    }
    let n = scratch_len / size_of::<SliceSegment>();
    // SAFETY: `scratch` holds scratch_len writable bytes, 8-aligned; any
    // bit pattern is a valid SliceSegment (plain f64 and u32 fields).
    Ok(unsafe { core::slice::from_raw_parts_mut(scratch.cast::<SliceSegment>(), n) })
}

/// Writes the contours `ccss_query_slice_layer` chained in `scratch`
/// (`stats` = what it returned): points as (x, y) pairs of the plane's
/// frame into `out_points` (capacity `out_points_len` points, i.e.
/// `2 out_points_len` doubles), contours into `out_contours` (capacity
/// `out_contours_len`). The frame: for the normal +z, x and y; else `e1` =
/// the normalised projection of +x (of +y when the normal is within 26
/// degrees of x) onto the plane, `e2 = n x e1`. Outer contours run
/// counter-clockwise seen from +normal, holes clockwise. A short array is
/// BUFFER_TOO_SMALL with the exact count (points first), nothing written.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL, INVALID_ARGUMENT
/// (scratch and stats do not match).
///
/// # Safety
/// `scratch` the block `ccss_query_slice_layer` filled (unmodified), with
/// `scratch_len` bytes; `stats` readable; `out_points` NULL (with 0) or
/// `2 out_points_len` writable doubles; `out_contours` NULL (with 0) or
/// `out_contours_len` writable contours, not overlapping the others;
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_slice_write(
    scratch: *mut c_void,
    scratch_len: usize,
    stats: *const CcssQuerySliceLayerStats,
    out_points: *mut f64,
    out_points_len: usize,
    out_contours: *mut CcssQueryContour,
    out_contours_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let st = unsafe { try_ref(stats, "stats") }?;
        // SAFETY: forwarded caller promise.
        let all = unsafe { scratch_segments(scratch, scratch_len) }?;
        let n = usize::try_from(st.segments).map_err(|_| Failure::invalid("stats"))?;
        if n > all.len() {
            return Err(Failure::invalid("stats do not match the scratch"));
        }
        // SAFETY: forwarded caller promises.
        unsafe {
            write_layer(
                &mut all[..n],
                out_points,
                out_points_len,
                out_contours,
                out_contours_len,
            )
        }
    })
}

/// Writes one layer's chained segments `segs` as points and contours (the
/// checks and the writing of `ccss_query_slice_write`).
///
/// # Safety
/// As the output arguments of `ccss_query_slice_write`.
pub(crate) unsafe fn write_layer(
    segs: &mut [SliceSegment],
    out_points: *mut f64,
    out_points_len: usize,
    out_contours: *mut CcssQueryContour,
    out_contours_len: usize,
) -> Result<(), Failure> {
    let np2 = out_points_len
        .checked_mul(2)
        .ok_or(Failure::invalid("out_points_len too large"))?;
    if out_points_len > 0 {
        check_ptr(out_points as *const f64, "out_points")?;
        check_len::<f64>(np2, "out_points_len too large")?;
    }
    if out_contours_len > 0 {
        check_ptr(out_contours as *const CcssQueryContour, "out_contours")?;
        check_len::<CcssQueryContour>(out_contours_len, "out_contours_len too large")?;
    }
    // SAFETY: `out_points` holds 2 out_points_len writable doubles
    // (checked); [f64; 2] has the alignment of f64.
    let pts: &mut [[f64; 2]] = if out_points_len == 0 {
        &mut []
    } else {
        unsafe { core::slice::from_raw_parts_mut(out_points.cast::<[f64; 2]>(), out_points_len) }
    };
    query::slice::write_contours(segs, pts, out_contours_len, |i, c: Contour| {
        // SAFETY: i < out_contours_len (write_contours checks the count
        // against it before writing).
        unsafe {
            *out_contours.add(i) = CcssQueryContour {
                start: c.start,
                len: c.len,
                outer: c.outer as c_int,
            }
        };
    })?;
    Ok(())
}
