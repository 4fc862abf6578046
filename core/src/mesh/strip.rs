//! Pieces of a straight, uniformly semi-sharp crease: where a quad's
//! neighbourhood is a regular grid and its only sharp edges are one line
//! of equal semi-sharpness `sigma` through one of its sides, every
//! Catmull-Clark rule with OpenSubdiv's semi-sharp variants \[OSD\]
//! (\[DKT98\]) factors into the cubic B-spline rule along the crease and a
//! one-dimensional rule across it. So the limit surface over the quad is
//! the tensor product of a cubic B-spline along the crease and the limit of
//! the one-dimensional scheme across it.
//!
//! Why the rules factor (a regular grid, the crease along `u` at row 1):
//! the face point is `(1/2, 1/2) (x) (1/2, 1/2)`; an edge across the crease
//! (smooth) is `(1/8, 6/8, 1/8) (x) (1/2, 1/2)`; a crease vertex is
//! `(1/8, 6/8, 1/8) (x) C` and a crease edge `(1/2, 1/2) (x) C`, where `C` is
//! the across rule at the crease: the point itself while the crease is
//! sharp, `(1/8, 6/8, 1/8)` once it is smooth, and the blend `w point +
//! (1 - w) (1/8, 6/8, 1/8)` with OpenSubdiv's fractional weight `w` in the
//! level where the sharpness decays to zero (the vertex and the edge rule
//! blend with the same weight here: both edges at every crease vertex
//! carry the same value, which decays the same way at every end). Every
//! other vertex is smooth of valence 4, `(1/8, 6/8, 1/8)` both ways.
//!
//! Across, one step of the scheme on the points `P0, P1, P2, P3` (crease at
//! `P1`, the quad spanning `P1..P2`) gives `(P0 + P1) / 2`, `C(P0, P1, P2)`,
//! `(P1 + P2) / 2`, `(P1 + 6 P2 + P3) / 8` and `(P2 + P3) / 2`: the last four
//! are the B-spline points of the half of the span away from the crease
//! (no later rule there reads the crease), the first four the same
//! configuration again, half as wide, with the sharpness decayed. After
//! `K` steps the value is zero and the half next to the crease is a
//! B-spline too: `K + 1` bicubic pieces, at distances `[2^-k, 2^-(k-1)]`
//! (`k = 1..K`) and `[0, 2^-K]` from the crease.
//!
//! Layer 3 (with the rest of `mesh/`): imports `sharpness`.

use super::sharpness::{decay_at, fractional_weight, is_sharp, Creasing, EndStats};
use glam::DVec3;

/// Most pieces of one strip: a semi-sharp value below
/// [`super::sharpness::INFINITE`] (10) decays to zero in at most 10 steps.
pub const MAX_PIECES: usize = 11;

/// A quad next to a straight, uniformly semi-sharp crease (from
/// [`super::local::LocalPatch::crease_strip`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseStrip {
    /// The quad's side on the crease (0: `v = 0`, 1: `u = 1`, 2: `v = 1`,
    /// 3: `u = 0`).
    pub side: usize,
    /// The crease's sharpness at the quad's level.
    pub sigma: f32,
    /// The 4 x 4 control points around the quad (row by row, `i` along
    /// `u`), as a B-spline patch's.
    pub grid: [DVec3; 16],
}

/// Whether the parameter across a crease on `side` (see
/// [`CreaseStrip::side`]) is `v` (sides 0 and 2: the crease runs along
/// `u`); else it is `u`.
#[inline]
pub fn across_is_v(side: usize) -> bool {
    side == 0 || side == 2
}

/// Whether a crease on `side` lies where the parameter across it is 0
/// (sides 0: `v = 0`, and 3: `u = 0`); else where it is 1.
#[inline]
pub fn crease_at_zero(side: usize) -> bool {
    side == 0 || side == 3
}

/// Index in a grid (row by row, `i` along `u`) of the point `across` steps
/// from the outer line behind the crease and `along` steps along it, for a
/// crease on `side`.
#[inline]
fn at(side: usize, across: usize, along: usize) -> usize {
    match side {
        0 => across * 4 + along,
        1 => along * 4 + 3 - across,
        2 => (3 - across) * 4 + along,
        _ => along * 4 + across,
    }
}

impl CreaseStrip {
    /// The weight of the crease point itself in the across rule of each
    /// step until the value has decayed (1 while it is sharp; OpenSubdiv's
    /// fractional weight in the step where it decays to zero), into `w`;
    /// returns the number of steps `K`. `None` when the decay does not fit
    /// the tensor form (a vertex and an edge weight that differ, possible
    /// only for Chaikin values within rounding of 1) or takes more than
    /// [`MAX_PIECES`] - 1 steps. Cheap: sharpness arithmetic only.
    pub fn steps(&self, creasing: Creasing, w: &mut [f64; MAX_PIECES]) -> Option<usize> {
        let mut sigma = self.sigma;
        let mut n = 0;
        while is_sharp(sigma) {
            if n + 1 >= MAX_PIECES {
                return None;
            }
            let end = EndStats {
                edges: 4,
                semi: 2,
                sum: sigma + sigma,
            };
            let child = decay_at(creasing, sigma, end);
            // Weights of the point itself in the crease's vertex rule and
            // edge rule (as `vertex_mask` and `edge_mask` compute them).
            let (wv, we) = if is_sharp(child) {
                (1.0, 1.0)
            } else {
                let pair = (sigma, child);
                let w = fractional_weight(creasing, 0.0, 0.0, [pair, pair].into_iter());
                (w as f64, sigma as f64)
            };
            if wv != we {
                return None;
            }
            w[n] = wv;
            sigma = child;
            n += 1;
        }
        Some(n)
    }

    /// Calls `emit` with the first `count` bicubic pieces of the strip in
    /// order (of the `K + 1` that [`CreaseStrip::steps`] gives `K` for,
    /// which must have succeeded), each as a B-spline grid in the quad's
    /// orientation (row by row, `i` along `u`): piece `k - 1` covers the
    /// distances `[2^-k, 2^-(k-1)]` from the crease side (`k = 1..K`), the
    /// last one `[0, 2^-K]`, each mapped linearly onto its unit square in
    /// the quad's orientation.
    pub fn pieces(&self, creasing: Creasing, count: usize, mut emit: impl FnMut(&[DVec3; 16])) {
        let mut w = [0.0; MAX_PIECES];
        let Some(steps) = self.steps(creasing, &mut w) else {
            return;
        };
        // Across (crease at index 1) by along.
        let mut q: [[DVec3; 4]; 4] =
            core::array::from_fn(|a| core::array::from_fn(|b| self.grid[at(self.side, a, b)]));
        for (n, &wv) in w[..steps].iter().enumerate() {
            if n >= count {
                return;
            }
            let mut c = [[DVec3::ZERO; 4]; 5];
            for b in 0..4 {
                let [p0, p1, p2, p3] = [q[0][b], q[1][b], q[2][b], q[3][b]];
                c[0][b] = (p0 + p1) * 0.5;
                c[1][b] = p1 * wv + (p0 + p1 * 6.0 + p2) * ((1.0 - wv) * 0.125);
                c[2][b] = (p1 + p2) * 0.5;
                c[3][b] = (p1 + p2 * 6.0 + p3) * 0.125;
                c[4][b] = (p2 + p3) * 0.5;
            }
            emit(&self.grid_of(&[c[1], c[2], c[3], c[4]]));
            q = [c[0], c[1], c[2], c[3]];
        }
        if count > steps {
            emit(&self.grid_of(&q));
        }
    }

    /// Across-by-along points as a grid in the quad's orientation.
    fn grid_of(&self, q: &[[DVec3; 4]; 4]) -> [DVec3; 16] {
        let mut g = [DVec3::ZERO; 16];
        for (a, row) in q.iter().enumerate() {
            for (b, &p) in row.iter().enumerate() {
                g[at(self.side, a, b)] = p;
            }
        }
        g
    }
}
