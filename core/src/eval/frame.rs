//! Corner frames of a patch: the parameter rotation between a face (or
//! slot) and the frame of one of its corners, and the quadrants of a
//! split slot.
//!
//! The rotations are `match`es: branch-free forms (bit-mask selection on
//! SSE2 lanes, candidates read by index) gave the same bits but ran 4-16 %
//! slower per point than the mispredicted jumps they replace (see
//! docs/bench-log.md, 2026-11-28). What paid was doing fewer rotations:
//! [`split_params`] turns a split slot's point into its child's with one
//! rotation instead of two.
//!
//! Layer 5 (with the rest of `eval/`): imports `math`.

use crate::math::simd::F2;
use crate::math::Eval;

/// Maps face parameters to the parameters of the corner-`r` frame
/// (origin at corner r, x toward corner r+1, y toward corner r-1).
#[inline(always)]
pub(crate) fn rot_param(r: u8, s: f64, t: f64) -> (f64, f64) {
    match r & 3 {
        0 => (s, t),
        1 => (t, 1.0 - s),
        2 => (1.0 - s, 1.0 - t),
        _ => (1.0 - t, s),
    }
}

/// Transforms derivatives from the corner-`r` frame back to the face frame,
/// multiplied by `scale` (first) and `scale^2` (second).
#[inline(always)]
pub(crate) fn rot_back<const SECOND: bool>(r: u8, e: &mut Eval, scale: f64) {
    let (du, dv) = (e.du, e.dv);
    let (a, b) = match r & 3 {
        0 => (du, dv),
        1 => (-dv, du),
        2 => (-du, -dv),
        _ => (dv, -du),
    };
    e.du = a * scale;
    e.dv = b * scale;
    if SECOND {
        let (uu, uv, vv) = (e.duu, e.duv, e.dvv);
        let (x, y, z) = match r & 3 {
            0 => (uu, uv, vv),
            1 => (vv, -uv, uu),
            2 => (uu, uv, vv),
            _ => (vv, -uv, uu),
        };
        let s2 = scale * scale;
        e.duu = x * s2;
        e.duv = y * s2;
        e.dvv = z * s2;
    }
}

/// The quadrant `c` of `(u, v)` in a split slot and the point doubled
/// and moved to that quadrant's unit square, `(2u - [u >= 1/2], 2v - [v
/// >= 1/2])`, without a branch. Child `c` evaluated there with rotation
/// `c` gives the bits of the rotate-then-double map (`rot_param(c, u, v)`
/// doubled, then the derivatives turned back by `c`): `2u - 1` is exact
/// for `u` in `[1/2, 1]`, and `1 - (2u - 1)` is `2 (1 - u)` rounded once,
/// as doubling the rounded `1 - u` is.
#[inline(always)]
pub(crate) fn split_params(u: f64, v: f64) -> (u8, f64, f64) {
    let (cx, cy) = (u >= 0.5, v >= 0.5);
    let c = ((cy as u8) * 3) ^ cx as u8;
    // By a compare mask: `2.0 * u - cx as u8 as f64` compiled to a jump.
    let w = F2::ld2(u, v);
    let d = w
        .mul(F2::splat(2.0))
        .minus_where_ge(w, F2::splat(0.5), F2::splat(1.0));
    (c, d.lo(), d.hi())
}

/// The quadrant of `(s, t)`: 0 lower left, 1 lower right, 2 upper right,
/// 3 upper left (halves closed at 1/2 upward).
#[inline(always)]
pub(crate) fn quadrant(s: f64, t: f64) -> u8 {
    match (s >= 0.5, t >= 0.5) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;
    use glam::DVec3;

    /// The split map gives the bits of the rotate-then-double map it
    /// replaces in the evaluator, on `[0, 1]^2` (random points, dyadic
    /// points, the halves' edges, signed zeros): the child frame's point
    /// is the doubled rotated point, and turning the derivatives back by
    /// the quadrant with scale 2 is the old scale-2 then turn.
    #[test]
    fn split_map_is_rotate_then_double_bit_for_bit() {
        let mut rng = XorShift(7);
        // Fewer points under Miri (about a minute per thousand there).
        let n = if cfg!(miri) { 400 } else { 40_000 };
        for k in 0..n {
            let (u, v) = match k % 4 {
                0 => (rng.unit(), rng.unit()),
                1 => (
                    (rng.next_u64() % 65) as f64 / 64.0,
                    (rng.next_u64() % 65) as f64 / 64.0,
                ),
                2 => (0.5, rng.unit()),
                _ => (rng.unit(), if k % 8 == 3 { -0.0 } else { 1.0 }),
            };
            let (c, x, y) = split_params(u, v);
            assert_eq!(c, quadrant(u, v));
            let (a, b) = rot_param(c, x, y);
            let (s, t) = rot_param(c, u, v);
            assert_eq!(
                (a.to_bits(), b.to_bits()),
                ((2.0 * s).to_bits(), (2.0 * t).to_bits()),
                "u {u} v {v}"
            );
            let d = |rng: &mut XorShift| DVec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit());
            let e0 = Eval {
                du: d(&mut rng),
                dv: d(&mut rng),
                duu: d(&mut rng),
                duv: d(&mut rng),
                dvv: d(&mut rng),
                ..Eval::default()
            };
            let (mut old, mut new) = (e0, e0);
            rot_back::<true>(0, &mut old, 2.0);
            rot_back::<true>(c, &mut old, 1.0);
            rot_back::<true>(c, &mut new, 2.0);
            for (p, q) in [
                (old.du, new.du),
                (old.dv, new.dv),
                (old.duu, new.duu),
                (old.duv, new.duv),
                (old.dvv, new.dvv),
            ] {
                assert_eq!(
                    p.to_array().map(f64::to_bits),
                    q.to_array().map(f64::to_bits)
                );
            }
        }
    }
}
