//! Validated half-edge topology of a closed mesh (`ccss_topology`).

use crate::boundary::try_handle;
use crate::boundary::{check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_slice};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::{Error, MeshInput, Topology};
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// Validated half-edge topology of a closed mesh, with its own copy of the
/// positions, face sizes and indices (opaque; lives at the start of its
/// memory block).
pub struct CcssTopology {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    pub(crate) topo: Topology<'static>,
}

impl crate::boundary::Handle for CcssTopology {
    const MAGIC: u64 = crate::boundary::magic(b"ccssTOP1");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssTopology, magic);
    const NAME: &'static str = "ccss_topology";
}

const TOPO_HEAD: usize = round8(size_of::<CcssTopology>());

// The handle needs at most the block's 8-byte alignment, and blocks are
// simply freed by C (checked at compile time).
const _: () = {
    assert!(align_of::<CcssTopology>() <= 8);
    assert!(!needs_drop::<CcssTopology>());
};

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
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_required_bytes(
    num_vertices: usize,
    face_sizes: *const u32,
    num_faces: usize,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const usize, "out")?;
        // SAFETY: forwarded caller promise.
        let sizes = unsafe { try_slice(face_sizes, num_faces, "face_sizes") }?;
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
/// seen from outside. `mem`: `mem_len` bytes, 8-byte aligned, at least
/// `ccss_topology_required_bytes`. On success writes the handle (which equals
/// `mem`) to `*out`.
///
/// Errors: NULL_POINTER (`out`, an array with a non-zero count, or `mem` with
/// `mem_len > 0`), MISALIGNED, BUFFER_TOO_SMALL (`detail.required` = bytes; mesh
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
/// `mem` is NULL or points to `mem_len` writable bytes not otherwise in use and
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
    mem_len: usize,
    out: *mut *const CcssTopology,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const *const CcssTopology, "out")?;
        if num_vertices > u32::MAX as usize / 2 {
            return Err(Failure::from(Error::InvalidArgument("too many vertices")));
        }
        let np = 3 * num_vertices;
        // SAFETY: forwarded caller promises (counts of readable elements).
        let (p, s, i) = unsafe {
            (
                try_slice(positions, np, "positions")?,
                try_slice(face_sizes, num_faces, "face_sizes")?,
                try_slice(indices, num_indices, "indices")?,
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
        let base = try_block(mem, mem_len, total)?;
        let (mb, ml) = (base as *const u8, mem_len);
        if overlaps(mb, ml, p.as_ptr() as *const u8, 8 * p.len())
            || overlaps(mb, ml, s.as_ptr() as *const u8, 4 * s.len())
            || overlaps(mb, ml, i.as_ptr() as *const u8, 4 * i.len())
        {
            return Err(Failure::invalid("mem overlaps an input array"));
        }
        // SAFETY: `base` is 8-aligned with `total <= mem_len` writable bytes, split
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
            let arena = core_mem(base, o_core, total)?;
            let topo = Topology::build(mesh, arena)?;
            let h = base as *mut CcssTopology;
            h.write(CcssTopology {
                magic: <CcssTopology as crate::boundary::Handle>::MAGIC,
                topo,
            });
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
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_vertex_count(
    topo: *const CcssTopology,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(topo, "topo")?.topo.num_vertices()) }
    })
}

/// Writes the number of faces to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_face_count(
    topo: *const CcssTopology,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(topo, "topo")?.topo.num_faces()) }
    })
}

/// Writes the number of (undirected) edges to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_edge_count(
    topo: *const CcssTopology,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(topo, "topo")?.topo.num_edges()) }
    })
}

/// Writes the number of vertices of face `face` to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `topo` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_topology_face_size(
    topo: *const CcssTopology,
    face: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { try_handle(topo, "topo") }?;
        check_ptr(out as *const u32, "out")?;
        if face as usize >= t.topo.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", t.topo.face_size(face as usize) as u32) }
    })
}
