//! The one status enum of the ABI, the error detail, and the mapping of every
//! core error to them (`ccss_status_message`, `ccss_error_detail_format`).
//!
//! Internally a failed export carries a [`Failure`] (status plus the detail
//! fields); the boundary ([`crate::boundary::guard`]) turns it into the
//! returned status and, if the caller passed one, the filled detail.

use ccss_core::{Error, SolidDefect};
use core::ffi::{c_char, c_int};
use core::fmt::{self, Write as _};
use core::ptr;
use std::panic::{catch_unwind, AssertUnwindSafe};

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
    /// be (bytes for memory blocks, elements for output arrays). This is the
    /// one capacity status: every too-small block or array reports it.
    ERR_BUFFER_TOO_SMALL = 2,
    /// A memory block is not 8-byte aligned, or an array is not aligned for
    /// its element type.
    ERR_MISALIGNED = 3,
    /// An argument is invalid (the detail message names it). For a NaN or
    /// negative sharpness (`ccss_feature_evaluator_build`) `detail.vertex` and
    /// `detail.vertex2` are the crease's vertices, or the corner vertex twice.
    ERR_INVALID_ARGUMENT = 4,
    /// The mesh has no vertices or no faces.
    ERR_EMPTY_MESH = 5,
    /// The face sizes add up to `detail.required` indices but `detail.value`
    /// were given.
    ERR_INDEX_COUNT_MISMATCH = 6,
    /// Face `detail.face` uses vertex `detail.vertex`, which does not exist;
    /// or (`detail.face` = -1) a corner tag of `ccss_feature_evaluator_build`
    /// names vertex `detail.vertex`, which does not exist.
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
    /// `ccss_weight_entry_check`): a weight is NaN, infinite or negative,
    /// `alpha + beta + gamma` differs from 1 by more than
    /// `CCSS_WEIGHT_ENTRY_SUM_TOLERANCE`, valence 4 has non-standard weights
    /// (regular patches are bicubic B-splines), or the valence is outside
    /// `3..=ccss_max_valence`. `detail.value` is the valence (`vertex` is -1:
    /// no particular vertex), `detail.query_index` the index of the offending
    /// entry in the array given to `ccss_tables_build`; the message says which
    /// rule was broken.
    ERR_INVALID_WEIGHTS = 22,
    /// Face `detail.face` is a hole: it has no surface
    /// (`ccss_feature_evaluator_eval*`; a face listed in `holes`, or in
    /// boundary mode NONE a face at a boundary vertex).
    ERR_HOLE_FACE = 23,
    /// A crease tag names vertices `detail.vertex` and `detail.vertex2`, which
    /// no edge of the mesh joins (`ccss_feature_evaluator_build`).
    ERR_NOT_AN_EDGE = 24,
    /// The neighbourhood of face `detail.face` exceeds the fixed capacity of
    /// local refinement (a valence above `ccss_max_valence`, or an edge with
    /// very many faces; `ccss_feature_evaluator_eval*`).
    ERR_NEIGHBOURHOOD_TOO_LARGE = 25,
    /// The mesh does not bound a solid (voxelization, flooding, mass
    /// properties of a `ccss_feature_evaluator`): `detail.vertex` and
    /// `detail.vertex2` name a boundary edge or an edge with more than two
    /// (or inconsistently oriented) faces, or `detail.vertex` alone a
    /// non-manifold vertex, or `detail.face` a hole face.
    ERR_NOT_CLOSED_SOLID = 26,
    /// An iterative solve reached its iteration limit
    /// (`ccss_interpolation_solve`; `detail.value` = the iterations).
    ERR_NOT_CONVERGED = 27,
    /// Requirement `detail.value` of `ccss_interpolation_solve` contradicts
    /// the interpolation conditions or an earlier requirement.
    ERR_CONFLICTING_REQUIREMENT = 28,
    /// An adaptive computation reached its documented work cap
    /// (`detail.required` is the cap, the message says what was counted):
    /// a pathological input (e.g. a needle-thin surface) stopped instead of
    /// running for minutes.
    ERR_WORK_LIMIT_EXCEEDED = 29,
    /// The coordinates' magnitude or dynamic range is beyond what the
    /// computation can certify in double precision (a bound or result would
    /// overflow, underflow or be dominated by rounding); the message says
    /// which.
    ERR_COORDINATE_RANGE = 30,
    /// The handle does not point at a live ccss object of this type and
    /// layout version (garbage, a handle of another type, or a block whose
    /// header was overwritten, e.g. after `free` and reuse). Every export
    /// checks the magic word at the handle before using it; the handle must
    /// still point to readable memory.
    ERR_INVALID_HANDLE = 31,
    /// A handle block failed its integrity check (its contents changed
    /// after it was built): `ccss_tables_verify`, `ccss_evaluator_verify`.
    ERR_CORRUPTED = 32,
    /// An output array overlaps memory the call reads (a handle's block).
    ERR_OVERLAP = 33,
    /// Boolean: the two surfaces cross at an angle too close to tangential
    /// for the accepted amplification (`ccss_boolean_options`):
    /// `detail.face` = the triangle of A, `detail.value` = the triangle of
    /// B.
    ERR_NEAR_TANGENTIAL = 34,
    /// Boolean: the two meshes touch degenerately (a vertex exactly on the
    /// other's triangle plane, an edge through an edge, coplanar
    /// triangles, too many crossings of one triangle): `detail.face` = the
    /// triangle of A, `detail.value` = the triangle of B (-1 when
    /// unknown); the message says which. Another tolerance (or a tiny
    /// shift) resolves it.
    ERR_DEGENERATE_CONTACT = 35,
    /// An internal error of ccss (a bug): a Rust panic caught at the ABI
    /// boundary, or an internal inconsistency detected by a check (before
    /// 0.2 such checks reported INVALID_ARGUMENT and this status was
    /// `CCSS_ERR_INTERNAL`). The detail message says which.
    ERR_INTERNAL = 99,
}

/// Capacity of `ccss_error_detail.message`, including the terminating NUL.
pub const CCSS_ERROR_DETAIL_MESSAGE_CAPACITY: usize = 256;

/// Where and why a call failed. Optional out-parameter (pass NULL if not
/// wanted) of every function that returns a status; written only on failure.
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
    /// Index of the offending query in a batch (`ccss_evaluator_eval_batch`), or of the
    /// offending weight entry (`ccss_tables_build`); else `UINT64_MAX`.
    pub query_index: u64,
    /// Human-readable message (the core library's error message, prefixed
    /// with `query N: ` for batch errors and `entry N: ` for weight entries),
    /// NUL-terminated UTF-8; truncated at a
    /// character boundary if longer than the capacity allows.
    pub message: [c_char; CCSS_ERROR_DETAIL_MESSAGE_CAPACITY],
}

/// What an internal failure says; formatted into the detail message.
#[derive(Clone, Copy)]
pub(crate) enum Msg {
    Core(Error),
    Null(&'static str),
    Text(&'static str),
    /// A valence listed twice in a weight-entry array.
    DuplicateValence {
        valence: u32,
        first: u64,
    },
    /// A handle argument whose magic word does not match (the argument,
    /// the C type expected).
    Handle {
        arg: &'static str,
        ty: &'static str,
    },
    /// A handle block whose checksum does not match (the C type).
    Corrupted(&'static str),
    /// A caught panic.
    Panic,
    /// An internal inconsistency (what was inconsistent).
    Internal(&'static str),
}

/// An internal failure: status plus everything that goes into the detail.
#[derive(Clone, Copy)]
pub(crate) struct Failure {
    pub(crate) status: CcssStatus,
    pub(crate) face: i64,
    pub(crate) vertex: i64,
    pub(crate) vertex2: i64,
    pub(crate) value: i64,
    pub(crate) required: u64,
    pub(crate) query_index: Option<u64>,
    /// What `query_index` counts ("query", "entry"): the message prefix.
    pub(crate) index_name: &'static str,
    pub(crate) msg: Msg,
}

impl Failure {
    pub(crate) fn new(status: CcssStatus, msg: Msg) -> Failure {
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

    pub(crate) fn null(arg: &'static str) -> Failure {
        Failure::new(CcssStatus::ERR_NULL_POINTER, Msg::Null(arg))
    }

    pub(crate) fn invalid(what: &'static str) -> Failure {
        Failure::new(CcssStatus::ERR_INVALID_ARGUMENT, Msg::Text(what))
    }

    pub(crate) fn too_small(required: usize) -> Failure {
        Failure::from(Error::BufferTooSmall { required })
    }

    pub(crate) fn misaligned() -> Failure {
        Failure::from(Error::Misaligned)
    }

    /// An internal inconsistency (a bug in ccss): ERR_INTERNAL.
    pub(crate) fn internal(what: &'static str) -> Failure {
        Failure::new(CcssStatus::ERR_INTERNAL, Msg::Internal(what))
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
            Error::NotAnEdge { v0, v1 } => edge(&mut f, S::ERR_NOT_AN_EDGE, v0, v1),
            // An invalid argument naming the crease (or the corner twice).
            Error::InvalidSharpness { v0, v1 } => edge(&mut f, S::ERR_INVALID_ARGUMENT, v0, v1),
            // A tag's vertex: reported as an index out of range of no face.
            Error::VertexOutOfRange { vertex } => {
                f.status = S::ERR_INDEX_OUT_OF_RANGE;
                f.vertex = vertex as i64;
            }
            Error::HoleFace { face } => {
                f.status = S::ERR_HOLE_FACE;
                f.face = face as i64;
            }
            Error::NotConverged { iterations } => {
                f.status = S::ERR_NOT_CONVERGED;
                f.value = iterations as i64;
            }
            Error::ConflictingRequirement { requirement } => {
                f.status = S::ERR_CONFLICTING_REQUIREMENT;
                f.value = requirement as i64;
            }
            Error::NeighbourhoodTooLarge { face } => {
                f.status = S::ERR_NEIGHBOURHOOD_TOO_LARGE;
                f.face = face as i64;
            }
            Error::NotClosedSolid(d) => match d {
                SolidDefect::BoundaryEdge { v0, v1 } | SolidDefect::NonManifoldEdge { v0, v1 } => {
                    edge(&mut f, S::ERR_NOT_CLOSED_SOLID, v0, v1)
                }
                SolidDefect::NonManifoldVertex { vertex } => {
                    f.status = S::ERR_NOT_CLOSED_SOLID;
                    f.vertex = vertex as i64;
                }
                SolidDefect::HoleFace { face } => {
                    f.status = S::ERR_NOT_CLOSED_SOLID;
                    f.face = face as i64;
                }
            },
            // Core reports its internal consistency checks as invalid
            // arguments whose message starts with "internal:" (it has no
            // variant of its own for them yet): a bug in ccss, not in the
            // caller's input.
            Error::InvalidArgument(m) if m.starts_with("internal:") => {
                f.status = S::ERR_INTERNAL;
            }
            Error::InvalidArgument(_) => {}
            Error::WorkLimitExceeded { limit, .. } => {
                f.status = S::ERR_WORK_LIMIT_EXCEEDED;
                f.required = limit;
            }
            Error::CoordinateRange(_) => f.status = S::ERR_COORDINATE_RANGE,
            Error::NearTangential {
                triangle_a,
                triangle_b,
                ..
            } => {
                f.status = S::ERR_NEAR_TANGENTIAL;
                f.face = triangle_a as i64;
                f.value = triangle_b as i64;
            }
            Error::DegenerateContact {
                triangle_a,
                triangle_b,
                ..
            } => {
                f.status = S::ERR_DEGENERATE_CONTACT;
                let id = |t: u32| if t == u32::MAX { -1 } else { t as i64 };
                f.face = id(triangle_a);
                f.value = id(triangle_b);
            }
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
    pub(crate) fn to_detail(self) -> CcssErrorDetail {
        let mut bytes = [0u8; CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
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
            Msg::Handle { arg, ty } => write!(
                w,
                "invalid handle: `{arg}` is not a live {ty} handle (magic/version mismatch)"
            ),
            Msg::Corrupted(ty) => write!(
                w,
                "integrity check failed: the {ty} block changed after it was built"
            ),
            Msg::Panic => write!(w, "internal error: a Rust panic was caught (bug in ccss)"),
            Msg::Internal(t) => write!(w, "internal error: {t} (bug in ccss)"),
        };
        let mut message = [0 as c_char; CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
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
        23 => c"the face is a hole: it has no surface",
        24 => c"a crease tag names two vertices that no edge joins",
        25 => c"a face's neighbourhood is too large for local refinement (valence above the maximum, or an edge with very many faces)",
        26 => c"the mesh does not bound a solid (a boundary edge, a hole face or a non-manifold edge or vertex)",
        27 => c"an iterative solve did not converge within its iteration limit",
        28 => c"a requirement conflicts with the interpolation conditions or an earlier requirement",
        29 => c"a work limit was exceeded (a pathological input stopped instead of running for minutes)",
        30 => c"coordinates out of the certifiable range (a bound or result would overflow, underflow or be dominated by rounding)",
        31 => c"invalid handle (not a live ccss object of this type and layout version)",
        32 => c"a handle block failed its integrity check (tables or evaluator changed after build)",
        33 => c"an output array overlaps memory the call reads",
        34 => c"the two surfaces cross nearly tangentially: the Boolean is ill-conditioned there",
        35 => c"the two meshes touch degenerately (vertex on a plane, edge through an edge, coplanar triangles)",
        99 => c"internal error of ccss (a caught panic or an internal inconsistency; a bug)",
        _ => c"unknown status",
    };
    s.as_ptr()
}

/// Copies the message of `detail` into `out` (capacity `out_len` bytes),
/// truncated at a UTF-8 character boundary and always NUL-terminated when
/// `out_len > 0`. Returns the length of the whole message excluding the NUL (like
/// `snprintf`: the message was truncated iff the result is `>= out_len`).
/// `out` may be NULL when `out_len` is 0 (a length query). A NULL `detail` is an
/// empty message.
///
/// # Safety
/// `detail` is NULL or points to a readable `ccss_error_detail` (any bytes;
/// only `message` is read, up to its capacity); `out` is NULL or points to
/// `out_len` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn ccss_error_detail_format(
    detail: *const CcssErrorDetail,
    out: *mut c_char,
    out_len: usize,
) -> usize {
    catch_unwind(AssertUnwindSafe(|| {
        let mut msg = [0u8; CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
        let mut n = 0;
        if !detail.is_null() {
            // SAFETY: the caller promises a readable struct; the field is
            // reached by a raw projection and read unaligned as plain bytes.
            unsafe {
                let m = ptr::addr_of!((*detail).message)
                    as *const [u8; CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
                msg = ptr::read_unaligned(m);
            }
            n = msg
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(CCSS_ERROR_DETAIL_MESSAGE_CAPACITY);
        }
        if !out.is_null() && out_len > 0 {
            let mut k = n.min(out_len - 1);
            if k < n {
                // Do not cut a UTF-8 sequence: back off continuation bytes.
                while k > 0 && (msg[k] & 0xC0) == 0x80 {
                    k -= 1;
                }
            }
            // SAFETY: `out` has `out_len > k` writable bytes; `msg` is a local copy.
            unsafe {
                ptr::copy_nonoverlapping(msg.as_ptr(), out as *mut u8, k);
                *out.add(k) = 0;
            }
        }
        n
    }))
    .unwrap_or(0)
}
