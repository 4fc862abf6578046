//! `ccss`: exact Catmull-Clark limit surface evaluation from the command line.
//!
//! This file only parses the command line (clap) and dispatches to one
//! module per verb; every failure ends here as one line
//! `ccss: error: <reason>` on stderr and a non-zero exit code (see
//! [`error`]).

mod bench_cmd;
mod bench_tables;
mod bench_tessellate;
mod classes;
mod context;
mod depth_cmd;
mod error;
mod eval_cmd;
mod info_cmd;
mod measure_cmd;
mod mesh;
mod mesh_out;
mod numfmt;
mod points;
mod query;
mod refine_cmd;
mod rng;
mod stats;
mod tessellate_cmd;
mod timing;
mod voxel_bench;
mod voxel_cmd;
mod weights_file;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};
use error::CliError;

const ABOUT: &str = "Exact Catmull-Clark subdivision surface evaluation";

const LONG_ABOUT: &str = "\
Exact Catmull-Clark subdivision surface evaluation. ccss reads a closed polygon mesh from an \
OBJ file and evaluates its limit surface (position and derivatives) at any (face, u, v), \
exactly, from per-valence eigen tables (Stam 1998) rather than by repeated subdivision. \
Faces and vertices are numbered from 0 in file order (face f is the f-th 'f' line, vertex i \
the i-th used 'v' line); OpenSubdiv crease and corner tags ('t' lines) are ignored. \
Every failure prints one line 'ccss: error: <reason>' to stderr; the exit code is 2 for \
usage and input errors and 1 for other failures (such as a mesh the evaluator does not \
support).";

const EVAL_ABOUT: &str = "\
Evaluate the limit surface at queries read from stdin. Each input line is 'face u v [sub]' \
(whitespace separated; u and v in [0, 1]; sub, the sub-face of an N-gon with N != 4, \
defaults to 0 and must be 0 for quads); blank lines and lines starting with '#' are skipped. \
For each query one line 'px py pz dux duy duz dvx dvy dvz' is written to stdout, in input \
order, every number with 17 significant digits ('{:.16e}', e.g. -5.5555555555555558e-1, \
which reads back to the identical double); --second appends 'duux duuy duuz duvx duvy duvz \
dvvx dvvy dvvz'. Derivatives are with respect to the (sub-)face's own (u, v): quad v0 v1 v2 \
v3 has (0,0)=v0, (1,0)=v1, (1,1)=v2; sub-face k of an N-gon has (0,0)=v_k, (1,0) on edge \
v_k v_k+1 and (1,1) at the face centre (the OpenSubdiv conventions). Work is done in chunks \
of 4096 lines on all cores (RAYON_NUM_THREADS to change), keeping the order; output is \
flushed whenever stdin has nothing more buffered, so a co-process can send one query and \
read its answer. The first bad line stops the command after \
the output of all lines before it, with 'ccss: error: stdin line N: <reason>' (exit code 2). \
--weights W.tsv evaluates the surface of a general vertex rule: W.tsv has lines \
'n alpha beta gamma' (whitespace separated; '#' comments and blank lines skipped) giving \
the rule V' = alpha V + beta/n sum(E_i) + gamma/n sum(F_i) of valence n (E_i edge \
neighbours, F_i face-diagonal vertices; edge and face points stay standard); valences not \
listed keep the standard Catmull-Clark rule (alpha = 1-7/(4n), beta = 3/(2n), gamma = \
1/(4n)), and valence 4 must stay standard. Weights must be finite, non-negative and add \
up to 1; a bad line fails with 'ccss: error: W.tsv line N: <reason>' (exit code 2).";

const INFO_ABOUT: &str = "\
Print facts about a mesh as 'key: value' lines: vertex, face and edge counts, the face-size \
and valence histograms ('face size 4: 6', 'valence 3: 8'), connected components, Euler \
characteristic and genus; then what the evaluator makes of it: sub-faces, regular and \
extraordinary patches, internal refinement levels, and the bytes used by the topology, \
the evaluator and the eigen tables, with build times. If the mesh is not supported \
(open, non-manifold, valence out of range, ...) the counts are printed and the command \
fails with the reason, naming the vertex, edge or face (exit code 1). With --weights W.tsv \
(the format of 'ccss eval --help') the tables are built for that vertex rule, and for each \
valence that occurs (vertex valences, and the sizes of non-quad faces, whose centres become \
vertices of that valence) a line 'weights n: alpha beta gamma tangent_plane_continuous=yes|no' \
tells the rule and whether it gives a tangent-plane continuous surface there (the \
frequency-0 eigenvalues below the subdominant one).";

const DEPTH_ABOUT: &str = "\
Subdivision depth for a tolerance (Cheng & Lai report, ch. 3): for each (sub-)face, the number \
of uniform Catmull-Clark steps of the base mesh after which its control faces (as bilinear \
patches) lie within --eps of the limit surface. Prints one line 'face depth' per quad and \
'face.sub depth' per sub-face of an N-gon (N != 4), in face order, then a summary line \
'# eps=E method=M faces=F slots=S max_depth=D mean_depth=X histogram=d:count,... seconds=T \
build_seconds=B depth_seconds=C' (mean over the printed lines; T = B + C, B the topology and \
evaluator build, C the depth computation; the eigen tables are not counted). Regular patches \
use Lemma 1 (depth = ceil(log4(M / (3 eps))), M the second-order norm of the 4x4 control \
points); extraordinary ones the --method: old (Theorem 6, rate and constant of Lemmas 2-5; \
standard weights only), new (Theorem 11, the matrix technique with rates r1 = \
||A Lambda A^+||, r2 = ||A Lambda^2 A^+|| and the supremum constant c_new), tight (Theorem \
11's constant with the measured norms of the exactly subdivided control points; never deeper \
than new) or best (the smallest of all; default). A depth that cannot be bounded (only with \
general weights where r2 >= 1) prints as 'inf'. --weights W.tsv (the format of 'ccss eval \
--help') computes the depths of that vertex rule's surface; --method old then requires every \
valence to keep the standard rule. --rates N prints 'n r1 r2' for valence N (3..=max \
valence), --rates all for every valence, and --verbose adds 'c_new c_lemma10 r_old c_old' \
(c_lemma10: the report's Lemma 10 constant; r_old, c_old: 0 where the old technique does not \
apply). Bad or missing --eps is a usage error (exit code 2).";

const BENCH_ABOUT: &str = "Benchmarks (single-threaded timings)";

const BENCH_EVAL_ABOUT: &str = "\
Time single-threaded evaluation per class of points and print one line per class, \
'ccss class=R points=N ns_per_eval=XX.X' (median over --samples samples, after a warm-up \
pass), then 'ccss checksum=...'. Class R: random points on quads whose 1-ring is fully \
regular (4 corners and all their neighbours of valence 4, all faces around them quads); \
class X: random points on quads with an extraordinary vertex, with sub-class lines X3, X5, \
..., Xmulti (two or more extraordinary vertices) when there are several. Points are drawn \
with SplitMix64 from --seed, --points per class, uniform over the faces of the class and \
uniform in (u, v); --write-points F writes them in the OpenSubdiv harness format \
('face sub u v class', bench/osd/README.md; X lines carry the sub-class as a sixth token, \
which osd_eval ignores) and exits, and --points-file F times the points \
of such a file instead, so that ccss and bench/osd/osd_eval time identical points. A \
progress bar is shown on stderr for long runs when stderr is a terminal. --weights W.tsv \
times the surface of that vertex rule (format: see 'ccss eval --help').";

const BENCH_TABLES_ABOUT: &str = "\
Time the construction of the eigen table of each valence 3..=max (ValenceTable::build_into, \
single-threaded, into preallocated memory) and print 'ccss tables n=N us=XX.X \
weights=standard' per valence, the median of --reps builds in microseconds, then 'ccss \
tables total_us=XX.X weights=standard' (the sum: one whole table set). With --weights W.tsv \
(the format of 'ccss eval --help') the same lines follow for that rule, with \
weights=custom (valences the file does not list use the standard rule).";

const VOXELIZE_ABOUT: &str = "\
Voxelize the limit surface of a closed mesh into an N x N x N grid (S. Lai and F. Cheng's \
recursive parameter-space subdivision with the N-adjacency stop test, plus a certification \
pass that guarantees no holes) and classify the other voxels as interior or outside \
(bit-parallel flooding from the grid border and a certified ray test per enclosed region). \
The model is scaled uniformly into [0, N-1]^3 (voxel centres at integers). Writes binvox \
(voxel (i,j,k) covers [t + i s/N, t + (i+1) s/N) per axis with the header's translate t and \
scale s; data in binvox order, x slowest, then z, then y fastest): the surface voxels, plus the \
interior ones with --fill. --adjacency 6 gives a thick surface containing the voxel of every \
surface point; 18 and 26 thinner, still 6-separating ones. --runs F writes 'z y x0 x1 class' \
lines (x1 exclusive, class 1 surface, 2 interior), --preview F.png a montage of 16 z-slices. \
Prints one line 'res=N adjacency=A surface=S interior=I volume=V area=A seconds=T threads=P': \
V = (S + I) voxel volumes and A the sum of the final recursion quads (the paper's estimates, \
model units); T the voxelization and classification time on P threads (RAYON_NUM_THREADS).";

const MEASURE_ABOUT: &str = "\
Exact integral properties of the solid bounded by the limit surface, by quadrature on the \
limit surface (divergence theorem; Gauss-Legendre rules exact on every polynomial piece, \
corner squares at extraordinary vertices bounded). Prints one line 'volume=V area=A \
centroid=x,y,z inertia=Ixx,Iyy,Izz,Ixy,Iyz,Izx mass=M error_bound=E area_error_bound=B \
seconds=T': inertia about the centroid, mass-weighted with --density D (default 1; products \
of inertia as tensor entries, Ixy = -integral of x y dm), mass = D V, E a bound of the volume \
error and B of the area error.";

const BENCH_VOXELIZE_ABOUT: &str = "\
Time ccss's voxelization and flooding (single thread, whole grid, best of --reps) next to a \
baseline on the same grid: uniform Catmull-Clark refinement until edges are at most one \
voxel, triangle voxelization by the separating-axis test, scanline parity fill. Prints \
'ccss ...', 'baseline ...', 'speedup=X' and a 'parallel ...' line with the CLI's slab \
parallelism on all threads.";

#[derive(Parser, Debug)]
#[command(name = "ccss", version, about = ABOUT, long_about = LONG_ABOUT)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Evaluate limit surface points (queries on stdin, results on stdout)
    #[command(long_about = EVAL_ABOUT)]
    Eval(eval_cmd::EvalArgs),
    /// Print counts, histograms, patch counts and memory of a mesh
    #[command(long_about = INFO_ABOUT)]
    Info(info_cmd::InfoArgs),
    /// Subdivision depth per face for a tolerance, or the per-valence rates
    #[command(long_about = DEPTH_ABOUT)]
    Depth(depth_cmd::DepthArgs),
    /// Adaptive tessellation to a guaranteed flatness (OBJ, STL or PLY out)
    #[command(long_about = tessellate_cmd::ABOUT)]
    Tessellate(tessellate_cmd::TessellateArgs),
    /// Uniform refinement with the Maillot-Stam unified scheme (OBJ out)
    #[command(long_about = refine_cmd::ABOUT)]
    Refine(refine_cmd::RefineArgs),
    /// Voxelize the limit surface into a binvox file (surface, optionally interior)
    #[command(long_about = VOXELIZE_ABOUT)]
    Voxelize(voxel_cmd::VoxelizeArgs),
    /// Exact volume, area, centroid, inertia and mass of the solid
    #[command(long_about = MEASURE_ABOUT)]
    Measure(measure_cmd::MeasureArgs),
    /// Benchmarks
    #[command(about = BENCH_ABOUT, long_about = BENCH_ABOUT)]
    Bench {
        #[command(subcommand)]
        what: BenchCmd,
    },
}

#[derive(Subcommand, Debug)]
enum BenchCmd {
    /// Time evaluation per point class (R regular, X extraordinary)
    #[command(long_about = BENCH_EVAL_ABOUT)]
    Eval(bench_cmd::BenchEvalArgs),
    /// Time the eigen table construction per valence
    #[command(long_about = BENCH_TABLES_ABOUT)]
    Tables(bench_tables::BenchTablesArgs),
    /// Time adaptive tessellation against uniform refinement (one thread)
    #[command(long_about = bench_tessellate::ABOUT)]
    Tessellate(bench_tessellate::BenchTessellateArgs),
    /// Time voxelization + flooding against refinement + triangle voxelization + scanline fill
    #[command(long_about = BENCH_VOXELIZE_ABOUT)]
    Voxelize(voxel_bench::BenchVoxelizeArgs),
}

/// The `--help` command that fits the command line: `ccss bench eval --help`
/// for errors inside `ccss bench eval ...`, and so on.
fn help_hint() -> String {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let verb: Vec<&str> = match args.first().map(String::as_str) {
        Some(
            v @ ("eval" | "info" | "depth" | "tessellate" | "refine" | "voxelize" | "measure"),
        ) => {
            vec![v]
        }
        Some("bench") => match args.get(1).map(String::as_str) {
            Some("eval") => vec!["bench", "eval"],
            Some("tables") => vec!["bench", "tables"],
            Some("tessellate") => vec!["bench", "tessellate"],
            Some("voxelize") => vec!["bench", "voxelize"],
            _ => vec!["bench"],
        },
        _ => vec![],
    };
    let mut h = String::from("ccss ");
    for v in verb {
        h.push_str(v);
        h.push(' ');
    }
    h + "--help"
}

/// A clap error as one line: its first paragraph, plus its tips.
fn usage_error(e: &clap::Error) -> CliError {
    let text = e.to_string();
    let mut paragraphs = text.split("\n\n");
    let first = paragraphs.next().unwrap_or("invalid command line");
    let mut msg = first.split_whitespace().collect::<Vec<_>>().join(" ");
    if let Some(rest) = msg.strip_prefix("error: ") {
        msg = rest.to_string();
    }
    for l in text.lines().map(str::trim) {
        if let Some(tip) = l.strip_prefix("tip: ") {
            msg.push_str("; ");
            msg.push_str(tip);
        }
    }
    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        msg = "missing subcommand".to_string();
    }
    CliError::input(format!("{msg} (see '{}')", help_hint()))
}

fn run() -> Result<(), CliError> {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                let _ = e.print();
                return Ok(());
            }
            _ => return Err(usage_error(&e)),
        },
    };
    match &cli.cmd {
        Cmd::Eval(a) => eval_cmd::run(a),
        Cmd::Voxelize(a) => voxel_cmd::run(a),
        Cmd::Measure(a) => measure_cmd::run(a),
        Cmd::Info(a) => info_cmd::run(a),
        Cmd::Depth(a) => depth_cmd::run(a),
        Cmd::Tessellate(a) => tessellate_cmd::run(a),
        Cmd::Refine(a) => refine_cmd::run(a),
        Cmd::Bench {
            what: BenchCmd::Eval(a),
        } => bench_cmd::run(a),
        Cmd::Bench {
            what: BenchCmd::Tables(a),
        } => bench_tables::run(a),
        Cmd::Bench {
            what: BenchCmd::Tessellate(a),
        } => bench_tessellate::run(a),
        Cmd::Bench {
            what: BenchCmd::Voxelize(a),
        } => voxel_bench::run(a),
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
