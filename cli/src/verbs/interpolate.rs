//! `ccss interpolate P.obj -o Q.obj [--subdivided G.obj] [--normals N.tsv] [--tolerance T]
//! [--max-iterations N] [--fold-rounds R] [--fold-rows orientation|anchors] [--weights W.tsv]`: similarity-based interpolation
//! (`ccss_core::interpolate`, report ch. 4).
//!
//! Prints one line (stdout):
//!
//! ```text
//! vertices=98 faces=96 iterations=13 residual=8.2e-7 similarity=0.24 naive=92.0 seconds=0.004 fold_rounds=0 folds=0
//! ```

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::control_obj::write_obj;
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::progress::Progress;
use ccss_core::interpolate::{
    FoldRemoval, InterpolationOptions, Interpolator, Preconditioner, Prescribed, Requirement,
};
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
on the assembled normal matrix with a block-Jacobi preconditioner, started from G; \
--matrix-free multiplies face by face with less memory; --preconditioner \
symmetric-gauss-seidel|none). --subdivided G.obj also writes G. \
--tolerance T (default 1e-6) stops when the residual of the normal equations has dropped to \
T times its start; --max-iterations N (default 10000) makes a longer solve an error. \
--normals N.tsv prescribes limit normals of Q at (face, u, v) exactly (lines 'face u v nx \
ny nz', faces of Q); a normal that contradicts the interpolation conditions or an earlier \
one is an error naming its line. --weights W.tsv uses a general vertex rule. \
--fold-rounds R (default 16; 8 with anchors; 0: no check) re-solves up to R times with orientation rows \
(the condition n_G . (Q_u x Q_v) >= 0.1 |G_u x G_v|, linearised around the previous \
solution) at the points of a 7x7 grid per face where it fails; --fold-rows anchors pulls the \
first derivatives of folded faces towards G's instead (the former default, 8 rounds, \
fewer iterations, folds remain on some meshes). Folds are counted at the 7x7 points of the orientation grid per face. \
Prints 'vertices=V faces=F iterations=I \
residual=R similarity=S naive=N seconds=T fold_rounds=K folds=F' (R the final relative residual of the \
last round, S and N the similarity residual of Q and of the naive solution, T the wall time \
of build and solve, K the fold rounds run, F the check points still folded). \
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
    /// Prescribed normals: lines 'face u v nx ny nz' ('#' comments), faces
    /// and parameters of Q (= G), met exactly.
    #[arg(long, value_name = "N.tsv")]
    pub normals: Option<PathBuf>,
    /// Iteration limit of the solve.
    #[arg(long, default_value_t = 10_000)]
    pub max_iterations: u32,
    /// Fold-removal rounds after the first solve (0: no fold check;
    /// default 16 with orientation rows, 8 with anchors).
    #[arg(long)]
    pub fold_rounds: Option<u32>,
    /// Rows the fold rounds add.
    #[arg(long, value_enum, default_value_t = FoldRows::Orientation)]
    pub fold_rows: FoldRows,
    /// Preconditioner of the conjugate-gradient solve (symmetric
    /// Gauss-Seidel needs the assembled matrix; with --matrix-free or
    /// --normals it falls back to block Jacobi).
    #[arg(long, value_enum, default_value_t = Precond::BlockJacobi)]
    pub preconditioner: Precond,
    /// Multiply with the normal matrix face by face instead of assembling
    /// it (less memory, slower; the former default).
    #[arg(long)]
    pub matrix_free: bool,
    #[command(flatten)]
    pub weights: WeightsArg,
}

/// `--fold-rows` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FoldRows {
    /// Linearised orientation rows at the points below the margin.
    Orientation,
    /// Anchor rows pulling folded faces' first derivatives towards G's
    /// (first weight 0.01).
    Anchors,
}

/// `--preconditioner` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Precond {
    /// Plain conjugate gradients.
    None,
    /// Inverse 3x3 diagonal blocks.
    BlockJacobi,
    /// One forward and one backward block Gauss-Seidel sweep over the
    /// assembled matrix.
    SymmetricGaussSeidel,
}

/// Reads `face u v nx ny nz` lines; returns the requirements and the line
/// number of each.
fn load_normals(path: &std::path::Path) -> CliResult<(Vec<Requirement>, Vec<usize>)> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("{}: cannot read: {e}", path.display())))?;
    let (mut reqs, mut lines) = (Vec::new(), Vec::new());
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = |what: &str| CliError::input(format!("{}:{}: {what}", path.display(), i + 1));
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() != 6 {
            return Err(bad("expected 'face u v nx ny nz'"));
        }
        let face: u32 = f[0].parse().map_err(|_| bad("bad face index"))?;
        let mut x = [0.0f64; 5];
        for (k, s) in f[1..].iter().enumerate() {
            x[k] = s.parse().map_err(|_| bad("bad number"))?;
            if !x[k].is_finite() {
                return Err(bad("NaN or infinite number"));
            }
        }
        reqs.push(Requirement {
            face,
            u: x[0],
            v: x[1],
            what: Prescribed::Normal([x[2], x[3], x[4]]),
        });
        lines.push(i + 1);
    }
    Ok((reqs, lines))
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
        fold_rounds: a.fold_rounds.unwrap_or(match a.fold_rows {
            FoldRows::Orientation => InterpolationOptions::default().fold_rounds,
            FoldRows::Anchors => 8,
        }),
        fold_removal: match a.fold_rows {
            FoldRows::Orientation => FoldRemoval::Orientation,
            FoldRows::Anchors => FoldRemoval::Anchors,
        },
        fold_weight: match a.fold_rows {
            FoldRows::Orientation => InterpolationOptions::default().fold_weight,
            FoldRows::Anchors => 0.01,
        },
        preconditioner: match a.preconditioner {
            Precond::None => Preconditioner::None,
            Precond::BlockJacobi => Preconditioner::BlockJacobi,
            Precond::SymmetricGaussSeidel => Preconditioner::SymmetricGaussSeidel,
        },
        ..Default::default()
    };
    let (reqs, lines) = match &a.normals {
        Some(p) => load_normals(p)?,
        None => (Vec::new(), Vec::new()),
    };
    let req_error = |e: Error| -> Option<CliError> {
        let path = a.normals.as_ref()?.display();
        let at = |i: usize| lines.get(i).copied().unwrap_or(0);
        match e {
            Error::ConflictingRequirement { requirement } => Some(CliError::input(format!(
                "{path}:{}: this normal conflicts with the interpolation conditions or an earlier normal",
                at(requirement as usize)
            ))),
            Error::FaceOutOfRange { face } => Some(CliError::input(format!(
                "{path}: face {face} does not exist in Q ({} faces)",
                topo.num_half_edges()
            ))),
            Error::ParameterOutOfRange => Some(CliError::input(format!(
                "{path}: a parameter (u, v) is outside [0, 1]"
            ))),
            Error::InvalidArgument(m) if m.contains("requirement") => {
                Some(CliError::input(format!("{path}: {m}")))
            }
            _ => None,
        }
    };
    let start = Instant::now();
    let mut mem = words(Interpolator::required_bytes(&topo, &reqs));
    let name = a.mesh.display();
    let mut it = Interpolator::build(&topo, &tables, opts, &reqs, &mut mem).map_err(|e| {
        if let Some(c) = req_error(e) {
            return c;
        }
        match e {
            Error::InvalidArgument(_) => {
                CliError::input(format!("{name}: cannot interpolate: {e}"))
            }
            _ => mesh.error(e),
        }
    })?;
    let mut matrix_mem = words(if a.matrix_free {
        0
    } else {
        it.assembled_bytes()
    });
    if !a.matrix_free {
        it.assemble(&mut matrix_mem)
            .map_err(|e| CliError::failure(format!("{name}: cannot interpolate: {e}")))?;
    }
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
            _ => req_error(e)
                .unwrap_or_else(|| CliError::failure(format!("{name}: cannot interpolate: {e}"))),
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
        "vertices={} faces={} iterations={} residual={rel:.3e} similarity={:.6e} naive={:.6e} seconds={seconds:.6} fold_rounds={} folds={}",
        it.num_vertices(),
        g.num_faces(),
        stats.iterations,
        stats.objective,
        stats.naive_objective,
        stats.fold_rounds,
        stats.folds
    );
    if stats.folds > 0 {
        eprintln!(
            "ccss interpolate: warning: {} check points of Q still have a limit normal reversed \
             against G's after {} fold rounds",
            stats.folds, stats.fold_rounds
        );
    }
    Ok(())
}
