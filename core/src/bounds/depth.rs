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
    /// Near-exact distances (\[CL-R ch. 3, ch. 7\], see [`tight_depth`] and
    /// [`regular_tight_depth`]): every control face of a regular patch or
    /// of a ring region `G_{m,b}` subdivided up to `RING_EXACT` steps gets
    /// the Bezier-net distance of [`super::face_distance`] (Lemma 1 from
    /// there on); the corner face the eigen-expansion flatness with its
    /// cell split into ring regions, or Theorem 11's constant with the
    /// measured norm `M(A^i G)` where smaller. Never larger than `New`.
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

/// How many subdivision steps of a ring-region grid `G_{m,b}` get the
/// per-face Bezier-net distance ([`super::face_distance`]); beyond that,
/// Lemma 1 from the grids of that depth (`M / (3 * 4^d)`). 4^RING_EXACT
/// faces per grid: the cost of the bound grows fourfold per step.
const RING_EXACT: usize = 3;
const _: () = assert!(RING_EXACT <= super::face_distance::MAX_DEPTH);

/// How many levels the corner cell is split into its ring regions at most
/// ([`corner_split_distance`]).
const CORNER_SPLITS: u32 = 24;

/// Relative rounding margin of the Bezier-net distances, times the size
/// `|L| + sum_c |ghat_c|` of the patch: the grids and nets are sums of at
/// most 2n+8 products of table constants and `ghat` entries, followed by
/// B-spline refinement, conversion to Bezier form and de Casteljau
/// (convex combinations), each step rounded to 2^-53 relative.
const NET_MARGIN: f64 = 1e-11;

/// `|L| + sum_c |ghat_c|` of a projection (for the rounding margins).
fn ghat_size(ghat: &[f64]) -> f64 {
    ghat.chunks_exact(3)
        .fold(0.0, |s, g| s + DVec3::new(g[0], g[1], g[2]).length())
}

/// Guaranteed distance between the level-`i` corner control face (the
/// bilinear map `B` of `pts`' labels `V, E_0, F_0, E_1`, in corner-cell
/// coordinates `w = 2^i (u, v)` at `(0,0), (1,0), (1,1), (0,1)`) and the
/// limit surface over the corner cell `[0, 2^-i]^2`, by splitting the cell:
/// `[0, 2^-i]^2` is the union of the ring regions `Omega_{i+l,b}` (l = 1..J,
/// b = 1..3) and the corner cell `[0, 2^-(i+J)]^2`. On each ring region
/// the limit surface is the bicubic of `G_{i+l,b}` (\[CL-R ch. 7\]) and `B`
/// is bilinear, so [`super::face_distance::net_distance`] bounds `|S - B|`
/// there; on the small corner cell `|S - B| <= E_(i+J) + max_j |B(w_j) -
/// L - A(w_j)|` (`A` the affine function of the flatness `E_(i+J)`, see
/// [`corner_face_distance`], `w_j` the small cell's corners, where the
/// bilinear `B - A` takes its largest length). The bound is the maximum of
/// the parts, minimised over J = 0..CORNER_SPLITS (J = 0 is
/// [`corner_face_distance`]), plus a rounding margin. The splitting stops
/// once the bound is at most `stop` or the ring regions' part alone
/// exceeds it (that part only grows with J), so the result is exact-valued
/// as a bound but only decides `<= stop`. `None` for a table with a 2x2
/// block.
#[inline(never)] // own frame: the depth bounds run on an 8 KiB stack
fn corner_split_distance(
    tab: &crate::eigen::ValenceTable,
    ghat: &[f64],
    i: u32,
    pts: &[DVec3],
    stop: f64,
) -> Option<f64> {
    let n = tab.valence();
    let mut best = corner_face_distance(tab, ghat, i, pts)?;
    if best <= stop {
        return Some(best);
    }
    let mut face = [DVec3::ZERO; 4];
    for (q, (x, y)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
        face[q] = pts[label_at(n, x, y)?];
    }
    let bl = |w: (f64, f64)| {
        face[0] * ((1.0 - w.0) * (1.0 - w.1))
            + face[1] * (w.0 * (1.0 - w.1))
            + face[2] * (w.0 * w.1)
            + face[3] * ((1.0 - w.0) * w.1)
    };
    let margin = NET_MARGIN * ghat_size(ghat);
    let limit = DVec3::new(ghat[0], ghat[1], ghat[2]);
    let mut rings = 0.0f64;
    for l in 1..=CORNER_SPLITS {
        let h = libm::scalbn(1.0, -(l as i32)); // side of Omega_{i+l,b} in w
        for (b, du, dv) in [(1usize, 1.0, 0.0), (2, 1.0, 1.0), (3, 0.0, 1.0)] {
            let mut g = [0.0; 48];
            tab.sub_patch(ghat, i + l, b, true, &mut g);
            let mut net = [0.0; 48];
            crate::math::bezier::from_grid_rotated(&g, 0, &mut net);
            let at = |s: f64, t: f64| bl((h * (s + du), h * (t + dv)));
            let corners = [at(0.0, 0.0), at(1.0, 0.0), at(1.0, 1.0), at(0.0, 1.0)];
            rings = rings.max(super::face_distance::net_distance(&net, corners));
        }
        if rings + margin >= best.min(stop) {
            break; // more splits cannot get below the ring regions' part
        }
        let mut off = 0.0f64;
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            let a = limit + tab.corner_affine(ghat, i + l, (x, y));
            off = off.max((bl((h * x, h * y)) - a).length());
        }
        let tail = tab.corner_flatness(ghat, i + l) + off;
        best = best.min(rings.max(tail) + margin);
        if best <= stop {
            break;
        }
    }
    Some(best)
}

/// Whether every face of `g` after `d` subdivision steps is within `eps`
/// of the bicubic of `g`: a subtree whose root grid at depth `k` has
/// [`super::face_distance::second_norm`]` / (6 * 4^(d-k)) <= eps` passes
/// whole; the faces at depth `d` the cheap bound does not settle get the
/// Bezier-net distance ([`super::face_distance::grid_face_within`]).
/// Depth first, keeping only the path (one grid and the next quadrant per
/// depth).
#[inline(never)] // own frame: the depth bounds run on an 8 KiB stack
fn faces_within(g: &Grid, d: usize, eps: f64) -> bool {
    use super::face_distance::{child_grid, grid_face_within, second_norm};
    if d > RING_EXACT {
        return false; // deeper than the path (never asked)
    }
    let settled =
        |g: &Grid, k: usize| second_norm(g) <= 6.0 * eps * libm::scalbn(1.0, 2 * (d - k) as i32);
    if settled(g, 0) {
        return true;
    }
    if d == 0 {
        return grid_face_within(g, eps);
    }
    // path[k - 1] = the grid at depth k >= 1 whose children are visited.
    let mut path = [[0.0f64; 48]; RING_EXACT];
    let mut next = [0usize; RING_EXACT + 1];
    let mut k = 0usize;
    loop {
        if next[k] == 4 {
            if k == 0 {
                return true;
            }
            k -= 1;
            continue;
        }
        let q = next[k];
        next[k] += 1;
        let child = child_grid(if k == 0 { g } else { &path[k - 1] }, q & 1, q >> 1);
        if settled(&child, k + 1) {
            continue;
        }
        if k + 1 == d {
            if !grid_face_within(&child, eps) {
                return false;
            }
            continue;
        }
        path[k] = child;
        next[k + 1] = 0;
        k += 1;
    }
}

/// Lemma 1's coefficient for the faces of `g` at any depth `d`: they are
/// within `lemma1_term(g) / 4^d` of the bicubic (`M / 3` of `CL-R` Lemma 1
/// or the direction-split `second_norm / 6` of
/// [`super::face_distance::second_norm`], whichever is smaller; both shrink
/// by 1/4 per step).
fn lemma1_term(g: &Grid) -> f64 {
    (grid_norm(g) / 3.0).min(super::face_distance::second_norm(g) / 6.0)
}

/// [`Method::Tight`] depth of a regular patch with B-spline grid `g`: a
/// depth `d` at which the faces of `g` subdivided `d` times are within
/// eps. First `by_m`, the smaller of Lemma 1 (`M / 3`) and its
/// direction-split form ([`super::face_distance::second_norm`]` / 6`);
/// then, for `d = by_m - 1, by_m - 2, ...` down to the first failure and
/// only while `d <= RING_EXACT`, the Bezier-net distance of every face
/// (`faces_within`); for `by_m - 1 > RING_EXACT` it stays `by_m`. A rounding margin of
/// `NET_MARGIN` times the grid's magnitude. Never above [`regular_depth`]
/// of `grid_norm(g)`. (Descending and stopping at the first failure keeps
/// the cost to about one full check per patch; the bound of a shallower
/// depth is almost never met when a deeper one is not.)
pub fn regular_tight_depth(g: &Grid, eps: f64) -> u32 {
    let by_m = regular_depth(grid_norm(g), eps).min(
        levels(1.0 / 6.0, 0.25, super::face_distance::second_norm(g), eps).unwrap_or(u32::MAX),
    );
    let eps = eps - NET_MARGIN * super::face_distance::grid_magnitude(g);
    let mut best = by_m;
    if by_m > RING_EXACT as u32 + 1 {
        return by_m;
    }
    while best > 0 && faces_within(g, (best - 1) as usize, eps) {
        best -= 1;
    }
    best
}

/// [`Method::Tight`] depth of an extraordinary patch from its eigen
/// projection `ghat` (see [`crate::eigen::ValenceTable::project`]): the
/// smallest level `i` at which every control face of level `i` is within
/// eps. Those are the corner face and the faces of the ring-region grids
/// `G_{m,b}` (m = 1..i, b = 1..3, \[CL-R ch. 7\]) subdivided `i - m` times.
/// * Ring faces: for `i - m <= RING_EXACT` the Bezier-net distance of each
///   face ([`super::face_distance`]), else Lemma 1 (`M / 3`, M shrinking by
///   1/4 per step) from the grids of depth `<= RING_EXACT`.
/// * Corner face: the smallest of Theorem 11 with the measured norm
///   (`C_n M(A^i G)`) and the split eigen-expansion bound
///   (`corner_split_distance`, which includes `corner_face_distance`).
///
/// None when the constants are unavailable or no level up to 200 suffices.
pub fn tight_depth(tab: &crate::eigen::ValenceTable, ghat: &[f64], eps: f64) -> Option<u32> {
    tight_scan(tab, ghat, eps, true, true)
}

/// The first level at which each part of the [`Method::Tight`] bound of an
/// extraordinary patch holds on its own: the ring regions (`[0]`) and the
/// corner control face (`[1]`); [`tight_depth`] is the first level where
/// both hold. For the breakdown of which part decides the depth.
pub fn tight_parts(tab: &crate::eigen::ValenceTable, ghat: &[f64], eps: f64) -> [Option<u32>; 2] {
    [
        tight_scan(tab, ghat, eps, true, false),
        tight_scan(tab, ghat, eps, false, true),
    ]
}

/// The scan of [`tight_depth`] with the ring part (`ring`) and the corner
/// part (`corner`) switched on or off.
fn tight_scan(
    tab: &crate::eigen::ValenceTable,
    ghat: &[f64],
    eps: f64,
    ring: bool,
    corner: bool,
) -> Option<u32> {
    const W: usize = RING_EXACT + 1;
    let c = tab.rates().c_new;
    if !(c > 0.0 && c.is_finite()) {
        return None;
    }
    let n = tab.valence();
    let k = 2 * n + 8;
    let eps_net = eps - NET_MARGIN * ghat_size(ghat);
    let mut pts = [DVec3::ZERO; MAX_K];
    // `reg` = the largest Lemma-1 coefficient times 4^m of the levels m whose
    // faces at depth i - m are beyond RING_EXACT; the others get the net
    // distance (their grids G_{m,b} recomputed, which is cheap).
    let mut reg = 0.0f64;
    let mut four_i = 1.0f64;
    let mut g = [0.0f64; 48];
    for i in 0..=200u32 {
        let iu = i as usize;
        if i >= 1 && ring {
            four_i *= 4.0;
            if iu > W {
                // Level m = i - W leaves the window.
                let m = iu - W;
                let four_m = libm::scalbn(1.0, 2 * m as i32);
                for b in 1..=3 {
                    tab.sub_patch(ghat, m as u32, b, true, &mut g);
                    reg = reg.max(lemma1_term(&g) * four_m);
                }
            }
        }
        if corner {
            tab.level_points(ghat, i, &mut pts[..k]);
            let mi = second_order_norm(n, &pts[..k]);
            let near = c * mi <= eps
                || corner_split_distance(tab, ghat, i, &pts[..k], eps).is_some_and(|d| d <= eps);
            if !near {
                continue;
            }
        }
        // The ring part (the costlier one) only where the corner part holds.
        if ring && i >= 1 {
            let mut ok = reg / four_i <= eps_net;
            for m in (iu.saturating_sub(RING_EXACT).max(1)..=iu).rev() {
                for b in 1..=3 {
                    if ok {
                        tab.sub_patch(ghat, m as u32, b, true, &mut g);
                        ok = faces_within(&g, iu - m, eps_net);
                    }
                }
            }
            if !ok {
                continue;
            }
        }
        return Some(i);
    }
    None
}

/// Per slot, the first level (base-mesh steps, internal levels included)
/// at which the ring-region part and the corner-face part of the
/// [`Method::Tight`] bound hold ([`tight_parts`]; a regular patch's depth
/// counts as ring part, its corner part is 0), with the same rounding
/// margin as [`depths`]; `u32::MAX` where a part never holds. For the
/// breakdown of which part decides the depth. `out.len() >= num_slots()`.
pub fn tight_depth_parts(ev: &Evaluator, eps: f64, out: &mut [[u32; 2]]) -> Result<(), Error> {
    let ns = ev.num_slots();
    if out.len() < ns {
        return Err(Error::BufferTooSmall { required: ns });
    }
    for s in 0..ns {
        let p0 = ev.slot_patch[s] as usize;
        let np = if ev.slot_split[s] != 0 { 4 } else { 1 };
        let mut d = [0u32; 2];
        for pi in p0..p0 + np {
            let meta = ev.patch_meta[pi];
            let n = (meta & 0xff) as usize;
            let level = meta >> 16;
            let eps = eps - super::rounding::term(super::rounding::patch_magnitude(ev, pi))?;
            let parts = if n == 4 {
                let by_m = regular_depth(patch_norm(ev, pi), eps);
                let d =
                    regular_grid(ev, pi).map_or(by_m, |g| by_m.min(regular_tight_depth(g, eps)));
                [Some(d), Some(0)]
            } else {
                let o = ev.patch_data[pi] as usize;
                let ghat = &ev.data[ev.ev_layout(o, n).ghat()];
                ev.tables
                    .get(n)
                    .map_or([None, None], |t| tight_parts(t, ghat, eps))
            };
            for (dj, pj) in d.iter_mut().zip(parts) {
                *dj = (*dj).max(pj.unwrap_or(u32::MAX).saturating_add(level));
            }
        }
        out[s] = d;
    }
    Ok(())
}

/// The B-spline grid of regular patch `pi` (None if the data is short).
fn regular_grid<'e>(ev: &'e Evaluator, pi: usize) -> Option<&'e Grid> {
    let o = ev.patch_data[pi] as usize;
    <&Grid>::try_from(ev.data.get(o..o + 48)?).ok()
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
                let by_m = regular_depth(m, eps);
                match (method, regular_grid(ev, pi)) {
                    (Method::Tight | Method::Best, Some(g)) => {
                        by_m.min(regular_tight_depth(g, eps))
                    }
                    _ => by_m,
                }
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
