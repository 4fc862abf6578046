//! Memory for the core's builders (`Topology::build`, `Evaluator::build`,
//! `Tessellation::build`, `VoxelGrid::new`, refinement, ...), which work in
//! caller-owned blocks of `u64` words sized by their size queries (bytes).
//!
//! A block is a `Vec<u64>` from [`words`], handed over as `&mut block`.

/// A zeroed block of at least `bytes` bytes (at least one word).
pub fn words(bytes: usize) -> Vec<u64> {
    vec![0u64; ccss_core::mem::words_for(bytes).max(1)]
}
