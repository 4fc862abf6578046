//! `ccss closest [--tol T] MESH.obj`: certified closest points on the
//! limit surface (ccss-core's `query::closest`) for points read from stdin.

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::stdin_rows::read_rows;
use crate::io::stdin_rows::Row;
use crate::progress::Progress;
use crate::stdout;
use crate::surface::{with_surface, FeatureArgs, SurfaceJob};
use crate::verbs::raycast::tolerance;
use ccss_core::query::{closest, ClosestOptions, QuerySurface, QueryWork};
use ccss_core::{DVec3, Weights};
use rayon::prelude::*;
use std::path::PathBuf;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Certified closest point on the limit surface. Each stdin line is 'x y z'; blank lines and \
lines starting with '#' are skipped. For each point one line, in input order: 'dist face sub \
u v px py pz' (numbers as 'ccss eval' writes them), p the exact limit point S(face, sub, u, v) and dist = |p - x|. Certified: the \
global minimum (not a local Newton result) to within --tol (model units; default 1e-9 times \
the diagonal of the control points' box): dist is at most the true minimum distance plus \
tol (branch and bound on the guaranteed cell bounds). A bad line fails with 'ccss: error: \
stdin line N: <reason>' (exit code 2) before any output. OpenSubdiv tags and --boundary / \
--creasing are honoured; open meshes are fine. Points run on all cores.";

/// Arguments of `ccss closest`.
#[derive(clap::Args, Debug)]
pub struct ClosestArgs {
    /// Polygon mesh (OBJ; OpenSubdiv tags honoured, open meshes allowed).
    pub mesh: PathBuf,
    /// Tolerance in model units (default: 1e-9 x the control box diagonal).
    #[arg(long, value_name = "T")]
    pub tol: Option<f64>,
    /// Print one line to stderr after the queries: `ccss closest:
    /// points=N seconds=S points_per_s=R` (query loop only; for
    /// benchmarks, `bench/closest_bench.sh`).
    #[arg(long)]
    pub timing: bool,
    /// Work budget: cells one query may visit before it stops with
    /// `work limit exceeded` (docs/WORST_CASE.md).
    #[arg(long, value_name = "N", default_value_t = ccss_core::query::MAX_CELLS)]
    pub max_cells: u64,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// Runs the verb on stdin/stdout.
pub fn run(a: &ClosestArgs) -> CliResult {
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let tol = tolerance(a.tol, &mesh.positions)?;
    let rows = read_rows(std::io::stdin().lock(), 3)?;
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let opts = ClosestOptions {
        tol,
        max_cells: a.max_cells,
    };
    with_surface(
        &mesh,
        &tables,
        a.features,
        Job {
            rows: &rows,
            opts,
            timing: a.timing,
        },
    )
}

/// The verb's work on either surface.
struct Job<'j> {
    rows: &'j [Row],
    opts: ClosestOptions,
    timing: bool,
}

impl SurfaceJob<()> for Job<'_> {
    fn run<S: QuerySurface + Sync + ?Sized>(self, ev: &S, _feature: bool) -> CliResult {
        crate::surface::with_index(ev, |ev| {
            let (rows, opts) = (self.rows, self.opts);
            let bar = Progress::delayed("{msg} [{bar:40}] {pos}/{len} points");
            bar.phase("closest", rows.len());
            let t0 = std::time::Instant::now();
            let lines: Vec<CliResult<String>> =
                rows.par_iter()
                    .map_init(
                        || Box::new(QueryWork::ZERO),
                        |w, r| {
                            let v = &r.values;
                            let c = closest(ev, DVec3::new(v[0], v[1], v[2]), &opts, w).map_err(
                                |e| CliError::failure(format!("stdin line {}: {e}", r.line)),
                            )?;
                            bar.inc();
                            Ok(format!(
                                "{:.16e} {} {} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e}\n",
                                c.dist, c.face, c.sub, c.u, c.v, c.point.x, c.point.y, c.point.z
                            ))
                        },
                    )
                    .collect();
            let seconds = t0.elapsed().as_secs_f64();
            bar.finish();
            if self.timing {
                eprintln!(
                    "ccss closest: points={} seconds={seconds:.6} points_per_s={:.0}",
                    rows.len(),
                    rows.len() as f64 / seconds
                );
            }
            let mut out = String::new();
            for l in lines {
                out.push_str(&l?);
            }
            stdout::text(&out)
        })
    }
}
