//! The surface a verb works on: the smooth evaluator of a closed manifold
//! mesh, or the feature evaluator when the OBJ has OpenSubdiv tags (creases,
//! corners, holes, boundary options), when `--boundary` / `--creasing` are
//! given, or when the mesh is open or non-manifold (the feature path then
//! reports what is wrong, e.g. "not a closed solid"). One chooser for the
//! verbs that accept any `ccss_core::voxel::Surface` or
//! `ccss_core::query::QuerySurface` (`voxelize`, `measure`, `raycast`,
//! `closest`, `slice`): they implement [`SurfaceJob`] once, generic over the
//! surface.

use crate::context::{with_context, BuildError};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::verbs::eval::{with_feature_mesh, BoundaryArg, CreasingArg};
use ccss_core::query::{IndexNode, Indexed, QuerySurface, SlotIndex};
use ccss_core::voxel::Surface;
use ccss_core::{Error, TableSet};

/// Work on a surface, written once for both evaluator families.
pub trait SurfaceJob<R> {
    /// Runs on `ev`; `feature` tells which family it is.
    fn run<S: Surface + QuerySurface + Sync + ?Sized>(self, ev: &S, feature: bool) -> CliResult<R>;
}

/// `--boundary` and `--creasing` of a verb.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct FeatureArgs {
    /// Boundary interpolation (overrides 't interpolateboundary'):
    /// none, edge (edge-only) or edge-corner. Selects OpenSubdiv's rules.
    #[arg(long, value_name = "MODE")]
    pub boundary: Option<BoundaryArg>,
    /// Creasing method (overrides 't creasemethod'): uniform or chaikin.
    /// Selects OpenSubdiv's rules.
    #[arg(long, value_name = "METHOD")]
    pub creasing: Option<CreasingArg>,
}

/// Runs `job` on the surface of `mesh` (module docs). `tables`: the
/// standard tables of the smooth path.
pub fn with_surface<R>(
    mesh: &Mesh,
    tables: &TableSet,
    opts: FeatureArgs,
    job: impl SurfaceJob<R>,
) -> CliResult<R> {
    let forced = opts.boundary.is_some() || opts.creasing.is_some();
    if !mesh.tags.any() && !forced {
        // The job is moved into the closure only if the build succeeds.
        let mut job = Some(job);
        match with_context(mesh, tables, |ctx| {
            job.take()
                .map(|j| j.run(&ctx.evaluator, false))
                .unwrap_or_else(|| Err(CliError::failure("internal: job ran twice")))
        }) {
            Ok(r) => return r,
            // Open, non-manifold or high-valence meshes: the feature path
            // (which names the boundary edge of an open mesh).
            Err(BuildError::Topology(
                Error::BoundaryEdge { .. }
                | Error::NonManifoldEdge { .. }
                | Error::NonManifoldVertex { .. }
                | Error::InconsistentOrientation { .. }
                | Error::UnusedVertex { .. }
                | Error::UnsupportedValence { .. },
            )) => {
                let job = job
                    .take()
                    .ok_or_else(|| CliError::failure("internal: job ran twice"))?;
                return with_feature_mesh(mesh, opts.boundary, opts.creasing, |fe| {
                    job.run(fe, true)
                });
            }
            Err(e) => return Err(e.into_cli(mesh)),
        }
    }
    with_feature_mesh(mesh, opts.boundary, opts.creasing, |fe| job.run(fe, true))
}

/// Runs `f` on `ev` with its slot index (`ccss_core::query::SlotIndex`,
/// one root cell per slot, built here once): the queries then visit only
/// the slots their ray, point or planes can reach, with the same answers.
pub fn with_index<S: QuerySurface + Sync + ?Sized, R>(
    ev: &S,
    f: impl FnOnce(&Indexed<'_, S>) -> CliResult<R>,
) -> CliResult<R> {
    let fail = |e: Error| CliError::failure(format!("slot index: {e}"));
    let mut nodes = vec![IndexNode::default(); SlotIndex::required_len(ev)];
    let ix = SlotIndex::build(ev, &mut nodes).map_err(fail)?;
    let iev = Indexed::new(ev, &ix).map_err(fail)?;
    f(&iev)
}
