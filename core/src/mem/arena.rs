//! Carving typed slices out of one caller-provided byte buffer.
//!
//! `core` never allocates: structures that need memory proportional to the
//! mesh take a `&mut [u8]` from the caller. [`Arena`] hands out 8-byte aligned
//! `u32`/`f64` slices from it; [`Layout`] performs the same sequence of
//! requests without memory, so that a size query returns exactly what a
//! build will use.

use crate::error::Error;

const ALIGN: usize = 8;

#[inline]
fn round_up(bytes: usize) -> usize {
    bytes.div_ceil(ALIGN) * ALIGN
}

/// Counts the bytes a sequence of slice requests needs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Layout {
    bytes: usize,
}

impl Layout {
    /// Records a request for `n` values of `u32`.
    pub fn u32s(&mut self, n: usize) {
        self.bytes += round_up(n * 4);
    }
    /// Records a request for `n` values of `f64`.
    pub fn f64s(&mut self, n: usize) {
        self.bytes += round_up(n * 8);
    }
    /// Total bytes required.
    pub fn bytes(&self) -> usize {
        self.bytes
    }
}

/// A bump allocator over a caller buffer (8-byte aligned).
pub struct Arena<'a> {
    rest: &'a mut [u8],
}

impl<'a> Arena<'a> {
    /// Wraps `mem`, which must start at an 8-byte boundary.
    pub fn new(mem: &'a mut [u8]) -> Result<Self, Error> {
        if !(mem.as_ptr() as usize).is_multiple_of(ALIGN) {
            return Err(Error::Misaligned);
        }
        Ok(Arena { rest: mem })
    }

    fn take_bytes(&mut self, bytes: usize) -> &'a mut [u8] {
        let r = round_up(bytes);
        let rest = core::mem::take(&mut self.rest);
        // The caller checked the total size beforehand (see `Layout`).
        let (head, tail) = rest.split_at_mut(r.min(rest.len()));
        self.rest = tail;
        head
    }

    /// Takes `n` zeroed `u32` values.
    pub fn u32s(&mut self, n: usize) -> &'a mut [u32] {
        let b = self.take_bytes(n * 4);
        // SAFETY: `b` is 8-byte aligned (every piece is a multiple of 8 bytes
        // from an aligned start) and every bit pattern is a valid u32.
        let (pre, mid, _) = unsafe { b.align_to_mut::<u32>() };
        debug_assert!(pre.is_empty());
        let s = &mut mid[..n];
        s.fill(0);
        s
    }

    /// Takes `n` zeroed `f64` values.
    pub fn f64s(&mut self, n: usize) -> &'a mut [f64] {
        let b = self.take_bytes(n * 8);
        // SAFETY: as above; every bit pattern is a valid f64.
        let (pre, mid, _) = unsafe { b.align_to_mut::<f64>() };
        debug_assert!(pre.is_empty());
        let s = &mut mid[..n];
        s.fill(0.0);
        s
    }
}

impl<'a> Arena<'a> {
    /// Takes `n` zeroed points.
    pub fn vec3s(&mut self, n: usize) -> &'a mut [glam::DVec3] {
        let f = self.f64s(3 * n);
        // SAFETY: `glam::DVec3` is `repr(C)` with three `f64` fields (size 24,
        // align 8); `f` is 8-byte aligned and holds exactly 3n initialised f64.
        unsafe { core::slice::from_raw_parts_mut(f.as_mut_ptr() as *mut glam::DVec3, n) }
    }
}

impl<'a> Arena<'a> {
    /// Takes `n` raw bytes (rounded up to a multiple of 8), for a nested
    /// structure that carves its own arena.
    pub fn bytes(&mut self, n: usize) -> &'a mut [u8] {
        self.take_bytes(n)
    }
}

impl Layout {
    /// Records a request for `n` raw bytes.
    pub fn raw(&mut self, n: usize) {
        self.bytes += round_up(n);
    }
    /// Records a request for `n` points.
    pub fn vec3s(&mut self, n: usize) {
        self.f64s(3 * n);
    }
}
