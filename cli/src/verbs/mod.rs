//! One file per verb of `ccss`: its arguments (clap), its `--help` text
//! (`ABOUT`) and its `run`, which reads the input, calls the core and
//! writes the output.

pub mod boolean;
pub mod closest;
pub mod depth;
pub mod eval;
pub mod info;
pub mod interpolate;
pub mod measure;
pub mod raycast;
pub mod refine;
pub mod slice;
pub mod tessellate;
pub mod voxelize;
