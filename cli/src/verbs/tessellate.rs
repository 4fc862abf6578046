//! `ccss tessellate (--abs-flatness E | --rel-flatness R) [--triangulate]
//! MESH.obj -o OUT.(obj|stl|ply)`: error-controlled adaptive tessellation
//! of the limit surface (`ccss_core::tessellate`).
//!
//! Prints one line (stdout):
//!
//! ```text
//! polygons=1234 triangles=2600 vertices=1400 max_depth=9 uniform_depth=9 au_ratio=0.00458 bound=0.00099 seconds=0.0123
//! ```
//!
//! * `triangles`: triangles of the triangulated polygons (written when
//!   `--triangulate` is given or the output is STL);
//! * `max_depth`: deepest quadtree level of the adaptive tessellation;
//! * `uniform_depth`: the smallest uniform level L such that every level-L
//!   cell of every (sub-)face passes the same test (so the uniform
//!   tessellation meets the same guaranteed bound); `none` above level 30;
//! * `au_ratio`: polygons / polygons of that uniform tessellation (slots x
//!   4^L), as in the report's Table 7.1;
//! * `bound`: the guaranteed bound of the output (largest cell bound; model
//!   units);
//! * `seconds`: wall time of marking (all cores) + counting + emission
//!   (one core); not the uniform check, not writing the file.
//!
//! A progress bar appears on stderr when a phase runs for more than half a
//! second and stderr is a terminal.
//!
//! Meshes with OpenSubdiv tags (creases, corners, holes, boundary options),
//! open or non-manifold meshes, and any mesh given `--boundary` or
//! `--creasing` take the feature path (`Tessellation::build_feature`, one
//! core), routed as `ccss eval` routes them
//! ([`crate::verbs::eval::smooth_or_feature`]); there `uniform_depth` and
//! `au_ratio` are not computed (`-`) and the line ends with
//! `boundary_edges=N`, the output edges in one polygon (0 for a closed
//! input).

use crate::context::Context;
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::mesh_out::{self, Format, MeshOut};
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::parallel::tessellate::{emit_vecs, tessellate, uniform_depth, Tess, PROGRESS};
use crate::progress::Progress;
use crate::stdout;
use crate::verbs::eval::{smooth_or_feature, with_feature_mesh, BoundaryArg, CreasingArg};
use ccss_core::tessellate::{Criterion, Options, Scratch, Tessellation};
use ccss_core::FeatureEvaluator;
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Adaptive tessellation of the limit surface with a guaranteed error bound. Every output vertex \
is an exact limit point; each (sub-)face's parameter square is split into dyadic cells until \
every cell is flat enough, measured by a guaranteed bound on the distance between the \
surface and any triangulation of the cell's polygon (not by sampling). --abs-flatness E: the \
bound is at most E (model units). --rel-flatness R: the bound is at most R times the longer \
diagonal of the cell's corner quad (invariant under scaling and rotation; cells at \
extraordinary vertices, whose ratio does not shrink, are accepted at R times the (sub-)face's \
diagonal). Cracks are eliminated by inserting every vertex of finer neighbours into a cell's \
polygon, so a closed input gives a closed, consistently oriented 2-manifold. -o OUT: .obj \
(polygons, or triangles with --triangulate; with vertex normals), .stl (binary, always \
triangles) or .ply (binary little endian, with normals). Prints one line 'polygons=P \
triangles=T vertices=V max_depth=D uniform_depth=L au_ratio=A bound=B seconds=S': D the \
deepest cell level, L the smallest uniform level whose cells all pass the same test ('none' \
above 30), A = P / (sub-faces x 4^L), B the guaranteed bound of the output, S the wall time \
of marking (all cores; RAYON_NUM_THREADS to change) and emission. A tolerance that needs \
more than --max-level (30) levels fails (exit code 2). --weights W.tsv: see 'ccss eval \
--help'. Meshes with OpenSubdiv tags ('t crease', 't corner', 't hole', \
't interpolateboundary', 't creasemethod'), open or non-manifold meshes and meshes given \
--boundary none|edge|edge-corner or --creasing uniform|chaikin are tessellated with \
OpenSubdiv's rules (one core): the same guarantee, with cells next to irregular crease, \
corner, boundary or extraordinary vertices bounded by the convex hull of their control \
points (deeper there; for --rel-flatness such cells are also accepted at R times the \
(sub-)face's diagonal); hole faces produce nothing; an open input gives an open output \
whose boundary loops lie on the input's boundary and hole borders; the line then has \
uniform_depth=- au_ratio=- and ends with boundary_edges=N.";

/// Arguments of `ccss tessellate`.
#[derive(clap::Args, Debug)]
#[command(group(clap::ArgGroup::new("flatness").required(true).args(["abs_flatness", "rel_flatness"])))]
pub struct TessellateArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Absolute flatness: guaranteed distance bound in model units.
    #[arg(long, value_name = "E", value_parser = parse_tol, allow_negative_numbers = true)]
    pub abs_flatness: Option<f64>,
    /// Relative flatness: bound / longer diagonal of each cell's corner quad.
    #[arg(long, value_name = "R", value_parser = parse_tol, allow_negative_numbers = true)]
    pub rel_flatness: Option<f64>,
    /// Write triangles instead of polygons (STL output is always triangles).
    #[arg(long)]
    pub triangulate: bool,
    /// Output file: .obj, .stl (binary) or .ply (binary).
    #[arg(short = 'o', long, value_name = "OUT")]
    pub output: PathBuf,
    /// Deepest quadtree level (1..=30); a tolerance that needs more is an error.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=30))]
    pub max_level: u32,
    #[command(flatten)]
    pub weights: WeightsArg,
    /// Boundary interpolation (overrides 't interpolateboundary'):
    /// none, edge (edge-only) or edge-corner.
    #[arg(long, value_name = "MODE")]
    pub boundary: Option<BoundaryArg>,
    /// Creasing method (overrides 't creasemethod'): uniform or chaikin.
    #[arg(long, value_name = "METHOD")]
    pub creasing: Option<CreasingArg>,
}

/// Parses a tolerance: positive and finite.
pub fn parse_tol(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(e) if e.is_finite() && e > 0.0 => Ok(e),
        Ok(_) => Err("the tolerance must be positive and finite".into()),
        Err(_) => Err(format!("'{s}' is not a number")),
    }
}

/// The criterion of the two options (exactly one is given).
pub fn criterion(abs: Option<f64>, rel: Option<f64>) -> Criterion {
    match (abs, rel) {
        (Some(e), _) => Criterion::Absolute(e),
        (None, Some(r)) => Criterion::Relative(r),
        (None, None) => Criterion::Absolute(f64::NAN),
    }
}

/// Maps a core error to a CLI error naming the mesh.
pub fn core_err(mesh: &str, e: ccss_core::Error) -> CliError {
    match e {
        ccss_core::Error::InvalidArgument(_) => {
            CliError::input(format!("{mesh}: cannot tessellate: {e}"))
        }
        _ => CliError::failure(format!("{mesh}: cannot tessellate: {e}")),
    }
}

/// polygons / (slots 4^L).
pub fn au_ratio(polygons: usize, slots: usize, l: Option<u32>) -> f64 {
    match l {
        Some(l) => polygons as f64 / (slots as f64 * 4f64.powi(l as i32)),
        None => f64::NAN,
    }
}

fn run_ctx(a: &TessellateArgs, mesh: &Mesh, ctx: &Context, format: Format) -> CliResult {
    let crit = criterion(a.abs_flatness, a.rel_flatness);
    let opts = Options {
        criterion: crit,
        max_level: a.max_level,
    };
    let tri = a.triangulate || format == Format::Stl;
    let progress = Progress::delayed(PROGRESS);
    let t0 = Instant::now();
    let t = tessellate(&ctx.topology, &ctx.evaluator, opts, tri, &progress)
        .map_err(|e| core_err(&mesh.name, e))?;
    let seconds = t0.elapsed().as_secs_f64();
    let ud = uniform_depth(&ctx.evaluator, crit, t.stats.max_level, &progress)
        .map_err(|e| core_err(&mesh.name, e))?;
    progress.finish();
    write_out(&a.output, format, &t, tri)?;
    let ud_s = ud.map_or("none".to_string(), |l| l.to_string());
    stdout::line(&format!(
        "polygons={} triangles={} vertices={} max_depth={} uniform_depth={ud_s} au_ratio={:.6} bound={:.6e} seconds={seconds:.6}",
        t.counts.polygons,
        t.counts.triangles,
        t.counts.vertices,
        t.stats.max_level,
        au_ratio(t.counts.polygons, ctx.evaluator.num_slots(), ud),
        t.stats.bound,
    ))
}

/// Writes a tessellation (its triangles with `tri`).
fn write_out(path: &std::path::Path, format: Format, t: &Tess, tri: bool) -> CliResult {
    let tri_sizes;
    let out = if tri {
        tri_sizes = vec![3u32; t.counts.triangles];
        MeshOut {
            positions: &t.positions,
            normals: &t.normals,
            face_sizes: &tri_sizes,
            indices: &t.triangles,
        }
    } else {
        MeshOut {
            positions: &t.positions,
            normals: &t.normals,
            face_sizes: &t.sizes,
            indices: &t.indices,
        }
    };
    mesh_out::write(path, format, &out)
}

/// Output edges in exactly one polygon (each polygon edge counted by its
/// unordered end points).
fn boundary_edges(t: &Tess) -> usize {
    let mut count = std::collections::HashMap::<(u32, u32), u32>::new();
    let mut at = 0;
    for &n in &t.sizes {
        let p = &t.indices[at..at + n as usize];
        at += n as usize;
        for k in 0..p.len() {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    count.values().filter(|&&c| c == 1).count()
}

/// The feature path: one core, marking and emission.
fn run_feature(
    a: &TessellateArgs,
    mesh: &Mesh,
    fe: &FeatureEvaluator,
    format: Format,
) -> CliResult {
    let opts = Options {
        criterion: criterion(a.abs_flatness, a.rel_flatness),
        max_level: a.max_level,
    };
    let tri = a.triangulate || format == Format::Stl;
    let progress = Progress::delayed(PROGRESS);
    progress.phase("tessellating", 1);
    let t0 = Instant::now();
    let err = |e| core_err(&mesh.name, e);
    let need = Tessellation::required_bytes_feature(fe, &opts, &mut Box::new(Scratch::ZERO))
        .map_err(err)?;
    let mut mem = words(need);
    let mut t = Tessellation::build_feature(fe, opts, &mut mem).map_err(err)?;
    let t = emit_vecs(&mut t, tri).map_err(err)?;
    let seconds = t0.elapsed().as_secs_f64();
    progress.inc();
    progress.finish();
    write_out(&a.output, format, &t, tri)?;
    stdout::line(&format!(
        "polygons={} triangles={} vertices={} max_depth={} uniform_depth=- au_ratio=- bound={:.6e} seconds={seconds:.6} boundary_edges={}",
        t.counts.polygons,
        t.counts.triangles,
        t.counts.vertices,
        t.stats.max_level,
        t.stats.bound,
        boundary_edges(&t),
    ))
}

/// Runs the verb.
pub fn run(a: &TessellateArgs) -> CliResult {
    let Some(format) = Format::of(&a.output) else {
        return Err(CliError::input(format!(
            "{}: unknown output format; use .obj, .stl or .ply",
            a.output.display()
        )));
    };
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let forced = a.boundary.is_some() || a.creasing.is_some();
    if let Some(r) = smooth_or_feature(&mesh, &a.weights, forced, |ctx| {
        run_ctx(a, &mesh, ctx, format)
    })? {
        return Ok(r);
    }
    with_feature_mesh(&mesh, a.boundary, a.creasing, |fe| {
        run_feature(a, &mesh, fe, format)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerances_and_ratio() {
        assert_eq!(parse_tol("0.01"), Ok(0.01));
        for bad in ["0", "-1", "nan", "inf"] {
            assert!(parse_tol(bad).is_err(), "{bad}");
        }
        assert!(parse_tol("x").unwrap_err().contains("not a number"));
        assert_eq!(criterion(Some(1.0), None), Criterion::Absolute(1.0));
        assert_eq!(criterion(None, Some(0.1)), Criterion::Relative(0.1));
        assert_eq!(au_ratio(24, 6, Some(1)), 1.0);
        assert!(au_ratio(1, 1, None).is_nan());
    }
}
