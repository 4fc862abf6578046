//! The ABI boundary: the panic guard every export runs behind, and the typed
//! pointer helpers that turn C arguments into Rust references, slices and
//! core memory. Every export goes through them, so none can forget a NULL,
//! length or alignment check:
//!
//! * [`guard`]: catches panics (`CCSS_ERR_INTERNAL`), fills the detail.
//! * [`check_ptr`] / [`try_ref`] / [`put`]: one object (non-NULL,
//!   aligned); [`try_handle`] / [`try_handle_mut`]: a handle, also checking
//!   its magic word.
//! * [`try_slice`] / [`try_slice_mut`]: arrays (NULL allowed when empty,
//!   resp. optional; aligned; at most `isize::MAX` bytes).
//! * [`try_block`]: a caller memory block `mem, mem_len` (non-NULL, at most
//!   `isize::MAX` bytes, large enough, 8-byte aligned), and [`core_mem`]:
//!   the one place where a checked block becomes a core memory slice.

use crate::status::{CcssErrorDetail, CcssStatus, Failure, Msg};
use core::ffi::c_void;
use core::mem::{align_of, size_of};
use core::ptr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `body` behind the ABI boundary: catches panics (reported as
/// `CCSS_ERR_INTERNAL`), maps the failure to its status and fills `detail`
/// (if non-NULL) on failure. Every status-returning export is one call of
/// this function.
#[inline]
pub(crate) fn guard(
    detail: *mut CcssErrorDetail,
    body: impl FnOnce() -> Result<(), Failure>,
) -> CcssStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => CcssStatus::OK,
        Ok(Err(f)) => fail(detail, f),
        Err(_) => fail(detail, Failure::new(CcssStatus::ERR_INTERNAL, Msg::Panic)),
    }
}

/// The failure half of [`guard`]: fills `detail` (if non-NULL) and
/// returns the status. Out of line and cold, so that the success path of
/// every export is one test of the body's result (the per-point
/// evaluations count it: BENCHMARKS.md).
#[cold]
#[inline(never)]
fn fail(detail: *mut CcssErrorDetail, f: Failure) -> CcssStatus {
    if !detail.is_null() {
        let _ = catch_unwind(|| {
            // SAFETY: the caller promises `detail` is NULL or points to a
            // writable `ccss_error_detail`; unaligned writes are tolerated.
            unsafe { ptr::write_unaligned(detail, f.to_detail()) }
        });
    }
    f.status
}

// ---------------------------------------------------------------------------
// Pointer helpers.

/// Checks that `p` can point to one `T`: non-NULL (NULL_POINTER naming
/// `arg`), aligned for `T` (MISALIGNED). Used for out-parameters before any
/// work is done, so that a bad one fails early and nothing is written.
pub(crate) fn check_ptr<T>(p: *const T, arg: &'static str) -> Result<(), Failure> {
    if p.is_null() {
        Err(Failure::null(arg))
    } else if (p as usize) % align_of::<T>() != 0 {
        Err(Failure::misaligned())
    } else {
        Ok(())
    }
}

/// Checks that `n` elements of `T` span at most `isize::MAX` bytes (the
/// limit of a Rust slice); INVALID_ARGUMENT naming `what` otherwise.
pub(crate) fn check_len<T>(n: usize, what: &'static str) -> Result<(), Failure> {
    if n.checked_mul(size_of::<T>())
        .map_or(true, |b| b > isize::MAX as usize)
    {
        Err(Failure::invalid(what))
    } else {
        Ok(())
    }
}

/// A shared reference to a handle or input struct (non-NULL, aligned).
///
/// # Safety
/// `p` is NULL or points to a live `T` that outlives the returned reference.
pub(crate) unsafe fn try_ref<'a, T>(p: *const T, arg: &'static str) -> Result<&'a T, Failure> {
    check_ptr(p, arg)?;
    // SAFETY: checked non-NULL and aligned; liveness is the caller's promise.
    Ok(unsafe { &*p })
}

/// An input array of `n` elements (NULL allowed when `n == 0`).
///
/// # Safety
/// Unless NULL, `p` points to `n` readable `T` that outlive the slice.
pub(crate) unsafe fn try_slice<'a, T>(
    p: *const T,
    n: usize,
    arg: &'static str,
) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    check_ptr(p, arg)?;
    check_len::<T>(n, "array length too large")?;
    // SAFETY: non-NULL, aligned, and the caller promises `n` readable elements.
    Ok(unsafe { core::slice::from_raw_parts(p, n) })
}

/// An optional output array of `n` elements (`None` for NULL): aligned, at
/// most `isize::MAX` bytes.
///
/// # Safety
/// Unless NULL, `p` points to `n` writable `T` not otherwise in use.
pub(crate) unsafe fn try_slice_mut<'a, T>(
    p: *mut T,
    n: usize,
    arg: &'static str,
) -> Result<Option<&'a mut [T]>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    check_ptr(p as *const T, arg)?;
    check_len::<T>(n, "array length too large")?;
    // SAFETY: non-NULL, aligned, and the caller promises `n` writable
    // elements, exclusively ours for the call.
    Ok(Some(unsafe { core::slice::from_raw_parts_mut(p, n) }))
}

/// Writes a result to an out-parameter (non-NULL, aligned).
///
/// # Safety
/// `p` is NULL or points to writable memory for a `T`.
pub(crate) unsafe fn put<T>(p: *mut T, arg: &'static str, value: T) -> Result<(), Failure> {
    check_ptr(p as *const T, arg)?;
    // SAFETY: checked non-NULL and aligned; writability is the caller's promise.
    unsafe { p.write(value) };
    Ok(())
}

// ---------------------------------------------------------------------------
// Caller memory blocks.

/// Alignment of every caller memory block (`malloc` gives at least this).
pub(crate) const BLOCK_ALIGN: usize = 8;

/// A caller memory block `mem, mem_len`, checked in this order (the order
/// core uses too): NULL_POINTER (`mem` NULL with `mem_len > 0`),
/// INVALID_ARGUMENT (`mem_len > isize::MAX`), BUFFER_TOO_SMALL
/// (`mem_len < required`; `detail.required` = `required` bytes),
/// MISALIGNED (not 8-byte aligned; a NULL `mem` with `mem_len == 0` too).
/// Returns the block's base address.
pub(crate) fn try_block(
    mem: *mut c_void,
    mem_len: usize,
    required: usize,
) -> Result<*mut u8, Failure> {
    if mem.is_null() && mem_len != 0 {
        return Err(Failure::null("mem"));
    }
    if mem_len > isize::MAX as usize {
        return Err(Failure::invalid("mem_len too large"));
    }
    if mem_len < required {
        return Err(Failure::too_small(required));
    }
    if mem.is_null() || (mem as usize) % BLOCK_ALIGN != 0 {
        return Err(Failure::misaligned());
    }
    Ok(mem as *mut u8)
}

/// The core memory block (words) of bytes `from..to` of a block checked
/// by [`try_block`] (`to <= mem_len`, `from` a multiple of 8 as every
/// handle header and array offset is); a trailing partial word is not
/// part of it.
///
/// This is the **only** place where caller memory becomes a core memory
/// block: core's builders take `&mut [u64]`, the C caller hands `void*`
/// and a length in bytes.
///
/// # Safety
/// `base` comes from [`try_block`] for a block of at least `to` writable
/// bytes, exclusively ours for the lifetime `'a` (for a handle's arena: as
/// long as the handle lives, by the C-side contract).
pub(crate) unsafe fn core_mem<'a>(
    base: *mut u8,
    from: usize,
    to: usize,
) -> Result<&'a mut [u64], Failure> {
    if from > to || from % BLOCK_ALIGN != 0 || (base as usize) % BLOCK_ALIGN != 0 {
        return Err(Failure::internal("core memory range"));
    }
    // SAFETY: `base .. base + to` is writable and ours (caller promise),
    // `base + from` is 8-byte aligned (checked above), so it holds
    // `(to - from) / 8` words; `to - from <= isize::MAX` as
    // `to <= mem_len <= isize::MAX`.
    Ok(unsafe { core::slice::from_raw_parts_mut(base.add(from).cast::<u64>(), (to - from) / 8) })
}

/// Whether two byte ranges overlap (empty ranges overlap nothing).
pub(crate) fn overlaps(a: *const u8, a_len: usize, b: *const u8, b_len: usize) -> bool {
    let (a, b) = (a as usize, b as usize);
    a_len != 0 && b_len != 0 && a < b.saturating_add(b_len) && b < a.saturating_add(a_len)
}

/// `n` rounded up to a multiple of 8 (handle headers and block offsets).
pub(crate) const fn round8(n: usize) -> usize {
    n.div_ceil(8) * 8
}

/// Bytes of a handle block: the core's requirement plus the handle header
/// in front of it (`what` names the overflow).
pub(crate) fn block_bytes(core: usize, head: usize, what: &'static str) -> Result<usize, Failure> {
    core.checked_add(head).ok_or(Failure::invalid(what))
}

/// A handle type living at the start of a caller block, carrying a magic
/// word (type and layout version) that every export checks before use.
pub(crate) trait Handle {
    /// Type tag and layout version; changes whenever the layout does.
    const MAGIC: u64;
    /// Byte offset of the magic field.
    const MAGIC_OFFSET: usize;
    /// The C type name (messages).
    const NAME: &'static str;
}

/// Eight ASCII bytes as a magic word: `magic(b"ccssEVL1")`.
pub(crate) const fn magic(tag: &[u8; 8]) -> u64 {
    u64::from_le_bytes(*tag)
}

/// [`check_ptr`], then the handle's magic word: a garbage pointer to
/// readable memory, a handle of another type or a block whose header was
/// overwritten is `CCSS_ERR_INVALID_HANDLE`, not undefined behaviour in our
/// code (a pointer to unreadable memory still faults when read).
///
/// # Safety
/// `p` is NULL or points to at least `MAGIC_OFFSET + 8` readable bytes; if
/// the magic matches, to a live `T` built by this library.
pub(crate) unsafe fn try_handle<'a, T: Handle>(
    p: *const T,
    arg: &'static str,
) -> Result<&'a T, Failure> {
    check_ptr(p, arg)?;
    // SAFETY: caller promise (readable header); aligned by check_ptr (T has
    // the magic's alignment at MAGIC_OFFSET, a multiple of 8).
    let m = unsafe { ptr::read((p as *const u8).add(T::MAGIC_OFFSET) as *const u64) };
    if m != T::MAGIC {
        return Err(Failure::new(
            CcssStatus::ERR_INVALID_HANDLE,
            Msg::Handle { arg, ty: T::NAME },
        ));
    }
    // SAFETY: the magic is written last by the build and matches.
    Ok(unsafe { &*p })
}

/// [`try_handle`] for a mutable handle.
///
/// # Safety
/// As [`try_handle`], and no other reference to `*p` is live.
pub(crate) unsafe fn try_handle_mut<'a, T: Handle>(
    p: *mut T,
    arg: &'static str,
) -> Result<&'a mut T, Failure> {
    // SAFETY: forwarded.
    unsafe { try_handle(p as *const T, arg) }?;
    // SAFETY: checked; caller promise of exclusivity.
    Ok(unsafe { &mut *p })
}

/// A 64-bit checksum over words (the integrity check of handle blocks,
/// `ccss_tables_verify`, `ccss_evaluator_verify`): per word
/// `h = (h ^ w) * K` with an odd `K`, a bijection of `h` for each word, so
/// a change of any single word (any flipped byte) always changes the sum;
/// several changed words cancel with probability about `2^-64`.
pub(crate) struct Checksum(u64);

impl Checksum {
    const K: u64 = 0x9e37_79b9_7f4a_7c15;
    pub(crate) const fn new() -> Self {
        Checksum(0xcbf2_9ce4_8422_2325)
    }
    #[inline]
    pub(crate) fn word(&mut self, w: u64) {
        self.0 = (self.0 ^ w).wrapping_mul(Self::K);
    }
    pub(crate) fn value(&self) -> u64 {
        // Final mix (keeps the sum of an all-zero block away from zero).
        self.0 ^ (self.0 >> 29)
    }
}

/// The [`Checksum`] of the words `base + from .. base + to` (byte offsets,
/// multiples of 8).
///
/// # Safety
/// `base + from .. base + to` is readable, 8-byte aligned memory.
pub(crate) unsafe fn checksum_words(base: *const u8, from: usize, to: usize) -> u64 {
    let mut h = Checksum::new();
    let mut at = from;
    while at + 8 <= to {
        // SAFETY: caller promise; aligned (multiples of 8 from an aligned base).
        h.word(unsafe { ptr::read(base.add(at) as *const u64) });
        at += 8;
    }
    h.value()
}
