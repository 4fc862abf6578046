//! Similarity-based interpolation (\[CL-R ch. 4\]): a control mesh `Q` whose
//! Catmull-Clark limit surface passes exactly through the vertices of a
//! closed mesh `P`, and whose derivatives follow those of `S(G)`, `G` being
//! `P` after one Catmull-Clark step.
//!
//! * `Q` has `G`'s topology; its Type I vertices (the first `n`, one per
//!   vertex of `P`) are fixed by the hard conditions (4.1) from their rings
//!   ([`ring`]), so interpolation is exact whatever the rest is.
//! * The Type II vertices are the unknowns of a least-squares problem: at
//!   the nine points `{0, 1/2, 1}^2` of every face (4.2) the sampled
//!   derivatives of `S(Q)` must be parallel to those of `S(G)` (4.5)
//!   ([`samples`], [`system`]).
//! * The normal equations (4.6) are solved by preconditioned conjugate
//!   gradients ([`solver`]) from the naive solution (`G`'s Type II
//!   vertices), multiplying face by face ([`system`]) or, after
//!   [`Interpolator::assemble`], with the assembled block-sparse matrix
//!   ([`assembled`]; same solution, fewer flops per product, more memory).
//! * Folds (the normal of `S(Q)` reversed against `S(G)`, which the
//!   homogeneous rows of (4.5) allow) are removed in rounds after the
//!   solve: points of a grid on every face whose orientation
//!   `n_G . (Q_u x Q_v)` is below a margin get that condition as a row
//!   linearised around the current solution, re-linearised each round
//!   ([`orient`], the default); or folded faces get anchor rows pulling
//!   their first derivatives towards `G`'s ([`folds`]).
//!
//! Files: [`labels`] (patch control points as vertex indices), [`samples`]
//! (derivative weights per valence), [`ring`] (the Type I substitution),
//! [`system`] (the matrix-free normal matrix and the preconditioner),
//! [`assembled`] (pattern and assembly of the normal matrix), [`blocks`]
//! (its compressed 3x3 blocks: product, symmetric Gauss-Seidel),
//! [`solver`] (PCG), [`requirements`] (extra hard requirements: positions
//! and normals anywhere), [`options`], [`interpolator`] (memory, build,
//! solve), [`hard_rows`] (their rows over the unknowns), [`folds`] (fold
//! detection and the anchor rows), [`orient`] (the orientation rows).
//!
//! Layer 7: imports `config`, `error`, `mem`, `math`, `mesh`, `eigen`.

pub mod assembled;
pub mod blocks;
pub mod folds;
pub mod hard_rows;
pub mod interpolator;
pub mod labels;
pub mod options;
pub mod orient;
pub mod requirements;
pub mod ring;
pub mod samples;
pub mod solver;
pub mod system;

pub use interpolator::Interpolator;
pub use options::{derivative, FoldRemoval, InterpolationOptions, Preconditioner, SolveStats};
pub use requirements::{Prescribed, Requirement};
