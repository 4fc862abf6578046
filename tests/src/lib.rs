//! Test support for ccss: independent oracles (a plain reference Catmull-Clark
//! subdivider with limit masks), mesh generators and OBJ loading for tests.
//!
//! Nothing here is used by the library itself; it exists so that integration
//! tests compare the library against code that is obviously correct.
#![deny(missing_docs)]

pub mod feature_input;
pub mod harness;
pub mod reference;
pub mod shapes;
pub mod sharp;
