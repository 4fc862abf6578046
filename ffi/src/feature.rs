//! Meshes with boundaries, creases, corners and holes
//! (`ccss_feature_evaluator`, with `ccss_feature_options` and the enums
//! `ccss_feature_boundary`, `ccss_feature_creasing`): ccss-core's
//! `FeatureMesh` (OpenSubdiv's sharpening and one sharp refinement step) and
//! its `FeatureEvaluator`, in one caller block.
//!
//! Block layout: the handle (which holds the core `FeatureMesh` and the
//! `FeatureEvaluator` that refers to it), then the `FeatureMesh` arena, then
//! the `FeatureEvaluator` arena. The core mesh copies what it needs from the
//! input arrays (it does not borrow them), so the block holds no copies of
//! them and the caller's arrays may be freed right after the build.

use crate::boundary::{
    check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_ref, try_slice,
};
use crate::boundary::{checksum_words, try_handle};
use crate::evaluator::{
    eval_batch_into, eval_point, CcssEvaluatorQuery, CcssEvaluatorResult, Outputs, PointEval,
};
use crate::status::{CcssErrorDetail, CcssStatus, Failure, Msg};
use crate::tables::CcssTables;
use ccss_core::eval::Query;
use ccss_core::mem::words_for;
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::{Error, Eval, FeatureEvaluator, MeshInput, TableSet};
use core::ffi::{c_int, c_void};
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// Boundary interpolation of a feature mesh (`ccss_feature_options.boundary`;
/// OpenSubdiv's `VtxBoundaryInterpolation`, same numeric values, stable ABI).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssFeatureBoundary {
    /// Boundary edges are sharp, but every face at a boundary vertex with an
    /// un-sharpened boundary edge is a hole (no surface): evaluating it fails
    /// with CCSS_ERR_HOLE_FACE.
    FEATURE_BOUNDARY_NONE = 0,
    /// Boundary edges are infinitely sharp (the default).
    FEATURE_BOUNDARY_EDGE_ONLY = 1,
    /// As EDGE_ONLY, and a vertex with one face and two edges is an
    /// infinitely sharp corner.
    FEATURE_BOUNDARY_EDGE_AND_CORNER = 2,
}

/// How semi-sharp creases decay (`ccss_feature_options.creasing`;
/// OpenSubdiv's `CreasingMethod`, same numeric values, stable ABI).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssFeatureCreasing {
    /// Sharpness minus one per level (the default).
    FEATURE_CREASING_UNIFORM = 0,
    /// Chaikin: at each end vertex, 3/4 of the value plus 1/4 of the average
    /// of the other semi-sharp edges there, then minus one.
    FEATURE_CREASING_CHAIKIN = 1,
}

/// Scheme options of a feature mesh. Get the defaults from
/// `ccss_feature_options_default` (EDGE_ONLY, UNIFORM, no smooth
/// triangles): a zero-initialised struct is NOT the default (its boundary
/// mode is NONE, as in OpenSubdiv's numbering).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssFeatureOptions {
    /// A `ccss_feature_boundary` (taken as `uint32_t`: any value is safe;
    /// others fail with INVALID_ARGUMENT).
    pub boundary: u32,
    /// A `ccss_feature_creasing` (taken as `uint32_t`: any value is safe;
    /// others fail with INVALID_ARGUMENT).
    pub creasing: u32,
    /// OpenSubdiv's `TRI_SUB_SMOOTH` when 1: edge points next to triangles
    /// use the weight 0.47 for the triangle's centroid; 0 is
    /// `TRI_SUB_CATMARK` (the default). Other values fail with
    /// INVALID_ARGUMENT.
    pub smooth_triangles: u8,
}

/// Core options of C options (every value checked).
fn core_options(o: &CcssFeatureOptions) -> Result<FeatureOptions, Failure> {
    let boundary = match o.boundary {
        0 => Boundary::None,
        1 => Boundary::EdgeOnly,
        2 => Boundary::EdgeAndCorner,
        _ => {
            return Err(Failure::invalid(
                "options.boundary is not a ccss_feature_boundary",
            ))
        }
    };
    let creasing = match o.creasing {
        0 => Creasing::Uniform,
        1 => Creasing::Chaikin,
        _ => {
            return Err(Failure::invalid(
                "options.creasing is not a ccss_feature_creasing",
            ))
        }
    };
    let smooth_triangles = match o.smooth_triangles {
        0 => false,
        1 => true,
        _ => return Err(Failure::invalid("options.smooth_triangles must be 0 or 1")),
    };
    Ok(FeatureOptions {
        boundary,
        creasing,
        smooth_triangles,
    })
}

/// Writes the default options to `*out`: boundary
/// `CCSS_FEATURE_BOUNDARY_EDGE_ONLY`, creasing
/// `CCSS_FEATURE_CREASING_UNIFORM`, `smooth_triangles` 0 (OpenSubdiv's
/// defaults, and those of `ccss eval`).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_options_default(
    out: *mut CcssFeatureOptions,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        let d = FeatureOptions::default();
        let o = CcssFeatureOptions {
            boundary: d.boundary as u32,
            creasing: d.creasing as u32,
            smooth_triangles: d.smooth_triangles as u8,
        };
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", o) }
    })
}

/// Exact evaluator of a mesh with boundaries, creases, corners and holes
/// (opaque; lives at the start of its memory block, which also holds the
/// refined mesh). Refers to nothing outside its block.
pub struct CcssFeatureEvaluator {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// Checksum of the block after the header, `FEATURE_HEAD..arena_end`
    /// (refined mesh and patch cache), taken at build
    /// ([`ccss_feature_evaluator_verify`]).
    checksum: u64,
    /// End of the part of the block the build wrote (bytes from the handle).
    arena_end: usize,
    /// The tables given at build (NULL if none), verified with the block.
    tables: *const CcssTables,
    /// The refined mesh; `ev` refers to it (same block, never moved).
    mesh: FeatureMesh<'static>,
    pub(crate) ev: FeatureEvaluator<'static, 'static>,
}

impl CcssFeatureEvaluator {
    /// The evaluator of the handle.
    pub(crate) fn evaluator(&self) -> &FeatureEvaluator<'static, 'static> {
        &self.ev
    }
}

impl crate::boundary::Handle for CcssFeatureEvaluator {
    const MAGIC: u64 = crate::boundary::magic(b"ccssFEV2");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssFeatureEvaluator, magic);
    const NAME: &'static str = "ccss_feature_evaluator";
}

const FEATURE_HEAD: usize = round8(size_of::<CcssFeatureEvaluator>());

// The handle needs at most the block's 8-byte alignment, and blocks are
// simply freed by C (checked at compile time).
const _: () = {
    assert!(align_of::<CcssFeatureEvaluator>() <= 8);
    assert!(!needs_drop::<CcssFeatureEvaluator>());
};

/// The C inputs of a feature mesh, checked and viewed as slices.
struct Inputs<'a> {
    mesh: MeshInput<'a>,
    features: FeatureInput<'a>,
}

impl Inputs<'_> {
    /// Every array as (address, bytes), for the overlap check of a block.
    fn ranges(&self) -> [(*const u8, usize); 8] {
        fn r<T>(s: &[T]) -> (*const u8, usize) {
            (s.as_ptr() as *const u8, core::mem::size_of_val(s))
        }
        let (m, f) = (&self.mesh, &self.features);
        [
            r(m.positions),
            r(m.face_sizes),
            r(m.indices),
            r(f.crease_vertices),
            r(f.crease_sharpness),
            r(f.corner_vertices),
            r(f.corner_sharpness),
            r(f.holes),
        ]
    }
}

/// Checks the C arguments (NULL, alignment, lengths, options) and views
/// them as core inputs.
///
/// # Safety
/// Each array pointer is NULL or points to its count of readable elements
/// (two vertices per crease); `options` is NULL or readable.
#[allow(clippy::too_many_arguments)]
unsafe fn inputs<'a>(
    positions: *const f64,
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    indices: *const u32,
    num_indices: usize,
    crease_vertices: *const u32,
    crease_sharpness: *const f32,
    num_creases: usize,
    corner_vertices: *const u32,
    corner_sharpness: *const f32,
    num_corners: usize,
    holes: *const u32,
    num_holes: usize,
    options: *const CcssFeatureOptions,
) -> Result<Inputs<'a>, Failure> {
    if num_vertices > u32::MAX as usize / 2 {
        return Err(Failure::from(Error::InvalidArgument("too many vertices")));
    }
    if num_creases > isize::MAX as usize / 8 {
        return Err(Failure::invalid("too many creases"));
    }
    // SAFETY (all of the block): forwarded caller promises.
    unsafe {
        let options = core_options(try_ref(options, "options")?)?;
        Ok(Inputs {
            mesh: MeshInput {
                positions: try_slice(positions, 3 * num_vertices, "positions")?,
                face_sizes: try_slice(face_sizes, num_faces, "face_sizes")?,
                indices: try_slice(indices, num_indices, "indices")?,
            },
            features: FeatureInput {
                crease_vertices: try_slice(crease_vertices, 2 * num_creases, "crease_vertices")?,
                crease_sharpness: try_slice(crease_sharpness, num_creases, "crease_sharpness")?,
                corner_vertices: try_slice(corner_vertices, num_corners, "corner_vertices")?,
                corner_sharpness: try_slice(corner_sharpness, num_corners, "corner_sharpness")?,
                holes: try_slice(holes, num_holes, "holes")?,
                options,
            },
        })
    }
}

/// Bytes of the `FeatureMesh` arena (validates the mesh).
fn mesh_bytes(i: &Inputs) -> Result<usize, Failure> {
    Ok(round8(FeatureMesh::required_bytes(&i.mesh)?))
}

/// Bytes of a whole block, given the bytes of its mesh arena and the built
/// mesh.
fn total_bytes(
    mesh_bytes: usize,
    fm: &FeatureMesh,
    tables: Option<&TableSet>,
) -> Result<usize, Failure> {
    FEATURE_HEAD
        .checked_add(mesh_bytes)
        .and_then(|b| b.checked_add(FeatureEvaluator::required_bytes(fm, tables)))
        .filter(|&b| b <= isize::MAX as usize)
        .ok_or(Failure::invalid("mesh too large"))
}

/// The exact block size, by a build of the feature mesh on the heap (the
/// evaluator's size depends on the refined mesh).
fn heap_total(i: &Inputs, tables: Option<&TableSet>) -> Result<usize, Failure> {
    let mb = mesh_bytes(i)?;
    let mut tmp = vec![0u64; words_for(mb)];
    let fm = FeatureMesh::build(&i.mesh, &i.features, &mut tmp)?;
    total_bytes(mb, &fm, tables)
}

/// The optional eigen tables (NULL: none). They must have been built with
/// the standard rule (else `INVALID_ARGUMENT`) and, for a build, outlive
/// the evaluator (C contract), hence any lifetime.
///
/// # Safety
/// `tables` is NULL or a live `ccss_tables` handle.
unsafe fn optional_tables<'t>(tables: *const CcssTables) -> Result<Option<&'t TableSet>, Failure> {
    if tables.is_null() {
        return Ok(None);
    }
    // SAFETY: forwarded caller promise.
    let t: &'t CcssTables = unsafe { try_handle(tables, "tables")? };
    Ok(Some(&t.set))
}

/// Writes to `*out` the number of bytes `ccss_feature_evaluator_build`
/// needs for this mesh, these tags and options: the handle, the refined
/// mesh and the evaluator's cache of B-spline patches.
///
/// Cost: the evaluator's size depends on the refined mesh, so this builds
/// the refined mesh once on the heap (about the work and memory of the
/// build itself); it validates everything the build does and fails with the
/// same statuses (see `ccss_feature_evaluator_build`).
///
/// # Safety
/// As `ccss_feature_evaluator_build`; `out` is NULL or points to a writable
/// `size_t`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ccss_feature_evaluator_required_bytes(
    positions: *const f64,
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    indices: *const u32,
    num_indices: usize,
    crease_vertices: *const u32,
    crease_sharpness: *const f32,
    num_creases: usize,
    corner_vertices: *const u32,
    corner_sharpness: *const f32,
    num_corners: usize,
    holes: *const u32,
    num_holes: usize,
    options: *const CcssFeatureOptions,
    tables: *const CcssTables,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const usize, "out")?;
        // SAFETY: forwarded caller promises.
        let i = unsafe {
            inputs(
                positions,
                num_vertices,
                face_sizes,
                num_faces,
                indices,
                num_indices,
                crease_vertices,
                crease_sharpness,
                num_creases,
                corner_vertices,
                corner_sharpness,
                num_corners,
                holes,
                num_holes,
                options,
            )
        }?;
        // SAFETY: forwarded caller promise.
        let tb = unsafe { optional_tables(tables) }?;
        let total = heap_total(&i, tb)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Builds the exact evaluator of a polygon mesh with boundaries, creases,
/// corners and holes into `mem`, following OpenSubdiv's rules (Far's
/// base-level sharpening, Sdc's masks; boundary and non-manifold edges
/// become infinitely sharp).
///
/// Mesh: `positions` (`3 * num_vertices` doubles), `face_sizes` (per face,
/// at least 3), `indices` (`num_indices` vertex indices, the faces
/// concatenated); open, non-manifold and unused vertices are fine. Tags (any
/// array may be NULL when its count is 0): `crease_vertices` holds
/// `2 * num_creases` vertex indices, one pair per edge, with
/// `crease_sharpness[k]` the sharpness of edge `k`; `corner_vertices[k]` has
/// sharpness `corner_sharpness[k]` (`num_corners` each); `holes` lists
/// `num_holes` faces that have no surface. Sharpness is OpenSubdiv's: 0
/// smooth, 10 or more infinitely sharp, in between semi-sharp. `options`:
/// see `ccss_feature_options` (non-NULL; `ccss_feature_options_default`).
/// `tables`: NULL, or eigen tables built with the standard rule
/// (`ccss_tables_build_standard`; others fail with INVALID_ARGUMENT): with
/// them, smooth extraordinary patches are evaluated with the eigen kernel
/// (cached at build, about 0.2 us a point) instead of local refinement
/// (same surface, some 3-15 us a point); they must outlive the handle.
/// `mem`: `mem_len` bytes, 8-byte aligned, at least
/// `ccss_feature_evaluator_required_bytes`. On success writes the handle
/// (which equals `mem`) to `*out`.
///
/// Errors: NULL_POINTER (`out`, `options`, an array with a non-zero count,
/// or `mem` with `mem_len > 0`), MISALIGNED, INVALID_ARGUMENT (an options
/// value out of range, a NaN or negative sharpness with the crease's two
/// vertices, or the corner vertex twice, in `detail.vertex` /
/// `detail.vertex2`; `mem` overlapping an input), the mesh errors
/// EMPTY_MESH, INDEX_COUNT_MISMATCH, INDEX_OUT_OF_RANGE, FACE_TOO_SMALL,
/// REPEATED_VERTEX, NON_FINITE_COORDINATE, the tag errors NOT_AN_EDGE (a
/// crease on two vertices no edge joins: `detail.vertex`, `detail.vertex2`),
/// INDEX_OUT_OF_RANGE (a corner on a vertex that does not exist:
/// `detail.vertex`, `detail.face` = -1), FACE_OUT_OF_RANGE (a hole on a face
/// that does not exist), then BUFFER_TOO_SMALL (`detail.required` = bytes).
/// On failure `*out` is not written and `mem`'s contents are unspecified.
///
/// Cost: no allocation, except that a `mem_len` too small even for the
/// refined mesh makes this function compute the exact required size as
/// `ccss_feature_evaluator_required_bytes` does (a build on the heap).
///
/// Ownership: the input arrays are not referred to after this returns (the
/// refined mesh is computed into `mem`); free them whenever. `tables`, when
/// given, is referred to by the handle. The caller owns
/// `mem`: the handle is valid while `mem` stays allocated, unmoved and
/// unmodified; nothing to destroy.
///
/// # Safety
/// Each array pointer is NULL or points to its count of readable elements;
/// `options` is NULL or readable; `tables` is NULL or a live tables handle;
/// `mem` is NULL or points to `mem_len`
/// writable bytes not otherwise in use and not overlapping the inputs;
/// `out` / `detail` are NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ccss_feature_evaluator_build(
    positions: *const f64,
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    indices: *const u32,
    num_indices: usize,
    crease_vertices: *const u32,
    crease_sharpness: *const f32,
    num_creases: usize,
    corner_vertices: *const u32,
    corner_sharpness: *const f32,
    num_corners: usize,
    holes: *const u32,
    num_holes: usize,
    options: *const CcssFeatureOptions,
    tables: *const CcssTables,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssFeatureEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const *const CcssFeatureEvaluator, "out")?;
        // SAFETY: forwarded caller promises.
        let i = unsafe {
            inputs(
                positions,
                num_vertices,
                face_sizes,
                num_faces,
                indices,
                num_indices,
                crease_vertices,
                crease_sharpness,
                num_creases,
                corner_vertices,
                corner_sharpness,
                num_corners,
                holes,
                num_holes,
                options,
            )
        }?;
        // SAFETY: forwarded caller promise (the tables outlive the handle).
        let tb: Option<&'static TableSet> = unsafe { optional_tables(tables) }?;
        let mb = mesh_bytes(&i)?;
        let mesh_end = FEATURE_HEAD
            .checked_add(mb)
            .ok_or(Failure::invalid("mesh too large"))?;
        let base = match try_block(mem, mem_len, mesh_end) {
            // Too small even for the refined mesh: the exact size needs a
            // build elsewhere (which reports the tag errors first).
            Err(f) if f.status == CcssStatus::ERR_BUFFER_TOO_SMALL => {
                return Err(Failure::too_small(heap_total(&i, tb)?))
            }
            r => r?,
        };
        if i.ranges()
            .iter()
            .any(|&(p, n)| overlaps(base as *const u8, mem_len, p, n))
        {
            return Err(Failure::invalid("mem overlaps an input array"));
        }
        // SAFETY: `base` is 8-aligned with `mem_len >= mesh_end` writable
        // bytes, ours (C contract) and not overlapping the inputs: the
        // handle at 0, the mesh arena at FEATURE_HEAD..mesh_end, the
        // evaluator arena after it (a multiple of 8 each). The block
        // outlives the handle and is never moved, hence 'static; the
        // evaluator refers to the mesh inside the handle, i.e. inside the
        // same block.
        unsafe {
            let arena = core_mem(base, FEATURE_HEAD, mesh_end)?;
            let fm = FeatureMesh::build(&i.mesh, &i.features, arena)?;
            let total = total_bytes(mb, &fm, tb)?;
            if mem_len < total {
                return Err(Failure::too_small(total));
            }
            let h = base as *mut CcssFeatureEvaluator;
            ptr::addr_of_mut!((*h).mesh).write(fm);
            let m: &'static FeatureMesh<'static> = &*ptr::addr_of!((*h).mesh);
            let arena = core_mem(base, mesh_end, mem_len)?;
            let ev = FeatureEvaluator::build(m, tb, arena)?;
            ptr::addr_of_mut!((*h).ev).write(ev);
            ptr::addr_of_mut!((*h).checksum).write(checksum_words(base, FEATURE_HEAD, total));
            ptr::addr_of_mut!((*h).arena_end).write(total);
            ptr::addr_of_mut!((*h).tables).write(tables);
            ptr::addr_of_mut!((*h).magic)
                .write(<CcssFeatureEvaluator as crate::boundary::Handle>::MAGIC);
            *out = h;
        }
        Ok(())
    })
}

/// Checks the integrity of the feature evaluator's block (the refined mesh
/// and the cached patches, every word after the handle header) against the
/// checksum taken by `ccss_feature_evaluator_build`, then the tables given
/// at build (if any) as `ccss_tables_verify` does. Any single changed word
/// is found; several go unnoticed with probability about 2^-64. Cost: one
/// pass over the block; the other calls check only the magic word.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_HANDLE, CORRUPTED.
///
/// # Safety
/// `fe` is NULL or a live handle (its tables, if any, alive); `detail` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_verify(
    fe: *const CcssFeatureEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(fe, "fe") }?;
        // SAFETY: the handle is live, so `fe .. fe + arena_end` is its block.
        let now = unsafe { checksum_words(fe as *const u8, FEATURE_HEAD, e.arena_end) };
        if now != e.checksum {
            return Err(Failure::new(
                CcssStatus::ERR_CORRUPTED,
                Msg::Corrupted("ccss_feature_evaluator"),
            ));
        }
        if e.tables.is_null() {
            return Ok(());
        }
        // SAFETY: the tables outlive the evaluator (build contract).
        crate::tables::verify_tables(unsafe { &*e.tables })
    })
}

/// Writes the number of base faces (holes included) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `fe` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_face_count(
    fe: *const CcssFeatureEvaluator,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(fe, "fe")?.ev.num_faces()) }
    })
}

/// Writes the number of sub-faces of base face `face` to `*out`: 1 for a
/// quad, N for an N-gon (sub-face k is its quad at corner k after one
/// refinement step, as with `ccss_evaluator_subface_count`).
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `fe` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_subface_count(
    fe: *const CcssFeatureEvaluator,
    face: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(fe, "fe") }?;
        check_ptr(out as *const u32, "out")?;
        if face as usize >= e.ev.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", e.ev.num_subfaces(face as usize) as u32) }
    })
}

/// Writes to `*out` whether base face `face` is a hole (1) or has a surface
/// (0). Holes are the faces listed in `holes` and, in boundary mode NONE,
/// the faces at boundary vertices with an un-sharpened boundary edge.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `fe` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_face_is_hole(
    fe: *const CcssFeatureEvaluator,
    face: u32,
    out: *mut u8,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(fe, "fe") }?;
        check_ptr(out as *const u8, "out")?;
        let f = face as usize;
        if f >= e.mesh.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        let hole = e.mesh.hole[e.mesh.child_face(f, 0)] != 0;
        // SAFETY: checked above.
        unsafe { put(out, "out", hole as u8) }
    })
}

/// # Safety
/// `fe` is NULL or a live handle; `out`, `detail` are NULL or writable.
#[allow(clippy::too_many_arguments)]
unsafe fn eval_one(
    fe: *const CcssFeatureEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    second: bool,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(fe, "fe") }?;
        // SAFETY: forwarded caller promise.
        unsafe { eval_point(&e.ev, (face, sub, u, v), Outputs::with_normal(second), out) }
    })
}

/// Evaluates position, first derivatives and normal at (u, v) of sub-face
/// `sub` (0 for quads) of base face `face` into `*out` (second derivatives
/// are set to zero); the parameterisation is that of `ccss_evaluator_eval`,
/// and on a closed smooth mesh without tags the surface is the same. At an
/// irregular corner itself the position is the exact limit, `du` / `dv` are
/// unit tangents (their lengths carry no meaning) and second derivatives are
/// zero.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE,
/// SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE (u or v NaN or outside
/// [0, 1]), HOLE_FACE (`detail.face`: the face has no surface),
/// NEIGHBOURHOOD_TOO_LARGE (`detail.face`). `*out` is written only on
/// success.
///
/// # Safety
/// `fe` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_eval(
    fe: *const CcssFeatureEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(fe, face, sub, u, v, false, out, detail) }
}

/// As `ccss_feature_evaluator_eval`, plus second derivatives (`duu`, `duv`,
/// `dvv`).
///
/// Errors: as `ccss_feature_evaluator_eval`.
///
/// # Safety
/// `fe` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_eval_second(
    fe: *const CcssFeatureEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(fe, face, sub, u, v, true, out, detail) }
}

/// Evaluates `count` queries into `out[0..count]` (`out_len` elements
/// available), with second derivatives when `second` is non-zero; as
/// `ccss_evaluator_eval_batch`.
///
/// All queries are validated before anything is written (a hole face
/// included): on the first bad query the function fails with its status and
/// `detail.query_index` (plus `face` / `value` = sub-face) and `out` is
/// untouched. NEIGHBOURHOOD_TOO_LARGE is found only while evaluating: then
/// `out[0..query_index)` hold results.
///
/// Errors: NULL_POINTER (`fe`; `queries` or `out` with a non-zero count),
/// MISALIGNED, BUFFER_TOO_SMALL (`out_len < count`; `detail.required` =
/// `count` elements), INVALID_ARGUMENT (`out` overlaps `queries`),
/// FACE_OUT_OF_RANGE, SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE,
/// HOLE_FACE, NEIGHBOURHOOD_TOO_LARGE.
///
/// # Safety
/// `fe` is NULL or a live handle; `queries` is NULL or points to `count`
/// readable queries; `out` is NULL or points to `out_len` writable results;
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_feature_evaluator_eval_batch(
    fe: *const CcssFeatureEvaluator,
    queries: *const CcssEvaluatorQuery,
    count: usize,
    second: c_int,
    out: *mut CcssEvaluatorResult,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(fe, "fe") }?;
        // SAFETY: forwarded caller promises.
        unsafe {
            eval_batch_into(
                &e.ev,
                queries,
                count,
                Outputs::with_normal(second != 0),
                out,
                out_len,
            )
        }
    })
}

impl PointEval for FeatureEvaluator<'_, '_> {
    fn check(&self, q: &Query) -> Result<(), Error> {
        FeatureEvaluator::check(self, q)
    }
    fn point(&self, face: u32, sub: u32, u: f64, v: f64, second: bool) -> Result<Eval, Error> {
        if second {
            self.eval_second(face, sub, u, v)
        } else {
            self.eval(face, sub, u, v)
        }
    }
}
