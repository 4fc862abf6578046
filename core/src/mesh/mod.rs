//! The control mesh: validated half-edge topology in caller memory
//! ([`topology`]), one uniform Catmull-Clark step ([`refine`], \[CC78\]),
//! the labelling of a patch's 2n+8 control points and its local
//! subdivision matrices ([`stencil`], \[Stam98\]), and the vertex rules per
//! valence ([`weights`], \[CL-R ch. 1\]).
//!
//! Layer 3: imports `config`, `error`, `mem` and `math`.

pub mod features;
pub mod local;
pub mod refine;
pub mod sharpness;
pub mod stencil;
pub mod strip;
pub mod topology;
pub mod weights;

pub use topology::{MeshInput, Topology};
pub use weights::Weights;
