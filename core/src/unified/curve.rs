//! Curve rules of the unified scheme (MS §3.1, eqs. (1)–(7)) for closed and
//! open polylines, into a caller buffer.
//!
//! One step:
//!
//! 1. linear subdivision into `d` pieces per segment, eqs. (1)–(2):
//!    `P_{di} = P̄_i`, `P_{di+k} = (d-k)/d P̄_i + k/d P̄_{i+1}`;
//! 2. `(p - 1) / 2` passes of
//!    * smoothing, eq. (3):
//!      `P_i := (1/d²) [d P_i + Σ_{k=1}^{d-1} (d-k)(P_{i+k} + P_{i-k})]`
//!      (the mask `(1/d²)[1, 2, .., d, .., 2, 1]`, a box of width `d`
//!      convolved with itself);
//!    * push-back, eqs. (4)–(6): `D_i = a (P̄_i - P_{di})`, `P_{di} += D_i`,
//!      `P_{di+k} += (d-k)/d D_i + k/d D_{i+1}`, the interpolated vectors
//!      renormalised with the rounding factor `b` exactly as the surface edge
//!      points, eq. (18) (`b = 0` is eq. (6) as printed).
//!
//! Every rule is evaluated in Jacobi manner (from the values before the
//! rule), with the second half of the caller buffer as the temporary array.
//!
//! For `p = 3`, `d = 2` this is the matrix (7): even points
//! `((1-a), (6+2a), (1-a)) / 8`, odd points `(-a, 8+a, 8+a, -a) / 16`; `a = 1`
//! gives the four-point scheme and `a = 0` the `d`-ary cubic B-spline.
//!
//! **Open polylines** (also the rule for the boundary of open meshes once
//! those are supported): the linearly subdivided polyline is extended beyond
//! each end by odd reflection, `P_{-j} = 2 P_0 - P_j`, before smoothing. The
//! mask is symmetric and sums to one, so both end points stay fixed (and
//! their push-back vector is zero); next to the ends the rules are those of
//! the cubic B-spline with a "corner" end (end point interpolated).

use super::interp::renormalize;
use super::params::UnifiedParams;
use crate::error::Error;
use glam::DVec3;

/// Number of points after one step on `n` input points:
/// `n d` for a closed polygon, `(n - 1) d + 1` for an open polyline.
///
/// Errors: `n == 0`, `d < 2` or a count that does not fit `usize`
/// ([`Error::InvalidArgument`]).
pub fn curve_len(n: usize, closed: bool, d: u32) -> Result<usize, Error> {
    if n == 0 {
        return Err(Error::InvalidArgument("unified curve: no points"));
    }
    if d < 2 {
        return Err(Error::InvalidArgument("unified: d must be at least 2"));
    }
    let segs = if closed { n } else { n - 1 };
    let m = segs
        .checked_mul(d as usize)
        .and_then(|x| x.checked_add(usize::from(!closed)))
        .ok_or(Error::InvalidArgument("unified curve: too many points"))?;
    Ok(m)
}

/// Length (in points) of the buffer [`refine_curve`] needs: twice
/// [`curve_len`] (result plus the Jacobi temporary array).
pub fn curve_buffer_len(n: usize, closed: bool, params: &UnifiedParams) -> Result<usize, Error> {
    params.validate()?;
    curve_len(n, closed, params.d)?
        .checked_mul(2)
        .ok_or(Error::InvalidArgument("unified curve: too many points"))
}

/// One step of the curve scheme on `points` (closed polygon or open
/// polyline). The result is written to `out[..len]` and `len` is returned;
/// `out[len..2 len]` is used as temporary storage.
///
/// Errors: invalid parameters or point count ([`Error::InvalidArgument`]),
/// a non-finite coordinate ([`Error::NonFiniteCoordinate`] with the point
/// index), `out` shorter than [`curve_buffer_len`]
/// ([`Error::BufferTooSmall`], in points).
pub fn refine_curve(
    points: &[DVec3],
    closed: bool,
    params: &UnifiedParams,
    out: &mut [DVec3],
) -> Result<usize, Error> {
    let required = curve_buffer_len(points.len(), closed, params)?;
    if out.len() < required {
        return Err(Error::BufferTooSmall { required });
    }
    for (i, p) in points.iter().enumerate() {
        if !p.is_finite() {
            return Err(Error::NonFiniteCoordinate { vertex: i as u32 });
        }
    }
    let m = required / 2;
    let n = points.len();
    let d = params.d as usize;
    let (q, rest) = out.split_at_mut(m);
    let tmp = &mut rest[..m];
    if !closed && n == 1 {
        q[0] = points[0];
        return Ok(1);
    }
    // Eqs. (1)-(2): linear subdivision.
    let segs = if closed { n } else { n - 1 };
    let inv = 1.0 / d as f64;
    for i in 0..segs {
        let p0 = points[i];
        let p1 = points[if i + 1 == n { 0 } else { i + 1 }];
        q[d * i] = p0;
        for k in 1..d {
            let s = k as f64 * inv;
            q[d * i + k] = p0 * (1.0 - s) + p1 * s;
        }
    }
    if !closed {
        q[m - 1] = points[n - 1];
    }
    let inv2 = inv * inv;
    for _ in 0..params.passes() {
        // Eq. (3), Jacobi: read q, write tmp.
        for i in 0..m {
            let mut s = q[i] * d as f64;
            for k in 1..d {
                let w = (d - k) as f64;
                s += (fetch(q, closed, i as isize + k as isize)
                    + fetch(q, closed, i as isize - k as isize))
                    * w;
            }
            tmp[i] = s * inv2;
        }
        // Eqs. (4)-(6) on tmp, streaming: D_i is formed from tmp[d i]
        // before that point moves; D_0 is kept for the closing segment.
        let push = |i: usize, tmp: &[DVec3]| (points[i] - tmp[d * i]) * params.a;
        if params.a != 0.0 {
            let d0 = push(0, tmp);
            for i in 0..segs {
                let di = if i == 0 { d0 } else { push(i, tmp) };
                let dn = if i + 1 == n { d0 } else { push(i + 1, tmp) };
                let (li, ln) = (di.length(), dn.length());
                for k in 1..d {
                    let s = k as f64 * inv;
                    let lin = di * (1.0 - s) + dn * s;
                    let len = li * (1.0 - s) + ln * s;
                    tmp[d * i + k] += renormalize(lin, len, params.b);
                }
                tmp[d * i] += di;
            }
            if !closed {
                let last = push(n - 1, tmp);
                tmp[m - 1] += last;
            }
        }
        q.copy_from_slice(tmp);
    }
    Ok(m)
}

/// `q[j]`, cyclically for closed curves, by odd reflection at the ends for
/// open ones (`|j|` exceeds the range by less than its length).
#[inline]
fn fetch(q: &[DVec3], closed: bool, j: isize) -> DVec3 {
    let m = q.len() as isize;
    if closed {
        q[j.rem_euclid(m) as usize]
    } else if j < 0 {
        q[0] * 2.0 - q[((-j).min(m - 1)) as usize]
    } else if j >= m {
        q[(m - 1) as usize] * 2.0 - q[(2 * (m - 1) - j).max(0) as usize]
    } else {
        q[j as usize]
    }
}
