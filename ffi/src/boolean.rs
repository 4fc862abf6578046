//! Booleans of two closed triangle meshes in the C ABI
//! (`ccss_core::boolean`): typically the tessellations of two limit
//! surfaces made by `ccss_tessellation_emit` (triangles) at a tolerance
//! `t`; the result is within `amplification x t` of the exact Boolean of
//! the limit solids (see `ccss_boolean_counts_info.amplification`; shrink
//! `t` to `eps / amplification` and repeat for a target `eps`).
//!
//! Same conventions as the rest of the ABI. A `ccss_boolean` lives at the
//! start of its memory block and refers to the caller's input arrays, which
//! must stay alive and unchanged while it is used. `ccss_boolean_emit`
//! uses the handle's block as working memory: one handle must not be
//! emitted from two threads at once.

use crate::boundary::{
    block_bytes, check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_handle,
    try_handle_mut, try_ref, try_slice, try_slice_mut,
};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::boolean::{
    Boolean, FaceSource, Op, Options, Output, PatchTriangle, SolidMesh, UvTriangle,
};
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, offset_of, size_of};

/// The operation (`ccss_boolean_build`'s `op`; stable values).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssBooleanOp {
    /// A ∪ B: A outside B and B outside A.
    BOOLEAN_UNION = 0,
    /// A ∩ B: A inside B and B inside A.
    BOOLEAN_INTERSECTION = 1,
    /// A − B: A outside B and B inside A (reversed).
    BOOLEAN_DIFFERENCE = 2,
}

/// A closed triangle mesh, counter-clockwise seen from outside.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct CcssBooleanMesh {
    /// x y z per vertex (`3 * num_vertices` doubles).
    pub positions: *const f64,
    /// Vertices.
    pub num_vertices: usize,
    /// Three vertex indices per triangle (`3 * num_triangles`).
    pub triangles: *const u32,
    /// Triangles.
    pub num_triangles: usize,
}

/// Options of `ccss_boolean_build`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssBooleanOptions {
    /// Largest accepted amplification `1 / cos(gamma / 2)` (`gamma` the
    /// angle between the outward normals of the kept sheets where they
    /// cross); above it the build fails with NEAR_TANGENTIAL. 0 means the
    /// default, 100.
    pub max_amplification: f64,
}

/// Sizes and facts of a built Boolean (`ccss_boolean_counts`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssBooleanCountsInfo {
    /// Output vertices.
    pub vertices: usize,
    /// Output triangles.
    pub triangles: usize,
    /// Closed loops of the intersection curve.
    pub curve_loops: usize,
    /// Points of all loops.
    pub curve_points: usize,
    /// Crossing triangle pairs.
    pub crossing_pairs: usize,
    /// `max 1 / cos(gamma / 2)` over the crossings (1 when none): the
    /// output is within `amplification x t` of the exact result when both
    /// inputs are within `t` of their surfaces.
    pub amplification: f64,
}

/// Where an output triangle comes from.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssBooleanSource {
    /// 0 = A, 1 = B.
    pub solid: u32,
    /// Triangle of that input mesh.
    pub triangle: u32,
}

/// An input triangle in the parameter space of the patch it was
/// tessellated from (`ccss_boolean_emit_uv`, one per input triangle):
/// base face, sub-face and the (u, v) of its three vertices, in the
/// triangle's vertex order, all in that sub-face's domain.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssBooleanPatchTriangle {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// u0 v0 u1 v1 u2 v2.
    pub uv: [f64; 6],
}

/// Parameter-space provenance of an output triangle
/// (`ccss_boolean_emit_uv`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssBooleanUv {
    /// 0 = A, 1 = B.
    pub solid: u32,
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// Always 0.
    pub reserved: u32,
    /// u0 v0 u1 v1 u2 v2 of the output triangle's vertices, mapped by their
    /// barycentric coordinates in the source triangle.
    pub uv: [f64; 6],
}

/// Caller arrays for `ccss_boolean_emit` (lengths in elements).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct CcssBooleanOutput {
    /// x y z per vertex (`3 * vertices`). Required.
    pub positions: *mut f64,
    /// Length of `positions`.
    pub positions_len: usize,
    /// Three indices per triangle, counter-clockwise seen from outside
    /// (`3 * triangles`). Required.
    pub triangles: *mut u32,
    /// Length of `triangles`.
    pub triangles_len: usize,
    /// Source of each triangle (`triangles`), optional.
    pub sources: *mut CcssBooleanSource,
    /// Length of `sources`.
    pub sources_len: usize,
    /// Points per curve loop (`curve_loops`), optional with `curve_indices`.
    pub curve_sizes: *mut u32,
    /// Length of `curve_sizes`.
    pub curve_sizes_len: usize,
    /// Output vertex indices of the loops, concatenated (`curve_points`).
    pub curve_indices: *mut u32,
    /// Length of `curve_indices`.
    pub curve_indices_len: usize,
}

/// A Boolean of two triangle meshes (opaque; lives at the start of its
/// memory block).
pub struct CcssBoolean {
    magic: u64,
    b: Boolean<'static>,
}

impl crate::boundary::Handle for CcssBoolean {
    const MAGIC: u64 = crate::boundary::magic(b"ccssBOO1");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssBoolean, magic);
    const NAME: &'static str = "ccss_boolean";
}

const HEAD: usize = round8(size_of::<CcssBoolean>());

const _: () = {
    assert!(size_of::<CcssBooleanSource>() == size_of::<FaceSource>());
    assert!(align_of::<CcssBooleanSource>() == align_of::<FaceSource>());
    assert!(offset_of!(CcssBooleanSource, solid) == offset_of!(FaceSource, solid));
    assert!(offset_of!(CcssBooleanSource, triangle) == offset_of!(FaceSource, triangle));
    assert!(size_of::<CcssBooleanPatchTriangle>() == size_of::<PatchTriangle>());
    assert!(align_of::<CcssBooleanPatchTriangle>() == align_of::<PatchTriangle>());
    assert!(offset_of!(CcssBooleanPatchTriangle, uv) == offset_of!(PatchTriangle, uv));
    assert!(offset_of!(CcssBooleanPatchTriangle, sub) == offset_of!(PatchTriangle, sub));
    assert!(size_of::<CcssBooleanUv>() == size_of::<UvTriangle>());
    assert!(align_of::<CcssBooleanUv>() == align_of::<UvTriangle>());
    assert!(offset_of!(CcssBooleanUv, face) == offset_of!(UvTriangle, face));
    assert!(offset_of!(CcssBooleanUv, sub) == offset_of!(UvTriangle, sub));
    assert!(offset_of!(CcssBooleanUv, reserved) == offset_of!(UvTriangle, reserved));
    assert!(offset_of!(CcssBooleanUv, uv) == offset_of!(UvTriangle, uv));
    assert!(align_of::<CcssBoolean>() <= 8);
    assert!(!needs_drop::<CcssBoolean>());
};

/// The core mesh of a C mesh.
///
/// # Safety
/// `m` is NULL or readable, its arrays readable for their lengths and alive
/// for `'a`.
unsafe fn solid<'a>(
    m: *const CcssBooleanMesh,
    arg: &'static str,
) -> Result<SolidMesh<'a>, Failure> {
    // SAFETY: forwarded caller promises.
    unsafe {
        let m = try_ref(m, arg)?;
        let nv = m
            .num_vertices
            .checked_mul(3)
            .ok_or(Failure::invalid("num_vertices too large"))?;
        let nt = m
            .num_triangles
            .checked_mul(3)
            .ok_or(Failure::invalid("num_triangles too large"))?;
        let positions = try_slice(m.positions, nv, "mesh->positions")?;
        let triangles = try_slice(m.triangles, nt, "mesh->triangles")?;
        Ok(SolidMesh {
            positions,
            triangles,
        })
    }
}

fn core_op(op: u32) -> Result<Op, Failure> {
    use CcssBooleanOp::*;
    match op {
        x if x == BOOLEAN_UNION as u32 => Ok(Op::Union),
        x if x == BOOLEAN_INTERSECTION as u32 => Ok(Op::Intersection),
        x if x == BOOLEAN_DIFFERENCE as u32 => Ok(Op::Difference),
        _ => Err(Failure::invalid("op is not a ccss_boolean_op")),
    }
}

fn core_options(o: &CcssBooleanOptions) -> Result<Options, Failure> {
    let m = o.max_amplification;
    if m == 0.0 {
        return Ok(Options::default());
    }
    if m.is_nan() || m < 1.0 {
        return Err(Failure::invalid(
            "max_amplification must be 0 or at least 1",
        ));
    }
    Ok(Options {
        max_amplification: m,
    })
}

/// Writes to `*out` the bytes `ccss_boolean_build` needs before the
/// crossings are known (edge twins, the hierarchy, classes, vertex maps);
/// the crossings need more: `ccss_boolean_build` then fails with
/// BUFFER_TOO_SMALL and `detail.required` = the exact total for these
/// inputs.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT.
///
/// # Safety
/// `a`, `b` NULL or readable with readable arrays; `out`, `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_boolean_required_bytes(
    a: *const CcssBooleanMesh,
    b: *const CcssBooleanMesh,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (sa, sb) = unsafe { (solid(a, "a")?, solid(b, "b")?) };
        check_ptr(out as *const usize, "out")?;
        let total = block_bytes(
            Boolean::required_bytes_base(&sa, &sb),
            HEAD,
            "boolean too large",
        )?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Builds the Boolean `op` (a `ccss_boolean_op`) of the closed meshes `a`
/// and `b` in `mem` (`mem_len` bytes, 8-byte aligned) and writes the
/// handle (which equals `mem`) to `*out`. The input arrays are referred to,
/// not copied.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// the exact size), INVALID_ARGUMENT (bad op or options), EMPTY_MESH,
/// INDEX_OUT_OF_RANGE, NON_FINITE_COORDINATE, NOT_CLOSED_SOLID (an input
/// edge with one or more than two triangles, or inconsistently oriented:
/// `detail.vertex`-`detail.vertex2`), NEAR_TANGENTIAL (`detail.face` /
/// `detail.value`: the triangles of A and B where the amplification is
/// exceeded), DEGENERATE_CONTACT (the same triangles; -1 when unknown).
/// On failure `*out` is not written.
///
/// # Safety
/// `a`, `b` NULL or readable with arrays alive and unchanged while the
/// handle is used; `options` NULL or readable; `mem` NULL or `mem_len`
/// writable bytes not otherwise in use; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_boolean_build(
    a: *const CcssBooleanMesh,
    b: *const CcssBooleanMesh,
    op: u32,
    options: *const CcssBooleanOptions,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssBoolean,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the inputs outlive the handle
        // by the C contract, hence 'static.
        let (sa, sb, o): (SolidMesh<'static>, SolidMesh<'static>, &CcssBooleanOptions) =
            unsafe { (solid(a, "a")?, solid(b, "b")?, try_ref(options, "options")?) };
        check_ptr(out as *const *mut CcssBoolean, "out")?;
        let op = core_op(op)?;
        let opts = core_options(o)?;
        let base = try_block(mem, mem_len, HEAD)?;
        // SAFETY: `base` is 8-aligned with `mem_len >= HEAD` writable bytes:
        // the handle at 0, the core arena after it.
        unsafe {
            let arena = core_mem(base, HEAD, mem_len)?;
            let bo = Boolean::build(sa, sb, op, opts, arena).map_err(|err| match err {
                ccss_core::Error::BufferTooSmall { required } => {
                    Failure::too_small(required.saturating_add(HEAD))
                }
                other => Failure::from(other),
            })?;
            let h = base as *mut CcssBoolean;
            h.write(CcssBoolean {
                magic: <CcssBoolean as crate::boundary::Handle>::MAGIC,
                b: bo,
            });
            *out = h;
        }
        Ok(())
    })
}

/// Writes the output sizes and the measured amplification to `*out`.
///
/// # Safety
/// `h` NULL or a live handle; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_boolean_counts(
    h: *const CcssBoolean,
    out: *mut CcssBooleanCountsInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let h = unsafe { try_handle(h, "h")? };
        check_ptr(out as *const CcssBooleanCountsInfo, "out")?;
        let c = h.b.counts();
        let r = CcssBooleanCountsInfo {
            vertices: c.vertices,
            triangles: c.triangles,
            curve_loops: c.curve_loops,
            curve_points: c.curve_points,
            crossing_pairs: c.crossing_pairs,
            amplification: h.b.stats().amplification.max(1.0),
        };
        // SAFETY: checked above.
        unsafe { put(out, "out", r) }
    })
}

/// Writes the result into the arrays of `*output`: vertices, triangles
/// (closed, counter-clockwise seen from outside, shared vertices),
/// optional sources, the curve loops. Each array must hold at least what
/// `ccss_boolean_counts` says; all are checked before anything is written:
/// NULL_POINTER (`positions`, `triangles`, `curve_sizes`, `curve_indices`),
/// MISALIGNED, INVALID_ARGUMENT (arrays overlap each other or the handle's
/// block), BUFFER_TOO_SMALL (`detail.required` = the element count of the
/// first short array).
///
/// # Safety
/// `h` NULL or a live handle not used by another thread during the call;
/// `output` NULL or readable, its non-NULL pointers writable for their
/// lengths; `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_boolean_emit(
    h: *mut CcssBoolean,
    output: *const CcssBooleanOutput,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (hb, o) = unsafe { (try_handle_mut(h, "h")?, try_ref(output, "output")?) };
        let arrays: [(*const u8, usize); 5] = [
            (o.positions as *const u8, o.positions_len.saturating_mul(8)),
            (o.triangles as *const u8, o.triangles_len.saturating_mul(4)),
            (
                o.sources as *const u8,
                o.sources_len.saturating_mul(size_of::<CcssBooleanSource>()),
            ),
            (
                o.curve_sizes as *const u8,
                o.curve_sizes_len.saturating_mul(4),
            ),
            (
                o.curve_indices as *const u8,
                o.curve_indices_len.saturating_mul(4),
            ),
        ];
        let block = h as *const u8;
        for (k, &(p, n)) in arrays.iter().enumerate() {
            if p.is_null() {
                continue;
            }
            if overlaps(p, n, block, HEAD) {
                return Err(Failure::invalid("an output array overlaps the boolean"));
            }
            for &(q, m) in &arrays[k + 1..] {
                if !q.is_null() && overlaps(p, n, q, m) {
                    return Err(Failure::invalid("two output arrays overlap"));
                }
            }
        }
        // SAFETY: forwarded caller promises; the arrays are disjoint.
        unsafe {
            let positions = try_slice_mut(o.positions, o.positions_len, "output->positions")?
                .ok_or(Failure::null("output->positions"))?;
            let triangles = try_slice_mut(o.triangles, o.triangles_len, "output->triangles")?
                .ok_or(Failure::null("output->triangles"))?;
            let sources = try_slice_mut(
                o.sources as *mut FaceSource,
                o.sources_len,
                "output->sources",
            )?;
            let curve_sizes =
                try_slice_mut(o.curve_sizes, o.curve_sizes_len, "output->curve_sizes")?
                    .ok_or(Failure::null("output->curve_sizes"))?;
            let curve_indices = try_slice_mut(
                o.curve_indices,
                o.curve_indices_len,
                "output->curve_indices",
            )?
            .ok_or(Failure::null("output->curve_indices"))?;
            hb.b.emit(Output {
                positions,
                triangles,
                sources,
                curve_sizes,
                curve_indices,
            })?;
        }
        Ok(())
    })
}

/// Writes the parameter-space provenance of every output triangle (same
/// order as the triangles of `ccss_boolean_emit`) into `out`: solid, base
/// face, sub-face and the (u, v) of its three vertices. `a_uv` and `b_uv`
/// hold one `ccss_boolean_patch_triangle` per input triangle of A and B
/// (from the tessellation's params and polygon cells; a vertex on a
/// sub-face border must be given in the triangle's own sub-face). A kept
/// input vertex takes its (u, v); a curve point the barycentric combination
/// of its source triangle's three. Statuses: NULL_POINTER, MISALIGNED,
/// INVALID_ARGUMENT (`a_uv_len`/`b_uv_len` below the input triangle
/// counts, or `out` overlaps an input or the handle), BUFFER_TOO_SMALL
/// (`detail.required` = triangles; nothing written).
///
/// # Safety
/// `h` NULL or a live handle; `a_uv`, `b_uv` NULL or readable for their
/// lengths; `out` NULL or writable for `out_len`; `detail` NULL or
/// writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ccss_boolean_emit_uv(
    h: *const CcssBoolean,
    a_uv: *const CcssBooleanPatchTriangle,
    a_uv_len: usize,
    b_uv: *const CcssBooleanPatchTriangle,
    b_uv_len: usize,
    out: *mut CcssBooleanUv,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let hb = unsafe { try_handle(h, "h")? };
        check_ptr(a_uv, "a_uv")?;
        check_ptr(b_uv, "b_uv")?;
        let ob = out_len.saturating_mul(size_of::<CcssBooleanUv>());
        let ib = size_of::<CcssBooleanPatchTriangle>();
        if overlaps(out as *const u8, ob, h as *const u8, HEAD)
            || overlaps(
                out as *const u8,
                ob,
                a_uv as *const u8,
                a_uv_len.saturating_mul(ib),
            )
            || overlaps(
                out as *const u8,
                ob,
                b_uv as *const u8,
                b_uv_len.saturating_mul(ib),
            )
        {
            return Err(Failure::invalid("out overlaps an input or the boolean"));
        }
        // SAFETY: forwarded caller promises; `out` is disjoint from the
        // inputs.
        unsafe {
            let a = try_slice(a_uv as *const PatchTriangle, a_uv_len, "a_uv")?;
            let b = try_slice(b_uv as *const PatchTriangle, b_uv_len, "b_uv")?;
            let o = try_slice_mut(out as *mut UvTriangle, out_len, "out")?
                .ok_or(Failure::null("out"))?;
            hb.b.emit_uv(a, b, o)?;
        }
        Ok(())
    })
}
