//! Mesh-level exact evaluation: the patch table ([`Evaluator`]) built from
//! a topology and the eigen tables, `(face, sub, u, v)` to [`Eval`].
//!
//! Files: `evaluator.rs` (the patch table, its build and the per-point and
//! batch paths; the batches run their bicubics on AVX2 vectors where the
//! CPU has them, the same bits), `frame.rs` (corner-frame rotations,
//! quadrants and the split map), `single.rs` (`f32`), `feature.rs`,
//! `feature_pack.rs`, `feature_cell.rs` (meshes with creases and
//! boundaries: the cache tree, its packing, dyadic cells).
//!
//! Layer 5: imports `config`, `error`, `mem`, `math`, `mesh` and `eigen`.

pub(crate) mod evaluator;
pub mod feature;
pub mod feature_cell;
mod feature_pack;
mod frame;
mod single;

pub use crate::math::Eval;
pub use evaluator::{Evaluator, EvaluatorOptions, Query, DEFAULT_DEEP_LEVEL, MAX_DEEP_LEVEL};
pub use feature::{CacheCounts, FeatureCache, FeatureEvaluator, MAX_CACHE_DEPTH};
pub use feature_cell::{CellCursor, CellGeom, HullBound, CURSOR_STATES, MAX_CELL_LEVEL};
pub(crate) use frame::{quadrant, rot_back, rot_param};
pub use single::{EvalF32, F32_BASIS_ERR};
