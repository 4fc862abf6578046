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

use super::{
    block_bytes, check_block, guard, handle, nonnull, overlaps, put, round8, CcssErrorDetail,
    CcssEvaluator, CcssQuery, CcssStatus, CcssTopology, Failure,
};
use ccss_core::eval::Query;
use ccss_core::tessellate::{
    uniform_depth, Criterion, Options, Output, PolygonCell, Scratch, Tessellation, MAX_LEVEL,
};
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, offset_of, size_of};
use core::ptr;

/// Deepest quadtree level of a tessellation.
pub const CCSS_TESS_MAX_LEVEL: u32 = 30;

/// When a cell of the tessellation is accepted (`ccss_tess_options.criterion`;
/// the numeric values are stable ABI).
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CcssTessCriterion {
    /// Absolute flatness: the guaranteed distance bound between the limit
    /// surface and the output triangles is at most `tolerance` (model units).
    TESS_ABSOLUTE = 0,
    /// Relative flatness: bound / longer diagonal of each cell's corner quad
    /// at most `tolerance` (invariant under scaling and rotation; cells at an
    /// extraordinary vertex are accepted at `tolerance` times the diagonal of
    /// their sub-face).
    TESS_RELATIVE = 1,
    /// Every sub-face split uniformly to `uniform_level`.
    TESS_UNIFORM = 2,
}

/// Options of a tessellation.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssTessOptions {
    /// A `ccss_tess_criterion` (taken as `uint32_t`: any value is safe).
    pub criterion: u32,
    /// ABSOLUTE / RELATIVE: the tolerance (positive and finite).
    pub tolerance: f64,
    /// UNIFORM: the level.
    pub uniform_level: u32,
    /// Deepest level allowed, 1..=CCSS_TESS_MAX_LEVEL; 0 means
    /// CCSS_TESS_MAX_LEVEL. A tolerance that needs more fails with
    /// INVALID_ARGUMENT.
    pub max_level: u32,
}

/// Sizes and facts of a built tessellation (`ccss_tessellation_counts`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssTessCounts {
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
pub struct CcssTessCell {
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
pub struct CcssTessOutput {
    /// x y z per vertex: at least `3 * vertices` doubles. Required.
    pub positions: *mut f64,
    /// Length of `positions` (doubles).
    pub positions_len: usize,
    /// Unit normal per vertex (`3 * vertices` doubles), optional.
    pub normals: *mut f64,
    /// Length of `normals` (doubles).
    pub normals_len: usize,
    /// `(face, sub, u, v)` of each vertex (`vertices`), optional.
    pub params: *mut CcssQuery,
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
    pub cells: *mut CcssTessCell,
    /// Length of `cells`.
    pub cells_len: usize,
}

/// An adaptive tessellation of one evaluator's limit surface (opaque; lives
/// at the start of its memory block).
pub struct CcssTessellation {
    t: Tessellation<'static>,
}

const TESS_HEAD: usize = round8(size_of::<CcssTessellation>());

const _: () = {
    assert!(size_of::<CcssTessCell>() == size_of::<PolygonCell>());
    assert!(align_of::<CcssTessCell>() == align_of::<PolygonCell>());
    assert!(offset_of!(CcssTessCell, face) == offset_of!(PolygonCell, face));
    assert!(offset_of!(CcssTessCell, sub) == offset_of!(PolygonCell, sub));
    assert!(offset_of!(CcssTessCell, level) == offset_of!(PolygonCell, level));
    assert!(offset_of!(CcssTessCell, i) == offset_of!(PolygonCell, i));
    assert!(offset_of!(CcssTessCell, j) == offset_of!(PolygonCell, j));
    assert!(size_of::<CcssQuery>() == size_of::<Query>());
    assert!(CCSS_TESS_MAX_LEVEL == MAX_LEVEL);
    assert!(align_of::<CcssTessellation>() <= 8);
    assert!(!needs_drop::<CcssTessellation>());
};

/// Core options of C options (validated).
fn options(o: &CcssTessOptions) -> Result<Options, Failure> {
    let max_level = if o.max_level == 0 {
        MAX_LEVEL
    } else {
        o.max_level
    };
    let criterion = match o.criterion {
        0 => Criterion::Absolute(o.tolerance),
        1 => Criterion::Relative(o.tolerance),
        2 => Criterion::Uniform(o.uniform_level),
        _ => return Err(Failure::invalid("criterion is not a ccss_tess_criterion")),
    };
    let opts = Options {
        criterion,
        max_level,
    };
    opts.validate()?;
    Ok(opts)
}

/// A mutable output array of `n` elements (`None` for NULL).
///
/// # Safety
/// Unless NULL, `p` points to `n` writable `T` not otherwise in use.
unsafe fn out_slice<'a, T>(
    p: *mut T,
    n: usize,
    arg: &'static str,
) -> Result<Option<&'a mut [T]>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    nonnull(p as *const T, arg)?;
    if n.checked_mul(size_of::<T>())
        .map_or(true, |b| b > isize::MAX as usize)
    {
        return Err(Failure::invalid("array length too large"));
    }
    // SAFETY: non-NULL, aligned, and the caller promises `n` writable
    // elements, exclusively ours for the call.
    Ok(Some(unsafe { core::slice::from_raw_parts_mut(p, n) }))
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
    options_in: *const CcssTessOptions,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (t, e, o) = unsafe {
            (
                handle(topo, "topo")?,
                handle(ev, "ev")?,
                handle(options_in, "options")?,
            )
        };
        nonnull(out as *const usize, "out")?;
        let opts = options(o)?;
        let mut scratch = Scratch::ZERO;
        let core = Tessellation::required_bytes(&t.topo, &e.ev, &opts, &mut scratch)?;
        let total = block_bytes(core, TESS_HEAD, "tessellation too large")?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Marks the quadtrees of all sub-faces and prepares emission, in `mem`
/// (`len` bytes, 8-byte aligned) and writes the handle (which equals `mem`)
/// to `*out`. `topo` must be the topology `ev` was built from; it is copied
/// (its block may be freed afterwards), `ev` is referred to.
///
/// A too-small `len` fails with BUFFER_TOO_SMALL and `detail.required` =
/// the exact size (the marking then finishes in count-only mode) as soon as
/// `len` covers the fixed part (the traversal scratch and the topology copy,
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
/// NULL or `len` writable bytes not otherwise in use (not the blocks of the
/// other handles); `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_build(
    topo: *const CcssTopology,
    ev: *const CcssEvaluator,
    options_in: *const CcssTessOptions,
    mem: *mut c_void,
    len: usize,
    out: *mut *mut CcssTessellation,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the evaluator outlives the
        // tessellation by the C-side contract, hence 'static.
        let (t, e, o): (&CcssTopology, &'static CcssEvaluator, &CcssTessOptions) = unsafe {
            (
                handle(topo, "topo")?,
                handle(ev, "ev")?,
                handle(options_in, "options")?,
            )
        };
        nonnull(out as *const *mut CcssTessellation, "out")?;
        let opts = options(o)?;
        let base = check_block(mem, len, TESS_HEAD)?;
        // SAFETY: `base` is 8-aligned with `len >= TESS_HEAD` writable bytes:
        // the handle at 0, the core arena after it; 'static by the C
        // contract.
        unsafe {
            let arena = crate::block_words(base, TESS_HEAD, len);
            let tess =
                Tessellation::build(&t.topo, &e.ev, opts, arena).map_err(|err| match err {
                    ccss_core::Error::BufferTooSmall { required } => {
                        Failure::too_small(required.saturating_add(TESS_HEAD))
                    }
                    other => Failure::from(other),
                })?;
            let h = base as *mut CcssTessellation;
            h.write(CcssTessellation { t: tess });
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
#[no_mangle]
pub unsafe extern "C" fn ccss_tessellation_counts(
    tess: *const CcssTessellation,
    out: *mut CcssTessCounts,
) -> CcssStatus {
    guard(ptr::null_mut(), || {
        // SAFETY: forwarded caller promise.
        let t = unsafe { handle(tess, "tess") }?;
        let (c, s) = (t.t.counts(), t.t.stats());
        let r = CcssTessCounts {
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
/// `ccss_tess_output`): vertices (exact limit points; normals and
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
    output: *const CcssTessOutput,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        nonnull(tess as *const CcssTessellation, "tess")?;
        // SAFETY: forwarded caller promise.
        let o = unsafe { handle(output, "output") }?;
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
            (o.positions as *const u8, 8 * o.positions_len),
            (o.normals as *const u8, 8 * o.normals_len),
            (o.params as *const u8, size_of::<CcssQuery>() * o.params_len),
            (o.polygon_sizes as *const u8, 4 * o.polygon_sizes_len),
            (o.polygon_indices as *const u8, 4 * o.polygon_indices_len),
            (o.triangles as *const u8, 4 * o.triangles_len),
            (
                o.cells as *const u8,
                size_of::<CcssTessCell>() * o.cells_len,
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
            let t = &mut (*tess).t;
            let positions = out_slice(o.positions, o.positions_len, "output->positions")?
                .ok_or(Failure::null("output->positions"))?;
            let normals = out_slice(o.normals, o.normals_len, "output->normals")?;
            let params = out_slice(o.params as *mut Query, o.params_len, "output->params")?;
            let sizes = out_slice(
                o.polygon_sizes,
                o.polygon_sizes_len,
                "output->polygon_sizes",
            )?
            .ok_or(Failure::null("output->polygon_sizes"))?;
            let indices = out_slice(
                o.polygon_indices,
                o.polygon_indices_len,
                "output->polygon_indices",
            )?
            .ok_or(Failure::null("output->polygon_indices"))?;
            let triangles = out_slice(o.triangles, o.triangles_len, "output->triangles")?;
            let cells = out_slice(o.cells as *mut PolygonCell, o.cells_len, "output->cells")?;
            t.emit(Output {
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
/// CCSS_TESS_MAX_LEVEL) such that every level-L cell of every sub-face
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
    options_in: *const CcssTessOptions,
    from_level: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (e, o) = unsafe { (handle(ev, "ev")?, handle(options_in, "options")?) };
        nonnull(out as *const u32, "out")?;
        let opts = options(o)?;
        if let Criterion::Uniform(_) = opts.criterion {
            return Err(Failure::invalid("uniform depth of a UNIFORM criterion"));
        }
        let mut scratch = Scratch::ZERO;
        let l = uniform_depth(&e.ev, opts.criterion, from_level, MAX_LEVEL, &mut scratch)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", l.unwrap_or(u32::MAX)) }
    })
}

#[cfg(test)]
mod tests {
    use super::super::*;
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
    fn tessellate_through_the_abi_without_allocating() {
        let (p, s, i) = cube();
        let (mut tb, mut gb, mut eb, mut nb) = (0usize, 0usize, 0usize, 0usize);
        let mut d = Failure::invalid("x").to_detail();
        let opts = CcssTessOptions {
            criterion: 0,
            tolerance: 1e-3,
            uniform_level: 0,
            max_level: 0,
        };
        unsafe {
            assert_eq!(ccss_tables_required_bytes(&mut tb), CcssStatus::OK);
            assert_eq!(
                ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb),
                CcssStatus::OK
            );
        }
        let (mut tm, mut gm) = (block(tb), block(gb));
        let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
        let mut tess: *mut CcssTessellation = ptr::null_mut();
        unsafe {
            assert_eq!(
                ccss_tables_build_standard(tm.as_mut_ptr().cast(), tb, &mut tables),
                CcssStatus::OK
            );
            let st = ccss_topology_build(
                p.as_ptr(),
                8,
                s.as_ptr(),
                6,
                i.as_ptr(),
                24,
                gm.as_mut_ptr().cast(),
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
        let mut em = block(eb);
        unsafe {
            let st =
                ccss_evaluator_build(topo, tables, em.as_mut_ptr().cast(), eb, &mut ev, &mut d);
            assert_eq!(st, CcssStatus::OK);
        }
        // Size query, then a too-small block reports the same exact size.
        unsafe {
            assert_eq!(
                ccss_tessellation_required_bytes(topo, ev, &opts, &mut nb, &mut d),
                CcssStatus::OK
            );
        }
        let mut small = block(nb - 8);
        let st = unsafe {
            ccss_tessellation_build(
                topo,
                ev,
                &opts,
                small.as_mut_ptr().cast(),
                nb - 8,
                &mut tess,
                &mut d,
            )
        };
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(d.required as usize, nb);
        assert!(tess.is_null());
        let mut nm = block(nb);
        let mut c = CcssTessCounts::default();
        unsafe {
            let st = ccss_tessellation_build(
                topo,
                ev,
                &opts,
                nm.as_mut_ptr().cast(),
                nb,
                &mut tess,
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(ccss_tessellation_counts(tess, &mut c), CcssStatus::OK);
        }
        assert!(
            c.bound <= 1e-3 && c.polygons > 0 && c.triangles == c.polygon_indices - 2 * c.polygons
        );
        let mut pos = vec![0.0; 3 * c.vertices];
        let mut sizes = vec![0u32; c.polygons];
        let mut idx = vec![0u32; c.polygon_indices];
        let mut tri = vec![0u32; 3 * c.triangles];
        let mut cells = vec![CcssTessCell::default(); c.polygons];
        let mut o = CcssTessOutput {
            positions: pos.as_mut_ptr(),
            positions_len: pos.len(),
            normals: ptr::null_mut(),
            normals_len: 0,
            params: ptr::null_mut(),
            params_len: 0,
            polygon_sizes: sizes.as_mut_ptr(),
            polygon_sizes_len: sizes.len(),
            polygon_indices: idx.as_mut_ptr(),
            polygon_indices_len: idx.len(),
            triangles: tri.as_mut_ptr(),
            triangles_len: tri.len(),
            cells: cells.as_mut_ptr(),
            cells_len: cells.len(),
        };
        let before = alloc_count::get();
        let mut level = 0u32;
        unsafe {
            assert_eq!(ccss_tessellation_emit(tess, &o, &mut d), CcssStatus::OK);
            assert_eq!(
                ccss_tessellation_uniform_depth(ev, &opts, c.max_level, &mut level, &mut d),
                CcssStatus::OK
            );
        }
        assert_eq!(alloc_count::get(), before, "emission allocated");
        assert!(level >= c.max_level && level != u32::MAX);
        assert_eq!(
            sizes.iter().map(|&x| x as usize).sum::<usize>(),
            c.polygon_indices
        );
        assert!(cells.iter().all(|x| x.level <= c.max_level && x.face < 6));
        // Errors write nothing and name the problem.
        o.triangles_len -= 1;
        let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(d.required as usize, 3 * c.triangles);
        o.triangles_len += 1;
        o.cells = idx.as_mut_ptr().cast();
        let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        o.cells = ptr::null_mut();
        o.positions = ptr::null_mut();
        let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        for bad in [
            CcssTessOptions {
                criterion: 7,
                ..opts
            },
            CcssTessOptions {
                tolerance: -1.0,
                ..opts
            },
            CcssTessOptions {
                tolerance: f64::NAN,
                ..opts
            },
            CcssTessOptions {
                max_level: 31,
                ..opts
            },
            CcssTessOptions {
                tolerance: 1e-300,
                max_level: 3,
                ..opts
            },
        ] {
            let st = unsafe { ccss_tessellation_required_bytes(topo, ev, &bad, &mut nb, &mut d) };
            assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "{bad:?}");
        }
        let st = unsafe { ccss_tessellation_counts(ptr::null(), &mut c) };
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
    }
}
