//! Subdivision depth for a tolerance (\[CL-R ch. 3\]).
//!
//! "Depth" = number of uniform Catmull-Clark steps after which the control
//! mesh of a patch lies within `eps` of its limit surface:
//! `max ||L(u,v) - S(u,v)|| <= eps`, L the bilinear maps of the refined
//! control faces. All bounds use the second-order norm `M`, the largest
//! Euclidean norm of the second-order forward differences (SOFDs) of the
//! patch's control points.
//!
//! * Regular patch, Lemma 1: distance <= M/3, and M shrinks by 1/4 per step,
//!   so `depth = ceil(log4(M / (3 eps)))`.
//! * Extraordinary patch, old technique (Theorem 6): distance after k steps
//!   <= `c_n r^k M`, with Lemma 2's rate r (2/3, 18/25, 3/4 + (8n-46)/(4n^2))
//!   and Lemma 5's constant c_n (1, 5/7, 4n/(n^2-8n+46), n^2/(2(n^2-8n+46)),
//!   the last from the geometric series; \[CL-R\] prints a 4 there: decision,
//!   the series' value). Standard weights only.
//! * Extraordinary patch, matrix technique (Theorem 11): with the group-I SOFD
//!   matrix `A` (2n x (2n+1)) and the 1-ring subdivision matrix `Lambda`,
//!   `r_i = ||A Lambda^i A^+||_inf`; `M_{2j} <= r_2^j M`, `M_{2j+1} <= r_1 r_2^j M`,
//!   and the distance at level i is <= `C_n M_i` where `C_n` is the supremum
//!   over m of the bound (3.17). The report takes `C_n` as the m -> infinity
//!   limit `(1 + r_1)/(min(n,8)(1 - r_2))` (Lemma 10), which fails for n = 8
//!   (decision: we take the true supremum, so the bound holds for all n).
//!   `depth = min(2l, 2k+1)`, the smallest even / odd level meeting eps.
//!
//! `M` here is the maximum over group I (`2V - E_i - E_(i+2)`,
//! `2E_(i+1) - F_i - F_(i+1)`) and over every row/column SOFD of the 4x4 grid
//! that exists around the patch (which contains group II), so it is never
//! smaller than the report's M.

use crate::config::MAX_K;
use crate::error::Error;
use crate::eval::Evaluator;
use crate::math::bspline::Grid;
use crate::mesh::stencil::label_at;
use glam::DVec3;

pub use crate::eigen::rates::{old_constants, rates, Rates};

/// Which bound to use for extraordinary patches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Method {
    /// Theorem 6 (Lemmas 2-5); standard weights only.
    Old = 0,
    /// Theorem 11 (matrix technique).
    New = 1,
    /// The smaller valid depth of all methods.
    Best = 2,
    /// Measured norms: the second-order norms of the exactly subdivided
    /// control points at each level (`A^i G` for the extraordinary part, the
    /// regular sub-patches `G_{m,b}` with Lemma 1's rate), with Theorem 11's
    /// constant for the extraordinary part (the report: "the same bound
    /// applies at any level i with M_i in place of M_0"), or, where smaller,
    /// the eigen-expansion flatness of the corner cell for the corner face
    /// (\[CL-R ch. 7\], see [`tight_depth`]). Never larger than `New` (it
    /// replaces the estimate `M_i <= r_i M_0` by the true `M_i`).
    Tight = 3,
}

/// Second-order norm `M` of a patch from its 2n+8 control points in label
/// order (see module docs for which SOFDs count).
pub fn second_order_norm(n: usize, g: &[DVec3]) -> f64 {
    let mut m = 0.0f64;
    if n != 4 {
        for i in 0..n {
            let a = g[0] * 2.0 - g[1 + 2 * i] - g[1 + 2 * ((i + 2) % n)];
            let b = g[1 + 2 * ((i + 1) % n)] * 2.0 - g[2 + 2 * i] - g[2 + 2 * ((i + 1) % n)];
            m = m.max(a.length()).max(b.length());
        }
    }
    let at = |x: i32, y: i32| label_at(n, x, y).map(|l| g[l]);
    for y in -1..=2 {
        for x in 0..=1 {
            if let (Some(a), Some(b), Some(c)) = (at(x - 1, y), at(x, y), at(x + 1, y)) {
                m = m.max((b * 2.0 - a - c).length());
            }
        }
    }
    for x in -1..=2 {
        for y in 0..=1 {
            if let (Some(a), Some(b), Some(c)) = (at(x, y - 1), at(x, y), at(x, y + 1)) {
                m = m.max((b * 2.0 - a - c).length());
            }
        }
    }
    m
}

/// Smallest integer `d >= 0` with `c * q^d * m <= eps` (q in (0,1)); None if
/// no such d below 10_000 (q >= 1 or not finite).
fn levels(c: f64, q: f64, m: f64, eps: f64) -> Option<u32> {
    if !(q.is_finite() && q > 0.0 && q < 1.0 && c.is_finite() && m.is_finite()) {
        return None;
    }
    let mut bound = c * m;
    for d in 0..10_000u32 {
        if bound <= eps {
            return Some(d);
        }
        bound *= q;
    }
    None
}

/// Depth of a regular patch (Lemma 1) with second-order norm `m`.
pub fn regular_depth(m: f64, eps: f64) -> u32 {
    levels(1.0 / 3.0, 0.25, m, eps).unwrap_or(u32::MAX)
}

/// Depth of an extraordinary patch with norm `m` by Theorem 6, if applicable.
pub fn old_depth(r: &Rates, m: f64, eps: f64) -> Option<u32> {
    if r.r_old == 0.0 {
        return None;
    }
    levels(r.c_old, r.r_old, m, eps)
}

/// Depth of an extraordinary patch with norm `m` by Theorem 11:
/// `min(2l, 2k+1)`.
pub fn new_depth(r: &Rates, m: f64, eps: f64) -> Option<u32> {
    if r.c_new == 0.0 {
        return None;
    }
    let l = levels(r.c_new, r.r2, m, eps)?;
    let k = levels(r.c_new * r.r1, r.r2, m, eps)?;
    Some((2 * l).min(2 * k + 1))
}

/// Depth by `method` (Best = the smaller valid one).
pub fn ev_depth(r: &Rates, m: f64, eps: f64, method: Method) -> Option<u32> {
    match method {
        Method::Old => old_depth(r, m, eps),
        Method::New => new_depth(r, m, eps),
        Method::Tight => new_depth(r, m, eps),
        Method::Best => match (old_depth(r, m, eps), new_depth(r, m, eps)) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        },
    }
}

/// Second-order norm of a regular 4x4 grid (structure of arrays, see
/// [`crate::math::bspline::Grid`]): the 16 row and column SOFDs (Lemma 1's M).
pub fn grid_norm(g: &crate::math::bspline::Grid) -> f64 {
    let p = |i: usize, j: usize| DVec3::new(g[i * 4 + j], g[16 + i * 4 + j], g[32 + i * 4 + j]);
    let mut m = 0.0f64;
    for a in 0..4 {
        for b in 1..3 {
            m = m.max((p(b, a) * 2.0 - p(b - 1, a) - p(b + 1, a)).length());
            m = m.max((p(a, b) * 2.0 - p(a, b - 1) - p(a, b + 1)).length());
        }
    }
    m
}

/// Guaranteed distance between the corner control face of level `i`
/// (labels `V`, `E_0`, `F_0`, `E_1` of `pts = A^i G`, at the corners
/// `w = (0,0), (1,0), (1,1), (0,1)` of the corner cell `[0, 2^-i]^2`) and
/// the limit surface over that cell, from the eigen-expansion flatness
/// (\[CL-R ch. 7\]): with the affine `A` of
/// [`crate::eigen::ValenceTable::corner_flatness`] (`|S - A| <= E_i` on
/// the cell) and the bilinear map `B` of the face, `B - A` is the bilinear
/// interpolant of `P_j - A(w_j)` (A is affine), so
/// `|S - B| <= E_i + max_j |P_j - A(w_j)|`. Plus a rounding margin of
/// `1e-12 (|L| + sum_c |ghat_c|)` (the sums have at most 2n+8 terms of
/// that size, each rounded to 2^-53 relative). `None` for a table with a
/// 2x2 block (whose affine part `corner_affine` does not describe).
fn corner_face_distance(
    tab: &crate::eigen::ValenceTable,
    ghat: &[f64],
    i: u32,
    pts: &[DVec3],
) -> Option<f64> {
    let n = tab.valence();
    if tab.has_complex_pair() || ghat.len() < 3 * (2 * n + 8) || pts.len() < 2 * n + 8 {
        return None;
    }
    let limit = DVec3::new(ghat[0], ghat[1], ghat[2]);
    let mut off = 0.0f64;
    for (x, y) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
        let label = label_at(n, x, y)?;
        let a = limit + tab.corner_affine(ghat, i, (f64::from(x), f64::from(y)));
        off = off.max((pts[label] - a).length());
    }
    let size = ghat.chunks_exact(3).fold(limit.length(), |s, g| {
        s + DVec3::new(g[0], g[1], g[2]).length()
    });
    Some(tab.corner_flatness(ghat, i) + off + 1e-12 * size)
}

/// [`Method::Tight`] depth of an extraordinary patch from its eigen
/// projection `ghat` (see [`crate::eigen::ValenceTable::project`]): the smallest
/// level `i` at which every regular sub-patch `G_{m,b}` (m <= i) satisfies
/// `M(G_{m,b}) / (3 * 4^(i-m)) <= eps` (Lemma 1 on the ring regions) and
/// the corner control face is within eps: `C_n M(A^i G) <= eps`
/// (Theorem 11 with the measured norm) or its eigen-expansion distance
/// (`corner_face_distance`) is. The control faces of level `i` are the
/// corner face and those of the `G_{m,b}` subdivided `i - m` times, so
/// both bounds together cover all of them.
/// None when the constants are unavailable or no level up to 200 suffices.
pub fn tight_depth(tab: &crate::eigen::ValenceTable, ghat: &[f64], eps: f64) -> Option<u32> {
    let c = tab.rates().c_new;
    if !(c > 0.0 && c.is_finite()) {
        return None;
    }
    let n = tab.valence();
    let k = 2 * n + 8;
    let mut pts = [DVec3::ZERO; MAX_K];
    let mut reg = 0.0f64; // max over m <= i of M(G_{m,b}) * 4^m
    let mut four_i = 1.0f64;
    for i in 0..=200u32 {
        if i >= 1 {
            four_i *= 4.0;
            for b in 1..=3 {
                let mut g = [0.0; 48];
                tab.sub_patch(ghat, i, b, true, &mut g);
                reg = reg.max(grid_norm(&g) * four_i);
            }
        }
        tab.level_points(ghat, i, &mut pts[..k]);
        if reg / (3.0 * four_i) > eps {
            continue;
        }
        let mi = second_order_norm(n, &pts[..k]);
        if c * mi <= eps || corner_face_distance(tab, ghat, i, &pts[..k]).is_some_and(|d| d <= eps)
        {
            return Some(i);
        }
    }
    None
}

/// Second-order norm `M` of patch `pi` (see [`crate::bounds::depth`]).
fn patch_norm(ev: &Evaluator, pi: usize) -> f64 {
    let meta = ev.patch_meta[pi];
    let n = (meta & 0xff) as usize;
    let o = ev.patch_data[pi] as usize;
    if n == 4 {
        match <&Grid>::try_from(&ev.data[o..o + 48]) {
            Ok(g) => grid_norm(g),
            Err(_) => f64::INFINITY,
        }
    } else {
        let lay = ev.ev_layout(o, n);
        let stored = &ev.data[lay.points()];
        let mut pts = [DVec3::ZERO; MAX_K];
        for (c, q) in pts.iter_mut().take(lay.k).enumerate() {
            *q = DVec3::new(stored[3 * c], stored[3 * c + 1], stored[3 * c + 2]);
        }
        second_order_norm(n, &pts[..lay.k])
    }
}

/// Subdivision depth per slot for tolerance `eps` (\[CL-R ch. 3\]): the
/// number of uniform Catmull-Clark steps of the **base** mesh (internal
/// pre-refinement included) after which every control face of that
/// (sub-)face is within `eps` of the limit surface. Written in slot order
/// into `out` (`out.len() >= num_slots()`, else
/// [`Error::BufferTooSmall`] with the count; nothing written on error).
///
/// Rounding: each patch's depth is for `eps` less its rounding term
/// ([`crate::bounds::rounding::term`] of its control data's magnitude).
///
/// Errors: `eps` not positive and finite; [`Method::Old`]
/// with non-standard weights at a valence present in the mesh;
/// `CoordinateRange` if `eps` is not above a patch's rounding term or the
/// data is out of range.
pub fn depths(ev: &Evaluator, eps: f64, method: Method, out: &mut [u32]) -> Result<(), Error> {
    if !(eps.is_finite() && eps > 0.0) {
        return Err(Error::InvalidArgument("eps must be positive and finite"));
    }
    let ns = ev.num_slots();
    if out.len() < ns {
        return Err(Error::BufferTooSmall { required: ns });
    }
    // First pass: validate (so that nothing is written on error).
    for pi in 0..ev.patch_meta.len() {
        let n = (ev.patch_meta[pi] & 0xff) as usize;
        if n != 4 {
            let Some(t) = ev.tables.get(n) else {
                return Err(Error::MissingTable { valence: n as u32 });
            };
            if ev_depth(t.rates(), 1.0, 1.0, method).is_none() {
                return Err(Error::InvalidArgument(
                    "the old depth technique needs standard weights",
                ));
            }
        }
        if eps <= super::rounding::term(super::rounding::patch_magnitude(ev, pi))? {
            return Err(Error::CoordinateRange(
                "eps is below the rounding of the coordinates",
            ));
        }
    }
    for s in 0..ns {
        let p0 = ev.slot_patch[s] as usize;
        let np = if ev.slot_split[s] != 0 { 4 } else { 1 };
        let mut d = 0u32;
        for pi in p0..p0 + np {
            let meta = ev.patch_meta[pi];
            let n = (meta & 0xff) as usize;
            let level = meta >> 16;
            let m = patch_norm(ev, pi);
            // Rounding: the depth for eps less the patch's rounding term
            // (checked positive above).
            let eps = eps
                - super::rounding::term(super::rounding::patch_magnitude(ev, pi))
                    .unwrap_or(f64::INFINITY);
            let pd = if n == 4 {
                regular_depth(m, eps)
            } else {
                let o = ev.patch_data[pi] as usize;
                let ghat = &ev.data[ev.ev_layout(o, n).ghat()];
                ev.tables
                    .get(n)
                    .and_then(|t| {
                        let by_m = ev_depth(t.rates(), m, eps, method);
                        match method {
                            Method::Tight | Method::Best => {
                                match (tight_depth(t, ghat, eps), by_m) {
                                    (Some(a), Some(b)) => Some(a.min(b)),
                                    (a, b) => a.or(b),
                                }
                            }
                            _ => by_m,
                        }
                    })
                    .unwrap_or(u32::MAX)
            };
            d = d.max(pd.saturating_add(level));
        }
        out[s] = d;
    }
    Ok(())
}
