//! `ccss refine [--a A] [--b B] [--g G] [--d D] [--p P] [--levels L]
//! [--scheme unified|catmull-clark] [--boundary M] [--creasing C] MESH.obj
//! -o OUT.obj`: uniform refinement with the unified scheme of Maillot &
//! Stam (`ccss_core::unified`), or, for `--scheme catmull-clark` on meshes
//! with OpenSubdiv tags, boundaries or non-manifold parts, OpenSubdiv's
//! sharp Catmull-Clark rules (one `FeatureMesh` step per level, the output
//! carrying the refined sharpness and holes as `t` tags, so that it has the
//! same limit surface). The unified scheme has no rules for those meshes:
//! a clear error.
//!
//! Prints one line (stdout):
//!
//! ```text
//! vertices=98 faces=96 levels=2 seconds=0.0001
//! ```

use super::eval::{with_feature_mesh_only, BoundaryArg, CreasingArg};
use crate::error::{CliError, CliResult};
use crate::io::control_obj::{write_obj, write_obj_tagged, LevelTags};
use crate::io::mesh_in::Mesh;
use crate::mem::words;
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::unified::{
    refine_unified_levels, unified_levels_bytes, TriangleRule, UnifiedParams, MAX_LEVELS,
};
use ccss_core::{Error, MeshInput, Topology};
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
writing). Bad parameters are usage errors (exit code 2). Meshes with OpenSubdiv tags ('t crease', 't corner', 't hole', 't interpolateboundary', 't creasemethod'), boundaries or non-manifold parts are refined with --scheme catmull-clark only, by OpenSubdiv's rules (--boundary none|edge|edge-corner and --creasing uniform|chaikin override the file's options); the output then carries the refined sharpness, corners and holes as 't' tags, so it has the same limit surface. The unified scheme has no rules for them (an error).";

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
    /// Boundary interpolation for --scheme catmull-clark (overrides 't
    /// interpolateboundary'): none, edge (edge-only) or edge-corner.
    #[arg(long, value_name = "MODE")]
    pub boundary: Option<BoundaryArg>,
    /// Creasing method for --scheme catmull-clark (overrides 't
    /// creasemethod'): uniform or chaikin.
    #[arg(long, value_name = "METHOD")]
    pub creasing: Option<CreasingArg>,
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
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let forced = a.boundary.is_some() || a.creasing.is_some();
    let mut tmem = words(Topology::required_bytes(
        mesh.num_vertices(),
        &mesh.face_sizes,
    ));
    let topo = match Topology::build(mesh.input(), &mut tmem) {
        Ok(_) if mesh.tags.any() || forced => {
            return refine_features(a, &mesh, "has OpenSubdiv tags")
        }
        Ok(t) => t,
        Err(
            e @ (Error::BoundaryEdge { .. }
            | Error::NonManifoldEdge { .. }
            | Error::NonManifoldVertex { .. }
            | Error::UnsupportedValence { .. }),
        ) => return refine_features(a, &mesh, &mesh.error(e).to_string()),
        Err(e) => return Err(mesh.error(e)),
    };
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

/// One level of a mesh with features, in the form `FeatureMesh::build`
/// takes (and `write_obj_tagged` writes).
struct Level {
    positions: Vec<f64>,
    sizes: Vec<u32>,
    indices: Vec<u32>,
    tags: LevelTags,
}

impl Level {
    /// The level-1 mesh of `fm` with its sharpness and holes.
    fn child_of(fm: &FeatureMesh) -> Level {
        let adj = &fm.level1;
        let mut tags = LevelTags {
            options: fm.options,
            ..LevelTags::default()
        };
        for e in 0..adj.num_edges() {
            let s = fm.sharpness.edge(e);
            if s > 0.0 {
                tags.crease_vertices
                    .extend_from_slice(&adj.edge_vert[2 * e..2 * e + 2]);
                tags.crease_sharpness.push(s);
            }
        }
        for v in 0..adj.num_vertices() {
            let s = fm.sharpness.vertex(v);
            if s > 0.0 {
                tags.corner_vertices.push(v as u32);
                tags.corner_sharpness.push(s);
            }
        }
        tags.holes = (0..adj.num_faces())
            .filter(|&f| fm.hole[f] != 0)
            .map(|f| f as u32)
            .collect();
        Level {
            positions: fm.points.to_vec(),
            sizes: vec![4; adj.num_faces()],
            indices: adj.face_vert.to_vec(),
            tags,
        }
    }

    /// The next level.
    fn refine(&self) -> Result<Level, Error> {
        let input = MeshInput {
            positions: &self.positions,
            face_sizes: &self.sizes,
            indices: &self.indices,
        };
        let t = &self.tags;
        let features = FeatureInput {
            crease_vertices: &t.crease_vertices,
            crease_sharpness: &t.crease_sharpness,
            corner_vertices: &t.corner_vertices,
            corner_sharpness: &t.corner_sharpness,
            holes: &t.holes,
            options: t.options,
        };
        let mut mem = words(FeatureMesh::required_bytes(&input)?);
        let fm = FeatureMesh::build(&input, &features, &mut mem)?;
        Ok(Level::child_of(&fm))
    }
}

/// `--scheme catmull-clark` with OpenSubdiv's sharp rules (`why` says why
/// the mesh needs them, for the unified scheme's error).
fn refine_features(a: &RefineArgs, mesh: &Mesh, why: &str) -> CliResult {
    if a.scheme == Scheme::Unified {
        return Err(CliError::input(format!(
            "{}: the unified scheme has no rules for boundaries, creases, corners, holes or \
             non-manifold parts (the mesh {why}); use --scheme catmull-clark (OpenSubdiv's rules)",
            a.mesh.display()
        )));
    }
    let start = Instant::now();
    let mut level =
        with_feature_mesh_only(mesh, a.boundary, a.creasing, |fm| Ok(Level::child_of(fm)))?;
    for _ in 1..a.levels {
        level = level
            .refine()
            .map_err(|e| CliError::failure(format!("{}: cannot refine: {e}", a.mesh.display())))?;
    }
    let seconds = start.elapsed().as_secs_f64();
    write_obj_tagged(
        &a.output,
        &level.positions,
        &level.sizes,
        &level.indices,
        &level.tags,
    )?;
    println!(
        "vertices={} faces={} levels={} seconds={seconds:.6}",
        level.positions.len() / 3,
        level.sizes.len(),
        a.levels
    );
    Ok(())
}
