//! Uniform cubic B-spline basis and bicubic patch evaluation.
//!
//! Basis on t in [0,1]: `(1-t)^3/6`, `(3t^3 - 6t^2 + 4)/6`,
//! `(-3t^3 + 3t^2 + 3t + 1)/6`, `t^3/6`. A patch has a 4x4 control grid
//! `grid[j*4 + i]` (i along u, j along v) and covers its middle square.

use crate::Eval;
use glam::DVec3;

/// Basis values and first and second derivatives at `t`.
#[inline(always)]
pub fn basis(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    let b = [
        s * s * s / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ];
    let d = [
        -0.5 * s * s,
        1.5 * t2 - 2.0 * t,
        -1.5 * t2 + t + 0.5,
        0.5 * t2,
    ];
    let dd = [s, 3.0 * t - 2.0, -3.0 * t + 1.0, t];
    (b, d, dd)
}

/// Evaluates a bicubic B-spline patch: position and derivatives with respect
/// to the patch's own (u, v); second derivatives only when `SECOND`.
#[inline(always)]
pub fn eval_grid<const SECOND: bool>(grid: &[DVec3; 16], u: f64, v: f64) -> Eval {
    let (bu, du, duu) = basis(u);
    let (bv, dv, dvv) = basis(v);
    let mut r = [DVec3::ZERO; 4];
    let mut ru = [DVec3::ZERO; 4];
    let mut ruu = [DVec3::ZERO; 4];
    for j in 0..4 {
        let row = &grid[j * 4..j * 4 + 4];
        r[j] = row[0] * bu[0] + row[1] * bu[1] + row[2] * bu[2] + row[3] * bu[3];
        ru[j] = row[0] * du[0] + row[1] * du[1] + row[2] * du[2] + row[3] * du[3];
        if SECOND {
            ruu[j] = row[0] * duu[0] + row[1] * duu[1] + row[2] * duu[2] + row[3] * duu[3];
        }
    }
    let comb = |w: &[f64; 4], x: &[DVec3; 4]| x[0] * w[0] + x[1] * w[1] + x[2] * w[2] + x[3] * w[3];
    let mut e = Eval {
        p: comb(&bv, &r),
        du: comb(&bv, &ru),
        dv: comb(&dv, &r),
        ..Eval::default()
    };
    if SECOND {
        e.duu = comb(&bv, &ruu);
        e.duv = comb(&dv, &ru);
        e.dvv = comb(&dvv, &r);
    }
    e
}
