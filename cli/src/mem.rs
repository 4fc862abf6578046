//! Memory for the core's builders (`Topology::build`, `Evaluator::build`,
//! `Tessellation::build`, `VoxelGrid::new`, refinement, ...), which work in
//! caller-owned, 8-byte aligned blocks sized by their size queries.
//!
//! A block is a `Vec<u64>` from [`words`]. The core still takes the block as
//! `&mut [u8]`, so call sites hand it over as `as_bytes_mut(&mut block)`;
//! [`as_bytes_mut`] is the command's one `unsafe`. When the core takes
//! `&mut [u64]` (issue #23), that function and its call-site wrappers are
//! deleted and nothing else changes.

/// A zeroed, 8-byte aligned block of at least `bytes` bytes (at least one
/// word).
pub fn words(bytes: usize) -> Vec<u64> {
    vec![0u64; bytes.div_ceil(8).max(1)]
}

/// The bytes of `v`: the same memory, borrowed mutably.
pub fn as_bytes_mut(v: &mut [u64]) -> &mut [u8] {
    let len = std::mem::size_of_val(v);
    // SAFETY: u8 has alignment 1 and no invalid bit patterns; the slice
    // covers exactly the memory of `v` and borrows it mutably.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<u8>(), len) }
}
