//! `ccss interpolate P.obj -o Q.obj [--subdivided G.obj] [--tolerance T]
//! [--max-iterations N] [--weights W.tsv]`: similarity-based interpolation
//! (`ccss_core::interpolate`, report ch. 4).
//!
//! Prints one line (stdout):
//!
//! ```text
//! vertices=98 faces=96 iterations=13 residual=8.2e-7 similarity=0.24 naive=92.0 seconds=0.004
//! ```

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::control_obj::write_obj;
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::progress::Progress;
use ccss_core::interpolate::{InterpolationOptions, Interpolator};
use ccss_core::{Error, Topology};
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Similarity-based interpolation (Cheng/Lai report, chapter 4): writes to -o Q.obj a control \
mesh Q with the topology of G = P.obj after one Catmull-Clark step whose limit surface \
passes exactly through P's vertices (Q's first vertices, in P's order, are those Type I \
vertices), while its first and second derivatives follow the directions of G's limit \
surface at the nine points {0, 1/2, 1}^2 of every face (least squares, conjugate gradients \
with a block-Jacobi preconditioner, started from G). --subdivided G.obj also writes G. \
--tolerance T (default 1e-6) stops when the residual of the normal equations has dropped to \
T times its start; --max-iterations N (default 10000) makes a longer solve an error. \
--weights W.tsv uses a general vertex rule. Prints 'vertices=V faces=F iterations=I \
residual=R similarity=S naive=N seconds=T' (R the final relative residual, S and N the \
similarity residual of Q and of the naive solution, T the wall time of build and solve). \
P must be a closed manifold mesh.";

/// Arguments of `ccss interpolate`.
#[derive(clap::Args, Debug)]
pub struct InterpolateArgs {
    /// Closed polygon mesh P (OBJ).
    pub mesh: PathBuf,
    /// Output control mesh Q (OBJ).
    #[arg(short = 'o', long, value_name = "Q.obj")]
    pub output: PathBuf,
    /// Also write G, P after one Catmull-Clark step (OBJ).
    #[arg(long, value_name = "G.obj")]
    pub subdivided: Option<PathBuf>,
    /// Relative residual at which the solve stops, in (0, 1).
    #[arg(long, default_value_t = 1e-6)]
    pub tolerance: f64,
    /// Iteration limit of the solve.
    #[arg(long, default_value_t = 10_000)]
    pub max_iterations: u32,
    #[command(flatten)]
    pub weights: WeightsArg,
}

/// Runs `ccss interpolate`.
pub fn run(a: &InterpolateArgs) -> CliResult {
    if !(a.tolerance > 0.0 && a.tolerance < 1.0) {
        return Err(CliError::input(format!(
            "--tolerance must be in (0, 1), got {}",
            a.tolerance
        )));
    }
    if a.max_iterations == 0 {
        return Err(CliError::input("--max-iterations must be at least 1"));
    }
    let weights = a.weights.load()?;
    let (tables, _) = build_tables(&weights)?;
    let mesh = Mesh::load(&a.mesh)?;
    let mut tmem = words(Topology::required_bytes(
        mesh.num_vertices(),
        &mesh.face_sizes,
    ));
    let topo = Topology::build(mesh.input(), &mut tmem).map_err(|e| mesh.error(e))?;
    let opts = InterpolationOptions {
        tolerance: a.tolerance,
        max_iterations: a.max_iterations,
        ..Default::default()
    };
    let start = Instant::now();
    let mut mem = words(Interpolator::required_bytes(&topo));
    let name = a.mesh.display();
    let mut it = Interpolator::build(&topo, &tables, opts, &mut mem).map_err(|e| match e {
        Error::InvalidArgument(_) => CliError::input(format!("{name}: cannot interpolate: {e}")),
        _ => mesh.error(e),
    })?;
    let mut q = vec![0.0; 3 * it.num_vertices()];
    let bar = Progress::delayed("{msg} [{bar:30}] {pos}/{len}");
    // The bar's length is the number of decades the residual has to fall.
    let decades = (-a.tolerance.log10()).ceil().max(1.0) as usize;
    bar.phase("interpolate: residual decades", decades);
    let mut shown = 0usize;
    let stats = it
        .solve(&mut q, &mut |_, rel| {
            let done = ((-rel.log10()).max(0.0) as usize).min(decades);
            while shown < done {
                bar.inc();
                shown += 1;
            }
        })
        .map_err(|e| match e {
            Error::NotConverged { iterations } => CliError::failure(format!(
                "{name}: the solve did not converge within {iterations} iterations \
                 (raise --max-iterations or --tolerance)"
            )),
            _ => CliError::failure(format!("{name}: cannot interpolate: {e}")),
        })?;
    bar.finish();
    let seconds = start.elapsed().as_secs_f64();
    let g = it.subdivided();
    write_obj(&a.output, &q, g.face_sizes(), g.indices())?;
    if let Some(path) = &a.subdivided {
        write_obj(path, g.positions(), g.face_sizes(), g.indices())?;
    }
    let rel = if stats.initial_residual > 0.0 {
        stats.final_residual / stats.initial_residual
    } else {
        0.0
    };
    println!(
        "vertices={} faces={} iterations={} residual={rel:.3e} similarity={:.6e} naive={:.6e} seconds={seconds:.6}",
        it.num_vertices(),
        g.num_faces(),
        stats.iterations,
        stats.objective,
        stats.naive_objective
    );
    Ok(())
}
