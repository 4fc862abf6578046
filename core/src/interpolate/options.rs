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

/// Rows added to remove folds ([`InterpolationOptions::fold_rounds`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FoldRemoval {
    /// Anchor rows on folded faces pulling their first derivatives towards
    /// `G`'s ([`super::folds`]).
    Anchors,
    /// Orientation rows at points whose normal is reversed or nearly so,
    /// linearised around the previous round's solution
    /// ([`super::orient`]).
    Orientation,
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
    /// Fold removal: after a solve, points whose limit normal is reversed
    /// against `G`'s (or, with [`FoldRemoval::Orientation`], below
    /// [`InterpolationOptions::fold_margin`]) get rows and the problem is
    /// re-solved, at most this many times (0: no fold check). Default 16:
    /// measured on `catmark_lefthanded` with orientation rows, 8 rounds
    /// leave 74 reversed points of 140,616 at 9 x 9 per face, 12, 16 and
    /// 20 none (BENCHMARKS.md); meshes without folds stop after the first
    /// check when no point is below the margin.
    pub fold_rounds: u32,
    /// First weight of a fold row (an orientation row of a point, or the
    /// anchor rows of a face), relative to the similarity rows (which are
    /// scaled to unit RMS per derivative kind); it grows 4x per round the
    /// point (face) stays folded or below the margin. Default 1: measured
    /// with orientation rows, 0.1 leaves more folds and 100 costs
    /// similarity (BENCHMARKS.md); anchors were measured best at 0.01.
    pub fold_weight: f64,
    /// Check points per side of each face for the fold count (a
    /// `fold_grid x fold_grid` grid over `[0, 1]^2`, at least 2; with
    /// [`FoldRemoval::Anchors`] also the grid that decides which faces are
    /// anchored). Default 7, the [`super::samples::ORIENT_GRID`] grid of
    /// the orientation rows: their marking pass then counts the folds
    /// without a pass of its own (the default was 5 before; 7 checks more
    /// points, at less cost).
    pub fold_grid: u32,
    /// Which rows the fold rounds add. Default
    /// [`FoldRemoval::Orientation`].
    pub fold_removal: FoldRemoval,
    /// Margin of the orientation rows ([`FoldRemoval::Orientation`]): a
    /// point whose orientation `n_G . (Q_u x Q_v)` is below this fraction
    /// of `G`'s area element `|G_u x G_v|` there gets a row pushing it up
    /// to the margin. Default 0.1.
    pub fold_margin: f64,
}

impl Default for InterpolationOptions {
    fn default() -> Self {
        InterpolationOptions {
            derivatives: derivative::FIRST | derivative::SECOND,
            tolerance: 1e-6,
            max_iterations: 10_000,
            preconditioner: Preconditioner::BlockJacobi,
            parallel_weight: 0.0,
            fold_rounds: 16,
            fold_weight: 1.0,
            fold_grid: super::samples::ORIENT_GRID as u32,
            fold_removal: FoldRemoval::Orientation,
            fold_margin: 0.1,
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
    /// Grid points carrying orientation rows at the end
    /// ([`FoldRemoval::Orientation`]).
    pub orientation_rows: u32,
}
