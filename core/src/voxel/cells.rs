//! Parameter cells of the patch table as bicubic Bezier nets.
//!
//! Every patch of the [`Evaluator`] is a union of polynomial pieces: a
//! regular patch is one bicubic B-spline; an extraordinary patch is the
//! union of the regions `Omega_{m,b}` (report §2.1, each one bicubic over
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

use crate::eigen::table::ValenceTable;
use crate::eval::Evaluator;
use crate::math::bspline::{basis, Grid};
use glam::DVec3;

/// Bicubic Bezier control net `P[k*4 + l]`, `k` along u, `l` along v.
pub(crate) type Net = [DVec3; 16];

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

/// Bezier coefficients over `[t1, t2]` of the cubic `sum_i g_i B_i(t)`.
#[inline]
fn bezier4(
    g: [DVec3; 4],
    b1: &([f64; 4], [f64; 4]),
    b2: &([f64; 4], [f64; 4]),
    h: f64,
) -> [DVec3; 4] {
    let dot = |w: &[f64; 4]| g[0] * w[0] + g[1] * w[1] + g[2] * w[2] + g[3] * w[3];
    let (p1, q1, p2, q2) = (dot(&b1.0), dot(&b1.1), dot(&b2.0), dot(&b2.1));
    [p1, p1 + q1 * h, p2 - q2 * h, p2]
}

/// Bezier net of the B-spline grid `g` over `[u1,u2] x [v1,v2]` (patch or
/// region coordinates), mapped by `a`.
pub(crate) fn grid_net(g: &Grid, u1: f64, u2: f64, v1: f64, v2: f64, a: &Affine) -> Net {
    let pt = |i: usize, j: usize| {
        a.apply(DVec3::new(
            g[i * 4 + j],
            g[16 + i * 4 + j],
            g[32 + i * 4 + j],
        ))
    };
    let bu1 = {
        let (b, d, _) = basis(u1);
        (b, d)
    };
    let bu2 = {
        let (b, d, _) = basis(u2);
        (b, d)
    };
    let bv1 = {
        let (b, d, _) = basis(v1);
        (b, d)
    };
    let bv2 = {
        let (b, d, _) = basis(v2);
        (b, d)
    };
    let hu = (u2 - u1) / 3.0;
    let hv = (v2 - v1) / 3.0;
    // rows[j][k]: u-Bezier point k of B-spline row j (v index j).
    let mut rows = [[DVec3::ZERO; 4]; 4];
    for (j, r) in rows.iter_mut().enumerate() {
        *r = bezier4([pt(0, j), pt(1, j), pt(2, j), pt(3, j)], &bu1, &bu2, hu);
    }
    let mut net = [DVec3::ZERO; 16];
    for k in 0..4 {
        let col = bezier4(
            [rows[0][k], rows[1][k], rows[2][k], rows[3][k]],
            &bv1,
            &bv2,
            hv,
        );
        for l in 0..4 {
            net[k * 4 + l] = col[l];
        }
    }
    net
}

/// The net as four rows `P[4k..4k+4]` of 12 coordinates (`x y z` of each
/// point).
#[inline(always)]
fn rows(n: &Net) -> &[[f64; 12]; 4] {
    // SAFETY: `DVec3` is `#[repr(C)]` with exactly three `f64` fields (size
    // 24, alignment 8, no padding), so `[DVec3; 16]` has the layout of
    // `[[f64; 12]; 4]`.
    unsafe { &*(n as *const Net as *const [[f64; 12]; 4]) }
}

#[inline(always)]
fn rows_mut(n: &mut Net) -> &mut [[f64; 12]; 4] {
    // SAFETY: as in `rows`.
    unsafe { &mut *(n as *mut Net as *mut [[f64; 12]; 4]) }
}

/// `(a[A + i] + b[B + i]) * 0.5` for `i < W`: a lane loop over fixed
/// arrays that the compiler keeps in vector registers.
#[inline(always)]
fn mid<const W: usize, const N: usize, const M: usize, const A: usize, const B: usize>(
    a: &[f64; N],
    b: &[f64; M],
) -> [f64; W] {
    let mut o = [0.0; W];
    for i in 0..W {
        o[i] = (a[A + i] + b[B + i]) * 0.5;
    }
    o
}

/// Midpoint de Casteljau split along v of one row of a net (four points,
/// coordinates `3l..3l+3`): left and right halves.
#[inline(always)]
fn split_row(p: &[f64; 12], left: &mut [f64; 12], right: &mut [f64; 12]) {
    let q = mid::<9, 12, 12, 0, 3>(p, p); // q0 q1 q2
    let r = mid::<6, 9, 9, 0, 3>(&q, &q); // r0 r1
    let m = mid::<3, 6, 6, 0, 3>(&r, &r);
    left[..3].copy_from_slice(&p[..3]);
    left[3..6].copy_from_slice(&q[..3]);
    left[6..9].copy_from_slice(&r[..3]);
    left[9..].copy_from_slice(&m);
    right[..3].copy_from_slice(&m);
    right[3..6].copy_from_slice(&r[3..]);
    right[6..9].copy_from_slice(&q[6..]);
    right[9..].copy_from_slice(&p[9..]);
}

/// The four children of a net at the parameter midpoints, in the order
/// `[0,.5]x[0,.5]`, `[.5,1]x[0,.5]`, `[.5,1]x[.5,1]`, `[0,.5]x[.5,1]`.
pub(crate) fn split4(n: &Net, out: &mut [Net; 4]) {
    let [a, b, c, d] = out;
    split4_into(n, [a, b, c, d]);
}

/// [`split4`] into four separate nets. Along u the control points are the
/// rows (12 contiguous coordinates each, split lane by lane); along v,
/// within one row, the points `P[4k + l]` (coordinates `3l..3l+3`). The
/// arithmetic is that of the scalar midpoint formulas, lane by lane.
pub(crate) fn split4_into(n: &Net, out: [&mut Net; 4]) {
    let [o0, o1, o2, o3] = out;
    let [p0, p1, p2, p3] = rows(n);
    let q0 = mid::<12, 12, 12, 0, 0>(p0, p1);
    let q1 = mid::<12, 12, 12, 0, 0>(p1, p2);
    let q2 = mid::<12, 12, 12, 0, 0>(p2, p3);
    let r0 = mid::<12, 12, 12, 0, 0>(&q0, &q1);
    let r1 = mid::<12, 12, 12, 0, 0>(&q1, &q2);
    let m = mid::<12, 12, 12, 0, 0>(&r0, &r1);
    let lo = [p0, &q0, &r0, &m];
    let hi = [&m, &r1, &q2, p3];
    let (o0, o1, o2, o3) = (rows_mut(o0), rows_mut(o1), rows_mut(o2), rows_mut(o3));
    for k in 0..4 {
        split_row(lo[k], &mut o0[k], &mut o3[k]);
        split_row(hi[k], &mut o1[k], &mut o2[k]);
    }
}

/// Axis-aligned box of a net (a guaranteed bound of the surface over the
/// cell, by the convex hull property). Plain comparisons (`minpd`/`maxpd`
/// semantics) over pairs of points, six lanes at a time.
#[inline]
pub(crate) fn net_box(n: &Net) -> (DVec3, DVec3) {
    let r = rows(n);
    let mut lo = [0.0f64; 6];
    lo.copy_from_slice(&r[0][..6]);
    let mut hi = lo;
    for p in 1..8 {
        for c in 0..6 {
            let x = r[p / 2][6 * (p % 2) + c];
            lo[c] = if x < lo[c] { x } else { lo[c] };
            hi[c] = if x > hi[c] { x } else { hi[c] };
        }
    }
    let mn = |a: f64, b: f64| if a < b { a } else { b };
    let mx = |a: f64, b: f64| if a > b { a } else { b };
    (
        DVec3::new(mn(lo[0], lo[3]), mn(lo[1], lo[4]), mn(lo[2], lo[5])),
        DVec3::new(mx(hi[0], hi[3]), mx(hi[1], hi[4]), mx(hi[2], hi[5])),
    )
}

/// The four corners of a net in counter-clockwise parameter order:
/// S(0,0), S(1,0), S(1,1), S(0,1).
#[inline]
pub(crate) fn net_corners(n: &Net) -> [DVec3; 4] {
    [n[0], n[12], n[15], n[3]]
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
    let mut out = [[DVec3::ZERO; 16]; 3];
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
    [l_point, kids[0][12], kids[1][15], kids[2][3]]
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
