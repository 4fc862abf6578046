//! `ccss bench`: single-threaded timings of the core, one file per
//! sub-verb (`eval`, `features`, `query`, `tables`, `tessellate`, `voxelize`), plus the helpers
//! only the benchmarks use: point classes, a seeded generator, the timed
//! evaluation loop and the conventional voxelization baseline.

pub mod classes;
pub mod eval;
pub mod features;
pub mod query;
pub mod regions;
pub mod rng;
pub mod tables;
pub mod tessellate;
pub mod timing;
pub mod voxel_baseline;
pub mod voxelize;

/// `--help` text of `ccss bench`.
pub const ABOUT: &str = "Benchmarks (single-threaded timings)";
