//! `ccss`: exact Catmull-Clark limit surface evaluation from the command line.
//!
//! This file only parses the command line (clap) and dispatches to one
//! module per verb; every failure ends here as one line
//! `ccss: error: <reason>` on stderr and a non-zero exit code (see
//! [`error`]).
//!
//! Layout: [`verbs`] holds one file per verb (`ccss eval`, `ccss info`,
//! ...), [`bench`](mod@bench) the `ccss bench` verbs and their helpers,
//! [`io`] the file and stream formats, [`parallel`] the multi-core drivers
//! shared by verbs and benchmarks; [`context`] builds the core objects of a
//! mesh in memory from [`mem`], [`progress`] is the progress bar of long
//! verbs and [`stdout`] writes results.

mod bench;
mod boolean_field;
mod context;
use ccss_cli::error;
mod io;
mod mem;
mod mesh_stats;
mod parallel;
mod progress;
mod solid_boolean;
mod stdout;
mod surface;
mod usage;
mod verbs;

use bench::{
    eval as bench_eval, features as bench_features, query as bench_query, tables as bench_tables,
    tessellate as bench_tessellate, voxelize as bench_voxelize,
};
use clap::error::ErrorKind;
use clap::{Parser, Subcommand};
use error::CliError;
use verbs::{
    boolean, closest, depth, eval, info, interpolate, measure, raycast, refine, slice, tessellate,
    voxelize,
};

const ABOUT: &str = "Exact Catmull-Clark subdivision surface evaluation";

const LONG_ABOUT: &str = "\
Exact Catmull-Clark subdivision surface evaluation. ccss reads a closed polygon mesh from an \
OBJ file and evaluates its limit surface (position and derivatives) at any (face, u, v), \
exactly, from per-valence eigen tables (Stam 1998) rather than by repeated subdivision. \
Faces and vertices are numbered from 0 in file order (face f is the f-th 'f' line, vertex i \
the i-th used 'v' line); OpenSubdiv tags ('t' lines: creases, corners, holes, boundary \
options) are honoured by 'eval', 'tessellate', 'info' and 'refine' and ignored, with a warning, by \
the others. \
Every failure prints one line 'ccss: error: <reason>' to stderr; the exit code is 2 for \
usage and input errors and 1 for other failures (such as a mesh the evaluator does not \
support).";

#[derive(Parser, Debug)]
#[command(name = "ccss", version, about = ABOUT, long_about = LONG_ABOUT)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Evaluate limit surface points (queries on stdin, results on stdout)
    #[command(long_about = eval::ABOUT)]
    Eval(eval::EvalArgs),
    /// Print counts, histograms, patch counts and memory of a mesh
    #[command(long_about = info::ABOUT)]
    Info(info::InfoArgs),
    /// Subdivision depth per face for a tolerance, or the per-valence rates
    #[command(long_about = depth::ABOUT)]
    Depth(depth::DepthArgs),
    /// Adaptive tessellation to a guaranteed flatness (OBJ, STL or PLY out)
    #[command(long_about = tessellate::ABOUT)]
    Tessellate(tessellate::TessellateArgs),
    /// Control mesh whose limit surface interpolates the vertices of a mesh (OBJ out)
    #[command(long_about = interpolate::ABOUT)]
    Interpolate(interpolate::InterpolateArgs),
    /// Uniform refinement with the Maillot-Stam unified scheme (OBJ out)
    #[command(long_about = refine::ABOUT)]
    Refine(refine::RefineArgs),
    /// Voxelize the limit surface into a binvox file (surface, optionally interior)
    #[command(long_about = voxelize::ABOUT)]
    Voxelize(voxelize::VoxelizeArgs),
    /// Exact volume, area, centroid, inertia and mass of the solid
    #[command(long_about = measure::ABOUT)]
    Measure(measure::MeasureArgs),
    /// Union, intersection or difference of two solids within eps (OBJ, STL or PLY out)
    #[command(long_about = boolean::ABOUT)]
    Boolean(boolean::BooleanArgs),
    /// Certified ray intersection (rays on stdin, hits on stdout)
    #[command(long_about = raycast::ABOUT)]
    Raycast(raycast::RaycastArgs),
    /// Certified closest points (points on stdin, results on stdout)
    #[command(long_about = closest::ABOUT)]
    Closest(closest::ClosestArgs),
    /// Planar slices as closed oriented contours within eps (text or SVG)
    #[command(long_about = slice::ABOUT)]
    Slice(slice::SliceArgs),
    /// Benchmarks
    #[command(about = bench::ABOUT, long_about = bench::ABOUT)]
    Bench {
        #[command(subcommand)]
        what: BenchCmd,
    },
}

#[derive(Subcommand, Debug)]
enum BenchCmd {
    /// Time evaluation per point class (R regular, X extraordinary)
    #[command(long_about = bench_eval::ABOUT)]
    Eval(bench_eval::BenchEvalArgs),
    /// Time evaluation of a mesh with creases, corners, holes or boundaries
    #[command(long_about = bench_features::ABOUT)]
    Features(bench_features::BenchFeaturesArgs),
    /// Time the certified queries: rays/s, closest points/s, slices vs tessellation
    #[command(long_about = bench_query::ABOUT)]
    Query(bench_query::BenchQueryArgs),
    /// Time the eigen table construction per valence
    #[command(long_about = bench_tables::ABOUT)]
    Tables(bench_tables::BenchTablesArgs),
    /// Time adaptive tessellation against uniform refinement (one thread)
    #[command(long_about = bench_tessellate::ABOUT)]
    Tessellate(bench_tessellate::BenchTessellateArgs),
    /// Time voxelization + flooding against refinement + triangle voxelization + scanline fill
    #[command(long_about = bench_voxelize::ABOUT)]
    Voxelize(bench_voxelize::BenchVoxelizeArgs),
}

fn run() -> Result<(), CliError> {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                let _ = e.print();
                return Ok(());
            }
            _ => return Err(usage::usage_error(&e)),
        },
    };
    match &cli.cmd {
        Cmd::Eval(a) => eval::run(a),
        Cmd::Voxelize(a) => voxelize::run(a),
        Cmd::Measure(a) => measure::run(a),
        Cmd::Boolean(a) => boolean::run(a),
        Cmd::Raycast(a) => raycast::run(a),
        Cmd::Closest(a) => closest::run(a),
        Cmd::Slice(a) => slice::run(a),
        Cmd::Info(a) => info::run(a),
        Cmd::Depth(a) => depth::run(a),
        Cmd::Tessellate(a) => tessellate::run(a),
        Cmd::Refine(a) => refine::run(a),
        Cmd::Interpolate(a) => interpolate::run(a),
        Cmd::Bench {
            what: BenchCmd::Eval(a),
        } => bench_eval::run(a),
        Cmd::Bench {
            what: BenchCmd::Features(a),
        } => bench_features::run(a),
        Cmd::Bench {
            what: BenchCmd::Tables(a),
        } => bench_tables::run(a),
        Cmd::Bench {
            what: BenchCmd::Query(a),
        } => bench_query::run(a),
        Cmd::Bench {
            what: BenchCmd::Tessellate(a),
        } => bench_tessellate::run(a),
        Cmd::Bench {
            what: BenchCmd::Voxelize(a),
        } => bench_voxelize::run(a),
    }
}

fn main() {
    if let Err(e) = run() {
        if !e.is_quiet() {
            eprintln!("{e}");
        }
        std::process::exit(if e.is_quiet() { 0 } else { e.code });
    }
}
