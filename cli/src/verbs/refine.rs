//! `ccss refine [--a A] [--b B] [--g G] [--d D] [--p P] [--levels L]
//! [--scheme unified|catmull-clark] MESH.obj -o OUT.obj`: uniform refinement
//! with the unified scheme of Maillot & Stam (`ccss_core::unified`).
//!
//! Prints one line (stdout):
//!
//! ```text
//! vertices=98 faces=96 levels=2 seconds=0.0001
//! ```

use crate::error::{CliError, CliResult};
use crate::io::control_obj::write_obj;
use crate::io::mesh_in::Mesh;
use crate::mem::words;
use ccss_core::unified::{
    refine_unified_levels, unified_levels_bytes, TriangleRule, UnifiedParams, MAX_LEVELS,
};
use ccss_core::Topology;
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Uniform refinement with the unified subdivision scheme of Maillot & Stam ('A unified \
subdivision scheme for polygonal modeling', 2001): every edge is cut into --d pieces (faces \
grow by d^2 per level), --p is the odd degree ((p-1)/2 smoothing passes), --a the push-back \
(0 approximating, 1 interpolating), --b the rounding factor and --g the Catmull-Clark \
correction at extraordinary vertices. Defaults are the paper's tool defaults a = b = 0.5, \
g = 0, d = 2, p = 3; triangles are split into d^2 triangles. --scheme catmull-clark ignores \
those options and applies plain Catmull-Clark steps (a = b = 0, g = 1, d = 2, p = 3, \
triangles as polygons). --levels L (1..=16) applies L steps with the same parameters. The \
refined control mesh is written to -o OUT.obj ('v' and 'f' lines). Prints one line \
'vertices=V faces=F levels=L seconds=S' (S the wall time of refinement, not of reading or \
writing). Bad parameters are usage errors (exit code 2).";

/// The scheme of `ccss refine`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Scheme {
    /// Maillot-Stam unified scheme with --a --b --g --d --p.
    Unified,
    /// Plain Catmull-Clark steps.
    CatmullClark,
}

/// Arguments of `ccss refine`.
#[derive(clap::Args, Debug)]
pub struct RefineArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Output file (OBJ).
    #[arg(short = 'o', long, value_name = "OUT")]
    pub output: PathBuf,
    /// Push-back parameter a.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub a: f64,
    /// Rounding factor b.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub b: f64,
    /// Catmull-Clark correction g.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub g: f64,
    /// Split count d (pieces per edge, at least 2).
    #[arg(long, default_value_t = 2)]
    pub d: u32,
    /// Odd degree p.
    #[arg(long, default_value_t = 3)]
    pub p: u32,
    /// Number of refinement levels (1..=16).
    #[arg(long, default_value_t = 1)]
    pub levels: usize,
    /// Subdivision scheme.
    #[arg(long, value_enum, default_value_t = Scheme::Unified)]
    pub scheme: Scheme,
}

/// The parameters of every level (validated: bad ones are usage errors).
fn params(a: &RefineArgs) -> CliResult<UnifiedParams> {
    let p = match a.scheme {
        Scheme::CatmullClark => UnifiedParams::CATMULL_CLARK,
        Scheme::Unified => UnifiedParams {
            a: a.a,
            b: a.b,
            g: a.g,
            d: a.d,
            p: a.p,
            triangles: TriangleRule::Split,
        },
    };
    p.validate()
        .map_err(|e| CliError::input(format!("bad parameters: {e}")))?;
    if a.levels == 0 || a.levels > MAX_LEVELS {
        return Err(CliError::input(format!(
            "--levels must be in 1..={MAX_LEVELS}, got {}",
            a.levels
        )));
    }
    Ok(p)
}

/// Runs `ccss refine`.
pub fn run(a: &RefineArgs) -> CliResult {
    let p = params(a)?;
    let levels = vec![p; a.levels];
    let mesh = Mesh::load(&a.mesh)?;
    let mut tmem = words(Topology::required_bytes(
        mesh.num_vertices(),
        &mesh.face_sizes,
    ));
    let topo = Topology::build(mesh.input(), &mut tmem).map_err(|e| mesh.error(e))?;
    let bytes = unified_levels_bytes(&topo, &levels).map_err(|e| match e {
        ccss_core::Error::InvalidArgument(_) => {
            CliError::input(format!("{}: cannot refine: {e}", a.mesh.display()))
        }
        _ => mesh.error(e),
    })?;
    let mut mem = words(bytes);
    let start = Instant::now();
    let lv = refine_unified_levels(&topo, &levels, &mut mem)
        .map_err(|e| CliError::failure(format!("{}: cannot refine: {e}", a.mesh.display())))?;
    let seconds = start.elapsed().as_secs_f64();
    let fine = lv
        .finest()
        .ok_or_else(|| CliError::failure("no refined level"))?;
    write_obj(&a.output, fine.positions, fine.face_sizes, fine.indices)?;
    println!(
        "vertices={} faces={} levels={} seconds={seconds:.6}",
        fine.positions.len() / 3,
        fine.face_sizes.len(),
        a.levels
    );
    Ok(())
}
