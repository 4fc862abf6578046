//! The Boolean pipeline of `ccss boolean` and `ccss bench boolean`:
//! tessellate both solids with a guaranteed bound `t`, combine the two
//! inscribed meshes with `ccss_core::boolean` (exact predicates), and
//! shrink `t` until `amplification x t <= eps` (see the core module's
//! error bound).

use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::parallel::tessellate::mark_parallel;
use crate::progress::Progress;
use crate::verbs::eval::{smooth_or_feature, with_feature_mesh};
use ccss_core::boolean::{
    self, patch_triangles, Boolean, Counts, FaceSource, Op, Options as BoolOptions, Output,
    PatchTriangle, SolidMesh, Stats, TessellationUv, UvTriangle,
};
use ccss_core::tessellate::{Options, Output as TessOutput, PolygonCell, Scratch, Tessellation};
use ccss_core::{DVec3, Query};

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
    /// `amplification x max(tessellation bounds)`: the error bound.
    pub bound: f64,
    /// Passes run.
    pub passes: u32,
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
    };
    let mut sizes = vec![0u32; c.polygons];
    let mut idx = vec![0u32; c.polygon_indices];
    let mut cells = vec![PolygonCell::default(); c.polygons];
    let mut params = vec![Query::default(); if uv.is_some() { c.vertices } else { 0 }];
    t.emit(TessOutput {
        positions: &mut r.positions,
        normals: None,
        params: uv.is_some().then_some(&mut params[..]),
        polygon_sizes: &mut sizes,
        polygon_indices: &mut idx,
        triangles: Some(&mut r.triangles),
        cells: Some(&mut cells),
    })?;
    for (p, &n) in sizes.iter().enumerate() {
        for _ in 2..n {
            r.tri_face.push(cells[p].face);
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
    Ok(r)
}

/// Tessellates `mesh` at absolute tolerance `tol` (smooth path on all
/// cores for marking, or the feature path on one); with `want_uv`, the
/// parameter-space triangles too.
pub fn tessellate(mesh: &Mesh, tol: f64, want_uv: bool, progress: &Progress) -> CliResult<TriMesh> {
    let opts = Options::absolute(tol);
    let err =
        |e: ccss_core::Error| CliError::failure(format!("{}: cannot tessellate: {e}", mesh.name));
    let smooth = smooth_or_feature(mesh, &WeightsArg::default(), false, |ctx| {
        let (marks, trees) = mark_parallel(&ctx.evaluator, &opts, progress).map_err(err)?;
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
        emit_tris(&mut t, want_uv.then_some(&ev as SurfaceEval)).map_err(err)
    })?;
    if let Some(t) = smooth {
        return Ok(t);
    }
    with_feature_mesh(mesh, None, None, |fe| {
        // Open meshes, holes: named on the input, before any tessellation.
        ccss_core::voxel::solid::check_closed_solid(fe.mesh())
            .map_err(|e| CliError::input(format!("{}: {e}", mesh.name)))?;
        let need = Tessellation::required_bytes_feature(fe, &opts, &mut Box::new(Scratch::ZERO))
            .map_err(err)?;
        let mut mem = words(need);
        let mut t = Tessellation::build_feature(fe, opts, &mut mem).map_err(err)?;
        let ev = |q: Query| Ok(fe.eval(q.face, q.sub, q.u, q.v)?.p);
        emit_tris(&mut t, want_uv.then_some(&ev as SurfaceEval)).map_err(err)
    })
}

/// Runs the core Boolean on two triangle meshes.
pub fn combine(
    a: &TriMesh,
    b: &TriMesh,
    op: Op,
    opts: BoolOptions,
) -> Result<BoolResult, ccss_core::Error> {
    let sa = SolidMesh {
        positions: &a.positions,
        triangles: &a.triangles,
    };
    let sb = SolidMesh {
        positions: &b.positions,
        triangles: &b.triangles,
    };
    let mut mem = words(Boolean::required_bytes_base(&sa, &sb));
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
    };
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

/// Most passes of the tolerance loop.
const MAX_PASSES: u32 = 6;

/// The whole pipeline: first pass at `eps / 1.25`, then `t = eps / (1.05 a)`
/// until `a x bound <= eps` (a degenerate contact of two tessellations
/// retries at `0.9 t`). With `want_uv`, [`BoolResult::uv`] is filled.
pub fn run(
    a: &Mesh,
    b: &Mesh,
    op: Op,
    eps: f64,
    opts: BoolOptions,
    want_uv: bool,
    progress: &Progress,
) -> CliResult<BoolResult> {
    let mut tol = boolean::tessellation_tolerance(eps, 1.25)
        .map_err(|e| CliError::input(format!("--eps: {e}")))?;
    for pass in 1..=MAX_PASSES {
        progress.phase("tessellating", 2);
        let ta = tessellate(a, tol, want_uv, progress)?;
        progress.inc();
        let tb = tessellate(b, tol, want_uv, progress)?;
        progress.inc();
        progress.phase("combining", 1);
        let mut r = match combine(&ta, &tb, op, opts) {
            // An artefact of these two tessellations: another tolerance
            // gives other triangles.
            Err(ccss_core::Error::DegenerateContact { .. }) if pass < MAX_PASSES => {
                tol *= 0.9;
                continue;
            }
            r => r.map_err(|e| bool_err(e, a, b, &ta, &tb))?,
        };
        progress.inc();
        let bound = ta.bound.max(tb.bound);
        let amp = r.stats.amplification.max(1.0);
        if amp * bound <= eps || pass == MAX_PASSES {
            if amp * bound > eps {
                return Err(CliError::failure(format!(
                    "cannot reach --eps {eps:e}: after {pass} passes the bound is {:.3e} (amplification {amp:.3})",
                    amp * bound
                )));
            }
            r.tolerance = tol;
            r.bound = amp * bound;
            r.passes = pass;
            return Ok(r);
        }
        tol = boolean::tessellation_tolerance(eps, 1.05 * amp)
            .map_err(|e| CliError::input(format!("--eps: {e}")))?;
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
