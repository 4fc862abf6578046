//! The cells of a [`FeatureEvaluator`] (creases, corners, semi-sharp
//! edges, boundaries, holes, non-manifold parts) for the queries.
//!
//! A cell is what [`FeatureEvaluator::cell`] says the surface is over it
//! (\[OSD\]; `eval/feature_cell.rs`):
//!
//! * [`CellGeom::Poly`]: one bicubic piece; the cell carries its exact
//!   Bezier net (`math::bezier::net_over_points`, positions relative to an
//!   offset for precision) and its children are de Casteljau halves, with
//!   no further call to the evaluator;
//! * [`CellGeom::Hull`]: the surface lies in the convex hull of the cell's
//!   control points ([`Bound::Hull`]: their box and ball); children ask the
//!   evaluator again, down to [`MAX_CELL_LEVEL`], the walks' depth limit
//!   for these cells ([`CellSurface::at_floor`]);
//! * [`CellGeom::Split`]: the level-0 cell of a quad face, no bound.
//!
//! Hole faces have no sub-faces here (no surface). Open meshes (boundary
//! edges, holes, non-manifold edges or vertices) answer rays and closest
//! points; [`CellSurface::check_solid`] refuses them for inside/outside
//! and slices ([`Error::NotClosedSolid`]).

use super::cell::{Bound, Cell, CellSurface, QUADRANT};
use crate::error::Error;
use crate::eval::{CellGeom, FeatureEvaluator, MAX_CELL_LEVEL};
use crate::math::bezier;
use crate::math::Eval;
use glam::DVec3;

/// `tag[0]` of a cell: no bound (split it).
const SPLIT: u32 = 0;
/// `tag[0]` of a cell: a polynomial piece (children by de Casteljau).
const POLY: u32 = 1;
/// `tag[0]` of a cell: a hull cell (children from the evaluator).
const HULL: u32 = 2;
/// `tag[0]` of a cell the evaluator refused (capacity): not split.
const REFUSED: u32 = 3;

/// The query cell of `(face, sub)` at `(level, i, j)` from the evaluator's
/// answer.
fn cell_of(fe: &FeatureEvaluator, face: u32, sub: u32, level: u32, i: u64, j: u64) -> Cell {
    let mut c = Cell {
        face,
        sub,
        level,
        i,
        j,
        ..Cell::ZERO
    };
    let geom = if level <= MAX_CELL_LEVEL {
        fe.cell(face, sub, level, i as u32, j as u32)
    } else {
        Err(Error::InvalidArgument("cell level"))
    };
    match geom {
        Ok(CellGeom::Poly { grid, rect }) => {
            // Relative to an inner control point (rounding scales with the
            // piece, not with its distance from the origin).
            let off = grid[5];
            // net_over_points reads point `i * 4 + j` (i along u); the grid
            // is row by row (`j * 4 + i`).
            c.net = bezier::net_over_points(
                |k| grid[(k % 4) * 4 + k / 4] - off,
                rect[0],
                rect[1],
                rect[2],
                rect[3],
            );
            c.off = off;
            c.bound = Bound::Net;
            c.tag[0] = POLY;
        }
        Ok(CellGeom::Hull(h)) => {
            c.bound = Bound::Hull {
                lo: h.lo,
                hi: h.hi,
                radius: h.radius,
            };
            c.tag[0] = HULL;
        }
        // The level-0 cell of a quad face.
        Ok(CellGeom::Split) => {
            c.bound = Bound::None;
            c.tag[0] = SPLIT;
        }
        // Refused (capacity): no bound, and the walks stop at it.
        Err(_) => {
            c.bound = Bound::None;
            c.tag[0] = REFUSED;
        }
    }
    c
}

impl CellSurface for FeatureEvaluator<'_, '_> {
    fn faces(&self) -> usize {
        self.num_faces()
    }
    fn subfaces(&self, f: usize) -> usize {
        let fm = self.mesh();
        if fm.hole[fm.child_face(f, 0)] != 0 {
            0
        } else {
            self.num_subfaces(f)
        }
    }
    fn root(&self, face: u32, sub: u32) -> Cell {
        cell_of(self, face, sub, 0, 0, 0)
    }
    fn split(&self, c: &Cell, out: &mut [Cell; 4]) {
        if c.tag[0] == POLY {
            let mut nets = [[0.0; 48]; 4];
            bezier::split4(&c.net, &mut nets);
            for q in 0..4 {
                let (di, dj) = QUADRANT[q];
                out[q] = Cell {
                    level: c.level + 1,
                    i: 2 * c.i + di,
                    j: 2 * c.j + dj,
                    net: nets[q],
                    key: 0.0,
                    ..*c
                };
            }
            return;
        }
        for q in 0..4 {
            let (di, dj) = QUADRANT[q];
            let (l, i, j) = (c.level + 1, 2 * c.i + di, 2 * c.j + dj);
            out[q] = cell_of(self, c.face, c.sub, l, i, j);
        }
    }
    fn at_floor(&self, c: &Cell) -> bool {
        (c.tag[0] == HULL && c.level >= MAX_CELL_LEVEL) || c.tag[0] == REFUSED
    }
    fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        FeatureEvaluator::eval(self, face, sub, u, v)
    }
    fn check_solid(&self) -> Result<(), Error> {
        crate::voxel::solid::check_closed_solid(self.mesh())
    }
    /// Over the level-1 control points: every rule is a convex
    /// combination, so every cached grid, hull and limit point lies in
    /// their range.
    fn magnitude(&self) -> f64 {
        super::rounding::max_abs(self.mesh().points)
    }
}

/// A point of the surface over a hull cell: the exact limit point at the
/// cell's centre (an upper bound for the closest-point search).
pub(crate) fn hull_point<S: CellSurface + ?Sized>(surf: &S, c: &Cell) -> Option<DVec3> {
    let (u, v) = c.param(0.5, 0.5);
    surf.eval(c.face, c.sub, u, v).ok().map(|e| e.p)
}
