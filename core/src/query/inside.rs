//! Inside/outside of a point for a closed solid, by the parity of the
//! certified crossings of a ray ([`super::ray`]).
//!
//! Along a ray from the point, the crossings of a closed embedded surface
//! alternate between entering and leaving; the point is inside iff their
//! number is odd. A ray is accepted only when every hit is
//! [`HitKind::Transversal`] (at most one crossing per cell, orientation
//! fixed), the first hit is farther than `tol` from the point and the
//! orientations `sign(d . n)` alternate along it; otherwise the next of a
//! fixed list of directions is tried.
//!
//! Rounding: the crossings inherit the rays' rounding terms
//! ([`super::ray`]); the transversal certificate needs the rounding term
//! `r` well below the tolerance, so `tol < 64 r` is
//! [`Error::CoordinateRange`] here.
//!
//! Work: at most 8 rays of [`MAX_CELLS`]` / 8` cells each (so at most
//! [`MAX_CELLS`] in all); more is [`Error::WorkLimitExceeded`].

use super::cell::CellSurface;
use super::ray::{all_hits_in_work, HitKind, QueryWork, Ray, RayOptions, MAX_CELLS};
use crate::error::Error;
use glam::DVec3;

/// Directions tried in turn (unit length not needed; no two parallel, none
/// along a coordinate axis or diagonal).
const DIRECTIONS: [[f64; 3]; 8] = [
    [0.301_511_3, 0.492_159_7, 0.816_496_6],
    [-0.573_462_2, 0.712_345_6, 0.404_124_5],
    [0.811_107_1, -0.284_733_3, 0.511_056_9],
    [-0.137_840_5, -0.923_579_4, 0.357_770_9],
    [0.654_321_9, 0.123_456_7, -0.745_966_7],
    [-0.399_999_7, -0.456_789_1, -0.794_719_3],
    [0.957_427_1, 0.221_359_4, 0.185_164_3],
    [-0.212_132_0, 0.282_842_7, -0.935_414_3],
];

/// Whether `p` is inside the closed solid bounded by `surf` (see module
/// docs). `tol` (model units, > 0) is the tolerance of the ray queries and
/// the least distance from `p` to the surface that is decided.
pub(crate) fn inside<S: CellSurface + ?Sized>(
    surf: &S,
    p: DVec3,
    tol: f64,
    work: &mut QueryWork,
) -> Result<bool, Error> {
    if !p.is_finite() {
        return Err(Error::InvalidArgument("point not finite"));
    }
    // Transversal certificates (Krawczyk) need the rounding well below
    // the tolerance: `tol >= 64 r` (`rounding.rs`).
    let r = super::rounding::term(surf, p.abs().max_element())?;
    if tol < 64.0 * r {
        return Err(Error::CoordinateRange(
            "inside: tolerance below 64x the rounding term of the coordinates (model far \
             from the origin or tolerance too small for its size)",
        ));
    }
    let opts = RayOptions {
        tol,
        t_min: 0.0,
        max_cells: MAX_CELLS / DIRECTIONS.len() as u64,
    };
    for d in DIRECTIONS {
        let ray = Ray {
            origin: p,
            dir: DVec3::from_array(d),
        };
        let n = all_hits_in_work(surf, &ray, &opts, work)?;
        let hits = &work.hits[..n];
        let dl = ray.dir.length();
        let ok = hits.iter().all(|h| h.kind == HitKind::Transversal)
            && hits.first().is_none_or(|h| h.t * dl > tol)
            && hits.windows(2).all(|w| {
                let a = w[0].normal.dot(ray.dir);
                let b = w[1].normal.dot(ray.dir);
                a * b < 0.0
            });
        if ok {
            return Ok(n % 2 == 1);
        }
    }
    Err(Error::InvalidArgument(
        "point on the surface (within tol) or every ray degenerate",
    ))
}
