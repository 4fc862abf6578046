//! Parameter cells of the patch table as bicubic Bezier nets.
//!
//! Every patch of the [`Evaluator`] is a union of polynomial pieces: a
//! regular patch is one bicubic B-spline; an extraordinary patch is the
//! union of the regions `Omega_{m,b}` (\[CL-R §2.1\], each one bicubic over
//! its own unit square) plus the extraordinary vertex itself. The voxelizer,
//! the ray test and the bounding box walk these pieces as
//!
//! * [`Cell::Poly`]: a bicubic **Bezier net** (exact conversion from the
//!   B-spline grid over a sub-interval). The corners of the net are exact
//!   limit points, and the surface over the cell lies in the convex hull of
//!   the net, so its axis-aligned box is a guaranteed bound; midpoint de
//!   Casteljau splitting gives the four children exactly.
//! * [`Cell::Corner`]: the corner square `[0, 2^-level]^2` at an
//!   extraordinary vertex: every point is within
//!   [`crate::eigen::ValenceTable::corner_radius`] of the limit point `L`. It splits
//!   into the three regions `Omega_{level+1, b}` and the next corner.
//!
//! Nets are stored in the caller's coordinates after an affine map
//! `x -> scale x + offset` (voxel coordinates for the voxelizer): affine maps
//! commute with Bezier and B-spline combinations.

use crate::eigen::ValenceTable;
use crate::error::Error;
use crate::eval::{CellGeom, Evaluator, FeatureEvaluator};
use crate::math::bezier;
use crate::math::bspline::Grid;
use glam::DVec3;

/// The nets, their split, box and corners are those of [`crate::math::bezier`]
/// (the tessellation's kernels; a net is `P[k*4 + l]` per coordinate, `k`
/// along u, `l` along v).
pub(crate) use crate::math::bezier::{
    corners as net_corners, net_box, plane_range, point, split4, split4_parts as split4_into, Net,
};

/// `x -> scale * x + offset`, applied to model points.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Affine {
    pub scale: f64,
    pub offset: DVec3,
}

impl Affine {
    pub const IDENTITY: Affine = Affine {
        scale: 1.0,
        offset: DVec3::ZERO,
    };
    #[inline]
    pub fn apply(&self, p: DVec3) -> DVec3 {
        p * self.scale + self.offset
    }
}

/// One patch of the table.
#[derive(Clone, Copy)]
pub enum Patch<'e> {
    /// Bicubic B-spline grid (model coordinates).
    Regular(&'e Grid),
    /// Extraordinary patch: its table, eigen projection `ghat`, the cached
    /// region grids of levels 1 and 2 (empty when the evaluator does not
    /// store them: [`crate::EvaluatorOptions`]), and its 2n+8 control
    /// points (x y z interleaved).
    Extra {
        tab: &'e ValenceTable,
        ghat: &'e [f64],
        cache: &'e [f64],
        ctrl: &'e [f64],
    },
    /// One level-1 face of a [`FeatureEvaluator`] (a quadrant of a quad
    /// base face, or a sub-face of an N-gon); its cells are named in the
    /// base face's parameters: see [`FeaturePatch`].
    Feature(FeaturePatch<'e>),
}

/// A level-1 face of a feature mesh as a patch: base face `face`,
/// sub-face `sub`; cells of level `l >= base` of the sub-face with index
/// `(i, j)` inside `[i0, i0 + 2^(l - base)) x [j0, ...)` (in level-`l`
/// units) belong to it. `base` is 1 for a quadrant of a quad face, 0 for
/// a sub-face of an N-gon.
#[derive(Clone, Copy)]
pub struct FeaturePatch<'e> {
    pub fe: &'e FeatureEvaluator<'e, 'e>,
    pub face: u32,
    pub sub: u32,
    pub base: u32,
    pub i0: u32,
    pub j0: u32,
}

/// The surfaces the voxel algorithms walk: patches of polynomial pieces,
/// extraordinary corners and (feature meshes) convex-hull cells. Sealed:
/// implemented by [`Evaluator`] and [`FeatureEvaluator`].
pub trait Source {
    /// Number of patches.
    fn patch_count(&self) -> usize;
    /// Patch `pi` (None if the data is inconsistent).
    fn patch_at(&self, pi: usize) -> Option<Patch<'_>>;
    /// Ok if the surface bounds a solid (see [`super::solid`]).
    fn check_solid(&self) -> Result<(), crate::error::Error>;
}

impl Source for Evaluator<'_> {
    #[inline]
    fn patch_count(&self) -> usize {
        num_patches(self)
    }
    #[inline]
    fn patch_at(&self, pi: usize) -> Option<Patch<'_>> {
        patch(self, pi)
    }
    /// A [`crate::mesh::Topology`] is closed, oriented and manifold.
    #[inline]
    fn check_solid(&self) -> Result<(), crate::error::Error> {
        Ok(())
    }
}

impl<'m, 'a> Source for FeatureEvaluator<'m, 'a> {
    fn check_solid(&self) -> Result<(), crate::error::Error> {
        super::solid::check_closed_solid(self.mesh())
    }
    fn patch_count(&self) -> usize {
        self.mesh().level1.num_faces()
    }
    fn patch_at(&self, pi: usize) -> Option<Patch<'_>> {
        let fm = self.mesh();
        let off = fm.base.face_off;
        // Base face f with face_off[f] <= pi < face_off[f + 1].
        let f = off.partition_point(|&o| o as usize <= pi).checked_sub(1)?;
        if f >= fm.num_faces() {
            return None;
        }
        let k = pi - off[f] as usize;
        // Shorten the lifetimes (the evaluator is covariant in both).
        let fe: &FeatureEvaluator<'_, '_> = self;
        Some(Patch::Feature(if fm.base.face(f).len() == 4 {
            let (ci, cj) = quadrant_offset(k);
            FeaturePatch {
                fe,
                face: f as u32,
                sub: 0,
                base: 1,
                i0: ci,
                j0: cj,
            }
        } else {
            FeaturePatch {
                fe,
                face: f as u32,
                sub: k as u32,
                base: 0,
                i0: 0,
                j0: 0,
            }
        }))
    }
}

/// `(i, j)` of quadrant `q` (0: `(0,0)`, 1: `(1,0)`, 2: `(1,1)`, 3: `(0,1)`).
#[inline]
pub(crate) fn quadrant_offset(q: usize) -> (u32, u32) {
    match q {
        0 => (0, 0),
        1 => (1, 0),
        2 => (1, 1),
        _ => (0, 1),
    }
}

/// What a feature cell is, in the caller's coordinates.
#[allow(clippy::large_enum_variant)] // a by-value result (no heap)
pub(crate) enum FCell {
    /// A polynomial piece as a Bezier net.
    Poly(Net),
    /// A hull cell: exact corner points (counter-clockwise from
    /// `(u0, v0)`) and a box containing the surface over the cell.
    Hull {
        corners: [DVec3; 4],
        lo: DVec3,
        hi: DVec3,
    },
}

impl FeaturePatch<'_> {
    /// Whether the face is a hole (no surface, no cells).
    pub fn is_hole(&self) -> bool {
        let fm = self.fe.mesh();
        fm.hole[fm.child_face(self.face as usize, 0)] != 0
    }

    /// Cell `(level, i, j)` of the sub-face mapped by `a`. A hull cell's
    /// corners are evaluated exactly; cells the evaluator refuses (levels
    /// above [`crate::eval::MAX_CELL_LEVEL`], capacity) come back as hull cells with an
    /// infinite box and NaN corners, which no walk accepts as a leaf and
    /// which stop at the walks' depth guards.
    pub(crate) fn cell(&self, level: u32, i: u32, j: u32, a: &Affine) -> FCell {
        // Levels above MAX_CELL_LEVEL are the evaluator's errors.
        self.of_geom(
            self.fe.cell(self.face, self.sub, level, i, j),
            level,
            i,
            j,
            a,
        )
    }

    /// The four children of cell `(level, i, j)` (quadrant order of
    /// [`quadrant_offset`]), each as [`FeaturePatch::cell`] gives it, from
    /// one local descent ([`FeatureEvaluator::cell_children`]).
    pub(crate) fn children(&self, level: u32, i: u32, j: u32, a: &Affine) -> [FCell; 4] {
        let geoms = self.fe.cell_children(self.face, self.sub, level, i, j);
        core::array::from_fn(|q| {
            let (di, dj) = quadrant_offset(q);
            let g = geoms.as_ref().map(|g| g[q]).map_err(|e| *e);
            self.of_geom(g, level + 1, 2 * i + di, 2 * j + dj, a)
        })
    }

    /// Cell `(level, i, j)` from its geometry (see [`FeaturePatch::cell`]).
    fn of_geom(
        &self,
        geom: Result<CellGeom, Error>,
        level: u32,
        i: u32,
        j: u32,
        a: &Affine,
    ) -> FCell {
        let bad = FCell::Hull {
            corners: [DVec3::NAN; 4],
            lo: DVec3::NEG_INFINITY,
            hi: DVec3::INFINITY,
        };
        match geom {
            Ok(CellGeom::Poly { grid, rect }) => {
                // net_over_points reads point `i * 4 + j` (i along u); the
                // cell's grid is row by row (`j * 4 + i`).
                let pt = |k: usize| a.apply(grid[(k % 4) * 4 + k / 4]);
                FCell::Poly(bezier::net_over_points(
                    pt, rect[0], rect[1], rect[2], rect[3],
                ))
            }
            Ok(CellGeom::Hull(h)) => {
                let h0 = 1.0 / (1u64 << level) as f64;
                let (u0, v0) = (i as f64 * h0, j as f64 * h0);
                let (u1, v1) = ((i + 1) as f64 * h0, (j + 1) as f64 * h0);
                let mut corners = [DVec3::NAN; 4];
                for (c, (u, v)) in corners
                    .iter_mut()
                    .zip([(u0, v0), (u1, v0), (u1, v1), (u0, v1)])
                {
                    if let Ok(e) = self.fe.eval(self.face, self.sub, u, v) {
                        *c = a.apply(e.p);
                    }
                }
                if corners.iter().any(|c| !c.is_finite()) {
                    return bad;
                }
                FCell::Hull {
                    corners,
                    lo: a.apply(h.lo),
                    hi: a.apply(h.hi),
                }
            }
            // Split (a level-0 quad cell) never reaches here: patches of
            // quad faces start at level 1.
            Ok(CellGeom::Split) | Err(_) => bad,
        }
    }

    /// The root cell of the patch (level `base`).
    pub(crate) fn root(&self, a: &Affine) -> FCell {
        self.cell(self.base, self.i0, self.j0, a)
    }
}

/// Number of patches of the table.
#[inline]
pub(crate) fn num_patches(ev: &Evaluator) -> usize {
    ev.patch_meta.len().min(ev.patch_data.len())
}

/// Patch `pi` (None if its data is inconsistent, which a built evaluator
/// never is).
pub(crate) fn patch<'e>(ev: &'e Evaluator, pi: usize) -> Option<Patch<'e>> {
    let meta = *ev.patch_meta.get(pi)?;
    let n = (meta & 0xff) as usize;
    let o = *ev.patch_data.get(pi)? as usize;
    if n == 4 {
        let g = ev.data.get(o..o + 48)?;
        return <&Grid>::try_from(g).ok().map(Patch::Regular);
    }
    let tab = ev.tables.get(n)?;
    let lay = ev.ev_layout(o, n);
    Some(Patch::Extra {
        tab,
        ghat: ev.data.get(lay.ghat())?,
        // Empty when the evaluator does not store the grids
        // (`region_grid` then makes them, bit for bit).
        cache: ev.data.get(lay.grids())?,
        ctrl: ev.data.get(lay.points())?,
    })
}

/// Axis-aligned box of the control points of a patch (model coordinates):
/// the limit surface of the patch lies in their convex hull (every
/// Catmull-Clark rule is a convex combination).
pub(crate) fn patch_hull(p: &Patch) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    match p {
        Patch::Regular(g) => {
            for i in 0..16 {
                let q = DVec3::new(g[i], g[16 + i], g[32 + i]);
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
        Patch::Extra { ctrl, .. } => {
            for c in ctrl.chunks_exact(3) {
                let q = DVec3::new(c[0], c[1], c[2]);
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
        Patch::Feature(fp) => {
            if fp.is_hole() {
                return (lo, hi);
            }
            match fp.root(&Affine::IDENTITY) {
                FCell::Poly(n) => return net_box(&n),
                FCell::Hull { lo, hi, .. } => return (lo, hi),
            }
        }
    }
    (lo, hi)
}

/// Bezier net of the B-spline grid `g` over `[u1,u2] x [v1,v2]` (patch or
/// region coordinates), mapped by `a` (each control point first, then
/// [`bezier::net_over_points`]).
pub(crate) fn grid_net(g: &Grid, u1: f64, u2: f64, v1: f64, v2: f64, a: &Affine) -> Net {
    let pt = |i: usize| a.apply(DVec3::new(g[i], g[16 + i], g[32 + i]));
    bezier::net_over_points(pt, u1, u2, v1, v2)
}

/// A cell of a patch (see module docs).
#[derive(Clone, Copy)]
#[allow(clippy::large_enum_variant)] // passed by value once per root
pub enum Cell {
    /// Bicubic piece as a Bezier net.
    Poly(Net),
    /// Corner square `[0, 2^-level]^2` of the current extraordinary patch.
    Corner(u32),
    /// A hull cell of a feature patch (see [`HullCell`]).
    Hull(HullCell),
}

/// A feature cell that is not polynomial: cell `(level, i, j)` of its
/// sub-face, exact corners and a box containing its surface (caller
/// coordinates).
#[derive(Clone, Copy)]
pub struct HullCell {
    pub level: u32,
    pub i: u32,
    pub j: u32,
    pub corners: [DVec3; 4],
    pub lo: DVec3,
    pub hi: DVec3,
}

impl HullCell {
    /// The four children of this cell (quadrant order of
    /// [`quadrant_offset`]), as cells, from one local descent.
    pub(crate) fn children(&self, p: &FeaturePatch, a: &Affine) -> [Cell; 4] {
        let kids = p.children(self.level, self.i, self.j, a);
        let mut q = 0;
        kids.map(|c| {
            let (di, dj) = quadrant_offset(q);
            q += 1;
            as_cell(c, self.level + 1, 2 * self.i + di, 2 * self.j + dj)
        })
    }
}

/// Cell `(level, i, j)` of a feature patch as a [`Cell`].
pub(crate) fn feature_cell(p: &FeaturePatch, level: u32, i: u32, j: u32, a: &Affine) -> Cell {
    as_cell(p.cell(level, i, j, a), level, i, j)
}

/// A feature cell `(level, i, j)` as a [`Cell`].
fn as_cell(c: FCell, level: u32, i: u32, j: u32) -> Cell {
    match c {
        FCell::Poly(n) => Cell::Poly(n),
        FCell::Hull { corners, lo, hi } => Cell::Hull(HullCell {
            level,
            i,
            j,
            corners,
            lo,
            hi,
        }),
    }
}

/// Region grid `Omega_{m,b}` of an extraordinary patch (with the limit
/// term): the cached grids for m = 1, 2, else computed.
pub(crate) fn region_grid(
    tab: &ValenceTable,
    ghat: &[f64],
    cache: &[f64],
    m: u32,
    b: usize,
    out: &mut Grid,
) {
    if (1..=2).contains(&m) && cache.len() >= 288 {
        let i = ((m as usize - 1) * 3 + b - 1) * 48;
        out.copy_from_slice(&cache[i..i + 48]);
    } else {
        tab.sub_patch(ghat, m.max(1), b, true, out);
    }
}

/// Limit point `L` of an extraordinary patch (model coordinates).
#[inline]
pub(crate) fn limit_point(ghat: &[f64]) -> DVec3 {
    DVec3::new(ghat[0], ghat[1], ghat[2])
}

/// The three region nets `Omega_{level+1, b}`, b = 1, 2, 3 (the children of
/// corner cell `level` besides the next corner), mapped by `a`.
pub(crate) fn corner_children(
    tab: &ValenceTable,
    ghat: &[f64],
    cache: &[f64],
    level: u32,
    a: &Affine,
) -> [Net; 3] {
    let mut out = [[0.0; 48]; 3];
    for (bi, o) in out.iter_mut().enumerate() {
        let mut g = [0.0; 48];
        region_grid(tab, ghat, cache, level + 1, bi + 1, &mut g);
        *o = grid_net(&g, 0.0, 1.0, 0.0, 1.0, a);
    }
    out
}

/// Corners S(0,0) = L, S(2^-l, 0), S(2^-l, 2^-l), S(0, 2^-l) of corner
/// cell `l`, from its three region children (in the same coordinates).
#[inline]
pub(crate) fn corner_corners(l_point: DVec3, kids: &[Net; 3]) -> [DVec3; 4] {
    [
        l_point,
        point(&kids[0], 12),
        point(&kids[1], 15),
        point(&kids[2], 3),
    ]
}

/// Calls `f` with the `k x k` pre-split root cells of a patch (`k` a power of
/// two, 1..=64), mapped by `a`. For an extraordinary patch the cell at the
/// vertex is [`Cell::Corner`] and every other cell lies in one region
/// `Omega_{m,b}` (k is a power of two).
pub(crate) fn for_each_root(p: &Patch, k: u32, a: &Affine, mut f: impl FnMut(Cell)) {
    let kk = k.trailing_zeros();
    let kf = k as f64;
    match p {
        Patch::Regular(g) => {
            for i in 0..k {
                for j in 0..k {
                    let (u1, v1) = (i as f64 / kf, j as f64 / kf);
                    let (u2, v2) = ((i + 1) as f64 / kf, (j + 1) as f64 / kf);
                    f(Cell::Poly(grid_net(g, u1, u2, v1, v2, a)));
                }
            }
        }
        Patch::Extra {
            tab, ghat, cache, ..
        } => {
            let mut g = [0.0; 48];
            let mut last = (0u32, 0usize);
            for i in 0..k {
                for j in 0..k {
                    if i == 0 && j == 0 {
                        f(Cell::Corner(kk));
                        continue;
                    }
                    let mx = i.max(j); // in [2^(kk-m), 2^(kk-m+1))
                    let m = kk - (31 - mx.leading_zeros());
                    let edge = 1u32 << (kk - m); // 2^-m in units of 1/k
                    let b = match (i >= edge, j >= edge) {
                        (true, false) => 1usize,
                        (true, true) => 2,
                        _ => 3,
                    };
                    if last != (m, b) {
                        region_grid(tab, ghat, cache, m, b, &mut g);
                        last = (m, b);
                    }
                    let s = libm::scalbn(1.0, m as i32) / kf; // region units per cell
                    let du = if b <= 2 { 1.0 } else { 0.0 };
                    let dv = if b >= 2 { 1.0 } else { 0.0 };
                    let (u1, v1) = (i as f64 * s - du, j as f64 * s - dv);
                    f(Cell::Poly(grid_net(&g, u1, u1 + s, v1, v1 + s, a)));
                }
            }
        }
        Patch::Feature(fp) => {
            if fp.is_hole() {
                return;
            }
            // Top-down from the patch: a polynomial cell gives all its root
            // cells as sub-rectangles of one grid (one evaluator call, not
            // one local refinement per root); hull cells split.
            let target = fp.base + kk;
            const CAP: usize = 3 * 6 + 4;
            let mut st = [(0u32, 0u32, 0u32); CAP];
            st[0] = (fp.base, fp.i0, fp.j0);
            let mut n = 1usize;
            while n > 0 {
                n -= 1;
                let (l, i, j) = st[n];
                match fp.fe.cell(fp.face, fp.sub, l, i, j) {
                    Ok(CellGeom::Poly { grid, rect }) => {
                        let m = 1u32 << (target - l);
                        let h = (rect[1] - rect[0]) / m as f64;
                        let pt = |q: usize| a.apply(grid[(q % 4) * 4 + q / 4]);
                        for ii in 0..m {
                            for jj in 0..m {
                                let (u0, v0) = (rect[0] + ii as f64 * h, rect[2] + jj as f64 * h);
                                f(Cell::Poly(bezier::net_over_points(
                                    pt,
                                    u0,
                                    u0 + h,
                                    v0,
                                    v0 + h,
                                )));
                            }
                        }
                    }
                    Ok(CellGeom::Hull(_)) | Err(_) if l >= target => {
                        f(feature_cell(fp, l, i, j, a));
                    }
                    _ => {
                        for q in 0..4 {
                            let (di, dj) = quadrant_offset(q);
                            st[n] = (l + 1, 2 * i + di, 2 * j + dj);
                            n += 1;
                        }
                    }
                }
            }
        }
    }
}
