//! `ccss measure MESH.obj [--density D]`: exact volume, area, centroid,
//! inertia tensor and mass of the solid bounded by the limit surface, by
//! quadrature on the limit surface (ccss-core's
//! `voxel::mass_properties`: the divergence theorem with Gauss-Legendre
//! rules that are exact on every polynomial piece, and bounded corner
//! squares at extraordinary vertices).
//!
//! One line: `volume=V area=A centroid=x,y,z inertia=Ixx,Iyy,Izz,Ixy,Iyz,Izx
//! mass=M error_bound=E area_error_bound=B seconds=T`; the inertia tensor is
//! about the centroid and mass-weighted (density D, default 1), `Ixy = -∫xy
//! dm`; `error_bound` bounds the volume error (`area_error_bound` the
//! area's, part of it an estimate of the adaptive area quadrature).

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::stdout;
use crate::surface::{with_surface, FeatureArgs, SurfaceJob};
use ccss_core::voxel::{mass_properties, Surface};
use ccss_core::Weights;
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Exact integral properties of the solid bounded by the limit surface, by quadrature on the \
limit surface (divergence theorem; Gauss-Legendre rules exact on every polynomial piece, \
corner squares at extraordinary vertices bounded). Prints one line 'volume=V area=A \
centroid=x,y,z inertia=Ixx,Iyy,Izz,Ixy,Iyz,Izx mass=M error_bound=E area_error_bound=B \
seconds=T': inertia about the centroid, mass-weighted with --density D (default 1; products \
of inertia as tensor entries, Ixy = -integral of x y dm), mass = D V, E a bound of the volume \
error and B of the area error. OpenSubdiv tags ('t crease', 't corner', 't hole', 't interpolateboundary', 't creasemethod') are honoured (as are --boundary and --creasing); the mesh must bound a solid (closed, no holes), else a one-line 'not a closed solid' error names the boundary edge or hole face. On such meshes the cells left out at crease ends, corners and extraordinary vertices contribute estimated (not proven) bounds; a note says so.";

/// Arguments of `ccss measure`.
#[derive(clap::Args, Debug)]
pub struct MeasureArgs {
    /// Polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Density (mass = density x volume; inertia is mass-weighted).
    #[arg(long, default_value_t = 1.0)]
    pub density: f64,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// Runs the verb.
pub fn run(a: &MeasureArgs) -> CliResult {
    if !a.density.is_finite() {
        return Err(CliError::input("--density must be finite"));
    }
    let mut mesh = Mesh::load_with_tags(&a.mesh)?;
    // Translation invariance: measure the mesh moved to its box centre
    // (exact for coordinates of similar magnitude), add the centre back to
    // the centroid; the core's bounds cover the rest.
    let centre = box_centre(&mesh.positions);
    for p in mesh.positions.chunks_exact_mut(3) {
        for (x, c) in p.iter_mut().zip(centre) {
            *x -= c;
        }
    }
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    with_surface(
        &mesh,
        &tables,
        a.features,
        Job {
            a,
            mesh: &mesh,
            centre,
        },
    )
}

/// The verb's work on either surface.
struct Job<'j> {
    a: &'j MeasureArgs,
    mesh: &'j Mesh,
    /// The box centre subtracted from the positions (added back to the
    /// centroid).
    centre: [f64; 3],
}

impl SurfaceJob<()> for Job<'_> {
    fn run<S: Surface + Sync + ?Sized>(self, ev: &S, feature: bool) -> CliResult {
        let (a, mesh, centre) = (self.a, self.mesh, self.centre);
        let t0 = Instant::now();
        let p = mass_properties(ev).map_err(|e| mesh.error(e))?;
        let s = t0.elapsed().as_secs_f64();
        let centroid: Vec<f64> = p.centroid.iter().zip(centre).map(|(x, c)| x + c).collect();
        let d = a.density;
        let i = p.inertia.map(|x| x * d);
        let line = format!(
            "volume={:.15e} area={:.15e} centroid={:.15e},{:.15e},{:.15e} inertia={:.15e},{:.15e},{:.15e},{:.15e},{:.15e},{:.15e} mass={:.15e} error_bound={:.3e} area_error_bound={:.3e} seconds={s:.4}\n",
            p.volume,
            p.area,
            centroid[0],
            centroid[1],
            centroid[2],
            i[0],
            i[1],
            i[2],
            i[3],
            i[4],
            i[5],
            d * p.volume,
            p.volume_error_bound,
            p.area_error_bound,
        );
        if feature && !p.rigorous {
            eprintln!(
                "ccss: note: {}: the error bounds include estimates for the small cells left \
                 out at crease ends, corners and extraordinary vertices (see \
                 ccss_core::voxel::measure)",
                mesh.name
            );
        }
        if p.volume < 0.0 {
            eprintln!(
                "ccss: warning: {}: negative volume (the faces are oriented inward)",
                mesh.name
            );
        }
        stdout::text(&line)
    }
}

/// Midpoint of the bounding box of `positions` (x y z interleaved); zero
/// for a non-finite box (the core then names the offending vertex).
fn box_centre(positions: &[f64]) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions.chunks_exact(3) {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let c = [0, 1, 2].map(|a| lo[a] * 0.5 + hi[a] * 0.5);
    if c.iter().all(|x| x.is_finite()) {
        c
    } else {
        [0.0; 3]
    }
}
