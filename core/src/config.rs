//! Build-time constants (bottom layer: imports nothing from the crate).
//!
//! `MAX_VALENCE`, `TABLE_VALENCES` (with `TABLE_SLOT`) and `TESS_MAX_LEVEL`
//! come from `core/build.rs` (environment variables `CCSS_MAX_VALENCE`,
//! default 16; `CCSS_TABLE_VALENCES`, default every valence
//! `3..=MAX_VALENCE`; `CCSS_TESS_MAX_LEVEL`, default 30); everything sized
//! by them is derived here or from them.

include!(concat!(env!("OUT_DIR"), "/config.rs"));

/// Largest number of control points of a patch: `2 * MAX_VALENCE + 8`
/// ([`crate::mesh::stencil`] labels them).
pub const MAX_K: usize = 2 * MAX_VALENCE + 8;
