//! The surface-specific passes for a [`FeatureEvaluator`] (meshes with
//! creases, corners, boundaries, holes and non-manifold parts): the
//! marking of one slot's quadtree and the vertex positions. Everything
//! between them (numbering, crack elimination by side polylines, polygons,
//! triangles, counts) is the smooth path's, over the feature mesh's base
//! adjacency (see [`super::carrier`]).
//!
//! ## Cells and their bounds
//!
//! [`FeatureEvaluator::cell`] says what the surface is over a dyadic cell:
//!
//! * **polynomial** (`CellGeom::Poly`): one bicubic piece, whose exact Bezier
//!   net over the cell is converted from its B-spline grid
//!   (`bezier::net_over_points`) and then carried down by de Casteljau like
//!   the smooth path's nets; the bound is the same second-difference
//!   interpolation bound (`bezier::bound`, \[CL-R ch. 7\]), which holds for
//!   the cell's polygon with every extra point on its sides and any
//!   triangulation of it;
//! * **hull** (`CellGeom::Hull`): next to a vertex that stays irregular
//!   (crease end, corner, dart, boundary or extraordinary vertex) or before
//!   a semi-sharp value decayed, the surface over the cell lies in the
//!   convex hull of the cell's local control points (every rule with its
//!   sharp, semi-sharp and boundary variants is a convex combination). So
//!   do the exact limit points on the cell's sides, the polygon through
//!   them and any triangulation of it: both `S(x)` and `T(x)` lie in the
//!   hull and `|S(x) - T(x)| <=` its diameter
//!   ([`crate::eval::HullBound::diameter`]). This bound shrinks with the
//!   cell size, not its square: only the chain of cells at each irregular
//!   vertex goes deeper;
//! * **split** (the level-0 cell of a quad face: four level-1 patches):
//!   always split.
//!
//! ## Criteria
//!
//! Absolute flatness: accept when the bound is at most eps, as for smooth
//! meshes. Relative flatness: polynomial cells as for smooth meshes (bound
//! at most `r` times the longer diagonal of the cell's corner quad); hull
//! cells, whose bound / diagonal does not shrink with the level (the hull
//! contains the corner quad, so the ratio is at least 1), also once the
//! bound is at most `r` times the longer diagonal of the slot's corner
//! quad: the rule of the smooth path's corner cells at extraordinary
//! vertices, similarity invariant.
//!
//! ## Positions
//!
//! Every vertex is the exact limit point [`FeatureEvaluator::eval`] at its
//! dyadic parameters (with its normal), written once by its owner.

use super::cells::{Kind, CORNER, POLY, SPLIT};
use super::forest::{rec_at, Forest};
use super::mark::{child_ij, corner_uv, sides_on_boundary, too_deep, SlotId, Verdict};
use super::record::{DIAG, INDEX, OWN};
use super::scratch::{next_child, pair, Level, Scratch, LEVELS};
use super::vertices::{point_uv, Single, VertOut};
use super::{Criterion, Options, SlotMark, TOO_DEEP};
use crate::bounds::rounding;
use crate::error::Error;
use crate::eval::{CellCursor, CellGeom, FeatureEvaluator, Query};
use crate::math::bezier::{self, Net};
use glam::DVec3;

/// Kind tag of a hull cell (the smooth path's corner tag: not polynomial).
const HULL: u32 = CORNER;

/// Kind, Bezier net (polynomial cells) and bound of cell `(level, i, j)`
/// of slot `at`.
fn geom<'e>(
    fev: &FeatureEvaluator<'e, '_>,
    cursor: &mut CellCursor<'e>,
    at: SlotId,
    (level, i, j): (u32, u32, u32),
    kind: &mut Kind,
    net: &mut Net,
) -> Result<f64, Error> {
    Ok(match fev.cell_in(cursor, at.face, at.sub, level, i, j)? {
        CellGeom::Split => {
            kind.tag = SPLIT;
            f64::INFINITY
        }
        CellGeom::Poly { grid, rect } => {
            // The grid is row by row (index j * 4 + i, i along u); the net
            // conversion reads point i * 4 + j.
            *net = bezier::net_over_points(
                |k| grid[(k % 4) * 4 + k / 4],
                rect[0],
                rect[1],
                rect[2],
                rect[3],
            );
            kind.tag = POLY;
            bezier::bound(net)
        }
        CellGeom::Hull(h) => {
            kind.tag = HULL;
            h.diameter()
        }
    })
}

/// The acceptance test of one slot's cells.
struct Tester<'e> {
    fev: &'e FeatureEvaluator<'e, 'e>,
    crit: Criterion,
    at: SlotId,
    /// Relative flatness: longer diagonal of the slot's corner quad.
    slot_diag: f64,
    /// Rounding term added to every bound
    /// ([`rounding::feature_term`]).
    round: f64,
}

impl Tester<'_> {
    /// Longer diagonal of a cell's corner quad, by exact evaluation.
    fn eval_diag(&self, level: u32, i: u32, j: u32) -> f64 {
        let p: [DVec3; 4] = core::array::from_fn(|q| {
            let (u, v) = corner_uv(level, i, j, q);
            self.fev
                .eval(self.at.face, self.at.sub, u, v)
                .map(|e| e.p)
                .unwrap_or(DVec3::NAN)
        });
        (p[2] - p[0]).length().max((p[3] - p[1]).length())
    }

    /// Tests the cell (`kind`, `n`, bound `b`) at (level, i, j).
    fn test(&self, kind: &Kind, n: &Net, b: f64, (level, i, j): (u32, u32, u32)) -> Verdict {
        match self.crit {
            Criterion::Uniform(l) => Verdict {
                pass: level >= l,
                bound: f64::NAN,
                ratio: f64::NAN,
            },
            Criterion::Absolute(eps) => Verdict {
                pass: b <= eps,
                bound: b,
                ratio: f64::NAN,
            },
            Criterion::Relative(r) => {
                if kind.tag == SPLIT {
                    return Verdict {
                        pass: false,
                        bound: b,
                        ratio: f64::INFINITY,
                    };
                }
                let d = if kind.tag == POLY {
                    bezier::diagonal(n)
                } else {
                    self.eval_diag(level, i, j)
                };
                // Hull cells: b / d does not shrink with the level (module
                // docs); accepted once b <= r * (diagonal of the slot).
                let pass = b <= r * d || (kind.tag == HULL && b <= r * self.slot_diag);
                Verdict {
                    pass,
                    bound: b,
                    ratio: b / d,
                }
            }
        }
    }
}

/// The marking of one slot (as the smooth path's `Marker`).
struct Marker<'t, 'e, 'n, 'c> {
    t: &'t Tester<'e>,
    /// The local patches along the last refined path (children of hull
    /// cells refine once from their parent's patch).
    cursor: &'c mut CellCursor<'e>,
    max_level: u32,
    uniform: bool,
    eps: f64,
    nodes: Option<&'n mut [u32]>,
    next: u64,
    m: SlotMark,
}

impl Marker<'_, '_, '_, '_> {
    #[inline]
    fn store(&mut self, idx: u64, val: u64) {
        if let Some(x) = self
            .nodes
            .as_deref_mut()
            .and_then(|n| n.get_mut(idx as usize))
        {
            *x = val as u32;
        }
    }

    /// Splits node `node` (cell `kind`/`n` with bound `bound`) at
    /// (level, i, j) into `dst`: allocates and tests its children. Returns
    /// whether a child failed (`dst` then has to be walked).
    #[allow(clippy::too_many_arguments)]
    fn expand(
        &mut self,
        kind: &Kind,
        n: &Net,
        bound: f64,
        node: u32,
        (level, i, j): (u32, u32, u32),
        dst: &mut Level,
    ) -> Result<bool, Error> {
        if level >= self.max_level {
            return Err(too_deep(bound, self.t.round));
        }
        let first = self.next;
        self.next += 4;
        if self.next > super::MAX_NODES {
            return Err(super::nodes_exceeded());
        }
        self.store(node as u64, first);
        for q in 0..4 {
            self.store(first + q, 0);
        }
        self.m.side_mids += sides_on_boundary(level, i, j);
        // A polynomial cell's children have at most a quarter of its bound
        // (the smooth path's rule): accepted without their nets.
        let round = self.t.round;
        let child_bound = 0.25 * (bound - round) + round;
        if kind.tag == POLY && !self.uniform && child_bound <= self.eps {
            self.m.leaves_with(4, level + 1, child_bound);
            return Ok(false);
        }
        dst.start(node, first as u32, level, i, j);
        if !self.uniform {
            if kind.tag == POLY {
                bezier::split4(n, &mut dst.nets);
                dst.kinds = [*kind; 4];
                dst.bounds = bezier::bound4(&dst.nets).map(|b| b + round);
            } else {
                for q in 0..4 {
                    let (ci, cj) = child_ij(i, j, q);
                    dst.bounds[q] = geom(
                        self.t.fev,
                        self.cursor,
                        self.t.at,
                        (level + 1, ci, cj),
                        &mut dst.kinds[q],
                        &mut dst.nets[q],
                    )? + round;
                }
            }
        }
        for q in 0..4 {
            let (ci, cj) = child_ij(i, j, q);
            let v = self.t.test(
                &dst.kinds[q],
                &dst.nets[q],
                dst.bounds[q],
                (level + 1, ci, cj),
            );
            if v.pass {
                self.m.leaf(level + 1, &v);
            } else {
                dst.internal |= 1 << q;
            }
        }
        Ok(dst.internal != 0)
    }
}

/// Builds the quadtree of slot `at` of `fev` into `nodes` (the format and
/// preorder of the smooth path's `mark`: entry = local index of the first
/// of the node's four children, 0 for a leaf), or only counts when
/// `nodes` is `None` or too short.
pub(crate) fn mark_feature(
    fev: &FeatureEvaluator,
    opts: &Options,
    at: SlotId,
    nodes: Option<&mut [u32]>,
    scratch: &mut Scratch,
) -> Result<SlotMark, Error> {
    opts.validate()?;
    let mut t = Tester {
        fev,
        crit: opts.criterion,
        at,
        slot_diag: 0.0,
        round: 0.0,
    };
    let uniform = matches!(opts.criterion, Criterion::Uniform(_));
    if !uniform {
        t.round = rounding::feature_term(fev, at.face, at.sub)?;
    }
    if let Criterion::Relative(_) = opts.criterion {
        t.slot_diag = t.eval_diag(0, 0, 0);
    }
    // One cursor per slot (about 130 KiB on the stack of this feature-only
    // function; filling it is far cheaper than one slot's marking).
    let mut cursor = CellCursor::new();
    let mut mk = Marker {
        t: &t,
        cursor: &mut cursor,
        max_level: opts.max_level,
        uniform,
        eps: match opts.criterion {
            Criterion::Absolute(e) => e,
            _ => f64::NAN,
        },
        nodes,
        next: 1,
        m: SlotMark {
            nodes: 1,
            ..SlotMark::default()
        },
    };
    mk.store(0, 0);
    let mut kind = Kind::default();
    let mut net = [0.0; 48];
    let b = if uniform {
        f64::NAN
    } else {
        geom(fev, mk.cursor, at, (0, 0, 0), &mut kind, &mut net)? + t.round
    };
    let v = t.test(&kind, &net, b, (0, 0, 0));
    if v.pass {
        mk.m.leaf(0, &v);
        return Ok(mk.m);
    }
    let lv = &mut scratch.levels;
    if !mk.expand(&kind, &net, b, 0, (0, 0, 0), &mut lv[0])? {
        mk.m.nodes = mk.next as u32;
        return Ok(mk.m);
    }
    let mut l = 0usize;
    while let Some(q) = next_child(lv, &mut l) {
        if lv[l].internal & (1 << q) == 0 {
            continue;
        }
        if l + 1 >= LEVELS {
            return Err(Error::InvalidArgument(TOO_DEEP));
        }
        let (p, dst) = pair(lv, l);
        let (ci, cj) = child_ij(p.i, p.j, q);
        let walk = mk.expand(
            &p.kinds[q],
            &p.nets[q],
            p.bounds[q],
            p.first + q as u32,
            (p.level + 1, ci, cj),
            dst,
        )?;
        l += walk as usize;
    }
    mk.m.nodes = mk.next as u32;
    Ok(mk.m)
}

/// Writes every vertex's position, normal and parameters at the index the
/// numbering gave it: each one's owner (slot corner or node record with
/// [`OWN`]) evaluates it exactly. The bottom nodes' cuts ([`DIAG`]) are
/// left unknown: the polygon pass chooses them from the positions.
pub(crate) fn feature_positions<S: Single>(
    f: &Forest,
    fev: &FeatureEvaluator,
    recs: &mut [u32],
    corners: &[u32],
    scratch: &mut Scratch,
    out: &mut VertOut<S>,
) -> Result<(), Error> {
    let lv = &mut scratch.levels;
    for s in 0..f.num_slots() {
        let (face, sub) = f.topo.face_sub(s);
        let write = |out: &mut VertOut<S>, e: u32, (u, v): (f64, f64)| -> Result<(), Error> {
            if e & OWN == 0 {
                return Ok(());
            }
            let x = fev.eval(face, sub, u, v)?;
            out.put(e & INDEX, x.p, x.normal, || Query { face, sub, u, v })
        };
        for q in 0..4 {
            write(out, corners[4 * s + q], corner_uv(0, 0, 0, q))?;
        }
        let tree = f.tree(s);
        let c0 = tree[0];
        if c0 == 0 {
            continue;
        }
        let rbase = f.rec(s, 1);
        let mut node = |out: &mut VertOut<S>, lev: &Level| -> Result<(), Error> {
            let r = 5 * rec_at(rbase, lev.first);
            let rec = recs
                .get_mut(r..r + 5)
                .ok_or(Error::InvalidArgument("internal: node records"))?;
            rec[0] &= !DIAG;
            for (which, &e) in rec.iter().enumerate() {
                write(out, e, point_uv(lev.level, lev.i, lev.j, which))?;
            }
            Ok(())
        };
        lv[0].start(0, c0, 0, 0, 0);
        node(out, &lv[0])?;
        let mut l = 0usize;
        while let Some(q) = next_child(lv, &mut l) {
            let c = tree[(lv[l].first + q as u32) as usize];
            if c == 0 {
                continue;
            }
            if l + 1 >= LEVELS {
                return Err(Error::InvalidArgument(TOO_DEEP));
            }
            let (p, dst) = pair(lv, l);
            let (ci, cj) = child_ij(p.i, p.j, q);
            dst.start(p.first + q as u32, c, p.level + 1, ci, cj);
            node(out, dst)?;
            l += 1;
        }
    }
    Ok(())
}
