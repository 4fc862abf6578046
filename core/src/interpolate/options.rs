//! Options and statistics of an interpolation solve.

/// Bit of [`InterpolationOptions::derivatives`] for each sampled
/// derivative (the row index of [`super::samples::WeightRows`]).
pub mod derivative {
    /// dS/du.
    pub const DU: u8 = 1 << 1;
    /// dS/dv.
    pub const DV: u8 = 1 << 2;
    /// d2S/du2.
    pub const DUU: u8 = 1 << 3;
    /// d2S/dudv.
    pub const DUV: u8 = 1 << 4;
    /// d2S/dv2.
    pub const DVV: u8 = 1 << 5;
    /// First derivatives in u and v.
    pub const FIRST: u8 = DU | DV;
    /// Second derivatives in u and v (not mixed).
    pub const SECOND: u8 = DUU | DVV;
    /// Every supported derivative.
    pub const ALL: u8 = FIRST | SECOND | DUV;
}

/// Preconditioner of the conjugate-gradient solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preconditioner {
    /// Plain conjugate gradients.
    None,
    /// The inverse of each vertex's 3x3 diagonal block of the normal
    /// matrix (the x, y, z unknowns of one vertex are coupled by the
    /// cross-product rows of \[CL-R eq. 4.5\]).
    BlockJacobi,
    /// One symmetric block Gauss-Seidel sweep over the assembled normal
    /// matrix (forward then backward, 3x3 diagonal blocks). Needs
    /// [`super::Interpolator::assemble`] and no extra requirements (their
    /// projection is factored in the block-Jacobi metric); otherwise
    /// [`Preconditioner::BlockJacobi`] is used.
    SymmetricGaussSeidel,
}

/// Options of [`super::Interpolator`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolationOptions {
    /// Derivatives whose direction `S(Q)` must follow at the nine sample
    /// points of every face (bits of [`derivative`]). Default
    /// [`derivative::FIRST`] `|` [`derivative::SECOND`] (\[CL-R §4\]: first
    /// and second derivatives in u and v).
    pub derivatives: u8,
    /// Convergence: the solve stops when the Euclidean norm of the
    /// normal-equation residual (the gradient of the least-squares
    /// objective) has dropped to `tolerance` times its value at the start
    /// (the naive solution). Default `1e-6`.
    pub tolerance: f64,
    /// Iteration limit; reaching it is
    /// [`crate::Error::NotConverged`]. Default 10 000.
    pub max_iterations: u32,
    /// Default [`Preconditioner::BlockJacobi`]: measured, the symmetric
    /// Gauss-Seidel sweep saves 1.5-1.9x iterations on the larger meshes
    /// but costs more than that per iteration (BENCHMARKS.md).
    pub preconditioner: Preconditioner,
    /// Weight `mu` of the parallel term `mu ((S_d(Q) - S_d(G)) . S_d(G))^2`
    /// added to each similarity row `|S_d(Q) x S_d(G)|^2`: it keeps the
    /// derivatives of `Q` from shrinking, which (4.5) alone allows (see
    /// [`super::system`]). Default 0: measured, it speeds the solve up but
    /// does not reduce folds.
    pub parallel_weight: f64,
}

impl Default for InterpolationOptions {
    fn default() -> Self {
        InterpolationOptions {
            derivatives: derivative::FIRST | derivative::SECOND,
            tolerance: 1e-6,
            max_iterations: 10_000,
            preconditioner: Preconditioner::BlockJacobi,
            parallel_weight: 0.0,
        }
    }
}

/// What a solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// Conjugate-gradient iterations.
    pub iterations: u32,
    /// Residual norm of the normal equations at the naive solution.
    pub initial_residual: f64,
    /// Residual norm at the end.
    pub final_residual: f64,
    /// Similarity objective `sum |S_d(Q) x S_d(G)|^2` (\[CL-R eq. 4.5\],
    /// each derivative kind scaled by its RMS over `G`) of the naive
    /// solution: `G`'s Type II vertices with Type I vertices from (4.1).
    pub naive_objective: f64,
    /// The same objective at the solution.
    pub objective: f64,
}
