//! Voxelization of closed CCSS solids, volume flooding, voxel runs and
//! integral properties (\[CL-R ch. 5\]; S. Lai and F. Cheng, *Voxelization of
//! free-form solids represented by Catmull-Clark subdivision surfaces*).
//!
//! Everything here is allocation-free: grids live in caller memory
//! ([`VoxelGrid::required_bytes`]), the recursion uses the fixed-size
//! [`VoxelWork`], the flood a caller-chosen stack of row numbers.
//!
//! * [`VoxelGrid::voxelize`] — the paper's `Voxelization` /
//!   `VoxelizeSubPatch` (corner evaluation, rounding eq. (2), the N-adjacency
//!   stop tests for N = 18, 26, `k x k` pre-split, the recursion guard),
//!   followed by a certification walk that makes the "no holes" property
//!   (eq. 3) a guarantee; N = 6 stops at the N = 18 test and leaves the
//!   rest to the certification: see [`rasterize`].
//! * [`VoxelGrid::flood`] — inside/outside classification: bit-parallel
//!   flooding of rows with a bounded stack and linear sweeps (the paper's
//!   `FloodingXYZ` + `GRAYSTACK` + scan), and a certified ray test per
//!   enclosed component instead of the paper's normal-based seed: see
//!   [`flood`].
//! * [`VoxelGrid::write_runs`] — the voxel set as x-runs per (y, z) row.
//! * [`mass_properties`] — exact volume, area, centroid and inertia by
//!   quadrature on the limit surface (divergence theorem) with an error
//!   bound; the paper's voxel volume and quad area come with the
//!   voxelization ([`RasterStats::quad_area`], [`VoxelGrid::counts`]).
//!
//! Coordinates: voxel `(i, j, k)` is the unit cube centred at the integer
//! point `(i, j, k)` of voxel space (`[i - 1/2, i + 1/2)` per axis); model
//! point `p` is at `scale * p + offset` in voxel space ([`VoxelTransform`]).
//!
//! ```
//! use ccss_core::voxel::{Adjacency, VoxelGrid, VoxelParams, VoxelWork};
//! use ccss_core::mem::words_for;
//! use ccss_core::{BuildScratch, Evaluator, MeshInput, TableSet, Topology};
//! # fn main() -> Result<(), ccss_core::Error> {
//! let p = [-1.,-1.,-1., 1.,-1.,-1., 1.,1.,-1., -1.,1.,-1., -1.,-1.,1., 1.,-1.,1., 1.,1.,1., -1.,1.,1.];
//! let sizes = [4u32; 6];
//! let idx = [0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7];
//! let mesh = MeshInput { positions: &p, face_sizes: &sizes, indices: &idx };
//! let mut tables = Box::new(TableSet::ZERO);
//! tables.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))?;
//! let mut tmem = vec![0u64; words_for(Topology::required_bytes(8, &sizes))];
//! let topo = Topology::build(mesh, &mut tmem)?;
//! let mut emem = vec![0u64; words_for(Evaluator::required_bytes(&topo, &tables)?)];
//! let ev = Evaluator::build(&topo, &tables, &mut emem)?;
//! let params = VoxelParams::new([32, 32, 32], Adjacency::Six);
//! let mut gmem = vec![0u64; words_for(VoxelGrid::required_bytes(params.res)?)];
//! let mut grid = VoxelGrid::new(params.res, &mut gmem)?;
//! let mut work = Box::new(VoxelWork::ZERO);
//! grid.voxelize(&ev, &params, None, &mut work)?;
//! let mut stack = [0u32; 1024];
//! grid.flood(&ev, &mut stack, &mut work)?;
//! let c = grid.counts();
//! assert!(c.surface > 0 && c.interior > 0);
//! # Ok(())
//! # }
//! ```
//!
//! ## Layer
//!
//! Layer 7 (see the crate docs): imports the layers up to `eval` (the
//! Bezier nets are `math::bezier`'s), never `tessellate` or `unified`.

mod bounds;
mod cells;
pub mod flood;
mod grid;
pub mod measure;
mod measure_options;
pub mod rasterize;
mod ray;
mod runs;
pub mod solid;
mod stack;

pub use bounds::{fit_box, limit_bounds};
pub use flood::FloodStats;
pub use grid::{GridState, VoxelCounts, VoxelGrid, MAX_RESOLUTION, SLAB_MARGIN};
pub use measure::{mass_properties, mass_properties_with, MassProperties};
pub use measure_options::MeasureOptions;
pub use rasterize::{RasterStats, LEAF_EXTENT, TAU};
pub use runs::VoxelRun;
pub use stack::{VoxelWork, MAX_DEPTH};

use crate::error::Error;
use crate::eval::{Evaluator, FeatureEvaluator};
use glam::DVec3;

/// A surface the voxel algorithms accept: the smooth [`Evaluator`] (a
/// closed manifold mesh) or a [`FeatureEvaluator`] (creases, corners,
/// semi-sharp edges; it must bound a solid, else
/// [`Error::NotClosedSolid`] names the offending edge, face or vertex).
///
/// Both are walked as patches of cells: bicubic Bezier nets, corner
/// squares at extraordinary vertices of the smooth evaluator (bounded by
/// the eigen corner radius) and, on feature meshes, cells that are not
/// polynomial at their level ([`crate::eval::CellGeom::Hull`]: bounded by
/// the convex hull of their control points, split until their box is
/// small enough or beside what is tested). Sealed.
pub trait Surface: cells::Source {}

impl Surface for Evaluator<'_> {}
impl Surface for FeatureEvaluator<'_, '_> {}

/// Ok if `ev` bounds a solid (always for the smooth [`Evaluator`]; see
/// [`solid::check_closed_solid`] for feature meshes). The voxelizer, the
/// flood and [`mass_properties`] check this themselves.
pub fn check_solid<S: Surface + ?Sized>(ev: &S) -> Result<(), Error> {
    ev.check_solid()
}

/// The adjacency `N` of the voxelization (the paper's stop test).
///
/// `Six` gives a thick voxel set (every surface point's voxel is black, the
/// paper's eq. 3); `Eighteen` and `TwentySix` stop earlier and give thinner
/// sets whose certified property is 6-separability (see [`rasterize`]).
/// Every black voxel holds a limit-surface point for all three.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Adjacency {
    /// N = 6: the paper's test is corner voxels pairwise face-adjacent; the
    /// first walk stops at the N = 18 test instead and the certification
    /// adds every voxel the surface meets (module docs of [`rasterize`]).
    Six,
    /// N = 18: corner voxels pairwise edge-adjacent.
    Eighteen,
    /// N = 26: corner voxels pairwise vertex-adjacent.
    TwentySix,
}

impl Adjacency {
    /// From 6, 18 or 26.
    pub fn from_n(n: u32) -> Option<Adjacency> {
        match n {
            6 => Some(Adjacency::Six),
            18 => Some(Adjacency::Eighteen),
            26 => Some(Adjacency::TwentySix),
            _ => None,
        }
    }
    /// 6, 18 or 26.
    pub fn n(self) -> u32 {
        match self {
            Adjacency::Six => 6,
            Adjacency::Eighteen => 18,
            Adjacency::TwentySix => 26,
        }
    }
}

/// Class of a voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum VoxelClass {
    /// Neither surface nor interior.
    Outside = 0,
    /// Contains a point of the limit surface (black).
    Surface = 1,
    /// White, centre inside the solid (after flooding).
    Interior = 2,
}

/// Parameters of a voxelization.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VoxelParams {
    /// Resolution `[M1, M2, M3]` (2..=65536 each).
    pub res: [u32; 3],
    /// The adjacency N.
    pub adjacency: Adjacency,
    /// Pre-split count `k` (each patch is cut into `k x k` cells before the
    /// recursion; a power of two in 1..=64; the paper uses 8).
    pub presplit: u32,
}

impl VoxelParams {
    /// Resolution and adjacency with the paper's pre-split `k = 8`.
    pub fn new(res: [u32; 3], adjacency: Adjacency) -> VoxelParams {
        VoxelParams {
            res,
            adjacency,
            presplit: 8,
        }
    }
}

/// The model-to-voxel map `v = scale * p + offset` (uniform scale). Voxel
/// `(i, j, k)` covers the model box
/// `[(i - 1/2 - offset_x) / scale, (i + 1/2 - offset_x) / scale)` (same for
/// y, z): in binvox terms `translate = (-1/2 - offset) / scale` and
/// `scale_binvox = M / scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelTransform {
    /// Voxels per model unit.
    pub scale: f64,
    /// Voxel coordinates of the model origin.
    pub offset: [f64; 3],
}

impl VoxelTransform {
    /// The identity (scale 1, offset 0).
    pub const IDENTITY: VoxelTransform = VoxelTransform {
        scale: 1.0,
        offset: [0.0; 3],
    };
    /// Model point to voxel coordinates.
    pub fn to_voxel(&self, p: DVec3) -> DVec3 {
        p * self.scale + DVec3::from_array(self.offset)
    }
    /// Voxel coordinates to model point (the centre of voxel (i, j, k) is
    /// `to_model((i, j, k))`).
    pub fn to_model(&self, v: DVec3) -> DVec3 {
        (v - DVec3::from_array(self.offset)) / self.scale
    }
    /// Edge length of a voxel in model units.
    pub fn voxel_size(&self) -> f64 {
        1.0 / self.scale
    }
}

/// The paper's normalisation for resolution `res`: the guaranteed limit
/// box ([`limit_bounds`]) scaled uniformly into
/// `[0, M1-1] x [0, M2-1] x [0, M3-1]` ([`fit_box`]).
pub fn fit_transform<S: Surface + ?Sized>(
    ev: &S,
    res: [u32; 3],
    work: &mut VoxelWork,
) -> Result<VoxelTransform, Error> {
    if res.iter().any(|&m| !(2..=MAX_RESOLUTION).contains(&m)) {
        return Err(Error::InvalidArgument(
            "voxel resolution must be in 2..=65536 per axis",
        ));
    }
    let (lo, hi) = limit_bounds(ev, work)?;
    fit_box(lo, hi, res)
}
