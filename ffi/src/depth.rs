//! Subdivision depth for a tolerance (Cheng & Lai report, ch. 3):
//! `ccss_depth_compute` per (face, sub-face) slot of an evaluator, and the
//! constants of one valence (`ccss_depth_rates`).

use crate::boundary::try_handle;
use crate::boundary::{check_len, check_ptr, guard, put};
use crate::evaluator::CcssEvaluator;
use crate::feature::CcssFeatureEvaluator;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use crate::tables::CcssTables;
use ccss_core::bounds::depth::{Method, Rates};
use ccss_core::Error;

/// Which bound `ccss_depth_compute` uses for extraordinary patches (Cheng & Lai
/// report, ch. 3). Regular patches always use Lemma 1
/// (`depth = ceil(log4(M / (3 eps)))`). The numeric values are stable ABI.
///
/// Functions take the method as a `uint32_t` (any value is safe to pass;
/// values that are not a `ccss_depth_method` fail with
/// `CCSS_ERR_INVALID_ARGUMENT`).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssDepthMethod {
    /// Theorem 6 (Lemmas 2-5: rate `r_old`, constant `c_old`). Standard
    /// Catmull-Clark weights only: with tables of a general rule that changes
    /// a valence of the mesh, `ccss_depth_compute` fails with INVALID_ARGUMENT.
    DEPTH_OLD = 0,
    /// Theorem 11 (the matrix technique: rates `r1`, `r2`, constant `c_new`).
    DEPTH_NEW = 1,
    /// The smallest valid depth of all methods (OLD where it applies, NEW and
    /// TIGHT).
    DEPTH_BEST = 2,
    /// Theorem 11's constant with the measured second-order norms of the
    /// exactly subdivided control points at each level instead of the
    /// estimate `M_i <= r_i M_0`; never larger than NEW.
    DEPTH_TIGHT = 3,
}

impl CcssDepthMethod {
    /// The method of a C value (`None` if it is not one).
    pub(crate) fn from_raw(v: u32) -> Option<CcssDepthMethod> {
        match v {
            0 => Some(CcssDepthMethod::DEPTH_OLD),
            1 => Some(CcssDepthMethod::DEPTH_NEW),
            2 => Some(CcssDepthMethod::DEPTH_BEST),
            3 => Some(CcssDepthMethod::DEPTH_TIGHT),
            _ => None,
        }
    }

    pub(crate) fn core(self) -> Method {
        match self {
            CcssDepthMethod::DEPTH_OLD => Method::Old,
            CcssDepthMethod::DEPTH_NEW => Method::New,
            CcssDepthMethod::DEPTH_BEST => Method::Best,
            CcssDepthMethod::DEPTH_TIGHT => Method::Tight,
        }
    }
}

/// Subdivision depth for tolerance `eps` (Cheng & Lai report, ch. 3): writes
/// to `out[s]`, for every slot `s` (see `ccss_evaluator_slot_count`,
/// `ccss_evaluator_slot_start`), the number of uniform Catmull-Clark steps of
/// the base mesh after which every control face of that (sub-)face lies
/// within `eps` of the limit surface (the bilinear control faces against the
/// limit patch). `method` is a `ccss_depth_method`. A slot for which the
/// method gives no bound (e.g. NEW where a general rule has `r2 >= 1`) gets
/// `UINT32_MAX`.
///
/// Checks, in this order: NULL_POINTER / MISALIGNED (`ev`),
/// INVALID_ARGUMENT (`method` not a `ccss_depth_method`; `eps` not positive
/// and finite), NULL_POINTER (`out` with `out_len > 0`), BUFFER_TOO_SMALL
/// (`out_len` below the slot count; `detail.required` = the slot count),
/// MISALIGNED (`out`), then INVALID_ARGUMENT (CCSS_DEPTH_OLD with tables whose
/// rule is not standard at a valence of the mesh) and MISSING_TABLE. `out` is
/// written only on success. No allocation.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or points to `out_len`
/// writable `uint32_t`; `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_depth_compute(
    ev: *const CcssEvaluator,
    eps: f64,
    method: u32,
    out: *mut u32,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        let method = CcssDepthMethod::from_raw(method).ok_or(Failure::invalid(
            "method is not a ccss_depth_method (0..=3)",
        ))?;
        if !(eps.is_finite() && eps > 0.0) {
            return Err(Failure::invalid("eps must be positive and finite"));
        }
        if out.is_null() && out_len != 0 {
            return Err(Failure::null("out"));
        }
        let ns = e.ev.num_slots();
        if out_len < ns {
            return Err(Failure::too_small(ns));
        }
        if ns == 0 {
            // Not produced by core (meshes have faces); nothing to write.
            return Ok(());
        }
        check_ptr(out as *const u32, "out")?;
        check_len::<u32>(ns, "array length too large")?;
        // SAFETY: non-NULL, aligned, and the caller promises `out_len >= ns`
        // writable elements; only the first `ns` are viewed. Core validates
        // everything before it writes (nothing written on failure).
        let dst = unsafe { core::slice::from_raw_parts_mut(out, ns) };
        ccss_core::bounds::depth::depths(&e.ev, eps, method.core(), dst)?;
        Ok(())
    })
}

/// The subdivision-depth constants of one valence `n`, filled by
/// `ccss_depth_rates` (Cheng & Lai report, ch. 3; the type cannot share the
/// function's name in C). `A` is the group-I second-order-difference
/// matrix of the 1-ring (2n x (2n+1)) and `Lambda` the 1-ring subdivision
/// matrix of the table's vertex rule.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssDepthRatesInfo {
    /// The valence `n`.
    pub valence: u32,
    /// `r1 = ||A Lambda A^+||_inf` (report Table 2).
    pub r1: f64,
    /// `r2 = ||A Lambda^2 A^+||_inf` (report Table 2).
    pub r2: f64,
    /// Theorem 11's constant: the supremum over m of the bound (3.17) per
    /// unit second-order norm (0 when `r2 >= 1`: no bound).
    pub c_new: f64,
    /// The report's Lemma 10 constant `(1 + r1) / (min(n,8) (1 - r2))`, the
    /// m -> infinity limit of `c_new` (smaller than `c_new` for n = 8; 0 when
    /// `r2 >= 1`).
    pub c_lemma10: f64,
    /// Lemma 2's rate of the old technique (Theorem 6); 0 when the table's
    /// rule is not standard at this valence (the old technique does not
    /// apply).
    pub r_old: f64,
    /// Lemma 5's constant of the old technique; 0 when it does not apply.
    pub c_old: f64,
}

impl From<&Rates> for CcssDepthRatesInfo {
    fn from(r: &Rates) -> Self {
        CcssDepthRatesInfo {
            valence: r.n as u32,
            r1: r.r1,
            r2: r.r2,
            c_new: r.c_new,
            c_lemma10: r.c_lemma10,
            r_old: r.r_old,
            c_old: r.c_old,
        }
    }
}

/// Writes to `*out` the subdivision-depth constants of valence `valence` for
/// the vertex rule of `tables` (computed when the tables were built).
///
/// Errors: NULL_POINTER, MISALIGNED, UNSUPPORTED_VALENCE (`valence` outside
/// `3..=ccss_max_valence`). `*out` is written only on success.
///
/// # Safety
/// `tables` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_depth_rates(
    tables: *const CcssTables,
    valence: u32,
    out: *mut CcssDepthRatesInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let tb = unsafe { try_handle(tables, "tables") }?;
        check_ptr(out as *const CcssDepthRatesInfo, "out")?;
        let t = tb
            .set
            .get(valence as usize)
            .ok_or(Error::UnsupportedValence {
                vertex: u32::MAX,
                valence,
            })?;
        let mut r = CcssDepthRatesInfo::from(t.rates());
        r.valence = valence;
        // SAFETY: checked above.
        unsafe { put(out, "out", r) }
    })
}

/// Subdivision depth of sub-face `sub` of base face `face` of a feature
/// mesh for tolerance `eps`: writes to `*out` the number of uniform
/// refinement steps (OpenSubdiv's rules) after which every control face of
/// the sub-face lies within `eps` of the limit surface (ccss-core's
/// `bounds::feature_depth`: Lemma 1 on the B-spline pieces, phantom points
/// included; the diameter of the local control points' convex hull next to
/// crease ends, corners, darts, extraordinary and semi-sharp vertices), or
/// `UINT32_MAX` if a hull was still wider than `eps` at the deepest cell
/// level (30). Works on open meshes too.
///
/// Errors: NULL_POINTER / MISALIGNED (`ev`, `out`), INVALID_ARGUMENT
/// (`eps` not positive and finite), FACE_OUT_OF_RANGE,
/// SUBFACE_OUT_OF_RANGE, HOLE_FACE, NEIGHBOURHOOD_TOO_LARGE. `out` is
/// written only on success.
///
/// # Safety
/// `ev` NULL or a live handle; `out` NULL or writable; `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_depth(
    ev: *const CcssFeatureEvaluator,
    face: u32,
    sub: u32,
    eps: f64,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        if !(eps.is_finite() && eps > 0.0) {
            return Err(Failure::invalid("eps must be positive and finite"));
        }
        check_ptr(out as *const u32, "out")?;
        let d = ccss_core::bounds::feature_depth::feature_depth(e.evaluator(), face, sub, eps)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", d.steps.unwrap_or(u32::MAX)) }
    })
}
