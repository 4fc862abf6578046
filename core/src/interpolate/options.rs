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
    /// projection is factored in the block-Jacobi metric); otherwise, and
    /// in fold-removal rounds (the anchor rows are not in the assembled
    /// matrix), [`Preconditioner::BlockJacobi`] is used.
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
    /// (the naive solution; in a fold-removal round, the previous round's
    /// solution). Default `1e-6`.
    pub tolerance: f64,
    /// Iteration limit of each round; reaching it is
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
    /// Fold removal ([`super::folds`]): after a solve, faces whose limit
    /// normal is reversed against `G`'s at a check point get anchor rows
    /// and the problem is re-solved, at most this many times (0: no fold
    /// check). Default 8: measured on `catmark_lefthanded`, folds fall
    /// with every round up to about 8 and then level off (BENCHMARKS.md);
    /// the other test meshes have no folds and need no round.
    pub fold_rounds: u32,
    /// First weight of a folded face's anchor rows, relative to the
    /// similarity rows (which are scaled to unit RMS per derivative kind);
    /// it grows 4x per round the face stays folded. Default 0.01:
    /// measured, larger first weights (0.1, 1) leave more folds and a
    /// larger (4.5) residual (BENCHMARKS.md).
    pub fold_weight: f64,
    /// Check points per side of each face for the fold check (a
    /// `fold_grid x fold_grid` grid over `[0, 1]^2`, at least 2). Default
    /// 5: a finer grid than the nine similarity samples.
    pub fold_grid: u32,
}

impl Default for InterpolationOptions {
    fn default() -> Self {
        InterpolationOptions {
            derivatives: derivative::FIRST | derivative::SECOND,
            tolerance: 1e-6,
            max_iterations: 10_000,
            preconditioner: Preconditioner::BlockJacobi,
            parallel_weight: 0.0,
            fold_rounds: 8,
            fold_weight: 0.01,
            fold_grid: 5,
        }
    }
}

/// What a solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// Conjugate-gradient iterations (all rounds).
    pub iterations: u32,
    /// Residual norm of the normal equations at the naive solution.
    pub initial_residual: f64,
    /// Residual norm at the end (of the last round's system, whose start
    /// is the previous round's solution).
    pub final_residual: f64,
    /// Similarity objective `sum |S_d(Q) x S_d(G)|^2` (\[CL-R eq. 4.5\],
    /// each derivative kind scaled by its RMS over `G`) of the naive
    /// solution: `G`'s Type II vertices with Type I vertices from (4.1).
    pub naive_objective: f64,
    /// The same objective at the solution.
    pub objective: f64,
    /// Fold-removal rounds run after the first solve ([`super::folds`]).
    pub fold_rounds: u32,
    /// Check points where the normals of `Q` and `G` still disagree after
    /// the last round (0 unless the round limit was reached).
    pub folds: u32,
    /// Faces of `G` carrying anchor rows at the end.
    pub anchored_faces: u32,
}
