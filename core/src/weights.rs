//! Vertex-rule weights (alpha_n, beta_n, gamma_n) per valence.
//!
//! The general Catmull-Clark vertex rule (Cheng & Lai report, eq. 1.1):
//! `V' = alpha V + beta/n * sum(E_i) + gamma/n * sum(F_i)`, with `E_i` the old
//! edge neighbours and `F_i` the old face-diagonal vertices; edge and face
//! points keep the standard rules. Standard Catmull-Clark is
//! `alpha = 1 - 7/(4n)`, `beta = 3/(2n)`, `gamma = 1/(4n)`.
//!
//! For faces that are not quads the "diagonal" is taken as the virtual vertex
//! `D_i = 4 F_i' - V - E_i - E_(i+1)` (with `F_i'` the new face point), which
//! makes the rule equal to standard Catmull-Clark for any polygon when the
//! weights are standard: `V' = (alpha-gamma) V + (beta-2 gamma) avg(E) + 4 gamma avg(F')`.

use crate::MAX_VALENCE;

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
}

impl Default for Weights {
    fn default() -> Self {
        Self::STANDARD
    }
}
