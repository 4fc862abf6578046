//! Rounding terms of the certified queries (rays, inside/outside, closest
//! points, slices).
//!
//! The queries' guarantees are proved for exact arithmetic on the exact
//! limit surface. In `f64` the surface the walks see differs from the
//! exact one by the rounding of the evaluator's patch data and of the
//! Bezier nets carried down to [`super::MAX_LEVEL`] = 60 levels by de
//! Casteljau, and the reported points and distances carry the rounding of
//! their evaluation and of a few products with the query's own data (ray
//! origin, query point, plane offset). Each is a multiple of `eps M`, `M`
//! the largest coordinate magnitude of the control points and of the
//! query's data (`eps` = `f64::EPSILON`):
//!
//! * patch data: `BUILD_ROUNDING` = 64 `eps M` per coordinate
//!   ([`crate::bounds::rounding`], measured 3.9 on smooth and 2.6 on
//!   feature meshes);
//! * nets at level `L <= 60`: `(4 + 3 L) eps M <= 184 eps M` per
//!   coordinate;
//! * evaluated points: within the measured patch-data figure; distances,
//!   projections and the ray parameter: a few `eps (M + |query|)`.
//!
//! Together below `sqrt(3) (64 + 184) + 64 + 16 < 520 eps M`; the queries
//! use the tessellation's [`crate::bounds::rounding::TERM`] = 4096 `eps M`
//! (plus `2^-499` for underflow), with the same certified range: control
//! points or query data above `2^200` or a model entirely below `2^-200`
//! are [`Error::CoordinateRange`].
//!
//! Every exclusion test of a walk widens its bound by this term `r`, and the
//! walk runs at the inner tolerance `tol - 2 r`, so that the stated
//! tolerance holds for the computed outputs, rounding included. A
//! tolerance below `4 r` (the rounding, not the geometry, would decide the
//! answer: a unit model shifted by `1e6` has `r = 9.1e-7`) is
//! [`Error::CoordinateRange`].

use super::cell::CellSurface;
use crate::bounds::rounding;
use crate::error::Error;

/// The rounding term `r` of a query on `surf` whose own data (ray origin,
/// query point, plane offset) has magnitude `query_mag`.
pub(crate) fn term<S: CellSurface + ?Sized>(surf: &S, query_mag: f64) -> Result<f64, Error> {
    term_of(surf.magnitude(), query_mag)
}

/// [`term`] for a surface of magnitude `m` ([`CellSurface::magnitude`],
/// which reads every control point: callers with many queries ask once).
pub(crate) fn term_of(m: f64, query_mag: f64) -> Result<f64, Error> {
    if !query_mag.is_finite() || query_mag > rounding::MAX_MAGNITUDE {
        return Err(Error::CoordinateRange(
            "query coordinates are not finite or above 2^200",
        ));
    }
    if m.is_nan() {
        return Err(Error::CoordinateRange("control points are not finite"));
    }
    // The model's range first (a tiny model is refused even when the query
    // data is large), then the query's.
    rounding::term(m)?;
    rounding::term(m.max(query_mag))
}

/// The inner tolerance `tol - 2 r` the walk runs at; refuses a tolerance
/// below `4 r` with [`Error::CoordinateRange`].
pub(crate) fn inner(tol: f64, r: f64) -> Result<f64, Error> {
    if tol < 4.0 * r {
        return Err(Error::CoordinateRange(
            "tolerance below 4x the rounding term of the coordinates (model far from the \
             origin or tolerance too small for its size): raise the tolerance or move the model",
        ));
    }
    Ok(tol - 2.0 * r)
}

/// Largest coordinate magnitude of `vals` (NaN if one is NaN).
pub(crate) fn max_abs(vals: &[f64]) -> f64 {
    vals.iter().fold(0.0f64, |m, &x| {
        if x.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(x.abs())
        }
    })
}
