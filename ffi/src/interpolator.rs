//! `ccss_interpolator`: similarity-based interpolation (Cheng & Lai
//! report, ch. 4) as a handle, for the assembled normal matrix: build, ask
//! the matrix's size, assemble it into a second caller block, solve. The
//! solution is that of `ccss_interpolation_solve` (matrix-free) to the
//! convergence tolerance, in the same iterations, several times faster
//! (BENCHMARKS.md "Similarity-based interpolation"). The matrix's size is
//! counted while building, which is why it needs a handle.

use crate::boundary::{
    block_bytes, check_ptr, core_mem, guard, put, round8, try_block, try_handle, try_handle_mut,
    try_slice,
};
use crate::interpolation::{
    core_options, requirements, CcssInterpolationOptions, CcssInterpolationRequirement,
    CcssInterpolationStats,
};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use crate::tables::CcssTables;
use crate::topology::CcssTopology;
use ccss_core::interpolate::Interpolator;
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// An interpolation problem ready to solve (opaque; lives at the start of
/// its memory block).
pub struct CcssInterpolator {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    it: Interpolator<'static>,
}

impl crate::boundary::Handle for CcssInterpolator {
    const MAGIC: u64 = crate::boundary::magic(b"ccssINT1");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssInterpolator, magic);
    const NAME: &'static str = "ccss_interpolator";
}

const HEAD: usize = round8(size_of::<CcssInterpolator>());

const _: () = {
    assert!(align_of::<CcssInterpolator>() <= 8);
    assert!(!needs_drop::<CcssInterpolator>());
};

/// Writes to `*out_bytes` the size of the block `ccss_interpolator_build`
/// needs for `topology` and these requirements.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_HANDLE, INVALID_ARGUMENT (a
/// requirement kind not 0 or 1).
///
/// # Safety
/// `topology` is NULL or a live handle; `reqs` is NULL (with `num_reqs` 0)
/// or points to `num_reqs` readable requirements; `out_bytes` and `detail`
/// are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolator_required_bytes(
    topology: *const CcssTopology,
    reqs: *const CcssInterpolationRequirement,
    num_reqs: usize,
    out_bytes: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { try_handle(topology, "topology") }?;
        // SAFETY: forwarded caller promise.
        let r = requirements(unsafe { try_slice(reqs, num_reqs, "reqs") }?)?;
        check_ptr(out_bytes as *const usize, "out_bytes")?;
        let n = block_bytes(
            Interpolator::required_bytes(&t.topo, &r),
            HEAD,
            "interpolator too large",
        )?;
        // SAFETY: checked above.
        unsafe { put(out_bytes, "out_bytes", n) }
    })
}

/// Subdivides P = `topology` once with the vertex rule of `tables`,
/// prepares the similarity system of `ccss_interpolation_solve` (same
/// `options`, NULL: defaults, and `reqs`) in `mem` and writes the handle
/// (which equals `mem`) to `*out`. The handle refers to `tables` (keep
/// them alive) but not to `topology` nor `reqs`.
///
/// Errors, in this order: NULL_POINTER / MISALIGNED / INVALID_HANDLE
/// (handles, `reqs`, `out`), INVALID_ARGUMENT (options, a requirement
/// kind), the memory block's checks (BUFFER_TOO_SMALL: `detail.required` =
/// bytes), INVALID_ARGUMENT (all of P at one point), FACE_OUT_OF_RANGE /
/// PARAMETER_OUT_OF_RANGE (a requirement), CONFLICTING_REQUIREMENT. On
/// failure `*out` is not written.
///
/// # Safety
/// Handles are NULL or live; `reqs` as in
/// `ccss_interpolator_required_bytes`; `options` is NULL or readable; `mem`
/// is NULL or `mem_len` writable bytes not otherwise in use while the
/// handle lives; `out` and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolator_build(
    topology: *const CcssTopology,
    tables: *const CcssTables,
    options: *const CcssInterpolationOptions,
    reqs: *const CcssInterpolationRequirement,
    num_reqs: usize,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssInterpolator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the tables outlive the handle
        // by the C contract, hence 'static.
        let t = unsafe { try_handle(topology, "topology") }?;
        // SAFETY: as above.
        let tb: &'static CcssTables = unsafe { try_handle(tables, "tables") }?;
        // SAFETY: as above.
        let r = requirements(unsafe { try_slice(reqs, num_reqs, "reqs") }?)?;
        check_ptr(out as *const *mut CcssInterpolator, "out")?;
        // SAFETY: as above.
        let opts = unsafe { core_options(options) }?;
        let need = block_bytes(
            Interpolator::required_bytes(&t.topo, &r),
            HEAD,
            "interpolator too large",
        )?;
        let base = try_block(mem, mem_len, need)?;
        // SAFETY: `base` is 8-aligned with `mem_len >= need` writable bytes,
        // ours while the handle lives: the handle at 0, the core arena after.
        unsafe {
            let arena = core_mem(base, HEAD, need)?;
            let it = Interpolator::build(&t.topo, &tb.set, opts, &r, arena)?;
            let h = base as *mut CcssInterpolator;
            h.write(CcssInterpolator {
                magic: <CcssInterpolator as crate::boundary::Handle>::MAGIC,
                it,
            });
            *out = h;
        }
        Ok(())
    })
}

/// Writes to `*out_bytes` the size of the block `ccss_interpolator_assemble`
/// needs (exact, counted by the build).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_HANDLE.
///
/// # Safety
/// `interpolator` is NULL or a live handle; `out_bytes` and `detail` are
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolator_matrix_required_bytes(
    interpolator: *const CcssInterpolator,
    out_bytes: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let h = unsafe { try_handle(interpolator, "interpolator") }?;
        // SAFETY: forwarded caller promise.
        unsafe { put(out_bytes, "out_bytes", h.it.assembled_bytes()) }
    })
}

/// Assembles the normal matrix of the similarity system into `mem` (at
/// least `ccss_interpolator_matrix_required_bytes`, 8-byte aligned): later
/// solves multiply with it. The handle then refers to `mem` (keep it alive
/// and unmodified while the handle is used; assembling again into another
/// block releases the first one).
///
/// Errors: NULL_POINTER / MISALIGNED / INVALID_HANDLE (`interpolator`),
/// the memory block's checks (BUFFER_TOO_SMALL: `detail.required` =
/// bytes). On failure the handle is unchanged.
///
/// # Safety
/// `interpolator` is NULL or a live handle not otherwise in use during the
/// call; `mem` is NULL or `mem_len` writable bytes not otherwise in use
/// while the handle lives; `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolator_assemble(
    interpolator: *mut CcssInterpolator,
    mem: *mut c_void,
    mem_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let h = unsafe { try_handle_mut(interpolator, "interpolator") }?;
        let need = h.it.assembled_bytes();
        let base = try_block(mem, mem_len, need)?;
        // SAFETY: a checked block of `mem_len >= need` bytes, ours while
        // the handle lives (C contract), hence 'static.
        let words = unsafe { core_mem(base, 0, need) }?;
        h.it.assemble(words)?;
        Ok(())
    })
}

/// Solves the interpolation of the handle (with the assembled matrix if
/// `ccss_interpolator_assemble` ran, matrix-free otherwise) and writes Q as
/// `ccss_interpolation_solve` does: `3 * vertices` doubles to
/// `out_positions`, `4 * faces` indices to `out_indices` (counts from
/// `ccss_interpolation_counts`), `stats` if non-NULL. May be called again
/// (same result).
///
/// Errors, in this order: NULL_POINTER / MISALIGNED / INVALID_HANDLE
/// (`interpolator`), BUFFER_TOO_SMALL (`out_positions_len` or
/// `out_indices_len`; `required` in elements), NULL_POINTER / MISALIGNED
/// (outputs), CONFLICTING_REQUIREMENT, NOT_CONVERGED. The outputs are
/// written only on success.
///
/// # Safety
/// `interpolator` is NULL or a live handle not otherwise in use during the
/// call; the outputs are NULL or hold their lengths in writable elements;
/// `stats` and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolator_solve(
    interpolator: *mut CcssInterpolator,
    out_positions: *mut f64,
    out_positions_len: usize,
    out_indices: *mut u32,
    out_indices_len: usize,
    stats: *mut CcssInterpolationStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let h = unsafe { try_handle_mut(interpolator, "interpolator") }?;
        let nv = h.it.num_vertices();
        let nf = h.it.subdivided().num_faces();
        if out_positions_len < 3 * nv {
            return Err(Failure::too_small(3 * nv));
        }
        if out_indices_len < 4 * nf {
            return Err(Failure::too_small(4 * nf));
        }
        check_ptr(out_positions as *const f64, "out_positions")?;
        check_ptr(out_indices as *const u32, "out_indices")?;
        if !stats.is_null() {
            check_ptr(stats as *const CcssInterpolationStats, "stats")?;
        }
        // SAFETY: non-NULL, aligned, the caller promises the lengths.
        let pos = unsafe { core::slice::from_raw_parts_mut(out_positions, 3 * nv) };
        // Core writes `pos` only on success.
        let s = h.it.solve(pos, &mut |_, _| {})?;
        // SAFETY: as for `pos`.
        let idx = unsafe { core::slice::from_raw_parts_mut(out_indices, 4 * nf) };
        idx.copy_from_slice(&h.it.subdivided().indices()[..4 * nf]);
        if !stats.is_null() {
            // SAFETY: checked above.
            unsafe { ptr::write(stats, CcssInterpolationStats::from(s)) };
        }
        Ok(())
    })
}
