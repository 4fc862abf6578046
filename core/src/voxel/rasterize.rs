//! Voxelization by recursive parameter-space subdivision (the paper's
//! `VoxelizeSubPatch`), made certain by a second, certifying walk.
//!
//! ## First walk: the paper's algorithm
//!
//! Every patch is pre-split into `k x k` cells (`k` = [`VoxelParams::presplit`],
//! a power of two; default 8 as in the paper). Each cell is processed with an
//! explicit stack (no machine recursion):
//!
//! 1. its four corners `S(u1,v1), S(u2,v1), S(u2,v2), S(u1,v2)` are rounded to
//!    voxels with eq. (2), `i = floor(x + 0.5)` (same for j, k);
//! 2. it is a leaf when the corner voxels are `N`-adjacent (`Delta_i` =
//!    largest difference of the four `i`, etc.):
//!    N = 6: `Di + Dj + Dk <= 1`; N = 18: all `<= 1` and sum `<= 2`;
//!    N = 26: all `<= 1` — or when the paper's recursion guard
//!    `|u2 - u1| < 1 / max(M1, M2, M3)` holds;
//! 3. otherwise it is split at the parameter midpoints into four.
//!
//! The leaves' corner voxels are written to the surface plane. Corners are
//! exact limit points (corners of Bezier nets, see `cells.rs`), so
//! **every surface voxel contains a limit-surface point** (the paper's eq. 4,
//! minimality), up to floating-point rounding of the coordinates.
//!
//! A leaf must also have a guaranteed box (`cells.rs`: net box or
//! corner ball) of extent at most [`LEAF_EXTENT`] voxels; this changes
//! nothing for ordinary cells and bounds how far a leaf reaches, which is
//! what makes slabs exact (below).
//!
//! **N = 6.** The first walk uses the N = 18 corner test, not the paper's
//! `Di + Dj + Dk <= 1`: wherever the surface crosses a voxel edge, a cell
//! has corners in three or four voxels around that edge at every size, so
//! the face test splits it down to the recursion guard (cells far below a
//! voxel), and those corners mostly land in voxels that other leaves
//! already made black. What N = 6 promises (below: every surface point's
//! voxel black up to `TAU`, every black voxel holding a limit point) is the
//! certification's work for any leaves, so the stop test only moves work
//! between the walks: the voxel sets are the same up to voxels the surface
//! meets within `TAU` of their boundary (measured: identical sets for the
//! torus and righthanded at 512^3; instructions 13.8 G -> 5.7 G for
//! the torus with flooding, `BENCHMARKS.md`).
//!
//! ## Second walk: certification (the "no holes" guarantee)
//!
//! The corner test is a heuristic (paper §4.2): a cell whose corners are
//! adjacent may still bulge into a voxel no corner reached. Each leaf
//! therefore lists the voxels its guaranteed box requires:
//!
//! * N = 6 (**no holes**, paper eq. 3): every voxel meeting the box shrunk by
//!   [`TAU`] on each side. If all of them are black, every surface point `P`
//!   of the cell has a black voxel within `TAU` (max-norm) of `P`: clamp `P`
//!   into the shrunk box.
//! * N = 18 and 26 (**thin**, 6-separating): only points on the voxel
//!   centre lines (two integer coordinates) matter: for each axis and each
//!   centre line meeting the box, the voxels of that line meeting the shrunk
//!   box. Then every surface point on a centre line has a black voxel of that
//!   line within `TAU`.
//!
//! Required voxels that are not corner voxels of the leaf go to the work
//! plane. After the first walk, those that no corner made black are
//! "uncovered"; usually there are none. If there are, a second walk repeats
//! the first one's decisions, visits only cells whose box meets an uncovered
//! voxel, and refines such leaves further (each refinement subtree checks
//! its requirements against the first walk's surface plane plus the voxels
//! its own corners made black) until every requirement is met or the box is
//! smaller than `TAU`. New corner voxels are again exact limit points.
//!
//! **Separability.** Suppose a 6-path of white voxels joins a voxel whose
//! centre is outside the solid to one whose centre is inside. Some step
//! joins centres `c` and `c + e_a` on opposite sides, so the unit segment
//! between them, which lies on a centre line, meets the surface at a point
//! `P`. `P` has a black voxel of that line within `TAU < 0.5`: that can only
//! be the voxel of `c` or of `c + e_a`. Contradiction: the surface voxels
//! are 6-separating for all three adjacencies, and flooding from outside
//! never reaches a voxel whose centre is inside (see [`super::flood`]).
//!
//! **Slabs.** The first walk's marks do not depend on any state, and the
//! second walk's decisions read only the first walk's planes within a leaf's
//! box (at most `LEAF_EXTENT` voxels). A slab grid keeps
//! [`super::grid::SLAB_MARGIN`] extra layers on each side, so the surface
//! voxels of its slab are exactly those of the whole grid.

use super::cells::{
    corner_children, corner_corners, for_each_root, limit_point, net_box, net_corners, patch_hull,
    plane_range, point, split4_into, Affine, Cell, Net, Patch,
};
use super::grid::VoxelGrid;
use super::stack::{Entry, VoxelWork, HULL, MAX_DEPTH, POLY, STACK_CAP};
use super::{Adjacency, GridState, Surface, VoxelParams, VoxelTransform};
use crate::error::Error;
use crate::eval::MAX_CELL_LEVEL;
use glam::DVec3;

/// Tolerance of the certification, in voxels (see module docs).
pub const TAU: f64 = 1e-6;

/// Largest box extent (voxels, every axis) of a leaf of the first walk.
pub const LEAF_EXTENT: f64 = 2.0;

/// Work cap of the certification walk: at most
/// `CERTIFY_CELLS_MIN + CERTIFY_CELLS_PER_LEAF * leaves` cells (leaves of
/// the first walk). Ordinary meshes use a quarter of it at most (24 closed
/// corpus shapes at resolutions 24 and 64, adjacencies 6 and 26: at most
/// 1.86 cells per leaf, catmark_cube at N = 6, whose first walk stops at
/// the N = 18 test; test `voxel_certification_is_capped`); a needle-thin
/// surface along a voxel diagonal would need millions per leaf and gets
/// `WorkLimitExceeded` instead.
pub const CERTIFY_CELLS_PER_LEAF: u64 = 8;
/// See [`CERTIFY_CELLS_PER_LEAF`].
pub const CERTIFY_CELLS_MIN: u64 = 1 << 14;
/// Work cap of one certification subtree (the cells refined below one
/// first-walk leaf). The corpus needs at most 909 at the test's
/// resolutions (test `voxel_certification_is_capped` prints the largest);
/// catmark_righthanded at 512^3 with N = 6 needs 11,329 at one corner cell
/// of an extraordinary vertex (its box is a cube without a slab, so every
/// voxel of the cube is required until the cube shrinks past them). The
/// needle along a voxel diagonal exceeds it at its first leaf and is
/// refused at once.
pub const CERTIFY_SUBTREE_CELLS: u64 = 1 << 15;

/// Work cap of the first walk: at most `FIRST_CELLS_MIN +
/// FIRST_CELLS_PER_ROOT * roots + FIRST_CELLS_PER_VOXEL * voxels` cells
/// (`roots` = patches times `presplit^2`, `voxels` the grid's). A leaf
/// covers a box of at most [`LEAF_EXTENT`] voxels, so a surface needs
/// about as many leaves as the voxels it meets, a few per voxel where
/// patches fold over each other; the corpus at resolutions 24..512 stays
/// far below it (test `voxel_first_walk_is_capped`). What reaches it is
/// data the box tests cannot settle (e.g. control points beyond the
/// certified coordinate range, whose cells never shrink to a leaf before
/// depth [`super::stack::MAX_DEPTH`], `4^48` cells): `WorkLimitExceeded`
/// instead of a walk that does not end.
pub const FIRST_CELLS_PER_VOXEL: u64 = 16;
/// See [`FIRST_CELLS_PER_VOXEL`].
pub const FIRST_CELLS_PER_ROOT: u64 = 64;
/// See [`FIRST_CELLS_PER_VOXEL`].
pub const FIRST_CELLS_MIN: u64 = 1 << 22;

/// Largest rounding of the coordinates, in voxels, under which the
/// certification's guarantees are claimed (see [`VoxelGrid::voxelize`]).
pub const MAX_ROUNDING_VOXELS: f64 = 0.25;

/// The coordinate-range and rounding check of a voxelization of the limit
/// box `[lo, hi]` at `scale` voxels per model unit.
fn rounding_check(lo: DVec3, hi: DVec3, scale: f64) -> Result<(), Error> {
    use crate::bounds::rounding;
    let m = lo.abs().max(hi.abs()).max_element();
    rounding::term(m)?;
    if (hi - lo).max_element() < rounding::MIN_MAGNITUDE {
        return Err(Error::CoordinateRange(
            "the model's size is below 2^-200 (not certified)",
        ));
    }
    if rounding::TERM * f64::EPSILON * m * scale > MAX_ROUNDING_VOXELS {
        return Err(Error::CoordinateRange(
            "the model is too small for its distance from the origin at this resolution: \
             rounding of the coordinates exceeds a quarter voxel",
        ));
    }
    Ok(())
}

/// What a voxelization did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RasterStats {
    /// Cells visited by the first walk (the paper's algorithm).
    pub cells: u64,
    /// Leaves of the first walk.
    pub leaves: u64,
    /// Voxels required by some leaf that no corner of the first walk made
    /// black (the certification walk handles them).
    pub uncovered: u64,
    /// Cells visited by the certification walk.
    pub refined: u64,
    /// Deepest cell below a pre-split cell.
    pub max_depth: u32,
    /// Cells where the certification gave up at [`super::MAX_DEPTH`]
    /// (0 on every mesh we know; a non-zero value means the guarantee may
    /// fail there).
    pub guard_hits: u64,
    /// Largest certification subtree (cells below one first-walk leaf; see
    /// [`CERTIFY_SUBTREE_CELLS`]).
    pub max_subtree: u64,
    /// The paper's area estimate: the sum of the areas of the leaves'
    /// corner quadrilaterals, `|(c2 - c0) x (c3 - c1)| / 2`, in model units
    /// (leaves whose first corner lies in the slab).
    pub quad_area: f64,
}

/// `floor(x)`, with `x` clamped to `[-2^30, 2^30]` (NaN gives `-2^30`): far
/// outside any grid (at most 2^16 voxels per axis), so clamping changes no
/// voxel index; a truncating conversion and a correction, much cheaper
/// than a software `floor` or a saturating `as` conversion.
#[inline(always)]
fn ffloor(x: f64) -> i32 {
    const B: f64 = (1u32 << 30) as f64;
    let y = if x > -B { x } else { -B };
    let y = if y < B { y } else { B };
    // SAFETY: `y` is finite and within i32's range (NaN was mapped above).
    let t = unsafe { y.to_int_unchecked::<i32>() };
    t - ((y < t as f64) as i32)
}

/// Eq. (2): the voxel of a point.
#[inline(always)]
pub(crate) fn vox(p: DVec3) -> [i32; 3] {
    [ffloor(p.x + 0.5), ffloor(p.y + 0.5), ffloor(p.z + 0.5)]
}

/// Key of an in-grid voxel for membership tests (coordinates < 2^21).
#[inline(always)]
fn key(v: [u32; 3]) -> u64 {
    v[0] as u64 | (v[1] as u64) << 21 | (v[2] as u64) << 42
}

/// Keys of a leaf's corner voxels; a corner outside `[0, res)` gets a key
/// no in-grid voxel has.
#[inline(always)]
fn own_keys(v: &[[i32; 3]; 4], res: [u32; 3]) -> [u64; 4] {
    v.map(|q| {
        if (0..3).all(|a| q[a] >= 0 && (q[a] as u32) < res[a]) {
            key([q[0] as u32, q[1] as u32, q[2] as u32])
        } else {
            u64::MAX
        }
    })
}

#[inline(always)]
fn owns(own: &[u64; 4], v: [u32; 3]) -> bool {
    let k = key(v);
    (own[0] == k) | (own[1] == k) | (own[2] == k) | (own[3] == k)
}

/// Geometry of one cell: exact corners (counter-clockwise) and their
/// voxels, a guaranteed box, and (polynomial cells) a guaranteed slab
/// `s_lo <= (x - o) . n <= s_hi` around the plane of the corners; plus the
/// region children of a corner cell.
struct Node {
    corners: [DVec3; 4],
    vox: [[i32; 3]; 4],
    lo: DVec3,
    hi: DVec3,
    slab: Option<(DVec3, DVec3, f64, f64)>,
}

/// Corners and voxels of a polynomial cell only (box left empty).
#[inline]
fn poly_corners(e: &Entry) -> Node {
    let corners = net_corners(&e.net);
    Node {
        corners,
        vox: e.vox,
        lo: DVec3::ZERO,
        hi: DVec3::ZERO,
        slab: None,
    }
}

/// The slab of a polynomial cell (module docs of [`required`]).
fn add_slab(n: &mut Node, net: &Net) {
    let c = &n.corners;
    let nrm = (c[2] - c[0]).cross(c[3] - c[1]);
    let l2 = nrm.length_squared();
    if l2 > 1e-24 && l2.is_finite() {
        let nrm = nrm / libm::sqrt(l2);
        let o = c[0];
        let (a, b) = plane_range(net, o, nrm);
        n.slab = Some((nrm, o, a, b));
    }
}

fn node_info(e: &Entry, p: &Patch, aff: &Affine, want_slab: bool) -> Node {
    if e.corner == POLY {
        let (lo, hi) = net_box(&e.net);
        let corners = net_corners(&e.net);
        let mut n = Node {
            corners,
            // `push_poly` and `split_top` stored the corners' voxels.
            vox: e.vox,
            lo,
            hi,
            slab: None,
        };
        if want_slab {
            add_slab(&mut n, &e.net);
        }
        return n;
    }
    if e.corner == HULL {
        let h = e.hull();
        return Node {
            corners: h.corners,
            vox: h.corners.map(vox),
            lo: h.lo,
            hi: h.hi,
            slab: None,
        };
    }
    let l = e.corner;
    match p {
        Patch::Extra {
            tab, ghat, cache, ..
        } => {
            let kids = corner_children(tab, ghat, cache, l, aff);
            let c = aff.apply(limit_point(ghat));
            let r = DVec3::splat(tab.corner_radius(ghat, l) * aff.scale);
            let corners = corner_corners(c, &kids);
            Node {
                corners,
                vox: corners.map(vox),
                lo: c - r,
                hi: c + r,
                slab: None,
            }
        }
        Patch::Regular(_) | Patch::Feature(_) => Node {
            corners: [DVec3::ZERO; 4],
            vox: [[0; 3]; 4],
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            slab: None,
        },
    }
}

/// Pushes a polynomial cell with its corner voxels.
#[inline]
fn push_poly(work: &mut VoxelWork, net: Net, depth: u32, level: u32, mode: u8) {
    let v = net_corners(&net).map(vox);
    let mut e = Entry::new(Cell::Poly(net), depth, level, mode);
    e.vox = v;
    work.push(e);
}

/// The corner test of the first walk for adjacency `adj`: the paper's own
/// for N = 18 and 26; the N = 18 test for N = 6 (module docs, "N = 6").
fn first_walk_test(adj: Adjacency) -> Adjacency {
    match adj {
        Adjacency::Six | Adjacency::Eighteen => Adjacency::Eighteen,
        Adjacency::TwentySix => Adjacency::TwentySix,
    }
}

/// The paper's N-adjacency test on the four corner voxels (lines 6-11).
#[inline]
fn adjacent(v: &[[i32; 3]; 4], adj: Adjacency) -> bool {
    let mut d = [0i32; 3];
    for (a, da) in d.iter_mut().enumerate() {
        let mut lo = v[0][a];
        let mut hi = v[0][a];
        for q in &v[1..] {
            lo = lo.min(q[a]);
            hi = hi.max(q[a]);
        }
        // Saturating: clamped (NaN) corners lie 2^31 apart (fuzz finding).
        *da = hi.saturating_sub(lo);
    }
    let s = d[0].saturating_add(d[1]).saturating_add(d[2]);
    match adj {
        Adjacency::Six => s <= 1,
        Adjacency::Eighteen => d.iter().all(|&x| x <= 1) && s <= 2,
        Adjacency::TwentySix => d.iter().all(|&x| x <= 1),
    }
}

/// Voxel index range `[a, b]` of an interval (clamped to `[0, m-1]`);
/// None if empty.
#[inline]
fn vrange(lo: f64, hi: f64, m: u32) -> Option<(u32, u32)> {
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let a = ffloor(lo + 0.5).max(0);
    let b = ffloor(hi + 0.5).min(m as i32 - 1);
    if a > b {
        None
    } else {
        Some((a as u32, b as u32))
    }
}

/// Integer coordinates in `[lo, hi]`, clamped to `[0, m-1]`.
#[inline]
fn irange(lo: f64, hi: f64, m: u32) -> Option<(u32, u32)> {
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let a = (-ffloor(-lo)).max(0);
    let b = ffloor(hi).min(m as i32 - 1);
    if a > b {
        None
    } else {
        Some((a as u32, b as u32))
    }
}

/// Calls `f` for every voxel a leaf requires (module docs); stops early
/// when `f` returns false. Returns false if stopped.
///
/// With a slab `s_lo <= (x - o).n <= s_hi` (which contains the cell's
/// surface), a point `Q` of the surface moved by at most `TAU` (max norm)
/// stays within `TAU |n|_1` of the slab, so only voxels meeting the slab
/// widened by that much are required.
fn required(n: &Node, thin: bool, res: [u32; 3], mut f: impl FnMut([u32; 3]) -> bool) -> bool {
    let (lo, hi) = (n.lo, n.hi);
    let mut a = lo + DVec3::splat(TAU);
    let mut b = hi - DVec3::splat(TAU);
    for ax in 0..3 {
        if a[ax] > b[ax] {
            let m = 0.5 * (lo[ax] + hi[ax]);
            a[ax] = m;
            b[ax] = m;
        }
    }
    // Slab widened by TAU |n|_1 plus a rounding allowance.
    let slab = n.slab.map(|(nrm, o, s0, s1)| {
        let w = TAU * (nrm.x.abs() + nrm.y.abs() + nrm.z.abs()) + 1e-9;
        (nrm, o, s0 - w, s1 + w)
    });
    if !thin {
        let (Some(x), Some(y), Some(z)) = (
            vrange(a.x, b.x, res[0]),
            vrange(a.y, b.y, res[1]),
            vrange(a.z, b.z, res[2]),
        ) else {
            return true;
        };
        for k in z.0..=z.1 {
            for j in y.0..=y.1 {
                for i in x.0..=x.1 {
                    if let Some((nrm, o, s0, s1)) = slab {
                        let c = DVec3::new(i as f64, j as f64, k as f64);
                        let d = (c - o).dot(nrm);
                        let r = 0.5 * (nrm.x.abs() + nrm.y.abs() + nrm.z.abs());
                        if d + r < s0 || d - r > s1 {
                            continue;
                        }
                    }
                    if !f([i, j, k]) {
                        return false;
                    }
                }
            }
        }
        return true;
    }
    for ax in 0..3 {
        let (b1, b2) = ((ax + 1) % 3, (ax + 2) % 3);
        let (Some(s), Some(t)) = (
            irange(lo[b1], hi[b1], res[b1]),
            irange(lo[b2], hi[b2], res[b2]),
        ) else {
            continue;
        };
        for q2 in t.0..=t.1 {
            for q1 in s.0..=s.1 {
                let (mut ta, mut tb) = (a[ax], b[ax]);
                if let Some((nrm, o, s0, s1)) = slab {
                    // (X(t) - o).n = n_a t + k0 on the line.
                    let k0 = nrm[b1] * (q1 as f64 - o[b1]) + nrm[b2] * (q2 as f64 - o[b2])
                        - nrm[ax] * o[ax];
                    if nrm[ax].abs() > 1e-3 {
                        let (u, v) = ((s0 - k0) / nrm[ax], (s1 - k0) / nrm[ax]);
                        ta = ta.max(u.min(v));
                        tb = tb.min(u.max(v));
                        if ta > tb {
                            continue;
                        }
                    } else if (k0 + nrm[ax] * a[ax] > s1 + 1e-3 * (b[ax] - a[ax]).abs()
                        && k0 + nrm[ax] * b[ax] > s1 + 1e-3 * (b[ax] - a[ax]).abs())
                        || (k0 + nrm[ax] * a[ax] < s0 - 1e-3 * (b[ax] - a[ax]).abs()
                            && k0 + nrm[ax] * b[ax] < s0 - 1e-3 * (b[ax] - a[ax]).abs())
                    {
                        continue;
                    }
                }
                let Some(r) = vrange(ta, tb, res[ax]) else {
                    continue;
                };
                for q in r.0..=r.1 {
                    let mut v = [0u32; 3];
                    v[ax] = q;
                    v[b1] = q1;
                    v[b2] = q2;
                    if !f(v) {
                        return false;
                    }
                }
            }
        }
    }
    true
}

struct Run<'g, 'a> {
    grid: &'g mut VoxelGrid<'a>,
    /// The corner test of the first walk ([`first_walk_test`]).
    stop_adj: Adjacency,
    thin: bool,
    guard_level: u32,
    aff: Affine,
    /// Held layers as coordinates: a box outside `[zlo_f, zhi_f)` marks
    /// nothing held.
    zlo_f: f64,
    zhi_f: f64,
    /// A proper slab: boxes are computed for every cell (for culling).
    boxed: bool,
    stats: RasterStats,
    /// Cap of `stats.refined` (see [`CERTIFY_CELLS_PER_LEAF`]).
    refine_cap: u64,
    /// Cap of `stats.cells` in the first walk (see [`FIRST_CELLS_PER_VOXEL`]).
    first_cap: u64,
    /// `stats.refined` when the current certification subtree began.
    subtree_start: u64,
    /// The limit that was exceeded, if any.
    exceeded: Option<(u64, &'static str)>,
}

impl Run<'_, '_> {
    #[inline]
    fn bit(&self, v: [i32; 3]) -> Option<(usize, u64)> {
        if v.iter().any(|&c| c < 0) {
            return None;
        }
        self.grid.index(v[0] as u32, v[1] as u32, v[2] as u32)
    }

    #[inline]
    fn culled(&self, n: &Node) -> bool {
        n.hi.z < self.zlo_f || n.lo.z >= self.zhi_f
    }

    /// Whether a cell is a leaf of the first walk. For a polynomial cell `n`
    /// may come from [`poly_corners`]: its box is then computed (with the
    /// slab) only when the adjacency test passes, and `n` is updated.
    #[inline]
    fn decide(&self, n: &mut Node, e: &Entry) -> bool {
        let deepest = e.depth >= MAX_DEPTH || (e.corner == HULL && e.level >= MAX_CELL_LEVEL);
        let pass = deepest || adjacent(&n.vox, self.stop_adj) || e.level > self.guard_level;
        if !pass {
            return false;
        }
        if e.corner == POLY && !self.boxed {
            let (lo, hi) = net_box(&e.net);
            n.lo = lo;
            n.hi = hi;
        }
        deepest || (n.hi - n.lo).max_element() <= LEAF_EXTENT
    }

    /// Pops the top entry (whose geometry is `n`) and pushes its children.
    fn split_top(&mut self, work: &mut VoxelWork, p: &Patch, mode: u8) {
        let top = work.len - 1;
        let (depth, level, corner) = {
            let e = &work.stack[top];
            (e.depth + 1, e.level + 1, e.corner)
        };
        self.stats.max_depth = self.stats.max_depth.max(depth);
        if corner == POLY {
            let parent = work.stack[top].net;
            let pv = work.stack[top].vox;
            work.len = top + 4;
            let [a, b, c, d] = &mut work.stack[top..top + 4] else {
                return;
            };
            for x in [&mut *a, &mut *b, &mut *c, &mut *d] {
                x.corner = POLY;
                x.depth = depth;
                x.level = level;
                x.mode = mode;
            }
            split4_into(&parent, [&mut a.net, &mut b.net, &mut c.net, &mut d.net]);
            // Corner voxels: the parent's four and five new points.
            let (e0, c5, e3) = (
                vox(point(&a.net, 12)),
                vox(point(&a.net, 15)),
                vox(point(&a.net, 3)),
            );
            let (e1, e2) = (vox(point(&b.net, 15)), vox(point(&c.net, 3)));
            a.vox = [pv[0], e0, c5, e3];
            b.vox = [e0, pv[1], e1, c5];
            c.vox = [c5, e1, pv[2], e2];
            d.vox = [e3, c5, e2, pv[3]];
            if mode == 1 {
                // The parent's corners were marked with it (when it was
                // split, or as a subtree root): the five new points remain.
                for v in [e0, c5, e3, e1, e2] {
                    self.mark_voxel(work, v);
                }
            }
        } else if corner == HULL {
            let Patch::Feature(fp) = p else {
                work.len = top;
                return;
            };
            let h = work.stack[top].hull();
            work.len = top;
            if h.level >= MAX_CELL_LEVEL {
                self.stats.guard_hits += 1;
                return;
            }
            for c in h.children(fp, &self.aff) {
                match c {
                    Cell::Poly(net) => {
                        if mode == 1 {
                            self.mark_refined(work, &net_corners(&net));
                        }
                        push_poly(work, net, depth, level, mode);
                    }
                    c => {
                        if let Cell::Hull(k) = &c {
                            if mode == 1 {
                                self.mark_refined(work, &k.corners);
                            }
                        }
                        work.push(Entry::new(c, depth, level, mode));
                    }
                }
            }
        } else if let Patch::Extra {
            tab, ghat, cache, ..
        } = p
        {
            let kids = corner_children(tab, ghat, cache, corner, &self.aff);
            work.len = top;
            work.push(Entry::new(
                Cell::Corner(corner + 1),
                depth,
                corner + 1,
                mode,
            ));
            for k in kids.iter() {
                if mode == 1 {
                    self.mark_refined(work, &net_corners(k));
                }
                push_poly(work, *k, depth, corner + 1, mode);
            }
        } else {
            work.len = top;
        }
    }

    /// Certification marks go to the interior plane (merged at the end) and
    /// to the subtree's local list.
    fn mark_refined(&mut self, work: &mut VoxelWork, cs: &[DVec3; 4]) {
        for c in cs {
            self.mark_voxel(work, vox(*c));
        }
    }

    /// [`Run::mark_refined`] of one corner voxel.
    #[inline]
    fn mark_voxel(&mut self, work: &mut VoxelWork, v: [i32; 3]) {
        if let Some((w, b)) = self.bit(v) {
            self.grid.interior[w] |= b;
            // A voxel black in the first walk's plane needs no entry
            // ([`Run::certified`] reads that plane first).
            if self.grid.surface[w] & b == 0 {
                work.local_add([v[0] as u32, v[1] as u32, v[2] as u32]);
            }
        }
    }

    fn leaf1(&mut self, n: &mut Node, e: &Entry) {
        self.stats.leaves += 1;
        let v = n.vox;
        for q in &v {
            if let Some((w, b)) = self.bit(*q) {
                self.grid.surface[w] |= b;
            }
        }
        let res = self.grid.shape.res;
        if !self.covered_by_own(n) {
            if e.corner == POLY && n.slab.is_none() {
                add_slab(n, &e.net);
            }
            self.mark_required(n, &own_keys(&v, res), res);
        }
        let z = v[0][2] as i64;
        if z >= self.grid.shape.z0 as i64 && z < self.grid.shape.z1 as i64 {
            let c = &n.corners;
            self.stats.quad_area += 0.5 * (c[2] - c[0]).cross(c[3] - c[1]).length();
        }
    }

    /// A cheap sufficient test that a leaf requires no voxel besides its
    /// corner voxels: every voxel [`required`] could list without the slab
    /// (N = 6: the voxels meeting the box shrunk by `TAU`; N = 18/26: the
    /// voxels of the centre lines through the box) is a corner voxel. The
    /// slab only removes voxels, so this implies the full test.
    #[inline]
    fn covered_by_own(&self, n: &Node) -> bool {
        let res = self.grid.shape.res;
        if let Some(c) = self.covered_fast(n) {
            return c;
        }
        let own = &own_keys(&n.vox, res);
        let mut v = [(0u32, 0u32); 3];
        for ax in 0..3 {
            let (mut a, mut b) = (n.lo[ax] + TAU, n.hi[ax] - TAU);
            if a > b {
                a = 0.5 * (n.lo[ax] + n.hi[ax]);
                b = a;
            }
            match vrange(a, b, res[ax]) {
                Some(x) => v[ax] = x,
                None => return true,
            }
        }
        let len = |r: (u32, u32)| (r.1 - r.0 + 1) as u64;
        if !self.thin {
            if len(v[0]) * len(v[1]) * len(v[2]) > 4 {
                return false;
            }
            return Self::all_own(v, own);
        }
        let mut l = [None; 3];
        for ax in 0..3 {
            l[ax] = irange(n.lo[ax], n.hi[ax], res[ax]);
        }
        for ax in 0..3 {
            let (b1, b2) = ((ax + 1) % 3, (ax + 2) % 3);
            let (Some(s), Some(t)) = (l[b1], l[b2]) else {
                continue;
            };
            if len(v[ax]) * len(s) * len(t) > 4 {
                return false;
            }
            let mut r = [(0, 0); 3];
            r[ax] = v[ax];
            r[b1] = s;
            r[b2] = t;
            if !Self::all_own(r, own) {
                return false;
            }
        }
        true
    }

    /// [`Run::covered_by_own`] without `floor`s for the usual leaf: corner
    /// voxels in the grid, at most one apart on every axis. Every voxel the
    /// test lists must lie within the corner voxels' range `[o, o + 1]` per
    /// axis (else some listed voxel is not a corner voxel: false); within
    /// that range the index sets are decided by comparisons with
    /// `o - 0.5, o + 0.5, o + 1.5` (voxel ranges) and `o, o + 1` (integer
    /// lines), and sets of voxels are bit masks over the 2 x 2 x 2 block at
    /// `o` (bit `dx + 2 dy + 4 dz`). None: not the usual leaf.
    #[inline(always)]
    fn covered_fast(&self, n: &Node) -> Option<bool> {
        // Voxels of the block whose offset along an axis is in a 2-bit set.
        const SEL: [[u8; 4]; 3] = [
            [0x00, 0x55, 0xaa, 0xff],
            [0x00, 0x33, 0xcc, 0xff],
            [0x00, 0x0f, 0xf0, 0xff],
        ];
        let res = self.grid.shape.res;
        let mut o = [0i32; 3];
        let mut vm = [0usize; 3];
        let mut lm = [0usize; 3];
        for ax in 0..3 {
            let q = [n.vox[0][ax], n.vox[1][ax], n.vox[2][ax], n.vox[3][ax]];
            let lo_q = q[0].min(q[1]).min(q[2].min(q[3]));
            let top = q[0].max(q[1]).max(q[2].max(q[3]));
            if lo_q < 0 || top - lo_q > 1 || top as u32 >= res[ax] {
                return None;
            }
            o[ax] = lo_q;
            let (mut a, mut b) = (n.lo[ax] + TAU, n.hi[ax] - TAU);
            if a > b {
                a = 0.5 * (n.lo[ax] + n.hi[ax]);
                b = a;
            }
            let of = lo_q as f64;
            // Voxel range [floor(a + 0.5), floor(b + 0.5)] must lie in
            // [o, top]; then it is decided by a, b >= o + 0.5.
            if !(a >= of - 0.5 && b < top as f64 + 0.5) {
                return Some(false);
            }
            let (v0, v1) = ((a >= of + 0.5) as usize, (b >= of + 0.5) as usize);
            vm[ax] = (0b11 >> (1 - v1)) & (0b11 << v0);
            // Integers in [lo, hi]: here lo > o - 1 and hi < top + 0.5 + TAU
            // <= o + 1.5 + TAU, so ceil(lo) is o or o + 1 (or more: empty)
            // and floor(hi) is o - 1 (empty), o or o + 1 (NaN: empty).
            let (lo, hi) = (n.lo[ax], n.hi[ax]);
            let l_o = lo <= of && hi >= of;
            let l_o1 = lo <= of + 1.0 && hi >= of + 1.0;
            lm[ax] = l_o as usize | (l_o1 as usize) << 1;
        }
        let mut own = 0u8;
        for q in &n.vox {
            let d = (q[0] - o[0]) + 2 * (q[1] - o[1]) + 4 * (q[2] - o[2]);
            own |= 1 << d;
        }
        let listed = if !self.thin {
            SEL[0][vm[0]] & SEL[1][vm[1]] & SEL[2][vm[2]]
        } else {
            // Lines along x: x in the voxel range, y and z integers; etc.
            (SEL[0][vm[0]] & SEL[1][lm[1]] & SEL[2][lm[2]])
                | (SEL[0][lm[0]] & SEL[1][vm[1]] & SEL[2][lm[2]])
                | (SEL[0][lm[0]] & SEL[1][lm[1]] & SEL[2][vm[2]])
        };
        Some(listed & !own == 0)
    }

    #[inline]
    fn all_own(r: [(u32, u32); 3], own: &[u64; 4]) -> bool {
        for k in r[2].0..=r[2].1 {
            for j in r[1].0..=r[1].1 {
                for i in r[0].0..=r[0].1 {
                    if !owns(own, [i, j, k]) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Marks the voxels a leaf requires (kept out of line: after
    /// [`Run::covered_by_own`] only about one leaf in six gets here).
    #[inline(never)]
    fn mark_required(&mut self, n: &Node, own: &[u64; 4], res: [u32; 3]) {
        let thin = self.thin;
        let grid = &mut *self.grid;
        required(n, thin, res, |r| {
            if !owns(own, r) {
                if let Some((w, b)) = grid.index(r[0], r[1], r[2]) {
                    grid.work[w] |= b;
                }
            }
            true
        });
    }

    /// Geometry of the top cell for a walk: full for corner cells and in
    /// slab mode, corners only otherwise.
    #[inline]
    fn top_node(&self, work: &VoxelWork, p: &Patch) -> Node {
        let e = &work.stack[work.len - 1];
        if e.corner == POLY && !self.boxed {
            poly_corners(e)
        } else {
            node_info(e, p, &self.aff, false)
        }
    }

    /// First walk of one pre-split cell.
    fn walk1(&mut self, work: &mut VoxelWork, p: &Patch) {
        while work.len > 0 {
            self.stats.cells += 1;
            if self.stats.cells > self.first_cap {
                self.exceeded = Some((self.first_cap, "cells of the voxel first walk"));
                work.len = 0;
                return;
            }
            let top = work.len - 1;
            let mut n = self.top_node(work, p);
            if self.boxed && self.culled(&n) {
                work.len = top;
                continue;
            }
            if self.decide(&mut n, &work.stack[top]) || work.len + 4 > STACK_CAP {
                if work.stack[top].corner == POLY && n.hi == n.lo {
                    n = node_info(&work.stack[top], p, &self.aff, false);
                }
                self.leaf1(&mut n, &work.stack[top]);
                work.len = top;
            } else {
                self.split_top(work, p, 0);
            }
        }
    }

    /// Whether the voxels meeting `[lo, hi]` include an uncovered one.
    fn touches_uncovered(&self, lo: DVec3, hi: DVec3) -> bool {
        let res = self.grid.shape.res;
        let (Some(x), Some(y), Some(z)) = (
            vrange(lo.x, hi.x, res[0]),
            vrange(lo.y, hi.y, res[1]),
            vrange(lo.z, hi.z, res[2]),
        ) else {
            return false;
        };
        let wpr = self.grid.shape.wpr;
        for k in z.0..=z.1 {
            for j in y.0..=y.1 {
                let Some(r) = self.grid.shape.row(j, k) else {
                    continue;
                };
                for w in (x.0 / 64)..=(x.1 / 64) {
                    let lo_b = if w == x.0 / 64 { x.0 % 64 } else { 0 };
                    let hi_b = if w == x.1 / 64 { x.1 % 64 } else { 63 };
                    let mask = (!0u64 >> (63 - hi_b)) & (!0u64 << lo_b);
                    if self.grid.work[r * wpr + w as usize] & mask != 0 {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Whether every voxel the cell requires is black in the first walk's
    /// surface plane, in the local list, or not held.
    fn certified(&self, work: &VoxelWork, n: &Node) -> bool {
        let res = self.grid.shape.res;
        let grid = &*self.grid;
        required(n, self.thin, res, |r| match grid.index(r[0], r[1], r[2]) {
            Some((w, b)) => grid.surface[w] & b != 0 || work.local_has(r),
            None => true,
        })
    }

    /// Certification walk of one pre-split cell.
    fn walk2(&mut self, work: &mut VoxelWork, p: &Patch) {
        while work.len > 0 {
            let top = work.len - 1;
            let (depth, mut mode) = (work.stack[top].depth, work.stack[top].mode);
            // Corners and box only: the slab is computed when the box alone
            // does not certify the cell (see below).
            let mut n = node_info(&work.stack[top], p, &self.aff, false);
            if self.culled(&n) {
                work.len = top;
                continue;
            }
            if mode == 0 {
                // Not for hull cells: a polynomial child's net (phantom
                // points across sharp edges) may reach beyond its parent's
                // hull box, so the box does not bound the subtree's needs.
                if work.stack[top].corner == POLY && !self.touches_uncovered(n.lo, n.hi) {
                    work.len = top;
                    continue;
                }
                if !(self.decide(&mut n, &work.stack[top]) || work.len + 4 > STACK_CAP) {
                    self.split_top(work, p, 0);
                    continue;
                }
                // A first-walk leaf: root of a certification subtree.
                work.nlocal = 0;
                self.subtree_start = self.stats.refined;
                mode = 2;
                work.stack[top].mode = 2;
            }
            self.stats.refined += 1;
            let sub = self.stats.refined - self.subtree_start;
            self.stats.max_subtree = self.stats.max_subtree.max(sub);
            if self.stats.refined > self.refine_cap {
                self.exceeded = Some((self.refine_cap, "cells of the voxel certification walk"));
            } else if sub > CERTIFY_SUBTREE_CELLS {
                self.exceeded = Some((
                    CERTIFY_SUBTREE_CELLS,
                    "cells of one voxel certification subtree",
                ));
            }
            if self.exceeded.is_some() {
                work.len = 0;
                return;
            }
            if mode == 1 {
                // Polynomial and hull cells were marked when split.
                if work.stack[top].corner != POLY && work.stack[top].corner != HULL {
                    self.mark_refined(work, &n.corners);
                }
            } else {
                for q in &n.vox {
                    if let Some((w, b)) = self.bit(*q) {
                        if self.grid.surface[w] & b == 0 {
                            work.local_add([q[0] as u32, q[1] as u32, q[2] as u32]);
                        }
                    }
                }
            }
            // The slab only removes required voxels: a cell the box alone
            // certifies is certified with it.
            let done = (n.hi - n.lo).max_element() <= TAU
                || self.certified(work, &n)
                || (work.stack[top].corner == POLY && {
                    add_slab(&mut n, &work.stack[top].net);
                    n.slab.is_some() && self.certified(work, &n)
                });
            if done {
                work.len = top;
                continue;
            }
            if depth >= MAX_DEPTH || work.len + 4 > STACK_CAP {
                self.stats.guard_hits += 1;
                work.len = top;
                continue;
            }
            self.split_top(work, p, 1);
        }
    }
}

/// `floor(log2(m))`.
fn floor_log2(m: u32) -> u32 {
    31 - m.max(1).leading_zeros()
}

impl VoxelGrid<'_> {
    /// Voxelizes the limit surface of `ev` into this grid (clearing it
    /// first): the paper's algorithm `Voxelization(S, N, M1, M2, M3, k)`
    /// plus the certification walk (see the module docs of
    /// [`super::rasterize`]).
    ///
    /// `transform`: the model-to-voxel map; None normalises the model into
    /// the grid ([`super::fit_transform`]). A given transform must map the
    /// whole limit surface into `[-0.5, M - 0.5)` on every axis (checked
    /// against a guaranteed bound), else `InvalidArgument`. For slab grids
    /// of one model pass the same transform to every slab.
    ///
    /// On a feature mesh, cells that are not polynomial at their level
    /// ([`crate::eval::CellGeom::Hull`]) have exact corners (evaluated) and
    /// the box of their control points' hull: the certification treats
    /// that box as it treats a Bezier net's, so the guarantees hold.
    ///
    /// Work: the first walk stops at the recursion guard or [`MAX_DEPTH`];
    /// the certification walk is capped (see [`CERTIFY_CELLS_PER_LEAF`],
    /// [`CERTIFY_SUBTREE_CELLS`]).
    ///
    /// Rounding: the patch data and the map into voxel space are exact up
    /// to `TERM eps M` model units (`M` the largest coordinate magnitude;
    /// [`crate::bounds::rounding`]); that many voxels at most
    /// [`MAX_ROUNDING_VOXELS`] keep every certified surface point within
    /// `TAU + 1/4 < 1/2` voxel of a black voxel of its centre line, which
    /// is what separability needs (module docs).
    ///
    /// Errors: `InvalidArgument` (presplit not a power of two in 1..=64,
    /// transform), `EmptyMesh`, `NotClosedSolid` (feature meshes with a
    /// boundary, a hole or a non-manifold element), `WorkLimitExceeded`
    /// (first-walk or certification cap), `CoordinateRange` (coordinates outside
    /// `2^-200..2^200`, a model size below `2^-200`, or rounding above
    /// [`MAX_ROUNDING_VOXELS`]: a model too small for its distance from the
    /// origin at this resolution).
    pub fn voxelize<S: Surface + ?Sized>(
        &mut self,
        ev: &S,
        params: &VoxelParams,
        transform: Option<VoxelTransform>,
        work: &mut VoxelWork,
    ) -> Result<RasterStats, Error> {
        let k = params.presplit;
        if !(1..=64).contains(&k) || !k.is_power_of_two() {
            return Err(Error::InvalidArgument(
                "presplit must be a power of two in 1..=64",
            ));
        }
        if params.res != self.shape.res {
            return Err(Error::InvalidArgument(
                "params.res differs from the grid's resolution",
            ));
        }
        ev.check_solid()?;
        let (lo, hi) = super::bounds::limit_bounds(ev, work)?;
        let t = match transform {
            None => super::bounds::fit_box(lo, hi, self.shape.res)?,
            Some(t) => {
                if !(t.scale.is_finite() && t.scale > 0.0 && t.offset.iter().all(|o| o.is_finite()))
                {
                    return Err(Error::InvalidArgument(
                        "transform is not finite and positive",
                    ));
                }
                let (a, b) = (t.to_voxel(lo), t.to_voxel(hi));
                for ax in 0..3 {
                    if !(a[ax] >= -0.5 && b[ax] < self.shape.res[ax] as f64 - 0.5) {
                        return Err(Error::InvalidArgument(
                            "transform does not map the limit surface into the grid",
                        ));
                    }
                }
                t
            }
        };
        rounding_check(lo, hi, t.scale)?;
        if self.state != GridState::Empty {
            self.clear();
        }
        self.transform = t;
        let thin = params.adjacency != Adjacency::Six;
        self.thin = thin;
        let res = self.shape.res;
        let (zlo, zhi) = (self.shape.zlo, self.shape.zhi);
        let np = ev.patch_count();
        let mut run = Run {
            grid: self,
            stop_adj: first_walk_test(params.adjacency),
            thin,
            guard_level: floor_log2(res[0].max(res[1]).max(res[2])),
            aff: Affine {
                scale: t.scale,
                offset: DVec3::from_array(t.offset),
            },
            zlo_f: zlo as f64 - 0.5,
            zhi_f: zhi as f64 - 0.5,
            boxed: zlo > 0 || zhi < res[2],
            stats: RasterStats::default(),
            refine_cap: u64::MAX,
            first_cap: {
                let roots = (np as u64).saturating_mul((k as u64) * (k as u64));
                let voxels = res.iter().fold(1u64, |a, &r| a.saturating_mul(r as u64));
                FIRST_CELLS_MIN
                    .saturating_add(FIRST_CELLS_PER_ROOT.saturating_mul(roots))
                    .saturating_add(FIRST_CELLS_PER_VOXEL.saturating_mul(voxels))
            },
            subtree_start: 0,
            exceeded: None,
        };
        let kk = k.trailing_zeros();
        for pass in 0..2 {
            if pass == 1 {
                // Uncovered = required and not black.
                let mut count = 0u64;
                for (w, s) in run.grid.work.iter_mut().zip(run.grid.surface.iter()) {
                    *w &= !*s;
                    count += w.count_ones() as u64;
                }
                run.stats.uncovered = count;
                if count == 0 {
                    break;
                }
                run.refine_cap = CERTIFY_CELLS_MIN
                    .saturating_add(CERTIFY_CELLS_PER_LEAF.saturating_mul(run.stats.leaves));
            }
            for pi in 0..np {
                let Some(p) = ev.patch_at(pi) else {
                    run.grid.clear();
                    return Err(Error::InvalidArgument("patch table"));
                };
                let (hl, hh) = patch_hull(&p);
                let (hl, hh) = (run.aff.apply(hl), run.aff.apply(hh));
                if hh.z < run.zlo_f || hl.z >= run.zhi_f {
                    continue;
                }
                let aff = run.aff;
                for_each_root(&p, k, &aff, |cell| {
                    work.len = 0;
                    match cell {
                        Cell::Poly(net) => push_poly(work, net, 0, kk, 0),
                        Cell::Corner(_) | Cell::Hull(_) => {
                            work.push(Entry::new(cell, 0, kk, 0));
                        }
                    }
                    if pass == 0 {
                        run.walk1(work, &p);
                    } else if run.exceeded.is_none() {
                        run.walk2(work, &p);
                    }
                });
                if let Some((limit, what)) = run.exceeded {
                    run.grid.clear();
                    return Err(Error::WorkLimitExceeded { limit, what });
                }
            }
        }
        let mut stats = run.stats;
        stats.quad_area /= t.scale * t.scale;
        // Merge the certification's marks; leave the scratch planes clear.
        for ((s, i), w) in self
            .surface
            .iter_mut()
            .zip(self.interior.iter_mut())
            .zip(self.work.iter_mut())
        {
            *s |= *i;
            *i = 0;
            *w = 0;
        }
        self.state = GridState::Voxelized;
        Ok(stats)
    }
}
