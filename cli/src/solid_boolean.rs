//! The Boolean pipeline of `ccss boolean`: tessellate both solids with a
//! guaranteed bound, combine the two inscribed meshes with
//! `ccss_core::boolean` (exact predicates), and refine until the error
//! bound is at most `eps` (see the core module's error bound).
//!
//! **Local refinement.** The first pass tessellates both solids at `eps`
//! (`eps / 1.25` for meshes with features; `SLACK eps` on smooth meshes,
//! below). The triangles of a smooth tessellation whose a-priori bound is
//! above `eps` (the crossing ones among them) then get their a-posteriori
//! bounds ([`sharpen`], `ccss_core::boolean::triangle_bound_in`),
//! and the pass is accepted when every triangle's bound and every
//! crossing's `crossing_bound(a, t_A, t_B)` (core `boolean` module docs:
//! the wedge lemma with the two triangles' bounds kept apart, at most
//! `a max(t_A, t_B)`) are at most `eps`. Otherwise the next pass
//! tessellates with a tolerance field ([`crate::boolean_field`]): cells
//! whose surface comes within `2 eps +` (the other tessellation's bound)
//! of the other solid and within a crossing's reach (its error bound `+ 2
//! eps`) of the previous curve get `eps / (1.05 e s)` ([`SHARP_EXPECT`] `s
//! = 0.35`: the a-posteriori bounds are about a third of the tolerance),
//! `e` the largest effective amplification (`crossing_bound / max(t_A,
//! t_B)`, at most `a`) of the previous pass's crossings nearby; crossings
//! whose certificate failed in a local pass ask for the a-priori `eps /
//! (1.05 e k)` from then on (`k` = 1, 1.1, .. per pass; with slack the
//! measured `eps / (e r k / 0.9)`, `r` the ratio of bound to a-priori
//! bound of its triangles); all other cells keep `eps`. These requests go
//! only to a solid that was the worse side of a failing crossing, or
//! whose own bound there fails at equal bounds (`a t_X > eps`), in a
//! pass so far: a solid that passes at every crossing keeps its cells.
//! The field only steers the refinement: acceptance is always the
//! certificate above. Once a pass is certified, one more local pass runs
//! (its band follows the closer curve of the certified pass), and so on
//! while the certified output shrinks; the smallest is kept (on the hands
//! of `bench/boolean_bench.sh` the union's certified passes give 52,236 ->
//! 50,434 triangles). Meshes with features (creases) take the feature
//! tessellation, which has no field and no a-posteriori bounds: there the
//! smallest tolerance of the field applies to the whole surface (the
//! global shrink).
//!
//! **Spending the slack** (smooth meshes). The a-priori bound of a cell
//! is about 2-3 times its actual deviation, and the error is the largest
//! *bound*: tessellated at `eps`, most of both surfaces sits well below
//! `eps` (on the torus-cube pair of `bench/boolean_bench.sh` no crossing
//! needed refinement, and the output was exactly the tessellations at
//! `eps` combined). So the passes tessellate at [`SLACK`] `x eps` where no
//! other rule asks for less, and *every* triangle whose a-priori bound is
//! above `eps` gets its a-posteriori bound ([`sharpen`], with a cache
//! across passes): the certificate is unchanged (every triangle's proven
//! bound and every crossing's at most `eps`), only the bounds are the
//! measured ones (a second, finer bound where the first is above
//! `eps / a`, `a` the pass's largest amplification). A triangle still
//! above `eps` asks for
//! `0.9 eps x prior / bound` at its centroid in the next pass
//! ([`TIGHT_MARGIN`]; `prior` its cell's a-priori bound), so its cell
//! splits once, and cells whose bound passed keep `SLACK eps`. On the
//! torus-cube pair: 17,556 / 3,080 / 17,100 -> 6,090 / 2,166 / 6,004
//! triangles (union / intersection / difference), measured error 0.324
//! -> 0.850 eps (`docs/bench-log.md` 2026-11-27 `booltc`); with the
//! finer bound and the per-solid requests 5,470 / 1,650 / 5,688 at
//! 0.924 eps (bench-log `bool8`); with `crossing_bound`, the effective
//! amplifications and the passes that go on while the output shrinks
//! 5,252 / 1,382 / 5,540 (bench-log `bool9`).

use crate::boolean_field::{CrossingReach, Field, TightBox};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::parallel::tessellate::{mark_parallel, mark_parallel_field};
use crate::progress::Progress;
use crate::verbs::eval::{smooth_or_feature, with_feature_mesh};
use ccss_core::boolean::{
    self, crossing_bound, patch_triangle, patch_triangles, triangle_bound_in, Boolean, Counts,
    Crossing, FaceSource, Op, Options as BoolOptions, Output, PatchTriangle, SolidMesh, Stats,
    TessellationUv, UvTriangle, SHARP_SAMPLES, SHARP_SAMPLES_FINE,
};
use ccss_core::bounds::{cell_bound, CellBound};
use ccss_core::tessellate::{
    Options, Output as TessOutput, PolygonCell, Scratch, Tessellation, ToleranceField,
};
use ccss_core::{DVec3, Query};
use std::collections::HashMap;

/// A solid's tessellation as triangles, with the base face of each.
pub struct TriMesh {
    /// x y z per vertex.
    pub positions: Vec<f64>,
    /// Three indices per triangle.
    pub triangles: Vec<u32>,
    /// Base face of each triangle.
    pub tri_face: Vec<u32>,
    /// Parameter-space triangle of each triangle (empty unless asked for).
    pub uv: Vec<PatchTriangle>,
    /// The tessellation's guaranteed bound.
    pub bound: f64,
    /// Per triangle, a guaranteed bound of its cell (`bound`, or the
    /// field at the triangle's box when tessellated with one), lowered to
    /// its a-posteriori bound by [`sharpen`].
    pub tri_bound: Vec<f64>,
    /// Per triangle, its cell's a-priori bound once [`sharpen`] has
    /// bounded it (the steering value of `tri_bound` before).
    pub tri_prior: Vec<f64>,
    /// Smallest tolerance used.
    pub min_tol: f64,
    /// Parameter cell of each polygon.
    pub cells: Vec<PolygonCell>,
    /// Polygon (index into `cells`) of each triangle.
    pub tri_cell: Vec<u32>,
    /// `(face, sub, u, v)` of each vertex.
    pub params: Vec<Query>,
    /// Whether the smooth path made it (the a-posteriori bounds of
    /// [`sharpen`] apply).
    pub smooth: bool,
}

/// The Boolean's result.
pub struct BoolResult {
    pub counts: Counts,
    pub stats: Stats,
    pub positions: Vec<f64>,
    pub triangles: Vec<u32>,
    pub sources: Vec<FaceSource>,
    /// Parameter-space provenance per triangle (empty unless asked for).
    pub uv: Vec<UvTriangle>,
    pub curve_sizes: Vec<u32>,
    pub curve_indices: Vec<u32>,
    /// Tessellation tolerance used.
    pub tolerance: f64,
    /// The error bound: the largest triangle bound and
    /// `crossing_bound(a, t_A, t_B)` over the crossings.
    pub bound: f64,
    /// The pass whose output this is (the pass after it, if any, ran too
    /// and did not certify fewer triangles).
    pub passes: u32,
    /// Whether the accepted pass tessellated with tolerance fields (local
    /// refinement near the curve).
    pub local: bool,
    /// Every crossing: triangles of A and B, segment ends, amplification.
    pub crossings: Vec<Crossing>,
    /// Whether A's (B's) surface was found inside out (negative signed
    /// volume) and taken reversed ([`orient`]).
    pub reversed: [bool; 2],
}

/// The signed volume enclosed by `t`'s triangles (positive when they are
/// counter-clockwise seen from outside).
fn signed_volume(t: &TriMesh) -> f64 {
    let p = |v: u32| DVec3::from_slice(&t.positions[3 * v as usize..3 * v as usize + 3]);
    let sum: f64 = t
        .triangles
        .chunks_exact(3)
        .map(|c| p(c[0]).dot(p(c[1]).cross(p(c[2]))))
        .sum();
    sum / 6.0
}

/// Reverses every triangle of `t` (its second and third vertices, and
/// the same corners of its parameter-space triangle): the surface of an
/// inside-out mesh, oriented as the boundary of the solid it bounds.
fn reverse(t: &mut TriMesh) {
    for c in t.triangles.chunks_exact_mut(3) {
        c.swap(1, 2);
    }
    for pt in &mut t.uv {
        pt.uv.swap(2, 4);
        pt.uv.swap(3, 5);
    }
}

/// Orients a solid's tessellation outward. `reversed` is `None` before
/// the first pass: the sign of the enclosed volume decides (a control
/// mesh whose faces are clockwise seen from outside, such as OpenSubdiv's
/// `catmark_lefthanded`, bounds its solid with inward normals; the keep
/// rules read normals as outward, so it would stand for the solid's
/// complement); later passes do the same as the first.
fn orient(t: &mut TriMesh, reversed: &mut Option<bool>) -> bool {
    let flip = *reversed.get_or_insert_with(|| signed_volume(t) < 0.0);
    if flip {
        reverse(t);
    }
    flip
}

/// The exact surface at a query (for [`patch_triangles`]).
type SurfaceEval<'e> = &'e dyn Fn(Query) -> Result<DVec3, ccss_core::Error>;

fn emit_tris(t: &mut Tessellation, uv: Option<SurfaceEval>) -> Result<TriMesh, ccss_core::Error> {
    let c = t.counts();
    let mut r = TriMesh {
        positions: vec![0.0; 3 * c.vertices],
        triangles: vec![0; 3 * c.triangles],
        tri_face: Vec::with_capacity(c.triangles),
        uv: Vec::new(),
        bound: t.stats().bound,
        tri_bound: Vec::new(),
        tri_prior: Vec::new(),
        min_tol: 0.0,
        cells: Vec::new(),
        tri_cell: Vec::with_capacity(c.triangles),
        params: Vec::new(),
        smooth: false,
    };
    let mut sizes = vec![0u32; c.polygons];
    let mut idx = vec![0u32; c.polygon_indices];
    let mut cells = vec![PolygonCell::default(); c.polygons];
    let mut params = vec![Query::default(); c.vertices];
    t.emit(TessOutput {
        positions: &mut r.positions,
        normals: None,
        params: Some(&mut params[..]),
        polygon_sizes: &mut sizes,
        polygon_indices: &mut idx,
        triangles: Some(&mut r.triangles),
        cells: Some(&mut cells),
    })?;
    for (p, &n) in sizes.iter().enumerate() {
        for _ in 2..n {
            r.tri_face.push(cells[p].face);
            r.tri_cell.push(p as u32);
        }
    }
    if let Some(ev) = uv {
        r.uv = vec![PatchTriangle::default(); c.triangles];
        let tuv = TessellationUv {
            positions: &r.positions,
            params: &params,
            polygon_sizes: &sizes,
            cells: &cells,
            triangles: &r.triangles,
        };
        patch_triangles(tuv, &mut |q| ev(q), &mut r.uv)?;
    }
    r.cells = cells;
    r.params = params;
    Ok(r)
}

/// Tessellates `mesh` at absolute tolerance `tol` (smooth path on all
/// cores for marking, or the feature path on one); with a `field`, the
/// smooth path's tolerance is `min(tol, field)` per cell and the feature
/// path's the field's smallest; with `want_uv`, the parameter-space
/// triangles too.
pub fn tessellate(
    mesh: &Mesh,
    tol: f64,
    field: Option<&Field>,
    want_uv: bool,
    progress: &Progress,
) -> CliResult<TriMesh> {
    let opts = Options::absolute(tol);
    let err =
        |e: ccss_core::Error| CliError::failure(format!("{}: cannot tessellate: {e}", mesh.name));
    let smooth = smooth_or_feature(mesh, &WeightsArg::default(), false, |ctx| {
        let (marks, trees) = match field {
            Some(f) => mark_parallel_field(&ctx.evaluator, &opts, f, progress),
            None => mark_parallel(&ctx.evaluator, &opts, progress),
        }
        .map_err(err)?;
        let need = Tessellation::required_bytes_marked(&ctx.topology, &marks).map_err(err)?;
        let mut mem = words(need);
        let mut t = Tessellation::build_marked(
            &ctx.topology,
            &ctx.evaluator,
            opts,
            &marks,
            &trees,
            &mut mem,
        )
        .map_err(err)?;
        let ev = |q: Query| Ok(ctx.evaluator.eval(q.face, q.sub, q.u, q.v)?.p);
        let mut r = emit_tris(&mut t, want_uv.then_some(&ev as SurfaceEval)).map_err(err)?;
        set_bounds(&mut r, tol, field);
        r.smooth = true;
        Ok(r)
    })?;
    if let Some(t) = smooth {
        return Ok(t);
    }
    let tol = field.map_or(tol, |f| f.min_tolerance().min(tol));
    let opts = Options::absolute(tol);
    with_feature_mesh(mesh, None, None, |fe| {
        // Open meshes, holes: named on the input, before any tessellation.
        ccss_core::voxel::solid::check_closed_solid(fe.mesh())
            .map_err(|e| CliError::input(format!("{}: {e}", mesh.name)))?;
        let need = Tessellation::required_bytes_feature(fe, &opts, &mut Box::new(Scratch::ZERO))
            .map_err(err)?;
        let mut mem = words(need);
        let mut t = Tessellation::build_feature(fe, opts, &mut mem).map_err(err)?;
        let ev = |q: Query| Ok(fe.eval(q.face, q.sub, q.u, q.v)?.p);
        let mut r = emit_tris(&mut t, want_uv.then_some(&ev as SurfaceEval)).map_err(err)?;
        set_bounds(&mut r, tol, None);
        Ok(r)
    })
}

/// Fills [`TriMesh::tri_bound`] and [`TriMesh::min_tol`]: the
/// tessellation's bound, or (with a field) the field at each triangle's
/// box when smaller (module docs of `ccss_core::tessellate::ToleranceField`:
/// the triangle's box lies in its cell's box).
fn set_bounds(r: &mut TriMesh, tol: f64, field: Option<&Field>) {
    let p = |v: u32| DVec3::from_slice(&r.positions[3 * v as usize..3 * v as usize + 3]);
    r.tri_bound = match field {
        None => vec![r.bound; r.triangles.len() / 3],
        Some(f) => r
            .triangles
            .chunks_exact(3)
            .map(|t| {
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                f.tolerance(a.min(b).min(c), a.max(b).max(c))
                    .min(tol)
                    .min(r.bound)
            })
            .collect(),
    };
    r.tri_prior = r.tri_bound.clone();
    r.min_tol = field.map_or(tol, |f| f.min_tolerance().min(tol));
}

/// Lowers [`TriMesh::tri_bound`] of triangles `which` of `t` (a
/// tessellation of `mesh`) to their a-posteriori bounds
/// (`ccss_core::boolean::triangle_bound`: the actual deviation at
/// `SHARP_SAMPLES`-grid points plus a second-derivative term, a proven
/// bound), where smaller, and sets their [`TriMesh::tri_prior`] to their
/// cells' a-priori bounds. Feature tessellations keep their bounds.
/// A triangle whose bound is still above `fine_above` gets a second,
/// finer one (`SHARP_SAMPLES_FINE`; the smaller of the two is kept).
/// `cache` holds the bounds of earlier passes' triangles (the passes
/// re-tessellate most cells unchanged).
pub fn sharpen(
    mesh: &Mesh,
    t: &mut TriMesh,
    which: &mut Vec<u32>,
    fine_above: f64,
    cache: &mut BoundCache,
) -> CliResult<()> {
    which.sort_unstable();
    which.dedup();
    if !t.smooth || which.is_empty() {
        return Ok(());
    }
    let err = |e: ccss_core::Error| {
        CliError::failure(format!("{}: cannot bound a triangle: {e}", mesh.name))
    };
    let tm = &*t;
    let bounds = smooth_or_feature(mesh, &WeightsArg::default(), false, |ctx| {
        let ev = &ctx.evaluator;
        let mut eval = |q: Query| Ok(ev.eval(q.face, q.sub, q.u, q.v)?.p);
        let mut out = Vec::with_capacity(which.len());
        // Triangles of one polygon are consecutive: one cell bound each.
        let mut cached: Option<(u32, CellBound)> = None;
        for &k in which.iter() {
            let k = k as usize;
            let ci = tm.tri_cell[k];
            let cell = &tm.cells[ci as usize];
            let vs = [0, 1, 2].map(|c| tm.triangles[3 * k + c] as usize);
            let key = triangle_key(cell, &tm.positions, vs);
            let hit = cache.bounds.get(&key).copied();
            if let Some((b, prior, fine)) = hit {
                if fine || b <= fine_above {
                    out.push((b, prior));
                    continue;
                }
            }
            let cb = match cached {
                Some((c, cb)) if c == ci => cb,
                _ => {
                    let cb = cell_bound(ev, cell.face, cell.sub, cell.level, cell.i, cell.j)
                        .map_err(err)?;
                    cached = Some((ci, cb));
                    cb
                }
            };
            let pos = vs.map(|v| DVec3::from_slice(&tm.positions[3 * v..3 * v + 3]));
            let pt = match tm.uv.get(k) {
                Some(pt) => *pt,
                None => border_patch_triangle(cell, tm, vs, &pos, cache, &mut eval).map_err(err)?,
            };
            let mut b = match hit {
                Some((b, _, _)) => b,
                None => triangle_bound_in(ev, cell, &cb, &pt, &pos, SHARP_SAMPLES).map_err(err)?,
            };
            let fine = b > fine_above;
            if fine {
                let f = triangle_bound_in(ev, cell, &cb, &pt, &pos, SHARP_SAMPLES_FINE);
                b = b.min(f.map_err(err)?);
            }
            cache
                .bounds
                .insert(key, (b, cb.interpolation_bound(), fine));
            out.push((b, cb.interpolation_bound()));
        }
        Ok(out)
    })?;
    if let Some(b) = bounds {
        for (&k, (x, prior)) in which.iter().zip(b) {
            let k = k as usize;
            t.tri_bound[k] = t.tri_bound[k].min(x);
            t.tri_prior[k] = prior;
        }
    }
    Ok(())
}

/// What [`sharpen`] keeps across passes.
#[derive(Default)]
pub struct BoundCache {
    /// The a-posteriori and a-priori bounds of triangles met in earlier
    /// passes, by [`triangle_key`], and whether the finer bound was
    /// taken.
    bounds: HashMap<[u64; 12], (f64, f64, bool)>,
    /// `(u, v)` in sub-face `(face, sub)` of a vertex the tessellation
    /// wrote in a neighbour's parameters (`ccss_core::boolean::patch_triangle`
    /// finds it by a search of about 70 evaluations), by its position's
    /// bits and `(face, sub)`.
    border: HashMap<[u64; 4], (f64, f64)>,
}

/// [`patch_triangle`] of triangle `vs` of `t` in `cell`, with the
/// parameters of vertices on a sub-face border taken from
/// [`BoundCache::border`] where known (the same point of the border; the
/// bound measures the deviation at the corners anyway), the new ones
/// stored.
fn border_patch_triangle(
    cell: &PolygonCell,
    t: &TriMesh,
    vs: [usize; 3],
    pos: &[DVec3; 3],
    cache: &mut BoundCache,
    eval: &mut impl FnMut(Query) -> Result<DVec3, ccss_core::Error>,
) -> Result<PatchTriangle, ccss_core::Error> {
    let key = |c: usize| {
        let p = pos[c];
        let fs = (cell.face as u64) << 32 | cell.sub as u64;
        [p.x.to_bits(), p.y.to_bits(), p.z.to_bits(), fs]
    };
    let mut prm = vs.map(|v| t.params[v]);
    let mut found = [false; 3];
    for (c, q) in prm.iter_mut().enumerate() {
        if (q.face, q.sub) == (cell.face, cell.sub) {
            continue;
        }
        if let Some(&(u, v)) = cache.border.get(&key(c)) {
            *q = Query {
                face: cell.face,
                sub: cell.sub,
                u,
                v,
            };
        } else {
            found[c] = true;
        }
    }
    let pt = patch_triangle(cell, &prm, pos, eval)?;
    for c in (0..3).filter(|&c| found[c]) {
        cache
            .border
            .insert(key(c), (pt.uv[2 * c], pt.uv[2 * c + 1]));
    }
    Ok(pt)
}

/// A triangle of a tessellation as [`sharpen`] sees it: its cell and the
/// bits of its three corners (equal keys, equal bounds).
fn triangle_key(cell: &PolygonCell, positions: &[f64], vs: [usize; 3]) -> [u64; 12] {
    let mut k = [0u64; 12];
    k[0] = (cell.face as u64) << 32 | cell.sub as u64;
    k[1] = (cell.level as u64) << 32 | cell.i as u64;
    k[2] = cell.j as u64;
    for (c, &v) in vs.iter().enumerate() {
        for d in 0..3 {
            k[3 + 3 * c + d] = positions[3 * v + d].to_bits();
        }
    }
    k
}

/// Runs the core Boolean on two triangle meshes, expecting at most
/// `pairs_hint` crossing triangle pairs (a larger count builds twice).
pub fn combine(
    a: &TriMesh,
    b: &TriMesh,
    op: Op,
    opts: BoolOptions,
    pairs_hint: usize,
) -> Result<BoolResult, ccss_core::Error> {
    let sa = SolidMesh {
        positions: &a.positions,
        triangles: &a.triangles,
    };
    let sb = SolidMesh {
        positions: &b.positions,
        triangles: &b.triangles,
    };
    // One build: the block is sized for `pairs_hint` crossing pairs (its
    // untouched pages cost nothing); only more pairs than that build twice.
    let mut mem = words(Boolean::required_bytes_with_pairs(&sa, &sb, pairs_hint));
    let bo = match Boolean::build(sa, sb, op, opts, &mut mem) {
        Err(ccss_core::Error::BufferTooSmall { required }) => {
            mem = words(required);
            Boolean::build(sa, sb, op, opts, &mut mem)
        }
        r => r,
    };
    let mut bo = bo?;
    let c = bo.counts();
    let mut r = BoolResult {
        counts: c,
        stats: bo.stats(),
        positions: vec![0.0; 3 * c.vertices],
        triangles: vec![0; 3 * c.triangles],
        sources: vec![FaceSource::default(); c.triangles],
        uv: Vec::new(),
        curve_sizes: vec![0; c.curve_loops],
        curve_indices: vec![0; c.curve_points],
        tolerance: 0.0,
        bound: 0.0,
        passes: 0,
        local: false,
        crossings: Vec::with_capacity(c.crossing_pairs),
        reversed: [false; 2],
    };
    bo.crossings(&mut |x| r.crossings.push(x));
    bo.emit(Output {
        positions: &mut r.positions,
        triangles: &mut r.triangles,
        sources: Some(&mut r.sources),
        curve_sizes: &mut r.curve_sizes,
        curve_indices: &mut r.curve_indices,
    })?;
    if !a.uv.is_empty() && !b.uv.is_empty() {
        r.uv = vec![UvTriangle::default(); c.triangles];
        bo.emit_uv(&a.uv, &b.uv, &mut r.uv)?;
    }
    Ok(r)
}

/// The first pass's tolerance is `eps / FIRST_DIVISOR` on smooth meshes
/// (their crossing triangles get a-posteriori bounds, so a pass at `eps`
/// is often accepted as it is) and `eps / FIRST_DIVISOR_FEATURE` on meshes
/// with features (a-priori bounds only).
const FIRST_DIVISOR: f64 = 1.0;
/// See [`FIRST_DIVISOR`].
const FIRST_DIVISOR_FEATURE: f64 = 1.25;

/// Expected ratio of a crossing triangle's a-posteriori bound to its
/// tolerance: the local passes ask for `eps / (1.05 a SHARP_EXPECT)` near
/// a crossing of (effective) amplification `a`. 0.35 is about the mean
/// ratio measured (`ccss_core::boolean::triangle_bound`: 0.30-0.34). On
/// the six cases of `bench/boolean_bench.sh` (torus-cube and hands,
/// union / intersection / difference) 0.5 gives 5,336 / 1,478 / 5,518 /
/// 49,688 / 10,898 / 31,240 triangles, 0.45 5,274 / 1,412 / 5,442 /
/// 49,122 / 10,436 / 30,600, 0.35 5,252 / 1,382 / 5,540 / 48,786 /
/// 10,140 / 29,996, 0.3 5,252 / 1,382 / 5,566 / 48,868 / 10,062 / 30,090
/// (more passes the lower it is; bench-log 2026-11-27 `bool9`).
const SHARP_EXPECT: f64 = 0.35;

/// The tolerance of smooth meshes' cells no other rule lowers, in units of
/// `eps`: the a-posteriori bounds of every triangle certify what the
/// a-priori bound of `SLACK eps` tessellates to (module docs). On the
/// pairs of `bench/boolean_bench.sh`: 2 and 2.5 about equal on torus-cube
/// (6,280 / 6,542 union triangles before the centroid rule), 2.5 fewer on
/// the hands (34,634 / 35,694), 3 more (35,046, error 0.72 eps). (These
/// hands figures, like the others in this file before session 8, are of
/// the pair with the left hand inside out, i.e. its complement; on the
/// true pair 2, 2.5, 3 and 3.5 give the union 54,372 / 50,434 / 48,552 /
/// 47,416 triangles at 0.474 / 0.474 / 0.803 / 0.886 eps: bench-log
/// `bool8`.)
const SLACK: f64 = 2.5;

/// The tolerance asked for near a triangle whose bound `b` is above
/// `eps` is `eps prior / b` times this (`prior` its cell's a-priori bound:
/// the cell splits, and the ratio of bound to a-priori bound carries
/// over to its children), so the next pass's bound is about this times
/// `eps`.
const TIGHT_MARGIN: f64 = 0.9;

/// Appends the triangles of `t` whose bound is above `eps`.
fn above(t: &TriMesh, eps: f64, out: &mut Vec<u32>) {
    let over = t.tri_bound.iter().enumerate().filter(|(_, &b)| b > eps);
    out.extend(over.map(|(k, _)| k as u32));
}

/// Appends the boxes of `t`'s triangles whose bound is above `eps`, with
/// the tolerance asked for there ([`TIGHT_MARGIN`]).
fn add_tight(t: &TriMesh, eps: f64, out: &mut Vec<TightBox>) {
    let p = |v: u32| DVec3::from_slice(&t.positions[3 * v as usize..3 * v as usize + 3]);
    for (k, tri) in t.triangles.chunks_exact(3).enumerate() {
        let b = t.tri_bound[k];
        if b <= eps {
            continue;
        }
        // The centroid: in the box of the triangle's own cell (the
        // triangle lies in the convex hull of the cell's surface), in few
        // of its neighbours' (the triangle's box would meet all of them).
        let c = (p(tri[0]) + p(tri[1]) + p(tri[2])) / 3.0;
        let ratio = (t.tri_prior[k] / b).max(1.0);
        out.push(TightBox {
            bounds: [c.x, c.y, c.z, c.x, c.y, c.z],
            tolerance: TIGHT_MARGIN * eps * ratio,
        });
    }
}

/// Most passes of the tolerance loop. The looser requests of the
/// effective amplification certify later than the full amplification
/// did: on `bench/boolean_bench.sh` the first certified pass comes as
/// late as the 5th (before: the 2nd or 3rd), so 8 leaves room (75 runs
/// at other placements of the torus-cube kind, eps 1e-3 and 3e-3:
/// written pass at most the 5th).
const MAX_PASSES: u32 = 8;

/// The error bound of a combination: the largest triangle bound of both
/// tessellations, and `crossing_bound(amplification, t_A, t_B)` (at most
/// `amplification x max(t_A, t_B)`) over the crossings (module docs).
fn error_bound(ta: &TriMesh, tb: &TriMesh, r: &BoolResult) -> f64 {
    // Every triangle's own bound (at most its tessellation's bound).
    let mut b = ta
        .tri_bound
        .iter()
        .chain(&tb.tri_bound)
        .fold(0.0f64, |m, &x| m.max(x));
    for x in &r.crossings {
        let ba = ta.tri_bound[x.triangle_a as usize];
        let bb = tb.tri_bound[x.triangle_b as usize];
        b = b.max(crossing_bound(x.amplification, ba, bb));
    }
    b
}

/// The whole pipeline: a first pass with one tolerance everywhere, then
/// local passes with tolerance fields (module docs) until the error bound
/// is at most `eps`, and on while the certified output shrinks (a
/// degenerate contact of two tessellations retries with 0.9 times the
/// tolerances). With `want_uv`, [`BoolResult::uv`] is filled.
pub fn run(
    a: &Mesh,
    b: &Mesh,
    op: Op,
    eps: f64,
    opts: BoolOptions,
    want_uv: bool,
    progress: &Progress,
) -> CliResult<BoolResult> {
    let first_divisor = if a.tags.any() || b.tags.any() {
        FIRST_DIVISOR_FEATURE
    } else {
        FIRST_DIVISOR
    };
    let first = boolean::tessellation_tolerance(eps, first_divisor)
        .map_err(|e| CliError::input(format!("--eps: {e}")))?;
    // Smooth meshes: every triangle gets its a-posteriori bound, so the
    // passes may tessellate at `SLACK eps` wherever that certifies.
    let mut base = if first_divisor == FIRST_DIVISOR {
        SLACK * eps
    } else {
        eps
    };
    let mut tol = base.max(first);
    // Triangle boxes whose bound was above eps, per solid (kept for every
    // later pass, like `failed`).
    let mut tight_a: Vec<TightBox> = Vec::new();
    let mut tight_b: Vec<TightBox> = Vec::new();
    let (mut cache_a, mut cache_b) = (BoundCache::default(), BoundCache::default());
    // The fields of A and B for the next pass (none: global `tol`).
    let mut fields: Option<(Field, Field)> = None;
    let mut prev_pairs = 0usize;
    // Crossings that failed their certificate in earlier passes, with the
    // a-priori divisor (kept for every later pass: refinement only grows
    // where it was needed).
    let mut failed: Vec<CrossingReach> = Vec::new();
    // Whether A (B) is inside out: decided on the first pass.
    let (mut rev_a, mut rev_b) = (None, None);
    // Whether a crossing ever failed on A's (B's) side (below).
    let (mut need_a, mut need_b) = (false, false);
    // The certified result with the fewest triangles so far.
    let mut best: Option<BoolResult> = None;
    for pass in 1..=MAX_PASSES {
        progress.phase("tessellating", 2);
        let fa = fields.as_ref().map(|f| &f.0);
        let fb = fields.as_ref().map(|f| &f.1);
        let mut ta = tessellate(a, tol, fa, want_uv, progress)?;
        progress.inc();
        let mut tb = tessellate(b, tol, fb, want_uv, progress)?;
        progress.inc();
        let reversed = [orient(&mut ta, &mut rev_a), orient(&mut tb, &mut rev_b)];
        // Only smooth tessellations get a-posteriori bounds: otherwise
        // back to `eps` everywhere.
        if base > eps && !(ta.smooth && tb.smooth) {
            base = eps;
            tol = first;
            fields = None;
            continue;
        }
        progress.phase("combining", 1);
        // Crossing pairs grow about like the square root of the
        // triangles; a previous pass's count, doubled, bounds the next one's
        // in practice.
        let guess = 16.0 * ((ta.triangles.len() + tb.triangles.len()) as f64).sqrt();
        let hint = (guess as usize).max(2 * prev_pairs).max(1024);
        let mut r = match combine(&ta, &tb, op, opts, hint) {
            // An artefact of these two tessellations: other tolerances
            // give other triangles.
            Err(ccss_core::Error::DegenerateContact { .. }) if pass < MAX_PASSES => {
                tol *= 0.9;
                continue;
            }
            r => r.map_err(|e| bool_err(e, a, b, &ta, &tb))?,
        };
        progress.inc();
        prev_pairs = r.crossings.len();
        // The a-posteriori bounds of the crossing triangles and, when the
        // pass spends the slack, of every triangle whose a-priori bound is
        // above eps.
        let mut wa: Vec<u32> = r.crossings.iter().map(|x| x.triangle_a).collect();
        let mut wb: Vec<u32> = r.crossings.iter().map(|x| x.triangle_b).collect();
        if base > eps {
            above(&ta, eps, &mut wa);
            above(&tb, eps, &mut wb);
        }
        // The finer bound where the first one would fail the
        // certificate: above `eps / a`, `a` the pass's largest
        // amplification (a crossing's triangles need `a t <= eps`).
        let fine_above = eps / r.stats.amplification.max(1.0);
        sharpen(a, &mut ta, &mut wa, fine_above, &mut cache_a)?;
        sharpen(b, &mut tb, &mut wb, fine_above, &mut cache_b)?;
        let bound = error_bound(&ta, &tb, &r);
        // This pass's result, whose crossings the next pass's field
        // follows (kept in `best` when certified).
        let uncertified;
        let cur: &BoolResult = if bound <= eps {
            r.tolerance = ta.min_tol.min(tb.min_tol);
            r.bound = bound;
            r.passes = pass;
            r.local = fields.is_some();
            r.reversed = reversed;
            // A certified pass: one more local pass, whose band follows
            // this pass's (closer) curve, may certify with fewer
            // triangles; the smaller certified result is kept.
            if let Some(b) = best.take_if(|b| r.counts.triangles >= b.counts.triangles) {
                return Ok(b);
            }
            if pass == MAX_PASSES {
                return Ok(r);
            }
            best.insert(r)
        } else if let Some(b) = best {
            // The pass after a certified one did not certify.
            return Ok(b);
        } else if pass == MAX_PASSES {
            return Err(CliError::failure(format!(
                "cannot reach --eps {eps:e}: after {pass} passes the bound is {bound:.3e} (amplification {:.3})",
                r.stats.amplification
            )));
        } else {
            uncertified = r;
            &uncertified
        };
        // Local passes: cells far from the other solid keep eps. Each
        // crossing reaches as far as its own error bound + 2 eps and asks
        // for `eps / (1.05 a s)` near it, `s` the expected ratio of the
        // a-posteriori bound to the tolerance; crossings whose certificate
        // failed ask for the a-priori `eps / (1.05 a k)` from now on, `k`
        // a safety factor growing per pass.
        //
        // A solid that was never the worse side of a failing crossing nor
        // failed one on its own (`a t_X > eps`) gets none of these
        // requests: its cells near the curve keep `base` (on the
        // torus-cube pair of `bench/boolean_bench.sh` the torus passes at
        // every crossing and the cube's corners fail; intersection 1,808
        // -> 1,650 triangles). Once one of its crossings fails it takes them all,
        // as both solids' do on the hands: the facet normals of both
        // sides set the amplification, and refining only the failing side
        // costs more triangles there (32,668 -> 35,946 union). A solid
        // that needed them once keeps needing them.
        let shrink = 1.0 + 0.1 * (pass as f64 - 1.0);
        let mut segs: Vec<CrossingReach> = Vec::with_capacity(cur.crossings.len() + failed.len());
        for x in &cur.crossings {
            let (ka, kb) = (x.triangle_a as usize, x.triangle_b as usize);
            let (t_a, t_b) = (ta.tri_bound[ka], tb.tri_bound[kb]);
            let t = t_a.max(t_b);
            let amp = x.amplification.max(1.0);
            // The crossing's bound (`ccss_core::boolean::crossing_bound`,
            // the two sheets' bounds kept apart) and its ratio to the
            // larger bound: the amplification this crossing actually
            // has, at most `amp` (equal bounds).
            let h = crossing_bound(amp, t_a, t_b);
            let eff = (h / t.max(f64::MIN_POSITIVE)).clamp(1.0, amp);
            // A failing crossing needs its worse side refined, and a side
            // whose own bound fails at equal bounds (`a t_X > eps`).
            need_a |= h > eps && (t_a >= t_b || amp * t_a > eps);
            need_b |= h > eps && (t_b >= t_a || amp * t_b > eps);
            let reach = h + 2.0 * eps;
            // With slack, the measured ratio of bound to a-priori bound of
            // its two triangles replaces the expected one (and 1 after a
            // failure): the children of a cell keep about its ratio.
            let ratio = if base > eps {
                (t_a / ta.tri_prior[ka].max(f64::MIN_POSITIVE))
                    .max(t_b / tb.tri_prior[kb].max(f64::MIN_POSITIVE))
                    .min(1.0)
            } else {
                1.0
            };
            // The first pass is global: its failures are expected.
            if h > eps && fields.is_some() {
                let divisor = match base > eps {
                    true => eff * ratio * shrink / TIGHT_MARGIN,
                    false => 1.05 * eff * shrink,
                };
                failed.push(CrossingReach {
                    ends: x.ends,
                    divisor,
                    reach,
                });
            }
            segs.push(CrossingReach {
                ends: x.ends,
                divisor: 1.05 * eff * SHARP_EXPECT,
                reach,
            });
        }
        segs.extend_from_slice(&failed);
        let segs_a: &[CrossingReach] = if need_a { &segs } else { &[] };
        let segs_b: &[CrossingReach] = if need_b { &segs } else { &[] };
        add_tight(&ta, eps, &mut tight_a);
        add_tight(&tb, eps, &mut tight_b);
        fields = Some((
            Field::new(
                eps,
                base,
                &tb.positions,
                &tb.triangles,
                tb.bound,
                segs_a,
                &tight_a,
            ),
            Field::new(
                eps,
                base,
                &ta.positions,
                &ta.triangles,
                ta.bound,
                segs_b,
                &tight_b,
            ),
        ));
        tol = base;
    }
    unreachable!("the loop returns on its last pass")
}

/// A core error of the Boolean, naming the faces of both inputs.
fn bool_err(e: ccss_core::Error, a: &Mesh, b: &Mesh, ta: &TriMesh, tb: &TriMesh) -> CliError {
    let face = |t: &TriMesh, i: u32| t.tri_face.get(i as usize).copied().unwrap_or(u32::MAX);
    match e {
        ccss_core::Error::NearTangential {
            triangle_a,
            triangle_b,
            ..
        } => {
            let e = ccss_core::Error::NearTangential {
                face_a: face(ta, triangle_a),
                face_b: face(tb, triangle_b),
                triangle_a,
                triangle_b,
            };
            CliError::failure(format!("{} and {}: {e}", a.name, b.name))
        }
        ccss_core::Error::DegenerateContact {
            triangle_a,
            triangle_b,
            ..
        } => CliError::failure(format!(
            "{} and {}: {e} (face {} of A, face {} of B)",
            a.name,
            b.name,
            face(ta, triangle_a) as i64,
            face(tb, triangle_b) as i64,
        )),
        _ => CliError::failure(format!("{} and {}: {e}", a.name, b.name)),
    }
}
