//! `ccss raycast [--all] [--tol T] MESH.obj`: certified ray intersection
//! (ccss-core's `query::ray_first` / `ray_all`) for rays read from stdin.

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::stdin_rows::{control_diagonal, read_rows, Row};
use crate::progress::Progress;
use crate::stdout;
use crate::surface::{with_surface, FeatureArgs, SurfaceJob};
use ccss_core::query::{ray_all, ray_first, Hit, QuerySurface, QueryWork, Ray, RayOptions};
use ccss_core::{DVec3, Weights};
use rayon::prelude::*;
use std::path::PathBuf;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Certified ray intersection with the limit surface. Each stdin line is 'ox oy oz dx dy dz' (a \
ray origin + t dir, t >= 0; dir non-zero); blank lines and lines starting with '#' are \
skipped. For each ray one line, in input order: the first hit as 't face sub u v px py pz nx \
ny nz' (numbers as 'ccss eval' writes them, '{:.16e}'; p the exact limit point S(face, sub, u, v), n its unit normal), or 'miss'; with --all \
'n' followed by n such groups of 11 numbers, sorted by t ('0' for a miss). Certified: no \
crossing of the ray with the limit surface is missed, and every reported hit is within --tol \
(model units; default 1e-9 times the diagonal of the control points' box) of an exact \
crossing along the ray (interval subdivision with the guaranteed cell bounds, then a \
Krawczyk-Newton certificate). A bad line fails with 'ccss: error: stdin line N: <reason>' \
(exit code 2) before any output. OpenSubdiv tags ('t crease', 't corner', 't hole', \
't interpolateboundary', 't creasemethod') and --boundary / --creasing are honoured; open \
meshes are fine. Rays run on all cores (RAYON_NUM_THREADS to change).";

/// Arguments of `ccss raycast`.
#[derive(clap::Args, Debug)]
pub struct RaycastArgs {
    /// Polygon mesh (OBJ; OpenSubdiv tags honoured, open meshes allowed).
    pub mesh: PathBuf,
    /// Write every hit of each ray, not only the first.
    #[arg(long)]
    pub all: bool,
    /// Tolerance in model units (default: 1e-9 x the control box diagonal).
    #[arg(long, value_name = "T")]
    pub tol: Option<f64>,
    /// Work budget: cells one query may visit before it stops with
    /// `work limit exceeded` (docs/WORST_CASE.md).
    #[arg(long, value_name = "N", default_value_t = ccss_core::query::MAX_CELLS)]
    pub max_cells: u64,
    /// Write the wall time of the ray queries alone (no parsing, mesh
    /// setup or output) to stderr: `ccss raycast: rays=N seconds=S
    /// rays_per_s=R` (for benchmarks; `bench/ray_bench.sh`).
    #[arg(long)]
    pub timing: bool,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// The tolerance: `--tol`, else `1e-9` of the control box diagonal.
pub fn tolerance(tol: Option<f64>, positions: &[f64]) -> CliResult<f64> {
    let t = tol.unwrap_or(1e-9 * control_diagonal(positions));
    if !(t > 0.0 && t.is_finite()) {
        return Err(CliError::input("--tol must be positive and finite"));
    }
    Ok(t)
}

/// One hit as 11 numbers.
fn push_hit(s: &mut String, h: &Hit) {
    use std::fmt::Write;
    let _ = write!(
        s,
        "{:.16e} {} {} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e}",
        h.t,
        h.face,
        h.sub,
        h.u,
        h.v,
        h.point.x,
        h.point.y,
        h.point.z,
        h.normal.x,
        h.normal.y,
        h.normal.z
    );
}

/// Runs the verb on stdin/stdout.
pub fn run(a: &RaycastArgs) -> CliResult {
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let tol = tolerance(a.tol, &mesh.positions)?;
    let rows = read_rows(std::io::stdin().lock(), 6)?;
    for r in &rows {
        if r.values[3..].iter().all(|&x| x == 0.0) {
            return Err(CliError::input(format!(
                "stdin line {}: the ray direction is zero",
                r.line
            )));
        }
    }
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let opts = RayOptions {
        tol,
        t_min: 0.0,
        max_cells: a.max_cells,
    };
    let all = a.all;
    with_surface(
        &mesh,
        &tables,
        a.features,
        Job {
            rows: &rows,
            opts,
            all,
            timing: a.timing,
        },
    )
}

/// The verb's work on either surface.
struct Job<'j> {
    rows: &'j [Row],
    opts: RayOptions,
    all: bool,
    timing: bool,
}

impl SurfaceJob<()> for Job<'_> {
    fn run<S: QuerySurface + Sync + ?Sized>(self, ev: &S, _feature: bool) -> CliResult {
        crate::surface::with_index(ev, |ev| {
            let (rows, opts, all) = (self.rows, self.opts, self.all);
            let bar = Progress::delayed("{msg} [{bar:40}] {pos}/{len} rays");
            bar.phase("raycast", rows.len());
            let t0 = std::time::Instant::now();
            let lines: Vec<CliResult<String>> = rows
                .par_iter()
                .map_init(
                    || Box::new(QueryWork::ZERO),
                    |w, r| {
                        let v = &r.values;
                        let ray = Ray {
                            origin: DVec3::new(v[0], v[1], v[2]),
                            dir: DVec3::new(v[3], v[4], v[5]),
                        };
                        let fail = |e| CliError::failure(format!("stdin line {}: {e}", r.line));
                        let mut s = String::new();
                        if all {
                            let n = match ray_all(ev, &ray, &opts, w, &mut []) {
                                Ok(n) => n,
                                Err(ccss_core::Error::BufferTooSmall { required }) => required,
                                Err(e) => return Err(fail(e)),
                            };
                            s.push_str(&n.to_string());
                            for h in &w.last_hits()[..n] {
                                s.push(' ');
                                push_hit(&mut s, h);
                            }
                        } else {
                            match ray_first(ev, &ray, &opts, w).map_err(fail)? {
                                Some(h) => push_hit(&mut s, &h),
                                None => s.push_str("miss"),
                            }
                        }
                        s.push('\n');
                        bar.inc();
                        Ok(s)
                    },
                )
                .collect();
            let seconds = t0.elapsed().as_secs_f64();
            bar.finish();
            if self.timing {
                eprintln!(
                    "ccss raycast: rays={} seconds={seconds:.6} rays_per_s={:.0}",
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
