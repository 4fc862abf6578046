//! Building the core objects of one mesh: eigen tables, topology and
//! evaluator, each in caller memory sized by the core's size queries.
//!
//! The core borrows everything (mesh arrays and memory), so the objects live
//! inside [`with_context`], which owns the buffers for the duration of a
//! closure. The buffers come from [`crate::mem`] (8-byte aligned, as the
//! core requires).

use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::mem::words;
use ccss_core::{BuildScratch, Evaluator, TableSet, Topology, Weights};
use std::time::{Duration, Instant};

/// Bytes used by the core objects of a mesh.
#[derive(Clone, Copy, Debug)]
pub struct Memory {
    /// `Topology::required_bytes`.
    pub topology: usize,
    /// `Evaluator::required_bytes`.
    pub evaluator: usize,
    /// `size_of::<TableSet>()` (all valences).
    pub tables: usize,
}

/// Wall-clock build times.
#[derive(Clone, Copy, Debug)]
pub struct Timings {
    /// `Topology::build` (validation included).
    pub topology: Duration,
    /// `Evaluator::build` (refinement and patch projection included).
    pub evaluator: Duration,
}

/// The core objects of one mesh.
pub struct Context<'a> {
    /// Validated topology.
    pub topology: Topology<'a>,
    /// The evaluator (shared between threads: it is read-only).
    pub evaluator: Evaluator<'a>,
    /// Memory used.
    pub memory: Memory,
    /// Build times.
    pub timings: Timings,
}

/// Eigen tables of vertex rule `w` for every supported valence, with their
/// build time.
pub fn build_tables(w: &Weights) -> CliResult<(Box<TableSet>, Duration)> {
    let t0 = Instant::now();
    // ~400 KB and ~66 KB: on the heap.
    let mut tables = Box::new(TableSet::ZERO);
    let mut scratch = Box::new(BuildScratch::ZERO);
    tables
        .build_into(w, &mut scratch)
        .map_err(|e| CliError::failure(format!("cannot build the eigen tables: {e}")))?;
    Ok((tables, t0.elapsed()))
}

/// Where a build failed.
#[derive(Debug)]
pub enum BuildError {
    /// The mesh failed topology validation (core error).
    Topology(ccss_core::Error),
    /// The evaluator could not be built (core error).
    Evaluator(ccss_core::Error),
}

impl BuildError {
    /// As a CLI error naming the mesh file.
    pub fn into_cli(self, mesh: &Mesh) -> CliError {
        match self {
            BuildError::Topology(e) => mesh.error(e),
            BuildError::Evaluator(e) => {
                CliError::failure(format!("{}: cannot build the evaluator: {e}", mesh.name))
            }
        }
    }
}

/// Builds topology and evaluator of `mesh` and runs `f` on them.
pub fn with_context<R>(
    mesh: &Mesh,
    tables: &TableSet,
    f: impl for<'c> FnOnce(&Context<'c>) -> R,
) -> Result<R, BuildError> {
    let topo_bytes = Topology::required_bytes(mesh.num_vertices(), &mesh.face_sizes);
    let mut topo_mem = words(topo_bytes);
    let t0 = Instant::now();
    let topology = Topology::build(mesh.input(), &mut topo_mem).map_err(BuildError::Topology)?;
    let t_topo = t0.elapsed();
    let eval_bytes = Evaluator::required_bytes(&topology, tables).map_err(BuildError::Evaluator)?;
    let mut eval_mem = words(eval_bytes);
    let t1 = Instant::now();
    let evaluator =
        Evaluator::build(&topology, tables, &mut eval_mem).map_err(BuildError::Evaluator)?;
    let t_eval = t1.elapsed();
    let ctx = Context {
        topology,
        evaluator,
        memory: Memory {
            topology: topo_bytes,
            evaluator: eval_bytes,
            tables: std::mem::size_of::<TableSet>(),
        },
        timings: Timings {
            topology: t_topo,
            evaluator: t_eval,
        },
    };
    Ok(f(&ctx))
}

/// [`with_context`] with errors as CLI errors.
pub fn with_mesh<R>(
    mesh: &Mesh,
    tables: &TableSet,
    f: impl for<'c> FnOnce(&Context<'c>) -> CliResult<R>,
) -> CliResult<R> {
    with_context(mesh, tables, f).map_err(|e| e.into_cli(mesh))?
}
