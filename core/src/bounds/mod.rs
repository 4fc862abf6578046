//! Guaranteed bounds over an evaluator's patches: dyadic cell bounds
//! (`cell`, \[CL-R ch. 7\]) and subdivision depths ([`depth`], \[CL-R ch. 3\]),
//! with the rounding terms and coordinate range of [`rounding`]; the
//! Bezier-net distance of a control face ([`face_distance`]) for the tight
//! depths.
//!
//! Layer 6: imports everything below (`config`, `error`, `mem`, `math`,
//! `mesh`, `eigen`, `eval`); free functions taking `&Evaluator`.

mod cell;
pub mod depth;
pub mod face_distance;
pub mod feature_depth;
pub mod rounding;

pub use cell::*;
