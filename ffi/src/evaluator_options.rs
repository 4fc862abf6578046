//! `ccss_evaluator_options`: what an evaluator keeps precomputed per
//! extraordinary patch (memory against speed; every choice evaluates bit
//! for bit the same), for `ccss_evaluator_required_bytes_with_options` /
//! `ccss_evaluator_build_with_options`.

use crate::boundary::{guard, put};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::eval::{EvaluatorOptions, MAX_DEEP_LEVEL};

/// The deepest level `ccss_evaluator_options.deep_levels` can keep.
pub const CCSS_EVALUATOR_MAX_DEEP_LEVEL: u32 = MAX_DEEP_LEVEL as u32;

/// What an evaluator keeps per extraordinary patch (EV patches and N-gon
/// centre sub-patches) besides its eigen projection and control points.
/// Memory per patch of valence 3: 28,696 bytes by default, 672 with
/// `ccss_evaluator_options_compact`; the bytes of a mesh come from
/// `ccss_evaluator_required_bytes_with_options`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CcssEvaluatorOptions {
    /// 1: keep the control grids of the level-1 and level-2 sub-patches
    /// (2,304 bytes; a point there costs one bicubic evaluation); 0: compute
    /// them per query. Default 1.
    pub subpatch_grids: u8,
    /// 1: keep the corner bounds of depth and tessellation (376 bytes);
    /// 0: recompute them when asked. Default 1.
    pub corner_bounds: u8,
    /// Keep the sub-patch grids of levels 3..=deep_levels (1,152 bytes per
    /// level; 0 to 2 keep none; at most `CCSS_EVALUATOR_MAX_DEEP_LEVEL`):
    /// points within 1/4 .. 2^-deep_levels of an extraordinary vertex or
    /// N-gon centre cost one bicubic evaluation instead of the eigen kernel.
    /// Default 24.
    pub deep_levels: u8,
}

impl From<EvaluatorOptions> for CcssEvaluatorOptions {
    fn from(o: EvaluatorOptions) -> Self {
        CcssEvaluatorOptions {
            subpatch_grids: o.subpatch_grids as u8,
            corner_bounds: o.corner_bounds as u8,
            deep_levels: o.deep_levels,
        }
    }
}

/// The core options of `o`, or INVALID_ARGUMENT naming the bad field.
pub(crate) fn core_options(o: &CcssEvaluatorOptions) -> Result<EvaluatorOptions, Failure> {
    let flag = |v: u8, msg| match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(Failure::invalid(msg)),
    };
    if o.deep_levels > MAX_DEEP_LEVEL {
        return Err(Failure::invalid(
            "options.deep_levels must be at most CCSS_EVALUATOR_MAX_DEEP_LEVEL",
        ));
    }
    Ok(EvaluatorOptions {
        subpatch_grids: flag(o.subpatch_grids, "options.subpatch_grids must be 0 or 1")?,
        corner_bounds: flag(o.corner_bounds, "options.corner_bounds must be 0 or 1")?,
        deep_levels: o.deep_levels,
    })
}

/// Writes the default options to `*out` (everything kept: what
/// `ccss_evaluator_build` uses).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_options_default(
    out: *mut CcssEvaluatorOptions,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(detail, || unsafe {
        put(out, "out", EvaluatorOptions::FULL.into())
    })
}

/// Writes the smallest options to `*out` (nothing kept beyond the eigen
/// projection and the control points: for memory-bound hosts and
/// firmware; evaluation runs the eigen kernel per query).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_options_compact(
    out: *mut CcssEvaluatorOptions,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(detail, || unsafe {
        put(out, "out", EvaluatorOptions::COMPACT.into())
    })
}
