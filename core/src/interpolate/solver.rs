//! Preconditioned conjugate gradients on the normal equations
//! (\[CL-R eq. 4.6\]) in caller memory.
//!
//! The report solves (4.6) by Gauss-Seidel; conjugate gradients need only
//! products with the matrix, which [`super::system`] applies face by face
//! without assembling it, or [`super::assembled`] from the assembled
//! blocks. Convergence criterion: `sqrt(r . z)`, with `r =
//! b - A x` the residual (the gradient of the objective) and `z` the
//! preconditioned residual projected onto the directions the hard
//! requirements leave free, has dropped to `tolerance` times its value at
//! the start (the naive solution, moved onto the requirements); the solve
//! that follows the fold rounds ([`super::orient`]) also stops once it is
//! `tolerance` times the first solve's start value (the accuracy of a
//! solve without rounds: it starts near its solution, and its own start
//! value is no scale of the error; measured on `catmark_lefthanded`, 1,245
//! of the 2,766 iterations went to driving an already small residual down
//! another 10^6, BENCHMARKS.md). The
//! objective decreases monotonically over the iterations, so the result is
//! never worse than the naive solution.

use crate::error::Error;
use crate::mem::arena::Arena;

/// The solver's vectors, each `3m` values (Type I entries stay zero).
pub struct Work<'a> {
    /// Unknowns.
    pub(crate) x: &'a mut [f64],
    /// Residual.
    pub(crate) r: &'a mut [f64],
    /// Preconditioned residual.
    pub(crate) z: &'a mut [f64],
    /// Search direction.
    pub(crate) p: &'a mut [f64],
    /// Matrix times search direction.
    pub(crate) ap: &'a mut [f64],
    /// Scratch: the expanded control points.
    pub(crate) tmp: &'a mut [f64],
    /// Scratch of one value per requirement row.
    pub(crate) small: &'a mut [f64],
}

impl<'a> Work<'a> {
    /// Number of vectors carved by [`Work::carve`].
    pub(crate) const VECTORS: usize = 6;

    pub(crate) fn carve(arena: &mut Arena<'a>, len: usize, rows: usize) -> Self {
        Work {
            x: arena.f64s(len),
            r: arena.f64s(len),
            z: arena.f64s(len),
            p: arena.f64s(len),
            ap: arena.f64s(len),
            tmp: arena.f64s(len),
            small: arena.f64s(rows),
        }
    }

    pub(crate) fn empty() -> Self {
        Work {
            x: &mut [],
            r: &mut [],
            z: &mut [],
            p: &mut [],
            ap: &mut [],
            tmp: &mut [],
            small: &mut [],
        }
    }
}

/// A symmetric positive semi-definite system, solved by the crate's PCG.
pub trait NormalSystem {
    /// `ap = A p`; `tmp` is scratch of the same length.
    fn apply(&self, p: &[f64], tmp: &mut [f64], ap: &mut [f64]);
    /// `z = M^-1 r`, projected onto the directions the hard requirements
    /// leave free; `tmp` (same length) and `small` (one value per
    /// requirement row) are scratch.
    fn precondition(&self, r: &[f64], z: &mut [f64], tmp: &mut [f64], small: &mut [f64]);
    /// Projects `v` onto the directions the hard requirements leave free
    /// (the projection of [`NormalSystem::precondition`]); a no-op without
    /// requirements. PCG applies it to every search direction, so that
    /// rounding in `p = z + beta p` cannot carry the iterate off the
    /// requirements over many iterations.
    fn project(&self, v: &mut [f64], tmp: &mut [f64], small: &mut [f64]);
    /// `(tolerance, max_iterations, floor)`: PCG stops once `|r|_z <=
    /// max(tolerance |r_0|_z, floor)`.
    fn limits(&self) -> (f64, u32, f64);
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Runs PCG from `w.x` with the initial residual already in `w.r`.
/// Returns `(iterations, |r_0|_z, |r_end|_z)` with `|r|_z = sqrt(r . z)`,
/// `z` the preconditioned and projected residual.
pub(crate) fn pcg(
    it: &impl NormalSystem,
    w: &mut Work,
    progress: &mut dyn FnMut(u32, f64),
) -> Result<(u32, f64, f64), Error> {
    let (tol, max_iterations, floor) = it.limits();
    it.precondition(w.r, w.z, w.tmp, w.small);
    let mut rz = dot(w.r, w.z);
    if !rz.is_finite() {
        return Err(Error::InvalidArgument(
            "interpolation: the similarity system is not finite",
        ));
    }
    let r0 = libm::sqrt(rz.max(0.0));
    if r0 == 0.0 || r0 <= floor {
        return Ok((0, r0, r0));
    }
    w.p.copy_from_slice(w.z);
    let mut rn = r0;
    for k in 1..=max_iterations {
        it.apply(w.p, w.tmp, w.ap);
        let pap = dot(w.p, w.ap);
        if pap.is_nan() || pap <= 0.0 {
            // The direction has no curvature left: the system is solved
            // as far as it is determined.
            return Ok((k - 1, r0, rn));
        }
        let alpha = rz / pap;
        for (x, p) in w.x.iter_mut().zip(w.p.iter()) {
            *x += alpha * p;
        }
        for (r, ap) in w.r.iter_mut().zip(w.ap.iter()) {
            *r -= alpha * ap;
        }
        it.precondition(w.r, w.z, w.tmp, w.small);
        let rz_new = dot(w.r, w.z);
        rn = libm::sqrt(rz_new.max(0.0));
        progress(k, rn / r0);
        if rn <= (tol * r0).max(floor) {
            return Ok((k, r0, rn));
        }
        let beta = rz_new / rz;
        rz = rz_new;
        for (p, z) in w.p.iter_mut().zip(w.z.iter()) {
            *p = z + beta * *p;
        }
        it.project(w.p, w.tmp, w.small);
    }
    Err(Error::NotConverged {
        iterations: max_iterations,
    })
}
