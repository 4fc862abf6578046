//! Guaranteed bounds over an evaluator's patches: dyadic cell bounds
//! (`cell`, \[CL-R ch. 7\]) and subdivision depths ([`depth`], \[CL-R ch. 3\]).
//!
//! Layer 6: imports everything below (`config`, `error`, `mem`, `math`,
//! `mesh`, `eigen`, `eval`); free functions taking `&Evaluator`.

mod cell;
pub mod depth;
pub mod feature_depth;

pub use cell::*;
