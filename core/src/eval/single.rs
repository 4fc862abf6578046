//! Single-precision evaluation for FPUs without double precision (a
//! Cortex-M4F has single-precision hardware only; `f64` is software there).
//!
//! The evaluator's data stay `f64` (built once, exactly); [`Evaluator::eval_f32`]
//! reads the 16 control points of the bicubic piece that contains the
//! point, rounds them to `f32` and does the B-spline evaluation, the
//! parameter maps and the normal in `f32`. The bicubic piece is the
//! patch's own grid for a regular patch and, for an extraordinary patch,
//! one of the six level-1/2 grids the evaluator keeps (\[Stam98\]: the
//! regions `Omega_{m,b}`, `m = 1, 2`), which cover the patch except the
//! square `max(u, v) < 1/4` at the extraordinary vertex; there the eigen
//! expansion (`X_b B^{m-1} L G`, \[CL-R §2.1\]) runs in `f64` and the result
//! is rounded. The error against [`Evaluator::eval`] is rounding only
//! (control points to `f32`, then about 40 `f32` operations per
//! coordinate); `tests/tests/f32_eval.rs` measures it over the corpus.

use super::evaluator::Evaluator;
use super::frame::{quadrant, rot_param};
use crate::error::Error;
use crate::math::bspline::Grid;
use crate::math::sqrt32::sqrt_f32;

/// Position, first derivatives and unit normal in single precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EvalF32 {
    /// Position.
    pub p: [f32; 3],
    /// dS/du.
    pub du: [f32; 3],
    /// dS/dv.
    pub dv: [f32; 3],
    /// Unit normal (`du x dv` normalised).
    pub normal: [f32; 3],
}

/// `sum_i |b^_i - b_i|`, the error of the `f32` cubic B-spline basis
/// values (`basis32`) at every `f32` parameter in `[0, 1]` that is a
/// multiple of `2^-24` (`2^-24` times a small constant; checked over all
/// `2^24 + 1` such parameters by the unit test `basis_error_exhaustive`).
/// The `f32` tessellation's bound uses it (`tessellate/single.rs`).
pub const F32_BASIS_ERR: f64 = 4.0 / 16_777_216.0;

/// Uniform cubic B-spline basis and its derivative at `t`.
#[inline(always)]
fn basis32(t: f32) -> ([f32; 4], [f32; 4]) {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    let sixth = 1.0 / 6.0;
    (
        [
            s * s * s * sixth,
            (3.0 * t3 - 6.0 * t2 + 4.0) * sixth,
            (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) * sixth,
            t3 * sixth,
        ],
        [
            -0.5 * s * s,
            1.5 * t2 - 2.0 * t,
            -1.5 * t2 + t + 0.5,
            0.5 * t2,
        ],
    )
}

/// Bicubic B-spline of an `f64` grid (layout of [`Grid`]) in `f32`:
/// `[p, du, dv]`.
fn eval_grid32(g: &Grid, u: f32, v: f32) -> [[f32; 3]; 3] {
    let (bu, du) = basis32(u);
    let (bv, dv) = basis32(v);
    let mut out = [[0.0f32; 3]; 3];
    for c in 0..3 {
        let mut r = [0.0f32; 4];
        let mut ru = [0.0f32; 4];
        for i in 0..4 {
            for j in 0..4 {
                let x = g[c * 16 + i * 4 + j] as f32;
                r[j] += bu[i] * x;
                ru[j] += du[i] * x;
            }
        }
        let dot =
            |w: &[f32; 4], a: &[f32; 4]| w[0] * a[0] + w[1] * a[1] + w[2] * a[2] + w[3] * a[3];
        out[0][c] = dot(&bv, &r);
        out[1][c] = dot(&bv, &ru);
        out[2][c] = dot(&dv, &r);
    }
    out
}

fn scale(a: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn neg(a: [f32; 3]) -> [f32; 3] {
    [-a[0], -a[1], -a[2]]
}

/// `(du, dv)` from the corner-`r` frame back to the face frame (as
/// `rot_back`), times `s`.
fn rot_back32(r: u8, du: [f32; 3], dv: [f32; 3], s: f32) -> ([f32; 3], [f32; 3]) {
    let (a, b) = match r & 3 {
        0 => (du, dv),
        1 => (neg(dv), du),
        2 => (neg(du), neg(dv)),
        _ => (dv, neg(du)),
    };
    (scale(a, s), scale(b, s))
}

fn rot_param32(r: u8, s: f32, t: f32) -> (f32, f32) {
    match r & 3 {
        0 => (s, t),
        1 => (t, 1.0 - s),
        2 => (1.0 - s, 1.0 - t),
        _ => (1.0 - t, s),
    }
}

fn to32(v: glam::DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

impl Evaluator<'_> {
    /// As [`Evaluator::eval`] in single precision (see the module docs):
    /// position, first derivatives and normal at `(u, v)` of sub-face
    /// `sub` of base face `face`. Same errors as `eval`.
    pub fn eval_f32(&self, face: u32, sub: u32, u: f32, v: f32) -> Result<EvalF32, Error> {
        let f = face as usize;
        if f >= self.num_faces() {
            return Err(Error::FaceOutOfRange { face });
        }
        if sub as usize >= self.num_subfaces(f) {
            return Err(Error::SubFaceOutOfRange { face, sub });
        }
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(Error::ParameterOutOfRange);
        }
        let slot = self.slot_start(f) + sub as usize;
        let p0 = self.slot_patch[slot] as usize;
        let (pdu, pdv, p) = if self.slot_split[slot] == 0 {
            self.patch32(p0, u, v, 1.0, (u as f64, v as f64))
        } else {
            let c = quadrant(u as f64, v as f64);
            let (s, t) = rot_param32(c, u, v);
            let (s64, t64) = rot_param(c, u as f64, v as f64);
            let (du, dv, p) = self.patch32(
                p0 + c as usize,
                2.0 * s,
                2.0 * t,
                2.0,
                (2.0 * s64, 2.0 * t64),
            );
            let (du, dv) = rot_back32(c, du, dv, 1.0);
            (du, dv, p)
        };
        let n = [
            pdu[1] * pdv[2] - pdu[2] * pdv[1],
            pdu[2] * pdv[0] - pdu[0] * pdv[2],
            pdu[0] * pdv[1] - pdu[1] * pdv[0],
        ];
        let l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        let normal = if l2.is_normal() {
            scale(n, 1.0 / sqrt_f32(l2))
        } else {
            // At or next to an extraordinary vertex: the f64 normal (the
            // limit normal where the derivatives vanish).
            to32(self.eval(face, sub, u as f64, v as f64)?.normal)
        };
        Ok(EvalF32 {
            p,
            du: pdu,
            dv: pdv,
            normal,
        })
    }

    /// `(du, dv, p)` of patch `pi` at `(s, t)` (derivatives times `sc`);
    /// `st64` is `(s, t)` in `f64` for the fallback.
    fn patch32(
        &self,
        pi: usize,
        s: f32,
        t: f32,
        sc: f32,
        st64: (f64, f64),
    ) -> ([f32; 3], [f32; 3], [f32; 3]) {
        let zero = [0.0f32; 3];
        let meta = self.patch_meta[pi];
        let n = (meta & 0xff) as usize;
        let r = ((meta >> 8) & 3) as u8;
        let o = self.patch_data[pi] as usize;
        let (x, y) = rot_param32(r, s, t);
        // Made here when the evaluator does not store the level-1/2 grids.
        let mut made = [0.0f64; 48];
        let (grid, uu, vv, gs) = if n == 4 {
            (Some(o), x, y, 1.0f32)
        } else {
            let lay = self.ev_layout(o, n);
            let m = x.max(y);
            if m < 0.25 {
                // Level >= 3 at the extraordinary vertex: f64 eigen kernel.
                let Some(tab) = self.tables.get(n) else {
                    return (zero, zero, zero);
                };
                let (x64, y64) = rot_param(r, st64.0, st64.1);
                let e = tab.eval_projected_impl::<false, false>(
                    &self.data[lay.ghat()],
                    self.options()
                        .subpatch_grids
                        .then(|| &self.data[lay.grids()]),
                    &self.data[lay.deep()],
                    x64,
                    y64,
                );
                let (du, dv) = rot_back32(r, to32(e.du), to32(e.dv), sc);
                return (du, dv, to32(e.p));
            }
            let (lev, f) = if m >= 0.5 { (1, 2.0f32) } else { (2, 4.0f32) };
            let (ub, vb) = (x * f, y * f);
            let (b, uu, vv) = if ub >= 1.0 {
                if vb >= 1.0 {
                    (2, ub - 1.0, vb - 1.0)
                } else {
                    (1, ub - 1.0, vb)
                }
            } else {
                (3, ub, vb - 1.0)
            };
            let at = lay.grid(lev, b).map(|r| r.start);
            if at.is_none() {
                let Some(tab) = self.tables.get(n) else {
                    return (zero, zero, zero);
                };
                // The grid the build would have stored, bit for bit.
                tab.sub_patch(&self.data[lay.ghat()], lev as u32, b, true, &mut made);
            }
            (at, uu, vv, f)
        };
        let g: &Grid = match grid {
            Some(a) => match <&Grid>::try_from(&self.data[a..a + 48]) {
                Ok(g) => g,
                Err(_) => return (zero, zero, zero),
            },
            None => &made,
        };
        let [p, du, dv] = eval_grid32(g, uu, vv);
        let (du, dv) = rot_back32(r, du, dv, gs * sc);
        (du, dv, p)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::{basis32, F32_BASIS_ERR};

    /// Every multiple of `2^-24` in `[0, 1]` (all the parameters the
    /// kernel gets from the tessellation's vertices): the `f32` basis
    /// against the exact one (`f64`: `t` has 24 bits, `t^3` 72, the
    /// `f64` values are within `2^-50` of exact).
    #[test]
    #[cfg_attr(
        miri,
        ignore = "too slow under Miri: all 2^24 + 1 kernel inputs (seconds natively, days interpreted)"
    )]
    fn basis_error_exhaustive() {
        let mut worst = 0.0f64;
        for k in 0..=(1u32 << 24) {
            let t = k as f64 / 16_777_216.0;
            let (b, _) = basis32(t as f32);
            let s = 1.0 - t;
            let e = [
                s * s * s / 6.0,
                (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
                (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                t * t * t / 6.0,
            ];
            let d: f64 = (0..4).map(|i| (b[i] as f64 - e[i]).abs()).sum();
            worst = worst.max(d);
        }
        std::println!("f32 basis: sum |b^ - b| <= {:.3} u", worst * 16_777_216.0);
        assert!(worst + 4.0 * 2f64.powi(-50) <= F32_BASIS_ERR, "{worst:e}");
    }
}
