//! Multi-core drivers (rayon) of the core's per-slot and per-slab work,
//! shared by the verbs and the benchmarks.

pub mod slabs;
pub mod tessellate;
