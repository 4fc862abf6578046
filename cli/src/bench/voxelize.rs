//! `ccss bench voxelize MESH --res N`: ccss's voxelization (the paper's
//! parameter-space subdivision + certification, then bit-parallel flooding)
//! side by side with a conventional baseline on the same grid and the same
//! normalisation (refinement, triangle voxelization, scanline fill: see
//! [`super::voxel_baseline`]).
//!
//! Everything single-threaded except the `parallel` line (the CLI's slab
//! parallelism on all cores). Times are the best of `--reps` runs.

use super::voxel_baseline::baseline;
use crate::context::{build_tables, with_mesh};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::mem::words;
use crate::parallel::slabs::{cuts, run_slabs};
use crate::stdout;
use ccss_core::voxel::{fit_transform, Adjacency, VoxelGrid, VoxelParams, VoxelWork};
use ccss_core::Weights;
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Time ccss's voxelization and flooding (single thread, whole grid, best of --reps) next to a \
baseline on the same grid: uniform Catmull-Clark refinement until edges are at most one \
voxel, triangle voxelization by the separating-axis test, scanline parity fill. Prints \
'ccss ...', 'baseline ...', 'speedup=X' and a 'parallel ...' line with the CLI's slab \
parallelism on all threads.";

/// Arguments of `ccss bench voxelize`.
#[derive(clap::Args, Debug)]
pub struct BenchVoxelizeArgs {
    /// Polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Resolution N.
    #[arg(long, default_value_t = 512)]
    pub res: u32,
    /// Adjacency of ccss's stop test (6, 18, 26).
    #[arg(long, default_value_t = 26)]
    pub adjacency: u32,
    /// Runs per measurement (the best is reported).
    #[arg(long, default_value_t = 3)]
    pub reps: u32,
    /// Time ccss only (skip the baseline and the parallel run).
    #[arg(long)]
    pub ccss_only: bool,
}

/// The shortest time of `reps` runs of `f` (seconds) and the last result.
pub fn best<R>(reps: u32, mut f: impl FnMut() -> R) -> (f64, R) {
    let mut t = f64::INFINITY;
    let mut r = None;
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        let x = f();
        t = t.min(t0.elapsed().as_secs_f64());
        r = Some(x);
    }
    (t, r.expect("at least one run"))
}

/// Runs the verb.
pub fn run(a: &BenchVoxelizeArgs) -> CliResult {
    let adjacency = Adjacency::from_n(a.adjacency).ok_or_else(|| {
        CliError::input(format!(
            "--adjacency must be 6, 18 or 26, got {}",
            a.adjacency
        ))
    })?;
    if !(2..=2048).contains(&a.res) {
        return Err(CliError::input("--res must be in 2..=2048"));
    }
    let mesh = Mesh::load(&a.mesh)?;
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let res = [a.res; 3];
    let params = VoxelParams::new(res, adjacency);
    let out = |s: String| stdout::line(&s);
    with_mesh(&mesh, &tables, |ctx| {
        let ev = &ctx.evaluator;
        let fail = |e: ccss_core::Error| CliError::failure(format!("{}: {e}", mesh.name));
        let mut work = Box::new(VoxelWork::ZERO);
        let mut mem = words(VoxelGrid::required_bytes(res).map_err(fail)?);
        let rows = (a.res * a.res) as usize;
        let mut stack = vec![0u32; rows];
        let (fit_s, t) = best(a.reps, || fit_transform(ev, res, &mut work));
        let t = t.map_err(fail)?;
        let mut vox_s = f64::INFINITY;
        let mut flood_s = f64::INFINITY;
        let mut counts = Default::default();
        let mut stats = Default::default();
        let mut rstats = Default::default();
        for _ in 0..a.reps.max(1) {
            let mut grid = VoxelGrid::new(res, &mut mem).map_err(fail)?;
            let t0 = Instant::now();
            rstats = grid.voxelize(ev, &params, None, &mut work).map_err(fail)?;
            vox_s = vox_s.min(t0.elapsed().as_secs_f64());
            let t1 = Instant::now();
            stats = grid.flood(ev, &mut stack, &mut work).map_err(fail)?;
            flood_s = flood_s.min(t1.elapsed().as_secs_f64());
            counts = grid.counts();
        }
        let total = vox_s + flood_s;
        out(format!(
            "ccss res={} adjacency={} voxelize_s={vox_s:.4} flood_s={flood_s:.4} total_s={total:.4} surface={} interior={} row_visits={} rays={} (fit_transform_s={fit_s:.4}, included in voxelize_s)",
            a.res, a.adjacency, counts.surface, counts.interior, stats.row_visits, stats.rays
        ))?;
        if a.ccss_only {
            let r = rstats;
            return out(format!(
                "walk cells={} leaves={} uncovered={} refined={} max_depth={} guard_hits={}",
                r.cells, r.leaves, r.uncovered, r.refined, r.max_depth, r.guard_hits
            ));
        }
        let b = baseline(&mesh, &t, a.res, a.reps).map_err(fail)?;
        let btotal = b.refine_s + b.voxelize_s + b.fill_s;
        out(format!(
            "baseline res={} level={} triangles={} refine_s={:.4} voxelize_s={:.4} fill_s={:.4} total_s={btotal:.4} surface={} interior={}",
            a.res, b.level, b.triangles, b.refine_s, b.voxelize_s, b.fill_s, b.surface, b.interior
        ))?;
        out(format!("speedup={:.2}", btotal / total))?;
        let threads = rayon::current_num_threads();
        let c = cuts(a.res, threads);
        let (par_s, _) = best(a.reps, || {
            run_slabs(ev, &params, t, &c, true, None, |_, _| ())
        });
        out(format!(
            "parallel threads={threads} slabs={} total_s={par_s:.4} speedup_vs_single={:.2}",
            c.len() - 1,
            total / par_s
        ))
    })
}
