//! Certified closest point: the global minimum of `|S(x) - q|` over the
//! whole limit surface, by branch and bound over the dyadic cells of every
//! slot (`cell.rs`).
//!
//! Upper bounds are exact limit points (the corners of each cell's Bezier
//! net, the limit point of a corner ball). Lower bounds over a cell:
//!
//! * polynomial cells: the larger of the distance from `q` to the net's box
//!   (convex hull property) and the distance from `q` to the parallelogram
//!   of the cell's tangent model `L(s, t) = S(c) + S_s(c)(s - 1/2) +
//!   S_t(c)(t - 1/2)` minus the Taylor remainder bound
//!   `(a + 2c + b) / 8` (`a, b, c` the second-derivative bounds of the
//!   net, \[CL-R ch. 7\]): second order, so only a few cells per level
//!   survive near the minimum;
//! * corner cells at extraordinary vertices: `|q - L| - R_k` (corner ball);
//! * hull cells of feature meshes: the larger of the distances from `q` to
//!   the box and to the ball of the cell's control points (their upper
//!   bound: the exact limit point at the cell's centre).
//!
//! A cell is dropped when its lower bound is at least the best distance
//! found minus `tol`. So the reported distance (the exact distance to the
//! reported limit point) is at most the true minimum plus `tol`
//! ([`Closest::gap`] reports the bound actually certified, larger than
//! `tol` only where a corner ball at the deepest level was still larger).
//! The best point is finally polished by Gauss-Newton steps, kept only
//! when they bring it closer.
//!
//! Rounding (`rounding.rs`): every lower bound is lowered by the rounding
//! term `r` of the model and `q`, the walk runs at `tol - 2 r` and `gap`
//! includes `2 r` (the computed distance to the computed point against the
//! exact distance to the exact point), so `dist <= true minimum + gap`
//! holds for the computed output; `tol < 4 r` is
//! [`Error::CoordinateRange`].
//!
//! Work: at most [`ClosestOptions::max_cells`] cells taken from the stack
//! (each split into four), plus one root per slot, plus 8 polish steps;
//! more is [`Error::WorkLimitExceeded`] (a query point at the centre of a
//! sphere-like surface, equidistant from all of it, is the worst case).

use super::cell::{Bound, Cell, CellSurface, QUADRANT};
use super::index::{self, Visit};
use super::ray::QueryWork;
use super::taylor::{net_eval, parallelogram_distance, second_bounds};
use crate::error::Error;
use crate::math::bezier::CORNER_POINT;
use glam::DVec3;

/// Options of the closest-point query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestOptions {
    /// Tolerance in model units (> 0): the reported distance is at most the
    /// true minimum plus `tol`. Default 1e-9.
    pub tol: f64,
    /// Work budget: cells the branch and bound may take from its stack
    /// before it stops with [`Error::WorkLimitExceeded`]. Default
    /// [`super::MAX_CELLS`].
    pub max_cells: u64,
}

impl Default for ClosestOptions {
    fn default() -> Self {
        ClosestOptions {
            tol: 1e-9,
            max_cells: super::ray::MAX_CELLS,
        }
    }
}

/// The closest limit point to a query point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Closest {
    /// `|point - q|`.
    pub dist: f64,
    /// Base face.
    pub face: u32,
    /// Sub-face.
    pub sub: u32,
    /// Sub-face parameter u.
    pub u: f64,
    /// Sub-face parameter v.
    pub v: f64,
    /// The exact limit point `S(face, sub, u, v)`.
    pub point: DVec3,
    /// Certified: `dist <= true minimum + gap`, rounding included (`gap <=
    /// tol` unless a corner ball at the deepest level stayed wider).
    pub gap: f64,
}

/// Lower bound of the distance from `q` to the exact surface over `c`
/// (`r` the rounding term); the second-order bound is skipped when the
/// box bound reaches `cutoff`.
fn lower_bound(c: &Cell, q: DVec3, cutoff: f64, r: f64) -> f64 {
    lower_bound_net(c, q, cutoff) - r
}

/// [`lower_bound`] for the cell's data as computed.
fn lower_bound_net(c: &Cell, q: DVec3, cutoff: f64) -> f64 {
    match c.bound {
        Bound::Net => {
            let (lo, hi) = c.aabb();
            let box_d = (q - q.clamp(lo, hi)).length();
            if box_d >= cutoff {
                return box_d;
            }
            let (p, ps, pt) = net_eval(c, 0.5, 0.5);
            let [a, b, m] = second_bounds(c);
            let rem = (a + 2.0 * m + b) * 0.125;
            let o = p - 0.5 * ps - 0.5 * pt;
            let lin = parallelogram_distance(q, o, ps, pt) - rem;
            let lb = box_d.max(lin);
            // Rounding margin.
            lb - 1e-14 * (q.abs().max_element() + hi.abs().max(lo.abs()).max_element())
        }
        Bound::Ball { center, radius, .. } => (q - center).length() - radius,
        Bound::Hull { lo, hi, radius } => {
            let box_d = (q - q.clamp(lo, hi)).length();
            let ball_d = (q - 0.5 * (lo + hi)).length() - radius;
            box_d.max(ball_d)
                - 1e-14 * (q.abs().max_element() + hi.abs().max(lo.abs()).max_element())
        }
        Bound::None => f64::NEG_INFINITY,
    }
}

/// Best candidate so far.
#[derive(Clone, Copy)]
struct Best {
    dist: f64,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
}

/// The closest point (see module docs).
pub(crate) fn closest_point<S: CellSurface + ?Sized>(
    surf: &S,
    q: DVec3,
    opts: &ClosestOptions,
    work: &mut QueryWork,
) -> Result<Closest, Error> {
    if !q.is_finite() {
        return Err(Error::InvalidArgument("query point not finite"));
    }
    let tol = opts.tol;
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(Error::InvalidArgument("tolerance must be positive"));
    }
    if surf.faces() == 0 {
        return Err(Error::EmptyMesh);
    }
    let r = super::rounding::term(surf, q.abs().max_element())?;
    let tol = super::rounding::inner(tol, r)?;
    let mut visited = 0u64;
    let mut best = Best {
        dist: f64::INFINITY,
        face: 0,
        sub: 0,
        u: 0.0,
        v: 0.0,
    };
    let mut gap = tol;
    let consider = |c: &Cell, p: DVec3, (s, t): (f64, f64), best: &mut Best| {
        let d = (p - q).length();
        if d < best.dist {
            let (u, v) = c.param(s, t);
            *best = Best {
                dist: d,
                face: c.face,
                sub: c.sub,
                u,
                v,
            };
        }
    };
    let stack = &mut work.stack;
    let mut kids = [Cell::ZERO; 4];
    let qmag = q.abs().max_element();
    let mut visit = |v: Visit| -> Result<Option<f64>, Error> {
        let (face, sub) = match v {
            Visit::Box(lo, hi) => {
                // Below every distance from `q` to a point of the box, by
                // the rounding term and a relative margin.
                let slack = r + 1e-14 * (qmag + lo.abs().max(hi.abs()).max_element());
                let lb = index::box_distance(q, lo, hi) - slack;
                return Ok((lb < best.dist - tol).then_some(lb));
            }
            Visit::Slot(face, sub) => (face, sub),
        };
        stack.clear();
        let mut root = surf.root(face, sub);
        root.key = lower_bound(&root, q, best.dist - tol, r);
        stack.push(root);
        while let Some(c) = stack.pop() {
            if c.key >= best.dist - tol {
                continue;
            }
            visited += 1;
            if visited > opts.max_cells {
                return Err(Error::WorkLimitExceeded {
                    limit: opts.max_cells,
                    what: "cells of a closest-point query (ClosestOptions::max_cells)",
                });
            }
            match c.bound {
                Bound::Net => {
                    for k in 0..4 {
                        let (s, t) = QUADRANT[k];
                        consider(
                            &c,
                            c.point(CORNER_POINT[k]),
                            (s as f64, t as f64),
                            &mut best,
                        );
                    }
                }
                Bound::Ball { center, corner, .. } => {
                    let (s, t) = QUADRANT[corner as usize];
                    consider(&c, center, (s as f64, t as f64), &mut best);
                }
                Bound::Hull { .. } => {
                    if let Some(p) = super::feature::hull_point(surf, &c) {
                        consider(&c, p, (0.5, 0.5), &mut best);
                    }
                }
                Bound::None => {}
            }
            let lb = c.key;
            if lb >= best.dist - tol {
                continue;
            }
            if c.level >= super::cell::MAX_LEVEL || !stack.room(4) || surf.at_floor(&c) {
                // Left unresolved: it may be closer by up to this much.
                gap = gap.max(best.dist - lb);
                continue;
            }
            surf.split(&c, &mut kids);
            let cutoff = best.dist - tol;
            for k in kids.iter_mut() {
                k.key = lower_bound(k, q, cutoff, r);
            }
            // Farthest first, so that the nearest is visited first.
            let mut order = [0usize, 1, 2, 3];
            order.sort_unstable_by(|&a, &b| kids[b].key.total_cmp(&kids[a].key));
            for i in order {
                if kids[i].key < cutoff {
                    stack.push(kids[i]);
                }
            }
        }
        Ok(None)
    };
    index::nearest(surf, &mut visit)?;
    // Gauss-Newton polish inside the slot, kept only when closer.
    let mut e = surf.eval(best.face, best.sub, best.u, best.v)?;
    let (mut u, mut v) = (best.u, best.v);
    for _ in 0..8 {
        let r = e.p - q;
        let (g11, g12, g22) = (e.du.dot(e.du), e.du.dot(e.dv), e.dv.dot(e.dv));
        let (b1, b2) = (r.dot(e.du), r.dot(e.dv));
        let det = g11 * g22 - g12 * g12;
        if !(det > 0.0 && det.is_finite()) {
            break;
        }
        let nu = (u - (b1 * g22 - b2 * g12) / det).clamp(0.0, 1.0);
        let nv = (v - (b2 * g11 - b1 * g12) / det).clamp(0.0, 1.0);
        let ne = surf.eval(best.face, best.sub, nu, nv)?;
        if (ne.p - q).length() >= (e.p - q).length() {
            break;
        }
        (u, v, e) = (nu, nv, ne);
    }
    Ok(Closest {
        dist: (e.p - q).length(),
        face: best.face,
        sub: best.sub,
        u,
        v,
        point: e.p,
        gap: gap + 2.0 * r,
    })
}
