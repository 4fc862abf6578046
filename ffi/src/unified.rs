//! The unified subdivision scheme of Maillot & Stam in the C ABI
//! (`ccss_core::unified`): several levels, each with its own parameters,
//! into caller memory; the finest level is copied into caller arrays.
//!
//! Same conventions as the rest of the ABI: statuses, optional error
//! details, caller memory with size queries, no allocation, nothing written
//! on failure.

use crate::boundary::try_handle;
use crate::boundary::{check_len, check_ptr, core_mem, guard, overlaps, put, try_block, try_slice};
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use crate::topology::CcssTopology;
use ccss_core::unified::{
    refine_unified_levels, unified_levels_bytes, TriangleRule, UnifiedParams, MAX_LEVELS,
};
use ccss_core::Topology;
use core::ffi::c_void;

/// Parameters of one level of the unified scheme (Maillot & Stam 2001).
///
/// `a` push-back (0 approximating, 1 interpolating), `b` rounding factor,
/// `g` Catmull-Clark correction (1 = Catmull-Clark for d = 2), `d` split
/// count (every edge cut into `d` pieces, `d >= 2`), `p` odd degree
/// (`(p-1)/2` smoothing passes), `triangles` 0 = split each triangle into
/// `d^2` triangles (the paper's rule), 1 = treat triangles as polygons.
/// `a = b = 0, g = 1, d = 2, p = 3, triangles = 1` is one Catmull-Clark step.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcssUnifiedParams {
    /// Push-back parameter.
    pub a: f64,
    /// Rounding factor.
    pub b: f64,
    /// Catmull-Clark correction.
    pub g: f64,
    /// Split count (2..=4096).
    pub d: u32,
    /// Odd degree (1..=255).
    pub p: u32,
    /// 0 = split triangles into triangles, 1 = triangles as polygons.
    pub triangles: u32,
}

/// Core parameters of C parameters (the rule checked here, the rest by core).
fn core_params(p: &CcssUnifiedParams) -> Result<UnifiedParams, Failure> {
    let triangles = match p.triangles {
        0 => TriangleRule::Split,
        1 => TriangleRule::Polygon,
        _ => return Err(Failure::invalid("levels[].triangles must be 0 or 1")),
    };
    let q = UnifiedParams {
        a: p.a,
        b: p.b,
        g: p.g,
        d: p.d,
        p: p.p,
        triangles,
    };
    q.validate()?;
    Ok(q)
}

/// The core parameters of all levels, on the stack.
///
/// # Safety
/// `levels` is NULL or points to `n` readable parameters.
unsafe fn params_of(levels: *const CcssUnifiedParams, n: usize) -> Result<Levels, Failure> {
    if n > MAX_LEVELS {
        return Err(Failure::invalid("num_levels is larger than 16"));
    }
    // SAFETY: forwarded caller promise.
    let src = unsafe { try_slice(levels, n, "levels") }?;
    let mut out = Levels {
        p: [UnifiedParams::default(); MAX_LEVELS],
        n,
    };
    for (o, p) in out.p.iter_mut().zip(src) {
        *o = core_params(p)?;
    }
    Ok(out)
}

/// Up to `MAX_LEVELS` core parameters, on the stack.
struct Levels {
    p: [UnifiedParams; MAX_LEVELS],
    n: usize,
}

impl core::ops::Deref for Levels {
    type Target = [UnifiedParams];
    fn deref(&self) -> &[UnifiedParams] {
        &self.p[..self.n]
    }
}

/// Element counts of the finest level (closed form, the same as core's).
#[derive(Clone, Copy, Default)]
struct Counts {
    vertices: u64,
    faces: u64,
    indices: u64,
}

fn finest_counts(t: &Topology, levels: &[UnifiedParams]) -> Counts {
    let (mut v, mut e) = (t.num_vertices() as u64, t.num_edges() as u64);
    let (mut tris, mut polys, mut pc) = (0u64, 0u64, 0u64);
    for &n in t.face_sizes() {
        if n == 3 {
            tris += 1;
        } else {
            polys += 1;
            pc += n as u64;
        }
    }
    for p in levels {
        let d = p.d as u64;
        let m = d / 2;
        let (ts, ps, pcs) = match p.triangles {
            TriangleRule::Split => (tris, polys, pc),
            TriangleRule::Polygon => (0, polys + tris, pc + 3 * tris),
        };
        let (new_polys, new_pc, poly_interior) = if d % 2 == 0 {
            (pcs * m * m, 4 * pcs * m * m, ps + pcs * m * (m - 1))
        } else {
            (
                pcs * m * (m + 1) + ps,
                4 * pcs * m * (m + 1) + pcs,
                pcs * m * m,
            )
        };
        let tri_interior = ts * ((d - 1) * (d - 2) / 2);
        let new_tris = ts * d * d;
        v = v + e * (d - 1) + tri_interior + poly_interior;
        tris = new_tris;
        polys = new_polys;
        pc = new_pc;
        e = (3 * tris + pc) / 2;
    }
    Counts {
        vertices: v,
        faces: tris + polys,
        indices: 3 * tris + pc,
    }
}

/// Writes the tool defaults of the paper (MS §4) to `*out`: `a = b = 0.5`,
/// `g = 0`, `d = 2`, `p = 3`, `triangles = 0` (split).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_unified_params_default(
    out: *mut CcssUnifiedParams,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        let d = UnifiedParams::default();
        let p = CcssUnifiedParams {
            a: d.a,
            b: d.b,
            g: d.g,
            d: d.d,
            p: d.p,
            triangles: 0,
        };
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", p) }
    })
}

/// Sizes of `ccss_unified_refine` with these levels (`num_levels` <= 16; level `l`
/// refines level `l - 1` with `levels[l]`): the bytes of its memory block
/// and the vertex, face and index counts of the finest level. With
/// `num_levels == 0` the finest level is the input mesh (and 0 bytes).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (bad parameters,
/// more than 16 levels, a refined mesh too large); details in `*detail`
/// (may be NULL). Nothing is written on failure.
///
/// # Safety
/// `topo` is NULL or a live handle; `levels` NULL or `num_levels` readable
/// parameters; the out-parameters and `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_unified_required_bytes(
    topo: *const CcssTopology,
    levels: *const CcssUnifiedParams,
    num_levels: usize,
    out_bytes: *mut usize,
    out_vertices: *mut usize,
    out_faces: *mut usize,
    out_indices: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let t = unsafe { try_handle(topo, "topo") }?;
        // SAFETY: forwarded caller promise.
        let params = unsafe { params_of(levels, num_levels) }?;
        check_ptr(out_bytes as *const usize, "out_bytes")?;
        check_ptr(out_vertices as *const usize, "out_vertices")?;
        check_ptr(out_faces as *const usize, "out_faces")?;
        check_ptr(out_indices as *const usize, "out_indices")?;
        let bytes = unified_levels_bytes(&t.topo, &params)?;
        let c = finest_counts(&t.topo, &params);
        // SAFETY: checked above; writability is the caller's promise.
        unsafe {
            put(out_bytes, "out_bytes", bytes)?;
            put(out_vertices, "out_vertices", c.vertices as usize)?;
            put(out_faces, "out_faces", c.faces as usize)?;
            put(out_indices, "out_indices", c.indices as usize)
        }
    })
}

/// Refines `topo` once per entry of `levels` in `mem` (`mem_len` bytes,
/// 8-byte aligned, at least what `ccss_unified_required_bytes` says) and copies the
/// finest level into the caller's arrays: `3 * vertices` doubles of
/// positions, `faces` face sizes and `indices` vertex indices (faces
/// counter-clockwise as in the input). `mem` is working memory only: it may
/// be reused or freed after the call.
///
/// Everything is checked before anything is written: NULL_POINTER,
/// MISALIGNED, INVALID_ARGUMENT (as `ccss_unified_required_bytes`; two arrays, or
/// an array and `mem`, overlap), BUFFER_TOO_SMALL (`detail.required`: the
/// bytes of `mem`, or the element count of the first short array, in the
/// order positions, face sizes, indices), and any topology error of an
/// intermediate level. On failure the output arrays are not written (`mem`'s
/// contents are unspecified).
///
/// # Safety
/// `topo` is NULL or a live handle; `levels` NULL or `num_levels` readable
/// parameters; `mem` NULL or `mem_len` writable bytes; each output array
/// NULL or writable for its length, none of them otherwise in use; `detail`
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_unified_refine(
    topo: *const CcssTopology,
    levels: *const CcssUnifiedParams,
    num_levels: usize,
    mem: *mut c_void,
    mem_len: usize,
    out_positions: *mut f64,
    out_positions_len: usize,
    out_face_sizes: *mut u32,
    out_face_sizes_len: usize,
    out_indices: *mut u32,
    out_indices_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let t = unsafe { try_handle(topo, "topo") }?;
        // SAFETY: forwarded caller promise.
        let params = unsafe { params_of(levels, num_levels) }?;
        check_ptr(out_positions as *const f64, "out_positions")?;
        check_ptr(out_face_sizes as *const u32, "out_face_sizes")?;
        check_ptr(out_indices as *const u32, "out_indices")?;
        check_len::<f64>(out_positions_len, "array length too large")?;
        check_len::<u32>(out_face_sizes_len, "array length too large")?;
        check_len::<u32>(out_indices_len, "array length too large")?;
        let bytes = unified_levels_bytes(&t.topo, &params)?;
        let c = finest_counts(&t.topo, &params);
        let arrays: [(*const u8, usize); 3] = [
            (out_positions as *const u8, 8 * out_positions_len),
            (out_face_sizes as *const u8, 4 * out_face_sizes_len),
            (out_indices as *const u8, 4 * out_indices_len),
        ];
        for (k, &(p, n)) in arrays.iter().enumerate() {
            if !mem.is_null() && overlaps(p, n, mem as *const u8, mem_len) {
                return Err(Failure::invalid("an output array overlaps mem"));
            }
            for &(q, m) in &arrays[k + 1..] {
                if overlaps(p, n, q, m) {
                    return Err(Failure::invalid("two output arrays overlap"));
                }
            }
        }
        let need = [3 * c.vertices, c.faces, c.indices];
        let have = [out_positions_len, out_face_sizes_len, out_indices_len];
        for (&n, &h) in need.iter().zip(&have) {
            if n > h as u64 {
                return Err(Failure::too_small(n as usize));
            }
        }
        let (pos, sizes, idx): (&[f64], &[u32], &[u32]);
        if params.is_empty() {
            (pos, sizes, idx) = (t.topo.positions(), t.topo.face_sizes(), t.topo.indices());
        } else {
            let base = try_block(mem, mem_len, bytes)?;
            // SAFETY: `base` comes from `try_block` with `mem_len` writable
            // bytes, exclusively ours for the call (caller promise).
            let arena = unsafe { core_mem(base, 0, mem_len) }?;
            let lv = refine_unified_levels(&t.topo, &params, arena)?;
            let fine = lv.finest().ok_or(Failure::internal("no refined level"))?;
            (pos, sizes, idx) = (fine.positions, fine.face_sizes, fine.indices);
        }
        if pos.len() as u64 != 3 * c.vertices
            || sizes.len() as u64 != c.faces
            || idx.len() as u64 != c.indices
        {
            return Err(Failure::internal(
                "refined counts differ from the size query",
            ));
        }
        // SAFETY: non-NULL, aligned, long enough (checked above), disjoint
        // from each other and from `mem` (checked above); writability is the
        // caller's promise.
        unsafe {
            core::ptr::copy_nonoverlapping(pos.as_ptr(), out_positions, pos.len());
            core::ptr::copy_nonoverlapping(sizes.as_ptr(), out_face_sizes, sizes.len());
            core::ptr::copy_nonoverlapping(idx.as_ptr(), out_indices, idx.len());
        }
        Ok(())
    })
}
