//! Marking: the quadtree of one slot, built top down with an explicit stack
//! (the paper's AdaptiveMarking), and the uniform-level check.
//!
//! A cell is split while it fails the acceptance test ([`Tester`]). Bounds
//! are those of [`crate::bounds::cell`] (see the parent module), computed here
//! from Bezier nets carried down the tree by de Casteljau subdivision.
//!
//! Absolute flatness skips provably passing tests: for a polynomial cell the
//! Bezier nets of the second derivatives of its quadrants are convex
//! combinations of its own, scaled by 1/4 (the quadrant's parameter is
//! twice as fast), so each of `a, b, c` of a child is at most a quarter of
//! the parent's and so is `lambda_max([[a, c], [c, b]]) / 3`. When a
//! polynomial cell fails with bound `B <= 4 eps`, its children are accepted
//! with bound `B / 4` without computing theirs.
//!
//! Likewise at extraordinary vertices: the three ring-region children of a
//! corner cell `[0, 2^-k]^2` have Bezier nets `sum_c mu_c^k ghat_c
//! Bez(X_b[c])`, whose second differences are bounded by per-column table
//! constants ([`crate::eigen::ValenceTable::ring_terms`]; the evaluator keeps the
//! resulting bound per level). When that bound meets eps the split is
//! *light* ([`cells::light_split`]): the three children are accepted with
//! it, their nets are never made, only the corner child is tested, and the
//! split's five points are saved from the eigen expansion directly
//! ([`cells::store_corner_light`]). At righthanded's corner cells the ring
//! bound is 1.15 to 22 times the largest of the three nets' own bounds
//! (mean 1.6; the unit test in `cells.rs` prints it), so a split whose
//! children pass by less than that margin takes the full path.
//!
//! With a tolerance field (`field.rs`) each cell's `eps` is `min(eps,
//! field(box))`; the quarter rule and light splits use the parent's,
//! which is at most the children's (the field is monotone).

use super::cells::{self, Cell, Kind, CORNER, POLY, SPLIT};
use super::field::{net_box, ToleranceField, EVERYWHERE};
use super::scratch::{next_child, pair, Level, Scratch};
use super::{Criterion, Options, SlotMark, TOO_DEEP};
use crate::bounds::rounding;
use crate::error::Error;
use crate::eval::Evaluator;
use crate::math::bezier::{self, Net};
use core::cell::Cell as Memo;
use glam::DVec3;

/// Where a slot is: its index and (face, sub-face).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlotId {
    pub slot: usize,
    pub face: u32,
    pub sub: u32,
}

/// Offset of quadrant (or corner) `q` in cells: 0 (0, 0), 1 (1, 0),
/// 2 (1, 1), 3 (0, 1); by arithmetic, not a table the compiler may
/// rebuild on the stack at every call.
#[inline(always)]
pub(crate) fn quadrant_offset(q: usize) -> (u32, u32) {
    let q = (q & 3) as u32;
    (((q + 1) >> 1) & 1, q >> 1)
}

/// `2^-level`, exact (the exponent bits for the levels of a quadtree).
#[inline(always)]
pub(crate) fn cell_size(level: u32) -> f64 {
    if level < 1023 {
        f64::from_bits(((1023 - level) as u64) << 52)
    } else {
        libm::scalbn(1.0, -(level as i32))
    }
}

/// Slot coordinates of a cell corner, exact.
#[inline]
pub(crate) fn corner_uv(level: u32, i: u32, j: u32, q: usize) -> (f64, f64) {
    let (di, dj) = quadrant_offset(q);
    let s = cell_size(level);
    ((i + di) as f64 * s, (j + dj) as f64 * s)
}

/// The acceptance test of the cells of one slot.
pub(crate) struct Tester<'e> {
    ev: &'e Evaluator<'e>,
    crit: Criterion,
    at: SlotId,
    /// Relative flatness: longer diagonal of the slot's corner quad.
    slot_diag: f64,
    /// Rounding term added to every bound ([`rounding::term`] of the slot's
    /// control data; infinite if out of range).
    pub round: f64,
    /// Extraordinary-vertex points evaluated so far (slot coordinates as
    /// bits, point): every corner cell at that vertex has it as a corner.
    ev_points: Memo<[(u64, u64, DVec3); 4]>,
    ev_count: Memo<usize>,
}

/// Outcome of a test: accepted?, bound (model units), bound / diagonal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Verdict {
    pub pass: bool,
    pub bound: f64,
    pub ratio: f64,
}

impl<'e> Tester<'e> {
    pub fn new(ev: &'e Evaluator<'e>, crit: Criterion, at: SlotId) -> Self {
        Self::with_round(
            ev,
            crit,
            at,
            slot_round(ev, at.slot).unwrap_or(f64::INFINITY),
        )
    }

    /// [`Tester::new`] with the slot's rounding term already computed
    /// ([`slot_round`], infinite if out of range): the marking checks the
    /// range first and passes the term on instead of computing it twice.
    pub fn with_round(ev: &'e Evaluator<'e>, crit: Criterion, at: SlotId, round: f64) -> Self {
        let mut t = Tester {
            ev,
            crit,
            at,
            slot_diag: 0.0,
            round,
            ev_points: Memo::new([(0, 0, DVec3::ZERO); 4]),
            ev_count: Memo::new(0),
        };
        if let Criterion::Relative(_) = crit {
            t.slot_diag = t.eval_diag(0, 0, 0, 4, None);
        }
        t
    }

    /// The limit point at slot coordinates (u, v).
    fn point(&self, u: f64, v: f64) -> DVec3 {
        self.ev
            .eval_derivs(self.at.face, self.at.sub, u, v)
            .map(|e| e.p)
            .unwrap_or(DVec3::NAN)
    }

    /// Longer diagonal of the corner quad of a cell, by exact evaluation.
    /// Corner `ev` (0..4; 4: none) is an extraordinary vertex, evaluated
    /// once per slot and remembered (the same value: evaluation is a pure
    /// function of its arguments). With `ring`, corner `ev + b` is
    /// `ring[b - 1]` (see [`Tester::test_at`]).
    fn eval_diag(&self, level: u32, i: u32, j: u32, ev: usize, ring: Option<&[DVec3; 3]>) -> f64 {
        let mut p = [DVec3::ZERO; 4];
        for (q, pq) in p.iter_mut().enumerate() {
            if q != ev {
                *pq = match ring {
                    Some(r) => r[((q + 4 - ev) & 3) - 1],
                    None => {
                        let (u, v) = corner_uv(level, i, j, q);
                        self.point(u, v)
                    }
                };
                continue;
            }
            let (u, v) = corner_uv(level, i, j, q);
            let key = (u.to_bits(), v.to_bits());
            let mut known = self.ev_points.get();
            let n = self.ev_count.get();
            match known[..n].iter().find(|e| (e.0, e.1) == key) {
                Some(e) => *pq = e.2,
                None => {
                    *pq = self.point(u, v);
                    if n < known.len() {
                        known[n] = (key.0, key.1, *pq);
                        self.ev_points.set(known);
                        self.ev_count.set(n + 1);
                    }
                }
            }
        }
        (p[2] - p[0]).length().max((p[3] - p[1]).length())
    }

    /// The bound of a cell (infinite for SPLIT), rounding term included.
    #[inline]
    pub fn bound(&self, kind: &Kind, n: &Net) -> f64 {
        match kind.tag {
            POLY => bezier::bound(n) + self.round,
            CORNER => cells::corner_bound(self.ev, kind) + self.round,
            _ => f64::INFINITY,
        }
    }

    /// Whether a corner cell's bound covers every triangle with vertices in
    /// its region for this criterion (absolute: `bound <= eps`; relative:
    /// the corner rule `bound <= r * slot diagonal`).
    pub fn corner_settled(&self, kind: &Kind, n: &Net, level: u32, i: u32, j: u32) -> bool {
        match self.crit {
            Criterion::Absolute(_) => self.test(kind, n, level, i, j).pass,
            Criterion::Relative(r) => self.bound(kind, n) <= r * self.slot_diag,
            Criterion::Uniform(_) => false,
        }
    }

    /// Tests the cell (`kind`, `n`) at (level, i, j).
    pub fn test(&self, kind: &Kind, n: &Net, level: u32, i: u32, j: u32) -> Verdict {
        self.test_at(kind, n, level, i, j, None)
    }

    /// As [`Tester::test`]; for a corner cell `ring` may give the limit
    /// points at its corners other than the extraordinary vertex (as
    /// [`cells::expand_ex`] makes them: `ring[b - 1]` at cell-local corner
    /// `rho + b`), which are then not evaluated again.
    pub fn test_at(
        &self,
        kind: &Kind,
        n: &Net,
        level: u32,
        i: u32,
        j: u32,
        ring: Option<&[DVec3; 3]>,
    ) -> Verdict {
        let b = match self.crit {
            Criterion::Uniform(_) => f64::NAN,
            _ => self.bound(kind, n),
        };
        self.test_bound(kind, n, level, i, j, ring, b)
    }

    /// As [`Tester::test_at`], with the cell's bound `b` ([`Tester::bound`];
    /// not used by the uniform criterion) already known.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn test_bound(
        &self,
        kind: &Kind,
        n: &Net,
        level: u32,
        i: u32,
        j: u32,
        ring: Option<&[DVec3; 3]>,
        b: f64,
    ) -> Verdict {
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
                    self.eval_diag(level, i, j, kind.rho as usize, ring)
                };
                let ratio = b / d;
                // Corner cells: the interpolation error of the
                // characteristic map is proportional to the cell size, so
                // b / d does not decrease with the level; such a cell is
                // accepted once b <= R * (diagonal of the slot).
                let pass = b <= r * d || (kind.tag == CORNER && b <= r * self.slot_diag);
                Verdict {
                    pass,
                    bound: b,
                    ratio,
                }
            }
        }
    }
}

/// The rounding term of the bounds of `slot` ([`rounding::term`] of the
/// largest coordinate magnitude of its patches' control data).
pub(crate) fn slot_round(ev: &Evaluator, slot: usize) -> Result<f64, Error> {
    rounding::term(rounding::slot_magnitude(ev, slot))
}

/// The error of a cell that still fails at the deepest level: the
/// coordinate range when the rounding term is at least half its bound (the
/// tolerance is below what the coordinates' precision can certify), else
/// "too deep" (module docs of [`crate::bounds::rounding`]).
pub(crate) fn too_deep(bound: f64, round: f64) -> Error {
    if round >= 0.5 * bound || !round.is_finite() {
        Error::CoordinateRange(
            "the tolerance is below the rounding of the coordinates (a tiny model far from \
             the origin, or sizes near the f64 limits)",
        )
    } else {
        Error::InvalidArgument(TOO_DEEP)
    }
}

/// Cell indices of quadrant `q` of cell (i, j).
#[inline]
pub(crate) fn child_ij(i: u32, j: u32, q: usize) -> (u32, u32) {
    let (di, dj) = quadrant_offset(q);
    (2 * i + di, 2 * j + dj)
}

/// Number of slot sides a cell touches.
#[inline]
pub(super) fn sides_on_boundary(level: u32, i: u32, j: u32) -> u32 {
    let last = (1u32 << level) - 1;
    (j == 0) as u32 + (i == last) as u32 + (j == last) as u32 + (i == 0) as u32
}

impl SlotMark {
    pub(super) fn leaf(&mut self, level: u32, v: &Verdict) {
        self.leaves += 1;
        self.max_level = self.max_level.max(level);
        // NaN (uniform) never wins a max.
        self.bound = self.bound.max(v.bound);
        self.max_ratio = self.max_ratio.max(v.ratio);
    }

    /// `n` leaves at `level` with bound `bound` (absolute flatness: no
    /// ratio), as `n` calls of [`SlotMark::leaf`] would count them.
    pub(super) fn leaves_with(&mut self, n: u32, level: u32, bound: f64) {
        self.leaves += n;
        self.max_level = self.max_level.max(level);
        self.bound = self.bound.max(bound);
    }
}

/// The marking pass of one slot.
struct Marker<'t, 'e, 'n> {
    t: &'t Tester<'e>,
    ev: &'e Evaluator<'e>,
    max_level: u32,
    uniform: bool,
    relative: bool,
    eps: f64,
    nodes: Option<&'n mut [u32]>,
    /// Save corner-cell expansions at the back of `nodes` (see [`mark`]).
    cache: bool,
    /// Take light corner splits where the ring bound allows (always, but
    /// for the unit test that compares with the full path).
    light: bool,
    /// Light splits taken.
    lights: u32,
    /// Per-cell tolerance (absolute flatness only; see `field.rs`).
    field: Option<&'t dyn ToleranceField>,
    next: u64,
    m: SlotMark,
}

impl Marker<'_, '_, '_> {
    /// The tolerance of cell (`kind`, `n`, `off`): `eps`, or with a field
    /// `min(eps, field(box))` (`field.rs`).
    #[inline(always)]
    fn tol(&self, kind: &Kind, n: &Net, off: [f64; 3]) -> f64 {
        match self.field {
            None => self.eps,
            Some(f) => self.field_tol(f, kind, n, off),
        }
    }

    /// [`Marker::tol`] with a tolerance field (out of line: the plain
    /// marking has none).
    #[inline(never)]
    fn field_tol(&self, f: &dyn ToleranceField, kind: &Kind, n: &Net, off: [f64; 3]) -> f64 {
        let (lo, hi) = match kind.tag {
            POLY => net_box(n, off, self.t.round),
            // A corner cell's surface lies in the box of its control
            // points (convex hull property, `Evaluator::ev_corner_box`).
            CORNER => match self.ev.ev_corner_box(kind.patch as usize, kind.k) {
                Some((lo, hi)) => {
                    let pad = DVec3::splat(self.t.round);
                    (lo - pad, hi + pad)
                }
                None => EVERYWHERE,
            },
            _ => EVERYWHERE,
        };
        let t = f.tolerance(lo, hi);
        // NaN or non-positive fields accept nothing (the marking then
        // ends at max_level with an error).
        if t > 0.0 {
            t.min(self.eps)
        } else {
            0.0
        }
    }

    /// `v` with the field's tolerance applied to the cell.
    #[inline]
    fn refine(&self, kind: &Kind, n: &Net, off: [f64; 3], mut v: Verdict) -> Verdict {
        if self.field.is_some() && v.pass {
            v.pass = v.bound <= self.tol(kind, n, off);
        }
        v
    }

    /// Counts a corner-cell expansion (children tested) and, when caching,
    /// saves it just below the ones saved before, at the back of the node
    /// buffer (dropped when it does not fit: the caller then reports the
    /// size).
    #[inline(never)]
    fn save_corner(&mut self, kind: &Kind, dst: &Level) {
        let len = cells::corner_len(kind.rho, dst.internal);
        if let Some(f) = self.reserve_corner(len) {
            cells::store_corner(kind, dst.internal, &dst.kinds, &dst.nets, &dst.offs, f);
        }
    }

    /// As [`Marker::save_corner`] for a light split
    /// ([`cells::light_split`]): the five points from the eigen expansion.
    #[inline(never)]
    fn save_corner_light(&mut self, kind: &Kind) {
        let ev = self.ev;
        if let Some(f) = self.reserve_corner(cells::corner_len(kind.rho, 0)) {
            cells::store_corner_light(ev, kind, f);
        }
    }

    /// Counts `len` f64 of saved corner expansion and, when caching and
    /// they fit, gives their place below the ones saved before.
    #[inline(always)]
    fn reserve_corner(&mut self, len: usize) -> Option<&mut [f64]> {
        let used = self.m.corner_bytes as usize / 4;
        self.m.corner_bytes += 8 * len as u32;
        if !self.cache {
            return None;
        }
        let n = self.nodes.as_deref_mut()?;
        let need = used + 2 * len;
        let at = n.len().checked_sub(need)?;
        Some(as_f64s_mut(&mut n[at..at + 2 * len]))
    }

    #[inline]
    fn store(&mut self, idx: u64, val: u64) {
        if let Some(n) = self.nodes.as_deref_mut() {
            if let Some(x) = n.get_mut(idx as usize) {
                *x = val as u32;
            }
        }
    }

    /// Marks nodes `first..first + 4` as leaves (those that fit).
    #[inline]
    fn store_leaves(&mut self, first: u64) {
        if let Some(n) = self.nodes.as_deref_mut() {
            let a = first as usize;
            match n.get_mut(a..a + 4) {
                Some(four) => four.copy_from_slice(&[0; 4]),
                None => {
                    let a = a.min(n.len());
                    n[a..].fill(0);
                }
            }
        }
    }

    /// Splits node `node` (cell `kind`/`n`/`off` with bound `bound`) at
    /// (level, i, j) into `dst`: allocates and tests its children. Returns
    /// whether a child failed (`dst` then has to be walked).
    #[allow(clippy::too_many_arguments)]
    fn expand(
        &mut self,
        kind: &Kind,
        n: &Net,
        off: [f64; 3],
        bound: f64,
        node: u32,
        level: u32,
        i: u32,
        j: u32,
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
        self.store_leaves(first);
        self.m.side_mids += sides_on_boundary(level, i, j);
        // A polynomial cell's children are polynomial, with bounds at most
        // a quarter of the parent's (module docs): when that is at most
        // eps they are accepted without their nets.
        let round = self.t.round;
        let child_bound = 0.25 * (bound - round) + round;
        let skip = kind.tag == POLY && !self.uniform && child_bound <= self.tol(kind, n, off);
        if skip {
            self.m.leaves_with(4, level + 1, child_bound);
            return Ok(false);
        }
        // A corner cell whose ring-region children the stored ring bound
        // accepts: only its corner child is tested (module docs).
        let light = if self.light && kind.tag == CORNER && !self.uniform && !self.relative {
            cells::light_split(self.ev, kind, self.tol(kind, n, off) - round)
        } else {
            None
        };
        if let Some(rb) = light {
            dst.start(node, first as u32, level, i, j);
            let r = (kind.rho & 3) as usize;
            dst.kinds = [Kind::default(); 4];
            dst.kinds[r] = Kind {
                k: kind.k + 1,
                ..*kind
            };
            dst.offs[r] = [0.0; 3];
            self.m.leaves_with(3, level + 1, rb + round);
            let (ci, cj) = child_ij(i, j, r);
            let v = self
                .t
                .test_at(&dst.kinds[r], &dst.nets[r], level + 1, ci, cj, None);
            let v = self.refine(&dst.kinds[r], &dst.nets[r], [0.0; 3], v);
            if v.pass {
                self.m.leaf(level + 1, &v);
            } else {
                dst.internal = 1 << r;
                dst.bounds[r] = v.bound;
            }
            self.save_corner_light(kind);
            self.lights += 1;
            return Ok(dst.internal != 0);
        }
        dst.start(node, first as u32, level, i, j);
        // Relative flatness: the corner child's corners from the ring grids.
        let mut ring = [DVec3::ZERO; 3];
        let mut has_ring = false;
        if !self.uniform {
            let want = kind.tag == CORNER && self.relative;
            has_ring = cells::expand_ex(
                self.ev,
                kind,
                n,
                off,
                &mut dst.kinds,
                &mut dst.nets,
                &mut dst.offs,
                if want { Some(&mut ring) } else { None },
            );
        }
        // The polynomial children's bounds, four at once (the same values
        // as one by one; the other children's entries are not used).
        let b4 = if !self.uniform {
            Some(bezier::bound4(&dst.nets))
        } else {
            None
        };
        for q in 0..4 {
            let (ci, cj) = child_ij(i, j, q);
            let r = if has_ring && q as u32 == kind.rho {
                Some(&ring)
            } else {
                None
            };
            let (k, n) = (&dst.kinds[q], &dst.nets[q]);
            let v = match b4 {
                Some(b) if k.tag == POLY => {
                    self.t.test_bound(k, n, level + 1, ci, cj, r, b[q] + round)
                }
                _ => self.t.test_at(k, n, level + 1, ci, cj, r),
            };
            let v = self.refine(k, n, dst.offs[q], v);
            if v.pass {
                self.m.leaf(level + 1, &v);
            } else {
                dst.internal |= 1 << q;
                dst.bounds[q] = v.bound;
            }
        }
        if kind.tag == CORNER && !self.uniform {
            self.save_corner(kind, dst);
        }
        Ok(dst.internal != 0)
    }
}

/// `s` (8-byte aligned, even length) as f64 values.
pub(crate) fn as_f64s_mut(s: &mut [u32]) -> &mut [f64] {
    // SAFETY: every bit pattern is a valid f64; `align_to_mut` only yields
    // the aligned middle part.
    let (pre, mid, _) = unsafe { s.align_to_mut::<f64>() };
    if pre.is_empty() {
        mid
    } else {
        &mut []
    }
}

/// Builds the quadtree of `at.slot` into `nodes` (entry = local index of the
/// first of the node's four children, 0 for a leaf; the root is node 0), or
/// only counts when `nodes` is `None` (or too short: the caller compares
/// the returned node count with its length).
///
/// With `cache` (and `nodes`, 8-byte aligned, of even length), the
/// expansion of every split corner cell ([`cells::store_corner`]) is also
/// saved at the back of `nodes`, in preorder, each below the one before,
/// so that the emission need not redo the eigen expansions. Everything
/// fits when `4 nodes + corner_bytes <= 4 nodes.len()`.
pub(crate) fn mark(
    ev: &Evaluator,
    opts: &Options,
    at: SlotId,
    nodes: Option<&mut [u32]>,
    cache: bool,
    scratch: &mut Scratch,
) -> Result<SlotMark, Error> {
    mark_impl(ev, opts, at, nodes, cache, true, None, scratch).map(|(m, _)| m)
}

/// [`mark`] under absolute flatness with a tolerance field (`field.rs`);
/// no corner-cell cache (the trees go to `build_marked`).
pub(crate) fn mark_field(
    ev: &Evaluator,
    opts: &Options,
    at: SlotId,
    nodes: Option<&mut [u32]>,
    field: &dyn ToleranceField,
    scratch: &mut Scratch,
) -> Result<SlotMark, Error> {
    if !matches!(opts.criterion, Criterion::Absolute(_)) {
        return Err(Error::InvalidArgument(
            "a tolerance field needs absolute flatness",
        ));
    }
    mark_impl(ev, opts, at, nodes, false, true, Some(field), scratch).map(|(m, _)| m)
}

/// [`mark`], with light corner splits (`light`) or without, an optional
/// tolerance field, and the number of light splits taken.
#[allow(clippy::too_many_arguments)]
fn mark_impl(
    ev: &Evaluator,
    opts: &Options,
    at: SlotId,
    nodes: Option<&mut [u32]>,
    cache: bool,
    light: bool,
    field: Option<&dyn ToleranceField>,
    scratch: &mut Scratch,
) -> Result<(SlotMark, u32), Error> {
    let uniform = matches!(opts.criterion, Criterion::Uniform(_));
    let round = match slot_round(ev, at.slot) {
        Ok(r) => r,
        Err(e) if !uniform => return Err(e),
        Err(_) => f64::INFINITY,
    };
    let t = Tester::with_round(ev, opts.criterion, at, round);
    let mut mk = Marker {
        t: &t,
        ev,
        max_level: opts.max_level,
        uniform,
        relative: matches!(opts.criterion, Criterion::Relative(_)),
        eps: match opts.criterion {
            Criterion::Absolute(e) => e,
            _ => f64::NAN,
        },
        nodes,
        cache: cache && !uniform,
        light,
        lights: 0,
        field,
        next: 1,
        m: SlotMark {
            nodes: 1,
            ..SlotMark::default()
        },
    };
    mk.store(0, 0);
    let root = if uniform {
        Cell {
            kind: Kind::default(),
            net: [0.0; 48],
            off: DVec3::ZERO,
        }
    } else {
        cells::root(ev, at.slot)
    };
    let v = t.test(&root.kind, &root.net, 0, 0, 0);
    let v = mk.refine(&root.kind, &root.net, root.off.to_array(), v);
    if v.pass {
        mk.m.leaf(0, &v);
        return Ok((mk.m, 0));
    }
    let lv = &mut scratch.levels;
    let walk = mk.expand(
        &root.kind,
        &root.net,
        root.off.to_array(),
        v.bound,
        0,
        0,
        0,
        0,
        &mut lv[0],
    )?;
    if !walk {
        mk.m.nodes = mk.next as u32;
        return Ok((mk.m, mk.lights));
    }
    let mut l = 0usize;
    while let Some(q) = next_child(lv, &mut l) {
        let cur = &lv[l];
        if cur.internal & (1 << q) == 0 {
            continue;
        }
        let (p, dst) = pair(lv, l);
        let (ci, cj) = child_ij(p.i, p.j, q);
        let walk = mk.expand(
            &p.kinds[q],
            &p.nets[q],
            p.offs[q],
            p.bounds[q],
            p.first + q as u32,
            p.level + 1,
            ci,
            cj,
            dst,
        )?;
        l += walk as usize;
    }
    mk.m.nodes = mk.next as u32;
    Ok((mk.m, mk.lights))
}

/// Whether every cell of level `level` of the slot passes the test of
/// `crit` (the uniform tessellation of that level meets the same bound).
pub(crate) fn uniform_passes(
    ev: &Evaluator,
    crit: Criterion,
    at: SlotId,
    level: u32,
    scratch: &mut Scratch,
) -> Result<bool, Error> {
    let t = Tester::new(ev, crit, at);
    // Cells whose whole subtree down to `level` passes: polynomial cells
    // whose descendants' bounds (a quarter per level) meet eps, or (relative)
    // meet r times a lower bound of their diagonals; corner cells whose bound
    // covers every triangle with vertices in their region.
    let settled = |kind: &Kind, n: &Net, l: u32, i: u32, j: u32| match kind.tag {
        POLY => {
            let b = bezier::bound(n);
            let f = libm::scalbn(1.0, -((level - l) as i32));
            match crit {
                Criterion::Absolute(eps) => b * f * f + t.round <= eps,
                Criterion::Relative(r) => {
                    let g = bezier::diagonal_rate(n);
                    g > 0.0 && b * f + t.round / f <= r * g
                }
                Criterion::Uniform(_) => false,
            }
        }
        CORNER => t.corner_settled(kind, n, l, i, j),
        _ => false,
    };
    let root = cells::root(ev, at.slot);
    if level == 0 {
        return Ok(t.test(&root.kind, &root.net, 0, 0, 0).pass);
    }
    if settled(&root.kind, &root.net, 0, 0, 0) {
        return Ok(true);
    }
    let lv = &mut scratch.levels;
    let d = &mut lv[0];
    cells::expand(
        ev,
        &root.kind,
        &root.net,
        root.off.to_array(),
        &mut d.kinds,
        &mut d.nets,
        &mut d.offs,
    );
    (d.level, d.i, d.j, d.q) = (0, 0, 0, 0);
    let mut l = 0usize;
    while let Some(q) = next_child(lv, &mut l) {
        let cur = &lv[l];
        let (ci, cj) = child_ij(cur.i, cur.j, q);
        let cl = cur.level + 1;
        if cl >= level {
            if !t.test(&cur.kinds[q], &cur.nets[q], cl, ci, cj).pass {
                return Ok(false);
            }
            continue;
        }
        if settled(&cur.kinds[q], &cur.nets[q], cl, ci, cj) {
            continue;
        }
        let (p, dst) = pair(lv, l);
        cells::expand(
            ev,
            &p.kinds[q],
            &p.nets[q],
            p.offs[q],
            &mut dst.kinds,
            &mut dst.nets,
            &mut dst.offs,
        );
        (dst.level, dst.i, dst.j, dst.q) = (cl, ci, cj, 0);
        l += 1;
    }
    Ok(true)
}

/// The bound the marking uses for cell (level, i, j) of a slot: the root
/// cell refined down to it by de Casteljau (and the tables, at
/// extraordinary vertices). Infinite for the level-0 cell of a split slot.
pub(crate) fn top_down_bound(ev: &Evaluator, at: SlotId, level: u32, i: u32, j: u32) -> f64 {
    let mut cell = cells::root(ev, at.slot);
    let mut kinds = [Kind::default(); 4];
    let mut nets = [[0.0; 48]; 4];
    let mut offs = [[0.0; 3]; 4];
    for l in 0..level {
        let sh = level - 1 - l;
        let (bi, bj) = ((i >> sh) & 1, (j >> sh) & 1);
        let q = [[0, 3], [1, 2]][bi as usize][bj as usize];
        cells::expand(
            ev,
            &cell.kind,
            &cell.net,
            cell.off.to_array(),
            &mut kinds,
            &mut nets,
            &mut offs,
        );
        cell = Cell {
            kind: kinds[q],
            net: nets[q],
            off: DVec3::from_array(offs[q]),
        };
    }
    Tester::new(ev, Criterion::Absolute(1.0), at).bound(&cell.kind, &cell.net)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::eigen::{BuildScratch, TableSet};
    use crate::eval::evaluator::corner_flatness_tests::with_evaluator;
    use std::boxed::Box;
    use std::vec;

    /// The arithmetic quadrant offsets are the quadrant layout (0 (0, 0),
    /// 1 (1, 0), 2 (1, 1), 3 (0, 1), taken mod 4) and the exponent-bit cell
    /// sizes are `scalbn(1, -level)` bit for bit, at every level an f64
    /// power of two reaches and beyond.
    #[test]
    fn quadrant_offsets_and_cell_sizes() {
        let layout = [(0, 0), (1, 0), (1, 1), (0, 1)];
        for q in 0..16 {
            assert_eq!(quadrant_offset(q), layout[q & 3], "quadrant {q}");
        }
        for level in 0..1200u32 {
            let want = libm::scalbn(1.0, -(level as i32));
            assert_eq!(cell_size(level).to_bits(), want.to_bits(), "level {level}");
        }
    }

    /// Light corner splits change nothing but the work and the reported
    /// bound: on righthanded at AF 2e-3, 1e-3 and 1e-4 of its diagonal,
    /// every slot's tree and saved expansions' sizes are those of the full
    /// path, its bound no smaller and still within eps; light splits do
    /// occur.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn light_splits_keep_the_trees() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let (p, idx) = super::super::cells::tests::righthanded();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for v in p.chunks_exact(3) {
            for c in 0..3 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
        let diag = libm::sqrt(
            (0..3)
                .map(|c| (hi[c] - lo[c]) * (hi[c] - lo[c]))
                .sum::<f64>(),
        );
        with_evaluator(&ts, &p, &idx, |ev| {
            let mut scratch = Box::new(Scratch::ZERO);
            for f in [2e-3, 1e-3, 1e-4] {
                let eps = f * diag;
                let opts = Options::absolute(eps);
                let mut lights = 0;
                for s in 0..ev.num_slots() {
                    let at = super::super::plan::slot_id(ev, s).unwrap();
                    let mut a = vec![0u32; 1 << 16];
                    let mut b = vec![0u32; 1 << 16];
                    let (ma, na) =
                        mark_impl(ev, &opts, at, Some(&mut a), false, true, None, &mut scratch)
                            .unwrap();
                    let (mb, nb) = mark_impl(
                        ev,
                        &opts,
                        at,
                        Some(&mut b),
                        false,
                        false,
                        None,
                        &mut scratch,
                    )
                    .unwrap();
                    assert_eq!(nb, 0);
                    lights += na;
                    let n = ma.nodes as usize;
                    assert!(n <= a.len());
                    assert_eq!(a[..n], b[..n], "slot {s}");
                    assert_eq!(
                        (
                            ma.nodes,
                            ma.leaves,
                            ma.side_mids,
                            ma.corner_bytes,
                            ma.max_level
                        ),
                        (
                            mb.nodes,
                            mb.leaves,
                            mb.side_mids,
                            mb.corner_bytes,
                            mb.max_level
                        )
                    );
                    assert!(ma.bound >= mb.bound && ma.bound <= eps, "slot {s}");
                }
                std::println!("AF {f} x diagonal: {lights} light splits");
                assert!(lights > 0);
            }
        });
    }
}
