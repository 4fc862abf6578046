//! One level of the unified scheme on a mesh, into caller memory: linear
//! subdivision, then `(p - 1) / 2` passes of smoothing, Catmull-Clark
//! correction and push-back (MS §3.2–3.4).
//!
//! A pass, every rule in Jacobi manner (each reads the state before it):
//!
//! 1. smoothing ([`super::smooth`]): eq. (22) twice for odd `d`, eqs.
//!    (23)+(24) for even `d`;
//! 2. if `g != 0`, the Catmull-Clark correction ([`super::correction`]),
//!    eqs. (11)–(13) — part of the smoothing rule, so before push-back;
//! 3. if `a != 0`, push-back: `D(V_i) = a (V̄_i - V_i)` at the old vertices
//!    (eq. (14), `V̄_i` the original position), interpolated to the new ones
//!    and renormalised with `b` ([`super::interp`], eqs. (15)–(21)), then
//!    added. For `p > 3` this order is simply repeated (MS leaves the order
//!    open for surfaces; this is the curve order of §3.1).

use super::binary;
use super::correction;
use super::faces;
use super::fast;
use super::general;
use super::interp::{add_interpolated, set_interpolated};
use super::layout::{MeshStats, Numbering, Shape, UnifiedCounts};
use super::params::UnifiedParams;
use super::smooth;
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mesh::topology::{MeshInput, Topology};
use glam::DVec3;

/// A sequence of slice requests, replayed by [`Layout`] (exact byte count)
/// and by [`Bytes64`] (overflow-free check first, also on 32-bit targets).
pub(crate) trait Requests {
    fn u32s(&mut self, n: u64);
    fn f64s(&mut self, n: u64);
}

impl Requests for Layout {
    fn u32s(&mut self, n: u64) {
        Layout::u32s(self, n as usize);
    }
    fn f64s(&mut self, n: u64) {
        Layout::f64s(self, n as usize);
    }
}

/// Byte counter in `u64` (mirrors [`Layout`]'s 8-byte rounding).
#[derive(Default)]
pub(crate) struct Bytes64(pub u64);

impl Requests for Bytes64 {
    fn u32s(&mut self, n: u64) {
        self.0 += (n * 4).div_ceil(8) * 8;
    }
    fn f64s(&mut self, n: u64) {
        self.0 += n * 8;
    }
}

/// Runs `plan` on a [`Bytes64`] first and, if the total fits `isize`, on a
/// [`Layout`]; returns the byte count.
pub(crate) fn bytes_of(plan: impl Fn(&mut dyn Requests)) -> Result<usize, Error> {
    let mut b = Bytes64::default();
    plan(&mut b);
    if b.0 > isize::MAX as u64 {
        return Err(Error::InvalidArgument(
            "unified: refined mesh too large for memory",
        ));
    }
    let mut l = Layout::default();
    plan(&mut l);
    debug_assert_eq!(l.bytes() as u64, b.0);
    Ok(l.bytes())
}

/// The output part of a level: the refined mesh and its index maps.
pub(crate) fn out_requests(r: &mut dyn Requests, base: &MeshStats, fine: &MeshStats) {
    let bc = base.counts();
    let fc = fine.counts();
    r.f64s(3 * fc.vertices as u64); // positions
    r.u32s(fc.faces as u64); // face sizes
    r.u32s(fc.corners as u64); // indices
    r.u32s(bc.corners as u64); // edge_of
    r.u32s(bc.faces as u64 + 1); // interior_start
    r.u32s(bc.faces as u64 + 1); // child_start
}

/// Whether the averages of this level need the breadth-first search.
fn needs_search(p: &UnifiedParams) -> bool {
    p.passes() > 0 && p.d > 2
}

/// Whether this level uses the regular-face fast path ([`fast`]).
fn uses_fast(p: &UnifiedParams) -> bool {
    needs_search(p) && p.d as usize <= fast::FAST_MAX_D
}

/// The working part of a level (reused between levels).
pub(crate) fn work_requests(
    r: &mut dyn Requests,
    base: &MeshStats,
    fine: &MeshStats,
    p: &UnifiedParams,
) {
    let bv = base.vertices;
    let fc = fine.counts();
    let (v, f, c) = (fc.vertices as u64, fc.faces as u64, fc.corners as u64);
    r.u32s(f + 1); // face_start
    if uses_fast(p) {
        let z = fast::sizes(p.d as usize, bv, base.polys + base.tris, base.polys);
        r.u32s(z.slot);
        r.u32s(z.mask);
        r.u32s(z.vflag);
        r.u32s(z.grid);
        r.u32s(z.cell);
        r.u32s(z.base16);
        r.u32s(z.etab);
        r.u32s(z.itab);
        r.u32s(z.blocks);
        r.f64s(z.tables);
        r.u32s(z.win_idx);
        r.f64s(3 * z.win_val);
        r.f64s(3 * z.rows);
        r.u32s(v); // vertex done flags
        r.u32s(f); // face done flags
    }
    if p.passes() > 0 {
        if p.d == 2 {
            r.u32s(if p.passes() > 1 { v } else { 0 }); // faces per vertex
        }
        if p.d % 2 == 1 {
            r.f64s(3 * v); // Jacobi copy of the vertices
        } else if p.d > 2 || p.passes() > 1 {
            r.f64s(3 * f); // dual (face) values
        }
        r.f64s(3 * bv); // old vertices before the pass
        r.f64s(3 * bv); // C_i, then D(V_i)
        r.f64s(bv); // |D(V_i)|
        if needs_search(p) {
            // Last: carved only if the search is needed.
            r.u32s(v + 1); // vf_start
            r.u32s(c); // vf
            r.u32s(v); // vertex stamps
            r.u32s(f); // face stamps
            r.u32s(v); // queue
        }
    }
}

/// Bytes of caller memory [`refine_unified`] needs for `t` with `params`:
/// the refined mesh and its index maps plus working memory (Jacobi copies,
/// adjacency, search scratch), all carved from the one buffer.
///
/// Errors: invalid parameters, or a refined mesh too large
/// ([`Error::InvalidArgument`]).
pub fn unified_bytes(t: &Topology, params: &UnifiedParams) -> Result<usize, Error> {
    params.validate()?;
    let base = MeshStats::of(t);
    let fine = base.refined(params)?;
    bytes_of(|r| {
        out_requests(r, &base, &fine);
        work_requests(r, &base, &fine, params);
    })
}

/// One refined level in caller memory.
#[derive(Clone, Copy, Debug)]
pub struct UnifiedRefined<'a> {
    /// The refined mesh, ready for [`Topology::build`] (the next level).
    pub mesh: MeshInput<'a>,
    /// Edge index (first-appearance order) of each input half-edge; the
    /// `d - 1` points of edge `e` are vertices `V + e (d-1) ..`, ordered from
    /// the origin of the edge's lower-numbered half-edge.
    pub edge_of: &'a [u32],
    /// First interior vertex of each input face (`F + 1` entries).
    pub interior_start: &'a [u32],
    /// First refined face of each input face (`F + 1` entries).
    pub child_start: &'a [u32],
    shape: Shape,
    nv: usize,
}

impl UnifiedRefined<'_> {
    /// The refined vertex at grid point `(i, j)` of corner frame `k` of
    /// input face `f` (origin at corner `k`, `i` steps of `1/d` towards corner
    /// `k + 1`, `j` towards corner `k - 1`; see [`super::layout`]).
    /// Valid points: any `i, j <= d` for quads, `i + j <= d` for split
    /// triangles, and for other polygons points within `floor(d/2)` steps of
    /// edge `k` or edge `k - 1`. `t` must be the topology this level was
    /// refined from. `None` outside.
    pub fn frame_vertex(
        &self,
        t: &Topology,
        f: usize,
        k: usize,
        i: usize,
        j: usize,
    ) -> Option<u32> {
        if f >= t.num_faces() || t.num_half_edges() != self.edge_of.len() {
            return None;
        }
        let num = Numbering {
            shape: self.shape,
            nv: self.nv,
            edge_of: self.edge_of,
            interior_start: self.interior_start,
        };
        num.frame_point(t, f, k, i, j).map(|r| r as u32)
    }

    /// Counts of the refined mesh.
    pub fn counts(&self) -> UnifiedCounts {
        UnifiedCounts {
            vertices: self.mesh.positions.len() / 3,
            edges: self.mesh.indices.len() / 2,
            faces: self.mesh.face_sizes.len(),
            corners: self.mesh.indices.len(),
        }
    }
}

/// One level of the unified scheme on `t` into `mem` (at least
/// [`unified_bytes`] bytes, in words). The refined mesh's vertex and face
/// numbering is documented in [`super::layout`].
///
/// Errors: invalid parameters or a refined mesh too large
/// ([`Error::InvalidArgument`]), [`Error::BufferTooSmall`] (bytes).
pub fn refine_unified<'a>(
    t: &Topology,
    params: &UnifiedParams,
    mem: &'a mut [u64],
) -> Result<UnifiedRefined<'a>, Error> {
    params.validate()?;
    let base = MeshStats::of(t);
    let fine = base.refined(params)?;
    let out_bytes = bytes_of(|r| out_requests(r, &base, &fine))?;
    let required = unified_bytes(t, params)?;
    if crate::mem::bytes_of(mem.len()) < required {
        return Err(Error::BufferTooSmall { required });
    }
    let (out, work) = mem.split_at_mut(crate::mem::words_for(out_bytes));
    step(t, params, &base, &fine, out, work)
}

/// Views points as their coordinates.
fn flat(p: &[DVec3]) -> &[f64] {
    // SAFETY: `glam::DVec3` is `repr(C)` with three `f64` fields (size 24,
    // align 8), so `p` is `3 * p.len()` initialised, aligned `f64` values,
    // borrowed for the same lifetime.
    unsafe { core::slice::from_raw_parts(p.as_ptr() as *const f64, 3 * p.len()) }
}

/// One level with the output carved from `out` and scratch from `work`
/// (sizes checked by the caller).
pub(crate) fn step<'o>(
    t: &Topology,
    p: &UnifiedParams,
    base: &MeshStats,
    fine: &MeshStats,
    out: &'o mut [u64],
    work: &mut [u64],
) -> Result<UnifiedRefined<'o>, Error> {
    let shape = Shape::new(p);
    let bc = base.counts();
    let fc = fine.counts();
    let nv = bc.vertices;
    let mut oa = Arena::new(out);
    let x = oa.vec3s(fc.vertices);
    let sizes = oa.u32s(fc.faces);
    let idx = oa.u32s(fc.corners);
    let edge_of = oa.u32s(bc.corners);
    let interior_start = oa.u32s(bc.faces + 1);
    let child_start = oa.u32s(bc.faces + 1);
    let mut wa = Arena::new(work);
    let face_start = wa.u32s(fc.faces + 1);

    faces::number(t, &shape, edge_of, interior_start, child_start);
    let (edge_of, interior_start, child_start): (&'o [u32], &'o [u32], &'o [u32]) =
        (edge_of, interior_start, child_start);
    let num = Numbering {
        shape,
        nv,
        edge_of,
        interior_start,
    };
    // Charts of the quads (fast path of the averages, also used to emit the
    // quads' children).
    let mut fast = if uses_fast(p) {
        let z = fast::sizes(shape.d, base.vertices, base.polys + base.tris, base.polys);
        let mem = fast::ChartMem {
            slot: wa.u32s(z.slot as usize),
            mask: wa.u32s(z.mask as usize),
            vflag: wa.u32s(z.vflag as usize),
            grid: wa.u32s(z.grid as usize),
            cell: wa.u32s(z.cell as usize),
            base16: wa.u32s(z.base16 as usize),
            etab: wa.u32s(z.etab as usize),
            itab: wa.u32s(z.itab as usize),
            blocks: wa.u32s(z.blocks as usize),
        };
        let charts = fast::build(t, &num, child_start, mem);
        let tables = wa.f64s(z.tables as usize);
        let (w1, w2) = tables.split_at_mut(4 * (shape.d + 1));
        fast::first_pass_weights(shape.d, w1, w2);
        Some(general::Fast {
            charts,
            win: fast::Window {
                idx: wa.u32s(z.win_idx as usize),
                val: wa.vec3s(z.win_val as usize),
                rows: wa.vec3s(z.rows as usize),
            },
            w1,
            w2,
            vdone: wa.u32s(fc.vertices),
            fdone: wa.u32s(fc.faces),
        })
    } else {
        None
    };
    faces::emit(
        t,
        &num,
        sizes,
        idx,
        face_start,
        fast.as_ref().map(|f| &f.charts),
    );
    let (sizes, idx): (&'o [u32], &'o [u32]) = (sizes, idx);
    let face_start: &[u32] = face_start;

    // Linear subdivision, eqs. (1)-(2) / Fig. 8 (fused with the first pass
    // for d = 2).
    let passes = p.passes();
    let binary = shape.d == 2;
    let linear = |x: &mut [DVec3], wanted: &dyn Fn(usize) -> bool| {
        for (v, xv) in x[..nv].iter_mut().enumerate() {
            *xv = t.position(v);
        }
        let pos = |v: usize| (t.position(v), 0.0);
        set_interpolated(t, &num, &pos, x, wanted);
    };
    if passes == 0 {
        linear(x, &|_| true);
    }
    if passes > 0 {
        let counts: &[u32] = if binary {
            // The first pass is fused with the linear subdivision.
            binary::first_pass(t, &num, idx, face_start, child_start, x);
            let counts = wa.u32s(if passes > 1 { fc.vertices } else { 0 });
            faces::face_counts(idx, counts);
            counts
        } else {
            &[]
        };
        let odd = shape.odd;
        let buf = if odd {
            wa.vec3s(fc.vertices)
        } else if !binary || passes > 1 {
            wa.vec3s(fc.faces)
        } else {
            wa.vec3s(0)
        };
        let before = wa.vec3s(nv);
        let cd = wa.vec3s(nv);
        let lens = wa.f64s(nv);
        if !binary {
            // The linear subdivision, where the first pass reads it (not
            // inside regions the B-spline weights cover).
            match fast.as_ref() {
                Some(f) => linear(x, &|face| !f.charts.full(face) || f.charts.needed(face)),
                None => linear(x, &|_| true),
            }
        }
        let mut smoother = (!binary).then(|| general::General {
            k: if odd { (shape.d - 1) / 2 } else { shape.d / 2 },
            odd,
            fast: fast.take(),
            search: general::LazySearch {
                face_start,
                idx,
                num_vertices: fc.vertices,
                rest: wa,
                ready: None,
            },
            gen: 0,
        });
        for pass in 0..passes {
            if p.g != 0.0 {
                // Old vertices before this pass (for the first pass: the
                // input, whatever path computed the pass).
                for (v, bv) in before.iter_mut().enumerate() {
                    *bv = if pass == 0 { t.position(v) } else { x[v] };
                }
            }
            match smoother.as_mut() {
                None if pass == 0 => {} // done by `binary::first_pass`
                None => smooth::centroid_average(face_start, idx, counts, x, buf),
                Some(sm) => sm.pass(t, pass, x, buf),
            }
            if p.g != 0.0 {
                correction::apply(t, &num, p.g, before, x, cd);
                if pass == 0 {
                    correction::apply_edges(t, &num, p.g, x);
                }
            }
            if p.a != 0.0 {
                // Eq. (14), then (15)-(21).
                for v in 0..nv {
                    cd[v] = (t.position(v) - x[v]) * p.a;
                    x[v] += cd[v];
                }
                if p.b == 0.0 {
                    let dv = |v: usize| (cd[v], 0.0);
                    add_interpolated::<false>(t, &num, &dv, 0.0, x);
                } else {
                    for v in 0..nv {
                        lens[v] = cd[v].length();
                    }
                    let dv = |v: usize| (cd[v], lens[v]);
                    add_interpolated::<true>(t, &num, &dv, p.b, x);
                }
            }
        }
    }
    let x: &'o [DVec3] = x;
    Ok(UnifiedRefined {
        mesh: MeshInput {
            positions: flat(x),
            face_sizes: sizes,
            indices: idx,
        },
        edge_of,
        interior_start,
        child_start,
        shape,
        nv,
    })
}
