//! C ABI of voxelization, flooding, voxel runs and integral properties
//! (ccss-core's `voxel` module).
//!
//! A `ccss_voxel_grid` lives at the start of a caller block of
//! `ccss_voxel_grid_required_bytes` bytes (8-byte aligned): the handle, the
//! fixed work area of the recursion (about 60 KiB) and the bit planes of the
//! frame buffer (three bits per voxel). A grid is either the whole grid
//! (`z0 = 0`, `z1 = res[2]`) or a z-slab `[z0, z1)` (memory proportional to
//! the slab; its voxels and runs equal those of the whole grid). Unlike the
//! other handles a grid is **mutable**: `ccss_voxel_grid_voxelize` and
//! `ccss_voxel_grid_flood` write into it; do not use one grid from two threads at
//! once. It does not refer to the evaluator between calls (pass the same
//! evaluator to voxelize and flood).
//!
//! Typical use:
//!
//! ```c
//! uint32_t res[3] = {256, 256, 256};
//! size_t n; ccss_voxel_grid_required_bytes(res, 0, res[2], &n, &detail);
//! void *gm = malloc(n); ccss_voxel_grid *g;
//! ccss_voxel_grid_build(res, 0, res[2], gm, n, &g, &detail);
//! ccss_voxel_grid_voxelize(ev, g, 6, 8, NULL, &stats, &detail);      // NULL: normalise into the grid
//! uint32_t stack[4096]; ccss_voxel_grid_flood(ev, g, stack, 4096, &fstats, &detail);
//! ccss_voxel_grid_counts(g, &surface, &interior, &detail);
//! ```

use crate::boundary::{
    block_bytes, check_len, check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_ref,
    try_slice,
};
use crate::boundary::{try_handle, try_handle_mut};
use crate::evaluator::CcssEvaluator;
use crate::feature::CcssFeatureEvaluator;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::voxel::{
    mass_properties, Adjacency, GridState, Surface, VoxelGrid, VoxelParams, VoxelRun,
    VoxelTransform, VoxelWork,
};
use core::ffi::{c_int, c_void};
use core::mem::{align_of, needs_drop, offset_of, size_of};
use core::ptr;

/// Tolerance of the voxelizer's "no holes" certificate, in voxels
/// (ccss-core's `voxel::TAU`): every point of the limit surface has a
/// surface voxel within this max-norm distance (6-adjacency), or within this
/// distance along each voxel centre line it crosses (18/26-adjacency). So
/// white voxel centres are at least `0.5 - CCSS_VOXEL_GRID_TAU` voxels from the
/// surface along the centre lines.
pub const CCSS_VOXEL_GRID_TAU: f64 = 1e-6;

/// Model-to-voxel map `v = scale * p + offset`: voxel `(i, j, k)` is the
/// unit cube centred at the integer point `(i, j, k)`; it covers the model
/// box `[(i - 1/2 - offset[0]) / scale, (i + 1/2 - offset[0]) / scale)` (same
/// for y, z).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssVoxelGridTransform {
    /// Voxels per model unit.
    pub scale: f64,
    /// Voxel coordinates of the model origin.
    pub offset: [f64; 3],
}

impl From<VoxelTransform> for CcssVoxelGridTransform {
    fn from(t: VoxelTransform) -> Self {
        CcssVoxelGridTransform {
            scale: t.scale,
            offset: t.offset,
        }
    }
}

/// What `ccss_voxel_grid_voxelize` did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssVoxelGridVoxelizeStats {
    /// Cells visited by the paper's recursion.
    pub cells: u64,
    /// Its leaves.
    pub leaves: u64,
    /// Voxels the certification pass had to look at.
    pub uncovered: u64,
    /// Cells of the certification pass.
    pub refined: u64,
    /// Cells where the certification gave up at the depth limit (0 means
    /// the no-holes guarantee holds everywhere).
    pub guard_hits: u64,
    /// Deepest cell below a pre-split cell.
    pub max_depth: u32,
    /// The paper's area estimate (sum of the final recursion quads, model
    /// units, cells whose first corner lies in the slab).
    pub quad_area: f64,
}

/// What `ccss_voxel_grid_flood` did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssVoxelGridFloodStats {
    /// White regions not reached from the grid border (one ray test each).
    pub enclosed_components: u32,
    /// Of those, regions classified inside.
    pub inside_components: u32,
    /// Rays cast.
    pub rays: u32,
    /// Regions whose rays were all degenerate (taken as outside).
    pub unresolved: u32,
    /// Linear sweeps run because the stack overflowed.
    pub sweeps: u32,
    /// Rows processed.
    pub row_visits: u64,
}

/// One run of voxels of one class: voxels `x0 .. x1` (exclusive) of row
/// `(y, z)`; `voxel_class` 1 = surface, 2 = interior. Runs are ordered by
/// z, then y, then x.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CcssVoxelGridRun {
    /// First voxel.
    pub x0: u32,
    /// One past the last voxel.
    pub x1: u32,
    /// Row y.
    pub y: u32,
    /// Row z.
    pub z: u32,
    /// 1 = surface, 2 = interior.
    pub voxel_class: u32,
}

/// Exact integral properties of the solid (`ccss_mass_properties_compute`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssMassProperties {
    /// Volume (negative if the faces are oriented inward).
    pub volume: f64,
    /// Area of the limit surface.
    pub area: f64,
    /// Centroid.
    pub centroid: [f64; 3],
    /// Inertia tensor about the centroid for unit density
    /// (`Ixx, Iyy, Izz, Ixy, Iyz, Izx`, `Ixy = -∫ x y dV`); multiply by the
    /// density for a mass-weighted tensor (mass = density x volume).
    pub inertia: [f64; 6],
    /// Bound of the volume error.
    pub volume_error_bound: f64,
    /// Bound of the area error (corner squares plus the adaptive area
    /// quadrature's estimate).
    pub area_error_bound: f64,
    /// Bound of the centroid error.
    pub centroid_error_bound: f64,
    /// Bound of each inertia entry's error (unit density).
    pub inertia_error_bound: f64,
    /// 1 if every corner bound is rigorous (0 only for general weights with
    /// a complex eigenvalue pair).
    pub rigorous: c_int,
}

/// A voxel frame buffer (opaque; lives at the start of its memory block).
pub struct CcssVoxelGrid {
    /// The one field (at offset 0, checked below): C layout inside, so the
    /// magic word is the block's first 8 bytes.
    inner: GridInner,
}

/// The handle's contents in C layout (magic first).
#[repr(C)]
#[doc(hidden)]
pub struct GridInner {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// Bytes of the caller block (for the overlap check of outputs).
    block_len: usize,
    grid: VoxelGrid<'static>,
    work: VoxelWork,
}

impl core::ops::Deref for CcssVoxelGrid {
    type Target = GridInner;
    fn deref(&self) -> &GridInner {
        &self.inner
    }
}

impl core::ops::DerefMut for CcssVoxelGrid {
    fn deref_mut(&mut self) -> &mut GridInner {
        &mut self.inner
    }
}

impl crate::boundary::Handle for CcssVoxelGrid {
    const MAGIC: u64 = crate::boundary::magic(b"ccssVOX1");
    const MAGIC_OFFSET: usize = offset_of!(CcssVoxelGrid, inner) + offset_of!(GridInner, magic);
    const NAME: &'static str = "ccss_voxel_grid";
}

const _: () = assert!(<CcssVoxelGrid as crate::boundary::Handle>::MAGIC_OFFSET == 0);

const GRID_HEAD: usize = round8(size_of::<CcssVoxelGrid>());

const _: () = {
    assert!(CCSS_VOXEL_GRID_TAU == ccss_core::voxel::TAU);
    assert!(size_of::<CcssVoxelGridRun>() == size_of::<VoxelRun>());
    assert!(align_of::<CcssVoxelGridRun>() == align_of::<VoxelRun>());
    assert!(offset_of!(CcssVoxelGridRun, x0) == offset_of!(VoxelRun, x0));
    assert!(offset_of!(CcssVoxelGridRun, x1) == offset_of!(VoxelRun, x1));
    assert!(offset_of!(CcssVoxelGridRun, y) == offset_of!(VoxelRun, y));
    assert!(offset_of!(CcssVoxelGridRun, z) == offset_of!(VoxelRun, z));
    assert!(offset_of!(CcssVoxelGridRun, voxel_class) == offset_of!(VoxelRun, class));
    assert!(align_of::<CcssVoxelGrid>() <= 8);
    assert!(!needs_drop::<CcssVoxelGrid>());
};

/// Reads `res[0..3]`.
///
/// # Safety
/// `res` is NULL or points to three readable `uint32_t`.
unsafe fn read_res(res: *const u32) -> Result<[u32; 3], Failure> {
    // SAFETY: forwarded caller promise (three readable elements).
    let r = unsafe { try_slice(res, 3, "res") }?;
    Ok([r[0], r[1], r[2]])
}

fn grid_bytes(res: [u32; 3], z0: u32, z1: u32) -> Result<usize, Failure> {
    block_bytes(
        VoxelGrid::slab_required_bytes(res, z0, z1)?,
        GRID_HEAD,
        "voxel grid too large",
    )
}

/// Writes to `*out` the bytes `ccss_voxel_grid_build` needs for resolution
/// `res[0] x res[1] x res[2]` (each 2..=65536) and the z-slab `[z0, z1)`
/// (`z0 = 0, z1 = res[2]` for the whole grid): the handle, the work area
/// and three bits per held voxel (the slab plus 3 layers on each side).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (resolution, slab, too
/// large).
///
/// # Safety
/// `res` is NULL or points to three `uint32_t`; `out` NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_required_bytes(
    res: *const u32,
    z0: u32,
    z1: u32,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let r = unsafe { read_res(res) }?;
        check_ptr(out as *const usize, "out")?;
        let n = grid_bytes(r, z0, z1)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", n) }
    })
}

/// Initialises an empty grid (or z-slab `[z0, z1)`) in `mem` (`mem_len` bytes,
/// 8-byte aligned, at least `ccss_voxel_grid_required_bytes`) and writes the
/// handle (which equals `mem`) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// bytes), INVALID_ARGUMENT. On failure `*out` is not written.
///
/// Ownership: the caller owns `mem`; nothing to destroy.
///
/// # Safety
/// `res` points to three `uint32_t`; `mem` is NULL or `mem_len` writable bytes not
/// otherwise in use; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_build(
    res: *const u32,
    z0: u32,
    z1: u32,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssVoxelGrid,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let r = unsafe { read_res(res) }?;
        check_ptr(out as *const *mut CcssVoxelGrid, "out")?;
        let total = grid_bytes(r, z0, z1)?;
        let base = try_block(mem, mem_len, total)?;
        // SAFETY: `base` is 8-aligned with `mem_len >= total` writable bytes: the
        // handle at 0 (align <= 8), the planes after GRID_HEAD; 'static by
        // the C-side contract. The work area is initialised by copying from
        // a static zero value (no large temporary).
        unsafe {
            let planes = core_mem(base, GRID_HEAD, mem_len)?;
            let grid = VoxelGrid::new_slab(r, z0, z1, planes)?;
            let h = base as *mut CcssVoxelGrid;
            ptr::addr_of_mut!((*h).inner.magic).write(0);
            ptr::addr_of_mut!((*h).inner.grid).write(grid);
            ptr::copy_nonoverlapping(&ZERO_WORK, ptr::addr_of_mut!((*h).inner.work), 1);
            ptr::addr_of_mut!((*h).inner.block_len).write(mem_len);
            ptr::addr_of_mut!((*h).inner.magic)
                .write(<CcssVoxelGrid as crate::boundary::Handle>::MAGIC);
            *out = h;
        }
        Ok(())
    })
}

static ZERO_WORK: VoxelWork = VoxelWork::ZERO;

/// Writes the paper's normalisation for the grid's resolution to `*out`: the
/// guaranteed box of the limit surface of `ev` scaled uniformly into
/// `[0, res-1]` per axis (touching both ends on the tightest axis, centred on
/// the others). Uses the grid's work area (the grid's voxels are not
/// touched). For the slabs of one model, compute it once and pass it to
/// every `ccss_voxel_grid_voxelize`.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT.
///
/// # Safety
/// `ev` NULL or a live handle; `grid` NULL or a live grid not used elsewhere
/// during the call; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_fit_transform(
    ev: *const CcssEvaluator,
    grid: *mut CcssVoxelGrid,
    out: *mut CcssVoxelGridTransform,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { fit_transform_with(&e.ev, grid, out) }
    })
}

/// The body of the `fit_transform` entries, for either surface.
///
/// # Safety
/// As `ccss_voxel_grid_fit_transform` for `grid` and `out`.
unsafe fn fit_transform_with<S: Surface + ?Sized>(
    ev: &S,
    grid: *mut CcssVoxelGrid,
    out: *mut CcssVoxelGridTransform,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let g = unsafe { try_handle_mut(grid, "grid") }?;
    check_ptr(out as *const CcssVoxelGridTransform, "out")?;
    let res = g.grid.resolution();
    let t = ccss_core::voxel::fit_transform(ev, res, &mut g.work)?;
    // SAFETY: checked above.
    unsafe { put(out, "out", t.into()) }
}

/// `ccss_voxel_grid_fit_transform` for a feature evaluator (creases,
/// corners, semi-sharp edges).
///
/// Errors: those of `ccss_voxel_grid_fit_transform`.
///
/// # Safety
/// `ev` a live feature evaluator; otherwise as
/// `ccss_voxel_grid_fit_transform`.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_fit_transform_feature(
    ev: *const CcssFeatureEvaluator,
    grid: *mut CcssVoxelGrid,
    out: *mut CcssVoxelGridTransform,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { fit_transform_with(e.evaluator(), grid, out) }
    })
}

/// Voxelizes the limit surface of `ev` into `grid` (clearing it): the
/// paper's recursive parameter-space subdivision with the stop test of
/// `adjacency` (6, 18 or 26), `presplit x presplit` cells per patch (a power
/// of two in 1..=64; the paper uses 8), plus the certification pass (no
/// holes for 6, 6-separating for all). `transform` NULL normalises the
/// model into the grid (`ccss_voxel_grid_fit_transform`); give the same transform
/// to every slab of one model. `*out` (the statistics; may be NULL) is written
/// on success.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (adjacency, presplit,
/// a transform that does not map the surface into the grid), EMPTY_MESH.
///
/// # Safety
/// `ev` a live evaluator, `grid` a live grid not used elsewhere during the
/// call, `transform` NULL or readable, `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_voxelize(
    ev: *const CcssEvaluator,
    grid: *mut CcssVoxelGrid,
    adjacency: u32,
    presplit: u32,
    transform: *const CcssVoxelGridTransform,
    out: *mut CcssVoxelGridVoxelizeStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { voxelize_with(&e.ev, grid, adjacency, presplit, transform, out) }
    })
}

/// The body of the `voxelize` entries, for either surface.
///
/// # Safety
/// As `ccss_voxel_grid_voxelize` for the pointers.
unsafe fn voxelize_with<S: Surface + ?Sized>(
    ev: &S,
    grid: *mut CcssVoxelGrid,
    adjacency: u32,
    presplit: u32,
    transform: *const CcssVoxelGridTransform,
    out: *mut CcssVoxelGridVoxelizeStats,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let g = unsafe { try_handle_mut(grid, "grid") }?;
    let adj =
        Adjacency::from_n(adjacency).ok_or(Failure::invalid("adjacency must be 6, 18 or 26"))?;
    let t = if transform.is_null() {
        None
    } else {
        // SAFETY: non-NULL; readability is the caller's promise.
        let t = unsafe { try_ref(transform, "transform") }?;
        Some(VoxelTransform {
            scale: t.scale,
            offset: t.offset,
        })
    };
    if !out.is_null() {
        check_ptr(out as *const CcssVoxelGridVoxelizeStats, "out")?;
    }
    let params = VoxelParams {
        res: g.grid.resolution(),
        adjacency: adj,
        presplit,
    };
    let g = &mut g.inner;
    let st = g.grid.voxelize(ev, &params, t, &mut g.work)?;
    if !out.is_null() {
        let s = CcssVoxelGridVoxelizeStats {
            cells: st.cells,
            leaves: st.leaves,
            uncovered: st.uncovered,
            refined: st.refined,
            guard_hits: st.guard_hits,
            max_depth: st.max_depth,
            quad_area: st.quad_area,
        };
        // SAFETY: checked above.
        unsafe { out.write(s) };
    }
    Ok(())
}

/// `ccss_voxel_grid_voxelize` for a feature evaluator: the mesh must bound
/// a solid (closed, no holes, manifold).
///
/// Errors: those of `ccss_voxel_grid_voxelize`, NOT_CLOSED_SOLID (naming
/// the boundary edge, hole face or non-manifold element).
///
/// # Safety
/// `ev` a live feature evaluator; otherwise as `ccss_voxel_grid_voxelize`.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_voxelize_feature(
    ev: *const CcssFeatureEvaluator,
    grid: *mut CcssVoxelGrid,
    adjacency: u32,
    presplit: u32,
    transform: *const CcssVoxelGridTransform,
    out: *mut CcssVoxelGridVoxelizeStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { voxelize_with(e.evaluator(), grid, adjacency, presplit, transform, out) }
    })
}

/// Classifies the white voxels of a voxelized grid as interior or outside
/// (bit-parallel flooding from the grid border with the row stack
/// `stack[0..stack_len]`, any `stack_len >= 1`; a certified ray test per
/// enclosed region: right for several solids, any genus, internal voids).
/// `ev` must be the evaluator the grid was voxelized from. `*out` (the
/// statistics; may be NULL) is written on success.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (not voxelized,
/// `stack_len` 0).
///
/// # Safety
/// `ev` a live evaluator, `grid` a live grid not used elsewhere during the
/// call, `stack` NULL or `stack_len` writable `uint32_t`, `out`, `detail`
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_flood(
    ev: *const CcssEvaluator,
    grid: *mut CcssVoxelGrid,
    stack: *mut u32,
    stack_len: usize,
    out: *mut CcssVoxelGridFloodStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { flood_with(&e.ev, grid, stack, stack_len, out) }
    })
}

/// The body of the `flood` entries, for either surface.
///
/// # Safety
/// As `ccss_voxel_grid_flood` for the pointers.
unsafe fn flood_with<S: Surface + ?Sized>(
    ev: &S,
    grid: *mut CcssVoxelGrid,
    stack: *mut u32,
    stack_len: usize,
    out: *mut CcssVoxelGridFloodStats,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let g = unsafe { try_handle_mut(grid, "grid") }?;
    if stack_len == 0 {
        return Err(Failure::invalid("flood stack capacity must be at least 1"));
    }
    check_ptr(stack as *const u32, "stack")?;
    if !out.is_null() {
        check_ptr(out as *const CcssVoxelGridFloodStats, "out")?;
    }
    check_len::<u32>(stack_len, "flood stack too large")?;
    // SAFETY: non-NULL, aligned, `stack_len` writable elements by the
    // caller's promise.
    let st = unsafe { core::slice::from_raw_parts_mut(stack, stack_len) };
    let g = &mut g.inner;
    let f = g.grid.flood(ev, st, &mut g.work)?;
    if !out.is_null() {
        let s = CcssVoxelGridFloodStats {
            enclosed_components: f.enclosed_components,
            inside_components: f.inside_components,
            rays: f.rays,
            unresolved: f.unresolved,
            sweeps: f.sweeps,
            row_visits: f.row_visits,
        };
        // SAFETY: checked above.
        unsafe { out.write(s) };
    }
    Ok(())
}

/// `ccss_voxel_grid_flood` for a feature evaluator (the one the grid was
/// voxelized from).
///
/// Errors: those of `ccss_voxel_grid_flood`, NOT_CLOSED_SOLID.
///
/// # Safety
/// `ev` a live feature evaluator; otherwise as `ccss_voxel_grid_flood`.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_flood_feature(
    ev: *const CcssFeatureEvaluator,
    grid: *mut CcssVoxelGrid,
    stack: *mut u32,
    stack_len: usize,
    out: *mut CcssVoxelGridFloodStats,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { flood_with(e.evaluator(), grid, stack, stack_len, out) }
    })
}

/// Writes the numbers of surface and interior voxels of the grid's slab to
/// `*out_surface` and `*out_interior`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `grid` a live grid; `out_surface`, `out_interior` NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_counts(
    grid: *const CcssVoxelGrid,
    out_surface: *mut u64,
    out_interior: *mut u64,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let g = unsafe { try_handle(grid, "grid") }?;
        check_ptr(out_surface as *const u64, "out_surface")?;
        check_ptr(out_interior as *const u64, "out_interior")?;
        let c = g.grid.counts();
        // SAFETY: checked above.
        unsafe {
            out_surface.write(c.surface);
            out_interior.write(c.interior);
        }
        Ok(())
    })
}

/// Writes the class of voxel `(i, j, k)` to `*out`: 0 outside (also outside
/// the grid or the slab), 1 surface, 2 interior.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `grid` a live grid; `out` NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_class(
    grid: *const CcssVoxelGrid,
    i: u32,
    j: u32,
    k: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let g = unsafe { try_handle(grid, "grid") }?;
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", g.grid.class(i, j, k) as u32) }
    })
}

/// Writes the model-to-voxel transform of the last voxelization of the grid
/// to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (not voxelized).
///
/// # Safety
/// `grid` a live grid; `out` NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_last_transform(
    grid: *const CcssVoxelGrid,
    out: *mut CcssVoxelGridTransform,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let g = unsafe { try_handle(grid, "grid") }?;
        if g.grid.state() == GridState::Empty {
            return Err(Failure::invalid("grid is not voxelized"));
        }
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", g.grid.transform().into()) }
    })
}

/// Writes the runs of the grid's slab into `out[0..out_len]` and their
/// number to `*out_written`. A size query: `out` NULL with `out_len` 0 fails with
/// BUFFER_TOO_SMALL and `detail.required` = the number of runs (so does any
/// `out_len` that is too small; nothing is written then).
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL.
///
/// # Safety
/// `grid` a live grid; `out` NULL or `out_len` writable runs; `out_written`,
/// `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_voxel_grid_runs(
    grid: *const CcssVoxelGrid,
    out: *mut CcssVoxelGridRun,
    out_len: usize,
    out_written: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let g = unsafe { try_handle(grid, "grid") }?;
        check_ptr(out_written as *const usize, "out_written")?;
        let n = g.grid.run_count();
        if out_len < n {
            return Err(Failure::too_small(n));
        }
        check_ptr(out as *const CcssVoxelGridRun, "out")?;
        check_len::<CcssVoxelGridRun>(out_len, "out_len too large")?;
        let out_bytes = out_len * size_of::<CcssVoxelGridRun>();
        if overlaps(out as *const u8, out_bytes, grid as *const u8, g.block_len) {
            return Err(Failure::new(
                CcssStatus::ERR_OVERLAP,
                crate::status::Msg::Text("out overlaps the grid's memory block"),
            ));
        }
        // SAFETY: non-NULL, aligned, `out_len` writable runs; CcssVoxelGridRun and
        // VoxelRun have the same layout (checked at compile time).
        let o = unsafe { core::slice::from_raw_parts_mut(out as *mut VoxelRun, out_len) };
        let k = g.grid.write_runs(o)?;
        // SAFETY: checked above.
        unsafe { out_written.write(k) };
        Ok(())
    })
}

/// Writes the exact volume, area, centroid and inertia of the solid bounded
/// by the limit surface of `ev` (quadrature on the limit surface with error
/// bounds) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, EMPTY_MESH.
///
/// # Safety
/// `ev` a live evaluator; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_mass_properties_compute(
    ev: *const CcssEvaluator,
    out: *mut CcssMassProperties,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promise.
        unsafe { mass_with(&e.ev, out) }
    })
}

/// The body of the mass-properties entries, for either surface.
///
/// # Safety
/// `out` NULL or writable.
unsafe fn mass_with<S: Surface + ?Sized>(
    ev: &S,
    out: *mut CcssMassProperties,
) -> Result<(), Failure> {
    check_ptr(out as *const CcssMassProperties, "out")?;
    let p = mass_properties(ev)?;
    let m = CcssMassProperties {
        volume: p.volume,
        area: p.area,
        centroid: p.centroid,
        inertia: p.inertia,
        volume_error_bound: p.volume_error_bound,
        area_error_bound: p.area_error_bound,
        centroid_error_bound: p.centroid_error_bound,
        inertia_error_bound: p.inertia_error_bound,
        rigorous: c_int::from(p.rigorous),
    };
    // SAFETY: checked above.
    unsafe { put(out, "out", m) }
}

/// `ccss_mass_properties_compute` for a feature evaluator: the mesh must
/// bound a solid. Cells next to crease ends, corners and extraordinary
/// vertices that are not polynomial are refined until their control
/// points' ball is below 1e-8 of the model size; what is left contributes
/// estimated bounds (`rigorous` is then 0).
///
/// Errors: NULL_POINTER, MISALIGNED, NOT_CLOSED_SOLID.
///
/// # Safety
/// `ev` a live feature evaluator; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_mass_properties_compute_feature(
    ev: *const CcssFeatureEvaluator,
    out: *mut CcssMassProperties,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promise.
        unsafe { mass_with(e.evaluator(), out) }
    })
}
