//! # ccss-core
//!
//! Allocation-free, `no_std` core of **ccss**: exact evaluation of
//! Catmull-Clark subdivision surfaces (position, first and second
//! derivatives, normals) at any parameter value, from fixed-size per-valence
//! eigen tables (\[Stam98\]; \[CL-R ch. 2\]).
//!
//! Modules, in layers from the bottom; each imports only from the layers
//! below it (`scripts/imports.py` checks this: no circles, no import that
//! runs back up), and this file only declares them and re-exports:
//!
//! 0. [`config`] (build-time constants such as [`MAX_VALENCE`]) and the
//!    [`Error`] type.
//! 1. [`mem`]: caller memory. Builders take a block of `u64` words
//!    ([`mem::words_for`] of a `required_bytes` size query), so no caller
//!    writes `unsafe`.
//! 2. [`math`]: B-spline kernels, the one Bezier-net implementation (split,
//!    second-difference bounds), linear algebra, SIMD, the [`Eval`] type.
//! 3. [`mesh`]: [`Topology`] (validated half-edges in caller memory),
//!    [`mesh::refine`], [`mesh::stencil`], [`Weights`].
//! 4. [`eigen`]: per-valence eigen tables ([`TableSet`], [`ValenceTable`]),
//!    computed at run time without heap; the patch-level kernel and the
//!    constants of the bounds, computed with the tables.
//! 5. [`eval`]: the mesh-level API ([`Evaluator`]): `(face, sub, u, v)` to
//!    position, derivatives and normal, single points or batches.
//! 6. [`bounds`]: guaranteed cell bounds and subdivision depths over an
//!    evaluator.
//! 7. [`tessellate`], [`voxel`] (over the evaluator and the bounds),
//!    [`unified`] (the \[MS01\] unified scheme; it needs only `mesh` and
//!    `mem`) and [`interpolate`] (similarity-based interpolation,
//!    \[CL-R ch. 4\]), four siblings that do not import each other.
//! 8. [`query`]: certified ray intersection, inside/outside, closest
//!    points and planar slices, over the tessellation's cell quadtree.
//!
//! Nothing here allocates, recursion is absent, and no input makes it panic:
//! bad input is an [`Error`] naming the face, vertex or edge.
//!
//! ```
//! use ccss_core::mem::words_for;
//! use ccss_core::{BuildScratch, Evaluator, MeshInput, TableSet, Topology};
//! # fn main() -> Result<(), ccss_core::Error> {
//! // A cube: 8 vertices of valence 3, 6 quads.
//! let p = [-1.,-1.,-1., 1.,-1.,-1., 1.,1.,-1., -1.,1.,-1., -1.,-1.,1., 1.,-1.,1., 1.,1.,1., -1.,1.,1.];
//! let sizes = [4u32; 6];
//! let idx = [0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7];
//! let mesh = MeshInput { positions: &p, face_sizes: &sizes, indices: &idx };
//! let mut tables = Box::new(TableSet::ZERO);
//! tables.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))?;
//! let mut tmem = vec![0u64; words_for(Topology::required_bytes(8, &sizes))];
//! let topo = Topology::build(mesh, &mut tmem)?;
//! let need = Evaluator::required_bytes(&topo, &tables)?;
//! let mut emem = vec![0u64; words_for(need)];
//! let ev = Evaluator::build(&topo, &tables, &mut emem)?;
//! let e = ev.eval(0, 0, 0.5, 0.5)?;
//! assert!((e.p.z + 68.0 / 81.0).abs() < 1e-12); // centre of the bottom face
//! # Ok(())
//! # }
//! ```
#![no_std]
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]
// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

pub mod boolean;
pub mod bounds;
pub mod config;
pub mod eigen;
mod error;
pub mod eval;
pub mod interpolate;
pub mod math;
pub mod mem;
pub mod mesh;
pub mod query;
pub mod tessellate;
#[cfg(test)]
mod test_rng;
pub mod unified;
pub mod voxel;

pub use config::MAX_VALENCE;
pub use eigen::{BuildScratch, TableSet, ValenceTable};
pub use error::{Error, SolidDefect, WeightsProblem};
pub use eval::{
    CellGeom, Eval, EvalF32, Evaluator, EvaluatorOptions, FeatureEvaluator, HullBound, Query,
};
pub use glam::DVec3;
pub use mesh::{MeshInput, Topology, Weights};
pub use unified::{TriangleRule, UnifiedParams};
