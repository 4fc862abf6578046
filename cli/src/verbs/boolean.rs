//! `ccss boolean --op union|intersection|difference --eps E [--triangulate]
//! A.obj B.obj -o OUT.(obj|stl|ply) [--curve CURVE.obj] [--uv UV.tsv]`: Booleans of two
//! closed solids within `eps` ([`crate::solid_boolean`], `ccss_core::boolean`).
//!
//! One line on stdout:
//!
//! ```text
//! triangles=T vertices=V curve_loops=L curve_points=P tolerance=t amplification=a bound=B passes=N local=0|1 seconds=S
//! ```

use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::mesh_out::{self, Format, MeshOut};
use crate::parallel::tessellate::PROGRESS;
use crate::progress::Progress;
use crate::solid_boolean::{run as run_boolean, BoolResult};
use crate::stdout;
use crate::verbs::tessellate::parse_tol;
use ccss_core::boolean::{Op, Options};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Union, intersection or difference (A - B) of the solids bounded by two closed limit surfaces, \
within --eps (model units). Both surfaces are tessellated with a guaranteed bound (every \
vertex an exact limit point), the two triangle meshes are combined with exact orientation \
predicates (crossing points named by edge and triangle, shared by both sides: no cracks), and \
the error bound is the largest of the triangles' bounds and, over the crossings, the wedge \
bound h(a, t_A, t_B) <= a max(t_A, t_B), the amplification a = 1/cos(gamma/2) coming from the \
angle gamma between the outward normals of the two kept sheets where they cross (measured at \
the crossings) and t_A, t_B the bounds of the two crossing triangles (h = a t when they are \
equal, less when one sheet is closer): a proven a-posteriori bound of each triangle (the actual \
deviation at 15 points plus a second-derivative term, and at 45 points where that is not \
enough), about a third of the tessellation tolerance. The first pass tessellates smooth meshes \
at 2.5 eps (eps/1.25 with creases) and is accepted when every bound passes; otherwise the next \
passes refine locally: triangles above eps split, and near the curve (within a previous \
crossing's reach: its bound + 2 eps) the cells of a solid that was the worse side of a failing \
crossing get eps/(0.37 e), e = h/max(t_A, t_B) <= a of the previous pass's crossings nearby \
(smaller where a crossing failed again); the rest keeps its tolerance (meshes with creases: \
a-priori bounds, the smallest of these tolerances everywhere). After a certified pass one more \
runs, and again while the certified output shrinks; the smallest is written. Keep rules: union keeps A outside B and B outside \
A; intersection A inside B and B inside A; difference A outside B and B inside A (reversed). \
An input whose surface is inside out (faces clockwise seen from outside, negative enclosed \
volume) is taken as the solid it bounds, with a note. \
-o OUT: .obj, .stl or .ply; the output is triangles whatever the flags (the corefinement cuts \
the tessellations' triangles along the curve; --triangulate is accepted for symmetry with \
'ccss tessellate' and changes nothing), closed and consistently oriented (counter-clockwise \
seen from outside) with shared vertices. --curve C.obj writes the intersection curve as closed \
OBJ 'l' polylines. --uv UV.tsv writes one line per output triangle, in output order: 'solid \
face sub u0 v0 u1 v1 u2 v2' (solid 0 = A, 1 = B; the base face and sub-face of the patch the \
triangle lies on and the (u, v) of its three vertices there, mapped from the tessellation by \
barycentric coordinates): re-evaluating the surface there gives points within B of the output \
vertices. Disjoint solids: the union is both, the intersection empty (with a note), the \
difference A. A near-tangential contact (amplification above --max-amplification) fails \
naming the faces of A and B. Prints one line 'triangles=T vertices=V curve_loops=L \
curve_points=P tolerance=t amplification=a bound=B passes=N local=0|1 seconds=S': t the \
smallest tessellation tolerance used, B <= eps the error bound, N the pass written (the pass after it, \
if any, ran too), local=1 when the written pass refined locally.";

/// The operation.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpArg {
    /// A ∪ B.
    Union,
    /// A ∩ B.
    Intersection,
    /// A − B.
    Difference,
}

impl OpArg {
    /// The core's operation.
    pub fn op(self) -> Op {
        match self {
            OpArg::Union => Op::Union,
            OpArg::Intersection => Op::Intersection,
            OpArg::Difference => Op::Difference,
        }
    }
}

/// Arguments of `ccss boolean`.
#[derive(clap::Args, Debug)]
pub struct BooleanArgs {
    /// First solid (OBJ).
    pub a: PathBuf,
    /// Second solid (OBJ).
    pub b: PathBuf,
    /// The operation.
    #[arg(long, value_enum)]
    pub op: OpArg,
    /// Hausdorff tolerance in model units.
    #[arg(long, value_name = "E", value_parser = parse_tol, allow_negative_numbers = true)]
    pub eps: f64,
    /// No effect: the output is always triangles (the corefinement cuts the tessellations'
    /// triangles); accepted for symmetry with `ccss tessellate`.
    #[arg(long)]
    pub triangulate: bool,
    /// Output file: .obj, .stl (binary) or .ply (binary).
    #[arg(short = 'o', long, value_name = "OUT")]
    pub output: PathBuf,
    /// Write the intersection curve as OBJ `l` polylines.
    #[arg(long, value_name = "CURVE.obj")]
    pub curve: Option<PathBuf>,
    /// Write each output triangle's `solid face sub u0 v0 u1 v1 u2 v2` (tab-separated).
    #[arg(long, value_name = "UV.tsv")]
    pub uv: Option<PathBuf>,
    /// Largest amplification 1/cos(gamma/2) accepted before a near-tangential error.
    #[arg(long, default_value_t = Options::DEFAULT_MAX_AMPLIFICATION)]
    pub max_amplification: f64,
}

/// Area-weighted vertex normals of a triangle mesh.
pub fn vertex_normals(pos: &[f64], tris: &[u32]) -> Vec<f64> {
    let mut n = vec![0.0f64; pos.len()];
    let p = |i: u32| ccss_core::DVec3::from_slice(&pos[3 * i as usize..3 * i as usize + 3]);
    for t in tris.chunks_exact(3) {
        let f = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        for &v in t {
            for k in 0..3 {
                n[3 * v as usize + k] += f[k];
            }
        }
    }
    for c in n.chunks_exact_mut(3) {
        let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        if l > 0.0 {
            c.iter_mut().for_each(|x| *x /= l);
        }
    }
    n
}

/// Writes the curve as OBJ polylines (each loop closed).
pub fn write_curve(path: &Path, r: &BoolResult) -> CliResult {
    let werr =
        |e: std::io::Error| CliError::failure(format!("cannot write {}: {e}", path.display()));
    let f = std::fs::File::create(path).map_err(werr)?;
    let mut w = std::io::BufWriter::new(f);
    let mut at = 0;
    let mut next = 1;
    for &n in &r.curve_sizes {
        let idx = &r.curve_indices[at..at + n as usize];
        at += n as usize;
        for &v in idx {
            let p = &r.positions[3 * v as usize..3 * v as usize + 3];
            writeln!(w, "v {} {} {}", p[0], p[1], p[2]).map_err(werr)?;
        }
        let mut line = String::from("l");
        for k in 0..=n {
            line.push_str(&format!(" {}", next + (k % n)));
        }
        writeln!(w, "{line}").map_err(werr)?;
        next += n;
    }
    w.flush().map_err(werr)
}

/// Writes the parameter-space provenance, one triangle a line.
pub fn write_uv(path: &Path, r: &BoolResult) -> CliResult {
    let werr =
        |e: std::io::Error| CliError::failure(format!("cannot write {}: {e}", path.display()));
    let f = std::fs::File::create(path).map_err(werr)?;
    let mut w = std::io::BufWriter::new(f);
    for t in &r.uv {
        let u = &t.uv;
        writeln!(
            w,
            "{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}",
            t.solid, t.face, t.sub, u[0], u[1], u[2], u[3], u[4], u[5]
        )
        .map_err(werr)?;
    }
    w.flush().map_err(werr)
}

/// Runs the verb.
pub fn run(a: &BooleanArgs) -> CliResult {
    let Some(format) = Format::of(&a.output) else {
        return Err(CliError::input(format!(
            "{}: unknown output format; use .obj, .stl or .ply",
            a.output.display()
        )));
    };
    if a.max_amplification.is_nan() || a.max_amplification < 1.0 {
        return Err(CliError::input("--max-amplification must be at least 1"));
    }
    let ma = Mesh::load_with_tags(&a.a)?;
    let mb = Mesh::load_with_tags(&a.b)?;
    let progress = Progress::delayed(PROGRESS);
    let t0 = Instant::now();
    let opts = Options {
        max_amplification: a.max_amplification,
    };
    let r = run_boolean(&ma, &mb, a.op.op(), a.eps, opts, a.uv.is_some(), &progress)?;
    let seconds = t0.elapsed().as_secs_f64();
    progress.finish();
    for (rev, path) in r.reversed.iter().zip([&a.a, &a.b]) {
        if *rev {
            eprintln!(
                "ccss: note: {}: the surface is inside out (its faces are clockwise seen from outside: negative enclosed volume); taken as the solid it bounds",
                path.display()
            );
        }
    }
    if r.counts.crossing_pairs == 0 {
        eprintln!(
            "ccss: note: the surfaces do not cross; {}",
            match a.op {
                OpArg::Union => "the union is both solids (or the outer one)",
                OpArg::Intersection => "the intersection is empty (or the inner solid)",
                OpArg::Difference => "the difference is A (or empty, or A with a cavity)",
            }
        );
    }
    let normals = vertex_normals(&r.positions, &r.triangles);
    let sizes = vec![3u32; r.counts.triangles];
    mesh_out::write(
        &a.output,
        format,
        &MeshOut {
            positions: &r.positions,
            normals: &normals,
            face_sizes: &sizes,
            indices: &r.triangles,
        },
    )?;
    if let Some(c) = &a.curve {
        write_curve(c, &r)?;
    }
    if let Some(u) = &a.uv {
        write_uv(u, &r)?;
    }
    stdout::line(&format!(
        "triangles={} vertices={} curve_loops={} curve_points={} tolerance={:.6e} amplification={:.6} bound={:.6e} passes={} local={} seconds={seconds:.6}",
        r.counts.triangles,
        r.counts.vertices,
        r.counts.curve_loops,
        r.counts.curve_points,
        r.tolerance,
        r.stats.amplification.max(1.0),
        r.bound,
        r.passes,
        r.local as u32,
    ))
}
