//! Cell access for the queries: the dyadic cells of every slot `(face,
//! sub)` with a guaranteed bound of the surface over each, and the four
//! children of a cell, behind the small trait [`CellSurface`] so that a
//! second surface type can be plugged in.
//!
//! For the smooth closed [`Evaluator`] the cells are those of the
//! tessellation's quadtree (`tessellate::cells`, \[CL-R ch. 7\]): a
//! polynomial cell carries its bicubic Bezier net in the slot frame (the
//! surface over the cell lies in the net's convex hull), the corner cell
//! `[0, 2^-k]^2` of an extraordinary patch carries the ball of radius
//! [`crate::eigen::ValenceTable::corner_radius`] around the limit point
//! (every limit point of the cell lies in it, \[CL-R ch. 7\]), and the
//! level-0 cell of an internally split slot carries no bound (it is always
//! split).

use crate::error::Error;
use crate::eval::Evaluator;
use crate::math::bezier::{self, Net};
use crate::math::Eval;
use crate::tessellate::cells::{self as tc, Kind, CORNER, POLY};
use glam::DVec3;

/// What is known of the surface over a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// The surface over the cell is the bicubic of `net + off` (cell
    /// coordinates `[0, 1]^2`, slot orientation).
    Net,
    /// Every point of the cell is within `radius` of `center`, an exact
    /// limit point at the cell's corner `corner` (0: (0,0), 1: (1,0),
    /// 2: (1,1), 3: (0,1)).
    Ball {
        center: DVec3,
        radius: f64,
        corner: u8,
        /// The eigen expansion's radius alone (at least `radius`): the
        /// slicer joins contours through a ball only once this one is
        /// below `eps / 2` (a coarser ball can hold several arcs).
        eigen: f64,
    },
    /// Every point of the cell lies in the box `[lo, hi]` and within
    /// `radius` of the box centre (the convex hull of a feature cell's
    /// control points, [`crate::eval::HullBound`]); no point of the cell
    /// is known exactly.
    Hull { lo: DVec3, hi: DVec3, radius: f64 },
    /// No bound: the cell must be split.
    None,
}

/// A dyadic cell `[i/2^level, (i+1)/2^level] x [j/2^level, (j+1)/2^level]`
/// of slot `(face, sub)`, with its bound.
#[derive(Clone, Copy)]
pub struct Cell {
    pub face: u32,
    pub sub: u32,
    pub level: u32,
    pub i: u64,
    pub j: u64,
    pub bound: Bound,
    /// Surface-specific words (the evaluator's cell kind).
    pub tag: [u32; 4],
    /// The Bezier net (valid for [`Bound::Net`]); positions are `net + off`.
    pub net: Net,
    pub off: DVec3,
    /// The walk's sort key (a bound it computed when it made the cell).
    pub key: f64,
}

impl Cell {
    /// A cell that holds nothing (the stack's filler).
    pub const ZERO: Cell = Cell {
        face: 0,
        sub: 0,
        level: 0,
        i: 0,
        j: 0,
        bound: Bound::None,
        tag: [0; 4],
        net: [0.0; 48],
        off: DVec3::ZERO,
        key: 0.0,
    };

    /// Side `2^-level` of the cell in slot parameters.
    #[inline]
    pub fn size(&self) -> f64 {
        libm::scalbn(1.0, -(self.level as i32))
    }

    /// Slot parameters of the cell point with cell coordinates `(s, t)`.
    #[inline]
    pub fn param(&self, s: f64, t: f64) -> (f64, f64) {
        let h = self.size();
        let u = (self.i as f64 + s) * h;
        let v = (self.j as f64 + t) * h;
        (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
    }

    /// Control point `k` of the net with the offset.
    #[inline]
    pub fn point(&self, k: usize) -> DVec3 {
        bezier::point(&self.net, k) + self.off
    }

    /// Guaranteed axis-aligned box of the surface over the cell (infinite
    /// for [`Bound::None`]).
    pub fn aabb(&self) -> (DVec3, DVec3) {
        match self.bound {
            Bound::Net => {
                let (lo, hi) = bezier::net_box(&self.net);
                (lo + self.off, hi + self.off)
            }
            Bound::Ball { center, radius, .. } => {
                (center - DVec3::splat(radius), center + DVec3::splat(radius))
            }
            Bound::Hull { lo, hi, .. } => (lo, hi),
            Bound::None => (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
        }
    }
}

/// Cell corner `q` as `(di, dj)` offsets: quadrant `q` of a cell is its
/// child `(2i + di, 2j + dj)` (quadrant order of [`bezier::split4`]).
pub(crate) const QUADRANT: [(u64, u64); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// A surface the queries walk: slots, root cells, children, exact
/// evaluation. Implemented for the smooth closed [`Evaluator`] here and for
/// the [`crate::eval::FeatureEvaluator`] (creases, corners, boundaries,
/// holes) in `feature.rs`.
pub trait CellSurface {
    /// Number of base faces.
    fn faces(&self) -> usize;
    /// Number of sub-faces (slots) of base face `f`.
    fn subfaces(&self, f: usize) -> usize;
    /// The level-0 cell of slot `(face, sub)`.
    fn root(&self, face: u32, sub: u32) -> Cell;
    /// The four children of `c` in quadrant order, parameters included.
    fn split(&self, c: &Cell, out: &mut [Cell; 4]);
    /// Exact position, derivatives and normal at `(face, sub, u, v)`.
    fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error>;
    /// Whether `c` cannot be split into smaller bounds (a feature hull cell
    /// at the evaluator's deepest level): the walks treat it as their depth
    /// limit.
    fn at_floor(&self, _c: &Cell) -> bool {
        false
    }
    /// Ok if the surface bounds a solid (inside/outside and slices need
    /// one), else [`Error::NotClosedSolid`] naming the defect.
    fn check_solid(&self) -> Result<(), Error>;
    /// Largest coordinate magnitude of the control data every cell is made
    /// from (NaN if some value is NaN): the `M` of the rounding term
    /// (`rounding.rs`). Linear in the mesh size.
    fn magnitude(&self) -> f64;
    /// The slot index the walks may use to skip slots (`index.rs`); none
    /// unless the surface is an `Indexed` (`index.rs`).
    fn index(&self) -> Option<&super::slots::SlotIndex<'_>> {
        None
    }
}

fn kind_of(tag: [u32; 4]) -> Kind {
    Kind {
        tag: tag[0],
        patch: tag[1],
        rho: tag[2],
        k: tag[3],
    }
}

fn tag_of(k: &Kind) -> [u32; 4] {
    [k.tag, k.patch, k.rho, k.k]
}

/// Corner levels below which a corner ball also tries the control-point
/// hull ([`crate::eigen::ValenceTable::corner_hull_radius`], about 600
/// multiply-adds): level 0 only, the root ball of every extraordinary
/// patch (and so the slot index's boxes). Instructions of `ccss bench
/// query` (100 closest points / 300 first hits, whole process) with the
/// hull at no level, levels 0, 0-1, 0-2: righthanded 955 / 753 / 766 /
/// 773 M and 2,583 / 1,703 / 1,720 / 1,744 M; toroidal_tet 655 / 683 / 696
/// / 702 M and 1,082 / 1,214 / 1,240 / 1,238 M; cube 409 / 423 / 426 / 428
/// M and 488 / 523 / 508 / 513 M. Deeper levels cost more than they save.
const HULL_LEVELS: u32 = 1;

/// The bound of an evaluator cell of kind `k`.
fn bound_of(ev: &Evaluator, k: &Kind) -> Bound {
    match k.tag {
        POLY => Bound::Net,
        CORNER => match ev.ev_patch(k.patch as usize) {
            Some((tab, lay)) => match ev.data.get(lay.ghat()) {
                Some(ghat) if ghat.len() >= 3 => {
                    let center = DVec3::new(ghat[0], ghat[1], ghat[2]);
                    // The eigen ball, or at the first levels the smaller
                    // ball of the region's control points.
                    let eigen = tab.corner_radius(ghat, k.k);
                    let mut radius = eigen;
                    if k.k < HULL_LEVELS {
                        radius = radius.min(tab.corner_hull_radius(ghat, k.k));
                    }
                    Bound::Ball {
                        center,
                        radius,
                        corner: (k.rho & 3) as u8,
                        eigen,
                    }
                }
                _ => Bound::None,
            },
            None => Bound::None,
        },
        _ => Bound::None,
    }
}

impl CellSurface for Evaluator<'_> {
    fn faces(&self) -> usize {
        self.num_faces()
    }
    fn subfaces(&self, f: usize) -> usize {
        self.num_subfaces(f)
    }
    fn root(&self, face: u32, sub: u32) -> Cell {
        let slot = self.slot_start(face as usize) + sub as usize;
        let c = tc::root(self, slot);
        Cell {
            face,
            sub,
            level: 0,
            i: 0,
            j: 0,
            bound: bound_of(self, &c.kind),
            tag: tag_of(&c.kind),
            net: c.net,
            off: c.off,
            key: 0.0,
        }
    }
    fn split(&self, c: &Cell, out: &mut [Cell; 4]) {
        let mut kinds = [Kind::default(); 4];
        let mut nets = [[0.0; 48]; 4];
        let mut offs = [[0.0; 3]; 4];
        tc::expand(
            self,
            &kind_of(c.tag),
            &c.net,
            c.off.to_array(),
            &mut kinds,
            &mut nets,
            &mut offs,
        );
        for q in 0..4 {
            let (di, dj) = QUADRANT[q];
            out[q] = Cell {
                face: c.face,
                sub: c.sub,
                level: c.level + 1,
                i: 2 * c.i + di,
                j: 2 * c.j + dj,
                bound: bound_of(self, &kinds[q]),
                tag: tag_of(&kinds[q]),
                net: nets[q],
                off: DVec3::from_array(offs[q]),
                key: 0.0,
            };
        }
    }
    fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        Evaluator::eval(self, face, sub, u, v)
    }
    /// A [`crate::mesh::Topology`] is closed, oriented and manifold.
    fn check_solid(&self) -> Result<(), Error> {
        Ok(())
    }
    /// Over every patch: its B-spline grid, or its `2n + 8` control
    /// points and limit point.
    fn magnitude(&self) -> f64 {
        let mut m = 0.0f64;
        for pi in 0..self.patch_meta.len() {
            let x = crate::bounds::rounding::patch_magnitude(self, pi);
            if x.is_nan() {
                return f64::NAN;
            }
            m = m.max(x);
        }
        m
    }
}

/// Deepest cell level the queries split to (slot parameters keep their
/// dyadic cells exact down to `2^-60`).
pub const MAX_LEVEL: u32 = 60;

/// Cells a depth-first walk keeps pending: four children per split give at
/// most `3 * MAX_LEVEL + 4`.
pub(crate) const STACK_CAP: usize = 3 * MAX_LEVEL as usize + 8;

/// An explicit stack of cells (no machine recursion).
pub(crate) struct CellStack {
    cells: [Cell; STACK_CAP],
    len: usize,
}

impl CellStack {
    pub const ZERO: CellStack = CellStack {
        cells: [Cell::ZERO; STACK_CAP],
        len: 0,
    };
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
    }
    #[inline]
    pub fn pop(&mut self) -> Option<Cell> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.cells[self.len])
    }
    /// Pushes `c`; false (nothing pushed) when full.
    #[inline]
    pub fn push(&mut self, c: Cell) -> bool {
        if self.len >= STACK_CAP {
            return false;
        }
        self.cells[self.len] = c;
        self.len += 1;
        true
    }
    /// Number of pending cells.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }
    /// Room for `n` more cells.
    #[inline]
    pub fn room(&self, n: usize) -> bool {
        self.len + n <= STACK_CAP
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::eigen::{BuildScratch, TableSet};
    use crate::eval::evaluator::corner_flatness_tests::with_evaluator;
    use std::boxed::Box;

    /// The corner balls of extraordinary patches, and the control-point
    /// hull's balls at every level, hold dense exact limit points of their
    /// cells (17 x 17 per cell, levels 0 to 5 of every slot of
    /// righthanded); the radius used is the smaller of the eigen
    /// radius and the level's control-point hull's below
    /// [`HULL_LEVELS`] (the hull is the smaller in over 100 of those).
    #[test]
    #[cfg_attr(miri, ignore = "dense sampling: minutes under Miri")]
    fn corner_balls_hold_dense_points() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let (p, idx) = crate::tessellate::cells::tests::righthanded();
        with_evaluator(&ts, &p, &idx, |ev| {
            let (mut balls, mut hull_wins, mut worst) = (0usize, 0usize, 0.0f64);
            for f in 0..ev.faces() {
                for s in 0..ev.subfaces(f) {
                    let mut st = std::vec![ev.root(f as u32, s as u32)];
                    while let Some(c) = st.pop() {
                        if let Bound::Ball { center, radius, .. } = c.bound {
                            let k = kind_of(c.tag);
                            let (tab, lay) = ev.ev_patch(k.patch as usize).unwrap();
                            let ghat = ev.data.get(lay.ghat()).unwrap();
                            let eig = tab.corner_radius(ghat, k.k);
                            let hull = tab.corner_hull_radius(ghat, k.k);
                            if k.k < HULL_LEVELS {
                                assert_eq!(radius, eig.min(hull));
                                hull_wins += (hull < eig) as usize;
                            } else {
                                assert_eq!(radius, eig);
                            }
                            balls += 1;
                            for a in 0..=16 {
                                for b in 0..=16 {
                                    let (u, v) = c.param(a as f64 / 16.0, b as f64 / 16.0);
                                    let e = ev.eval(c.face, c.sub, u, v).unwrap();
                                    let d = (e.p - center).length();
                                    assert!(d <= radius, "level {}: {d} > {radius}", c.level);
                                    assert!(d <= hull, "level {}: {d} > hull {hull}", c.level);
                                    worst = worst.max(d / radius);
                                }
                            }
                        }
                        if c.level < 5 {
                            let mut kids = [Cell::ZERO; 4];
                            ev.split(&c, &mut kids);
                            st.extend(kids);
                        }
                    }
                }
            }
            std::println!("{balls} balls, hull radius smaller in {hull_wins}, tightness {worst}");
            assert!(balls > 500 && hull_wins > 100);
        });
    }

    /// Every cell's bound holds the exact limit points at its corners and
    /// centre (net corners agree with evaluation), over three levels of
    /// every slot of the righthanded model (valences 3, 4, 5).
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn cells_bound_their_points() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let (p, idx) = crate::tessellate::cells::tests::righthanded();
        with_evaluator(&ts, &p, &idx, |ev| {
            let mut n = 0;
            for f in 0..ev.faces() {
                for s in 0..ev.subfaces(f) {
                    let mut st = std::vec![ev.root(f as u32, s as u32)];
                    while let Some(c) = st.pop() {
                        let (lo, hi) = c.aabb();
                        let slack = 1e-12 * (1.0 + lo.abs().max(hi.abs()).max_element());
                        for (a, b) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5)] {
                            let (u, v) = c.param(a, b);
                            let e = ev.eval(c.face, c.sub, u, v).unwrap();
                            assert!(
                                e.p.cmpge(lo - slack).all() && e.p.cmple(hi + slack).all(),
                                "cell {} {} {} {} {}",
                                c.face,
                                c.sub,
                                c.level,
                                c.i,
                                c.j
                            );
                            n += 1;
                        }
                        if c.bound == Bound::Net {
                            for q in 0..4 {
                                let (u, v) = c.param(QUADRANT[q].0 as f64, QUADRANT[q].1 as f64);
                                let e = ev.eval(c.face, c.sub, u, v).unwrap();
                                let d = (e.p - c.point(bezier::CORNER_POINT[q])).length();
                                assert!(d < 1e-12, "net corner {d}");
                            }
                        }
                        if c.level < 3 {
                            let mut kids = [Cell::ZERO; 4];
                            ev.split(&c, &mut kids);
                            st.extend(kids);
                        }
                    }
                }
            }
            assert!(n > 10000);
        });
    }
}
