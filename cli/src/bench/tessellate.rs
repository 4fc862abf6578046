//! `ccss bench tessellate MESH [--abs-flatness E | --rel-flatness R]`:
//! single-threaded throughput of adaptive tessellation, side by side with
//! uniform refinement to the depth that meets the same bound.
//!
//! Output (stdout):
//!
//! ```text
//! ccss adaptive criterion=abs:0.00173 slots=6 polygons=3048 vertices=3298 max_depth=10 bound=1.7e-3 size_query_ms=0.61 mark_ms=0.52 emit_ms=0.31 ms=0.83 mvertices_per_s=3.97 ... outputs=full
//! ccss uniform depth=10 timed_depth=10 polygons=6291456 vertices=6291458 mark_ms=.. emit_ms=.. ms=.. mvertices_per_s=..
//! ccss au_ratio=0.000484 uniform_over_adaptive_time=...
//! ```
//!
//! `mark_ms` is `Tessellation::build` (marking with all flatness tests, and
//! counting) into memory sized beforehand by `Tessellation::required_bytes`
//! (timed separately as `size_query_ms`); `emit_ms` is `emit` of positions,
//! normals, polygons and triangles (`outputs=full`; with `--mesh-only`
//! positions and polygons, `outputs=mesh`) into preallocated buffers; `ms` their
//! sum and `mvertices_per_s` = vertices / ms. Medians of `--reps` runs;
//! `best_mvertices_per_s` uses the fastest run (less disturbed by other
//! load on a shared machine) and `fast_decile_mvertices_per_s` the 10th
//! percentile of the run times (a virtual machine's host can slow whole
//! stretches of runs, by 1.4-1.8x on ours: the fast decile is the rate
//! outside them, steadier than the single best run); `checksum` hashes every
//! output bit and `required_bytes` is the size query's answer (the plan's
//! memory), `corner_bytes` the part of it holding saved corner-cell
//! expansions.
//! The uniform tessellation is `Criterion::Uniform(depth)` through the same
//! code (no flatness tests); when it would exceed `--max-uniform-vertices`
//! it is timed at the deepest level that does not (`timed_depth`).

use crate::context::{build_tables, with_mesh, Context};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::parallel::tessellate::{uniform_depth, PROGRESS};
use crate::progress::Progress;
use crate::stdout;
use crate::verbs::tessellate::{au_ratio, core_err, criterion, parse_tol};
use ccss_core::tessellate::{mark_slot, Criterion, Options, Output, Scratch, Tessellation};
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Time single-threaded adaptive tessellation (size query, marking with the flatness tests, \
emission of positions, normals, polygons and triangles, or with --mesh-only positions and \
polygons; medians of --reps runs) and \
uniform refinement to the depth that meets the same bound (same code, no flatness tests), \
and print vertices per second of both, the A/U polygon ratio and the time ratio. Default \
tolerance: --abs-flatness 0.001 x the bounding-box diagonal. A uniform tessellation larger \
than --max-uniform-vertices is timed at the deepest level below that (timed_depth) and its \
full-depth time extrapolated by 4 per level.";

/// Arguments of `ccss bench tessellate`.
#[derive(clap::Args, Debug)]
pub struct BenchTessellateArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Absolute flatness (default: 0.001 x the bounding-box diagonal).
    #[arg(long, value_name = "E", value_parser = parse_tol, conflicts_with = "rel_flatness")]
    pub abs_flatness: Option<f64>,
    /// Relative flatness.
    #[arg(long, value_name = "R", value_parser = parse_tol)]
    pub rel_flatness: Option<f64>,
    /// Timed runs (the median is reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub reps: u32,
    /// Largest uniform tessellation timed (vertices).
    #[arg(long, default_value_t = 20_000_000)]
    pub max_uniform_vertices: usize,
    /// Time only the adaptive tessellation (skip the uniform comparison).
    #[arg(long)]
    pub adaptive_only: bool,
    /// Emit positions and polygons only (no normals, no triangles), as a
    /// host that writes an OBJ of polygons would.
    #[arg(long)]
    pub mesh_only: bool,
    #[command(flatten)]
    pub weights: WeightsArg,
}

fn median(v: Vec<f64>) -> f64 {
    quantile(v, 0.5)
}

/// The value below which a fraction `q` of `v` lies (nearest rank).
fn quantile(mut v: Vec<f64>, q: f64) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let at = ((q * v.len() as f64) as usize).min(v.len() - 1);
    v[at]
}

fn best(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Timings of one configuration (medians, milliseconds).
struct Timed {
    size_ms: f64,
    mark_ms: f64,
    emit_ms: f64,
    /// Fastest whole run (mark + emit).
    best_ms: f64,
    /// Whole runs: 10 % of them took at most this long.
    decile_ms: f64,
    polygons: usize,
    vertices: usize,
    max_level: u32,
    bound: f64,
    /// FNV-1a hash of every output bit (positions, normals, polygons,
    /// triangles): equal outputs give equal checksums.
    checksum: u64,
    /// `Tessellation::required_bytes`.
    bytes: usize,
    /// Of which saved corner-cell expansions (`SlotMark::corner_bytes`).
    corner_bytes: usize,
}

/// FNV-1a over the bit patterns of the output arrays.
fn checksum(f: &[&[f64]], u: &[&[u32]]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |x: u64| {
        h ^= x;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    };
    for a in f {
        a.iter().for_each(|x| eat(x.to_bits()));
    }
    for a in u {
        a.iter().for_each(|&x| eat(x as u64));
    }
    h
}

/// Times `reps` size queries, builds and emissions (normals and triangles
/// too when `full`).
fn time_one(
    ctx: &Context,
    opts: Options,
    reps: u32,
    full: bool,
) -> Result<Timed, ccss_core::Error> {
    let (topo, ev) = (&ctx.topology, &ctx.evaluator);
    let mut scratch = Box::new(Scratch::ZERO);
    let (mut size, mut mark, mut emit, mut total) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut need = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch)?;
        size.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    let mut mem = words(need);
    let c = Tessellation::build(topo, ev, opts, &mut mem)?.counts();
    let mut pos = vec![0.0; 3 * c.vertices];
    let extra = |n: usize| if full { n } else { 0 };
    let mut nrm = vec![0.0; extra(3 * c.vertices)];
    let mut sizes = vec![0u32; c.polygons];
    let mut idx = vec![0u32; c.polygon_indices];
    let mut tri = vec![0u32; extra(3 * c.triangles)];
    let mut last = None;
    for _ in 0..reps + 1 {
        let t0 = Instant::now();
        let mut t = Tessellation::build(topo, ev, opts, &mut mem)?;
        let t1 = Instant::now();
        t.emit(Output {
            positions: &mut pos,
            normals: full.then_some(&mut nrm[..]),
            params: None,
            polygon_sizes: &mut sizes,
            polygon_indices: &mut idx,
            triangles: full.then_some(&mut tri[..]),
            cells: None,
        })?;
        let t2 = Instant::now();
        if last.is_some() {
            // The first run warms up.
            mark.push((t1 - t0).as_secs_f64() * 1e3);
            emit.push((t2 - t1).as_secs_f64() * 1e3);
            total.push((t2 - t0).as_secs_f64() * 1e3);
        }
        last = Some(t.stats());
    }
    let st = last.unwrap_or_default();
    std::hint::black_box(&pos);
    let checksum = checksum(&[&pos, &nrm], &[&sizes, &idx, &tri]);
    let mut corner_bytes = 0;
    for s in 0..ev.num_slots() {
        corner_bytes += mark_slot(ev, &opts, s, None, &mut scratch)?.corner_bytes as usize;
    }
    Ok(Timed {
        checksum,
        bytes: need,
        corner_bytes,
        size_ms: median(size),
        mark_ms: median(mark),
        emit_ms: median(emit),
        best_ms: best(&total),
        decile_ms: quantile(total, 0.1),
        polygons: c.polygons,
        vertices: c.vertices,
        max_level: st.max_level,
        bound: st.bound,
    })
}

fn bench(a: &BenchTessellateArgs, mesh: &Mesh, ctx: &Context) -> CliResult {
    let (lo, hi) = ctx.topology.bounding_box();
    let diag = (hi - lo).length();
    let crit = match (a.abs_flatness, a.rel_flatness) {
        (None, None) => Criterion::Absolute(1e-3 * diag),
        (e, r) => criterion(e, r),
    };
    let name = match crit {
        Criterion::Absolute(e) => format!("abs:{e}"),
        Criterion::Relative(r) => format!("rel:{r}"),
        Criterion::Uniform(l) => format!("uniform:{l}"),
    };
    let slots = ctx.evaluator.num_slots();
    let err = |e| core_err(&mesh.name, e);
    let full = !a.mesh_only;
    let ad = time_one(ctx, Options::absolute(1.0).with(crit), a.reps, full).map_err(err)?;
    let ms = ad.mark_ms + ad.emit_ms;
    let outputs = if full { "full" } else { "mesh" };
    stdout::line(&format!(
        "ccss adaptive criterion={name} slots={slots} polygons={} vertices={} max_depth={} bound={:.3e} size_query_ms={:.3} mark_ms={:.3} emit_ms={:.3} ms={ms:.3} mvertices_per_s={:.2} best_mvertices_per_s={:.2} fast_decile_mvertices_per_s={:.2} checksum={:016x} required_bytes={} corner_bytes={} outputs={outputs}",
        ad.polygons,
        ad.vertices,
        ad.max_level,
        ad.bound,
        ad.size_ms,
        ad.mark_ms,
        ad.emit_ms,
        ad.vertices as f64 / ms / 1e3,
        ad.vertices as f64 / ad.best_ms / 1e3,
        ad.vertices as f64 / ad.decile_ms / 1e3,
        ad.checksum,
        ad.bytes,
        ad.corner_bytes
    ))?;
    if a.adaptive_only {
        return Ok(());
    }
    let progress = Progress::delayed(PROGRESS);
    let ud = uniform_depth(&ctx.evaluator, crit, ad.max_level, &progress).map_err(err)?;
    progress.finish();
    let Some(l) = ud else {
        return stdout::line("ccss uniform depth=none");
    };
    let mut timed = l;
    while timed > 0 && slots as f64 * 4f64.powi(timed as i32) > a.max_uniform_vertices as f64 {
        timed -= 1;
    }
    let un = time_one(ctx, Options::uniform(timed), a.reps, full).map_err(err)?;
    let ums = un.mark_ms + un.emit_ms;
    stdout::line(&format!(
        "ccss uniform depth={l} timed_depth={timed} polygons={} vertices={} mark_ms={:.3} emit_ms={:.3} ms={ums:.3} mvertices_per_s={:.2} best_mvertices_per_s={:.2} fast_decile_mvertices_per_s={:.2}",
        un.polygons,
        un.vertices,
        un.mark_ms,
        un.emit_ms,
        un.vertices as f64 / ums / 1e3,
        un.vertices as f64 / un.best_ms / 1e3,
        un.vertices as f64 / un.decile_ms / 1e3
    ))?;
    // Time of the full-depth uniform run, extrapolated by its vertex count
    // when it was not timed at that depth.
    let scale = 4f64.powi((l - timed) as i32);
    stdout::line(&format!(
        "ccss au_ratio={:.6} uniform_over_adaptive_time={:.2}",
        au_ratio(ad.polygons, slots, Some(l)),
        ums * scale / ms
    ))
}

trait With {
    fn with(self, c: Criterion) -> Self;
}
impl With for Options {
    fn with(mut self, c: Criterion) -> Self {
        self.criterion = c;
        self
    }
}

/// Runs the verb.
pub fn run(a: &BenchTessellateArgs) -> CliResult {
    let weights = a.weights.load()?;
    let mesh = Mesh::load(&a.mesh)?;
    let (tables, _) = build_tables(&weights)?;
    with_mesh(&mesh, &tables, |ctx| bench(a, &mesh, ctx)).map_err(|e: CliError| e)
}
