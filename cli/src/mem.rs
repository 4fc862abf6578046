//! Memory for the core's builders (`Topology::build`, `Evaluator::build`,
//! `Tessellation::build`, `VoxelGrid::new`, refinement, ...), which work in
//! caller-owned blocks of `u64` words sized by their size queries (bytes).
//!
//! A block is a `Vec<u64>` from [`words`], handed over as `&mut block`.

/// A zeroed block of at least `bytes` bytes (at least one word). Blocks
/// of [`HUGE_FROM`] bytes or more ask the kernel for transparent huge
/// pages ([`advise_huge`]).
pub fn words(bytes: usize) -> Vec<u64> {
    let block = vec![0u64; ccss_core::mem::words_for(bytes).max(1)];
    if bytes >= HUGE_FROM {
        advise_huge(&block);
    }
    block
}

/// Blocks from this size on get [`advise_huge`]: a few 2 MiB pages.
pub const HUGE_FROM: usize = 4 << 20;

/// Asks Linux to back `block` with transparent huge pages
/// (`madvise(MADV_HUGEPAGE)` on its whole 4 KiB pages; a hint, its result
/// is ignored; nothing elsewhere). The large blocks are the evaluator's
/// tables of big feature meshes, read at random by point queries: with 4
/// KiB pages a near-feature point of `catmark_car` touches about two
/// pages the 64-entry first-level TLB does not hold (BENCHMARKS.md,
/// issue #24). Fresh `vec!` zeroes of this size are untouched mappings,
/// so the advice comes before the pages exist.
pub fn advise_huge(block: &[u64]) {
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = block.as_ptr() as usize;
        let end = start + std::mem::size_of_val(block);
        let lo = start.div_ceil(PAGE) * PAGE;
        let hi = end / PAGE * PAGE;
        if hi > lo {
            // SAFETY: [lo, hi) lies inside `block`'s allocation, which
            // outlives the call; MADV_HUGEPAGE changes no contents and no
            // mapping, only how the kernel backs the pages.
            unsafe {
                libc::madvise(lo as *mut libc::c_void, hi - lo, libc::MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = block;
}
