//! Build-time constants (bottom layer: imports nothing from the crate).
//!
//! `MAX_VALENCE` comes from `core/build.rs` (environment variable
//! `CCSS_MAX_VALENCE`, default 16); everything sized by it is derived here.

include!(concat!(env!("OUT_DIR"), "/config.rs"));

/// Largest number of control points of a patch: `2 * MAX_VALENCE + 8`
/// ([`crate::mesh::stencil`] labels them).
pub const MAX_K: usize = 2 * MAX_VALENCE + 8;
