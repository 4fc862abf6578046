//! Per-valence eigen tables (\[Stam98\], \[CL-R §2.4\]): the eigen
//! decomposition of the local subdivision matrix, the evaluation kernel of
//! an extraordinary patch, and the constants computed with the tables for
//! the bounds above (ring-region second differences, the corner-fit
//! constants of `corner_fit`, the depth rates of `rates`).
//! [`TableSet`] holds valences 3..=MAX_VALENCE.
//!
//! Layer 4: imports `config`, `error`, `mem`, `math` and `mesh`.

pub mod bake;
pub(crate) mod corner_fit;
mod flatness;
mod kernel;
pub mod rates;
mod set;
mod table;

#[cfg(feature = "baked-tables")]
pub use bake::BAKED_TABLES;
pub(crate) use flatness::EigenTerms;
pub use rates::Rates;
pub use set::TableSet;
pub use table::{BuildScratch, ValenceTable};
