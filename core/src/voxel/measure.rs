//! Exact integral properties of the solid bounded by the limit surface:
//! volume, surface area, centroid and inertia tensor.
//!
//! By the divergence theorem, with `N = S_u x S_v` (outward for
//! counter-clockwise faces) and positions taken relative to a reference
//! point `O`:
//!
//! * `V = 1/3 ∮ S·N du dv`,
//! * `∫ x dV = 1/2 ∮ x² N_x du dv` (same for y, z),
//! * `∫ x² dV = 1/3 ∮ x³ N_x du dv`, `∫ x y dV = 1/2 ∮ x² y N_x du dv`,
//!   `∫ y z dV = 1/2 ∮ y² z N_y du dv`, `∫ z x dV = 1/2 ∮ z² x N_z du dv`.
//!
//! On a polynomial piece (a regular patch, or a region `Omega_{m,b}` of an
//! extraordinary patch, each bicubic over its own unit square; \[CL-R §2.1\])
//! these integrands are polynomials of degree at most 14 in each parameter
//! (`x³` is of degree 9, `N` of degree 5), so the 8-point Gauss-Legendre
//! rule per direction (exact to degree 15) integrates them **exactly**; the
//! piece's own coordinates may be used since `N du dv` is invariant under
//! the affine parameter maps. The area `∫ |N| du dv` is not polynomial: it
//! is integrated adaptively (8x8 Gauss on a cell against the sum over its
//! four children, until they agree to 1e-13 relative by default:
//! [`MeasureOptions`]).
//!
//! An extraordinary patch is summed over its regions `m = 1..K`; the corner
//! square `[0, 2^-K]^2` is left out and bounded. Its area is at most
//! `sum_{m>K} sum_b sup|S_x| sup|S_y|`, and with the eigen expansion of the
//! region grids (`sum_c mu_c^(m-1) ghat_c X_{b,c}`, \[CL-R eq. 2.5\]) and the
//! hodograph bounds `D_{b,c}` of each eigen component at level 1,
//! `sup|S_x| <= lambda^(m-1) sum_c Dx_{b,c}` (lambda = largest `|mu_c|`,
//! c >= 1), so the corner area is at most
//! `A_K = lambda^(2K) / (1 - lambda^2) * sum_b (sum_c Dx_{b,c})(sum_c Dy_{b,c})`.
//! Every point of the corner is within `R_K` of the limit point `L`
//! ([`crate::eigen::ValenceTable::corner_radius`]), so with `rho = |L - O| + R_K`
//! the left-out volume is at most `rho A_K / 3`, first moments
//! `rho² A_K / 2`, second moments `rho³ A_K / 2`. `K` grows until the volume
//! bound is below `1e-15` (default) of the model's size cubed (at most 60). The sums
//! of these bounds are the reported error bounds; the area bound adds the
//! adaptive quadrature's own estimate (the difference between the last two
//! refinement levels, an estimate rather than a bound).
//!
//! **Rounding.** The sums run in a local frame (control points minus the
//! box centre, scaled by a power of two: exact), so translation and scale
//! change nothing but the rounding of the patch data. That data is taken to
//! be within `delta = BUILD_ROUNDING eps M` of exact (`M` the largest
//! coordinate magnitude): the limit surface, an affine combination with
//! positive weights, then moves by at most `sqrt(3) delta` and its
//! derivatives by `6 sqrt(3) delta` per unit parameter, so the volume moves
//! by at most `sqrt(3) delta A` and the area by `6 sqrt(3) delta ∫(|S_u| +
//! |S_v|)`; the Gauss sums' own rounding adds `(256 + pieces) eps` times the
//! sums of absolute values. Both terms are in the reported bounds.
//!
//! For general weights
//! with a complex eigenvalue pair the corner bound uses the pair's modulus
//! and is an estimate too ([`MassProperties::rigorous`] is then false).
//!
//! ## Feature meshes
//!
//! On a [`crate::eval::FeatureEvaluator`] every cell that is polynomial at
//! its level ([`CellGeom::Poly`]: a B-spline grid restricted to a dyadic
//! rectangle of its unit square) is integrated exactly as above, with the
//! Gauss nodes mapped into the rectangle (the integrands stay polynomials
//! of the same degrees). Cells that are not polynomial ([`CellGeom::Hull`],
//! next to a crease end, corner, dart, extraordinary or semi-sharp vertex)
//! are split until the radius `r` of their control points' ball is at
//! most [`HULL_REL_RADIUS`] of the model size (or the cell level reaches
//! [`MAX_CELL_LEVEL`]); what is left out is a few cells per special
//! vertex, each within a ball of radius `r` about `c`. Its area is
//! estimated by that of the ball's surface, `A = 4 pi r^2` (exact for no
//! smooth piece, an over-estimate for any piece that is a graph over a
//! plane, which these small pieces are on the meshes we know, but not a
//! proof: [`MassProperties::rigorous`] is then false), and the volume,
//! moment and area bounds use `rho = |c - O| + r` as for the corner
//! squares above.
//!
//! Feature cells are moved into the same local frame as they are made (each
//! grid relative to its first point, that point relative to the box centre,
//! both scaled by the power of two), and their rounding sums enter the same
//! bound terms. The allowance `delta` holds for feature meshes too: the
//! test `build_rounding_constant_feature_meshes` finds the limit surfaces
//! of 12 creased, cornered, open, holed, semi-sharp and Chaikin corpus
//! shapes shifted by up to 1e12 within 2.6 eps M (at uniform points and
//! points within 2^-24 of sub-face corners, where local refinement is
//! deepest), 1/25 of the allowance.

use super::cells::{grid_net, patch_hull, point, Affine, FeaturePatch, Patch};
use super::Surface;
use crate::eigen::ValenceTable;
use crate::error::Error;
use crate::eval::{CellCursor, CellGeom, MAX_CELL_LEVEL};
use crate::math::bspline::{basis, Grid};
use glam::DVec3;

/// Hull cells of a feature mesh are split until their ball's radius is at
/// most this fraction of the model size (see the module docs).
pub const HULL_REL_RADIUS: f64 = 1e-8;

/// 8-point Gauss-Legendre nodes and weights on [0, 1].
const GAUSS_X: [f64; 8] = [
    0.019_855_071_751_231_856,
    0.101_666_761_293_186_63,
    0.237_233_795_041_835_5,
    0.408_282_678_752_175_1,
    0.591_717_321_247_825,
    0.762_766_204_958_164_5,
    0.898_333_238_706_813_4,
    0.980_144_928_248_768_2,
];
const GAUSS_W: [f64; 8] = [
    0.050_614_268_145_188_13,
    0.111_190_517_226_687_24,
    0.156_853_322_938_943_64,
    0.181_341_891_689_181,
    0.181_341_891_689_181,
    0.156_853_322_938_943_64,
    0.111_190_517_226_687_24,
    0.050_614_268_145_188_13,
];

/// Deepest corner level of an extraordinary patch.
const MAX_CORNER_LEVEL: u32 = 60;
/// Deepest adaptive area level per piece.
const AREA_DEPTH: u32 = 6;
/// Feature meshes: a cell of the adaptive area quadrature is also accepted
/// when its estimates agree to this fraction of the model size squared
/// (tiny pieces next to special vertices, whose relative agreement is
/// limited by rounding).
const AREA_ABS_TOL: f64 = 1e-18;
/// Relative difference of the area estimates below which refining cannot
/// help (rounding noise of 64-point Gauss sums of `|S_u x S_v|`).
const AREA_ROUND: f64 = 1024.0 * f64::EPSILON;
pub use super::measure_options::{
    MeasureOptions, AREA_CELLS_MIN, AREA_CELLS_PER_PIECE, AREA_REL_TOL, CORNER_REL_TOL,
};
/// Rounding allowance of the evaluator's patch data: every control point
/// (and every region grid point of an extraordinary patch) is taken to be
/// within `BUILD_ROUNDING * eps * M` of its exact value, `M` the largest
/// coordinate magnitude of the control points. Measured, not proved: the
/// test `build_rounding_constant` (tests/tests/hardening.rs) finds the
/// limit surfaces of 7 corpus shapes shifted by up to 1e12 within 3.9 eps M
/// (2,800 points each), 1/16 of this; the test requires 1/8. On feature
/// meshes (`build_rounding_constant_feature_meshes`, 12 shapes with creases,
/// corners, boundaries and holes): 2.6 eps M.
pub use crate::bounds::rounding::BUILD_ROUNDING;
/// Largest rounding allowance of the patch data, relative to the model's
/// size, for which results are returned (beyond it the bounds say nothing).
pub const MAX_ROUNDING_SHARE: f64 = 0.05;
/// Largest and smallest model sizes (largest box extent) measured: the
/// inertia scales with size^5, so 2^±200 keeps every result and bound a
/// normal `f64`.
pub const MAX_SIZE_EXP: i32 = 200;

/// Integral properties of the solid (unit density; multiply the inertia by
/// the density for a mass-weighted tensor, mass = density x volume).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MassProperties {
    /// Volume (signed: negative if the mesh is oriented inward).
    pub volume: f64,
    /// Surface area of the limit surface.
    pub area: f64,
    /// Centroid of the solid.
    pub centroid: [f64; 3],
    /// Inertia tensor about the centroid for unit density:
    /// `[Ixx, Iyy, Izz, Ixy, Iyz, Izx]` with `Ixx = ∫(y² + z²) dV` and
    /// `Ixy = -∫ x y dV` (tensor entries).
    pub inertia: [f64; 6],
    /// Bound of the volume error: left-out corner squares (the Gauss rule is
    /// exact elsewhere) plus rounding (of the patch data, allowance
    /// [`BUILD_ROUNDING`], and of the sums).
    pub volume_error_bound: f64,
    /// Bound of the area error from the corner squares plus the adaptive
    /// quadrature's estimate.
    pub area_error_bound: f64,
    /// Bound of the centroid error (max norm).
    pub centroid_error_bound: f64,
    /// Bound of the error of each inertia entry.
    pub inertia_error_bound: f64,
    /// Polynomial pieces integrated.
    pub pieces: u64,
    /// Cells of the adaptive area quadrature.
    pub area_cells: u64,
    /// Pieces whose area did not converge within the depth limit.
    pub area_unconverged: u64,
    /// Deepest corner level used.
    pub max_corner_level: u32,
    /// False if some corner bound is an estimate (complex eigenvalue pair).
    pub rigorous: bool,
}

/// Raw sums over the surface (relative to `O`).
#[derive(Clone, Copy, Default)]
struct Sums {
    v: f64,
    m: [f64; 3],
    s: [f64; 3], // ∫x² dV, ∫y² dV, ∫z² dV
    p: [f64; 3], // ∫xy, ∫yz, ∫zx
}

impl Sums {
    fn add(&mut self, o: &Sums) {
        self.v += o.v;
        for a in 0..3 {
            self.m[a] += o.m[a];
            self.s[a] += o.s[a];
            self.p[a] += o.p[a];
        }
    }
}

/// Position and first derivatives of the grid at (u, v).
#[inline]
fn eval(g: &Grid, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let (bu, du, _) = basis(u);
    let (bv, dv, _) = basis(v);
    let mut p = DVec3::ZERO;
    let mut pu = DVec3::ZERO;
    let mut pv = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            let q = DVec3::new(g[i * 4 + j], g[16 + i * 4 + j], g[32 + i * 4 + j]);
            p += q * (bu[i] * bv[j]);
            pu += q * (du[i] * bv[j]);
            pv += q * (bu[i] * dv[j]);
        }
    }
    (p, pu, pv)
}

/// First derivatives of the grid at (u, v): the `pu`, `pv` of [`eval`]
/// (the same operations), without the position.
#[inline]
fn eval_derivatives(g: &Grid, u: f64, v: f64) -> (DVec3, DVec3) {
    let (bu, du, _) = basis(u);
    let (bv, dv, _) = basis(v);
    let mut pu = DVec3::ZERO;
    let mut pv = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            let q = DVec3::new(g[i * 4 + j], g[16 + i * 4 + j], g[32 + i * 4 + j]);
            pu += q * (du[i] * bv[j]);
            pv += q * (bu[i] * dv[j]);
        }
    }
    (pu, pv)
}

/// Exact polynomial moments of a piece over its unit square; positions are
/// `base + g(u, v)`. Also returns `(sum |volume terms|, ∫ |S_u| + |S_v|)`
/// for the rounding terms of the bounds (module docs).
fn piece_sums(g: &Grid, base: DVec3) -> (Sums, f64, f64) {
    rect_sums(g, base, [0.0, 1.0, 0.0, 1.0])
}

/// [`piece_sums`] over the rectangle `r = [u0, u1, v0, v1]` of the unit
/// square (Gauss nodes mapped into it; `N du dv` scaled by its area).
fn rect_sums(g: &Grid, base: DVec3, r: [f64; 4]) -> (Sums, f64, f64) {
    let (hu, hv) = (r[1] - r[0], r[3] - r[2]);
    let mut s = Sums::default();
    let (mut vabs, mut l1) = (0.0, 0.0);
    for (iu, &x) in GAUSS_X.iter().enumerate() {
        for (iv, &y) in GAUSS_X.iter().enumerate() {
            let w = GAUSS_W[iu] * GAUSS_W[iv] * hu * hv;
            let (q, pu, pv) = eval(g, r[0] + hu * x, r[2] + hv * y);
            let p = base + q;
            let n = pu.cross(pv);
            s.v += w * p.dot(n) / 3.0;
            vabs += w * (p.abs().dot(n.abs())) / 3.0;
            l1 += w * (pu.length() + pv.length());
            s.m[0] += w * p.x * p.x * n.x / 2.0;
            s.m[1] += w * p.y * p.y * n.y / 2.0;
            s.m[2] += w * p.z * p.z * n.z / 2.0;
            s.s[0] += w * p.x * p.x * p.x * n.x / 3.0;
            s.s[1] += w * p.y * p.y * p.y * n.y / 3.0;
            s.s[2] += w * p.z * p.z * p.z * n.z / 3.0;
            s.p[0] += w * p.x * p.x * p.y * n.x / 2.0;
            s.p[1] += w * p.y * p.y * p.z * n.y / 2.0;
            s.p[2] += w * p.z * p.z * p.x * n.z / 2.0;
        }
    }
    (s, vabs, l1)
}

/// 8x8 Gauss of |N| over `[u1,u2] x [v1,v2]`.
fn area_gauss(g: &Grid, u1: f64, u2: f64, v1: f64, v2: f64) -> f64 {
    let (hu, hv) = (u2 - u1, v2 - v1);
    let mut a = 0.0;
    for (iu, &x) in GAUSS_X.iter().enumerate() {
        for (iv, &y) in GAUSS_X.iter().enumerate() {
            let (pu, pv) = eval_derivatives(g, u1 + hu * x, v1 + hv * y);
            a += GAUSS_W[iu] * GAUSS_W[iv] * pu.cross(pv).length();
        }
    }
    a * hu * hv
}

/// Adaptive area of a piece: (area, error estimate, cells, unconverged).
///
/// A cell is accepted when its two estimates agree to `rel_tol`, or
/// to `AREA_ROUND * |sum|` (below that the difference is rounding noise:
/// refining cannot reduce it; it is added to the error), or when `budget`
/// cells are used up (counted as unconverged).
fn piece_area(g: &Grid, rel_tol: f64, budget: &mut u64) -> (f64, f64, u64, u64) {
    rect_area(g, [0.0, 1.0, 0.0, 1.0], rel_tol, 1e-300, budget)
}

/// Adaptive area of a piece over the rectangle `r` of its unit square, as
/// [`piece_area`]; a cell is also accepted when its two estimates agree to
/// `abs_tol`.
fn rect_area(
    g: &Grid,
    r: [f64; 4],
    rel_tol: f64,
    abs_tol: f64,
    budget: &mut u64,
) -> (f64, f64, u64, u64) {
    const CAP: usize = 3 * AREA_DEPTH as usize + 8;
    let mut st = [(0.0f64, 0.0f64, 0.0f64, 0.0f64, 0u32, 0.0f64); CAP];
    st[0] = (
        r[0],
        r[1],
        r[2],
        r[3],
        0,
        area_gauss(g, r[0], r[1], r[2], r[3]),
    );
    let mut n = 1usize;
    let (mut area, mut err, mut cells, mut bad) = (0.0, 0.0, 1u64, 0u64);
    while n > 0 {
        n -= 1;
        let (u1, u2, v1, v2, d, q) = st[n];
        let (um, vm) = (0.5 * (u1 + u2), 0.5 * (v1 + v2));
        let kids = [
            (u1, um, v1, vm),
            (um, u2, v1, vm),
            (um, u2, vm, v2),
            (u1, um, vm, v2),
        ];
        let qs = kids.map(|(a, b, c, e)| area_gauss(g, a, b, c, e));
        cells += 4;
        *budget = budget.saturating_sub(4);
        let sum: f64 = qs.iter().sum();
        let diff = (sum - q).abs();
        if diff <= rel_tol * sum.abs() || diff <= abs_tol {
            area += sum;
            err += diff;
            continue;
        }
        if d >= AREA_DEPTH || n + 4 > CAP || *budget == 0 || diff <= AREA_ROUND * sum.abs() {
            area += sum;
            err += diff;
            if diff > AREA_ROUND * sum.abs() {
                bad += 1;
            }
            continue;
        }
        for (k, &(a, b, c, e)) in kids.iter().enumerate() {
            st[n] = (a, b, c, e, d + 1, qs[k]);
            n += 1;
        }
    }
    (area, err, cells, bad)
}

/// Hodograph bounds (sup |S_u|, sup |S_v|) of a grid over its unit square.
fn derivative_bounds(g: &Grid) -> (f64, f64) {
    let net = grid_net(g, 0.0, 1.0, 0.0, 1.0, &Affine::IDENTITY);
    let (mut du, mut dv) = (0.0f64, 0.0f64);
    for k in 0..4 {
        for l in 0..4 {
            if k < 3 {
                du = du.max((point(&net, (k + 1) * 4 + l) - point(&net, k * 4 + l)).length());
            }
            if l < 3 {
                dv = dv.max((point(&net, k * 4 + l + 1) - point(&net, k * 4 + l)).length());
            }
        }
    }
    (3.0 * du, 3.0 * dv)
}

/// `(lambda, sum_b (sum_c Dx_{b,c})(sum_c Dy_{b,c}))` of an extraordinary
/// patch (module docs).
fn corner_constants(tab: &ValenceTable, ghat: &[f64]) -> (f64, f64) {
    let k = tab.num_points();
    let mu = tab.eigenvalues();
    let lambda = mu.iter().skip(1).fold(0.0f64, |a, &m| a.max(m.abs()));
    let mut total = 0.0;
    for b in 1..=3usize {
        let (mut sx, mut sy) = (0.0, 0.0);
        for c in 1..k.min(ghat.len() / 3) {
            let mut g = [0.0; 48];
            tab.component_grid(ghat, c, b, &mut g);
            let (dx, dy) = derivative_bounds(&g);
            sx += dx;
            sy += dy;
        }
        total += sx * sy;
    }
    (lambda, total)
}

/// Sums of one feature patch (module docs), in the measure's local frame
/// (centre `o`, scale `sc`; `size` in local units): exact pieces, and the
/// bounds of the hull cells left out added to `bounds` (volume, first
/// moments, second moments, area). `acc` gathers the rounding sums
/// `(sum |volume terms|, ∫ |S_u| + |S_v|)`; every polynomial piece adds
/// `opts.area_cells_per_piece` to the area budget. Work memory: an explicit
/// stack of cells.
#[allow(clippy::too_many_arguments)]
#[inline(never)] // its cursor stays off the smooth path's stack
fn feature_patch(
    fp: &FeaturePatch,
    o: DVec3,
    sc: f64,
    size: f64,
    out: &mut MassProperties,
    sums: &mut Sums,
    area: &mut (f64, f64),
    bounds: &mut [f64; 3],
    acc: &mut (f64, f64),
    budget: &mut u64,
    opts: &MeasureOptions,
) -> Result<(), Error> {
    const CAP: usize = 3 * MAX_CELL_LEVEL as usize + 8;
    let mut st = [(0u32, 0u32, 0u32); CAP];
    st[0] = (fp.base, fp.i0, fp.j0);
    let mut n = 1usize;
    // Depth first: children refine once from their parent's patch.
    let mut cursor = CellCursor::new();
    while n > 0 {
        n -= 1;
        let (l, i, j) = st[n];
        match fp.fe.cell_in(&mut cursor, fp.face, fp.sub, l, i, j)? {
            CellGeom::Poly { grid, rect } => {
                // Relative to the grid's first point (small coordinates keep
                // the derivatives of tiny pieces accurate), in local units.
                let c0 = grid[0];
                let mut g = [0.0; 48];
                for (k, p) in grid.iter().enumerate() {
                    // Row by row (k = j * 4 + i) to i-major per coordinate.
                    let (ci, cj) = (k % 4, k / 4);
                    let p = (*p - c0) * sc;
                    g[ci * 4 + cj] = p.x;
                    g[16 + ci * 4 + cj] = p.y;
                    g[32 + ci * 4 + cj] = p.z;
                }
                let (ps, va, d1) = rect_sums(&g, (c0 - o) * sc, rect);
                sums.add(&ps);
                acc.0 += va;
                acc.1 += d1;
                *budget = budget.saturating_add(opts.area_cells_per_piece);
                let tol = AREA_ABS_TOL * size * size;
                let (a, e, c, bad) = rect_area(&g, rect, opts.area_rel_tol, tol, budget);
                area.0 += a;
                area.1 += e;
                out.pieces += 1;
                out.area_cells += c;
                out.area_unconverged += bad;
            }
            CellGeom::Hull(h) => {
                let r = h.radius * sc;
                if r <= HULL_REL_RADIUS * size || l >= MAX_CELL_LEVEL || n + 4 > CAP {
                    let rho = ((h.centre() - o) * sc).length() + r;
                    let a = 4.0 * core::f64::consts::PI * r * r;
                    bounds[0] += rho * a / 3.0;
                    bounds[1] += rho * rho * a / 2.0;
                    bounds[2] += rho * rho * rho * a / 2.0;
                    area.1 += a;
                    out.rigorous = false;
                    out.max_corner_level = out.max_corner_level.max(l);
                    continue;
                }
                for q in 0..4 {
                    let (di, dj) = super::cells::quadrant_offset(q);
                    st[n] = (l + 1, 2 * i + di, 2 * j + dj);
                    n += 1;
                }
            }
            CellGeom::Split => {
                for q in 0..4 {
                    let (di, dj) = super::cells::quadrant_offset(q);
                    st[n] = (l + 1, 2 * i + di, 2 * j + dj);
                    n += 1;
                }
            }
        }
    }
    Ok(())
}

/// `(g - o) * s` per control point: the grid in the measure's local frame.
fn local_grid(g: &Grid, o: DVec3, s: f64) -> Grid {
    let mut out = [0.0; 48];
    for a in 0..3 {
        for i in 0..16 {
            out[16 * a + i] = (g[16 * a + i] - o[a]) * s;
        }
    }
    out
}

/// Exact volume, area, centroid and inertia of the solid bounded by the
/// limit surface of `ev`, with error bounds (see module docs). A feature
/// mesh must bound a solid ([`Error::NotClosedSolid`] otherwise).
///
/// The integration runs in a local frame: control points relative to the
/// centre `O` of their bounding box, scaled by the power of two `2^-e` that
/// brings the box's largest extent into `[1/2, 1)` (exact), so results do
/// not depend on the translation and scale of the model beyond the rounding
/// of the patch data itself, which the bounds include. Feature meshes use
/// the same frame (their cells' grids are moved into it as they are made);
/// the rounding allowance [`BUILD_ROUNDING`] was measured on both
/// evaluator families.
///
/// Work: at most `MAX_CORNER_LEVEL` region levels per extraordinary patch
/// and [`AREA_CELLS_PER_PIECE`] area cells per piece on average (plus
/// [`AREA_CELLS_MIN`]), each cell 4 x 64 grid evaluations. Same as
/// [`mass_properties_with`] with the default [`MeasureOptions`].
///
/// Errors: `NotClosedSolid` (feature meshes), `EmptyMesh`; `CoordinateRange` if the control points' box is not
/// finite, its extent is outside `2^-200..2^200` (the inertia, of degree
/// 5, would leave the normal `f64` range) or zero, the rounding allowance
/// exceeds [`MAX_ROUNDING_SHARE`] of the size (a tiny model far from the
/// origin), or a result or bound is not finite.
pub fn mass_properties<S: Surface + ?Sized>(ev: &S) -> Result<MassProperties, Error> {
    mass_properties_with(ev, &MeasureOptions::default())
}

/// [`mass_properties`] with the accuracy and work budget of `opts`: at most
/// `MAX_CORNER_LEVEL` region levels per extraordinary patch (fewer as
/// `opts.corner_rel_tol` grows) and `opts.area_cells_min +
/// opts.area_cells_per_piece x pieces` area cells beyond the first of each
/// piece. The error bounds hold for the result returned at any options;
/// they grow as the options loosen. `InvalidArgument` if a tolerance is
/// not finite and positive ([`MeasureOptions::check`]); other errors as
/// [`mass_properties`].
pub fn mass_properties_with<S: Surface + ?Sized>(
    ev: &S,
    opts: &MeasureOptions,
) -> Result<MassProperties, Error> {
    opts.check()?;
    ev.check_solid()?;
    let np = ev.patch_count();
    if np == 0 {
        return Err(Error::EmptyMesh);
    }
    // Reference point and size: the control points' box.
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for pi in 0..np {
        let p = ev
            .patch_at(pi)
            .ok_or(Error::InvalidArgument("patch table"))?;
        let (a, b) = patch_hull(&p);
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::CoordinateRange(
            "the control points' bounding box is not finite",
        ));
    }
    let o = lo * 0.5 + hi * 0.5;
    let extent = (hi * 0.5 - lo * 0.5).max_element() * 2.0;
    if !(extent.is_finite() && extent > 0.0) {
        return Err(Error::CoordinateRange(
            "the extent of the control points' box is zero or overflows",
        ));
    }
    // extent = f * 2^e with f in [1/2, 1).
    let e = libm::ilogb(extent) + 1;
    if !(-MAX_SIZE_EXP..=MAX_SIZE_EXP).contains(&e) {
        return Err(Error::CoordinateRange(
            "model size outside 2^-200..2^200 (the inertia would leave the f64 range)",
        ));
    }
    let sc = libm::scalbn(1.0, -e);
    // Rounding allowance of the patch data, in local units.
    let mag = lo.abs().max(hi.abs()).max_element();
    let delta = BUILD_ROUNDING * f64::EPSILON * mag * sc;
    if delta.is_nan() || delta > MAX_ROUNDING_SHARE {
        return Err(Error::CoordinateRange(
            "the model is too small for its distance from the origin: rounding of the \
             coordinates exceeds 5 % of its size",
        ));
    }
    let size = extent * sc;
    let mut out = MassProperties {
        rigorous: true,
        ..Default::default()
    };
    let mut sums = Sums::default();
    let mut fsums = Sums::default();
    let mut any_feature = false;
    let (mut area, mut area_err) = (0.0, 0.0);
    let (mut vb, mut mb, mut sb) = (0.0, 0.0, 0.0);
    let (mut vabs, mut l1) = (0.0, 0.0);
    let mut budget = opts
        .area_cells_min
        .saturating_add(opts.area_cells_per_piece.saturating_mul(np as u64));
    // Feature patches: their own budget (a feature mesh has only feature
    // patches), grown by `area_cells_per_piece` per piece, and rounding sums.
    let mut fbudget = budget;
    let mut facc = (0.0, 0.0);
    // Positions are `base + g`: base = 0 for regular patches (local grid),
    // L - O for the limit-free region grids of extraordinary patches (which
    // keeps their derivatives exact near the vertex).
    let mut piece =
        |g: &Grid, base: DVec3, out: &mut MassProperties, area: &mut f64, err: &mut f64| {
            let (ps, va, d1) = piece_sums(g, base);
            sums.add(&ps);
            vabs += va;
            l1 += d1;
            let (a, e, c, bad) = piece_area(g, opts.area_rel_tol, &mut budget);
            *area += a;
            *err += e;
            out.pieces += 1;
            out.area_cells += c;
            out.area_unconverged += bad;
        };
    for pi in 0..np {
        let p = ev
            .patch_at(pi)
            .ok_or(Error::InvalidArgument("patch table"))?;
        match p {
            Patch::Regular(g) => {
                let g = local_grid(g, o, sc);
                piece(&g, DVec3::ZERO, &mut out, &mut area, &mut area_err);
            }
            Patch::Feature(fp) => {
                let mut a = (0.0, 0.0);
                let mut b = [0.0; 3];
                feature_patch(
                    &fp,
                    o,
                    sc,
                    size,
                    &mut out,
                    &mut fsums,
                    &mut a,
                    &mut b,
                    &mut facc,
                    &mut fbudget,
                    opts,
                )?;
                any_feature = true;
                area += a.0;
                area_err += a.1;
                vb += b[0];
                mb += b[1];
                sb += b[2];
            }
            Patch::Extra { tab, ghat, .. } => {
                if tab.has_complex_pair() {
                    out.rigorous = false;
                }
                let (lambda, dd) = corner_constants(tab, ghat);
                let dd = dd * sc * sc;
                let l = DVec3::new(ghat[0], ghat[1], ghat[2]);
                let base = (l - o) * sc;
                let mut m = 0u32;
                loop {
                    m += 1;
                    for b in 1..=3usize {
                        let mut g = [0.0; 48];
                        tab.sub_patch(ghat, m, b, false, &mut g);
                        for x in g.iter_mut() {
                            *x *= sc;
                        }
                        piece(&g, base, &mut out, &mut area, &mut area_err);
                    }
                    let tail = if lambda < 1.0 {
                        libm::pow(lambda, 2.0 * m as f64) / (1.0 - lambda * lambda) * dd
                    } else {
                        f64::INFINITY
                    };
                    let rho = base.length() + tab.corner_radius(ghat, m) * sc;
                    let v_bound = rho * tail / 3.0;
                    if v_bound <= opts.corner_rel_tol * size * size * size || m >= MAX_CORNER_LEVEL
                    {
                        vb += v_bound;
                        mb += rho * rho * tail / 2.0;
                        sb += rho * rho * rho * tail / 2.0;
                        area_err += tail;
                        out.max_corner_level = out.max_corner_level.max(m);
                        break;
                    }
                }
            }
        }
    }
    if any_feature {
        sums.add(&fsums);
        vabs += facc.0;
        l1 += facc.1;
    }
    // Rounding terms (module docs): the patch data within `delta` moves the
    // surface by at most sqrt(3) delta and its derivatives by 6 sqrt(3)
    // delta per unit parameter; the sums' own rounding is below
    // `(256 + pieces) eps` of the sums of absolute values.
    let gam = (256.0 + out.pieces as f64) * f64::EPSILON;
    let r3 = libm::sqrt(3.0);
    let rho_all = 0.5 * r3 * size + r3 * delta;
    vb += r3 * delta * (area + area_err) * 1.01 + gam * vabs;
    area_err += 6.0 * r3 * delta * l1 * 1.01 + gam * area;
    mb += rho_all * (r3 * delta * (area + area_err) + gam * vabs) * 1.5;
    sb += rho_all * rho_all * (r3 * delta * (area + area_err) + gam * vabs) * 1.5;
    // Back to model units: lengths scale by 2^e.
    let up = |x: f64, k: i32| libm::scalbn(x, k * e);
    let v = sums.v;
    out.volume = up(v, 3);
    out.area = up(area, 2);
    out.volume_error_bound = up(vb, 3);
    out.area_error_bound = up(area_err, 2);
    let c = if v != 0.0 {
        DVec3::new(sums.m[0] / v, sums.m[1] / v, sums.m[2] / v)
    } else {
        DVec3::ZERO
    };
    out.centroid = (o + c * up(1.0, 1)).to_array();
    // Second moments about the centroid.
    let sxx = sums.s[0] - v * c.x * c.x;
    let syy = sums.s[1] - v * c.y * c.y;
    let szz = sums.s[2] - v * c.z * c.z;
    let pxy = sums.p[0] - v * c.x * c.y;
    let pyz = sums.p[1] - v * c.y * c.z;
    let pzx = sums.p[2] - v * c.z * c.x;
    out.inertia = [syy + szz, sxx + szz, sxx + syy, -pxy, -pyz, -pzx].map(|x| up(x, 5));
    if v.abs() > 0.0 {
        let cmax = c.abs().max_element();
        let cb = (mb + cmax * vb) / (v.abs() - vb).max(f64::MIN_POSITIVE);
        // s - v c^2 with errors in s (sb), v (vb) and c (cb).
        let ib = 2.0 * (sb + vb * (cmax + cb) * (cmax + cb) + 2.0 * v.abs() * (cmax + cb) * cb);
        // The centroid's own rounding when O is added back.
        out.centroid_error_bound = up(cb, 1) + f64::EPSILON * (o.abs().max_element() + up(cmax, 1));
        out.inertia_error_bound = up(ib, 5);
    }
    let all = [
        out.volume,
        out.area,
        out.volume_error_bound,
        out.area_error_bound,
    ];
    if !all
        .iter()
        .chain(&out.centroid)
        .chain(&out.inertia)
        .chain(&[out.centroid_error_bound, out.inertia_error_bound])
        .all(|x| x.is_finite())
    {
        return Err(Error::CoordinateRange(
            "a result or bound is not finite in double precision",
        ));
    }
    Ok(out)
}
