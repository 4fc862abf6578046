//! Carving typed slices out of one caller-provided block of words.
//!
//! `core` never allocates: structures that need memory proportional to the
//! mesh take a `&mut [u64]` from the caller. [`Arena`] hands out `u32`/`f64`
//! slices from it, each starting on a word; [`Layout`] performs the same
//! sequence of requests without memory, so that a size query returns exactly
//! what a build will use (in bytes, a multiple of 8; see
//! [`super::words_for`]).

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

/// A bump allocator over a caller block of words.
pub struct Arena<'a> {
    rest: &'a mut [u64],
}

impl<'a> Arena<'a> {
    /// Wraps `mem` (a `u64` block is always aligned for every piece).
    pub fn new(mem: &'a mut [u64]) -> Self {
        Arena { rest: mem }
    }

    /// The next `round_up(bytes) / 8` words.
    fn take_words(&mut self, bytes: usize) -> &'a mut [u64] {
        let r = round_up(bytes) / ALIGN;
        let rest = core::mem::take(&mut self.rest);
        // The caller checked the total size beforehand (see `Layout`).
        let (head, tail) = rest.split_at_mut(r.min(rest.len()));
        self.rest = tail;
        head
    }

    /// Takes `n` zeroed `u32` values.
    pub fn u32s(&mut self, n: usize) -> &'a mut [u32] {
        let s = &mut super::as_u32s(self.take_words(n * 4))[..n];
        s.fill(0);
        s
    }

    /// Takes `n` zeroed `f64` values.
    pub fn f64s(&mut self, n: usize) -> &'a mut [f64] {
        let w = self.take_words(n * 8);
        // SAFETY: `f64` has the size and alignment of `u64`, and every bit
        // pattern is a valid f64, so the words can be viewed as f64.
        let (pre, mid, _) = unsafe { w.align_to_mut::<f64>() };
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
    /// Takes the words of `n` bytes (rounded up to a multiple of 8), for a
    /// nested structure that carves its own arena.
    pub fn words(&mut self, n: usize) -> &'a mut [u64] {
        self.take_words(n)
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
