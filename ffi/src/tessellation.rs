//! Adaptive tessellation in the C ABI (`ccss_core::tessellate`).
//!
//! Same conventions as the rest of the ABI: statuses, optional error
//! details, caller memory with size queries, no allocation. A
//! `ccss_tessellation` lives at the start of its memory block; it refers to
//! its `ccss_evaluator` (and so to that evaluator's tables), which must stay
//! alive while it is used, but not to the `ccss_topology` (the connectivity
//! it needs is copied into its block). Unlike the other handles it is
//! mutable: `ccss_tessellation_emit` uses its block as working memory, so
//! one tessellation must not be emitted from two threads at once.
//! `ccss_tessellation_feature_required_bytes` / `_feature_build` make the
//! same handle for the surface of a `ccss_feature_evaluator` (which it then
//! refers to instead).

use crate::boundary::{
    block_bytes, check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_ref,
    try_slice_mut,
};
use crate::boundary::{try_handle, try_handle_mut};
use crate::evaluator::{CcssEvaluator, CcssEvaluatorQuery};
use crate::feature::CcssFeatureEvaluator;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use crate::topology::CcssTopology;
use ccss_core::eval::Query;
use ccss_core::tessellate::{
    uniform_depth, Criterion, Options, Output, PolygonCell, Scratch, Tessellation, MAX_LEVEL,
};
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, offset_of, size_of};

/// Deepest quadtree level of a tessellation.
pub const CCSS_TESSELLATION_MAX_LEVEL: u32 = 30;

/// When a cell of the tessellation is accepted (`ccss_tessellation_options.criterion`;
/// the numeric values are stable ABI).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssTessellationCriterion {
    /// Absolute flatness: the guaranteed distance bound between the limit
    /// surface and the output triangles is at most `tolerance` (model units).
    TESSELLATION_ABSOLUTE = 0,
    /// Relative flatness: bound / longer diagonal of each cell's corner quad
    /// at most `tolerance` (invariant under scaling and rotation; cells at an
    /// extraordinary vertex are accepted at `tolerance` times the diagonal of
    /// their sub-face).
    TESSELLATION_RELATIVE = 1,
    /// Every sub-face split uniformly to `uniform_level`.
    TESSELLATION_UNIFORM = 2,
}

/// Options of a tessellation.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssTessellationOptions {
    /// A `ccss_tessellation_criterion` (taken as `uint32_t`: any value is safe).
    pub criterion: u32,
    /// ABSOLUTE / RELATIVE: the tolerance (positive and finite).
    pub tolerance: f64,
    /// UNIFORM: the level.
    pub uniform_level: u32,
    /// Deepest level allowed, 1..=CCSS_TESSELLATION_MAX_LEVEL; 0 means
    /// CCSS_TESSELLATION_MAX_LEVEL. A tolerance that needs more fails with
    /// INVALID_ARGUMENT.
    pub max_level: u32,
}

/// Sizes and facts of a built tessellation (`ccss_tessellation_counts`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssTessellationCountsInfo {
    /// Vertices (`positions` holds 3 doubles per vertex).
    pub vertices: usize,
    /// Polygons (one per accepted parameter cell).
    pub polygons: usize,
    /// Sum of the polygon sizes.
    pub polygon_indices: usize,
    /// Triangles of the triangulated polygons (`polygon_indices - 2 polygons`).
    pub triangles: usize,
    /// Deepest accepted cell.
    pub max_level: u32,
    /// Guaranteed bound of the output (model units; 0 for UNIFORM, which
    /// computes no bounds).
    pub bound: f64,
    /// Largest bound / diagonal of an accepted cell (RELATIVE; else 0).
    pub max_ratio: f64,
}

/// The parameter cell of one output polygon: `[i/2^level, (i+1)/2^level] x
/// [j/2^level, (j+1)/2^level]` of sub-face `sub` of base face `face`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssTessellationCell {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// Quadtree level.
    pub level: u32,
    /// Cell index along u.
    pub i: u32,
    /// Cell index along v.
    pub j: u32,
}

/// Caller arrays for `ccss_tessellation_emit`; lengths count elements of the
/// pointed-to type. Optional arrays may be NULL (with any length).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct CcssTessellationOutput {
    /// x y z per vertex: at least `3 * vertices` doubles. Required.
    pub positions: *mut f64,
    /// Length of `positions` (doubles).
    pub positions_len: usize,
    /// Unit normal per vertex (`3 * vertices` doubles), optional.
    pub normals: *mut f64,
    /// Length of `normals` (doubles).
    pub normals_len: usize,
    /// `(face, sub, u, v)` of each vertex (`vertices`), optional.
    pub params: *mut CcssEvaluatorQuery,
    /// Length of `params`.
    pub params_len: usize,
    /// Vertex count of each polygon (`polygons`). Required.
    pub polygon_sizes: *mut u32,
    /// Length of `polygon_sizes`.
    pub polygon_sizes_len: usize,
    /// Vertex indices of all polygons, concatenated, counter-clockwise seen
    /// from outside (`polygon_indices`). Required.
    pub polygon_indices: *mut u32,
    /// Length of `polygon_indices`.
    pub polygon_indices_len: usize,
    /// Triangles, 3 indices each (`3 * triangles`), optional; polygon p
    /// gives `size(p) - 2` consecutive triangles, in polygon order.
    pub triangles: *mut u32,
    /// Length of `triangles` (indices).
    pub triangles_len: usize,
    /// Parameter cell of each polygon (`polygons`), optional.
    pub cells: *mut CcssTessellationCell,
    /// Length of `cells`.
    pub cells_len: usize,
}

/// An adaptive tessellation of one evaluator's limit surface (opaque; lives
/// at the start of its memory block).
pub struct CcssTessellation {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    t: Tessellation<'static>,
}

impl crate::boundary::Handle for CcssTessellation {
    const MAGIC: u64 = crate::boundary::magic(b"ccssTES1");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssTessellation, magic);
    const NAME: &'static str = "ccss_tessellation";
}

const TESS_HEAD: usize = round8(size_of::<CcssTessellation>());

const _: () = {
    assert!(size_of::<CcssTessellationCell>() == size_of::<PolygonCell>());
    assert!(align_of::<CcssTessellationCell>() == align_of::<PolygonCell>());
    assert!(offset_of!(CcssTessellationCell, face) == offset_of!(PolygonCell, face));
    assert!(offset_of!(CcssTessellationCell, sub) == offset_of!(PolygonCell, sub));
    assert!(offset_of!(CcssTessellationCell, level) == offset_of!(PolygonCell, level));
    assert!(offset_of!(CcssTessellationCell, i) == offset_of!(PolygonCell, i));
    assert!(offset_of!(CcssTessellationCell, j) == offset_of!(PolygonCell, j));
    assert!(size_of::<CcssEvaluatorQuery>() == size_of::<Query>());
    assert!(CCSS_TESSELLATION_MAX_LEVEL == MAX_LEVEL);
    assert!(align_of::<CcssTessellation>() <= 8);
    assert!(!needs_drop::<CcssTessellation>());
};

/// Core options of C options (validated).
fn core_options(o: &CcssTessellationOptions) -> Result<Options, Failure> {
    let max_level = if o.max_level == 0 {
        MAX_LEVEL
    } else {
        o.max_level
    };
    let criterion = match o.criterion {
        0 => Criterion::Absolute(o.tolerance),
        1 => Criterion::Relative(o.tolerance),
        2 => Criterion::Uniform(o.uniform_level),
        _ => {
            return Err(Failure::invalid(
                "criterion is not a ccss_tessellation_criterion",
            ))
        }
    };
    let opts = Options {
        criterion,
        max_level,
    };
    opts.validate()?;
    Ok(opts)
}

/// Writes to `*out` the number of bytes `ccss_tessellation_build` needs for
/// this topology (the one `ev` was built from), evaluator and options: the
/// marking runs to completion without storing anything (as expensive as
/// the marking of the build itself; uses about 60 KiB of stack).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (bad options; a
/// topology that is not the evaluator's; a tolerance that needs more than
/// `max_level` levels), MISSING_TABLE; details in `*detail` (may be NULL).
///
/// # Safety
/// `topo`, `ev` are NULL or live handles; `options` NULL or readable;
/// `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_required_bytes(
    topo: *const CcssTopology,
    ev: *const CcssEvaluator,
    options: *const CcssTessellationOptions,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (t, e, o) = unsafe {
            (
                try_handle(topo, "topo")?,
                try_handle(ev, "ev")?,
                try_ref(options, "options")?,
            )
        };
        check_ptr(out as *const usize, "out")?;
        let opts = core_options(o)?;
        let mut scratch = Scratch::ZERO;
        let core = Tessellation::required_bytes(&t.topo, &e.ev, &opts, &mut scratch)?;
        let total = block_bytes(core, TESS_HEAD, "tessellation too large")?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Marks the quadtrees of all sub-faces and prepares emission, in `mem`
/// (`mem_len` bytes, 8-byte aligned) and writes the handle (which equals `mem`)
/// to `*out`. `topo` must be the topology `ev` was built from; it is copied
/// (its block may be freed afterwards), `ev` is referred to.
///
/// A too-small `mem_len` fails with BUFFER_TOO_SMALL and `detail.required` =
/// the exact size (the marking then finishes in count-only mode) as soon as
/// `mem_len` covers the fixed part (the traversal scratch and the topology copy,
/// about 60 KiB plus 16 bytes per half-edge); below that, `required` is
/// that fixed part: call again with it (or use
/// `ccss_tessellation_required_bytes`).
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL, INVALID_ARGUMENT (as
/// `ccss_tessellation_required_bytes`), MISSING_TABLE. On failure `*out` is
/// not written and `mem`'s contents are unspecified.
///
/// Ownership: the caller owns `mem`; the handle is valid while `mem` stays
/// allocated and unmoved and the evaluator (and its tables) stay alive.
/// Nothing to destroy: free `mem` when done.
///
/// # Safety
/// `topo`, `ev` are NULL or live handles; `options` NULL or readable; `mem`
/// NULL or `mem_len` writable bytes not otherwise in use (not the blocks of the
/// other handles); `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_build(
    topo: *const CcssTopology,
    ev: *const CcssEvaluator,
    options: *const CcssTessellationOptions,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssTessellation,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the evaluator outlives the
        // tessellation by the C-side contract, hence 'static.
        let (t, e, o): (
            &CcssTopology,
            &'static CcssEvaluator,
            &CcssTessellationOptions,
        ) = unsafe {
            (
                try_handle(topo, "topo")?,
                try_handle(ev, "ev")?,
                try_ref(options, "options")?,
            )
        };
        check_ptr(out as *const *mut CcssTessellation, "out")?;
        let opts = core_options(o)?;
        let base = try_block(mem, mem_len, TESS_HEAD)?;
        // SAFETY: `base` is 8-aligned with `mem_len >= TESS_HEAD` writable bytes:
        // the handle at 0, the core arena after it; 'static by the C
        // contract.
        unsafe {
            let arena = core_mem(base, TESS_HEAD, mem_len)?;
            let tess =
                Tessellation::build(&t.topo, &e.ev, opts, arena).map_err(|err| match err {
                    ccss_core::Error::BufferTooSmall { required } => {
                        Failure::too_small(required.saturating_add(TESS_HEAD))
                    }
                    other => Failure::from(other),
                })?;
            let h = base as *mut CcssTessellation;
            h.write(CcssTessellation {
                magic: <CcssTessellation as crate::boundary::Handle>::MAGIC,
                t: tess,
            });
            *out = h;
        }
        Ok(())
    })
}

/// As `ccss_tessellation_required_bytes`, for the limit surface of a
/// `ccss_feature_evaluator` (creases, corners, boundaries, holes,
/// non-manifold parts): the bytes `ccss_tessellation_feature_build` needs.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (bad options; a
/// tolerance that needs more than `max_level` levels),
/// NEIGHBOURHOOD_TOO_LARGE; details in `*detail` (may be NULL).
///
/// # Safety
/// `fe` is NULL or a live handle; `options` NULL or readable; `out`,
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_feature_required_bytes(
    fe: *const CcssFeatureEvaluator,
    options: *const CcssTessellationOptions,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (e, o) = unsafe { (try_handle(fe, "fe")?, try_ref(options, "options")?) };
        check_ptr(out as *const usize, "out")?;
        let opts = core_options(o)?;
        let mut scratch = Scratch::ZERO;
        let core = Tessellation::required_bytes_feature(&e.ev, &opts, &mut scratch)?;
        let total = block_bytes(core, TESS_HEAD, "tessellation too large")?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// As `ccss_tessellation_build`, for the limit surface of a
/// `ccss_feature_evaluator`: marks the quadtrees of the sub-faces of every
/// face that is not a hole (cells next to irregular crease, corner,
/// boundary or extraordinary vertices are bounded by the convex hull of
/// their control points; RELATIVE also accepts such a cell at `tolerance`
/// times its sub-face's diagonal) and prepares emission, in `mem`. The
/// handle is emitted and queried with the other `ccss_tessellation_*`
/// functions. Hole faces produce nothing; an open mesh gives an open
/// output whose one-polygon edges lie on its boundary and hole borders; a
/// closed one a closed output.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (with the exact size
/// in `detail.required`, as `ccss_tessellation_build`), INVALID_ARGUMENT,
/// NEIGHBOURHOOD_TOO_LARGE. On failure `*out` is not written.
///
/// Ownership: the handle is valid while `mem` stays allocated and unmoved
/// and the feature evaluator stays alive.
///
/// # Safety
/// `fe` is NULL or a live handle; `options` NULL or readable; `mem` NULL or
/// `mem_len` writable bytes not otherwise in use; `out`, `detail` NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_feature_build(
    fe: *const CcssFeatureEvaluator,
    options: *const CcssTessellationOptions,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssTessellation,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the feature evaluator outlives
        // the tessellation by the C-side contract, hence 'static.
        let (e, o): (&'static CcssFeatureEvaluator, &CcssTessellationOptions) =
            unsafe { (try_handle(fe, "fe")?, try_ref(options, "options")?) };
        check_ptr(out as *const *mut CcssTessellation, "out")?;
        let opts = core_options(o)?;
        let base = try_block(mem, mem_len, TESS_HEAD)?;
        // SAFETY: as in `ccss_tessellation_build`.
        unsafe {
            let arena = core_mem(base, TESS_HEAD, mem_len)?;
            let tess =
                Tessellation::build_feature(&e.ev, opts, arena).map_err(|err| match err {
                    ccss_core::Error::BufferTooSmall { required } => {
                        Failure::too_small(required.saturating_add(TESS_HEAD))
                    }
                    other => Failure::from(other),
                })?;
            let h = base as *mut CcssTessellation;
            h.write(CcssTessellation {
                magic: <CcssTessellation as crate::boundary::Handle>::MAGIC,
                t: tess,
            });
            *out = h;
        }
        Ok(())
    })
}

/// Writes the output sizes and facts of a built tessellation to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `tess` is NULL or a live handle; `out` NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_counts(
    tess: *const CcssTessellation,
    out: *mut CcssTessellationCountsInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { try_handle(tess, "tess") }?;
        let (c, s) = (t.t.counts(), t.t.stats());
        let r = CcssTessellationCountsInfo {
            vertices: c.vertices,
            polygons: c.polygons,
            polygon_indices: c.polygon_indices,
            triangles: c.triangles,
            max_level: s.max_level,
            bound: s.bound,
            max_ratio: s.max_ratio,
        };
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", r) }
    })
}

/// Writes the tessellation into the arrays of `*output` (see
/// `ccss_tessellation_output`): vertices (exact limit points; normals and
/// `(face, sub, u, v)` optional), polygons counter-clockwise seen from
/// outside, optional triangles and polygon cells. Each non-NULL array must
/// hold at least what `ccss_tessellation_counts` says. May be called again.
///
/// All arrays are checked before anything is written: NULL_POINTER
/// (`positions`, `polygon_sizes`, `polygon_indices`), MISALIGNED,
/// INVALID_ARGUMENT (two arrays overlap, or one overlaps the tessellation's
/// block), BUFFER_TOO_SMALL (`detail.required` = the element count of the
/// first short array, in the order positions, normals, params, sizes,
/// indices, triangles, cells).
///
/// # Safety
/// `tess` is NULL or a live handle not used by another thread during the
/// call; `output` NULL or readable, its non-NULL pointers writable for
/// their lengths; `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_emit(
    tess: *mut CcssTessellation,
    output: *const CcssTessellationOutput,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises (`tess` is not used elsewhere
        // during the call).
        let (h, o) = unsafe { (try_handle_mut(tess, "tess")?, try_ref(output, "output")?) };
        if o.positions.is_null() {
            return Err(Failure::null("output->positions"));
        }
        if o.polygon_sizes.is_null() {
            return Err(Failure::null("output->polygon_sizes"));
        }
        if o.polygon_indices.is_null() {
            return Err(Failure::null("output->polygon_indices"));
        }
        let arrays: [(*const u8, usize); 7] = [
            (o.positions as *const u8, o.positions_len.saturating_mul(8)),
            (o.normals as *const u8, o.normals_len.saturating_mul(8)),
            (
                o.params as *const u8,
                o.params_len.saturating_mul(size_of::<CcssEvaluatorQuery>()),
            ),
            (
                o.polygon_sizes as *const u8,
                o.polygon_sizes_len.saturating_mul(4),
            ),
            (
                o.polygon_indices as *const u8,
                o.polygon_indices_len.saturating_mul(4),
            ),
            (o.triangles as *const u8, o.triangles_len.saturating_mul(4)),
            (
                o.cells as *const u8,
                o.cells_len
                    .saturating_mul(size_of::<CcssTessellationCell>()),
            ),
        ];
        let block = tess as *const u8;
        for (k, &(p, n)) in arrays.iter().enumerate() {
            if p.is_null() {
                continue;
            }
            if overlaps(p, n, block, TESS_HEAD) {
                return Err(Failure::invalid(
                    "an output array overlaps the tessellation",
                ));
            }
            for &(q, m) in &arrays[k + 1..] {
                if !q.is_null() && overlaps(p, n, q, m) {
                    return Err(Failure::invalid("two output arrays overlap"));
                }
            }
        }
        // SAFETY: forwarded caller promises; the arrays are disjoint (checked
        // above) and exclusively ours for the call.
        unsafe {
            let positions = try_slice_mut(o.positions, o.positions_len, "output->positions")?
                .ok_or(Failure::null("output->positions"))?;
            let normals = try_slice_mut(o.normals, o.normals_len, "output->normals")?;
            let params = try_slice_mut(o.params as *mut Query, o.params_len, "output->params")?;
            let sizes = try_slice_mut(
                o.polygon_sizes,
                o.polygon_sizes_len,
                "output->polygon_sizes",
            )?
            .ok_or(Failure::null("output->polygon_sizes"))?;
            let indices = try_slice_mut(
                o.polygon_indices,
                o.polygon_indices_len,
                "output->polygon_indices",
            )?
            .ok_or(Failure::null("output->polygon_indices"))?;
            let triangles = try_slice_mut(o.triangles, o.triangles_len, "output->triangles")?;
            let cells = try_slice_mut(o.cells as *mut PolygonCell, o.cells_len, "output->cells")?;
            h.t.emit(Output {
                positions,
                normals,
                params,
                polygon_sizes: sizes,
                polygon_indices: indices,
                triangles,
                cells,
            })?;
        }
        Ok(())
    })
}

/// Writes to `*out` the smallest uniform level L (from `from_level` up to
/// CCSS_TESSELLATION_MAX_LEVEL) such that every level-L cell of every sub-face
/// passes the test of `options` (so the uniform tessellation of level L
/// meets the same guaranteed bound), or `UINT32_MAX` if none does. The
/// adaptive tessellation's `max_level` is a lower bound: pass it as
/// `from_level`. Costs up to one test per uniform cell (uses about 60 KiB of
/// stack).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (bad options or
/// UNIFORM criterion), MISSING_TABLE.
///
/// # Safety
/// `ev` is NULL or a live handle; `options` NULL or readable; `out`,
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_uniform_depth(
    ev: *const CcssEvaluator,
    options: *const CcssTessellationOptions,
    from_level: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (e, o) = unsafe { (try_handle(ev, "ev")?, try_ref(options, "options")?) };
        check_ptr(out as *const u32, "out")?;
        let opts = core_options(o)?;
        if let Criterion::Uniform(_) = opts.criterion {
            return Err(Failure::invalid("uniform depth of a UNIFORM criterion"));
        }
        let mut scratch = Scratch::ZERO;
        let l = uniform_depth(&e.ev, opts.criterion, from_level, MAX_LEVEL, &mut scratch)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", l.unwrap_or(u32::MAX)) }
    })
}
