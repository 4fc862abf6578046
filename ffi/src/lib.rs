//! # ccss-ffi: the C ABI of ccss
//!
//! Built as `libccss.a` / `libccss.so` (and an rlib); the C header is
//! `include/ccss.h`, generated from this file by cbindgen (`ffi/gen_header.sh`).
//!
//! ## Conventions (modelled on rustls-ffi)
//!
//! * Every fallible function returns a [`CcssStatus`] (`ccss_status` in C);
//!   results go to out-parameters, which are written **only on success**.
//!   Functions that take a `ccss_error_detail *detail` (may be NULL) fill it
//!   on failure with the offending face / vertex / edge / query and a message.
//! * Every pointer is checked for NULL (a NULL array with a zero count is
//!   fine) and for the alignment of its type; every export catches panics
//!   and returns `CCSS_ERR_PANIC` instead of unwinding into C.
//! * **No allocation**: the C caller provides all memory. Each handle
//!   (`ccss_tables`, `ccss_topology`, `ccss_evaluator`) has a size query; the
//!   caller allocates a block of that many bytes, 8-byte aligned (`malloc` is
//!   fine), and the build function writes the handle at the start of the
//!   block and uses the rest as its arena. The returned handle pointer *is*
//!   the block address: there is nothing to destroy, the caller frees the
//!   block when done.
//!
//! ## Lifetime contract (C side)
//!
//! * A block must stay allocated, unmoved and unmodified while its handle is
//!   used, and while any handle built from it is used.
//! * `ccss_topology` copies the positions, face sizes and indices into its
//!   block: the caller's arrays may be freed right after
//!   `ccss_topology_build`.
//! * `ccss_evaluator` refers to its `ccss_tables` (keep the tables block alive
//!   as long as the evaluator) but **not** to the `ccss_topology`: core's
//!   `Evaluator` stores only its tables reference and slices of its own
//!   memory, so the topology block may be freed right after
//!   `ccss_evaluator_build`.
//! * Handles are immutable after build: const handles may be used from any
//!   number of threads at once.
//!
//! In Rust the handles hold core structures whose lifetimes are erased to
//! `'static`; the contract above is what makes that sound.
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

use ccss_core::bounds::depth::{Method, Rates};
use ccss_core::eval::Query;
use ccss_core::{
    BuildScratch, DVec3, Error, Eval, Evaluator, MeshInput, TableSet, Topology, Weights,
};
use core::ffi::{c_char, c_int, c_void};
use core::fmt::{self, Write as _};
use core::mem::{align_of, needs_drop, offset_of, size_of};
use core::ptr;
use std::panic::{catch_unwind, AssertUnwindSafe};

mod tessellate;
pub use tessellate::*;
mod unified;
mod voxel;
pub use unified::*;
pub use voxel::*;

// ---------------------------------------------------------------------------
// Status codes and error details.

/// Result of every fallible ccss function. The numeric values are stable ABI.
///
/// In C the constants read `CCSS_OK`, `CCSS_ERR_NULL_POINTER`, ...
/// Functions that *take* a status (`ccss_status_message`) take it as `int`, so
/// that any integer a C program passes is safe.
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssStatus {
    /// Success.
    OK = 0,
    /// A required pointer argument is NULL.
    ERR_NULL_POINTER = 1,
    /// A caller buffer is too small; `detail.required` says how large it must
    /// be (bytes for memory blocks, elements for output arrays).
    ERR_BUFFER_TOO_SMALL = 2,
    /// A memory block is not 8-byte aligned, or an array is not aligned for
    /// its element type.
    ERR_MISALIGNED = 3,
    /// An argument is invalid (the detail message names it).
    ERR_INVALID_ARGUMENT = 4,
    /// The mesh has no vertices or no faces.
    ERR_EMPTY_MESH = 5,
    /// The face sizes add up to `detail.required` indices but `detail.value`
    /// were given.
    ERR_INDEX_COUNT_MISMATCH = 6,
    /// Face `detail.face` uses vertex `detail.vertex`, which does not exist.
    ERR_INDEX_OUT_OF_RANGE = 7,
    /// Face `detail.face` has only `detail.value` (< 3) vertices.
    ERR_FACE_TOO_SMALL = 8,
    /// Face `detail.face` has `detail.value` vertices, more than
    /// `ccss_max_valence` allows.
    ERR_FACE_TOO_LARGE = 9,
    /// Face `detail.face` uses vertex `detail.vertex` twice.
    ERR_REPEATED_VERTEX = 10,
    /// Vertex `detail.vertex` has a NaN or infinite coordinate.
    ERR_NON_FINITE_COORDINATE = 11,
    /// Edge `detail.vertex`-`detail.vertex2` is shared by more than two faces.
    ERR_NON_MANIFOLD_EDGE = 12,
    /// The two faces on edge `detail.vertex`-`detail.vertex2` traverse it in
    /// the same direction.
    ERR_INCONSISTENT_ORIENTATION = 13,
    /// The faces around vertex `detail.vertex` do not form a single fan.
    ERR_NON_MANIFOLD_VERTEX = 14,
    /// Edge `detail.vertex`-`detail.vertex2` has only one face (open meshes are
    /// not supported).
    ERR_BOUNDARY_EDGE = 15,
    /// Vertex `detail.vertex` has valence `detail.value`, outside
    /// `3..=ccss_max_valence`.
    ERR_UNSUPPORTED_VALENCE = 16,
    /// Face index `detail.face` is out of range.
    ERR_FACE_OUT_OF_RANGE = 17,
    /// Face `detail.face` has no sub-face `detail.value`.
    ERR_SUBFACE_OUT_OF_RANGE = 18,
    /// A parameter u or v is NaN or outside `[0, 1]`.
    ERR_PARAMETER_OUT_OF_RANGE = 19,
    /// No eigen table for valence `detail.value`.
    ERR_MISSING_TABLE = 20,
    /// The eigen table of valence `detail.value` failed its self-check.
    ERR_TABLE_BUILD_FAILED = 21,
    /// Vertex-rule weights rejected (`ccss_tables_build`,
    /// `ccss_weights_check`): a weight is NaN, infinite or negative,
    /// `alpha + beta + gamma` differs from 1 by more than
    /// `CCSS_WEIGHTS_SUM_TOLERANCE`, valence 4 has non-standard weights
    /// (regular patches are bicubic B-splines), or the valence is outside
    /// `3..=ccss_max_valence`. `detail.value` is the valence (`vertex` is -1:
    /// no particular vertex), `detail.query_index` the index of the offending
    /// entry in the array given to `ccss_tables_build`; the message says which
    /// rule was broken.
    ERR_INVALID_WEIGHTS = 22,
    /// A Rust panic was caught at the ABI boundary (a bug in ccss).
    ERR_PANIC = 99,
}

/// Capacity of `ccss_error_detail.message`, including the terminating NUL.
pub const CCSS_ERROR_MESSAGE_CAPACITY: usize = 256;

/// Where and why a call failed. Optional out-parameter (pass NULL if not
/// wanted) of the functions that validate input; written only on failure.
///
/// Integer fields that do not apply to the error are -1 (signed fields) or 0
/// (`required`); `query_index` is `UINT64_MAX` unless the error is about one
/// query of a batch.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CcssErrorDetail {
    /// The status the function returned.
    pub status: CcssStatus,
    /// The offending face (or -1).
    pub face: i64,
    /// The offending vertex, or the first end of the offending edge (or -1).
    pub vertex: i64,
    /// The second end of the offending edge (or -1); the edge is
    /// `vertex`-`vertex2`.
    pub vertex2: i64,
    /// The offending number, by status: the face size (FACE_TOO_SMALL,
    /// FACE_TOO_LARGE), the valence (UNSUPPORTED_VALENCE, MISSING_TABLE,
    /// TABLE_BUILD_FAILED, INVALID_WEIGHTS, and INVALID_ARGUMENT for a valence
    /// listed twice in `ccss_tables_build`), the sub-face index
    /// (SUBFACE_OUT_OF_RANGE), the number of indices given
    /// (INDEX_COUNT_MISMATCH); else -1.
    pub value: i64,
    /// BUFFER_TOO_SMALL: the required size (bytes for memory blocks, elements
    /// for output arrays); INDEX_COUNT_MISMATCH: the number of indices the face
    /// sizes add up to; else 0.
    pub required: u64,
    /// Index of the offending query in a batch (`ccss_eval_batch`), or of the
    /// offending weight entry (`ccss_tables_build`); else `UINT64_MAX`.
    pub query_index: u64,
    /// Human-readable message (the core library's error message, prefixed
    /// with `query N: ` for batch errors and `entry N: ` for weight entries),
    /// NUL-terminated UTF-8; truncated at a
    /// character boundary if longer than the capacity allows.
    pub message: [c_char; CCSS_ERROR_MESSAGE_CAPACITY],
}

/// What an internal failure says; formatted into the detail message.
#[derive(Clone, Copy)]
enum Msg {
    Core(Error),
    Null(&'static str),
    Text(&'static str),
    /// A valence listed twice in a weight-entry array.
    DuplicateValence {
        valence: u32,
        first: u64,
    },
    Panic,
}

/// An internal failure: status plus everything that goes into the detail.
#[derive(Clone, Copy)]
struct Failure {
    status: CcssStatus,
    face: i64,
    vertex: i64,
    vertex2: i64,
    value: i64,
    required: u64,
    query_index: Option<u64>,
    /// What `query_index` counts ("query", "entry"): the message prefix.
    index_name: &'static str,
    msg: Msg,
}

impl Failure {
    fn new(status: CcssStatus, msg: Msg) -> Failure {
        Failure {
            status,
            face: -1,
            vertex: -1,
            vertex2: -1,
            value: -1,
            required: 0,
            query_index: None,
            index_name: "query",
            msg,
        }
    }

    fn null(arg: &'static str) -> Failure {
        Failure::new(CcssStatus::ERR_NULL_POINTER, Msg::Null(arg))
    }

    fn invalid(what: &'static str) -> Failure {
        Failure::new(CcssStatus::ERR_INVALID_ARGUMENT, Msg::Text(what))
    }

    fn too_small(required: usize) -> Failure {
        Failure::from(Error::BufferTooSmall { required })
    }

    fn misaligned() -> Failure {
        Failure::from(Error::Misaligned)
    }
}

/// Maps every core error to its status and detail fields.
impl From<Error> for Failure {
    fn from(e: Error) -> Failure {
        use CcssStatus as S;
        let mut f = Failure::new(S::ERR_INVALID_ARGUMENT, Msg::Core(e));
        let edge = |f: &mut Failure, st: CcssStatus, v0: u32, v1: u32| {
            f.status = st;
            f.vertex = v0 as i64;
            f.vertex2 = v1 as i64;
        };
        match e {
            Error::EmptyMesh => f.status = S::ERR_EMPTY_MESH,
            Error::IndexCountMismatch { expected, got } => {
                f.status = S::ERR_INDEX_COUNT_MISMATCH;
                f.required = expected as u64;
                f.value = got as i64;
            }
            Error::IndexOutOfRange { face, vertex } => {
                f.status = S::ERR_INDEX_OUT_OF_RANGE;
                f.face = face as i64;
                f.vertex = vertex as i64;
            }
            Error::FaceTooSmall { face, size } => {
                f.status = S::ERR_FACE_TOO_SMALL;
                f.face = face as i64;
                f.value = size as i64;
            }
            Error::FaceTooLarge { face, size } => {
                f.status = S::ERR_FACE_TOO_LARGE;
                f.face = face as i64;
                f.value = size as i64;
            }
            Error::RepeatedVertex { face, vertex } => {
                f.status = S::ERR_REPEATED_VERTEX;
                f.face = face as i64;
                f.vertex = vertex as i64;
            }
            Error::NonFiniteCoordinate { vertex } => {
                f.status = S::ERR_NON_FINITE_COORDINATE;
                f.vertex = vertex as i64;
            }
            Error::NonManifoldEdge { v0, v1 } => edge(&mut f, S::ERR_NON_MANIFOLD_EDGE, v0, v1),
            Error::InconsistentOrientation { v0, v1 } => {
                edge(&mut f, S::ERR_INCONSISTENT_ORIENTATION, v0, v1)
            }
            Error::NonManifoldVertex { vertex } => {
                f.status = S::ERR_NON_MANIFOLD_VERTEX;
                f.vertex = vertex as i64;
            }
            // No status of its own in the stable list: reported as an invalid
            // argument naming the vertex (core does not produce it today:
            // isolated vertices are ignored).
            Error::UnusedVertex { vertex } => f.vertex = vertex as i64,
            Error::BoundaryEdge { v0, v1 } => edge(&mut f, S::ERR_BOUNDARY_EDGE, v0, v1),
            Error::UnsupportedValence { vertex, valence } => {
                f.status = S::ERR_UNSUPPORTED_VALENCE;
                // u32::MAX: no particular vertex (table build for a valence).
                f.vertex = if vertex == u32::MAX {
                    -1
                } else {
                    vertex as i64
                };
                f.value = valence as i64;
            }
            Error::BufferTooSmall { required } => {
                f.status = S::ERR_BUFFER_TOO_SMALL;
                f.required = required as u64;
            }
            Error::Misaligned => f.status = S::ERR_MISALIGNED,
            Error::FaceOutOfRange { face } => {
                f.status = S::ERR_FACE_OUT_OF_RANGE;
                f.face = face as i64;
            }
            Error::SubFaceOutOfRange { face, sub } => {
                f.status = S::ERR_SUBFACE_OUT_OF_RANGE;
                f.face = face as i64;
                f.value = sub as i64;
            }
            Error::ParameterOutOfRange => f.status = S::ERR_PARAMETER_OUT_OF_RANGE,
            Error::MissingTable { valence } => {
                f.status = S::ERR_MISSING_TABLE;
                f.value = valence as i64;
            }
            Error::TableBuildFailed { valence } => {
                f.status = S::ERR_TABLE_BUILD_FAILED;
                f.value = valence as i64;
            }
            Error::InvalidWeights { valence, .. } => {
                f.status = S::ERR_INVALID_WEIGHTS;
                f.value = valence as i64;
            }
            Error::InvalidArgument(_) => {}
            // `Error` is non_exhaustive: future variants are invalid arguments
            // (their message still comes from core's Display).
            _ => {}
        }
        f
    }
}

/// `fmt::Write` into a fixed byte buffer, keeping one byte for the NUL and
/// truncating at a UTF-8 character boundary.
struct FixedBuf<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl fmt::Write for FixedBuf<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = self.buf.len().saturating_sub(1 + self.len);
        let mut n = s.len().min(room);
        while !s.is_char_boundary(n) {
            n -= 1;
        }
        self.buf[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        if n < s.len() {
            Err(fmt::Error) // full: stop formatting
        } else {
            Ok(())
        }
    }
}

impl Failure {
    fn to_detail(self) -> CcssErrorDetail {
        let mut bytes = [0u8; CCSS_ERROR_MESSAGE_CAPACITY];
        let mut w = FixedBuf {
            buf: &mut bytes,
            len: 0,
        };
        if let Some(q) = self.query_index {
            let _ = write!(w, "{} {q}: ", self.index_name);
        }
        // A formatting error only means the message was truncated.
        let _ = match self.msg {
            Msg::Core(e) => write!(w, "{e}"),
            Msg::Null(arg) => write!(w, "null pointer: argument `{arg}` is NULL"),
            Msg::Text(t) => write!(w, "invalid argument: {t}"),
            Msg::DuplicateValence { valence, first } => write!(
                w,
                "invalid argument: valence {valence} is listed twice (first in entry {first})"
            ),
            Msg::Panic => write!(w, "internal error: a Rust panic was caught (bug in ccss)"),
        };
        let mut message = [0 as c_char; CCSS_ERROR_MESSAGE_CAPACITY];
        for (m, b) in message.iter_mut().zip(bytes) {
            *m = b as c_char;
        }
        CcssErrorDetail {
            status: self.status,
            face: self.face,
            vertex: self.vertex,
            vertex2: self.vertex2,
            value: self.value,
            required: self.required,
            query_index: self.query_index.unwrap_or(u64::MAX),
            message,
        }
    }
}

/// Runs `body` behind the ABI boundary: catches panics, maps the failure to
/// its status and fills `detail` (if non-NULL) on failure.
fn guard(detail: *mut CcssErrorDetail, body: impl FnOnce() -> Result<(), Failure>) -> CcssStatus {
    let f = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => return CcssStatus::OK,
        Ok(Err(f)) => f,
        Err(_) => Failure::new(CcssStatus::ERR_PANIC, Msg::Panic),
    };
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

fn nonnull<T>(p: *const T, arg: &'static str) -> Result<(), Failure> {
    if p.is_null() {
        Err(Failure::null(arg))
    } else if (p as usize) % align_of::<T>() != 0 {
        Err(Failure::misaligned())
    } else {
        Ok(())
    }
}

/// A shared reference to a handle (non-NULL, aligned).
///
/// # Safety
/// `p` is NULL or points to a live `T` that outlives the returned reference.
unsafe fn handle<'a, T>(p: *const T, arg: &'static str) -> Result<&'a T, Failure> {
    nonnull(p, arg)?;
    // SAFETY: checked non-NULL and aligned; liveness is the caller's promise.
    Ok(unsafe { &*p })
}

/// An input array of `n` elements (NULL allowed when `n == 0`).
///
/// # Safety
/// Unless NULL, `p` points to `n` readable `T` that outlive the slice.
unsafe fn in_slice<'a, T>(p: *const T, n: usize, arg: &'static str) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    nonnull(p, arg)?;
    if n.checked_mul(size_of::<T>())
        .map_or(true, |b| b > isize::MAX as usize)
    {
        return Err(Failure::invalid("array length too large"));
    }
    // SAFETY: non-NULL, aligned, and the caller promises `n` readable elements.
    Ok(unsafe { core::slice::from_raw_parts(p, n) })
}

/// A caller memory block: non-NULL unless `len == 0`, then at least
/// `required` bytes, then 8-byte aligned (the order core uses too).
fn check_block(mem: *mut c_void, len: usize, required: usize) -> Result<*mut u8, Failure> {
    if mem.is_null() && len != 0 {
        return Err(Failure::null("mem"));
    }
    if len < required {
        return Err(Failure::too_small(required));
    }
    if mem.is_null() || (mem as usize) % 8 != 0 {
        return Err(Failure::misaligned());
    }
    Ok(mem as *mut u8)
}

/// The bytes `[off, len)` of a block checked by [`check_block`] as the
/// `(len - off) / 8` words core takes (`off` a multiple of 8).
///
/// # Safety
///
/// `base` is 8-byte aligned with `len` writable bytes, exclusively the
/// caller's for `'a`; `off <= len`.
pub(crate) unsafe fn block_words<'a>(base: *mut u8, off: usize, len: usize) -> &'a mut [u64] {
    debug_assert!(off % 8 == 0 && off <= len);
    // SAFETY: `base + off` is 8-aligned (both are) and the words lie inside
    // the caller's block; every bit pattern is a valid u64.
    unsafe { core::slice::from_raw_parts_mut(base.add(off) as *mut u64, (len - off) / 8) }
}

fn overlaps(a: *const u8, a_len: usize, b: *const u8, b_len: usize) -> bool {
    let (a, b) = (a as usize, b as usize);
    a_len != 0 && b_len != 0 && a < b.saturating_add(b_len) && b < a.saturating_add(a_len)
}

const fn round8(n: usize) -> usize {
    n.div_ceil(8) * 8
}

/// Writes a result to an out-parameter (non-NULL, aligned).
///
/// # Safety
/// Bytes of a handle block: the core's requirement plus the handle header
/// in front of it (`what` names the overflow).
pub(crate) fn block_bytes(core: usize, head: usize, what: &'static str) -> Result<usize, Failure> {
    core.checked_add(head).ok_or(Failure::invalid(what))
}

/// Bytes of an evaluator block for `t` and `tb` (size query and build).
fn evaluator_bytes(t: &CcssTopology, tb: &CcssTables) -> Result<usize, Failure> {
    block_bytes(
        Evaluator::required_bytes(&t.topo, &tb.set)?,
        EVAL_HEAD,
        "mesh too large",
    )
}

/// `p` is NULL or points to writable memory for a `T`.
unsafe fn put<T>(p: *mut T, arg: &'static str, value: T) -> Result<(), Failure> {
    nonnull(p as *const T, arg)?;
    // SAFETY: checked non-NULL and aligned; writability is the caller's promise.
    unsafe { p.write(value) };
    Ok(())
}

// ---------------------------------------------------------------------------
// Library information.

/// The ccss version, e.g. "0.1.0": a static NUL-terminated string (never
/// free it).
#[no_mangle]
pub extern "C" fn ccss_version() -> *const c_char {
    const V: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    V.as_ptr() as *const c_char
}

/// A static NUL-terminated English description of a status (never free it).
/// `status` is an `int` so that any value is safe to pass; values that are not
/// a `ccss_status` give "unknown status".
#[no_mangle]
pub extern "C" fn ccss_status_message(status: c_int) -> *const c_char {
    let s: &'static core::ffi::CStr = match status {
        0 => c"success",
        1 => c"a required pointer argument is NULL",
        2 => c"a caller-provided buffer is too small",
        3 => c"a memory block or array is not suitably aligned (blocks need 8 bytes)",
        4 => c"invalid argument",
        5 => c"the mesh has no vertices or no faces",
        6 => c"the face sizes do not add up to the number of indices",
        7 => c"a face refers to a vertex that does not exist",
        8 => c"a face has fewer than 3 vertices",
        9 => c"a face has more vertices than the maximum valence allows",
        10 => c"a face uses the same vertex more than once",
        11 => c"a vertex coordinate is NaN or infinite",
        12 => c"an edge is shared by more than two faces",
        13 => c"two faces traverse a shared edge in the same direction (inconsistent orientation)",
        14 => c"the faces around a vertex do not form a single fan (non-manifold vertex)",
        15 => c"an edge has only one face; open meshes are not supported",
        16 => c"a vertex valence is outside the supported range",
        17 => c"face index out of range",
        18 => c"sub-face index out of range for this face",
        19 => c"parameter u or v is NaN or outside [0, 1]",
        20 => c"no eigen table for a valence of the mesh",
        21 => c"an eigen table failed its self-check",
        22 => c"vertex-rule weights rejected (NaN, infinite or negative, sum not 1, non-standard valence 4, or valence out of range)",
        99 => c"internal error: a Rust panic was caught (bug in ccss)",
        _ => c"unknown status",
    };
    s.as_ptr()
}

/// Copies the message of `detail` into `buf` (capacity `len` bytes),
/// truncated at a UTF-8 character boundary and always NUL-terminated when
/// `len > 0`. Returns the length of the whole message excluding the NUL (like
/// `snprintf`: the message was truncated iff the result is `>= len`).
/// `buf` may be NULL when `len` is 0 (a length query). A NULL `detail` is an
/// empty message.
///
/// # Safety
/// `detail` is NULL or points to a readable `ccss_error_detail` (any bytes;
/// only `message` is read, up to its capacity); `buf` is NULL or points to
/// `len` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn ccss_error_detail_format(
    detail: *const CcssErrorDetail,
    buf: *mut c_char,
    len: usize,
) -> usize {
    catch_unwind(AssertUnwindSafe(|| {
        let mut msg = [0u8; CCSS_ERROR_MESSAGE_CAPACITY];
        let mut n = 0;
        if !detail.is_null() {
            // SAFETY: the caller promises a readable struct; the field is
            // reached by a raw projection and read unaligned as plain bytes.
            unsafe {
                let m =
                    ptr::addr_of!((*detail).message) as *const [u8; CCSS_ERROR_MESSAGE_CAPACITY];
                msg = ptr::read_unaligned(m);
            }
            n = msg
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(CCSS_ERROR_MESSAGE_CAPACITY);
        }
        if !buf.is_null() && len > 0 {
            let mut k = n.min(len - 1);
            if k < n {
                // Do not cut a UTF-8 sequence: back off continuation bytes.
                while k > 0 && (msg[k] & 0xC0) == 0x80 {
                    k -= 1;
                }
            }
            // SAFETY: `buf` has `len > k` writable bytes; `msg` is a local copy.
            unsafe {
                ptr::copy_nonoverlapping(msg.as_ptr(), buf as *mut u8, k);
                *buf.add(k) = 0;
            }
        }
        n
    }))
    .unwrap_or(0)
}

/// Writes the largest supported vertex valence (and face size) to `*out`;
/// ccss-core's compile-time `MAX_VALENCE` (default 16).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or points to a writable `size_t`.
#[no_mangle]
pub unsafe extern "C" fn ccss_max_valence(out: *mut usize) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(ptr::null_mut(), || unsafe {
        put(out, "out", ccss_core::MAX_VALENCE)
    })
}

// ---------------------------------------------------------------------------
// Tables.

/// Eigen tables of one vertex rule (standard Catmull-Clark, or general
/// weights per valence, see `ccss_tables_build`) for every valence
/// `3..=ccss_max_valence` (opaque; lives at the start of its memory block).
/// Evaluators built from them refine and evaluate with that rule.
pub struct CcssTables {
    set: TableSet,
}

static ZERO_TABLES: TableSet = TableSet::ZERO;
static ZERO_SCRATCH: BuildScratch = BuildScratch::ZERO;

const TABLES_HEAD: usize = round8(size_of::<CcssTables>());
const TABLES_BYTES: usize = TABLES_HEAD + round8(size_of::<BuildScratch>());

/// Writes to `*out` the number of bytes `ccss_tables_build_standard` and
/// `ccss_tables_build` need (the tables plus the build scratch; about 760 KiB
/// for the default maximum valence 16).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or points to a writable `size_t`.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_required_bytes(out: *mut usize) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(ptr::null_mut(), || unsafe { put(out, "out", TABLES_BYTES) })
}

/// Builds the standard-rule eigen tables of all valences into `mem` (`len`
/// bytes, 8-byte aligned, at least `ccss_tables_required_bytes`) and writes
/// the handle (which equals `mem`) to `*out`. Takes a few milliseconds.
///
/// Errors: NULL_POINTER (`out`, or `mem` with `len > 0`), BUFFER_TOO_SMALL,
/// MISALIGNED, TABLE_BUILD_FAILED. On failure `*out` is not written and the
/// contents of `mem` are unspecified.
///
/// Ownership: the caller owns `mem`; the handle is valid while `mem` stays
/// allocated, unmoved and unmodified. Evaluators built from it refer to it.
/// Nothing to destroy: free `mem` when no evaluator uses the tables any more.
///
/// # Safety
/// `mem` is NULL or points to `len` writable bytes not otherwise in use;
/// `out` is NULL or points to a writable `const ccss_tables *`.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_build_standard(
    mem: *mut c_void,
    len: usize,
    out: *mut *const CcssTables,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        nonnull(out as *const *const CcssTables, "out")?;
        // SAFETY: forwarded caller promise.
        unsafe { build_tables(mem, len, out, &Weights::STANDARD) }
    })
}

/// Builds the tables of rule `w` into the block `mem` (`len` bytes) and
/// writes the handle to `*out` (already checked non-NULL and aligned).
///
/// # Safety
/// `mem` is NULL or points to `len` writable bytes not otherwise in use;
/// `out` is writable.
unsafe fn build_tables(
    mem: *mut c_void,
    len: usize,
    out: *mut *const CcssTables,
    w: &Weights,
) -> Result<(), Failure> {
    let base = check_block(mem, len, TABLES_BYTES)?;
    let t = base as *mut CcssTables;
    // SAFETY: `base` is 8-aligned with TABLES_BYTES writable bytes: the
    // tables at offset 0, the scratch at TABLES_HEAD (both align <= 8,
    // see the assertions below). Both are initialised by copying from
    // zeroed statics (a memcpy: no large temporaries on the stack).
    unsafe {
        let scratch = base.add(TABLES_HEAD) as *mut BuildScratch;
        ptr::copy_nonoverlapping(&ZERO_TABLES, ptr::addr_of_mut!((*t).set), 1);
        ptr::copy_nonoverlapping(&ZERO_SCRATCH, scratch, 1);
        (*t).set.build_into(w, &mut *scratch)?;
        *out = t;
    }
    Ok(())
}

/// Largest accepted `|alpha + beta + gamma - 1|` of a weight entry (ccss-core's
/// `weights::SUM_TOLERANCE`).
pub const CCSS_WEIGHTS_SUM_TOLERANCE: f64 = 1e-12;

/// The vertex rule of one valence: a vertex `V` of valence `n` moves to
/// `alpha V + beta/n sum(E_i) + gamma/n sum(F_i)` (`E_i` its edge neighbours,
/// `F_i` its face-diagonal vertices; for a non-quad face the virtual vertex
/// `4 C - V - E_i - E_(i+1)`, `C` the face centroid). Edge and face points
/// keep the standard rules. Standard Catmull-Clark is `alpha = 1 - 7/(4n)`,
/// `beta = 3/(2n)`, `gamma = 1/(4n)`.
///
/// Valid entries: `3 <= valence <= ccss_max_valence`, finite non-negative
/// weights adding up to 1 (within `CCSS_WEIGHTS_SUM_TOLERANCE`), and for
/// valence 4 exactly the standard weights (9/16, 3/8, 1/16): regular patches
/// are bicubic B-splines.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssWeightEntry {
    /// The valence `n` this rule applies to.
    pub valence: u32,
    /// Weight of the vertex itself.
    pub alpha: f64,
    /// Total weight of the `n` edge neighbours.
    pub beta: f64,
    /// Total weight of the `n` face-diagonal vertices.
    pub gamma: f64,
}

/// The rule of `e` set into `w` (core's validation).
fn set_entry(w: &mut Weights, e: &CcssWeightEntry) -> Result<(), Error> {
    // u32 -> usize is lossless on every platform ccss supports (>= 32 bits).
    w.set(e.valence as usize, e.alpha, e.beta, e.gamma)
}

/// Validates `count` weight entries (all before any is used) into a rule:
/// valences not listed keep the standard rule.
fn weights_of(entries: &[CcssWeightEntry]) -> Result<Weights, Failure> {
    let mut w = Weights::STANDARD;
    for (i, e) in entries.iter().enumerate() {
        if let Some(first) = entries[..i].iter().position(|p| p.valence == e.valence) {
            let mut f = Failure::new(
                CcssStatus::ERR_INVALID_ARGUMENT,
                Msg::DuplicateValence {
                    valence: e.valence,
                    first: first as u64,
                },
            );
            f.value = e.valence as i64;
            f.query_index = Some(i as u64);
            f.index_name = "entry";
            return Err(f);
        }
        set_entry(&mut w, e).map_err(|err| {
            let mut f = Failure::from(err);
            f.query_index = Some(i as u64);
            f.index_name = "entry";
            f
        })?;
    }
    Ok(w)
}

/// Builds the eigen tables of a general vertex rule into `mem` (`len` bytes,
/// 8-byte aligned, at least `ccss_tables_required_bytes`, the same size as
/// for `ccss_tables_build_standard`) and writes the handle (which equals
/// `mem`) to `*out`. Takes a few milliseconds.
///
/// `entries[0..count]` give the rule of some valences (see
/// `ccss_weight_entry`); every valence not listed keeps the standard rule, so
/// `count == 0` (`entries` may then be NULL) builds the standard tables. Each
/// valence may be listed once. Evaluators built from these tables use the
/// rule both for the eigen evaluation near extraordinary vertices and for
/// their internal refinement steps.
///
/// All entries are validated before the memory block is looked at: on the
/// first bad entry the function fails with INVALID_WEIGHTS (or INVALID_ARGUMENT for a
/// valence listed twice), `detail.query_index` = the entry's index,
/// `detail.value` = its valence, and neither `mem` nor `*out` is written.
///
/// Errors: NULL_POINTER (`out`, `entries` with `count > 0`, `mem` with
/// `len > 0`), MISALIGNED, INVALID_WEIGHTS, INVALID_ARGUMENT,
/// BUFFER_TOO_SMALL (`detail.required` = bytes; checked after the entries),
/// TABLE_BUILD_FAILED. On a failure after validation `*out` is not written
/// and the contents of `mem` are unspecified.
///
/// Ownership: as `ccss_tables_build_standard`; the entries are not referred
/// to after the call.
///
/// # Safety
/// `entries` is NULL or points to `count` readable entries; `mem` is NULL or
/// points to `len` writable bytes not otherwise in use (not overlapping
/// `entries`); `out` and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_build(
    entries: *const CcssWeightEntry,
    count: usize,
    mem: *mut c_void,
    len: usize,
    out: *mut *const CcssTables,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        nonnull(out as *const *const CcssTables, "out")?;
        // SAFETY: forwarded caller promise.
        let es = unsafe { in_slice(entries, count, "entries") }?;
        // Validated into a small rule on the stack (no heap) before `mem` is
        // touched.
        let w = weights_of(es)?;
        // SAFETY: forwarded caller promises.
        unsafe { build_tables(mem, len, out, &w) }
    })
}

/// Validates one weight entry without building anything and writes to
/// `*tangent_plane_continuous` 1 if the rule gives a tangent-plane continuous
/// surface at extraordinary vertices of that valence, else 0: the
/// frequency-0 eigenvalues are dominated by the subdominant eigenvalue of the
/// rest of the spectrum, `|lambda_0| < lambda_2` (Ball and Storry; 1 for the
/// standard rule). Tangent-plane discontinuity is a property, not an error:
/// such weights are accepted by `ccss_tables_build`.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_WEIGHTS (`detail.value` = the
/// valence; `query_index` is `UINT64_MAX`). `*tangent_plane_continuous` is
/// written only on success.
///
/// # Safety
/// `entry` is NULL or points to a readable entry; `tangent_plane_continuous`
/// and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_weights_check(
    entry: *const CcssWeightEntry,
    tangent_plane_continuous: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { handle(entry, "entry") }?;
        nonnull(
            tangent_plane_continuous as *const c_int,
            "tangent_plane_continuous",
        )?;
        let mut w = Weights::STANDARD;
        set_entry(&mut w, e)?;
        let tpc = w.tangent_plane_continuous(e.valence as usize);
        // SAFETY: checked above.
        unsafe {
            put(
                tangent_plane_continuous,
                "tangent_plane_continuous",
                c_int::from(tpc),
            )
        }
    })
}

/// Facts about the eigen table of one valence `n` (`ccss_tables_valence_info`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssValenceInfo {
    /// The valence `n`.
    pub valence: u32,
    /// Control points of an extraordinary patch, `2n + 8`.
    pub num_points: u32,
    /// The vertex rule the table was built for (see `ccss_weight_entry`).
    pub alpha: f64,
    /// See `alpha`.
    pub beta: f64,
    /// See `alpha`.
    pub gamma: f64,
    /// The subdominant eigenvalue of the local subdivision matrix (largest
    /// modulus below 1; for a complex pair, its modulus).
    pub subdominant: f64,
    /// 1 if the rule is tangent-plane continuous at this valence
    /// (`|lambda_0| < lambda_2`, see `ccss_weights_check`), else 0.
    pub tangent_plane_continuous: c_int,
    /// 1 if the frequency-0 eigenvalues are a complex pair (possible with
    /// general weights), else 0.
    pub complex_pair: c_int,
    /// Limit-point weight of the extraordinary vertex itself (the left
    /// eigenvector of eigenvalue 1, report eq. 2.7): the limit position of a
    /// vertex whose faces are all quads is
    /// `limit_v V + limit_e sum(E_i) + limit_f sum(F_i)`.
    pub limit_v: f64,
    /// Limit-point weight of each of the `n` edge neighbours.
    pub limit_e: f64,
    /// Limit-point weight of each of the `n` face-diagonal vertices.
    pub limit_f: f64,
}

/// Writes to `*out` facts about the eigen table of valence `valence`: its
/// vertex rule, subdominant eigenvalue, tangent-plane continuity, complex
/// pair, and limit-point weights.
///
/// Errors: NULL_POINTER, MISALIGNED, UNSUPPORTED_VALENCE (`valence` outside
/// `3..=ccss_max_valence`).
///
/// # Safety
/// `tables` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_valence_info(
    tables: *const CcssTables,
    valence: u32,
    out: *mut CcssValenceInfo,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let tb = unsafe { handle(tables, "tables") }?;
        nonnull(out as *const CcssValenceInfo, "out")?;
        let t = tb
            .set
            .get(valence as usize)
            .ok_or(Error::UnsupportedValence {
                vertex: u32::MAX,
                valence,
            })?;
        let (alpha, beta, gamma) = t.weights();
        let lw = t.limit_weights();
        let at = |i: usize| lw.get(i).copied().unwrap_or(f64::NAN);
        let info = CcssValenceInfo {
            valence,
            num_points: t.num_points() as u32,
            alpha,
            beta,
            gamma,
            subdominant: t.subdominant(),
            tangent_plane_continuous: c_int::from(t.tangent_plane_continuous()),
            complex_pair: c_int::from(t.has_complex_pair()),
            limit_v: at(0),
            limit_e: at(1),
            limit_f: at(2),
        };
        // SAFETY: checked above.
        unsafe { put(out, "out", info) }
    })
}

// ---------------------------------------------------------------------------
// Topology.

/// Validated half-edge topology of a closed mesh, with its own copy of the
/// positions, face sizes and indices (opaque; lives at the start of its
/// memory block).
pub struct CcssTopology {
    topo: Topology<'static>,
}

const TOPO_HEAD: usize = round8(size_of::<CcssTopology>());

/// Block layout of a topology: (bytes, positions, face sizes, indices, core).
fn topology_layout(nv: usize, face_sizes: &[u32]) -> Result<(usize, [usize; 4]), Failure> {
    // Same limits as core's build, so that nothing below can overflow.
    if nv > u32::MAX as usize / 2 {
        return Err(Failure::from(Error::InvalidArgument("too many vertices")));
    }
    let nh: u64 = face_sizes.iter().map(|&s| s as u64).sum();
    if nh >= (u32::MAX / 16) as u64 || face_sizes.len() >= (u32::MAX / 16) as usize {
        return Err(Failure::from(Error::InvalidArgument("mesh too large")));
    }
    let nh = nh as usize;
    let pos = TOPO_HEAD;
    let sizes = pos + round8(24 * nv);
    let idx = sizes + round8(4 * face_sizes.len());
    let core = idx + round8(4 * nh);
    let total = core + Topology::required_bytes(nv, face_sizes);
    Ok((total, [pos, sizes, idx, core]))
}

/// Writes to `*out` the number of bytes `ccss_topology_build` needs for a mesh
/// of `num_vertices` vertices and these face sizes: the handle, copies of the
/// three input arrays, and the half-edge structure (closed form, O(faces)).
///
/// Errors: NULL_POINTER (`out`, or `face_sizes` with `num_faces > 0`),
/// MISALIGNED, INVALID_ARGUMENT (mesh too large for 32-bit indices).
///
/// # Safety
/// `face_sizes` is NULL or points to `num_faces` readable `uint32_t`; `out` is
/// NULL or points to a writable `size_t`.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_required_bytes(
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        nonnull(out as *const usize, "out")?;
        // SAFETY: forwarded caller promise.
        let sizes = unsafe { in_slice(face_sizes, num_faces, "face_sizes") }?;
        let (bytes, _) = topology_layout(num_vertices, sizes)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", bytes) }
    })
}

/// Validates a closed polygon mesh and builds its topology into `mem`.
///
/// `positions`: `3 * num_vertices` doubles (x y z per vertex); `face_sizes`:
/// the vertex count of each of the `num_faces` faces; `indices`: the
/// `num_indices` vertex indices of all faces, concatenated, counter-clockwise
/// seen from outside. `mem`: `len` bytes, 8-byte aligned, at least
/// `ccss_topology_required_bytes`. On success writes the handle (which equals
/// `mem`) to `*out`.
///
/// Errors: NULL_POINTER (`out`, an array with a non-zero count, or `mem` with
/// `len > 0`), MISALIGNED, BUFFER_TOO_SMALL (`detail.required` = bytes; mesh
/// validation errors come first), INVALID_ARGUMENT, and every mesh error:
/// EMPTY_MESH, INDEX_COUNT_MISMATCH, INDEX_OUT_OF_RANGE, FACE_TOO_SMALL,
/// FACE_TOO_LARGE, REPEATED_VERTEX, NON_FINITE_COORDINATE, NON_MANIFOLD_EDGE,
/// INCONSISTENT_ORIENTATION, NON_MANIFOLD_VERTEX, BOUNDARY_EDGE,
/// UNSUPPORTED_VALENCE, with the face / vertex / edge in `*detail` (may be
/// NULL). On failure `*out` is not written and `mem`'s contents are
/// unspecified.
///
/// Ownership: the three input arrays are copied into `mem` and may be freed
/// as soon as this returns. The caller owns `mem`: the handle is valid while
/// `mem` stays allocated, unmoved and unmodified; nothing to destroy.
///
/// # Safety
/// Each array pointer is NULL or points to its count of readable elements;
/// `mem` is NULL or points to `len` writable bytes not otherwise in use and
/// not overlapping the input arrays; `out` / `detail` are NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ccss_topology_build(
    positions: *const f64,
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    indices: *const u32,
    num_indices: usize,
    mem: *mut c_void,
    len: usize,
    out: *mut *const CcssTopology,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        nonnull(out as *const *const CcssTopology, "out")?;
        if num_vertices > u32::MAX as usize / 2 {
            return Err(Failure::from(Error::InvalidArgument("too many vertices")));
        }
        let np = 3 * num_vertices;
        // SAFETY: forwarded caller promises (counts of readable elements).
        let (p, s, i) = unsafe {
            (
                in_slice(positions, np, "positions")?,
                in_slice(face_sizes, num_faces, "face_sizes")?,
                in_slice(indices, num_indices, "indices")?,
            )
        };
        // Core's checks that need no memory (in core's order): a build into an
        // empty arena either fails on the mesh or asks for memory.
        let input = MeshInput {
            positions: p,
            face_sizes: s,
            indices: i,
        };
        match Topology::build(input, &mut []) {
            Err(Error::BufferTooSmall { .. }) | Ok(_) => {}
            Err(e) => return Err(e.into()),
        }
        let (total, [o_pos, o_sizes, o_idx, o_core]) = topology_layout(num_vertices, s)?;
        let base = check_block(mem, len, total)?;
        let (mb, ml) = (base as *const u8, len);
        if overlaps(mb, ml, p.as_ptr() as *const u8, 8 * p.len())
            || overlaps(mb, ml, s.as_ptr() as *const u8, 4 * s.len())
            || overlaps(mb, ml, i.as_ptr() as *const u8, 4 * i.len())
        {
            return Err(Failure::invalid("mem overlaps an input array"));
        }
        // SAFETY: `base` is 8-aligned with `total <= len` writable bytes, split
        // into disjoint regions at the offsets of `topology_layout` (each a
        // multiple of 8, large enough for its array; index count == sum of the
        // face sizes was checked by core above). The regions outlive the
        // handle by the C-side contract, hence 'static.
        unsafe {
            let cp = base.add(o_pos) as *mut f64;
            let cs = base.add(o_sizes) as *mut u32;
            let ci = base.add(o_idx) as *mut u32;
            ptr::copy_nonoverlapping(p.as_ptr(), cp, p.len());
            ptr::copy_nonoverlapping(s.as_ptr(), cs, s.len());
            ptr::copy_nonoverlapping(i.as_ptr(), ci, i.len());
            let mesh = MeshInput {
                positions: core::slice::from_raw_parts(cp, p.len()),
                face_sizes: core::slice::from_raw_parts(cs, s.len()),
                indices: core::slice::from_raw_parts(ci, i.len()),
            };
            let arena = block_words(base, o_core, total);
            let topo = Topology::build(mesh, arena)?;
            let h = base as *mut CcssTopology;
            h.write(CcssTopology { topo });
            *out = h;
        }
        Ok(())
    })
}

/// Writes the number of vertices (including unused ones) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_vertex_count(
    topo: *const CcssTopology,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", handle(topo, "topo")?.topo.num_vertices()) }
    })
}

/// Writes the number of faces to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_face_count(
    topo: *const CcssTopology,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", handle(topo, "topo")?.topo.num_faces()) }
    })
}

/// Writes the number of (undirected) edges to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_edge_count(
    topo: *const CcssTopology,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", handle(topo, "topo")?.topo.num_edges()) }
    })
}

/// Writes the number of vertices of face `face` to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_face_size(
    topo: *const CcssTopology,
    face: u32,
    out: *mut u32,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { handle(topo, "topo") }?;
        nonnull(out as *const u32, "out")?;
        if face as usize >= t.topo.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", t.topo.face_size(face as usize) as u32) }
    })
}

// ---------------------------------------------------------------------------
// Evaluator.

/// Patch table of one mesh for exact evaluation (opaque; lives at the start
/// of its memory block). Refers to its `ccss_tables`, not to the topology.
pub struct CcssEvaluator {
    ev: Evaluator<'static>,
}

const EVAL_HEAD: usize = round8(size_of::<CcssEvaluator>());

/// Writes to `*out` the number of bytes `ccss_evaluator_build` needs for this
/// topology and tables.
///
/// Errors: NULL_POINTER, MISALIGNED, MISSING_TABLE (a valence of the mesh has
/// no table; not with standard tables), INVALID_ARGUMENT; details in
/// `*detail` (may be NULL).
///
/// # Safety
/// `topo`, `tables` are NULL or live handles; `out`, `detail` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_required_bytes(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (t, tb) = unsafe { (handle(topo, "topo")?, handle(tables, "tables")?) };
        nonnull(out as *const usize, "out")?;
        let total = evaluator_bytes(t, tb)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Builds the evaluator (patch table) of `topo` into `mem` (`len` bytes,
/// 8-byte aligned, at least `ccss_evaluator_required_bytes`) and writes the
/// handle (which equals `mem`) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// bytes), MISSING_TABLE, INVALID_ARGUMENT; details in `*detail` (may be
/// NULL). On failure `*out` is not written and `mem`'s contents are
/// unspecified.
///
/// Ownership: the caller owns `mem`. The evaluator refers to the tables, which
/// must stay alive (allocated, unmoved, unmodified) as long as it is used; it
/// does NOT refer to the topology, whose block may be freed right after this
/// call. Nothing to destroy: free `mem` when done.
///
/// # Safety
/// `topo`, `tables` are NULL or live handles; `mem` is NULL or points to
/// `len` writable bytes not otherwise in use (not the topology's or tables'
/// blocks); `out`, `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_build(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    mem: *mut c_void,
    len: usize,
    out: *mut *const CcssEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the tables outlive the evaluator
        // by the C-side contract, hence 'static.
        let (t, tb): (&CcssTopology, &'static CcssTables) =
            unsafe { (handle(topo, "topo")?, handle(tables, "tables")?) };
        nonnull(out as *const *const CcssEvaluator, "out")?;
        let total = evaluator_bytes(t, tb)?;
        let base = check_block(mem, len, total)?;
        // SAFETY: `base` is 8-aligned with `len >= total` writable bytes: the
        // handle at 0, the core arena after it; 'static by the C contract.
        unsafe {
            let arena = block_words(base, EVAL_HEAD, len);
            let ev = Evaluator::build(&t.topo, &tb.set, arena)?;
            let h = base as *mut CcssEvaluator;
            h.write(CcssEvaluator { ev });
            *out = h;
        }
        Ok(())
    })
}

/// Writes the number of base faces to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_face_count(
    ev: *const CcssEvaluator,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", handle(ev, "ev")?.ev.num_faces()) }
    })
}

/// Writes the number of sub-faces of base face `face` to `*out`: 1 for a
/// quad, N for an N-gon (sub-face k is the quad at corner k after one
/// Catmull-Clark step, with its own (u, v)).
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_subface_count(
    ev: *const CcssEvaluator,
    face: u32,
    out: *mut u32,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { handle(ev, "ev") }?;
        nonnull(out as *const u32, "out")?;
        if face as usize >= e.ev.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", e.ev.num_subfaces(face as usize) as u32) }
    })
}

/// Writes the number of regular (bicubic) and extraordinary patches of the
/// patch table to `*regular` and `*extraordinary`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `regular`, `extraordinary` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_patch_counts(
    ev: *const CcssEvaluator,
    regular: *mut usize,
    extraordinary: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { handle(ev, "ev") }?;
        nonnull(regular as *const usize, "regular")?;
        nonnull(extraordinary as *const usize, "extraordinary")?;
        let (r, x) = e.ev.patch_counts();
        // SAFETY: checked above.
        unsafe {
            regular.write(r);
            extraordinary.write(x);
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------
// Evaluation.

/// One evaluation result. Derivatives are with respect to the (sub-)face's
/// own (u, v); `normal` is `normalize(du x dv)` (zero where that vanishes; at
/// an extraordinary vertex the limit normal). Second derivatives are zero
/// unless requested.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssEvalResult {
    /// Position.
    pub p: [f64; 3],
    /// dS/du.
    pub du: [f64; 3],
    /// dS/dv.
    pub dv: [f64; 3],
    /// d2S/du2.
    pub duu: [f64; 3],
    /// d2S/dudv.
    pub duv: [f64; 3],
    /// d2S/dv2.
    pub dvv: [f64; 3],
    /// Unit normal.
    pub normal: [f64; 3],
}

impl From<Eval> for CcssEvalResult {
    fn from(e: Eval) -> Self {
        let a = |d: DVec3| [d.x, d.y, d.z];
        CcssEvalResult {
            p: a(e.p),
            du: a(e.du),
            dv: a(e.dv),
            duu: a(e.duu),
            duv: a(e.duv),
            dvv: a(e.dvv),
            normal: a(e.normal),
        }
    }
}

/// One query of a batch: base face, sub-face (0 for quads), parameters in
/// `[0, 1]`. Same layout as ccss-core's `evaluator::Query`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssQuery {
    /// Base face index.
    pub face: u32,
    /// Sub-face index (0 for quads, 0..N-1 for N-gons).
    pub sub: u32,
    /// Parameter u in [0, 1].
    pub u: f64,
    /// Parameter v in [0, 1].
    pub v: f64,
}

// Layout and drop assumptions, checked at compile time.
const _: () = {
    assert!(size_of::<CcssQuery>() == size_of::<Query>());
    assert!(align_of::<CcssQuery>() == align_of::<Query>());
    assert!(offset_of!(CcssQuery, face) == offset_of!(Query, face));
    assert!(offset_of!(CcssQuery, sub) == offset_of!(Query, sub));
    assert!(offset_of!(CcssQuery, u) == offset_of!(Query, u));
    assert!(offset_of!(CcssQuery, v) == offset_of!(Query, v));
    assert!(align_of::<CcssTables>() <= 8 && align_of::<BuildScratch>() <= 8);
    assert!(align_of::<CcssTopology>() <= 8 && align_of::<CcssEvaluator>() <= 8);
    // Blocks are simply freed by C: nothing may need dropping.
    assert!(!needs_drop::<CcssTables>() && !needs_drop::<BuildScratch>());
    assert!(!needs_drop::<CcssTopology>() && !needs_drop::<CcssEvaluator>());
};

/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
unsafe fn eval_one(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    second: bool,
    out: *mut CcssEvalResult,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { handle(ev, "ev") }?;
        nonnull(out as *const CcssEvalResult, "out")?;
        let r = if second {
            e.ev.eval_second(face, sub, u, v)?
        } else {
            e.ev.eval(face, sub, u, v)?
        };
        // SAFETY: checked above.
        unsafe { put(out, "out", r.into()) }
    })
}

/// Evaluates position, first derivatives and normal at (u, v) of sub-face
/// `sub` (0 for quads) of base face `face` into `*out` (second derivatives
/// are set to zero). Quad parameterisation: (0,0) at the face's vertex 0,
/// (1,0) at vertex 1, (1,1) at vertex 2, (0,1) at vertex 3.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE,
/// SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE (u or v NaN or outside
/// [0, 1]). `*out` is written only on success. Use `ccss_eval_batch` for an
/// error detail.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_eval(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvalResult,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(ev, face, sub, u, v, false, out) }
}

/// As `ccss_eval`, plus second derivatives (`duu`, `duv`, `dvv`).
///
/// Errors: as `ccss_eval`.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_eval_second(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvalResult,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(ev, face, sub, u, v, true, out) }
}

/// Evaluates `count` queries into `out[0..count]` (`out_len` elements
/// available), with second derivatives when `second` is non-zero.
///
/// All queries are validated before anything is written: on the first bad
/// query the function fails with its status and `detail.query_index` (plus
/// `face` / `value` = sub-face) and `out` is untouched.
///
/// Errors: NULL_POINTER (`ev`; `queries` or `out` with a non-zero count),
/// MISALIGNED, BUFFER_TOO_SMALL (`out_len < count`; `detail.required` =
/// `count` elements), INVALID_ARGUMENT (`out` overlaps `queries`),
/// FACE_OUT_OF_RANGE, SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `queries` is NULL or points to `count`
/// readable queries; `out` is NULL or points to `out_len` writable results;
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_eval_batch(
    ev: *const CcssEvaluator,
    queries: *const CcssQuery,
    count: usize,
    second: c_int,
    out: *mut CcssEvalResult,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { handle(ev, "ev") }?;
        // SAFETY: forwarded caller promise.
        let qs = unsafe { in_slice(queries, count, "queries") }?;
        if out.is_null() && out_len != 0 {
            return Err(Failure::null("out"));
        }
        if out_len < count {
            return Err(Failure::too_small(count));
        }
        if count == 0 {
            return Ok(());
        }
        nonnull(out as *const CcssEvalResult, "out")?;
        let res_bytes = count.saturating_mul(size_of::<CcssEvalResult>());
        if overlaps(
            qs.as_ptr() as *const u8,
            count * size_of::<CcssQuery>(),
            out as *const u8,
            res_bytes,
        ) {
            return Err(Failure::invalid("out overlaps queries"));
        }
        for (i, q) in qs.iter().enumerate() {
            let cq = Query {
                face: q.face,
                sub: q.sub,
                u: q.u,
                v: q.v,
            };
            if let Err(err) = e.ev.check(&cq) {
                let mut f = Failure::from(err);
                f.query_index = Some(i as u64);
                return Err(f);
            }
        }
        for (i, q) in qs.iter().enumerate() {
            let r = if second != 0 {
                e.ev.eval_second(q.face, q.sub, q.u, q.v)
            } else {
                e.ev.eval(q.face, q.sub, q.u, q.v)
            };
            let r = r.map_err(|err| {
                let mut f = Failure::from(err);
                f.query_index = Some(i as u64);
                f
            })?;
            // SAFETY: `out` is non-NULL, aligned, with `out_len >= count`
            // writable elements not overlapping `queries`.
            unsafe { out.add(i).write(r.into()) };
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------
// Subdivision depth.

/// Which bound `ccss_depths` uses for extraordinary patches (Cheng & Lai
/// report, ch. 3). Regular patches always use Lemma 1
/// (`depth = ceil(log4(M / (3 eps)))`). The numeric values are stable ABI.
///
/// Functions take the method as a `uint32_t` (any value is safe to pass;
/// values that are not a `ccss_depth_method` fail with
/// `CCSS_ERR_INVALID_ARGUMENT`).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssDepthMethod {
    /// Theorem 6 (Lemmas 2-5: rate `r_old`, constant `c_old`). Standard
    /// Catmull-Clark weights only: with tables of a general rule that changes
    /// a valence of the mesh, `ccss_depths` fails with INVALID_ARGUMENT.
    DEPTH_OLD = 0,
    /// Theorem 11 (the matrix technique: rates `r1`, `r2`, constant `c_new`).
    DEPTH_NEW = 1,
    /// The smallest valid depth of all methods (OLD where it applies, NEW and
    /// TIGHT).
    DEPTH_BEST = 2,
    /// Theorem 11's constant with the measured second-order norms of the
    /// exactly subdivided control points at each level instead of the
    /// estimate `M_i <= r_i M_0`; never larger than NEW.
    DEPTH_TIGHT = 3,
}

impl CcssDepthMethod {
    /// The method of a C value (`None` if it is not one).
    fn from_raw(v: u32) -> Option<CcssDepthMethod> {
        match v {
            0 => Some(CcssDepthMethod::DEPTH_OLD),
            1 => Some(CcssDepthMethod::DEPTH_NEW),
            2 => Some(CcssDepthMethod::DEPTH_BEST),
            3 => Some(CcssDepthMethod::DEPTH_TIGHT),
            _ => None,
        }
    }

    fn core(self) -> Method {
        match self {
            CcssDepthMethod::DEPTH_OLD => Method::Old,
            CcssDepthMethod::DEPTH_NEW => Method::New,
            CcssDepthMethod::DEPTH_BEST => Method::Best,
            CcssDepthMethod::DEPTH_TIGHT => Method::Tight,
        }
    }
}

/// Writes to `*out` the number of (face, sub-face) slots of the evaluator:
/// one per quad, N per N-gon. This is the number of depths `ccss_depths`
/// writes (the size query of its output array).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_slot_count(
    ev: *const CcssEvaluator,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", handle(ev, "ev")?.ev.num_slots()) }
    })
}

/// Writes to `*out` the first slot of base face `face`: the depths of face
/// `face` are at `slot_start .. slot_start + n` of the `ccss_depths` array,
/// `n` its sub-face count (`ccss_evaluator_subface_count`; slots are faces in
/// order, the sub-faces of an N-gon consecutively).
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_slot_start(
    ev: *const CcssEvaluator,
    face: u32,
    out: *mut usize,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { handle(ev, "ev") }?;
        nonnull(out as *const usize, "out")?;
        if face as usize >= e.ev.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", e.ev.slot_start(face as usize)) }
    })
}

/// Subdivision depth for tolerance `eps` (Cheng & Lai report, ch. 3): writes
/// to `out[s]`, for every slot `s` (see `ccss_evaluator_slot_count`,
/// `ccss_evaluator_slot_start`), the number of uniform Catmull-Clark steps of
/// the base mesh after which every control face of that (sub-)face lies
/// within `eps` of the limit surface (the bilinear control faces against the
/// limit patch). `method` is a `ccss_depth_method`. A slot for which the
/// method gives no bound (e.g. NEW where a general rule has `r2 >= 1`) gets
/// `UINT32_MAX`.
///
/// Checks, in this order: NULL_POINTER / MISALIGNED (`ev`),
/// INVALID_ARGUMENT (`method` not a `ccss_depth_method`; `eps` not positive
/// and finite), NULL_POINTER (`out` with `out_len > 0`), BUFFER_TOO_SMALL
/// (`out_len` below the slot count; `detail.required` = the slot count),
/// MISALIGNED (`out`), then INVALID_ARGUMENT (CCSS_DEPTH_OLD with tables whose
/// rule is not standard at a valence of the mesh) and MISSING_TABLE. `out` is
/// written only on success. No allocation.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or points to `out_len`
/// writable `uint32_t`; `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_depths(
    ev: *const CcssEvaluator,
    eps: f64,
    method: u32,
    out: *mut u32,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { handle(ev, "ev") }?;
        let method = CcssDepthMethod::from_raw(method).ok_or(Failure::invalid(
            "method is not a ccss_depth_method (0..=3)",
        ))?;
        if !(eps.is_finite() && eps > 0.0) {
            return Err(Failure::invalid("eps must be positive and finite"));
        }
        if out.is_null() && out_len != 0 {
            return Err(Failure::null("out"));
        }
        let ns = e.ev.num_slots();
        if out_len < ns {
            return Err(Failure::too_small(ns));
        }
        if ns == 0 {
            // Not produced by core (meshes have faces); nothing to write.
            return Ok(());
        }
        nonnull(out as *const u32, "out")?;
        if ns
            .checked_mul(size_of::<u32>())
            .map_or(true, |b| b > isize::MAX as usize)
        {
            return Err(Failure::invalid("array length too large"));
        }
        // SAFETY: non-NULL, aligned, and the caller promises `out_len >= ns`
        // writable elements; only the first `ns` are viewed. Core validates
        // everything before it writes (nothing written on failure).
        let dst = unsafe { core::slice::from_raw_parts_mut(out, ns) };
        ccss_core::bounds::depth::depths(&e.ev, eps, method.core(), dst)?;
        Ok(())
    })
}

/// The subdivision-depth constants of one valence `n`, filled by
/// `ccss_depth_rates` (Cheng & Lai report, ch. 3; the type cannot share the
/// function's name in C). `A` is the group-I second-order-difference
/// matrix of the 1-ring (2n x (2n+1)) and `Lambda` the 1-ring subdivision
/// matrix of the table's vertex rule.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssDepthRatesInfo {
    /// The valence `n`.
    pub valence: u32,
    /// `r1 = ||A Lambda A^+||_inf` (report Table 2).
    pub r1: f64,
    /// `r2 = ||A Lambda^2 A^+||_inf` (report Table 2).
    pub r2: f64,
    /// Theorem 11's constant: the supremum over m of the bound (3.17) per
    /// unit second-order norm (0 when `r2 >= 1`: no bound).
    pub c_new: f64,
    /// The report's Lemma 10 constant `(1 + r1) / (min(n,8) (1 - r2))`, the
    /// m -> infinity limit of `c_new` (smaller than `c_new` for n = 8; 0 when
    /// `r2 >= 1`).
    pub c_lemma10: f64,
    /// Lemma 2's rate of the old technique (Theorem 6); 0 when the table's
    /// rule is not standard at this valence (the old technique does not
    /// apply).
    pub r_old: f64,
    /// Lemma 5's constant of the old technique; 0 when it does not apply.
    pub c_old: f64,
}

impl From<&Rates> for CcssDepthRatesInfo {
    fn from(r: &Rates) -> Self {
        CcssDepthRatesInfo {
            valence: r.n as u32,
            r1: r.r1,
            r2: r.r2,
            c_new: r.c_new,
            c_lemma10: r.c_lemma10,
            r_old: r.r_old,
            c_old: r.c_old,
        }
    }
}

/// Writes to `*out` the subdivision-depth constants of valence `valence` for
/// the vertex rule of `tables` (computed when the tables were built).
///
/// Errors: NULL_POINTER, MISALIGNED, UNSUPPORTED_VALENCE (`valence` outside
/// `3..=ccss_max_valence`). `*out` is written only on success.
///
/// # Safety
/// `tables` is NULL or a live handle; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_depth_rates(
    tables: *const CcssTables,
    valence: u32,
    out: *mut CcssDepthRatesInfo,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let tb = unsafe { handle(tables, "tables") }?;
        nonnull(out as *const CcssDepthRatesInfo, "out")?;
        let t = tb
            .set
            .get(valence as usize)
            .ok_or(Error::UnsupportedValence {
                vertex: u32::MAX,
                valence,
            })?;
        let mut r = CcssDepthRatesInfo::from(t.rates());
        r.valence = valence;
        // SAFETY: checked above.
        unsafe { put(out, "out", r) }
    })
}

/// Counts heap allocations per thread, to prove the FFI paths allocate nothing.
#[cfg(test)]
mod alloc_count {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        pub static COUNT: Cell<usize> = const { Cell::new(0) };
    }

    pub struct Counting;

    // SAFETY: forwards to the system allocator.
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, l: Layout) -> *mut u8 {
            let _ = COUNT.try_with(|c| c.set(c.get() + 1));
            // SAFETY: same contract as ours.
            unsafe { System.alloc(l) }
        }
        unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
            // SAFETY: same contract as ours.
            unsafe { System.dealloc(p, l) }
        }
    }

    #[global_allocator]
    static A: Counting = Counting;

    pub fn get() -> usize {
        COUNT.with(|c| c.get())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> ([f64; 24], [u32; 6], [u32; 24]) {
        (
            [
                -1., -1., -1., 1., -1., -1., 1., 1., -1., -1., 1., -1., -1., -1., 1., 1., -1., 1.,
                1., 1., 1., -1., 1., 1.,
            ],
            [4; 6],
            [
                0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
            ],
        )
    }

    fn block(bytes: usize) -> Vec<u64> {
        vec![0u64; bytes.div_ceil(8)]
    }

    #[test]
    fn build_eval_and_errors_do_not_allocate() {
        let (p, s, i) = cube();
        let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
        let mut d = Failure::invalid("x").to_detail();
        unsafe {
            assert_eq!(ccss_tables_required_bytes(&mut tb), CcssStatus::OK);
            assert_eq!(
                ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb),
                CcssStatus::OK
            );
        }
        let b = alloc_count::get();
        let probe = std::hint::black_box(vec![1u8]);
        assert!(alloc_count::get() > b, "the allocation counter counts");
        drop(probe);
        let mut tmem = block(tb);
        let mut gmem = block(gb);
        let mut bad = i;
        bad[5] = 7; // face 1 = 4 7 6 7: repeated vertex
        let mut tables = ptr::null();
        let mut topo = ptr::null();
        let mut ev = ptr::null();
        let before = alloc_count::get();
        unsafe {
            let st = ccss_tables_build_standard(tmem.as_mut_ptr().cast(), tb, &mut tables);
            assert_eq!(st, CcssStatus::OK);
            let st = ccss_topology_build(
                p.as_ptr(),
                8,
                s.as_ptr(),
                6,
                bad.as_ptr(),
                24,
                gmem.as_mut_ptr().cast(),
                gb,
                &mut topo,
                &mut d,
            );
            assert_eq!(st, CcssStatus::ERR_REPEATED_VERTEX);
            assert_eq!((d.face, d.vertex), (1, 7));
            let st = ccss_topology_build(
                p.as_ptr(),
                8,
                s.as_ptr(),
                6,
                i.as_ptr(),
                24,
                gmem.as_mut_ptr().cast(),
                gb,
                &mut topo,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(
                ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d),
                CcssStatus::OK
            );
        }
        assert_eq!(alloc_count::get(), before, "tables / topology allocated");
        let mut emem = block(eb);
        let qs = [
            CcssQuery {
                face: 0,
                sub: 0,
                u: 0.5,
                v: 0.5,
            },
            CcssQuery {
                face: 1,
                sub: 0,
                u: 0.0,
                v: 0.25,
            },
        ];
        let mut res = [CcssEvalResult::default(); 2];
        let mut r = CcssEvalResult::default();
        let before = alloc_count::get();
        unsafe {
            let st =
                ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(ccss_eval(ev, 0, 0, 0.5, 0.5, &mut r), CcssStatus::OK);
            assert!((r.p[2] + 68.0 / 81.0).abs() < 1e-12);
            assert_eq!(
                ccss_eval_second(ev, 0, 0, 0.5, f64::NAN, &mut r),
                CcssStatus::ERR_PARAMETER_OUT_OF_RANGE
            );
            let st = ccss_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 2, &mut d);
            assert_eq!(st, CcssStatus::OK);
            let st = ccss_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 1, &mut d);
            assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 2));
            let mut buf = [0 as c_char; 64];
            assert!(ccss_error_detail_format(&d, buf.as_mut_ptr(), 64) > 0);
        }
        assert_eq!(alloc_count::get(), before, "evaluator / eval allocated");
        drop((tmem, gmem, emem));
    }

    fn msg(d: &CcssErrorDetail) -> String {
        let b: Vec<u8> = d
            .message
            .iter()
            .take_while(|&&c| c != 0)
            .map(|&c| c as u8)
            .collect();
        String::from_utf8(b).unwrap()
    }

    fn entry(valence: u32, alpha: f64, beta: f64, gamma: f64) -> CcssWeightEntry {
        CcssWeightEntry {
            valence,
            alpha,
            beta,
            gamma,
        }
    }

    #[test]
    fn weighted_tables_build_eval_and_info() {
        let (p, s, i) = cube();
        let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
        let mut d = Failure::invalid("x").to_detail();
        let (a, b, g) = (0.5, 0.3, 0.2);
        let mut maxv = 0usize;
        unsafe {
            assert_eq!(ccss_max_valence(&mut maxv), CcssStatus::OK);
            assert_eq!(ccss_tables_required_bytes(&mut tb), CcssStatus::OK);
            assert_eq!(
                ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb),
                CcssStatus::OK
            );
        }
        let entries: Vec<CcssWeightEntry> = (3..=maxv as u32)
            .filter(|&n| n != 4)
            .map(|n| entry(n, a, b, g))
            .collect();
        let mut tmem = block(tb);
        let mut gmem = block(gb);
        let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
        let mut info = CcssValenceInfo::default();
        let mut r = CcssEvalResult::default();
        let before = alloc_count::get();
        unsafe {
            let st = ccss_tables_build(
                entries.as_ptr(),
                entries.len(),
                tmem.as_mut_ptr().cast(),
                tb,
                &mut tables,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(
                ccss_tables_valence_info(tables, 3, &mut info),
                CcssStatus::OK
            );
            let st = ccss_topology_build(
                p.as_ptr(),
                8,
                s.as_ptr(),
                6,
                i.as_ptr(),
                24,
                gmem.as_mut_ptr().cast(),
                gb,
                &mut topo,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(
                ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d),
                CcssStatus::OK
            );
        }
        assert_eq!(alloc_count::get(), before, "weighted tables allocated");
        // Valence 3: the rule, 2n+8 points, and the limit mask of eq. 2.7,
        // (5 V + (12b+8g) Ebar + (2b+8g) Fbar) / (5+14b+16g).
        let den = 5.0 + 14.0 * b + 16.0 * g;
        assert_eq!((info.valence, info.num_points), (3, 14));
        assert_eq!((info.alpha, info.beta, info.gamma), (a, b, g));
        assert!((info.limit_v - 5.0 / den).abs() < 1e-13, "{info:?}");
        assert!((info.limit_e - (12.0 * b + 8.0 * g) / (3.0 * den)).abs() < 1e-13);
        assert!((info.limit_f - (2.0 * b + 8.0 * g) / (3.0 * den)).abs() < 1e-13);
        assert!((info.limit_v + 3.0 * info.limit_e + 3.0 * info.limit_f - 1.0).abs() < 1e-13);
        let w = {
            let mut w = Weights::STANDARD;
            w.set(3, a, b, g).unwrap();
            w
        };
        assert_eq!(
            info.tangent_plane_continuous,
            w.tangent_plane_continuous(3) as c_int
        );
        // x^2 - (a - 1/4) x + (1 - 2b)/16 has complex roots of modulus
        // sqrt(1/40) < lambda_2(3), which stays subdominant.
        assert_eq!(info.complex_pair, 1);
        assert!(
            (info.subdominant - Weights::lambda2(3)).abs() < 1e-12,
            "{info:?}"
        );
        unsafe {
            assert_eq!(
                ccss_tables_valence_info(tables, 4, &mut info),
                CcssStatus::OK
            );
            assert_eq!((info.alpha, info.beta, info.gamma), (0.5625, 0.375, 0.0625));
            assert!((info.limit_v - 16.0 / 36.0).abs() < 1e-14);
            assert!((info.limit_e - 4.0 / 36.0).abs() < 1e-14);
            assert!((info.limit_f - 1.0 / 36.0).abs() < 1e-14);
            assert_eq!((info.tangent_plane_continuous, info.complex_pair), (1, 0));
            let keep = info;
            for bad in [0u32, 2, maxv as u32 + 1, u32::MAX] {
                assert_eq!(
                    ccss_tables_valence_info(tables, bad, &mut info),
                    CcssStatus::ERR_UNSUPPORTED_VALENCE
                );
            }
            assert_eq!(info, keep, "written on failure");
        }
        // Evaluation uses the rule: corner v0 of the cube (face 0, u=v=0),
        // E = v1 v3 v4, F = v2 v5 v7: 5 V + (12b+8g) Ebar + (2b+8g) Fbar,
        // where Ebar = V/3 and Fbar = -V/3 (V = (-1, -1, -1)).
        let mut emem = block(eb);
        unsafe {
            let st =
                ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(ccss_eval(ev, 0, 0, 0.0, 0.0, &mut r), CcssStatus::OK);
        }
        let c = (-5.0 - (12.0 * b + 8.0 * g) / 3.0 + (2.0 * b + 8.0 * g) / 3.0) / den;
        for k in 0..3 {
            assert!((r.p[k] - c).abs() < 1e-13, "{:?} vs {c}", r.p);
        }
        // Differs from the standard corner (-1/2).
        assert!((c + 0.5).abs() > 1e-3);
        drop((tmem, gmem, emem));
    }

    #[test]
    fn weight_errors_name_the_entry_and_write_nothing() {
        let mut tb = 0usize;
        unsafe { ccss_tables_required_bytes(&mut tb) };
        let mut tmem = block(tb);
        let sentinel = 0x5a5a_5a5a_5a5a_5a5au64;
        tmem.iter_mut().for_each(|x| *x = sentinel);
        let out_before = 8usize as *const CcssTables;
        let cases: [(Vec<CcssWeightEntry>, CcssStatus, u64, i64, &str); 7] = [
            (
                vec![entry(3, 0.5, 0.3, 0.2), entry(4, 0.5, 0.3, 0.2)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                1,
                4,
                "entry 1: weights for valence 4 rejected: valence 4 must keep the standard rule",
            ),
            (
                vec![entry(5, 0.5, -0.1, 0.6)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                0,
                5,
                "entry 0: weights for valence 5 rejected: a weight is negative",
            ),
            (
                vec![entry(3, 0.5, 0.3, 0.2), entry(6, 0.5, 0.3, 0.3)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                1,
                6,
                "alpha + beta + gamma is not 1",
            ),
            (
                vec![entry(3, f64::NAN, 0.3, 0.2)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                0,
                3,
                "NaN or infinite",
            ),
            (
                vec![entry(2, 0.5, 0.3, 0.2)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                0,
                2,
                "valence outside",
            ),
            (
                vec![entry(u32::MAX, 0.5, 0.3, 0.2)],
                CcssStatus::ERR_INVALID_WEIGHTS,
                0,
                u32::MAX as i64,
                "valence outside",
            ),
            (
                vec![
                    entry(3, 0.5, 0.3, 0.2),
                    entry(5, 0.5, 0.3, 0.2),
                    entry(3, 0.5, 0.3, 0.2),
                ],
                CcssStatus::ERR_INVALID_ARGUMENT,
                2,
                3,
                "entry 2: invalid argument: valence 3 is listed twice (first in entry 0)",
            ),
        ];
        for (es, want, idx, val, text) in cases {
            let mut d = Failure::invalid("x").to_detail();
            let mut out = out_before;
            // Also with a too-small block: the entries are checked first.
            for len in [tb, 16] {
                let before = alloc_count::get();
                let st = unsafe {
                    ccss_tables_build(
                        es.as_ptr(),
                        es.len(),
                        tmem.as_mut_ptr().cast(),
                        len,
                        &mut out,
                        &mut d,
                    )
                };
                assert_eq!(alloc_count::get(), before, "error path allocated");
                assert_eq!(st, want, "{es:?}");
                assert_eq!(d.status, want);
                assert_eq!((d.query_index, d.value, d.vertex), (idx, val, -1), "{es:?}");
                assert!(msg(&d).contains(text), "{}", msg(&d));
            }
            assert_eq!(out, out_before, "out written on failure");
            assert!(
                tmem.iter().all(|&x| x == sentinel),
                "mem written on failure"
            );
        }
        // Pointer errors.
        let mut d = Failure::invalid("x").to_detail();
        let mut out = ptr::null();
        unsafe {
            let st = ccss_tables_build(
                ptr::null(),
                1,
                tmem.as_mut_ptr().cast(),
                tb,
                &mut out,
                &mut d,
            );
            assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
            assert!(msg(&d).contains("`entries`"));
            let es = [entry(3, 0.5, 0.3, 0.2)];
            let st = ccss_tables_build(
                es.as_ptr(),
                1,
                tmem.as_mut_ptr().cast(),
                tb,
                ptr::null_mut(),
                &mut d,
            );
            assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
            let st = ccss_tables_build(
                es.as_ptr(),
                1,
                tmem.as_mut_ptr().cast(),
                16,
                &mut out,
                &mut d,
            );
            assert_eq!(
                (st, d.required),
                (CcssStatus::ERR_BUFFER_TOO_SMALL, tb as u64)
            );
            // No entries: the standard tables.
            let st = ccss_tables_build(
                ptr::null(),
                0,
                tmem.as_mut_ptr().cast(),
                tb,
                &mut out,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            let mut info = CcssValenceInfo::default();
            assert_eq!(ccss_tables_valence_info(out, 5, &mut info), CcssStatus::OK);
            assert_eq!(
                (info.alpha, info.beta, info.gamma),
                ccss_core::mesh::weights::standard(5)
            );
            assert!((info.limit_v - 25.0 / 50.0).abs() < 1e-14, "{info:?}");
            assert_eq!(
                ccss_tables_valence_info(out, 5, ptr::null_mut()),
                CcssStatus::ERR_NULL_POINTER
            );
            assert_eq!(
                ccss_tables_valence_info(ptr::null(), 5, &mut info),
                CcssStatus::ERR_NULL_POINTER
            );
        }
    }

    #[test]
    fn weights_check_reports_continuity() {
        let mut d = Failure::invalid("x").to_detail();
        let mut tpc: c_int = -7;
        let mut check =
            |e: CcssWeightEntry, tpc: &mut c_int| unsafe { ccss_weights_check(&e, tpc, &mut d) };
        for n in 3..=ccss_core::MAX_VALENCE as u32 {
            let (a, b, g) = ccss_core::mesh::weights::standard(n as usize);
            assert_eq!(check(entry(n, a, b, g), &mut tpc), CcssStatus::OK);
            assert_eq!(tpc, 1, "standard rule at valence {n}");
        }
        // alpha = 0.5, beta = 0.3, gamma = 0.2 at valence 3: x^2 - x/4 + 1/40
        // has complex roots of modulus sqrt(1/40) = 0.158 < lambda_2(3) = 0.41.
        assert_eq!(check(entry(3, 0.5, 0.3, 0.2), &mut tpc), CcssStatus::OK);
        assert_eq!(tpc, 1);
        // alpha close to 1: lambda_0 close to 3/4 > lambda_2(5) ~ 0.55.
        assert_eq!(check(entry(5, 0.98, 0.01, 0.01), &mut tpc), CcssStatus::OK);
        assert_eq!(tpc, 0);
        let mut w = Weights::STANDARD;
        w.set(5, 0.98, 0.01, 0.01).unwrap();
        assert!(!w.tangent_plane_continuous(5));
        tpc = -7;
        let before = alloc_count::get();
        let st = check(entry(4, 0.5, 0.3, 0.2), &mut tpc);
        assert_eq!(alloc_count::get(), before, "ccss_weights_check allocated");
        assert_eq!(st, CcssStatus::ERR_INVALID_WEIGHTS);
        assert_eq!(tpc, -7, "written on failure");
        assert_eq!((d.value, d.query_index), (4, u64::MAX));
        assert!(
            msg(&d).starts_with("weights for valence 4 rejected"),
            "{}",
            msg(&d)
        );
        unsafe {
            let e = entry(3, 0.5, 0.3, 0.2);
            assert_eq!(
                ccss_weights_check(ptr::null(), &mut tpc, ptr::null_mut()),
                CcssStatus::ERR_NULL_POINTER
            );
            assert_eq!(
                ccss_weights_check(&e, ptr::null_mut(), ptr::null_mut()),
                CcssStatus::ERR_NULL_POINTER
            );
        }
        assert_eq!(
            CCSS_WEIGHTS_SUM_TOLERANCE,
            ccss_core::mesh::weights::SUM_TOLERANCE
        );
        let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(22)) };
        assert!(m.to_str().unwrap().contains("weights"));
    }

    #[test]
    fn panics_become_a_status() {
        let mut d = Failure::invalid("x").to_detail();
        let st = guard(&mut d, || panic!("test panic"));
        assert_eq!(st, CcssStatus::ERR_PANIC);
        assert_eq!(d.status, CcssStatus::ERR_PANIC);
        let msg: Vec<u8> = d
            .message
            .iter()
            .take_while(|&&c| c != 0)
            .map(|&c| c as u8)
            .collect();
        assert!(std::str::from_utf8(&msg).unwrap().contains("panic"));
    }

    #[test]
    fn every_message_fits() {
        // The longest core messages, with the largest numbers.
        let m = u32::MAX;
        let errs = [
            Error::IndexCountMismatch {
                expected: usize::MAX,
                got: usize::MAX,
            },
            Error::BoundaryEdge { v0: m, v1: m },
            Error::UnsupportedValence {
                vertex: m,
                valence: m,
            },
            Error::FaceTooLarge { face: m, size: m },
            Error::InconsistentOrientation { v0: m, v1: m },
            Error::InvalidWeights {
                valence: m,
                problem: ccss_core::WeightsProblem::RegularValence,
            },
        ];
        for e in errs {
            let mut f = Failure::from(e);
            f.query_index = Some(u64::MAX - 1);
            let d = f.to_detail();
            let len = d.message.iter().position(|&c| c == 0).unwrap();
            assert!(len + 1 < CCSS_ERROR_MESSAGE_CAPACITY, "{e}: {len}");
        }
    }

    #[test]
    fn truncation_is_safe() {
        let mut f = Failure::from(Error::InvalidArgument("x"));
        f.msg = Msg::Text("ééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééé");
        let d = f.to_detail();
        let n = unsafe { ccss_error_detail_format(&d, ptr::null_mut(), 0) };
        assert!(n < CCSS_ERROR_MESSAGE_CAPACITY);
        let bytes: Vec<u8> = d.message[..n].iter().map(|&c| c as u8).collect();
        assert!(std::str::from_utf8(&bytes).is_ok());
        let mut buf = [0 as c_char; 8];
        let n2 = unsafe { ccss_error_detail_format(&d, buf.as_mut_ptr(), 8) };
        assert_eq!(n2, n);
        let k = buf.iter().position(|&c| c == 0).unwrap();
        let s: Vec<u8> = buf[..k].iter().map(|&c| c as u8).collect();
        assert_eq!(std::str::from_utf8(&s).unwrap(), "invalid");
    }

    /// Tables (standard, or `entries`), topology and evaluator of a mesh in
    /// test-owned blocks; the blocks are returned to keep them alive.
    struct Built {
        tables: *const CcssTables,
        ev: *const CcssEvaluator,
        _mem: [Vec<u64>; 3],
    }

    fn build_mesh(p: &[f64], s: &[u32], i: &[u32], entries: &[CcssWeightEntry]) -> Built {
        let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
        let mut d = Failure::invalid("x").to_detail();
        let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
        unsafe {
            assert_eq!(ccss_tables_required_bytes(&mut tb), CcssStatus::OK);
            let mut tmem = block(tb);
            let st = ccss_tables_build(
                entries.as_ptr(),
                entries.len(),
                tmem.as_mut_ptr().cast(),
                tb,
                &mut tables,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            let st = ccss_topology_required_bytes(p.len() / 3, s.as_ptr(), s.len(), &mut gb);
            assert_eq!(st, CcssStatus::OK);
            let mut gmem = block(gb);
            let st = ccss_topology_build(
                p.as_ptr(),
                p.len() / 3,
                s.as_ptr(),
                s.len(),
                i.as_ptr(),
                i.len(),
                gmem.as_mut_ptr().cast(),
                gb,
                &mut topo,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
            let st = ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d);
            assert_eq!(st, CcssStatus::OK);
            let mut emem = block(eb);
            let st =
                ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
            assert_eq!(st, CcssStatus::OK);
            Built {
                tables,
                ev,
                _mem: [tmem, gmem, emem],
            }
        }
    }

    const METHODS: [(u32, Method); 4] = [
        (CcssDepthMethod::DEPTH_OLD as u32, Method::Old),
        (CcssDepthMethod::DEPTH_NEW as u32, Method::New),
        (CcssDepthMethod::DEPTH_BEST as u32, Method::Best),
        (CcssDepthMethod::DEPTH_TIGHT as u32, Method::Tight),
    ];

    #[test]
    fn depths_match_core_and_do_not_allocate() {
        let (p, s, i) = cube();
        let b = build_mesh(&p, &s, &i, &[]);
        // SAFETY: a live handle built above.
        let core_ev = unsafe { &(*b.ev).ev };
        let mut d = Failure::invalid("x").to_detail();
        let mut n = 0usize;
        let mut start = 0usize;
        let mut got = [0u32; 6];
        let mut want = [0u32; 6];
        let before = alloc_count::get();
        unsafe {
            assert_eq!(ccss_evaluator_slot_count(b.ev, &mut n), CcssStatus::OK);
            assert_eq!(n, 6);
            for f in 0..6u32 {
                assert_eq!(
                    ccss_evaluator_slot_start(b.ev, f, &mut start),
                    CcssStatus::OK
                );
                assert_eq!(start, f as usize);
            }
            for eps in [0.1, 0.01, 1e-3, 1e-6] {
                for (m, cm) in METHODS {
                    let st = ccss_depths(b.ev, eps, m, got.as_mut_ptr(), 6, &mut d);
                    assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
                    ccss_core::bounds::depth::depths(core_ev, eps, cm, &mut want).unwrap();
                    assert_eq!(got, want, "eps {eps} method {m}");
                }
            }
        }
        assert_eq!(alloc_count::get(), before, "depth paths allocated");
        // Cube: all faces alike; smaller eps, deeper; TIGHT <= NEW, BEST <= all.
        let depth = |eps: f64, m: u32| {
            let mut o = [0u32; 6];
            let st = unsafe { ccss_depths(b.ev, eps, m, o.as_mut_ptr(), 6, ptr::null_mut()) };
            assert_eq!(st, CcssStatus::OK);
            assert!(o.iter().all(|&x| x == o[0]), "{o:?}");
            o[0]
        };
        for eps in [0.01, 1e-4] {
            let [old, new, best, tight] = [0, 1, 2, 3].map(|m| depth(eps, m));
            assert!(tight <= new && best <= old && best <= new && best <= tight);
            assert!(best > 0 && best < 40, "{best}");
        }
        assert!(depth(1e-4, 2) > depth(0.01, 2));
    }

    #[test]
    fn depth_errors_write_nothing() {
        let (p, s, i) = cube();
        let b = build_mesh(&p, &s, &i, &[]);
        let mut d = Failure::invalid("x").to_detail();
        let sentinel = 0xdead_beef_u32;
        let mut out = [sentinel; 8];
        // Each call, failing or not, allocates nothing (the checks of the
        // messages below do).
        let call = |eps: f64, m: u32, o: *mut u32, len: usize, d: &mut CcssErrorDetail| {
            let before = alloc_count::get();
            let st = unsafe { ccss_depths(b.ev, eps, m, o, len, d) };
            assert_eq!(alloc_count::get(), before, "ccss_depths allocated");
            st
        };
        let o = out.as_mut_ptr();
        for eps in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let st = call(eps, 2, o, 8, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "eps {eps}");
            assert!(
                msg(&d).contains("eps must be positive and finite"),
                "{}",
                msg(&d)
            );
        }
        for m in [4u32, 99, u32::MAX] {
            let st = call(0.01, m, o, 8, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "method {m}");
            assert!(msg(&d).contains("ccss_depth_method"), "{}", msg(&d));
        }
        let st = call(0.01, 2, o, 5, &mut d);
        assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 6));
        assert_eq!(d.status, CcssStatus::ERR_BUFFER_TOO_SMALL);
        let st = call(0.01, 2, ptr::null_mut(), 0, &mut d);
        assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 6));
        let st = call(0.01, 2, ptr::null_mut(), 6, &mut d);
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        assert!(msg(&d).contains("`out`"));
        let mis = (out.as_mut_ptr() as *mut u8).wrapping_add(1) as *mut u32;
        assert_eq!(call(0.01, 2, mis, 6, &mut d), CcssStatus::ERR_MISALIGNED);
        assert!(out.iter().all(|&x| x == sentinel), "written on failure");
        unsafe {
            let st = ccss_depths(ptr::null(), 0.01, 2, o, 8, &mut d);
            assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
            let mut n = 7usize;
            assert_eq!(
                ccss_evaluator_slot_count(ptr::null(), &mut n),
                CcssStatus::ERR_NULL_POINTER
            );
            assert_eq!(
                ccss_evaluator_slot_count(b.ev, ptr::null_mut()),
                CcssStatus::ERR_NULL_POINTER
            );
            for f in [6u32, u32::MAX] {
                assert_eq!(
                    ccss_evaluator_slot_start(b.ev, f, &mut n),
                    CcssStatus::ERR_FACE_OUT_OF_RANGE
                );
            }
            assert_eq!(n, 7, "written on failure");
        }
        // Enough room is enough: a larger buffer keeps its tail.
        assert_eq!(call(0.01, 2, o, 8, &mut d), CcssStatus::OK);
        assert_eq!(out[6..], [sentinel; 2]);
    }

    #[test]
    fn depth_slots_of_triangles_and_general_weights() {
        // Tetrahedron: 4 triangles, 3 sub-faces each.
        let p = [1., 1., 1., 1., -1., -1., -1., 1., -1., -1., -1., 1.];
        let s = [3u32; 4];
        let i = [0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2];
        let b = build_mesh(&p, &s, &i, &[]);
        let mut n = 0usize;
        unsafe {
            assert_eq!(ccss_evaluator_slot_count(b.ev, &mut n), CcssStatus::OK);
            assert_eq!(n, 12);
            for f in 0..4u32 {
                assert_eq!(ccss_evaluator_slot_start(b.ev, f, &mut n), CcssStatus::OK);
                assert_eq!(n, 3 * f as usize);
            }
            let mut o = [0u32; 12];
            let st = ccss_depths(b.ev, 0.01, 2, o.as_mut_ptr(), 12, ptr::null_mut());
            assert_eq!(st, CcssStatus::OK);
            // All sub-faces alike (the tetrahedron's symmetry).
            assert!(o.iter().all(|&x| x == o[0] && x > 0), "{o:?}");
        }
        // A general rule at valence 3: the old technique does not apply.
        let (p, s, i) = cube();
        let w = build_mesh(&p, &s, &i, &[entry(3, 0.5, 0.3, 0.2)]);
        let mut d = Failure::invalid("x").to_detail();
        let mut o = [7u32; 6];
        unsafe {
            let st = ccss_depths(w.ev, 0.01, 0, o.as_mut_ptr(), 6, &mut d);
            assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
            assert!(msg(&d).contains("standard weights"), "{}", msg(&d));
            assert_eq!(o, [7; 6]);
            for m in [1, 2, 3] {
                let st = ccss_depths(w.ev, 0.01, m, o.as_mut_ptr(), 6, &mut d);
                assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
                assert!(o.iter().all(|&x| x > 0 && x < 100), "{o:?}");
            }
            let mut r = CcssDepthRatesInfo::default();
            assert_eq!(ccss_depth_rates(w.tables, 3, &mut r), CcssStatus::OK);
            assert_eq!((r.valence, r.r_old, r.c_old), (3, 0.0, 0.0));
            assert!(r.r2 > 0.0 && r.r2 < 1.0 && r.c_new > 0.0, "{r:?}");
            // Valence 5 keeps the standard rule there.
            assert_eq!(ccss_depth_rates(w.tables, 5, &mut r), CcssStatus::OK);
            assert_eq!((r.r_old, r.c_old), (18.0 / 25.0, 5.0 / 7.0));
        }
    }

    #[test]
    fn depth_rates_are_the_tables_rates() {
        let (p, s, i) = cube();
        let b = build_mesh(&p, &s, &i, &[]);
        let mut maxv = 0usize;
        let mut r = CcssDepthRatesInfo::default();
        let before = alloc_count::get();
        unsafe {
            assert_eq!(ccss_max_valence(&mut maxv), CcssStatus::OK);
            // SAFETY: a live handle.
            let set = &(*b.tables).set;
            for n in 3..=maxv as u32 {
                assert_eq!(ccss_depth_rates(b.tables, n, &mut r), CcssStatus::OK);
                let want = set.get(n as usize).unwrap().rates();
                assert_eq!(r, CcssDepthRatesInfo::from(want), "n={n}");
                assert_eq!(r.valence, n);
            }
            // Report Table 2, n = 5 (and Lemma 2's rate).
            assert_eq!(ccss_depth_rates(b.tables, 5, &mut r), CcssStatus::OK);
            assert!(
                (r.r1 - 0.72).abs() < 5e-5 && (r.r2 - 0.4016).abs() < 5e-5,
                "{r:?}"
            );
            assert_eq!(r.r_old, 18.0 / 25.0);
            let keep = r;
            for bad in [0u32, 2, maxv as u32 + 1, u32::MAX] {
                assert_eq!(
                    ccss_depth_rates(b.tables, bad, &mut r),
                    CcssStatus::ERR_UNSUPPORTED_VALENCE
                );
            }
            assert_eq!(r, keep, "written on failure");
            assert_eq!(
                ccss_depth_rates(ptr::null(), 5, &mut r),
                CcssStatus::ERR_NULL_POINTER
            );
            assert_eq!(
                ccss_depth_rates(b.tables, 5, ptr::null_mut()),
                CcssStatus::ERR_NULL_POINTER
            );
        }
        assert_eq!(alloc_count::get(), before, "ccss_depth_rates allocated");
    }

    #[test]
    fn depth_method_values_are_stable() {
        for (v, m) in METHODS {
            assert_eq!(CcssDepthMethod::from_raw(v).map(|x| x.core()), Some(m));
        }
        assert_eq!(CcssDepthMethod::from_raw(4), None);
        assert_eq!(
            [0, 1, 2, 3].map(|v: u32| CcssDepthMethod::from_raw(v).unwrap() as u32),
            [0, 1, 2, 3]
        );
    }
}
