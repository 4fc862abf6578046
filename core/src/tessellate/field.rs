//! Tolerance fields: absolute flatness whose tolerance varies from cell to
//! cell ([`ToleranceField`], [`crate::tessellate::mark_slot_field`]).
//!
//! A cell is accepted when its bound is at most `min(eps, field(box))`,
//! `eps` the options' absolute tolerance and `box` an axis-aligned box
//! that contains the cell's surface: for a polynomial cell the box of its
//! Bezier net (convex hull property), widened by the slot's rounding term;
//! for a corner cell `[0, 2^-k]^2` at an extraordinary vertex the box of
//! its `2n + 8` control points after `k` subdivision steps (Catmull-Clark's
//! masks are non-negative: convex hull property again,
//! [`crate::eval::Evaluator`]'s `ev_corner_box`), widened the same way;
//! for any other cell (a slot split before its patches) the whole space. The marking also accepts
//! children without testing them (a polynomial cell's children have a
//! quarter of its bound) and takes light corner splits: both use the
//! parent's tolerance, which is at most the children's because a field is
//! **monotone** (a box inside another gets a tolerance at least the
//! other's). Every accepted cell's bound is then at most the field of any
//! box inside its surface's box, e.g. the box of one of its output
//! triangles: the caller recovers a per-triangle bound from the triangles
//! alone. Crack elimination does not depend on the tolerance (any quadtree
//! gives a crack-free output), so a field changes only which cells are
//! split.

use crate::math::bezier::Net;
use glam::DVec3;

/// A monotone tolerance over axis-aligned boxes (module docs): the largest
/// accepted bound of a cell whose surface lies in `[lo, hi]` (model units,
/// positive; values above the options' `eps` act as `eps`). Boxes may be
/// unbounded (`lo = -inf`, `hi = +inf`: the field's smallest value).
pub trait ToleranceField {
    /// The tolerance of a cell whose surface lies in `[lo, hi]`.
    fn tolerance(&self, lo: DVec3, hi: DVec3) -> f64;
}

/// The box of a Bezier net moved by `off`, widened by `pad`.
pub(crate) fn net_box(n: &Net, off: [f64; 3], pad: f64) -> (DVec3, DVec3) {
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    for c in 0..3 {
        let s = &n[16 * c..16 * c + 16];
        let (mn, mx) = s
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        lo[c] = mn + off[c] - pad;
        hi[c] = mx + off[c] + pad;
    }
    (DVec3::from_array(lo), DVec3::from_array(hi))
}

/// The whole space (the box of a cell known only by its bound).
pub(crate) const EVERYWHERE: (DVec3, DVec3) = (DVec3::NEG_INFINITY, DVec3::INFINITY);
