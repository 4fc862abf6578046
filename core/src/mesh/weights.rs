//! Vertex-rule weights (alpha_n, beta_n, gamma_n) per valence.
//!
//! The general Catmull-Clark vertex rule (\[CL-R eq. 1.1\]):
//! `V' = alpha V + beta/n * sum(E_i) + gamma/n * sum(F_i)`, with `E_i` the old
//! edge neighbours and `F_i` the old face-diagonal vertices; edge and face
//! points keep the standard rules. Standard Catmull-Clark is
//! `alpha = 1 - 7/(4n)`, `beta = 3/(2n)`, `gamma = 1/(4n)`.
//!
//! For faces that are not quads the "diagonal" is taken as the virtual vertex
//! `D_i = 4 F_i' - V - E_i - E_(i+1)` (with `F_i'` the new face point), which
//! makes the rule equal to standard Catmull-Clark for any polygon when the
//! weights are standard: `V' = (alpha-gamma) V + (beta-2 gamma) avg(E) + 4 gamma avg(F')`.

use crate::config::MAX_VALENCE;
use crate::error::{Error, WeightsProblem};

/// Largest accepted `|alpha + beta + gamma - 1|`.
pub const SUM_TOLERANCE: f64 = 1e-12;

/// Standard Catmull-Clark weights `(alpha, beta, gamma)` for valence `n`.
pub const fn standard(n: usize) -> (f64, f64, f64) {
    let nf = n as f64;
    (1.0 - 7.0 / (4.0 * nf), 3.0 / (2.0 * nf), 1.0 / (4.0 * nf))
}

/// A vertex rule per valence `3..=MAX_VALENCE`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights {
    table: [(f64, f64, f64); MAX_VALENCE + 1],
}

impl Weights {
    /// Standard Catmull-Clark weights for every valence.
    pub const STANDARD: Weights = {
        let mut table = [(0.0, 0.0, 0.0); MAX_VALENCE + 1];
        let mut n = 1;
        while n <= MAX_VALENCE {
            table[n] = standard(n);
            n += 1;
        }
        Weights { table }
    };

    /// `(alpha, beta, gamma)` for valence `n` (standard outside the table).
    #[inline]
    pub fn get(&self, n: usize) -> (f64, f64, f64) {
        if n <= MAX_VALENCE {
            self.table[n]
        } else {
            standard(n)
        }
    }

    /// True when valence `n` uses the standard rule.
    pub fn is_standard(&self, n: usize) -> bool {
        self.get(n) == standard(n)
    }

    /// Sets the rule of valence `n` (3..=MAX_VALENCE, not 4).
    ///
    /// Errors ([`Error::InvalidWeights`]): non-finite or negative weights,
    /// `|alpha + beta + gamma - 1| > SUM_TOLERANCE`, `n == 4` with
    /// non-standard weights, `n` out of range. Nothing changes on error.
    pub fn set(&mut self, n: usize, alpha: f64, beta: f64, gamma: f64) -> Result<(), Error> {
        let bad = |problem| Error::InvalidWeights {
            valence: n as u32,
            problem,
        };
        if !(3..=MAX_VALENCE).contains(&n) {
            return Err(bad(WeightsProblem::ValenceOutOfRange));
        }
        if !(alpha.is_finite() && beta.is_finite() && gamma.is_finite()) {
            return Err(bad(WeightsProblem::NonFinite));
        }
        if alpha < 0.0 || beta < 0.0 || gamma < 0.0 {
            return Err(bad(WeightsProblem::Negative));
        }
        if (alpha + beta + gamma - 1.0).abs() > SUM_TOLERANCE {
            return Err(bad(WeightsProblem::SumNotOne));
        }
        if n == 4 && (alpha, beta, gamma) != standard(4) {
            return Err(bad(WeightsProblem::RegularValence));
        }
        self.table[n] = (alpha, beta, gamma);
        Ok(())
    }

    /// The frequency-0 eigenvalues of valence `n` (\[CL-R §2.4\]): the roots of
    /// `x^2 - (alpha - 1/4) x + (1 - 2 beta)/16`, as `(re0, im0, re1, im1)`
    /// with `|lambda_0| >= |lambda_1|` (a complex pair has `im != 0`).
    pub fn frequency0_eigenvalues(&self, n: usize) -> (f64, f64, f64, f64) {
        let (a, b, _) = self.get(n);
        let t = a - 0.25;
        let d = (1.0 - 2.0 * b) / 16.0;
        let disc = t * t - 4.0 * d;
        if disc >= 0.0 {
            let s = libm::sqrt(disc);
            let (x, y) = ((t + s) / 2.0, (t - s) / 2.0);
            if x.abs() >= y.abs() {
                (x, 0.0, y, 0.0)
            } else {
                (y, 0.0, x, 0.0)
            }
        } else {
            let s = libm::sqrt(-disc) / 2.0;
            (t / 2.0, s, t / 2.0, -s)
        }
    }

    /// The subdominant eigenvalue of the rest of the spectrum,
    /// `lambda_2 = (c + 5 + sqrt((c+1)(c+9)))/16` with `c = cos(2 pi/n)`.
    pub fn lambda2(n: usize) -> f64 {
        let c = libm::cos(2.0 * core::f64::consts::PI / n as f64);
        (c + 5.0 + libm::sqrt((c + 1.0) * (c + 9.0))) / 16.0
    }

    /// Whether the surface is tangent-plane continuous at an extraordinary
    /// vertex of valence `n` with this rule: the frequency-0 eigenvalues are
    /// dominated by lambda_2 (`|lambda_0| < lambda_2`, \[CL-R §2.6\] / Ball and
    /// Storry). A property, not an error.
    pub fn tangent_plane_continuous(&self, n: usize) -> bool {
        let (r0, i0, _, _) = self.frequency0_eigenvalues(n);
        libm::sqrt(r0 * r0 + i0 * i0) < Self::lambda2(n)
    }
}

impl Default for Weights {
    fn default() -> Self {
        Self::STANDARD
    }
}
