//! The error bound of one crossing when its two sheets are moved by
//! different amounts ([`crossing_bound`]): the two-plane model of the
//! module docs of [`super`] ("wedge lemma"), with the two displacements
//! kept apart instead of both taken as their larger one.
//!
//! **Lemma.** Let `W = {m_A . x <= 0, m_B . x <= 0}` be a convex wedge (the
//! result near a crossing, or its complement) with unit normals, `c = m_A .
//! m_B = cos gamma`, and `W'` the wedge whose planes are moved by `d_A`,
//! `d_B` with `|d_A| <= t_A`, `|d_B| <= t_B`. Then the Hausdorff distance
//! between the boundaries of `W` and `W'` is at most
//!
//! `H = sqrt((t_A^2 + t_B^2 - 2 c t_A t_B) / (1 - c^2))` if `t_A >= c t_B`
//! and `t_B >= c t_A`, and `max(t_A, t_B)` otherwise,
//!
//! which is at most `max(t_A, t_B) / cos(gamma / 2)` (the bound with
//! equal displacements, [`crate::boolean::Crossing::amplification`]
//! times the larger), with equality when `t_A = t_B`.
//!
//! *Proof.* A face point of either boundary is within its own plane's
//! displacement of the other boundary unless its nearest point there is
//! the other wedge's apex, so the distance is largest at an apex. If both
//! planes move outward (`d_A, d_B >= 0`) the moved apex `x` solves `m_A .
//! x = d_A`, `m_B . x = d_B`; writing `x = alpha m_A + beta m_B`, `alpha =
//! (d_A - c d_B) / (1 - c^2)`, `beta = (d_B - c d_A) / (1 - c^2)`. When
//! both are non-negative `x` lies in the normal cone of `W` at its apex
//! and its distance to `W` is `|x|`, `|x|^2 = alpha d_A + beta d_B = g(d_A,
//! d_B) = (d_A^2 + d_B^2 - 2 c d_A d_B) / (1 - c^2)`; otherwise its
//! nearest point of `W` lies on a face and the distance is `d_A` or `d_B`.
//! Both moving inward is the same with the roles of `W` and `W'`
//! exchanged; moving in opposite directions, each apex projects onto the
//! other wedge's face that moved away from it (distance `|d_A|` or
//! `|d_B|`). `g` is convex, so its largest value on the polygon `{0 <= d_A
//! <= t_A, 0 <= d_B <= t_B, d_A >= c d_B, d_B >= c d_A}` is at a corner:
//! `g(t_A, t_B)` when that corner belongs to it; the corners on the lines
//! `d_B = c d_A` and `d_A = c d_B` give `g = d_A^2` or `d_B^2` resp. (and
//! `d_B^2 / c^2 <= t_A^2` where `d_B = t_B < c t_A`), i.e. at most `max(t_A,
//! t_B)^2`. Finally `g(t_A, t_B) - t_A^2 = (t_B - c t_A)^2 / (1 - c^2) >= 0`,
//! and `g` grows in both arguments on the polygon, so `g(t_A, t_B) <=
//! g(t, t) = 2 t^2 / (1 + c) = t^2 / cos^2(gamma / 2)`, `t = max(t_A,
//! t_B)`. `□`
//!
//! The test below checks the lemma against sampled boundaries of moved
//! wedges (and that it is reached); `tests.rs` checks it on moved boxes.

/// The bound of the lemma above for a crossing of amplification
/// `amplification = 1 / cos(gamma / 2)` whose sheets are within `t_a` and
/// `t_b` of the exact surfaces: at least `max(t_a, t_b)`, at most
/// `amplification max(t_a, t_b)`.
pub fn crossing_bound(amplification: f64, t_a: f64, t_b: f64) -> f64 {
    let t = t_a.max(t_b);
    let a = amplification.max(1.0);
    let equal = a * t;
    // cos(gamma) = 2 cos^2(gamma / 2) - 1; 1 - c^2 = (1 - c)(1 + c).
    let inv = 1.0 / (a * a);
    let c = 2.0 * inv - 1.0;
    let one_minus_c2 = (2.0 - 2.0 * inv) * (2.0 * inv);
    if one_minus_c2 <= 0.0 || !equal.is_finite() {
        // gamma = 0 (the bound is t) or a non-finite input: the larger.
        return equal;
    }
    if t_a < c * t_b || t_b < c * t_a {
        return t;
    }
    let g = (t_a * t_a + t_b * t_b - 2.0 * c * t_a * t_b) / one_minus_c2;
    libm::sqrt(g).clamp(t, equal)
}

#[cfg(test)]
mod tests {
    use super::crossing_bound;
    use crate::test_rng::XorShift;
    use glam::DVec2;

    /// Points of the boundary of the 2D wedge `{m_a . x <= d_a, m_b . x <=
    /// d_b}` within `len` of its apex, `k` per side.
    fn boundary(m_a: DVec2, m_b: DVec2, d_a: f64, d_b: f64, len: f64, k: usize) -> [DVec2; 402] {
        // Apex: m_a . x = d_a, m_b . x = d_b.
        let det = m_a.x * m_b.y - m_a.y * m_b.x;
        let apex = DVec2::new(
            (d_a * m_b.y - d_b * m_a.y) / det,
            (m_a.x * d_b - m_b.x * d_a) / det,
        );
        // Each face runs along its plane, away from the other plane.
        let dir = |m: DVec2, other: DVec2| {
            let t = DVec2::new(-m.y, m.x);
            if t.dot(other) > 0.0 {
                -t
            } else {
                t
            }
        };
        let (ea, eb) = (dir(m_a, m_b), dir(m_b, m_a));
        let mut out = [DVec2::ZERO; 402];
        for i in 0..=k {
            let s = len * i as f64 / k as f64;
            out[i] = apex + ea * s;
            out[k + 1 + i] = apex + eb * s;
        }
        out
    }

    /// Distance from `p` to the wedge boundary given by its apex side
    /// points `pts` (segments between consecutive points of each side).
    fn dist(p: DVec2, pts: &[DVec2], k: usize) -> f64 {
        let mut best = f64::INFINITY;
        for side in 0..2 {
            let s = &pts[side * (k + 1)..side * (k + 1) + k + 1];
            for w in s.windows(2) {
                let (a, b) = (w[0], w[1]);
                let ab = b - a;
                let h = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                best = best.min((a + ab * h - p).length());
            }
        }
        best
    }

    /// Random wedges and displacements: the sampled two-sided distance
    /// between the boundaries (near the apexes, where the largest
    /// distance is) is at most the lemma's bound, and with the worst signs
    /// the bound is reached (to the sampling's resolution).
    #[test]
    #[cfg_attr(miri, ignore = "sampled geometry: slow under Miri")]
    fn bound_holds_and_is_reached_on_sampled_wedges() {
        let mut rng = XorShift(0x3ed9e);
        let k = 200;
        let mut worst_ratio = 0.0f64;
        let mut reached = 0usize;
        let cases = 100;
        for case in 0..cases {
            // Angle between the outward normals: 5 to 170 degrees.
            let gamma = (5.0 + 165.0 * rng.unit()).to_radians();
            let rot = rng.unit() * core::f64::consts::TAU;
            let m_a = DVec2::new(libm::cos(rot), libm::sin(rot));
            let m_b = DVec2::new(libm::cos(rot + gamma), libm::sin(rot + gamma));
            let amp = 1.0 / libm::cos(gamma / 2.0);
            let t_a = 1e-3 * (0.05 + rng.unit());
            let t_b = 1e-3 * (0.05 + rng.unit());
            let bound = crossing_bound(amp, t_a, t_b);
            assert!(bound >= t_a.max(t_b) && bound <= amp * t_a.max(t_b) * (1.0 + 1e-12));
            // Long enough that the apexes (which slide by up to
            // `(t_a + t_b) / sin gamma`) are far from the truncated ends.
            let len = 40.0 * (amp * t_a.max(t_b) + (t_a + t_b) / libm::sin(gamma));
            let w = boundary(m_a, m_b, 0.0, 0.0, len, k);
            let mut largest = 0.0f64;
            for (sa, sb) in [(1.0, 1.0), (-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0)] {
                // The corners of the box of displacements, and a random inner one.
                for (fa, fb) in [(1.0, 1.0), (rng.unit(), rng.unit())] {
                    let (d_a, d_b) = (sa * fa * t_a, sb * fb * t_b);
                    let v = boundary(m_a, m_b, d_a, d_b, len, k);
                    // Two-sided, over the half of each side next to the
                    // apex (the truncated far ends are left out).
                    let n = k.div_ceil(2);
                    let mut d = 0.0f64;
                    for side in 0..2 {
                        for i in 0..n {
                            d = d.max(dist(v[side * (k + 1) + i], &w, k));
                            d = d.max(dist(w[side * (k + 1) + i], &v, k));
                        }
                    }
                    assert!(
                        d <= bound * (1.0 + 1e-9),
                        "case {case}: gamma {gamma}, t {t_a:e} {t_b:e}, moved {d_a:e} {d_b:e}: \
                         distance {d:e} > bound {bound:e}"
                    );
                    largest = largest.max(d);
                }
            }
            worst_ratio = worst_ratio.max(largest / bound);
            if largest >= bound * (1.0 - 1e-3) {
                reached += 1;
            }
        }
        extern crate std;
        std::eprintln!(
            "crossing_bound: {reached} of {cases} wedges reach the bound (largest sampled / bound {worst_ratio:.6})"
        );
        assert!(
            reached == cases,
            "the bound is reached at the corners of the displacements"
        );
    }

    /// Equal displacements give the amplification times the larger (the
    /// bound of the module docs); one side exact gives less.
    #[test]
    fn equal_displacements_give_the_amplified_bound() {
        for amp in [1.0, 1.1, 1.5, 2.0, 5.0, 40.0] {
            let b = crossing_bound(amp, 2e-3, 2e-3);
            assert!((b - amp * 2e-3).abs() <= 1e-15 * amp, "{amp}: {b:e}");
            let one = crossing_bound(amp, 2e-3, 0.0);
            assert!(one <= b && one >= 2e-3, "{amp}: {one:e}");
        }
        // gamma = 90 degrees (amp sqrt 2): one side exact gives t / sin(gamma) = t.
        let b = crossing_bound(core::f64::consts::SQRT_2, 1e-3, 0.0);
        assert!((b - 1e-3).abs() < 1e-15, "{b:e}");
        assert!(crossing_bound(f64::INFINITY, 1e-3, 1e-3).is_infinite());
    }
}
