//! Mesh-level exact evaluation: `(face, sub, u, v)` to position, derivatives
//! and normal.
//!
//! The [`Evaluator`] is a patch table in caller memory, built once per mesh:
//!
//! * a quad base face with at most one extraordinary vertex (EV) is one patch;
//! * a quad with two or more EVs is split by one Catmull-Clark step into four
//!   patches (its parameter quadrants);
//! * an N-gon (N != 4) has N sub-faces (the quads of one Catmull-Clark step);
//!   sub-face k is one patch when vertex k is regular, otherwise it is split
//!   once more into four (\[CL-R ch. 5\], "subdivide twice").
//!
//! Regular patches store their 16 B-spline control points. EV patches store
//! the eigen projection `L G` of their 2n+8 control points plus the control
//! grids of the six sub-patches of levels 1 and 2 (which cover 15/16 of the
//! parameter square), so most points cost one bicubic evaluation, their
//! control points, the flatness bounds `E_k` of their corner regions
//! for every level a cell can have (so that bounds at the extraordinary
//! vertex cost one load: [`crate::eigen::ValenceTable::corner_flatness`]), and the
//! bounds of the ring regions around those corners for levels below 16
//! (`Evaluator::ring_bound`, used by the adaptive tessellation), and the
//! sub-patch grids of levels 3..=24 (made at build by the evaluation
//! kernel itself, so a point within `2^-24` .. `1/4` of the vertex is one
//! bicubic evaluation too, bit for bit what the kernel gives per query;
//! [`EvaluatorOptions::deep_levels`]).
//!
//! Parameterisation (matches OpenSubdiv): quad `v0 v1 v2 v3` has (0,0)=v0,
//! (1,0)=v1, (1,1)=v2, (0,1)=v3. Sub-face k of an N-gon has (0,0)=v_k,
//! (1,0)=midpoint of edge v_k v_k+1, (1,1)=face centre, (0,1)=midpoint of
//! edge v_k-1 v_k; its derivatives are with respect to its own (u, v).

use super::frame::{rot_back, rot_param, split_params};
use crate::eigen::{EigenTerms, TableSet};
use crate::error::Error;
use crate::math::bspline::{eval_grid_with, Grid};
use crate::math::Eval;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;
use crate::mesh::refine::{refine, refine_bytes, refined_counts};
use crate::mesh::stencil::{label_at, outer, MAX_K};
use crate::mesh::topology::Topology;
use glam::DVec3;

/// What an [`Evaluator`] keeps precomputed per extraordinary patch, besides
/// its eigen projection and control points: memory against speed. Every
/// choice gives the same results bit for bit (what is not kept is
/// recomputed per query from the eigen projection by the same arithmetic).
///
/// The default keeps everything ([`EvaluatorOptions::FULL`]);
/// [`EvaluatorOptions::COMPACT`] keeps nothing more, for firmware whose RAM
/// is scarce: a valence-3 patch takes 672 bytes instead of 28,696 (the
/// level-1/2 grids are 2,304 bytes of those at every valence, the grids of
/// levels 3..=24 25,344, the corner bounds 376; 3,352 without the deep
/// grids, `deep_levels: 0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EvaluatorOptions {
    /// Keep the control grids of the six sub-patches of levels 1 and 2
    /// (`6 x 48` f64, 2,304 bytes; they cover 15/16 of the patch): a point
    /// there costs one bicubic evaluation instead of a sum over the
    /// `2n + 8` eigen terms first. Default `true`.
    pub subpatch_grids: bool,
    /// Keep the corner bounds of the adaptive algorithms: the flatness
    /// `E_k` of the corner regions of levels `0..=30` and the ring-region
    /// bounds of levels below 16 (47 f64, 376 bytes). Without, each bound
    /// is recomputed when asked (all levels up to the one asked, as the
    /// build does). Default `true`.
    pub corner_bounds: bool,
    /// Keep the control grids of the three sub-patches of every level
    /// `3..=deep_levels` (`3 x 48` f64, 1,152 bytes per level; values
    /// below 3 keep none, values above [`MAX_DEEP_LEVEL`] count as it),
    /// made at build by the evaluation kernel
    /// (`G = sum_c mu_c^(m-1) ghat_c X_b[c]`, without the eigenvalue-1
    /// term): a point within `2^-2` .. `2^-deep_levels` of the
    /// extraordinary vertex (or N-gon centre) then costs one bicubic
    /// evaluation instead of `16 x 3 x (2n + 8)` multiply-adds first.
    /// Deeper points run the kernel per query. The adaptive tessellation
    /// reads the same grids for its corner-cell expansions of levels 3
    /// and up (computing them only beyond the kept levels). Default
    /// [`DEFAULT_DEEP_LEVEL`].
    pub deep_levels: u8,
}

/// The deepest level whose sub-patch grids
/// [`EvaluatorOptions::deep_levels`] can keep.
pub const MAX_DEEP_LEVEL: u8 = 32;

/// [`EvaluatorOptions::deep_levels`] of [`EvaluatorOptions::FULL`] (the
/// default).
pub const DEFAULT_DEEP_LEVEL: u8 = 24;

impl EvaluatorOptions {
    /// Everything kept (the default).
    pub const FULL: EvaluatorOptions = EvaluatorOptions {
        subpatch_grids: true,
        corner_bounds: true,
        deep_levels: DEFAULT_DEEP_LEVEL,
    };
    /// Only the eigen projection and the control points kept.
    pub const COMPACT: EvaluatorOptions = EvaluatorOptions {
        subpatch_grids: false,
        corner_bounds: false,
        deep_levels: 0,
    };

    /// The number of levels whose grids [`EvaluatorOptions::deep_levels`]
    /// keeps (levels `3..3 + count`).
    #[inline(always)]
    pub const fn deep_count(self) -> usize {
        let l = if self.deep_levels > MAX_DEEP_LEVEL {
            MAX_DEEP_LEVEL
        } else {
            self.deep_levels
        };
        if l >= 3 {
            l as usize - 2
        } else {
            0
        }
    }
}

impl Default for EvaluatorOptions {
    fn default() -> Self {
        Self::FULL
    }
}

/// Number of f64 stored for a patch of valence `n`: a regular patch keeps
/// its control grid (48), an EV patch its eigen projection (3K), the six
/// level-1/2 sub-patch grids (6 x 48, with
/// [`EvaluatorOptions::subpatch_grids`]), its control points (3K, for the
/// subdivision-depth bounds), its corner flatness bounds
/// ([`FLAT_LEVELS`]) and its ring-region bounds ([`RING_LEVELS`]) (both
/// with [`EvaluatorOptions::corner_bounds`]), then the sub-patch grids of
/// levels `3..=deep_levels` (3 x 48 per level,
/// [`EvaluatorOptions::deep_levels`]).
#[inline]
fn patch_floats(n: usize, opts: EvaluatorOptions) -> usize {
    if n == 4 {
        48
    } else {
        EvLayout::new(0, n, opts).deep().end
    }
}

/// Where the parts of an extraordinary patch's data lie, in the order
/// [`patch_floats`] lists them: from its start `o`, with `k = 2n + 8`
/// control points (a part the options leave out is an empty range). The
/// one place that spells the layout out.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EvLayout {
    o: usize,
    /// Number of control points (`2n + 8`).
    pub k: usize,
    /// The sub-patch grids are stored.
    has_grids: bool,
    /// The corner bounds are stored.
    has_bounds: bool,
    /// Levels of deep sub-patch grids stored (levels `3..3 + deep`).
    deep: usize,
}

impl EvLayout {
    /// The layout of valence `n`'s data starting at `o`.
    #[inline(always)]
    pub(crate) const fn new(o: usize, n: usize, opts: EvaluatorOptions) -> EvLayout {
        EvLayout {
            o,
            k: 2 * n + 8,
            has_grids: opts.subpatch_grids,
            has_bounds: opts.corner_bounds,
            deep: opts.deep_count(),
        }
    }

    /// The eigen projection `ghat` (`3k` values).
    #[inline(always)]
    pub(crate) const fn ghat(self) -> core::ops::Range<usize> {
        self.o..self.o + 3 * self.k
    }

    /// The six level-1/2 sub-patch grids (`6 x 48` values; empty when not
    /// stored).
    #[inline(always)]
    pub(crate) const fn grids(self) -> core::ops::Range<usize> {
        let a = self.ghat().end;
        a..a + if self.has_grids { 6 * 48 } else { 0 }
    }

    /// The grid of sub-patch `Omega_{m,b}` (`m` = 1, 2; `b` = 1..=3), if
    /// stored.
    #[inline(always)]
    pub(crate) const fn grid(self, m: usize, b: usize) -> Option<core::ops::Range<usize>> {
        if !self.has_grids {
            return None;
        }
        let a = self.grids().start + ((m - 1) * 3 + b - 1) * 48;
        Some(a..a + 48)
    }

    /// The control points (`3k` values).
    #[inline(always)]
    pub(crate) const fn points(self) -> core::ops::Range<usize> {
        let a = self.grids().end;
        a..a + 3 * self.k
    }

    /// The corner flatness bounds `E_k`, `k < FLAT_LEVELS` (empty when not
    /// stored).
    #[inline(always)]
    pub(crate) const fn flat(self) -> core::ops::Range<usize> {
        let a = self.points().end;
        a..a + if self.has_bounds { FLAT_LEVELS } else { 0 }
    }

    /// The ring-region bounds, levels `k < RING_LEVELS` (empty when not
    /// stored).
    #[inline(always)]
    pub(crate) const fn ring(self) -> core::ops::Range<usize> {
        let a = self.flat().end;
        a..a + if self.has_bounds { RING_LEVELS } else { 0 }
    }

    /// The grids of the three sub-patches of levels `3..3 + deep`
    /// (`144` values per level, region `b` at `48 (b - 1)`; empty when
    /// none are stored).
    #[inline(always)]
    pub(crate) const fn deep(self) -> core::ops::Range<usize> {
        let a = self.ring().end;
        a..a + 144 * self.deep
    }
}

/// Corner levels `k = 0..FLAT_LEVELS` whose flatness `E_k`
/// ([`crate::eigen::ValenceTable::corner_flatness`]) an extraordinary patch keeps
/// precomputed: every level a cell of a sub-face can have (30).
const FLAT_LEVELS: usize = 31;

/// Corner levels `k = 0..RING_LEVELS` whose ring-region bound
/// ([`Evaluator::ring_bound`]) an extraordinary patch keeps precomputed
/// (deeper corner cells, which only tight tolerances reach, compute it).
const RING_LEVELS: usize = 16;

/// The corner flatness bounds `E_k` of levels `k = 0..out.len()` of the
/// patch with projection `ghat` (what the build stores and
/// [`Evaluator::corner_flatness`] recomputes when it does not).
fn flat_levels(tab: &crate::eigen::ValenceTable, ghat: &[f64], out: &mut [f64]) {
    let mut terms = EigenTerms::EMPTY;
    tab.flatness_terms(ghat, &mut terms);
    terms.levels(out);
}

/// Entry `k < FLAT_LEVELS` of [`flat_levels`], bit for bit (what
/// [`Evaluator::corner_flatness`] recomputes when it is not stored; a
/// frame of its own, off the callers' stack).
#[inline(never)]
fn flat_level(tab: &crate::eigen::ValenceTable, ghat: &[f64], k: u32) -> f64 {
    let mut terms = EigenTerms::EMPTY;
    tab.flatness_terms(ghat, &mut terms);
    terms.level(k)
}

/// The ring-region bound of level `k` when it is not stored: entry `k` of
/// [`ring_levels`] bit for bit for `k < RING_LEVELS`, else the table's
/// value; `None` for a table the bound does not cover (a frame of its
/// own, off the callers' stack).
#[inline(never)]
fn ring_level(tab: &crate::eigen::ValenceTable, ghat: &[f64], k: u32) -> Option<f64> {
    // By reference: the terms are large (no copy out of the option).
    let terms = tab.ring_terms(ghat);
    let t = terms.as_ref()?;
    Some(if (k as usize) < RING_LEVELS {
        t.level(k)
    } else {
        t.at(k)
    })
}

/// The ring-region bounds of levels `k = 0..out.len()` (infinite for a
/// table the bound does not cover), as [`flat_levels`].
fn ring_levels(tab: &crate::eigen::ValenceTable, ghat: &[f64], out: &mut [f64]) {
    match tab.ring_terms(ghat) {
        Some(t) => t.levels(out),
        None => out.fill(f64::INFINITY),
    }
}

/// A query: base face, sub-face (0 for quads), parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Query {
    /// Base face index.
    pub face: u32,
    /// Sub-face (0 for quads, 0..N for N-gons).
    pub sub: u32,
    /// Parameter u in [0, 1].
    pub u: f64,
    /// Parameter v in [0, 1].
    pub v: f64,
}

impl Query {
    /// Checks the face against `num_faces`, the sub-face against
    /// `num_subfaces(face)` and the parameters against `[0, 1]`.
    #[inline]
    pub fn check_ranges(
        &self,
        num_faces: usize,
        num_subfaces: impl Fn(usize) -> usize,
    ) -> Result<(), Error> {
        let f = self.face as usize;
        if f >= num_faces {
            return Err(Error::FaceOutOfRange { face: self.face });
        }
        if self.sub as usize >= num_subfaces(f) {
            return Err(Error::SubFaceOutOfRange {
                face: self.face,
                sub: self.sub,
            });
        }
        if !(0.0..=1.0).contains(&self.u) || !(0.0..=1.0).contains(&self.v) {
            return Err(Error::ParameterOutOfRange);
        }
        Ok(())
    }
}

/// How a slot (face, sub) maps to patches.
#[derive(Clone, Copy, Debug)]
struct PlanPatch {
    level: u8,
    face: usize,
    rot: u8,
    valence: usize,
}

/// Exact evaluator of a closed Catmull-Clark surface (see module docs).
pub struct Evaluator<'a> {
    pub(crate) tables: &'a TableSet,
    /// First slot of each face (F+1 entries).
    slot_start: &'a [u32],
    /// Per slot: first patch record, and 1 when split into four quadrants.
    pub(crate) slot_patch: &'a [u32],
    pub(crate) slot_split: &'a [u32],
    /// Per patch: first f64 in `data`, and valence | rot << 8 | level << 16.
    pub(crate) patch_data: &'a [u32],
    pub(crate) patch_meta: &'a [u32],
    pub(crate) data: &'a [f64],
    num_faces: usize,
    num_ev_patches: usize,
    num_regular_patches: usize,
    levels: u8,
    /// What each extraordinary patch keeps precomputed.
    opts: EvaluatorOptions,
}

/// Per-face decision: which level each slot's patches live on.
fn face_needs(t: &Topology, f: usize) -> (bool, u8) {
    let vs = t.face_vertices(f);
    if vs.len() == 4 {
        let evs = vs.iter().filter(|&&v| t.valence(v as usize) != 4).count();
        (false, if evs <= 1 { 0 } else { 1 })
    } else {
        let irregular = vs.iter().any(|&v| t.valence(v as usize) != 4);
        (true, if irregular { 2 } else { 1 })
    }
}

/// Calls `visit(slot_index_in_face, split, patches)` for each slot of face f.
fn plan_face(t: &Topology, f: usize, mut visit: impl FnMut(bool, &[PlanPatch])) {
    let vs = t.face_vertices(f);
    let n = vs.len();
    let val = |v: u32| t.valence(v as usize);
    let fs = t.face_half_edge(f);
    if n == 4 {
        let evs = vs.iter().filter(|&&v| val(v) != 4).count();
        if evs <= 1 {
            let r = vs.iter().position(|&v| val(v) != 4).unwrap_or(0);
            let p = PlanPatch {
                level: 0,
                face: f,
                rot: r as u8,
                valence: val(vs[r]),
            };
            visit(false, &[p]);
        } else {
            // Child k of face f at level 1 is face fs + k, its EV is corner 0.
            let mut ps = [PlanPatch {
                level: 1,
                face: 0,
                rot: 0,
                valence: 4,
            }; 4];
            for (k, p) in ps.iter_mut().enumerate() {
                p.face = fs + k;
                p.valence = val(vs[k]);
            }
            visit(true, &ps);
        }
    } else {
        for k in 0..n {
            let h = fs + k; // level-1 child face
            let nk = val(vs[k]);
            if nk == 4 {
                // EV is the face centre, corner 2 of the child.
                let p = PlanPatch {
                    level: 1,
                    face: h,
                    rot: 2,
                    valence: n,
                };
                visit(false, &[p]);
            } else {
                // Level-2 children of level-1 quad h are faces 4h + c.
                let mut ps = [PlanPatch {
                    level: 2,
                    face: 0,
                    rot: 0,
                    valence: 4,
                }; 4];
                for (c, p) in ps.iter_mut().enumerate() {
                    p.face = 4 * h + c;
                    p.valence = match c {
                        0 => nk,
                        2 => n,
                        _ => 4,
                    };
                    p.rot = 0; // child c has parent corner c (the EV, if any) at its corner 0
                }
                visit(true, &ps);
            }
        }
    }
}

/// Gathers the 2n+8 control points (label order of [`crate::mesh::stencil`]) of the
/// patch of face `q` whose EV (or any corner, for regular patches) is corner `r`.
fn gather(t: &Topology, q: usize, r: usize, n: usize, out: &mut [DVec3; MAX_K]) {
    let h0 = t.face_half_edge(q) + r;
    out[0] = t.position(t.origin(h0));
    let mut s = h0;
    for i in 0..n {
        out[1 + 2 * i] = t.position(t.dest(s));
        out[2 + 2 * i] = t.position(t.dest(t.next(s)));
        s = t.rotate_ccw(s);
    }
    let b = t.next(h0);
    let tb = t.twin(b); // F0 -> E0 in face (E0, O1, O2, F0)
    let g1 = t.next(tb); // E0 -> O1
    let o = |k: usize| outer(n, k);
    out[o(1)] = t.position(t.dest(g1));
    out[o(2)] = t.position(t.dest(t.next(g1)));
    out[o(0)] = t.position(t.origin(t.prev(t.twin(g1))));
    let d = t.twin(t.prev(tb)); // F0 -> O2 in the diagonal face
    out[o(3)] = t.position(t.dest(t.next(d)));
    let c = t.twin(t.next(b)); // E1 -> F0 in face (E1, F0, O4, O5)
    let c1 = t.next(c); // F0 -> O4
    out[o(4)] = t.position(t.dest(c1));
    out[o(5)] = t.position(t.dest(t.next(c1)));
    let e6 = t.twin(t.prev(c)); // E1 -> O5 in face (F1, E1, O5, O6)
    out[o(6)] = t.position(t.dest(t.next(e6)));
}

struct Levels<'a> {
    l1: Option<Topology<'a>>,
    l2: Option<Topology<'a>>,
}

impl<'a> Evaluator<'a> {
    fn scan(t: &Topology) -> (bool, bool, usize, usize) {
        let (mut need1, mut need2) = (false, false);
        let (mut slots, mut patches) = (0usize, 0usize);
        for f in 0..t.num_faces() {
            let (ngon, lvl) = face_needs(t, f);
            need1 |= lvl >= 1;
            need2 |= lvl >= 2;
            slots += if ngon { t.face_size(f) } else { 1 };
            plan_face(t, f, |_, ps| patches += ps.len());
        }
        (need1, need2, slots, patches)
    }

    /// The internal refinement levels (one or two uniform steps and their
    /// topologies): only the build uses them.
    fn level_layout(t: &Topology) -> Layout {
        let (need1, need2, _, _) = Self::scan(t);
        let mut l = Layout::default();
        if need1 {
            l.raw(refine_bytes(t));
            let c1 = refined_counts(t);
            l.raw(Topology::layout(c1.vertices, c1.faces, 4 * c1.faces).bytes());
            if need2 {
                // Level-1 counts: V1 = V+E+F, E1 = 2H, F1 = H, H1 = 4H.
                let h = t.num_half_edges();
                let mut lr = Layout::default();
                let v2 = c1.vertices + 2 * h + h;
                lr.f64s(3 * v2);
                lr.u32s(4 * h);
                lr.u32s(16 * h);
                lr.u32s(4 * h);
                l.raw(lr.bytes());
                l.raw(Topology::layout(v2, 4 * h, 16 * h).bytes());
            }
        }
        l
    }

    fn layout(t: &Topology, tables: &TableSet, opts: EvaluatorOptions) -> Result<Layout, Error> {
        let mut l = Layout::default();
        l.raw(Self::level_layout(t).bytes());
        l.raw(Self::table_layout(t, tables, opts)?.bytes());
        Ok(l)
    }

    /// What the evaluator keeps: slot and patch indices, patch data.
    fn table_layout(
        t: &Topology,
        tables: &TableSet,
        opts: EvaluatorOptions,
    ) -> Result<Layout, Error> {
        let (_, _, slots, patches) = Self::scan(t);
        let mut l = Layout::default();
        l.u32s(t.num_faces() + 1);
        l.u32s(slots);
        l.u32s(slots);
        l.u32s(patches);
        l.u32s(patches);
        let mut pts = 0usize;
        let mut missing = None;
        for f in 0..t.num_faces() {
            plan_face(t, f, |_, ps| {
                for p in ps {
                    if p.valence != 4 && tables.get(p.valence).is_none() {
                        missing = Some(p.valence);
                    }
                    pts += patch_floats(p.valence, opts);
                }
            });
        }
        if let Some(v) = missing {
            return Err(Error::MissingTable { valence: v as u32 });
        }
        if pts > u32::MAX as usize || patches > u32::MAX as usize {
            return Err(Error::InvalidArgument("mesh too large for the patch table"));
        }
        l.f64s(pts);
        Ok(l)
    }

    /// Bytes of caller memory [`Evaluator::build`] needs for topology `t`.
    pub fn required_bytes(t: &Topology, tables: &TableSet) -> Result<usize, Error> {
        Self::required_bytes_with(t, tables, EvaluatorOptions::default())
    }

    /// Bytes of caller memory [`Evaluator::build_with`] needs for
    /// topology `t` with `opts` (exact).
    pub fn required_bytes_with(
        t: &Topology,
        tables: &TableSet,
        opts: EvaluatorOptions,
    ) -> Result<usize, Error> {
        Ok(Self::layout(t, tables, opts)?.bytes())
    }

    /// The part of [`Evaluator::required_bytes_with`] that only the build
    /// uses (the internal refinement levels of meshes with N-gons or quads
    /// with several extraordinary vertices; 0 for others):
    /// [`Evaluator::build_split`] takes it as a block of its own, free
    /// again once the build returns.
    pub fn build_scratch_bytes(t: &Topology) -> usize {
        Self::level_layout(t).bytes()
    }

    /// Builds the patch table of `t` into `mem` (at least
    /// [`Evaluator::required_bytes`] bytes: [`crate::mem::words_for`] words),
    /// with the default [`EvaluatorOptions`].
    pub fn build(t: &Topology, tables: &'a TableSet, mem: &'a mut [u64]) -> Result<Self, Error> {
        Self::build_with(t, tables, EvaluatorOptions::default(), mem)
    }

    /// As [`Evaluator::build`], keeping what `opts` says per
    /// extraordinary patch (`mem`: at least
    /// [`Evaluator::required_bytes_with`] bytes). Every evaluation and
    /// bound is the same bit for bit whatever `opts`.
    pub fn build_with(
        t: &Topology,
        tables: &'a TableSet,
        opts: EvaluatorOptions,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        let required = Self::required_bytes_with(t, tables, opts)?;
        if bytes_of(mem.len()) < required {
            return Err(Error::BufferTooSmall { required });
        }
        // The same carving as one block: the levels first.
        let (scratch, mem) = mem.split_at_mut(Self::build_scratch_bytes(t) / 8);
        Self::build_split(t, tables, opts, mem, scratch)
    }

    /// As [`Evaluator::build_with`], with the memory only the build uses in
    /// a block of its own, `scratch` (at least
    /// [`Evaluator::build_scratch_bytes`] bytes), which the caller may use
    /// for anything else once this returns; `mem` (what the evaluator
    /// keeps) needs [`Evaluator::required_bytes_with`] minus that.
    /// [`Error::BufferTooSmall`] names the size of `mem` when it is short,
    /// else that of `scratch`.
    pub fn build_split(
        t: &Topology,
        tables: &'a TableSet,
        opts: EvaluatorOptions,
        mem: &'a mut [u64],
        scratch: &mut [u64],
    ) -> Result<Self, Error> {
        let kept = Self::table_layout(t, tables, opts)?.bytes();
        if bytes_of(mem.len()) < kept {
            return Err(Error::BufferTooSmall { required: kept });
        }
        let levels = Self::build_scratch_bytes(t);
        if bytes_of(scratch.len()) < levels {
            return Err(Error::BufferTooSmall { required: levels });
        }
        let (need1, need2, slots, patches) = Self::scan(t);
        let mut scratch = Arena::new(scratch);
        let mut arena = Arena::new(mem);
        let w = tables.weights();
        let mut lv = Levels { l1: None, l2: None };
        if need1 {
            let r1 = refine(t, w, scratch.words(refine_bytes(t)))?;
            let c1 = refined_counts(t);
            let tm = scratch.words(Topology::layout(c1.vertices, c1.faces, 4 * c1.faces).bytes());
            let t1 = Topology::build(r1.mesh, tm)?;
            if need2 {
                let rb = refine_bytes(&t1);
                let r2 = refine(&t1, w, scratch.words(rb))?;
                let c2 = refined_counts(&t1);
                let tm2 =
                    scratch.words(Topology::layout(c2.vertices, c2.faces, 4 * c2.faces).bytes());
                lv.l2 = Some(Topology::build(r2.mesh, tm2)?);
            }
            lv.l1 = Some(t1);
        }
        let slot_start = arena.u32s(t.num_faces() + 1);
        let slot_patch = arena.u32s(slots);
        let slot_split = arena.u32s(slots);
        let patch_data = arena.u32s(patches);
        let patch_meta = arena.u32s(patches);
        let mut pts = 0usize;
        let fill = |vis: &mut dyn FnMut(&PlanPatch, usize)| {
            let mut pi = 0usize;
            for f in 0..t.num_faces() {
                plan_face(t, f, |_, ps| {
                    for p in ps {
                        vis(p, pi);
                        pi += 1;
                    }
                });
            }
        };
        // Slot and patch indices.
        {
            let mut si = 0usize;
            let mut pi = 0usize;
            for f in 0..t.num_faces() {
                slot_start[f] = si as u32;
                plan_face(t, f, |split, ps| {
                    slot_patch[si] = pi as u32;
                    slot_split[si] = split as u32;
                    si += 1;
                    pi += ps.len();
                });
            }
            slot_start[t.num_faces()] = si as u32;
        }
        fill(&mut |p, pi| {
            patch_data[pi] = pts as u32;
            patch_meta[pi] = p.valence as u32 | (p.rot as u32) << 8 | (p.level as u32) << 16;
            pts += patch_floats(p.valence, opts);
        });
        let data = arena.f64s(pts);
        let (mut nev, mut nreg) = (0usize, 0usize);
        let mut err = None;
        fill(&mut |p, pi| {
            let topo = match p.level {
                0 => t,
                1 => match &lv.l1 {
                    Some(x) => x,
                    None => return,
                },
                _ => match &lv.l2 {
                    Some(x) => x,
                    None => return,
                },
            };
            let mut g = [DVec3::ZERO; MAX_K];
            gather(topo, p.face, p.rot as usize, p.valence, &mut g);
            let o = patch_data[pi] as usize;
            if p.valence == 4 {
                nreg += 1;
                for y in -1..=2i32 {
                    for x in -1..=2i32 {
                        let q = g[label_at(4, x, y).unwrap_or(0)];
                        let s = o + ((x + 1) * 4 + (y + 1)) as usize;
                        data[s] = q.x;
                        data[s + 16] = q.y;
                        data[s + 32] = q.z;
                    }
                }
            } else {
                nev += 1;
                let Some(tab) = tables.get(p.valence) else {
                    err = Some(Error::MissingTable {
                        valence: p.valence as u32,
                    });
                    return;
                };
                let lay = EvLayout::new(o, p.valence, opts);
                let k = lay.k;
                let mut gh = [0.0; 3 * MAX_K];
                tab.project(&g, &mut gh);
                data[lay.ghat()].copy_from_slice(&gh[..3 * k]);
                for m in 1..=2u32 {
                    for b in 1..=3usize {
                        if let Some(at) = lay.grid(m as usize, b) {
                            let mut grid = [0.0; 48];
                            tab.sub_patch(&gh[..3 * k], m, b, true, &mut grid);
                            data[at].copy_from_slice(&grid);
                        }
                    }
                }
                let pts = &mut data[lay.points()];
                for (c, q) in g.iter().take(k).enumerate() {
                    pts[3 * c] = q.x;
                    pts[3 * c + 1] = q.y;
                    pts[3 * c + 2] = q.z;
                }
                let deep = &mut data[lay.deep()];
                for (i, level) in deep.chunks_exact_mut(144).enumerate() {
                    for (b, grid) in level.chunks_exact_mut(48).enumerate() {
                        if let Ok(g) = <&mut Grid>::try_from(grid) {
                            tab.deep_grid(&gh[..3 * k], i as u32 + 3, b + 1, g);
                        }
                    }
                }
                flat_levels(tab, &gh[..3 * k], &mut data[lay.flat()]);
                ring_levels(tab, &gh[..3 * k], &mut data[lay.ring()]);
            }
        });
        if let Some(e) = err {
            return Err(e);
        }
        Ok(Evaluator {
            tables,
            slot_start,
            slot_patch,
            slot_split,
            patch_data,
            patch_meta,
            data,
            num_faces: t.num_faces(),
            num_ev_patches: nev,
            num_regular_patches: nreg,
            levels: need2 as u8 + need1 as u8,
            opts,
        })
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.num_faces
    }
    /// Number of sub-faces of base face `f` (1 for quads, N for N-gons).
    pub fn num_subfaces(&self, f: usize) -> usize {
        if f < self.num_faces {
            (self.slot_start[f + 1] - self.slot_start[f]) as usize
        } else {
            0
        }
    }
    /// Number of regular (bicubic) and extraordinary patches.
    pub fn patch_counts(&self) -> (usize, usize) {
        (self.num_regular_patches, self.num_ev_patches)
    }
    /// Internal refinement levels used (0, 1 or 2).
    pub fn internal_levels(&self) -> u8 {
        self.levels
    }

    #[inline]
    fn eval_patch<const SECOND: bool, const NORMAL: bool>(
        &self,
        pi: usize,
        s: f64,
        t: f64,
        scale: f64,
        turn: u8,
    ) -> Eval {
        self.patch_body::<SECOND, NORMAL, false, false>(pi, s, t, scale, turn)
    }

    /// The body of [`Evaluator::eval_patch`], always inlined: the paths
    /// that write into the caller's [`Eval`] ([`Evaluator::eval_to`],
    /// [`Evaluator::eval_checked_to`]) take it whole, so that its result
    /// is not copied out of a call frame (a 168-byte `memcpy` per level
    /// of call); [`Evaluator::eval_patch`] keeps it behind one call for
    /// the value-returning API (inlining it there made `eval_derivs`
    /// slower, callgrind: see BENCHMARKS.md). With `INLINE` the kernel of
    /// extraordinary patches is inlined too
    /// ([`crate::eigen::ValenceTable::eval_projected_inlined`]: the
    /// single-point path); without, it stays one call (the batch, whose
    /// loop ran slower with it inlined).
    ///
    /// `turn` is the quadrant of a split slot (0 otherwise; see
    /// `frame::split_params`): the patch is then evaluated as if its
    /// rotation were `turn` (its stored one is 0: every child of a split
    /// slot has its corner 0 at the slot's corner of its quadrant).
    ///
    /// With `WIDE` the bicubics run on four-lane vectors (the same bits;
    /// only in the body of a function compiled with AVX2), the kernel in
    /// one call ([`crate::eigen::ValenceTable::eval_projected_avx2`],
    /// whatever `INLINE`).
    #[inline(always)]
    fn patch_body<const SECOND: bool, const NORMAL: bool, const INLINE: bool, const WIDE: bool>(
        &self,
        pi: usize,
        s: f64,
        t: f64,
        scale: f64,
        turn: u8,
    ) -> Eval {
        let meta = self.patch_meta[pi];
        let n = (meta & 0xff) as usize;
        debug_assert!(
            turn == 0 || (meta >> 8) & 3 == 0,
            "split child with a rotation"
        );
        let r = ((meta >> 8) as u8 + turn) & 3;
        let o = self.patch_data[pi] as usize;
        if n == 4 && r == 0 {
            // Every regular patch is in its face's frame (`plan_face`),
            // and the rotation by 0 is the identity but for the scale.
            let Ok(g) = <&Grid>::try_from(&self.data[o..o + 48]) else {
                return Eval::default();
            };
            let mut e = eval_grid_with::<SECOND, WIDE>(g, s, t);
            e.scale_derivatives::<SECOND>(scale);
            e.normal = if NORMAL {
                e.du.cross(e.dv).normalize_or_zero()
            } else {
                DVec3::ZERO
            };
            return e;
        }
        let (x, y) = rot_param(r, s, t);
        let mut e = if n == 4 {
            match <&Grid>::try_from(&self.data[o..o + 48]) {
                Ok(g) => eval_grid_with::<SECOND, WIDE>(g, x, y),
                Err(_) => return Eval::default(),
            }
        } else {
            let Some(tab) = self.tables.get(n) else {
                return Eval::default();
            };
            let lay = EvLayout::new(o, n, self.opts);
            let (ghat, deep) = (&self.data[lay.ghat()], &self.data[lay.deep()]);
            let grids = if self.opts.subpatch_grids {
                Some(&self.data[lay.grids()])
            } else {
                None
            };
            if WIDE {
                // SAFETY: `WIDE` is only set in functions compiled with
                // AVX2, which run only where the CPU has it.
                unsafe { tab.eval_projected_avx2::<SECOND, NORMAL>(ghat, grids, deep, x, y) }
            } else if INLINE {
                tab.eval_projected_inlined::<SECOND, NORMAL>(ghat, grids, deep, x, y)
            } else {
                tab.eval_projected_impl::<SECOND, NORMAL>(ghat, grids, deep, x, y)
            }
        };
        rot_back::<SECOND>(r, &mut e, scale);
        if !NORMAL {
            e.normal = DVec3::ZERO;
        } else if n == 4 {
            e.normal = e.du.cross(e.dv).normalize_or_zero();
        }
        // Extraordinary patches: the table kernel already set the normal
        // (rotations and quadrant maps preserve orientation).
        e
    }

    #[inline]
    fn eval_impl<const SECOND: bool, const NORMAL: bool>(
        &self,
        face: u32,
        sub: u32,
        u: f64,
        v: f64,
    ) -> Result<Eval, Error> {
        let f = face as usize;
        if f >= self.num_faces {
            return Err(Error::FaceOutOfRange { face });
        }
        let s0 = self.slot_start[f] as usize;
        let ns = self.slot_start[f + 1] as usize - s0;
        if sub as usize >= ns {
            return Err(Error::SubFaceOutOfRange { face, sub });
        }
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(Error::ParameterOutOfRange);
        }
        // The body of `eval_slot`, written out: calling it here costs the
        // single-point path 20-30 instructions (callgrind, release build).
        let slot = s0 + sub as usize;
        let p0 = self.slot_patch[slot] as usize;
        if self.slot_split[slot] == 0 {
            Ok(self.eval_patch::<SECOND, NORMAL>(p0, u, v, 1.0, 0))
        } else {
            let (c, x, y) = split_params(u, v);
            Ok(self.eval_patch::<SECOND, NORMAL>(p0 + c as usize, x, y, 2.0, c))
        }
    }

    /// The evaluation at (u, v) of slot `slot` (`< num_slots()`).
    #[inline]
    fn eval_slot<const SECOND: bool, const NORMAL: bool>(
        &self,
        slot: usize,
        u: f64,
        v: f64,
    ) -> Eval {
        let p0 = self.slot_patch[slot] as usize;
        if self.slot_split[slot] == 0 {
            self.eval_patch::<SECOND, NORMAL>(p0, u, v, 1.0, 0)
        } else {
            let (c, x, y) = split_params(u, v);
            self.eval_patch::<SECOND, NORMAL>(p0 + c as usize, x, y, 2.0, c)
        }
    }

    /// [`Evaluator::eval_slot`] of the same values, with the patch
    /// evaluation inlined ([`Evaluator::patch_body`]), stored to `out` at
    /// the end (nothing before).
    #[inline(always)]
    fn eval_slot_to<
        const SECOND: bool,
        const NORMAL: bool,
        const INLINE: bool,
        const WIDE: bool,
    >(
        &self,
        slot: usize,
        u: f64,
        v: f64,
        out: &mut Eval,
    ) {
        let p0 = self.slot_patch[slot] as usize;
        let e = if self.slot_split[slot] == 0 {
            self.patch_body::<SECOND, NORMAL, INLINE, WIDE>(p0, u, v, 1.0, 0)
        } else {
            let (c, x, y) = split_params(u, v);
            self.patch_body::<SECOND, NORMAL, INLINE, WIDE>(p0 + c as usize, x, y, 2.0, c)
        };
        // Field by field: without `SECOND` the second derivatives are
        // zero on every path (`eval_grid`, the kernel and `rot_back` leave
        // them so), stored as such instead of carried through the frame.
        out.p = e.p;
        out.du = e.du;
        out.dv = e.dv;
        if SECOND {
            out.duu = e.duu;
            out.duv = e.duv;
            out.dvv = e.dvv;
        } else {
            out.duu = DVec3::ZERO;
            out.duv = DVec3::ZERO;
            out.dvv = DVec3::ZERO;
        }
        out.normal = e.normal;
    }

    /// [`Evaluator::eval_slot_to`] compiled with AVX2: its bicubics on
    /// four-lane vectors (the same bits).
    ///
    /// # Safety
    /// The CPU runs AVX2 ([`crate::math::simd::has_avx2`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn eval_slot_to_avx2<const SECOND: bool, const NORMAL: bool>(
        &self,
        slot: usize,
        u: f64,
        v: f64,
        out: &mut Eval,
    ) {
        self.eval_slot_to::<SECOND, NORMAL, false, true>(slot, u, v, out)
    }

    /// [`Evaluator::eval`] (`SECOND` false) or [`Evaluator::eval_second`]
    /// (`SECOND` true) into `out`: the same checks, in the same order
    /// (the same error), then the same values bit for bit, written to
    /// `out` only on success. Without `NORMAL` the unit normal is not
    /// computed and `out.normal` is set to zero (as
    /// [`Evaluator::eval_derivs`]): the normal's square root and division
    /// are a chain of about 50 cycles at the end of every call, which a
    /// caller that only wants the derivatives need not wait for
    /// (BENCHMARKS.md). The cheapest entry point of a host that
    /// keeps its own result struct (the C ABI's `ccss_evaluator_eval`
    /// writes straight into the caller's `ccss_evaluator_result`): no
    /// `Result<Eval, _>` to move, the patch evaluation inlined.
    #[inline]
    pub fn eval_to<const SECOND: bool, const NORMAL: bool>(
        &self,
        face: u32,
        sub: u32,
        u: f64,
        v: f64,
        out: &mut Eval,
    ) -> Result<(), Error> {
        let f = face as usize;
        if f >= self.num_faces {
            return Err(Error::FaceOutOfRange { face });
        }
        let s0 = self.slot_start[f] as usize;
        let ns = self.slot_start[f + 1] as usize - s0;
        if sub as usize >= ns {
            return Err(Error::SubFaceOutOfRange { face, sub });
        }
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(Error::ParameterOutOfRange);
        }
        // Without the AVX2 path of the batch (`eval_checked_to`): called
        // once per point, its extra call made meshes of extraordinary
        // patches slower (measured; docs/bench-log.md, 2026-11-28).
        self.eval_slot_to::<SECOND, NORMAL, true, false>(s0 + sub as usize, u, v, out);
        Ok(())
    }

    /// [`Evaluator::eval_checked`] into `out` (with `SECOND` the second
    /// derivatives; without `NORMAL` a zero normal, as
    /// [`Evaluator::eval_to`]): the same values bit for bit, what a batch whose
    /// queries are all checked first calls per query. A query whose slot
    /// does not exist leaves `out` untouched; one that fails the check
    /// otherwise writes a value of no meaning; never a panic. Where the
    /// CPU has AVX2 the bicubics run on four-lane vectors (the same bits;
    /// about 5-20 % faster per point in a batch, BENCHMARKS.md).
    #[inline]
    pub fn eval_checked_to<const SECOND: bool, const NORMAL: bool>(
        &self,
        q: &Query,
        out: &mut Eval,
    ) {
        let Some(&s0) = self.slot_start.get(q.face as usize) else {
            return;
        };
        let slot = (s0 as usize).saturating_add(q.sub as usize);
        if slot >= self.slot_patch.len() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::math::simd::has_avx2() {
            // SAFETY: the CPU runs AVX2 (checked just above).
            unsafe { self.eval_slot_to_avx2::<SECOND, NORMAL>(slot, q.u, q.v, out) };
            return;
        }
        self.eval_slot_to::<SECOND, NORMAL, false, false>(slot, q.u, q.v, out);
    }

    /// Position, first derivatives, normal and (with `second`) second
    /// derivatives of a query that passed [`Evaluator::check`], without
    /// checking it again: what a batch that validates all its queries
    /// first (as the C ABI's `ccss_evaluator_eval_batch`) calls per query.
    /// The same values as [`Evaluator::eval`] / [`Evaluator::eval_second`],
    /// bit for bit. A query that does not pass the check gives
    /// `Eval::default()` when its slot does not exist and otherwise a value
    /// of no meaning, never a panic.
    #[inline]
    pub fn eval_checked(&self, q: &Query, second: bool) -> Eval {
        let Some(&s0) = self.slot_start.get(q.face as usize) else {
            return Eval::default();
        };
        let slot = (s0 as usize).saturating_add(q.sub as usize);
        if slot >= self.slot_patch.len() {
            return Eval::default();
        }
        if second {
            self.eval_slot::<true, true>(slot, q.u, q.v)
        } else {
            self.eval_slot::<false, true>(slot, q.u, q.v)
        }
    }

    /// Position, first derivatives and normal at (u, v) of sub-face `sub` of
    /// base face `face`.
    pub fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl::<false, true>(face, sub, u, v)
    }

    /// As [`Evaluator::eval`], plus second derivatives.
    pub fn eval_second(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl::<true, true>(face, sub, u, v)
    }

    /// Position and first derivatives only (`normal` is left zero): the
    /// cheapest evaluation, the one the benchmarks time.
    pub fn eval_derivs(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl::<false, false>(face, sub, u, v)
    }

    /// Position, first and second derivatives (`normal` is left zero):
    /// [`Evaluator::eval_second`] without the normal's square root and
    /// division, the same other values bit for bit.
    pub fn eval_second_derivs(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl::<true, false>(face, sub, u, v)
    }

    /// Evaluates a batch into `out` (`out.len() >= queries.len()`, else
    /// [`Error::BufferTooSmall`] with the count). On the first bad query the
    /// error is returned with its index and nothing is written.
    pub fn eval_batch(
        &self,
        queries: &[Query],
        second: bool,
        out: &mut [Eval],
    ) -> Result<(), (usize, Error)> {
        if out.len() < queries.len() {
            return Err((
                0,
                Error::BufferTooSmall {
                    required: queries.len(),
                },
            ));
        }
        for (i, q) in queries.iter().enumerate() {
            self.check(q).map_err(|e| (i, e))?;
        }
        // Checked above: evaluated without a second check, in place, on
        // four-lane vectors where the CPU has AVX2 (the same bits).
        for (q, o) in queries.iter().zip(out.iter_mut()) {
            if second {
                self.eval_checked_to::<true, true>(q, o);
            } else {
                self.eval_checked_to::<false, true>(q, o);
            }
        }
        Ok(())
    }

    /// Number of (face, sub-face) slots: one per quad, N per N-gon. This is
    /// the length [`crate::bounds::depth::depths`] writes.
    pub fn num_slots(&self) -> usize {
        self.slot_patch.len()
    }

    /// First slot of base face `f` (slots of face f are
    /// `slot_start(f) .. slot_start(f) + num_subfaces(f)`).
    pub fn slot_start(&self, f: usize) -> usize {
        self.slot_start[f.min(self.num_faces)] as usize
    }

    /// What each extraordinary patch keeps precomputed (the options of
    /// [`Evaluator::build_with`]).
    pub fn options(&self) -> EvaluatorOptions {
        self.opts
    }

    /// The data layout of an extraordinary patch of valence `n` whose data
    /// start at `o` (`patch_data[pi]`).
    #[inline]
    pub(crate) fn ev_layout(&self, o: usize, n: usize) -> EvLayout {
        EvLayout::new(o, n, self.opts)
    }

    /// EV patch `pi`'s valence table and data layout; `None` for a regular
    /// patch (which stores only its grid: the valence-4 table exists, but
    /// there is no projection to read) or a missing table.
    #[inline]
    pub(crate) fn ev_patch(&self, pi: usize) -> Option<(&crate::eigen::ValenceTable, EvLayout)> {
        let n = (*self.patch_meta.get(pi)? & 0xff) as usize;
        if n == 4 {
            return None;
        }
        Some((
            self.tables.get(n)?,
            EvLayout::new(*self.patch_data.get(pi)? as usize, n, self.opts),
        ))
    }

    /// Flatness `E_k` of the corner region `[0, 2^-k]^2` of EV patch `pi`
    /// ([`crate::eigen::ValenceTable::corner_flatness`], precomputed at build for
    /// `k <= 30`, equal to that function's value up to a few ulps); `None`
    /// for a regular patch or a missing table.
    #[inline]
    pub(crate) fn corner_flatness(&self, pi: usize, k: u32) -> Option<f64> {
        let (tab, lay) = self.ev_patch(pi)?;
        if (k as usize) < FLAT_LEVELS {
            if self.opts.corner_bounds {
                return self.data.get(lay.flat().start + k as usize).copied();
            }
            return Some(flat_level(tab, self.data.get(lay.ghat())?, k));
        }
        Some(tab.corner_flatness(self.data.get(lay.ghat())?, k))
    }

    /// The bounding box of the control points of the corner region
    /// `[0, 2^-k]^2` of EV patch `pi` (its `2n + 8` control points after
    /// `k` subdivision steps, `A^k G`: the stored points for `k = 0`,
    /// [`crate::eigen::ValenceTable::level_points`] beyond), which contains
    /// every limit point of that region up to the rounding of its
    /// evaluation: Catmull-Clark's face, edge and vertex masks have
    /// non-negative weights summing to one (for valence `n >= 3` the
    /// vertex rule's are `1 - 7/(4n)`, `3/(2n^2)`, `1/(4n^2)`), so each
    /// step maps control points to convex combinations of them, and every
    /// limit point of the region, a limit of such combinations of `A^k G`,
    /// lies in their convex hull (`Stam98`'s evaluation computes that
    /// limit). `None` for a regular patch or a missing table. The
    /// tessellation's tolerance fields take it as a corner cell's box
    /// (`tessellate/field.rs`); `ev_corner_box_holds_the_region` samples
    /// it densely.
    pub(crate) fn ev_corner_box(&self, pi: usize, k: u32) -> Option<(DVec3, DVec3)> {
        let (tab, lay) = self.ev_patch(pi)?;
        let mut pts = [DVec3::ZERO; MAX_K];
        if k == 0 {
            let raw = self.data.get(lay.points())?;
            for (p, c) in pts.iter_mut().zip(raw.chunks_exact(3)) {
                *p = DVec3::new(c[0], c[1], c[2]);
            }
        } else {
            tab.level_points(self.data.get(lay.ghat())?, k, &mut pts);
        }
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for &q in &pts[..lay.k.min(MAX_K)] {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        Some((lo, hi))
    }

    /// Guaranteed bound of the ring-region cells `Omega_{k+1, b}` (b = 1,
    /// 2, 3) of EV patch `pi`, the children of its corner cell
    /// `[0, 2^-k]^2` other than the corner child: at least the
    /// [`crate::bounds::cell`] bound `lambda_max([[a, c], [c, b]]) / 3` of each
    /// of their Bezier nets ([`crate::eigen::ValenceTable::ring_terms`];
    /// precomputed at build for `k < 16`). `None` for a regular patch, a
    /// missing table or a table with a 2x2 block.
    #[inline]
    pub(crate) fn ring_bound(&self, pi: usize, k: u32) -> Option<f64> {
        let (tab, lay) = self.ev_patch(pi)?;
        let b = if (k as usize) < RING_LEVELS && self.opts.corner_bounds {
            *self.data.get(lay.ring().start + k as usize)?
        } else {
            ring_level(tab, self.data.get(lay.ghat())?, k)?
        };
        // Infinite: stored for a table the bound does not cover.
        b.is_finite().then_some(b)
    }

    /// Validates a query without evaluating it.
    #[inline]
    pub fn check(&self, q: &Query) -> Result<(), Error> {
        q.check_ranges(self.num_faces, |f| self.num_subfaces(f))
    }
}

#[cfg(test)]
pub(crate) mod corner_flatness_tests {
    extern crate std;
    use super::*;
    use crate::eigen::BuildScratch;
    use crate::mesh::MeshInput;
    use std::boxed::Box;
    use std::vec;

    /// Calls `f` with the evaluator of a quad mesh.
    pub(crate) fn with_evaluator(
        ts: &TableSet,
        p: &[f64],
        idx: &[u32],
        f: impl FnOnce(&Evaluator),
    ) {
        with_mesh(ts, p, &vec![4u32; idx.len() / 4], idx, f);
    }

    /// Calls `f` with the evaluator of a mesh with faces of `sizes`.
    pub(crate) fn with_mesh(
        ts: &TableSet,
        p: &[f64],
        sizes: &[u32],
        idx: &[u32],
        f: impl FnOnce(&Evaluator),
    ) {
        let mesh = MeshInput {
            positions: p,
            face_sizes: sizes,
            indices: idx,
        };
        let mut tm = vec![0u64; Topology::required_bytes(p.len() / 3, sizes) / 8 + 1];
        let topo = Topology::build(mesh, &mut tm).unwrap();
        let mut em = vec![0u64; Evaluator::required_bytes(&topo, ts).unwrap() / 8 + 1];
        f(&Evaluator::build(&topo, ts, &mut em).unwrap());
    }

    /// The stored corner bounds (flatness and ring region) are the table's
    /// values (to 1e-14 relative: powers by repeated multiplication), at
    /// every stored level and beyond (computed, bit for bit), on a cube with
    /// perturbed corners (each face has four extraordinary vertices, so it
    /// is split into four patches with one each: 24 EV patches); regular
    /// patches (a 4 x 4 torus) have none.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn stored_corner_flatness_is_the_tables() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let p = [
            -1., -1., -1., 1.1, -1., -1., 1., 1.3, -1., -1., 1., -1.2, -1., -1., 1., 1., -0.9, 1.,
            1., 1., 1., -1.4, 1., 1.,
        ];
        let idx = [
            0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
        ];
        with_evaluator(&ts, &p, &idx, |ev| {
            let mut checked = 0;
            for pi in 0..ev.patch_meta.len() {
                let n = (ev.patch_meta[pi] & 0xff) as usize;
                let o = ev.patch_data[pi] as usize;
                let ghat = &ev.data[EvLayout::new(o, n, ev.opts).ghat()];
                // A stored bound (levels below `stored`) equals the table's
                // to 1e-14 relative, a computed one bit for bit.
                let check = |what: &str, got: f64, want: f64, k: u32, stored: usize| {
                    if k as usize >= stored {
                        assert_eq!(got.to_bits(), want.to_bits(), "{what} k {k}");
                    }
                    assert!(
                        want > 0.0 && (got - want).abs() <= 1e-14 * want,
                        "{what} k {k}: {got} {want}"
                    );
                };
                let tab = ts.get(n).unwrap();
                for k in 0..40 {
                    let got = ev.corner_flatness(pi, k).unwrap();
                    check(
                        "flatness",
                        got,
                        tab.corner_flatness(ghat, k),
                        k,
                        FLAT_LEVELS,
                    );
                    let got = ev.ring_bound(pi, k).unwrap();
                    let want = tab.ring_terms(ghat).unwrap().at(k);
                    check("ring", got, want, k, RING_LEVELS);
                    checked += 1;
                }
            }
            assert_eq!(checked, 24 * 40);
        });
        // A 4 x 4 torus: every patch regular.
        let (mut tp, mut ti) = (vec![], vec![]);
        for i in 0..4u32 {
            for j in 0..4u32 {
                let q = core::f64::consts::FRAC_PI_2;
                let (a, b) = (i as f64 * q, j as f64 * q);
                let r = 2.0 + 0.5 * libm::cos(b);
                tp.extend([r * libm::cos(a), r * libm::sin(a), 0.5 * libm::sin(b)]);
                let v = |x: u32, y: u32| (x % 4) * 4 + y % 4;
                ti.extend([v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        with_evaluator(&ts, &tp, &ti, |ev| {
            assert_eq!(ev.patch_counts(), (16, 0));
            for pi in 0..16 {
                for k in [0, 3, 30, 31] {
                    assert_eq!(ev.corner_flatness(pi, k), None);
                    assert_eq!(ev.ring_bound(pi, k), None);
                }
            }
        });
    }

    /// [`Evaluator::eval_checked`] is [`Evaluator::eval`] /
    /// [`Evaluator::eval_second`] bit for bit on checked queries (the
    /// split cube: every patch extraordinary, points down to level 40),
    /// and on queries that fail the check it returns without a panic.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn eval_checked_is_eval_and_never_panics() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let p = [
            -1., -1., -1., 1.1, -1., -1., 1., 1.3, -1., -1., 1., -1.2, -1., -1., 1., 1., -0.9, 1.,
            1., 1., 1., -1.4, 1., 1.,
        ];
        let idx = [
            0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
        ];
        with_evaluator(&ts, &p, &idx, |ev| {
            let bits = |e: &Eval| {
                [e.p, e.du, e.dv, e.duu, e.duv, e.dvv, e.normal]
                    .map(|a| a.to_array().map(f64::to_bits))
            };
            for k in 0..400u32 {
                let sc = libm::scalbn(1.0, -((k % 41) as i32));
                let (u, v) = (sc * f64::from(k % 7) / 6.0, sc * f64::from(k % 5) / 4.0);
                let q = Query {
                    face: k % 6,
                    sub: 0,
                    u,
                    v,
                };
                assert_eq!(ev.check(&q), Ok(()));
                let want = [
                    ev.eval(q.face, 0, u, v).unwrap(),
                    ev.eval_second(q.face, 0, u, v).unwrap(),
                ];
                for (second, w) in [false, true].into_iter().zip(want) {
                    assert_eq!(bits(&ev.eval_checked(&q, second)), bits(&w), "{q:?}");
                }
            }
            for (face, sub, u, v) in [
                (6, 0, 0.5, 0.5),
                (u32::MAX, 0, 0.5, 0.5),
                (0, 1, 0.5, 0.5),
                (5, u32::MAX, 0.5, 0.5),
                (0, 0, -1.0, 2.0),
                (0, 0, f64::NAN, 0.5),
                (1, 0, f64::INFINITY, f64::NEG_INFINITY),
            ] {
                let q = Query { face, sub, u, v };
                assert!(ev.check(&q).is_err());
                let _ = ev.eval_checked(&q, false);
                let _ = ev.eval_checked(&q, true);
            }
        });
    }

    /// Every limit point of the corner region `[0, 2^-k]^2` of an
    /// extraordinary patch lies in the box of its control points
    /// (`Evaluator::ev_corner_box`, convex hull property), `k = 0..6`:
    /// dense samples (33 x 33 per region) of a cube whose faces are each
    /// cut into four quads (one valence-3 corner per quad, so each quad is
    /// one unsplit EV patch), with jittered vertices. Prints how tight the
    /// box is (the samples' extent against the box's).
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn ev_corner_box_holds_the_region() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        // Faces of the cube [-1, 1]^3: normal axis, sign; a 3 x 3 grid each.
        let mut pts: std::vec::Vec<[i32; 3]> = std::vec::Vec::new();
        let mut idx = std::vec::Vec::new();
        let id = |q: [i32; 3], pts: &mut std::vec::Vec<[i32; 3]>| -> u32 {
            match pts.iter().position(|&x| x == q) {
                Some(i) => i as u32,
                None => {
                    pts.push(q);
                    (pts.len() - 1) as u32
                }
            }
        };
        for axis in 0..3 {
            for sign in [-1i32, 1] {
                let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                let at = |x: i32, y: i32| {
                    let mut q = [0; 3];
                    q[axis] = sign;
                    q[a] = x;
                    q[b] = y;
                    q
                };
                for x in -1..1 {
                    for y in -1..1 {
                        // Counter-clockwise seen from outside: (a, b) is
                        // right-handed with the axis for sign +1.
                        let mut quad = [at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)];
                        if sign < 0 {
                            quad.reverse();
                        }
                        for q in quad {
                            let i = id(q, &mut pts);
                            idx.push(i);
                        }
                    }
                }
            }
        }
        let mut seed = 99u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let p: std::vec::Vec<f64> = pts
            .iter()
            .flat_map(|q| q.map(|c| c as f64))
            .map(|c| c + 0.3 * rnd())
            .collect();
        with_evaluator(&ts, &p, &idx, |ev| {
            let mut checked = 0;
            let mut fill = 0.0f64;
            for slot in 0..ev.num_slots() {
                let pi = ev.slot_patch[slot] as usize;
                if ev.slot_split[slot] != 0 || ev.ev_patch(pi).is_none() {
                    continue;
                }
                // The quad's corner at the cube's corner (valence 3).
                let q = (0..4)
                    .find(|&q| pts[idx[4 * slot + q] as usize].iter().all(|c| c.abs() == 1))
                    .unwrap();
                let (cu, cv) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][q];
                for k in 0..6u32 {
                    let (lo, hi) = ev.ev_corner_box(pi, k).unwrap();
                    let (mut slo, mut shi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
                    let n = 32;
                    let s = libm::scalbn(1.0, -(k as i32));
                    for i in 0..=n {
                        for j in 0..=n {
                            let (a, b) = (s * i as f64 / n as f64, s * j as f64 / n as f64);
                            let u = if cu == 0.0 { a } else { 1.0 - a };
                            let v = if cv == 0.0 { b } else { 1.0 - b };
                            let x = ev.eval(slot as u32, 0, u, v).unwrap().p;
                            let tol = DVec3::splat(1e-12);
                            assert!(
                                x.cmpge(lo - tol).all() && x.cmple(hi + tol).all(),
                                "slot {slot} k {k}: {x} outside [{lo}, {hi}]"
                            );
                            slo = slo.min(x);
                            shi = shi.max(x);
                        }
                    }
                    fill = fill.max(((shi - slo) / (hi - lo)).max_element());
                    checked += 1;
                }
            }
            // 24 quads, each one unsplit EV patch, 6 levels each.
            assert_eq!(checked, 24 * 6);
            std::println!("largest extent of the samples / the box's, per axis: {fill:.3}");
        });
    }
}
