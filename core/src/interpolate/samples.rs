//! Sample points and the weights of the sampled derivatives over a patch's
//! 2n+8 control points (\[CL-R eqs. 2.5, 2.6, 4.2\]).
//!
//! A derivative of the limit surface at a fixed (u, v) of a patch is a fixed
//! linear combination of its control points (the vector `V` of
//! \[CL-R eq. 4.5\]). The weights depend only on the valence, the rule and
//! (u, v); they are obtained here by evaluating the exact kernel (eigen
//! tables for extraordinary patches, the bicubic B-spline for regular ones)
//! on unit control points, three labels per evaluation (one per coordinate).
//!
//! At the extraordinary vertex itself (u = v = 0 of an extraordinary patch)
//! the parametric derivatives are 0 or unbounded; the kernel reports the
//! limit tangent directions there ([`crate::ValenceTable::eval_at_ev`]) and
//! zero second derivatives, so only direction-based rows use that sample.

use crate::eigen::TableSet;
use crate::error::Error;
use crate::math::bspline::eval_grid;
use crate::math::Eval;
use crate::mesh::stencil::{label_at, MAX_K};
use glam::DVec3;

/// The sample points of every face of `G` (\[CL-R eq. 4.2\]): `{0, 1/2, 1}^2`.
/// The set is invariant under the quarter turns between a face's own frame
/// and its patch frame.
pub const SAMPLES: [(f64, f64); 9] = [
    (0.0, 0.0),
    (0.5, 0.0),
    (1.0, 0.0),
    (0.0, 0.5),
    (0.5, 0.5),
    (1.0, 0.5),
    (0.0, 1.0),
    (0.5, 1.0),
    (1.0, 1.0),
];

/// Points per side of the grid of orientation rows on every sampled face
/// ([`super::orient`])
/// (`{0, 1/6, .., 1}^2`).
pub const ORIENT_GRID: usize = 7;

/// Grid points per face.
pub(crate) const OG: usize = ORIENT_GRID * ORIENT_GRID;

/// Values stored per (face, grid point) of a row: `a` (3), `b` (3),
/// target (its weight sits in a separate array, the only one zeroed and
/// scanned: rows are read and written only where their weight is set).
pub(crate) const OROW: usize = 7;

/// `(u, v)` of grid point `p` (patch frame).
#[inline]
pub(crate) fn grid_point(p: usize) -> (f64, f64) {
    let s = 1.0 / (ORIENT_GRID - 1) as f64;
    ((p / ORIENT_GRID) as f64 * s, (p % ORIENT_GRID) as f64 * s)
}

/// Offset of the weight row `(valence n, grid point p, d)` (`d` 0: du, 1:
/// dv) in the grid weight table.
#[inline]
pub(crate) fn gwrow(n: usize, p: usize, d: usize) -> usize {
    ((n * OG + p) * 2 + d) * MAX_K
}

/// Number of rows of a [`WeightRows`]: position, du, dv, duu, duv, dvv.
pub const ROWS: usize = 6;

/// One row of weights per quantity (index: 0 position, 1 du, 2 dv, 3 duu,
/// 4 duv, 5 dvv), one column per label.
pub type WeightRows = [[f64; MAX_K]; ROWS];

fn quantities(e: &Eval) -> [DVec3; ROWS] {
    [e.p, e.du, e.dv, e.duu, e.duv, e.dvv]
}

/// Weights of position and derivatives at (u, v) (patch frame, the
/// extraordinary vertex at (0, 0)) of a patch of valence `n`, over its
/// `2n + 8` labels.
///
/// Errors: [`Error::MissingTable`] when `n != 4` has no table,
/// [`Error::ParameterOutOfRange`] for (u, v) outside `[0, 1]^2`.
pub fn patch_weights(
    tables: &TableSet,
    n: usize,
    u: f64,
    v: f64,
    out: &mut WeightRows,
) -> Result<(), Error> {
    if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
        return Err(Error::ParameterOutOfRange);
    }
    let k = 2 * n + 8;
    for row in out.iter_mut() {
        *row = [0.0; MAX_K];
    }
    let table = if n == 4 {
        None
    } else {
        Some(
            tables
                .get(n)
                .ok_or(Error::MissingTable { valence: n as u32 })?,
        )
    };
    let mut c = 0;
    while c < k {
        let e = match table {
            None => {
                let mut grid = [0.0; 48];
                for y in -1..=2i32 {
                    for x in -1..=2i32 {
                        let l = label_at(4, x, y).unwrap_or(0);
                        if (c..c + 3).contains(&l) {
                            let s = ((x + 1) * 4 + (y + 1)) as usize;
                            grid[s + 16 * (l - c)] = 1.0;
                        }
                    }
                }
                eval_grid::<true>(&grid, u, v)
            }
            Some(tab) => {
                let mut pts = [DVec3::ZERO; MAX_K];
                for j in 0..3 {
                    if c + j < k {
                        pts[c + j][j] = 1.0;
                    }
                }
                tab.eval_patch(&pts, u, v, true)?
            }
        };
        for (row, q) in out.iter_mut().zip(quantities(&e)) {
            for j in 0..3 {
                if c + j < k {
                    row[c + j] = q[j];
                }
            }
        }
        c += 3;
    }
    Ok(())
}
