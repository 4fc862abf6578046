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
use crate::eval::Evaluator;
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
pub(crate) enum Patch<'e> {
    /// Bicubic B-spline grid (model coordinates).
    Regular(&'e Grid),
    /// Extraordinary patch: its table, eigen projection `ghat`, the cached
    /// region grids of levels 1 and 2, and its 2n+8 control points (x y z
    /// interleaved).
    Extra {
        tab: &'e ValenceTable,
        ghat: &'e [f64],
        cache: &'e [f64],
        ctrl: &'e [f64],
    },
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
    let k = 2 * n + 8;
    Some(Patch::Extra {
        tab,
        ghat: ev.data.get(o..o + 3 * k)?,
        cache: ev.data.get(o + 3 * k..o + 3 * k + 288)?,
        ctrl: ev.data.get(o + 3 * k + 288..o + 6 * k + 288)?,
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
pub(crate) enum Cell {
    /// Bicubic piece as a Bezier net.
    Poly(Net),
    /// Corner square `[0, 2^-level]^2` of the current extraordinary patch.
    Corner(u32),
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
    }
}
