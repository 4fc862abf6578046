//! Similarity-based interpolation (Cheng & Lai report, ch. 4):
//! `ccss_interpolation_solve` writes a control mesh Q whose limit surface
//! passes through the vertices of a closed mesh P (Q has the topology of P
//! after one Catmull-Clark step), with optional positions and normals
//! prescribed anywhere.

use crate::boundary::{check_ptr, core_mem, guard, put, try_block, try_handle, try_ref, try_slice};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use crate::tables::CcssTables;
use crate::topology::CcssTopology;
use ccss_core::interpolate::{
    FoldRemoval, InterpolationOptions, Interpolator, Preconditioner, Prescribed, Requirement,
    SolveStats,
};
use ccss_core::mesh::refine::refined_counts;
use core::ffi::c_void;

/// A requirement of `ccss_interpolation_solve`: at parameter (u, v) of face
/// `face` of Q, the limit position (`kind` 0) equals `value`, or the limit
/// normal (`kind` 1) is parallel to `value`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssInterpolationRequirement {
    /// Face of Q (faces of P after one Catmull-Clark step).
    pub face: u32,
    /// 0: position, 1: normal.
    pub kind: u32,
    /// Parameter u in [0, 1].
    pub u: f64,
    /// Parameter v in [0, 1].
    pub v: f64,
    /// The position, or the normal direction (any non-zero length).
    pub value: [f64; 3],
}

/// Options of `ccss_interpolation_solve` (NULL: the defaults given here).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcssInterpolationOptions {
    /// The solve stops when its residual has dropped to this fraction of its
    /// start, in (0, 1). Default 1e-6.
    pub tolerance: f64,
    /// Iteration limit (at least 1); reaching it is ERR_NOT_CONVERGED.
    /// Default 10000.
    pub max_iterations: u32,
    /// 0: plain conjugate gradients, 1: block Jacobi (default).
    pub preconditioner: u32,
    /// Fold-removal rounds after the first solve (points whose limit normal
    /// is reversed against G's, or nearly so, get rows and the problem is
    /// re-solved; see `fold_rows`). Default (NULL options) 16; 0: no fold
    /// check (what a zero-initialised struct of the earlier layout asked
    /// for).
    pub fold_rounds: u32,
    /// First weight of a fold row; 0 selects the default 1 (anchor rows
    /// were measured best at 0.01); otherwise finite and > 0.
    pub fold_weight: f64,
    /// Check points per side of each face for the fold check; 0 selects the
    /// default 7; otherwise at least 2.
    pub fold_grid: u32,
    /// Rows of the fold rounds: 0 orientation rows (default), 1 anchor rows
    /// on folded faces (the earlier behaviour).
    pub fold_rows: u32,
}

/// What a solve did (see `ccss_interpolation_solve`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssInterpolationStats {
    /// Conjugate-gradient iterations.
    pub iterations: u32,
    /// Residual norm at the start and at the end.
    pub initial_residual: f64,
    /// Residual norm at the end.
    pub final_residual: f64,
    /// Similarity residual of the naive solution (G's Type II vertices).
    pub naive_objective: f64,
    /// Similarity residual of Q.
    pub objective: f64,
    /// Fold-removal rounds run.
    pub fold_rounds: u32,
    /// Check points where the normals of Q and G still disagree (0 unless
    /// the round limit was reached).
    pub folds: u32,
    /// Faces of Q carrying anchor rows at the end.
    pub anchored_faces: u32,
    /// Grid points carrying orientation rows at the end.
    pub orientation_rows: u32,
}

impl From<SolveStats> for CcssInterpolationStats {
    fn from(s: SolveStats) -> Self {
        CcssInterpolationStats {
            iterations: s.iterations,
            initial_residual: s.initial_residual,
            final_residual: s.final_residual,
            naive_objective: s.naive_objective,
            objective: s.objective,
            fold_rounds: s.fold_rounds,
            folds: s.folds,
            anchored_faces: s.anchored_faces,
            orientation_rows: s.orientation_rows,
        }
    }
}

/// The core requirements of `reqs` (INVALID_ARGUMENT for a kind not 0 or 1).
pub(crate) fn requirements(
    reqs: &[CcssInterpolationRequirement],
) -> Result<Vec<Requirement>, Failure> {
    reqs.iter()
        .map(|r| {
            Ok(Requirement {
                face: r.face,
                u: r.u,
                v: r.v,
                what: match r.kind {
                    0 => Prescribed::Position(r.value),
                    1 => Prescribed::Normal(r.value),
                    _ => return Err(Failure::invalid("requirement kind must be 0 or 1")),
                },
            })
        })
        .collect()
}

/// The core options of `options` (NULL: the defaults), checked.
///
/// # Safety
/// `options` is NULL or readable.
pub(crate) unsafe fn core_options(
    options: *const CcssInterpolationOptions,
) -> Result<InterpolationOptions, Failure> {
    let mut opts = InterpolationOptions::default();
    if !options.is_null() {
        // SAFETY: caller promise.
        let o = unsafe { try_ref(options, "options") }?;
        if o.max_iterations == 0 {
            return Err(Failure::invalid("max_iterations must be at least 1"));
        }
        opts.tolerance = o.tolerance;
        opts.max_iterations = o.max_iterations;
        opts.preconditioner = match o.preconditioner {
            0 => Preconditioner::None,
            1 => Preconditioner::BlockJacobi,
            _ => return Err(Failure::invalid("preconditioner must be 0 or 1")),
        };
        opts.fold_rounds = o.fold_rounds;
        if o.fold_weight != 0.0 {
            if !(o.fold_weight.is_finite() && o.fold_weight > 0.0) {
                return Err(Failure::invalid("fold_weight must be finite and > 0"));
            }
            opts.fold_weight = o.fold_weight;
        }
        opts.fold_removal = match o.fold_rows {
            0 => FoldRemoval::Orientation,
            1 => FoldRemoval::Anchors,
            _ => return Err(Failure::invalid("fold_rows must be 0 or 1")),
        };
        match o.fold_grid {
            0 => {}
            1 => return Err(Failure::invalid("fold_grid must be 0 or at least 2")),
            k => opts.fold_grid = k,
        }
        if !(opts.tolerance > 0.0 && opts.tolerance < 1.0) {
            return Err(Failure::invalid("tolerance must be in (0, 1)"));
        }
    }
    Ok(opts)
}

/// Writes the number of vertices and faces of Q (all quads) for P =
/// `topology`: `V + E + F` and the number of half-edges of P.
///
/// # Safety
/// `topology` is NULL or a live handle; the outs are NULL or writable;
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolation_counts(
    topology: *const CcssTopology,
    out_vertices: *mut usize,
    out_faces: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { try_handle(topology, "topology") }?;
        check_ptr(out_vertices as *const usize, "out_vertices")?;
        check_ptr(out_faces as *const usize, "out_faces")?;
        let c = refined_counts(&t.topo);
        // SAFETY: checked above.
        unsafe { put(out_vertices, "out_vertices", c.vertices) }?;
        // SAFETY: checked above.
        unsafe { put(out_faces, "out_faces", c.faces) }
    })
}

/// Writes to `*out_bytes` the size of the memory block
/// `ccss_interpolation_solve` needs for `topology` and these requirements.
///
/// # Safety
/// `topology` is NULL or a live handle; `reqs` is NULL (with `num_reqs`
/// 0) or points to `num_reqs` readable requirements; `out_bytes` is NULL
/// or writable; `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolation_required_bytes(
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
        let n = Interpolator::required_bytes(&t.topo, &r);
        // SAFETY: checked above.
        unsafe { put(out_bytes, "out_bytes", n) }
    })
}

/// Similarity-based interpolation of P = `topology` with the vertex rule of
/// `tables`: writes Q's control points (`3 * vertices` doubles, x y z; the
/// first vertices of P's count are the Type I vertices, in P's order) to
/// `out_positions` and its quads (`4 * faces` indices, 0-based) to
/// `out_indices` (counts from `ccss_interpolation_counts`). The limit
/// surface of Q passes through P's vertices; its first and second
/// derivatives follow those of P after one Catmull-Clark step (least
/// squares, conjugate gradients); `reqs` are met exactly.
///
/// Errors, in this order: NULL_POINTER / MISALIGNED (handles, `reqs`),
/// INVALID_ARGUMENT (options out of range, a requirement kind not 0 or 1),
/// the memory block's checks (`mem`, see `ccss_interpolation_required_bytes`),
/// BUFFER_TOO_SMALL (`out_positions_len` or `out_indices_len`; `required` in
/// elements), NULL_POINTER / MISALIGNED (outputs), INVALID_ARGUMENT (all of
/// P at one point), FACE_OUT_OF_RANGE / PARAMETER_OUT_OF_RANGE (a
/// requirement), CONFLICTING_REQUIREMENT (`detail.value` = its index),
/// NOT_CONVERGED. The outputs are written only on success; `stats` (NULL if
/// not wanted) too.
///
/// # Safety
/// Handles are NULL or live; `reqs` as in
/// `ccss_interpolation_required_bytes`; `options` is NULL or readable;
/// `mem` is NULL or `mem_len` writable bytes not otherwise in use during the
/// call; the outputs are NULL or hold their lengths in writable elements;
/// `stats` and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_interpolation_solve(
    topology: *const CcssTopology,
    tables: *const CcssTables,
    options: *const CcssInterpolationOptions,
    reqs: *const CcssInterpolationRequirement,
    num_reqs: usize,
    mem: *mut c_void,
    mem_len: usize,
    out_positions: *mut f64,
    out_positions_len: usize,
    out_indices: *mut u32,
    out_indices_len: usize,
    stats: *mut CcssInterpolationStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let t = unsafe { try_handle(topology, "topology") }?;
        // SAFETY: as above.
        let tb = unsafe { try_handle(tables, "tables") }?;
        // SAFETY: as above.
        let opts = unsafe { core_options(options) }?;
        // SAFETY: as above.
        let r = requirements(unsafe { try_slice(reqs, num_reqs, "reqs") }?)?;
        let need = Interpolator::required_bytes(&t.topo, &r);
        let base = try_block(mem, mem_len, need)?;
        let c = refined_counts(&t.topo);
        if out_positions_len < 3 * c.vertices {
            return Err(Failure::too_small(3 * c.vertices));
        }
        if out_indices_len < 4 * c.faces {
            return Err(Failure::too_small(4 * c.faces));
        }
        check_ptr(out_positions as *const f64, "out_positions")?;
        check_ptr(out_indices as *const u32, "out_indices")?;
        if !stats.is_null() {
            check_ptr(stats as *const CcssInterpolationStats, "stats")?;
        }
        // SAFETY: `base` is a checked block of `mem_len >= need` bytes.
        let words = unsafe { core_mem(base, 0, need) }?;
        let mut it = Interpolator::build(&t.topo, &tb.set, opts, &r, words)?;
        // SAFETY: non-NULL, aligned, the caller promises the lengths.
        let pos = unsafe { core::slice::from_raw_parts_mut(out_positions, 3 * c.vertices) };
        // Core writes `pos` only on success.
        let s = it.solve(pos, &mut |_, _| {})?;
        // SAFETY: as for `pos`.
        let idx = unsafe { core::slice::from_raw_parts_mut(out_indices, 4 * c.faces) };
        idx.copy_from_slice(&it.subdivided().indices()[..4 * c.faces]);
        if !stats.is_null() {
            // SAFETY: checked above.
            unsafe { put(stats, "stats", CcssInterpolationStats::from(s)) }?;
        }
        Ok(())
    })
}
