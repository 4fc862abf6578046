//! Preconditioned conjugate gradients on the normal equations
//! (\[CL-R eq. 4.6\]) in caller memory.
//!
//! The report solves (4.6) by Gauss-Seidel; conjugate gradients need only
//! products with the matrix, which [`super::system`] applies face by face
//! without assembling it. Convergence criterion: the Euclidean norm of the
//! residual `b - A x` (the gradient of the objective) has dropped to
//! `tolerance` times its value at the start, the naive solution. The
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
}

impl<'a> Work<'a> {
    /// Number of vectors carved by [`Work::carve`].
    pub(crate) const VECTORS: usize = 6;

    pub(crate) fn carve(arena: &mut Arena<'a>, len: usize) -> Self {
        Work {
            x: arena.f64s(len),
            r: arena.f64s(len),
            z: arena.f64s(len),
            p: arena.f64s(len),
            ap: arena.f64s(len),
            tmp: arena.f64s(len),
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
        }
    }
}

/// A symmetric positive semi-definite system, solved by the crate's PCG.
pub trait NormalSystem {
    /// `ap = A p`; `tmp` is scratch of the same length.
    fn apply(&self, p: &[f64], tmp: &mut [f64], ap: &mut [f64]);
    /// `z = M^-1 r`.
    fn precondition(&self, r: &[f64], z: &mut [f64]);
    /// Projects onto the space of admissible directions.
    fn project(&self, v: &mut [f64]);
    /// `(tolerance, max_iterations)`.
    fn limits(&self) -> (f64, u32);
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Runs PCG from `w.x` with the initial residual already in `w.r`.
/// Returns `(iterations, |r_0|, |r_end|)`.
pub(crate) fn pcg(
    it: &impl NormalSystem,
    w: &mut Work,
    progress: &mut dyn FnMut(u32, f64),
) -> Result<(u32, f64, f64), Error> {
    let (tol, max_iterations) = it.limits();
    let r0 = libm::sqrt(dot(w.r, w.r));
    if !r0.is_finite() {
        return Err(Error::InvalidArgument(
            "interpolation: the similarity system is not finite",
        ));
    }
    if r0 == 0.0 {
        return Ok((0, 0.0, 0.0));
    }
    it.project(w.r);
    it.precondition(w.r, w.z);
    it.project(w.z);
    w.p.copy_from_slice(w.z);
    let mut rz = dot(w.r, w.z);
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
        it.project(w.r);
        rn = libm::sqrt(dot(w.r, w.r));
        progress(k, rn / r0);
        if rn <= tol * r0 {
            return Ok((k, r0, rn));
        }
        it.precondition(w.r, w.z);
        it.project(w.z);
        let rz_new = dot(w.r, w.z);
        let beta = rz_new / rz;
        rz = rz_new;
        for (p, z) in w.p.iter_mut().zip(w.z.iter()) {
            *p = z + beta * *p;
        }
    }
    Err(Error::NotConverged {
        iterations: max_iterations,
    })
}
