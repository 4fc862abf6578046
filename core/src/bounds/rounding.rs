//! Rounding terms of the guaranteed bounds (tessellation, cell bounds,
//! depths) and the coordinate range in which they are certified.
//!
//! The bounds of [`crate::bounds::cell_bound`], [`crate::bounds::depth`] and the
//! tessellation are proved for exact arithmetic on the evaluator's patch
//! data. In floating point three things differ, each by at most a multiple
//! of `eps M`, `M` the largest coordinate magnitude of the control points
//! involved (`eps` = `f64::EPSILON`):
//!
//! * the patch data itself is within `BUILD_ROUNDING eps M` per coordinate
//!   of exact ([`BUILD_ROUNDING`], measured: 3.9 eps M on smooth and 2.6
//!   eps M on feature meshes, allowance 64), so the surface it defines moves
//!   by at most `sqrt(3) BUILD_ROUNDING eps M`; evaluated output points
//!   (the tessellation's vertices) are inside that same measured figure;
//! * Bezier nets carried down `L <= 30` levels by de Casteljau (three
//!   halvings per direction and level, each a convex combination that adds
//!   at most `eps/2` of the values' magnitude) are within
//!   `delta = (4 + 3 L) eps M <= 94 eps M` per coordinate of the exact nets
//!   (the first 4 for the B-spline-to-Bezier conversion);
//! * the interpolation bound `lambda_max([[a, c], [c, b]]) / 3` from second
//!   differences moves by at most `(24 + 36) sqrt(3) delta / 3 = 20 sqrt(3)
//!   delta` when the net moves by `delta` (second differences by `4 delta`
//!   per coordinate, `a, b = 6 |.|`, `c = 9 |.|`), the vertices of a cell's
//!   polygon by `sqrt(3) delta`.
//!
//! Together: `sqrt(3) (64 + 94 + 20 * 94) eps M < 3,600 eps M`, rounded up
//! to [`TERM`] = 4096 eps M. The bounds' own evaluation (a few operations,
//! relative error below `1e-14`) is covered by the same margin for bounds up
//! to `10 M`. Underflow: squared second differences below `2^-1022` lose
//! at most `2^-500` in any bound ([`ABS_TERM`] = `2^-499`, added too).
//!
//! Range: magnitudes above `2^200` ([`MAX_MAGNITUDE`]) or below `2^-200`
//! ([`MIN_MAGNITUDE`], zero allowed) or non-finite data are refused with
//! [`Error::CoordinateRange`] (the range of
//! `voxel::measure::MAX_SIZE_EXP`; beyond about `2^300` dense
//! sampling finds the tessellation's bounds violated, squares and products
//! of coordinates leaving the normal `f64` range, so the margin is wide);
//! tiny models far from the origin are refused where the rounding term,
//! not the geometry, decides the result (the tessellation's deepest cells
//! fail only by rounding).

use crate::error::Error;
use crate::eval::{CellGeom, Evaluator, FeatureEvaluator};

/// Rounding allowance of the evaluator's patch data (per coordinate, in
/// units of `eps M`); measured by `tests/tests/hardening.rs`
/// (`build_rounding_constant`, `build_rounding_constant_feature_meshes`).
pub const BUILD_ROUNDING: f64 = 64.0;

/// The rounding term of a bound, in units of `eps M` (module docs).
pub const TERM: f64 = 4096.0;

/// Absolute part of the rounding term (underflow of squares).
pub const ABS_TERM: f64 = f64::from_bits((1023 - 499) << 52);

/// Largest coordinate magnitude whose bounds are certified (`2^200`).
pub const MAX_MAGNITUDE: f64 = f64::from_bits((1023 + 200) << 52);

/// Smallest non-zero coordinate magnitude whose bounds are certified
/// (`2^-200`).
pub const MIN_MAGNITUDE: f64 = f64::from_bits((1023 - 200) << 52);

/// The rounding term `TERM eps m + ABS_TERM` of bounds over data of
/// magnitude `m`; [`Error::CoordinateRange`] if `m` is not finite or above
/// [`MAX_MAGNITUDE`], or non-zero and below [`MIN_MAGNITUDE`].
pub fn term(m: f64) -> Result<f64, Error> {
    if !(m.is_finite() && m <= MAX_MAGNITUDE) {
        return Err(Error::CoordinateRange(
            "control point coordinates are not finite or above 2^200",
        ));
    }
    if m > 0.0 && m < MIN_MAGNITUDE {
        return Err(Error::CoordinateRange(
            "control point coordinates are all below 2^-200 (a model this small is not certified)",
        ));
    }
    Ok(TERM * f64::EPSILON * m + ABS_TERM)
}

/// Largest coordinate magnitude of the control data of patch `pi` (its
/// B-spline grid, or the `2n + 8` control points and limit point of an
/// extraordinary patch); NaN if some value is NaN.
pub(crate) fn patch_magnitude(ev: &Evaluator, pi: usize) -> f64 {
    let n = (ev.patch_meta[pi] & 0xff) as usize;
    let o = ev.patch_data[pi] as usize;
    // The largest |x|, NaN if some x is NaN: a branch-free maximum and a
    // NaN flag (the same value as a NaN-propagating fold; the tessellation
    // asks once per slot per marking).
    let max_abs = |s: &[f64]| {
        let (mut m, mut nan) = (0.0f64, false);
        for &x in s {
            let a = x.abs();
            nan |= a.is_nan();
            m = if a > m { a } else { m };
        }
        if nan {
            f64::NAN
        } else {
            m
        }
    };
    if n == 4 {
        return max_abs(ev.data.get(o..o + 48).unwrap_or(&[f64::NAN]));
    }
    let lay = ev.ev_layout(o, n);
    let pts = ev.data.get(lay.points()).unwrap_or(&[f64::NAN]);
    let ghat = ev.data.get(lay.ghat()).unwrap_or(&[f64::NAN]);
    max_abs(pts).max(max_abs(&ghat[..3.min(ghat.len())]))
}

/// Largest coordinate magnitude of the patches of `slot` (one, or four
/// for a slot split into quadrants).
pub(crate) fn slot_magnitude(ev: &Evaluator, slot: usize) -> f64 {
    let p0 = ev.slot_patch[slot] as usize;
    let np = if ev.slot_split[slot] != 0 { 4 } else { 1 };
    let mut m = 0.0f64;
    for pi in p0..p0 + np {
        let x = patch_magnitude(ev, pi);
        if x.is_nan() {
            return f64::NAN;
        }
        m = m.max(x);
    }
    m
}

/// The rounding term of the bounds over sub-face `sub` of face `face` of a
/// feature mesh: [`term`] of the largest coordinate magnitude of its
/// level-0 cell's control points (or of its four level-1 cells' for a quad
/// face).
pub fn feature_term(fev: &FeatureEvaluator, face: u32, sub: u32) -> Result<f64, Error> {
    let mag = |g: CellGeom| -> f64 {
        let m = match g {
            CellGeom::Split => 0.0,
            CellGeom::Poly { grid, .. } => grid
                .iter()
                .fold(0.0f64, |m, p| m.max(p.abs().max_element())),
            CellGeom::Hull(h) => h.lo.abs().max(h.hi.abs()).max_element(),
        };
        if m.is_nan() {
            f64::INFINITY
        } else {
            m
        }
    };
    let root = fev.cell(face, sub, 0, 0, 0)?;
    let m = if matches!(root, CellGeom::Split) {
        let mut m = 0.0f64;
        for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            m = m.max(mag(fev.cell(face, sub, 1, i, j)?));
        }
        m
    } else {
        mag(root)
    };
    term(m)
}
