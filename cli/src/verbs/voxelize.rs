//! `ccss voxelize --res N [--adjacency 6|18|26] [--fill] [--runs RUNS.txt]
//! [--preview SLICES.png] MESH.obj -o OUT.binvox`: voxelization of the limit
//! surface (ccss-core's `voxel` module: the paper's recursive
//! parameter-space subdivision with a certification pass, then flooding).
//!
//! The per-patch work runs on all cores (`RAYON_NUM_THREADS` to change): the
//! grid is cut into z-slabs, and each slab is voxelized and classified in its
//! own slab grid, which gives exactly the voxels of the whole grid (see
//! `ccss_core::voxel::rasterize`; [`crate::parallel::slabs`]). The slabs
//! are then written as binvox (x slowest, then z, then y fastest;
//! run-length coded), optionally as runs and as a PNG montage of z-slices
//! (the writers are in [`crate::io`]).

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::binvox::write_binvox;
use crate::io::mesh_in::Mesh;
use crate::io::preview::write_preview;
use crate::io::slab_bits::slab_bits;
use crate::io::voxel_runs::write_runs;
use crate::parallel::slabs::{cuts, run_slabs};
use crate::progress::Progress;
use crate::stdout;
use crate::surface::{with_surface, FeatureArgs, SurfaceJob};
use ccss_core::voxel::{check_solid, fit_transform, Adjacency, Surface, VoxelParams, VoxelWork};
use ccss_core::Weights;
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
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
model units); T the voxelization and classification time on P threads (RAYON_NUM_THREADS). OpenSubdiv tags ('t crease', 't corner', 't hole', 't interpolateboundary', \
't creasemethod') are honoured (as are --boundary and --creasing); the mesh must bound a solid \
(closed, no holes), else a one-line 'not a closed solid' error names the boundary edge or hole \
face.";

/// Arguments of `ccss voxelize`.
#[derive(clap::Args, Debug)]
pub struct VoxelizeArgs {
    /// Polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Output binvox file.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Resolution N (an N x N x N grid, 2..=4096).
    #[arg(long)]
    pub res: u32,
    /// Adjacency of the stop test: 6 (thick, no holes), 18 or 26 (thin).
    #[arg(long, default_value_t = 26)]
    pub adjacency: u32,
    /// Also write the interior voxels (surface only without it).
    #[arg(long)]
    pub fill: bool,
    /// Write the voxel runs as text: lines 'z y x0 x1 class' (x1 exclusive;
    /// class 1 surface, 2 interior).
    #[arg(long)]
    pub runs: Option<PathBuf>,
    /// Write a PNG montage of up to 16 z-slices.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Pre-split count k (a power of two, 1..=64).
    #[arg(long, default_value_t = 8)]
    pub presplit: u32,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// Runs the verb.
pub fn run(a: &VoxelizeArgs) -> CliResult {
    let adjacency = Adjacency::from_n(a.adjacency).ok_or_else(|| {
        CliError::input(format!(
            "--adjacency must be 6, 18 or 26, got {}",
            a.adjacency
        ))
    })?;
    if !(2..=4096).contains(&a.res) {
        return Err(CliError::input(format!(
            "--res must be in 2..=4096, got {}",
            a.res
        )));
    }
    if !(1..=64).contains(&a.presplit) || !a.presplit.is_power_of_two() {
        return Err(CliError::input(
            "--presplit must be a power of two in 1..=64",
        ));
    }
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let params = VoxelParams {
        res: [a.res; 3],
        adjacency,
        presplit: a.presplit,
    };
    with_surface(
        &mesh,
        &tables,
        a.features,
        Job {
            a,
            mesh: &mesh,
            params,
        },
    )
}

/// The verb's work on either surface.
struct Job<'j> {
    a: &'j VoxelizeArgs,
    mesh: &'j Mesh,
    params: VoxelParams,
}

impl SurfaceJob<()> for Job<'_> {
    fn run<S: Surface + Sync + ?Sized>(self, ev: &S, _feature: bool) -> CliResult {
        let (a, mesh, params) = (self.a, self.mesh, self.params);
        let res = params.res;
        let t0 = Instant::now();
        let mut work = Box::new(VoxelWork::ZERO);
        // A feature mesh must bound a solid: say so before any work.
        check_solid(ev).map_err(|e| mesh.error(e))?;
        let t = fit_transform(ev, res, &mut work).map_err(|e| mesh.error(e))?;
        let threads = rayon::current_num_threads();
        let cuts = cuts(a.res, threads);
        let progress = Progress::new(
            "voxelizing [{bar:40}] {pos}/{len} slabs",
            (cuts.len() - 1) as u64,
            a.res >= 256,
        );
        let out = run_slabs(ev, &params, t, &cuts, true, Some(&progress), |g, st| {
            (slab_bits(g), st, g.counts())
        })
        .map_err(|e| mesh.error(e))?;
        progress.finish();
        let seconds = t0.elapsed().as_secs_f64();
        let (mut surface, mut interior, mut area) = (0u64, 0u64, 0.0);
        let mut slabs = Vec::with_capacity(out.len());
        for (bits, st, c) in out {
            surface += c.surface;
            interior += c.interior;
            area += st.quad_area;
            slabs.push(bits);
        }
        let volume = (surface + interior) as f64 / t.scale.powi(3);
        write_binvox(&a.output, &slabs, a.res, &t, a.fill)?;
        if let Some(p) = &a.runs {
            write_runs(p, &slabs, a.res, a.fill)?;
        }
        if let Some(p) = &a.preview {
            write_preview(p, &slabs, a.res, a.fill)?;
        }
        let line = format!(
            "res={} adjacency={} surface={surface} interior={interior} volume={volume:.9e} area={area:.9e} seconds={seconds:.4} threads={threads}\n",
            a.res, a.adjacency
        );
        stdout::text(&line)
    }
}
