//! Subdivision depth of a feature mesh (creases, corners, semi-sharp edges,
//! boundaries): per sub-face, the number of uniform refinement steps after
//! which every control face of the sub-face is within `eps` of the limit
//! surface over it (`max ||L(u,v) - S(u,v)|| <= eps`, `L` the bilinear map
//! of a refined control face, `S` the limit surface over the same
//! parameters), at that level and every later one.
//!
//! The sub-face is walked as cells of [`FeatureEvaluator::cell`]:
//!
//! * a **polynomial cell** of level `k` is a B-spline grid (phantom points
//!   across infinitely sharp sides included) of some level `j0 <= k`
//!   restricted to the cell. Refining the grid is uniform B-spline
//!   refinement, which reproduces Catmull-Clark's smooth and crease rules
//!   there (the phantoms are the reflections the crease rule implies), so
//!   the refined control faces inside the cell are the central faces of
//!   the refined grids and \[CL-R\] Lemma 1 holds: distance at level `m`
//!   `<= M / (3 * 4^(m - j0))`, `M` the grid's second-order norm. Depth:
//!   `max(k, j0 + ceil(log4(M / (3 eps))))`.
//! * a **hull cell** (next to a crease end, corner, dart, extraordinary
//!   vertex, or before a semi-sharp edge has decayed) bounds nothing
//!   polynomial, but every later control point of the cell and the limit
//!   surface over it lie in the convex hull of its local control points
//!   (every rule is a convex combination, and a child's points are
//!   combinations of its parent's), so the distance at every level `>= k`
//!   is at most the hull's diameter ([`crate::eval::HullBound::diameter`]).
//!   A hull cell whose diameter is at most `eps` has depth `k`; others are
//!   split. This bound shrinks like `2^-k`, not `4^-k`: near such vertices
//!   the depth is about twice the regular one (measured in the tests).
//!
//! The depth of a sub-face is the largest depth of its cells, in refinement
//! steps of the base mesh (cell level `k` of a quad face is `k` steps; of a
//! sub-face of an N-gon, `k + 1`).

use crate::error::Error;
use crate::eval::{CellCursor, CellGeom, FeatureEvaluator, MAX_CELL_LEVEL};
use glam::DVec3;

use super::depth::regular_depth;

/// Depth of one sub-face and what bounded it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FeatureDepth {
    /// Refinement steps of the base mesh (None: a hull cell was still wider
    /// than `eps` at cell level [`MAX_CELL_LEVEL`]).
    pub steps: Option<u32>,
    /// Polynomial cells whose Lemma 1 bound was used.
    pub poly_cells: u32,
    /// Hull cells that were split.
    pub split_hulls: u32,
    /// Hull cells whose diameter met `eps`.
    pub final_hulls: u32,
}

/// Second-order norm of a 4x4 grid (row by row): the largest norm of the
/// second differences along rows and along columns.
pub fn grid_points_norm(g: &[DVec3; 16]) -> f64 {
    let mut m = 0.0f64;
    for r in 0..4 {
        for c in 1..3 {
            let row = g[4 * r + c - 1] - g[4 * r + c] * 2.0 + g[4 * r + c + 1];
            let col = g[4 * (c - 1) + r] - g[4 * c + r] * 2.0 + g[4 * (c + 1) + r];
            m = m.max(row.length()).max(col.length());
        }
    }
    m
}

/// The depth of sub-face `sub` of base face `face` for tolerance `eps`
/// (module docs). Work memory: an explicit stack on the machine stack.
///
/// Errors: those of [`FeatureEvaluator::cell`] (face or sub-face out of
/// range, a hole face, capacity); `InvalidArgument` for `eps` not finite
/// and positive; `CoordinateRange` if `eps` is not above the rounding term
/// of the sub-face's coordinates ([`super::rounding::term`]; the depth is
/// computed for `eps` less that term).
pub fn feature_depth(
    fe: &FeatureEvaluator,
    face: u32,
    sub: u32,
    eps: f64,
) -> Result<FeatureDepth, Error> {
    if !(eps.is_finite() && eps > 0.0) {
        return Err(Error::InvalidArgument("eps must be finite and positive"));
    }
    // Rounding (module docs of `rounding`): the depth is for `eps` less
    // the rounding term of the sub-face's coordinates.
    let eps = eps - super::rounding::feature_term(fe, face, sub)?;
    if eps <= 0.0 {
        return Err(Error::CoordinateRange(
            "eps is below the rounding of the coordinates",
        ));
    }
    let quad = fe.mesh().base.face(face as usize).len() == 4;
    let extra = u32::from(!quad);
    const CAP: usize = 3 * MAX_CELL_LEVEL as usize + 8;
    let mut st = [(0u32, 0u32, 0u32); CAP];
    st[0] = (0, 0, 0);
    let mut n = 1usize;
    let mut out = FeatureDepth {
        steps: Some(0),
        ..Default::default()
    };
    let mut deepest = 0u32;
    // Depth first: children refine once from their parent's patch.
    let mut cursor = CellCursor::new();
    while n > 0 {
        n -= 1;
        let (k, i, j) = st[n];
        let split = match fe.cell_in(&mut cursor, face, sub, k, i, j)? {
            CellGeom::Split => true,
            CellGeom::Poly { grid, rect } => {
                out.poly_cells += 1;
                // The grid's level: the cell is 2^-(k - j0) of its square.
                let size = rect[1] - rect[0];
                let below = libm::round(-libm::log2(size)) as u32;
                let j0 = k.saturating_sub(below);
                let d = regular_depth(grid_points_norm(&grid), eps);
                deepest = deepest.max(k.max(j0.saturating_add(d)));
                false
            }
            CellGeom::Hull(h) => {
                if h.diameter() <= eps {
                    out.final_hulls += 1;
                    deepest = deepest.max(k);
                    false
                } else if k >= MAX_CELL_LEVEL || n + 4 > CAP {
                    out.steps = None;
                    false
                } else {
                    out.split_hulls += 1;
                    true
                }
            }
        };
        if split {
            for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                st[n] = (k + 1, 2 * i + di, 2 * j + dj);
                n += 1;
            }
        }
    }
    if out.steps.is_some() {
        out.steps = Some(deepest.saturating_add(extra));
    }
    Ok(out)
}
