//! Caller memory: the arena that carves typed slices out of one caller
//! block, and the exact size queries that replay it.
//!
//! Every structure that grows with the mesh lives in a caller block of
//! `u64` words, so a Rust caller never writes `unsafe`:
//!
//! ```
//! use ccss_core::mem::words_for;
//! # let required_bytes = 100;
//! let mut mem = vec![0u64; words_for(required_bytes)]; // 13 words
//! assert!(mem.len() * 8 >= required_bytes);
//! ```
//!
//! Size queries (`required_bytes`) answer in bytes, exactly what a build
//! uses (always a multiple of 8); [`words_for`] turns them into words. The
//! C ABI receives `void* + len`, checks the 8-byte alignment and views the
//! block as words (ffi/).
//!
//! Layer 1: imports only `error` and `config`.

pub mod arena;

/// Number of `u64` words that hold `bytes` bytes (`bytes / 8` rounded up).
#[inline]
pub const fn words_for(bytes: usize) -> usize {
    bytes.div_ceil(8)
}

/// Size in bytes of a block of `words` words (saturating), for comparing a
/// caller block with a size query in bytes.
#[inline]
pub const fn bytes_of(words: usize) -> usize {
    words.saturating_mul(8)
}

/// The words `w` viewed as `2 * w.len()` `u32` values (not zeroed). The
/// one place where caller words are viewed as `u32`.
#[inline]
pub(crate) fn as_u32s(w: &mut [u64]) -> &mut [u32] {
    // SAFETY: `u64` is at least as aligned as `u32`, so `align_to_mut`
    // returns an empty prefix and suffix, and every bit pattern is a valid
    // u32.
    let (pre, mid, _) = unsafe { w.align_to_mut::<u32>() };
    debug_assert!(pre.is_empty());
    mid
}
