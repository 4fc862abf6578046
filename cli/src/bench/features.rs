//! `ccss bench features`: single-threaded evaluation of a mesh with
//! creases, corners, holes or boundaries (`FeatureEvaluator`), per class of
//! points: R, answered from a cached B-spline piece of levels 1 to 3; X,
//! next to special vertices or semi-sharp values (a deeper piece of the
//! cache tree, or local refinement closer than the tree reaches). The points file format is
//! `bench eval`'s, so `bench/osd/osd_eval MESH F --tags` times the same
//! points in OpenSubdiv.

use super::rng::SplitMix64;
use super::timing::{measure, Api};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::points;
use crate::stdout;
use crate::verbs::eval::{with_feature_mesh_cached, BoundaryArg, CacheArgs, CreasingArg};
use ccss_core::eval::Query;
use std::path::PathBuf;
use std::time::Instant;

pub const ABOUT: &str = "\
Time single-threaded evaluation of a mesh with OpenSubdiv tags, boundaries or holes (the \
evaluator of 'ccss eval' for such meshes) and print 'ccss class=R points=N ns_per_eval=XX.X' \
for points answered from a cached B-spline piece of levels 1 to 3 and 'class=X' for points \
next to special vertices or semi-sharp creases (a deeper piece of the cache tree, or local \
refinement closer than the tree reaches), median over --samples \
samples after a warm-up pass, then 'ccss checksum=...'; with random points a first line \
'ccss uniform_draws=N local_share=S' tells which share of uniform points needs local \
refinement. Points are drawn with SplitMix64 \
from --seed, uniform over the sub-faces that have a surface and uniform in (u, v), until \
--points of each class are found; --write-points F writes them in the OpenSubdiv harness \
format and exits, --points-file F times the points of such a file instead (then \
'bench/osd/osd_eval MESH F --tags' times the same points in OpenSubdiv).";

#[derive(clap::Args, Debug)]
pub struct BenchFeaturesArgs {
    /// Polygon mesh (OBJ) with OpenSubdiv tags, boundaries or holes.
    pub mesh: PathBuf,
    /// Points per class.
    #[arg(long, default_value_t = 100_000)]
    pub points: usize,
    /// Seed of the point generator (SplitMix64).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Time the points of this file instead of random ones.
    #[arg(long, value_name = "F", conflicts_with_all = ["write_points"])]
    pub points_file: Option<PathBuf>,
    /// Write the generated points to F and exit.
    #[arg(long, value_name = "F")]
    pub write_points: Option<PathBuf>,
    /// Also evaluate second derivatives.
    #[arg(long)]
    pub second: bool,
    /// Timed samples per class (the median is reported).
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub samples: u32,
    /// Boundary interpolation (overrides the file's tag).
    #[arg(long, value_name = "MODE")]
    pub boundary: Option<BoundaryArg>,
    /// Creasing method (overrides the file's tag).
    #[arg(long, value_name = "METHOD")]
    pub creasing: Option<CreasingArg>,
    #[command(flatten)]
    pub cache: CacheArgs,
}

/// Runs the verb.
pub fn run(a: &BenchFeaturesArgs) -> CliResult {
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let t0 = Instant::now();
    with_feature_mesh_cached(&mesh, a.boundary, a.creasing, a.cache.cache(), |ev| {
        let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
        let pts = match &a.points_file {
            Some(f) => points::read(f, ev)?,
            None => {
                let mut rng = SplitMix64::new(a.seed);
                let mut slots = Vec::new();
                for f in 0..ev.num_faces() {
                    for s in 0..ev.num_subfaces(f) {
                        let q = Query {
                            face: f as u32,
                            sub: s as u32,
                            u: 0.5,
                            v: 0.5,
                        };
                        if ev.check(&q).is_ok() {
                            slots.push((f as u32, s as u32));
                        }
                    }
                }
                if slots.is_empty() {
                    return Err(CliError::input(format!(
                        "{}: no face has a surface",
                        mesh.name
                    )));
                }
                let (mut r, mut x) = (Vec::new(), Vec::new());
                let (mut draws, mut local) = (0usize, 0usize);
                let limit = 200 * a.points.max(1);
                for _ in 0..limit {
                    if r.len() >= a.points && x.len() >= a.points {
                        break;
                    }
                    let (face, sub) = slots[rng.below(slots.len())];
                    let q = Query {
                        face,
                        sub,
                        u: rng.next_f64(),
                        v: rng.next_f64(),
                    };
                    draws += 1;
                    let depth = ev.piece_depth(&q);
                    if depth.is_none() {
                        local += 1;
                    }
                    // R: a piece of levels 1 to 3; X: deeper (the cache
                    // tree near special vertices) or refined locally.
                    if depth.is_some_and(|d| d <= 2) {
                        if r.len() < a.points {
                            r.push((q, 'R'));
                        }
                    } else if x.len() < a.points {
                        x.push((q, 'X'));
                    }
                }
                stdout::line(&format!(
                    "ccss uniform_draws={draws} local_share={:.4}",
                    local as f64 / draws.max(1) as f64
                ))?;
                r.extend(x);
                r
            }
        };
        if let Some(w) = &a.write_points {
            points::write(w, &pts, |_| None)?;
            let count = |l: char| pts.iter().filter(|p| p.1 == l).count();
            return stdout::line(&format!(
                "ccss wrote {} points to {} (R={}, X={})",
                pts.len(),
                w.display(),
                count('R'),
                count('X')
            ));
        }
        stdout::line(&format!("ccss setup_ms={setup_ms:.3}"))?;
        let mut checksum = 0.0;
        for label in ['R', 'X'] {
            let qs: Vec<Query> = pts.iter().filter(|p| p.1 == label).map(|p| p.0).collect();
            if qs.is_empty() {
                stdout::line(&format!("ccss class={label} points=0 ns_per_eval=nan"))?;
                continue;
            }
            let m = measure(ev, &qs, a.second, Api::Derivs, a.samples as usize, || {});
            checksum += m.checksum;
            stdout::line(&format!(
                "ccss class={label} points={} ns_per_eval={:.1}",
                qs.len(),
                m.ns_per_eval
            ))?;
        }
        stdout::line(&format!("ccss checksum={checksum:.16e}"))
    })
}
