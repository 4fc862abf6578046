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
//! four children, until they agree to 1e-13 relative).
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
//! bound is below `1e-15` of the model's size cubed (at most 60). The sums
//! of these bounds are the reported error bounds; the area bound adds the
//! adaptive quadrature's own estimate (the difference between the last two
//! refinement levels, an estimate rather than a bound). For general weights
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

use super::cells::{grid_net, patch_hull, point, Affine, FeaturePatch, Patch};
use super::Surface;
use crate::eigen::ValenceTable;
use crate::error::Error;
use crate::eval::{CellGeom, MAX_CELL_LEVEL};
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
const AREA_REL_TOL: f64 = 1e-13;
/// Feature meshes: a cell of the adaptive area quadrature is also accepted
/// when its estimates agree to this fraction of the model size squared
/// (tiny pieces next to special vertices, whose relative agreement is
/// limited by rounding).
const AREA_ABS_TOL: f64 = 1e-18;

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
    /// Bound of the volume error (left-out corner squares; the Gauss rule is
    /// exact elsewhere; floating-point rounding not included).
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

/// Exact polynomial moments of a piece over its unit square; positions are
/// `base + g(u, v)`.
fn piece_sums(g: &Grid, base: DVec3) -> Sums {
    let mut s = Sums::default();
    for (iu, &u) in GAUSS_X.iter().enumerate() {
        for (iv, &v) in GAUSS_X.iter().enumerate() {
            let w = GAUSS_W[iu] * GAUSS_W[iv];
            let (q, pu, pv) = eval(g, u, v);
            let p = base + q;
            let n = pu.cross(pv);
            s.v += w * p.dot(n) / 3.0;
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
    s
}

/// [`piece_sums`] over the rectangle `r = [u0, u1, v0, v1]` of the unit
/// square (Gauss nodes mapped into it; `N du dv` scaled by its area).
fn rect_sums(g: &Grid, base: DVec3, r: [f64; 4]) -> Sums {
    let (hu, hv) = (r[1] - r[0], r[3] - r[2]);
    let mut s = Sums::default();
    for (iu, &x) in GAUSS_X.iter().enumerate() {
        for (iv, &y) in GAUSS_X.iter().enumerate() {
            let w = GAUSS_W[iu] * GAUSS_W[iv] * hu * hv;
            let (q, pu, pv) = eval(g, r[0] + hu * x, r[2] + hv * y);
            let p = base + q;
            let n = pu.cross(pv);
            s.v += w * p.dot(n) / 3.0;
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
    s
}

/// 8x8 Gauss of |N| over `[u1,u2] x [v1,v2]`.
fn area_gauss(g: &Grid, u1: f64, u2: f64, v1: f64, v2: f64) -> f64 {
    let (hu, hv) = (u2 - u1, v2 - v1);
    let mut a = 0.0;
    for (iu, &x) in GAUSS_X.iter().enumerate() {
        for (iv, &y) in GAUSS_X.iter().enumerate() {
            let (_, pu, pv) = eval(g, u1 + hu * x, v1 + hv * y);
            a += GAUSS_W[iu] * GAUSS_W[iv] * pu.cross(pv).length();
        }
    }
    a * hu * hv
}

/// Adaptive area of a piece: (area, error estimate, cells, unconverged).
fn piece_area(g: &Grid) -> (f64, f64, u64, u64) {
    rect_area(g, [0.0, 1.0, 0.0, 1.0], 1e-300)
}

/// Adaptive area of a piece over the rectangle `r` of its unit square; a
/// cell is accepted when its two estimates agree to [`AREA_REL_TOL`]
/// relative or to `abs_tol`.
fn rect_area(g: &Grid, r: [f64; 4], abs_tol: f64) -> (f64, f64, u64, u64) {
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
        let sum: f64 = qs.iter().sum();
        let diff = (sum - q).abs();
        if diff <= AREA_REL_TOL * sum.abs() || diff <= abs_tol {
            area += sum;
            err += diff;
            continue;
        }
        if d >= AREA_DEPTH || n + 4 > CAP {
            area += sum;
            err += diff;
            bad += 1;
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
    let mut one = [0.0f64; 3 * crate::mesh::stencil::MAX_K];
    for b in 1..=3usize {
        let (mut sx, mut sy) = (0.0, 0.0);
        for c in 1..k.min(ghat.len() / 3) {
            one.fill(0.0);
            one[3 * c..3 * c + 3].copy_from_slice(&ghat[3 * c..3 * c + 3]);
            let mut g = [0.0; 48];
            tab.sub_patch(&one[..3 * k], 1, b, false, &mut g);
            let (dx, dy) = derivative_bounds(&g);
            sx += dx;
            sy += dy;
        }
        total += sx * sy;
    }
    (lambda, total)
}

/// Sums of one feature patch (module docs): exact pieces, and the bounds of
/// the hull cells left out added to `bounds` (volume, first moments, second
/// moments, area). Work memory: an explicit stack of cells.
fn feature_patch(
    fp: &FeaturePatch,
    o: DVec3,
    size: f64,
    out: &mut MassProperties,
    sums: &mut Sums,
    area: &mut (f64, f64),
    bounds: &mut [f64; 3],
) -> Result<(), Error> {
    const CAP: usize = 3 * MAX_CELL_LEVEL as usize + 8;
    let mut st = [(0u32, 0u32, 0u32); CAP];
    st[0] = (fp.base, fp.i0, fp.j0);
    let mut n = 1usize;
    while n > 0 {
        n -= 1;
        let (l, i, j) = st[n];
        match fp.fe.cell(fp.face, fp.sub, l, i, j)? {
            CellGeom::Poly { grid, rect } => {
                // Relative to the grid's first point (small coordinates keep
                // the derivatives of tiny pieces accurate).
                let c0 = grid[0];
                let mut g = [0.0; 48];
                for (k, p) in grid.iter().enumerate() {
                    // Row by row (k = j * 4 + i) to i-major per coordinate.
                    let (ci, cj) = (k % 4, k / 4);
                    let p = *p - c0;
                    g[ci * 4 + cj] = p.x;
                    g[16 + ci * 4 + cj] = p.y;
                    g[32 + ci * 4 + cj] = p.z;
                }
                sums.add(&rect_sums(&g, c0 - o, rect));
                let (a, e, c, bad) = rect_area(&g, rect, AREA_ABS_TOL * size * size);
                area.0 += a;
                area.1 += e;
                out.pieces += 1;
                out.area_cells += c;
                out.area_unconverged += bad;
            }
            CellGeom::Hull(h) => {
                let r = h.radius;
                if r <= HULL_REL_RADIUS * size || l >= MAX_CELL_LEVEL || n + 4 > CAP {
                    let rho = (h.centre() - o).length() + r;
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

/// Exact volume, area, centroid and inertia of the solid bounded by the
/// limit surface of `ev`, with error bounds (see module docs). A feature
/// mesh must bound a solid ([`Error::NotClosedSolid`] otherwise).
pub fn mass_properties<S: Surface + ?Sized>(ev: &S) -> Result<MassProperties, Error> {
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
    let o = (lo + hi) * 0.5;
    let size = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let mut out = MassProperties {
        rigorous: true,
        ..Default::default()
    };
    let mut sums = Sums::default();
    let mut fsums = Sums::default();
    let mut any_feature = false;
    let (mut area, mut area_err) = (0.0, 0.0);
    let (mut vb, mut mb, mut sb) = (0.0, 0.0, 0.0);
    // Positions are `base + g`: base = -O for regular patches, L - O for the
    // limit-free region grids of extraordinary patches (which keeps their
    // derivatives exact near the vertex).
    let mut piece =
        |g: &Grid, base: DVec3, out: &mut MassProperties, area: &mut f64, err: &mut f64| {
            sums.add(&piece_sums(g, base));
            let (a, e, c, bad) = piece_area(g);
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
                piece(g, -o, &mut out, &mut area, &mut area_err);
            }
            Patch::Feature(fp) => {
                let mut a = (0.0, 0.0);
                let mut b = [0.0; 3];
                feature_patch(&fp, o, size, &mut out, &mut fsums, &mut a, &mut b)?;
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
                let l = DVec3::new(ghat[0], ghat[1], ghat[2]);
                let mut m = 0u32;
                loop {
                    m += 1;
                    for b in 1..=3usize {
                        let mut g = [0.0; 48];
                        tab.sub_patch(ghat, m, b, false, &mut g);
                        piece(&g, l - o, &mut out, &mut area, &mut area_err);
                    }
                    let tail = if lambda < 1.0 {
                        libm::pow(lambda, 2.0 * m as f64) / (1.0 - lambda * lambda) * dd
                    } else {
                        f64::INFINITY
                    };
                    let rho = (l - o).length() + tab.corner_radius(ghat, m);
                    let v_bound = rho * tail / 3.0;
                    if v_bound <= 1e-15 * size * size * size || m >= MAX_CORNER_LEVEL {
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
    }
    let v = sums.v;
    out.volume = v;
    out.area = area;
    out.volume_error_bound = vb;
    out.area_error_bound = area_err;
    let c = if v != 0.0 {
        DVec3::new(sums.m[0] / v, sums.m[1] / v, sums.m[2] / v)
    } else {
        DVec3::ZERO
    };
    out.centroid = (o + c).to_array();
    // Second moments about the centroid.
    let sxx = sums.s[0] - v * c.x * c.x;
    let syy = sums.s[1] - v * c.y * c.y;
    let szz = sums.s[2] - v * c.z * c.z;
    let pxy = sums.p[0] - v * c.x * c.y;
    let pyz = sums.p[1] - v * c.y * c.z;
    let pzx = sums.p[2] - v * c.z * c.x;
    out.inertia = [syy + szz, sxx + szz, sxx + syy, -pxy, -pyz, -pzx];
    if v.abs() > 0.0 {
        let cmax = c.abs().max_element();
        out.centroid_error_bound = (mb + cmax * vb) / (v.abs() - vb).max(f64::MIN_POSITIVE);
        let cb = out.centroid_error_bound;
        // s - v c^2 with errors in s (sb), v (vb) and c (cb).
        out.inertia_error_bound =
            2.0 * (sb + vb * (cmax + cb) * (cmax + cb) + 2.0 * v.abs() * (cmax + cb) * cb);
    }
    Ok(out)
}
