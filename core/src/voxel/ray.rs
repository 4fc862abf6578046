//! Certified inside/outside test of a point: the signed number of crossings
//! of an axis-parallel ray with the limit surface, as a sum of topological
//! degrees.
//!
//! Let the ray start at `p` and run along `+e_a`, and let `pi` project onto
//! the other two axes `(b1, b2)` (cyclic order, so that the Jacobian of
//! `pi o S` is `(S_u x S_v)_a`). Every cell of the surface whose guaranteed
//! box (Bezier net box, or corner ball) lies
//!
//! * beside the ray (`pi(p)` outside the box's projection) or behind `p`
//!   contributes nothing;
//! * wholly ahead of `p` contributes the degree of `pi o S` over the cell at
//!   `pi(p)`, which equals the winding number of the projected boundary curve
//!   (four cubic Bezier curves) around `pi(p)`, which in turn equals the sum
//!   of `sign((S_u x S_v)_a)` over the crossings in the cell;
//! * otherwise it is split. A box that meets the ray on both sides of `p`
//!   contains `p`, which is impossible once the box is smaller than the
//!   distance from `p` to the surface, so the splitting ends.
//!
//! The winding number of a Bezier curve is summed piecewise: a piece whose
//! control polygon's box excludes `pi(p)` sweeps exactly the principal angle
//! between its end points (it stays in a convex set that excludes the
//! point). Each cell's sum is rounded to an integer (it is `2 pi` times one,
//! up to rounding; a sum further than 1/4 from an integer, or a point too
//! close to a curve or to an extraordinary vertex's projection, fails the
//! test, and the caller tries another ray). The total is the winding number
//! of the surface around `p`; `p` is inside iff it is odd.
//!
//! **Rounding margin.** Neighbouring cells are computed along different
//! paths (another B-spline grid, another Bezier conversion), so the two
//! copies of their shared boundary curve differ by rounding. A ray through
//! that curve (a symmetric shape whose symmetry plane holds both the ray
//! and a crease, say) could then see `pi(p)` inside both cells, or inside
//! neither, and count the crossing twice or never: a wrong parity with no
//! degenerate sum to notice. So every exclusion keeps the margin
//! [`RAY_EPS`] (voxel units, far above the rounding of nets with
//! coordinates up to 65536, far below a voxel): a box is beside the ray
//! only if `pi(p)` is outside it by `RAY_EPS`, a curve piece sweeps its
//! principal angle only if its box excludes `pi(p)` by `RAY_EPS`, and a
//! curve that passes within `RAY_EPS` of `pi(p)` fails the ray.
//!
//! A hull cell of a feature mesh (not polynomial at its level) has no
//! boundary curve to wind: it contributes nothing when its box is beside
//! the ray and is split otherwise, so its pieces end up beside the ray or
//! polynomial; a ray through the limit point of the special vertex itself
//! fails (depth guard) and another ray is tried.

use super::cells::{
    corner_children, for_each_root, limit_point, net_box, patch_hull, split4, Affine, Cell, Net,
    Patch,
};
use super::stack::{Entry, VoxelWork, MAX_DEPTH, STACK_CAP};
use super::Surface;
use glam::{DVec2, DVec3};

const CURVE_DEPTH: u32 = 52;
const CURVE_CAP: usize = 64;

/// The rounding margin of every exclusion (voxel units; see the module
/// docs).
pub(crate) const RAY_EPS: f64 = 1e-6;

/// Angle swept by the cubic Bezier curve `c` (relative to the origin).
fn curve_angle(c: [DVec2; 4]) -> Option<f64> {
    let mut st = [([DVec2::ZERO; 4], 0u32); CURVE_CAP];
    let mut n = 1usize;
    st[0] = (c, 0);
    let mut total = 0.0;
    while n > 0 {
        n -= 1;
        let (q, d) = st[n];
        let lo = q[0].min(q[1]).min(q[2]).min(q[3]);
        let hi = q[0].max(q[1]).max(q[2]).max(q[3]);
        if lo.x > RAY_EPS || lo.y > RAY_EPS || hi.x < -RAY_EPS || hi.y < -RAY_EPS {
            let (a, b) = (q[0], q[3]);
            total += libm::atan2(a.perp_dot(b), a.dot(b));
            continue;
        }
        // A piece within the margin and no larger than it: the curve
        // passes within 2 RAY_EPS of the point.
        let small = (hi - lo).max_element() <= RAY_EPS;
        if small || d >= CURVE_DEPTH || n + 2 > CURVE_CAP {
            return None;
        }
        let ab = (q[0] + q[1]) * 0.5;
        let bc = (q[1] + q[2]) * 0.5;
        let cd = (q[2] + q[3]) * 0.5;
        let abc = (ab + bc) * 0.5;
        let bcd = (bc + cd) * 0.5;
        let m = (abc + bcd) * 0.5;
        st[n] = ([m, bcd, cd, q[3]], d + 1);
        st[n + 1] = ([q[0], ab, abc, m], d + 1);
        n += 2;
    }
    Some(total)
}

/// Winding number of the projected boundary of a net around `q`.
fn net_winding(net: &Net, b1: usize, b2: usize, q: DVec2) -> Option<i64> {
    let pr = |i: usize| DVec2::new(net[b1 * 16 + i], net[b2 * 16 + i]) - q;
    let edges = [
        [pr(0), pr(4), pr(8), pr(12)],
        [pr(12), pr(13), pr(14), pr(15)],
        [pr(15), pr(11), pr(7), pr(3)],
        [pr(3), pr(2), pr(1), pr(0)],
    ];
    let mut s = 0.0;
    for e in edges {
        s += curve_angle(e)?;
    }
    let w = s / core::f64::consts::TAU;
    let r = libm::round(w);
    if (w - r).abs() > 0.25 {
        return None;
    }
    Some(r as i64)
}

/// Winding number of the surface around `p` (voxel coordinates, `aff` maps
/// model to voxel space) from the ray along `+e_axis`, or None if this ray
/// is too close to a degenerate configuration.
pub(crate) fn winding<S: Surface + ?Sized>(
    ev: &S,
    aff: &Affine,
    p: DVec3,
    axis: usize,
    work: &mut VoxelWork,
) -> Option<i64> {
    let mut total = 0i64;
    for pi in 0..ev.patch_count() {
        total += patch_winding(ev, aff, p, axis, pi, work)?;
    }
    Some(total)
}

/// The contribution of patch `pi` to [`winding`] (None: degenerate ray).
pub(crate) fn patch_winding<S: Surface + ?Sized>(
    ev: &S,
    aff: &Affine,
    p: DVec3,
    axis: usize,
    pi: usize,
    work: &mut VoxelWork,
) -> Option<i64> {
    let a = axis % 3;
    let (b1, b2) = ((a + 1) % 3, (a + 2) % 3);
    let q = DVec2::new(p[b1], p[b2]);
    let beside = |lo: DVec3, hi: DVec3| {
        q.x < lo[b1] - RAY_EPS
            || q.x > hi[b1] + RAY_EPS
            || q.y < lo[b2] - RAY_EPS
            || q.y > hi[b2] + RAY_EPS
            || hi[a] < p[a]
    };
    let mut total = 0i64;
    let mut failed = false;
    {
        let pt = ev.patch_at(pi)?;
        let (hl, hh) = patch_hull(&pt);
        if beside(aff.apply(hl), aff.apply(hh)) {
            return Some(0);
        }
        work.len = 0;
        for_each_root(&pt, 1, aff, |c| {
            work.push(Entry::new(c, 0, 0, 0));
        });
        while let Some(e) = work.pop() {
            match e.cell() {
                Cell::Poly(n) => {
                    let (lo, hi) = net_box(&n);
                    if beside(lo, hi) {
                        continue;
                    }
                    if lo[a] > p[a] {
                        match net_winding(&n, b1, b2, q) {
                            Some(w) => total += w,
                            None => failed = true,
                        }
                        continue;
                    }
                    if e.depth >= MAX_DEPTH || work.len + 4 > STACK_CAP {
                        failed = true;
                        continue;
                    }
                    let mut kids: [Net; 4] = [[0.0; 48]; 4];
                    split4(&n, &mut kids);
                    for k in kids {
                        work.push(Entry::new(Cell::Poly(k), e.depth + 1, e.level + 1, 0));
                    }
                }
                Cell::Corner(l) => {
                    let Patch::Extra {
                        tab, ghat, cache, ..
                    } = pt
                    else {
                        continue;
                    };
                    let c = aff.apply(limit_point(ghat));
                    let r = DVec3::splat(tab.corner_radius(ghat, l) * aff.scale);
                    if beside(c - r, c + r) {
                        continue;
                    }
                    if e.depth >= MAX_DEPTH || work.len + 4 > STACK_CAP {
                        failed = true;
                        continue;
                    }
                    let kids = corner_children(tab, ghat, cache, l, aff);
                    work.push(Entry::new(Cell::Corner(l + 1), e.depth + 1, l + 1, 0));
                    for k in kids {
                        work.push(Entry::new(Cell::Poly(k), e.depth + 1, l + 1, 0));
                    }
                }
                Cell::Hull(h) => {
                    let Patch::Feature(fp) = &pt else {
                        continue;
                    };
                    if beside(h.lo, h.hi) {
                        continue;
                    }
                    if e.depth >= MAX_DEPTH || work.len + 4 > STACK_CAP {
                        failed = true;
                        continue;
                    }
                    for c in h.children(fp, aff) {
                        work.push(Entry::new(c, e.depth + 1, e.level + 1, 0));
                    }
                }
            }
            if failed {
                return None;
            }
        }
    }
    // Arms that `continue` after a failure skip the check in the loop.
    if failed {
        return None;
    }
    Some(total)
}

/// Perpendicular offsets tried for a thick (N = 6) voxelization, where the
/// whole voxel minus a `TAU` rim is free of the surface.
const OFFSETS: [(f64, f64); 6] = [
    (0.0, 0.0),
    (0.123_456_7, 0.234_567_8),
    (-0.271_828_1, 0.141_421_3),
    (0.314_159_2, -0.173_205_0),
    (-0.223_606_7, -0.264_575_1),
    (0.057_721_5, -0.311_029_9),
];

/// Inside/outside of the voxel centre `c` (voxel coordinates): None if
/// every ray tried was degenerate. With `thin` only rays through the
/// centre itself are valid (the surface may pass through a white voxel
/// off its centre lines).
pub(crate) fn inside<S: Surface + ?Sized>(
    ev: &S,
    aff: &Affine,
    c: DVec3,
    thin: bool,
    work: &mut VoxelWork,
) -> Option<bool> {
    let tries = if thin { 1 } else { OFFSETS.len() };
    for &(d1, d2) in &OFFSETS[..tries] {
        for axis in 0..3 {
            let mut p = c;
            p[(axis + 1) % 3] += d1;
            p[(axis + 2) % 3] += d2;
            if let Some(w) = winding(ev, aff, p, axis, work) {
                return Some(w.rem_euclid(2) == 1);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Net of the axis-aligned rectangle `[y0, y1] x [z0, z1]` in the
    /// plane `x = 5` (a flat bilinear cell, `u` along y, `v` along z).
    fn rect_net(y0: f64, y1: f64, z0: f64, z1: f64) -> Net {
        let mut n = [0.0; 48];
        for k in 0..4 {
            for l in 0..4 {
                let i = k * 4 + l;
                n[i] = 5.0;
                n[16 + i] = y0 + (y1 - y0) * k as f64 / 3.0;
                n[32 + i] = z0 + (z1 - z0) * l as f64 / 3.0;
            }
        }
        n
    }

    /// The root cause of the chaikin0 flood bug: two cells whose copies of
    /// the shared side differ by rounding (1e-15) both contain a point on
    /// that side; without the margin each winds once around it and the ray
    /// counts one crossing twice (even parity). With it, both fail and the
    /// caller takes another ray.
    #[test]
    fn a_point_on_a_shared_side_fails_instead_of_counting_twice() {
        let left = rect_net(-1.0, 1e-15, -1.0, 1.0);
        let right = rect_net(-1e-15, 1.0, -1.0, 1.0);
        let q = DVec2::ZERO;
        assert_eq!(net_winding(&left, 1, 2, q), None);
        assert_eq!(net_winding(&right, 1, 2, q), None);
        // Clear of the side by more than the margin: exactly one cell.
        for (y, want) in [(-1e-5, (1, 0)), (1e-5, (0, 1))] {
            let q = DVec2::new(y, 0.3);
            let got = (net_winding(&left, 1, 2, q), net_winding(&right, 1, 2, q));
            assert_eq!(got, (Some(want.0), Some(want.1)), "y = {y}");
        }
    }

    /// A curve through the point's margin fails; one clear of it sweeps
    /// the principal angle.
    #[test]
    fn curve_angle_fails_within_the_margin() {
        let seg = |d: f64| {
            let (a, b) = (DVec2::new(-1.0, d), DVec2::new(1.0, d));
            [a, a + (b - a) / 3.0, a + (b - a) * 2.0 / 3.0, b]
        };
        for d in [0.0, 1e-15, -1e-12, 1e-7, -9e-7] {
            assert_eq!(curve_angle(seg(d)), None, "d = {d}");
        }
        for d in [1e-4, -1e-4, 0.5] {
            let a = curve_angle(seg(d)).unwrap();
            let want = libm::atan2(-2.0 * d, d * d - 1.0);
            assert!((a - want).abs() < 1e-12, "d = {d}: {a} vs {want}");
        }
    }
}
