//! Numerics with no knowledge of meshes: bicubic B-spline kernels
//! ([`bspline`]), the one bicubic Bezier-net implementation (`bezier`:
//! B-spline to Bezier conversion, de Casteljau splits, second-difference
//! bounds; used by the eigen tables, the bounds, tessellation and
//! voxelization), small dense linear algebra (`linalg`), the two-lane SIMD
//! vector and the run-time AVX2 switch (`simd`), the `f32` square root
//! (`sqrt32`), and the evaluation value
//! type [`Eval`].
//!
//! Layer 2 of the crate (see `lib.rs`): imports only `config`, `error` and
//! `mem`.

pub(crate) mod bezier;
pub mod bspline;
pub(crate) mod linalg;
mod point;
pub(crate) mod simd;
pub(crate) mod sqrt32;

pub use point::Eval;
