//! Error-controlled adaptive tessellation of the limit surface (\[CL-R
//! ch. 7\], Lai & Cheng's adaptive marking and rendering), allocation-free.
//!
//! The output is an **inscribed polyhedron**: every vertex is an exact limit
//! point `S(face, sub, u, v)` at dyadic parameters, and its polygons tile
//! the parameter domains of the slots (one per quad, N per N-gon: see
//! [`crate::eval`]). Each slot is covered by a quadtree of dyadic cells
//! `[i/2^l, (i+1)/2^l] x [j/2^l, (j+1)/2^l]`; a cell is accepted when flat
//! enough, otherwise split at its midpoints (up to [`MAX_LEVEL`]).
//!
//! ## The guarantee
//!
//! Acceptance uses the bound of [`crate::bounds::cell_bound`]
//! ([`crate::bounds::CellBound::interpolation_bound`]): for the
//! polygon of a cell (exact limit points on its boundary) and **any**
//! triangulation of it, `|S(x) - T(x)| <= bound` for every parameter `x` of
//! the cell, where `T` is the piecewise-linear interpolant. So every point
//! of the limit surface is within the bound of the output triangles and
//! every point of the triangles within the bound of the surface (both
//! one-sided Hausdorff distances), with no sampling involved. The report's
//! (7.5) test, an offset of the corner polygon, is replaced by this bound on
//! the actual output triangles (which include the extra points of finer
//! neighbours). The bounds are computed top down from Bezier nets split by
//! de Casteljau, the same quantities as `bounds::cell_bound` (the tests
//! check that they agree).
//!
//! Every bound includes the rounding term of [`crate::bounds::rounding`]
//! (`TERM eps M`, `M` the largest control-point magnitude of the slot):
//! the stated bound holds for the computed output. Slots with coordinates
//! outside `2^-200..2^200`, and cells that still fail at `max_level` with
//! the rounding term at least half their bound (a tolerance below what the
//! coordinates can certify), are [`Error::CoordinateRange`].
//!
//! ## Criteria ([`Criterion`])
//!
//! * **Absolute flatness** `Absolute(eps)`: accept when `bound <= eps`
//!   (model units); the reported [`Stats::bound`] is then `<= eps`.
//! * **Relative flatness** `Relative(r)`: accept when
//!   `bound <= r * d`, `d` the longer 3D diagonal of the cell's corner quad;
//!   invariant under similarity transforms of the input. At an
//!   extraordinary vertex the parametric interpolation error of a corner
//!   cell is proportional to its size (the characteristic map is not
//!   linear), so `bound / d` does not shrink with the level: corner cells
//!   are also accepted once `bound <= r * D`, `D` the longer diagonal of the
//!   slot's corner quad (still similarity invariant).
//! * `Uniform(l)`: every slot split to level `l` (for comparisons).
//!
//! [`uniform_depth`] finds the uniform level meeting the same guarantee:
//! the smallest `L` such that every level-`L` cell of every slot passes the
//! same test, or lies inside a corner cell whose bound (which covers every
//! triangle with vertices in that cell) meets it (for relative flatness:
//! the corner rule). The adaptive tessellation's deepest level is a lower
//! bound; A/U ratios (\[CL-R Table 7.1\]) are `polygons / (slots 4^L)`.
//!
//! ## Crack elimination and vertex identity
//!
//! Every side of an accepted cell is replaced by the polyline of all output
//! vertices on it (the corners of finer cells on the other side, in the
//! same slot or across the slot boundary), so neighbouring cells, slots and
//! faces share identical vertices and edges: for a closed input the output
//! is a closed, consistently oriented 2-manifold. Vertices are identified
//! by their place, never by comparing floats: base vertex; base edge +
//! dyadic parameter; N-gon centre; internal N-gon edge + parameter; or a
//! point inside one slot (see `vertices.rs` and `sides.rs`).
//!
//! ## Passes and memory
//!
//! 1. **Marking** ([`Tessellation::build`], or [`mark_slot`] per slot,
//!    e.g. in parallel, then [`Tessellation::build_marked`]): the quadtree
//!    of each slot, depth first with an explicit stack in a [`Scratch`].
//!    Then counting: vertices, polygons, polygon indices, triangles
//!    ([`Tessellation::counts`]).
//!    Counting numbers every vertex: points inside a slot through the node
//!    records, slot corners by their identity, points on slot boundaries
//!    by merging the sorted points of the two slots along each base edge
//!    or internal N-gon edge (which also gives every slot side the sorted
//!    list of its vertices, for the polygons); the polygon-index count
//!    follows from Euler's formula (the output has the input's
//!    characteristic), and emission checks it.
//! 2. **Emission** ([`Tessellation::emit`]): vertices (positions, optional
//!    normals and `(face, sub, u, v)`), polygons (sizes + indices,
//!    counter-clockwise seen from outside, one per accepted cell, with its
//!    parameter cell optionally) and optional triangles (each polygon cut
//!    by its shorter diagonal into two corner regions filled by zig-zag
//!    strips: no new vertices, no zero-area triangles), into caller buffers
//!    of at least the counted sizes.
//!
//! The marking keeps what the emission needs of the children of every
//! split corner cell (the five new points, and the Bezier nets of the split
//! ring-region children) so that the emission does not redo their eigen
//! expansions.
//!
//! Everything lives in one caller buffer ([`Tessellation::required_bytes`];
//! a too-small buffer gives [`crate::error::Error::BufferTooSmall`] with the exact
//! requirement, found by finishing the marking in count-only mode). The
//! module is single-threaded and reentrant; nothing recurses or allocates.
//!
//! ```
//! # use ccss_core::{BuildScratch, Evaluator, MeshInput, TableSet, Topology};
//! use ccss_core::mem::words_for;
//! use ccss_core::tessellate::{Options, Output, Scratch, Tessellation};
//! # fn main() -> Result<(), ccss_core::Error> {
//! # let p = [-1.,-1.,-1., 1.,-1.,-1., 1.,1.,-1., -1.,1.,-1., -1.,-1.,1., 1.,-1.,1., 1.,1.,1., -1.,1.,1.];
//! # let sizes = [4u32; 6];
//! # let idx = [0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7];
//! # let mesh = MeshInput { positions: &p, face_sizes: &sizes, indices: &idx };
//! # let mut tables = Box::new(TableSet::ZERO);
//! # tables.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))?;
//! # let mut tmem = vec![0u64; words_for(Topology::required_bytes(8, &sizes))];
//! # let topo = Topology::build(mesh, &mut tmem)?;
//! # let mut emem = vec![0u64; words_for(Evaluator::required_bytes(&topo, &tables)?)];
//! # let ev = Evaluator::build(&topo, &tables, &mut emem)?;
//! let opts = Options::absolute(1e-3);
//! let need = Tessellation::required_bytes(&topo, &ev, &opts, &mut Box::new(Scratch::ZERO))?;
//! let mut mem = vec![0u64; words_for(need)];
//! let mut t = Tessellation::build(&topo, &ev, opts, &mut mem)?;
//! let c = t.counts();
//! let (mut pos, mut sizes, mut ids) = (vec![0.0; 3 * c.vertices], vec![0; c.polygons], vec![0; c.polygon_indices]);
//! t.emit(Output { positions: &mut pos, normals: None, params: None,
//!                 polygon_sizes: &mut sizes, polygon_indices: &mut ids, triangles: None, cells: None })?;
//! assert!(t.stats().bound <= 1e-3);
//! # Ok(())
//! # }
//! ```
//!
//! ## Meshes with features
//!
//! [`Tessellation::build_feature`] (sized by
//! [`Tessellation::required_bytes_feature`]) tessellates the surface of a
//! [`crate::eval::FeatureEvaluator`] (creases, corners, boundaries, holes,
//! non-manifold parts) with the same guarantee: only the marking and the
//! vertex positions are its own (`feature.rs`: polynomial cells by their
//! Bezier nets, cells next to irregular vertices by the diameter of their
//! control points' hull); numbering, crack elimination, polygons and counts
//! are the passes above, over the base mesh's edges, which may have one
//! face (boundary: the output is open there), two, or more (non-manifold).
//! Hole faces have no slots and produce nothing.
//!
//! ## Layer
//!
//! Layer 7 (see the crate docs): imports `config`, `error`, `mem`, `math`
//! (the Bezier nets and their kernels), `mesh`, `eigen`, `eval` and
//! `bounds`, never `voxel` or `unified`. Inside, `record.rs` (the record
//! bits) is the bottom file; the passes import it and each other without
//! circles.

mod carrier;
pub(crate) mod cells;
mod feature;
mod field;
mod forest;
mod mark;
mod plan;
mod polygons;
mod record;
mod scratch;
mod sides;
mod single;
mod triangulate;
mod vertices;

pub use crate::eval::Query as VertexParam;
pub use field::ToleranceField;
pub use plan::{
    mark_slot, mark_slot_field, marking_bound, uniform_depth, uniform_passes, Tessellation,
};
pub use scratch::Scratch;
pub use single::OutputF32;

use crate::error::Error;
use crate::eval::Query;

/// Deepest quadtree level (cells of size 2^-30 of a slot; a firmware
/// may lower it at build time with `CCSS_TESS_MAX_LEVEL`, which shrinks
/// [`Scratch`] by one level record per level).
pub const MAX_LEVEL: u32 = crate::config::TESS_MAX_LEVEL;

/// Work cap of the marking: quadtree nodes of one tessellation (all slots
/// together; `2^29 - 1`, what the node records' `u32` indices allow). Each
/// node is one bound test (a Bezier net split by de Casteljau, or an
/// eigen-expansion of a corner cell). The budget a caller chooses is
/// [`Options::max_level`]: at most `S (4^(L + 1) - 1) / 3` nodes over `S`
/// slots (`docs/WORST_CASE.md`).
pub const MAX_NODES: u64 = u32::MAX as u64 / 8;

/// The error of a marking past [`MAX_NODES`].
pub(crate) fn nodes_exceeded() -> Error {
    Error::WorkLimitExceeded {
        limit: MAX_NODES,
        what: "quadtree nodes of a tessellation (tessellate::MAX_NODES; lower max_level or \
               raise the tolerance)",
    }
}

pub(crate) const TOO_DEEP: &str =
    "the tolerance needs more subdivision levels than max_level allows; use a larger tolerance";

/// When a cell is accepted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Criterion {
    /// Absolute flatness: the guaranteed bound is at most this (model
    /// units, positive and finite).
    Absolute(f64),
    /// Relative flatness: bound / longer diagonal of the cell's corner quad
    /// is at most this (positive and finite; see the module docs for
    /// corner cells).
    Relative(f64),
    /// Every cell split to exactly this level.
    Uniform(u32),
}

/// What a [`Tessellation`] keeps in its caller buffer between marking and
/// emission: memory against time. The output is the same bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Keep {
    /// Keep the expansion of every split corner cell (at extraordinary
    /// vertices) from marking to emission ([`SlotMark::corner_bytes`]:
    /// per cell 248 bytes of points plus 392 per split ring-region
    /// child), so that emission does not redo the eigen expansions.
    /// Without, emission redoes them. Default `true`.
    pub corner_expansions: bool,
}

impl Keep {
    /// Everything kept (the default).
    pub const ALL: Keep = Keep {
        corner_expansions: true,
    };
    /// Nothing kept that emission can redo (least memory).
    pub const LEAST: Keep = Keep {
        corner_expansions: false,
    };
}

impl Default for Keep {
    fn default() -> Self {
        Self::ALL
    }
}

/// Where [`Tessellation::emit_stream`] hands each polygon:
/// `(positions, vertices, triangles)` (all the vertex positions, `x y z`
/// each; the polygon's vertex indices, counter-clockwise from outside;
/// its triangles, 3 indices each).
pub type PolygonSink<'s> = dyn FnMut(&[f64], &[u32], &[u32]) + 's;

/// Tessellation options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// The acceptance test.
    pub criterion: Criterion,
    /// Deepest level allowed (`<= MAX_LEVEL`); a cell at this level that
    /// still fails the test is an error.
    pub max_level: u32,
}

impl Options {
    /// Absolute flatness `eps`, up to [`MAX_LEVEL`].
    pub const fn absolute(eps: f64) -> Self {
        Options {
            criterion: Criterion::Absolute(eps),
            max_level: MAX_LEVEL,
        }
    }
    /// Relative flatness `r`, up to [`MAX_LEVEL`].
    pub const fn relative(r: f64) -> Self {
        Options {
            criterion: Criterion::Relative(r),
            max_level: MAX_LEVEL,
        }
    }
    /// Uniform level `l`.
    pub const fn uniform(l: u32) -> Self {
        Options {
            criterion: Criterion::Uniform(l),
            max_level: MAX_LEVEL,
        }
    }
    /// Checks the values.
    pub fn validate(&self) -> Result<(), Error> {
        if self.max_level > MAX_LEVEL {
            return Err(Error::InvalidArgument("max_level above MAX_LEVEL"));
        }
        match self.criterion {
            Criterion::Absolute(e) | Criterion::Relative(e) if !(e.is_finite() && e > 0.0) => Err(
                Error::InvalidArgument("flatness tolerance must be positive and finite"),
            ),
            Criterion::Uniform(l) if l > self.max_level => {
                Err(Error::InvalidArgument("uniform level above max_level"))
            }
            _ => Ok(()),
        }
    }
}

/// Sizes of the output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Vertices (positions: 3 per vertex).
    pub vertices: usize,
    /// Polygons (one per accepted cell).
    pub polygons: usize,
    /// Sum of the polygon sizes.
    pub polygon_indices: usize,
    /// Triangles of the triangulated polygons (`polygon_indices - 2 polygons`).
    pub triangles: usize,
}

impl Counts {
    /// The length check of an emission: the lengths of positions, normals,
    /// params, polygon sizes, polygon indices, triangles and cells (`None`
    /// for an output not asked for), in that order, against these counts;
    /// the first short one is [`Error::BufferTooSmall`] with its element
    /// count.
    pub(crate) fn check_output_lengths(&self, lens: [Option<usize>; 7]) -> Result<(), Error> {
        let v = self.vertices;
        let need = [
            3 * v,
            3 * v,
            v,
            self.polygons,
            self.polygon_indices,
            3 * self.triangles,
            self.polygons,
        ];
        for (len, n) in lens.into_iter().zip(need) {
            if len.is_some_and(|l| l < n) {
                return Err(Error::BufferTooSmall { required: n });
            }
        }
        Ok(())
    }
}

/// What the marking of one slot found.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlotMark {
    /// Quadtree nodes (`1 + 4 * internal`).
    pub nodes: u32,
    /// Accepted cells.
    pub leaves: u32,
    /// Side midpoints of internal nodes on the slot boundary (sizes the
    /// slot sides' vertex lists).
    pub side_mids: u32,
    /// Bytes of the expansions of split corner cells (at extraordinary
    /// vertices) the tessellation keeps from marking to emission (per
    /// cell 248 bytes of points, plus 392 per split ring-region child).
    pub corner_bytes: u32,
    /// Deepest accepted cell.
    pub max_level: u32,
    /// Largest bound of an accepted cell (0 for uniform tessellations,
    /// which compute none).
    pub bound: f64,
    /// Largest bound / diagonal of an accepted cell (relative flatness).
    pub max_ratio: f64,
}

/// Facts about a tessellation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Deepest accepted cell.
    pub max_level: u32,
    /// Guaranteed bound of the whole output (largest cell bound; 0 for
    /// uniform tessellations, which compute none).
    pub bound: f64,
    /// Largest bound / diagonal (relative flatness, else 0).
    pub max_ratio: f64,
    /// Quadtree nodes of all slots.
    pub nodes: usize,
}

/// Caller buffers for [`Tessellation::emit`], each at least the size
/// [`Tessellation::counts`] gives.
pub struct Output<'o> {
    /// x y z per vertex (`3 * vertices`).
    pub positions: &'o mut [f64],
    /// Unit normal per vertex (`3 * vertices`), optional.
    pub normals: Option<&'o mut [f64]>,
    /// `(face, sub, u, v)` per vertex (`vertices`), optional.
    pub params: Option<&'o mut [Query]>,
    /// Vertex count of each polygon (`polygons`).
    pub polygon_sizes: &'o mut [u32],
    /// Vertex indices of all polygons, concatenated, counter-clockwise seen
    /// from outside (`polygon_indices`).
    pub polygon_indices: &'o mut [u32],
    /// Triangles, 3 indices each (`3 * triangles`), optional. Polygon p
    /// gives `size(p) - 2` consecutive triangles, in polygon order.
    pub triangles: Option<&'o mut [u32]>,
    /// The parameter cell of each polygon (`polygons`), optional.
    pub cells: Option<&'o mut [PolygonCell]>,
}

/// The dyadic parameter cell a polygon covers: `[i/2^level, (i+1)/2^level]
/// x [j/2^level, (j+1)/2^level]` of sub-face `sub` of base face `face`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct PolygonCell {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// Quadtree level.
    pub level: u32,
    /// Cell index along u.
    pub i: u32,
    /// Cell index along v.
    pub j: u32,
}
