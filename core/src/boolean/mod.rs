//! Booleans (union, intersection, difference) of two closed solids bounded
//! by limit surfaces, with an error bound (issue #25; \[CL-R ch. 6\] for
//! the voxel-based method this replaces).
//!
//! ## Method
//!
//! 1. Each solid's limit surface is tessellated with a guaranteed bound
//!    `t` ([`crate::tessellate::Tessellation`], absolute flatness): a
//!    closed, consistently oriented triangle mesh whose vertices are exact
//!    limit points and whose every point is within `t` of the surface and
//!    vice versa. This module takes the two triangle meshes
//!    ([`SolidMesh`]); the caller picks `t` with [`tessellation_tolerance`].
//! 2. **Corefinement with exact predicates** ([`Boolean::build`]): every
//!    pair of crossing triangles is found through a bounding-volume
//!    hierarchy over B and decided by the exact `orient3d`
//!    (`predicates.rs`: static filter, expansion-arithmetic fallback). Each
//!    end of a crossing segment is the point where one triangle's **edge
//!    pierces** the other triangle and is named by (edge, triangle), not
//!    by its coordinates (which are computed in `f64` from the predicate's
//!    determinants). Equal names are the same vertex on both sides of the
//!    edge and in both solids, so the output is crack-free by
//!    construction (the paper's voxel-centre vertices, which break an
//!    `eps` guarantee, are not used).
//! 3. Each cut triangle is split by its chains of segments into polygons
//!    (`pieces.rs`), each classified inside/outside the other solid by the
//!    other triangle's normal at a chain segment on its boundary, and
//!    triangulated by ear clipping without new vertices. Uncut triangles
//!    take the class of their neighbours across uncut edges (flooding);
//!    components the other surface does not cross are classified by an
//!    exact ray parity.
//! 4. **Keep rules**: union keeps A outside B and B outside A;
//!    intersection keeps A inside B and B inside A; difference `A - B`
//!    keeps A outside B and B inside A, the latter with reversed
//!    orientation. The output is closed and consistently oriented
//!    (outward normals, counter-clockwise seen from outside); disjoint
//!    solids give both (union), nothing (intersection) or A (difference).
//!    The rules read every input's normals as outward: a mesh oriented
//!    inward (clockwise seen from outside, negative enclosed volume)
//!    stands for the complement of its solid. `ccss boolean` orients its
//!    inputs first (it reverses an inside-out tessellation, with a note);
//!    other callers check the sign of the enclosed volume themselves.
//!
//! Several crossings of one triangle (several chains) are handled by
//! splitting polygons chain after chain. Not handled, and reported as
//! [`Error::DegenerateContact`] naming both triangles: a tessellation
//! vertex exactly on the other's triangle plane, an edge through an edge,
//! a closed intersection loop inside one triangle, more than
//! [`MAX_CROSSINGS`] crossings of one triangle. A smaller tolerance (or a
//! shift far below it) resolves these.
//!
//! ## The error bound
//!
//! **Wedge lemma** (planar model of the neighbourhood of the curve): let
//! two half-spaces with outward unit normals `n_A`, `n_B` be replaced by
//! half-spaces whose planes are moved by at most `t`. The boundary of the
//! union, intersection or difference changes by at most
//! `t / cos(gamma / 2)` in Hausdorff distance, `gamma` the angle between
//! the outward normals of the two kept sheets as they appear in the result
//! (`n_A, n_B` for union and intersection, `n_A, -n_B` for difference):
//! the result is (or its complement is) a convex wedge of opening
//! `pi - gamma`, whose apex moves by `t / sin((pi - gamma) / 2)` and whose
//! faces by `t`. Away from the curve (farther than `t` from the other
//! surface) the kept sheet is within `t` of the exact result's boundary.
//! So with **amplification** `a = max 1 / cos(gamma / 2)` over the
//! crossing pairs, the output's Hausdorff distance to the exact boundary is
//! at most `a t` to first order in `t` (curvature terms are second order
//! in the cell size). [`Boolean::stats`] reports `a` measured with the
//! facet normals of the crossing triangle pairs (a posteriori, at the
//! crossings only; not certified between them: that would need normal
//! cones over cell pairs, not done); the caller tessellates with
//! `t = eps / a` (after a first pass at `eps / 2`), and
//! [`Options::max_amplification`] turns a near-tangential contact into
//! [`Error::NearTangential`] naming the triangles. The tests check the
//! resulting two-sided distance against dense exact samples
//! (`tests/tests/boolean_solids.rs`) and the lemma itself on polyhedra
//! (`tests.rs`, `wedge_lemma_on_moved_boxes`: both boxes' faces moved out
//! by `t`; union and intersection move by exactly `amplification x t`, so
//! the bound is tight).
//!
//! **Tolerances that vary along the surfaces** (local refinement, see
//! [`crate::tessellate::ToleranceField`]): in the planar model each sheet
//! is moved by at most its own bound, and the result's boundary by at
//! most [`crossing_bound`]`(a, t_A, t_B)` (`wedge.rs`: the two
//! displacements kept apart; at most `max(t_A, t_B) / cos(gamma / 2)`,
//! with equality when `t_A = t_B`, and down to `max(t_A, t_B)` when one
//! sheet is much closer than the other), `t_A`, `t_B` the bounds of the
//! two crossing triangles; away from the other surface (farther than
//! `t_A + t_B`) a kept triangle crosses nothing, keeps the class of the
//! exact surface (the straight homotopy from the tessellation to the
//! surface does not pass through the point) and is within its own bound.
//! So with per-triangle bounds the output's error is at most the largest
//! of every triangle's bound and `crossing_bound(a_c, t_A, t_B)` over the
//! crossings ([`Boolean::crossings`] lists them with their
//! amplifications), again to first order. The CLI refines the cells near
//! the other solid and within a previous crossing's reach (that
//! crossing's own bound `+ 2 eps`) to `eps / (1.05 a s)`, `a` the
//! effective amplification (`crossing_bound / max(t_A, t_B)`) of the
//! previous pass's crossings nearby, and keeps about `eps` elsewhere; it
//! accepts a pass only when the bound above is at most `eps`.
//!
//! **A-posteriori bounds of the crossing triangles** ([`triangle_bound`],
//! proof in `sharp.rs`): `t_A`, `t_B` above may be any proven bounds of
//! `sup |S(x) - T(x)|` over the two crossing triangles, not only the
//! tolerance their cells were accepted at. The cell's a-priori bound (the
//! second-derivative bound of the whole cell, `M / 3`) is typically 3 times
//! the actual deviation; [`triangle_bound`] evaluates the surface at the
//! points of a grid of `k / 4` barycentric coordinates of the triangle and
//! adds the interpolation term of the grid's triangles (`1/16` of the
//! a-priori bound), a bound still proven for every point of the triangle
//! (about 0.34 of the a-priori bound on average on righthanded, `sharp.rs`
//! tests); where that is not small enough, a second try on the grid of
//! `k / 8` ([`SHARP_SAMPLES_FINE`]: 45 points, `1/64` of the a-priori
//! bound; 0.30 on average). Since the wedge lemma takes one crossing's two triangles, only
//! the crossing triangles need it: the CLI accepts a pass when every
//! triangle's a-priori bound is at most `eps` and every crossing's
//! `crossing_bound(a_c, t_A, t_B)` with these bounds is, so steep crossings need a
//! 3 times coarser band instead of `eps / a` (on the hands of
//! `bench/boolean_bench.sh`, difference: 20,016 -> 14,726 triangles at the
//! same measured error, `docs/bench-log.md` 2026-11-27 `booldiff3`).
//!
//! The same bounds certify the triangles away from the curve: with every
//! triangle's a-posteriori bound at most `eps`, the tessellation's own
//! error is too, whatever tolerance made it. `ccss boolean` tessellates
//! smooth meshes at `2.5 eps` where that certifies and splits the cells
//! whose triangles do not (on the torus-cube pair of the benchmark 17,556
//! -> 6,090 union triangles; [`triangle_bound_in`] takes the cell bound
//! once per cell).
//!
//! Not covered: where a **sharp crease** of one surface (a feature mesh's
//! crease, or a box edge) crosses the other surface, three planes meet and
//! the displacement can exceed the two-plane bound (the test leaves those
//! corners out); the edges of a tessellation of a smooth surface are nearly
//! flat, where the two-plane bound applies.
//!
//! ## Parameter space
//!
//! [`Boolean::emit_uv`] gives every output triangle its (solid, base face,
//! sub-face, `(u, v)` of its three vertices), so a caller can re-evaluate
//! the result on the exact surfaces (trimmed patches in parameter space).
//! The caller passes one [`PatchTriangle`] per input triangle; for a
//! tessellation, [`patch_triangles`] makes them from its `params` and
//! polygon cells. A tessellation triangle never spans a sub-face border:
//! it lies in one polygon, i.e. one dyadic cell of one sub-face, and all
//! three `(u, v)` are given in that sub-face (a shared border vertex that
//! the tessellation wrote in a neighbour's parameters is placed on the
//! cell's border side by a nearest-point search, see `uv.rs`). Each output
//! vertex maps by its barycentric coordinates in its source triangle
//! (kept tessellation vertices exactly, curve points from their position).
//! The tessellation's bound is parametric (`|S(x) - T(x)| <= t` for the
//! piecewise-linear interpolant `T` over the cell's parameters), so the
//! surface point at a reported `(u, v)` lies within `t <= ` the Boolean's
//! bound of the output vertex, up to rounding; the tests re-evaluate every
//! output vertex (`tests/tests/boolean_solids.rs`, `cli/tests/boolean.rs`).
//!
//! ## Memory
//!
//! Everything lives in one caller block of `u64` words.
//! [`Boolean::required_bytes_base`] is the part known from the sizes (edge
//! twins, the hierarchy, classes, vertex maps); the crossings need more:
//! [`Boolean::build`] counts them first and returns
//! `BufferTooSmall { required }` with the exact total, so a second build
//! with that block succeeds. Output sizes are [`Boolean::counts`];
//! [`Boolean::emit`] writes into caller buffers of at least those sizes.
//! More than two operands: a sequence of binary operations, the result of
//! one (a closed triangle mesh) being an input of the next; two blocks at
//! a time.

mod adjacency;
mod bvh;
mod engine;
mod pairs;
mod pieces;
pub mod predicates;
mod sharp;
mod uv;
mod wedge;

pub use engine::Boolean;
pub use sharp::{triangle_bound, triangle_bound_in, SHARP_SAMPLES, SHARP_SAMPLES_FINE};
pub use uv::{patch_triangle, patch_triangles, TessellationUv};
pub use wedge::crossing_bound;

use crate::error::Error;
use glam::DVec3;

/// Largest number of crossing segments inside one triangle.
pub const MAX_CROSSINGS: usize = pieces::MAX_SEGS;

/// The operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `A ∪ B`.
    Union,
    /// `A ∩ B`.
    Intersection,
    /// `A − B`.
    Difference,
}

/// A closed triangle mesh (a tessellation), counter-clockwise seen from
/// outside.
#[derive(Clone, Copy, Debug)]
pub struct SolidMesh<'a> {
    /// `x y z` per vertex.
    pub positions: &'a [f64],
    /// Three vertex indices per triangle.
    pub triangles: &'a [u32],
}

impl SolidMesh<'_> {
    fn point(&self, v: u32) -> DVec3 {
        let v = v as usize;
        DVec3::from_slice(&self.positions[3 * v..3 * v + 3])
    }
    fn tri(&self, t: usize) -> [DVec3; 3] {
        let p = |k: usize| self.point(self.triangles[3 * t + k]);
        [p(0), p(1), p(2)]
    }
    fn normal(&self, t: usize) -> DVec3 {
        let [a, b, c] = self.tri(t);
        (b - a).cross(c - a)
    }
}

/// Options of [`Boolean::build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Largest accepted amplification `1 / cos(gamma / 2)` (see the module
    /// docs); a crossing with more is [`Error::NearTangential`]. Default
    /// [`Options::DEFAULT_MAX_AMPLIFICATION`] (`gamma` up to about 178.9°).
    pub max_amplification: f64,
}

impl Options {
    /// Default of [`Options::max_amplification`].
    pub const DEFAULT_MAX_AMPLIFICATION: f64 = 100.0;
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_amplification: Self::DEFAULT_MAX_AMPLIFICATION,
        }
    }
}

/// Output sizes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Output vertices (kept tessellation vertices of A, of B, then the
    /// curve points).
    pub vertices: usize,
    /// Output triangles.
    pub triangles: usize,
    /// Closed loops of the intersection curve.
    pub curve_loops: usize,
    /// Points of all loops (each loop lists each point once; it closes
    /// from the last back to the first).
    pub curve_points: usize,
    /// Crossing triangle pairs (= curve segments).
    pub crossing_pairs: usize,
}

/// What the crossings measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// `max 1 / cos(gamma / 2)` over the crossing pairs (1 when none).
    pub amplification: f64,
    /// The triangles (of A, of B) where it is reached.
    pub worst: [u32; 2],
}

/// One crossing triangle pair ([`Boolean::crossings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Triangle of A.
    pub triangle_a: u32,
    /// Triangle of B.
    pub triangle_b: u32,
    /// `1 / cos(gamma / 2)` of this pair (module docs).
    pub amplification: f64,
    /// The ends of its curve segment.
    pub ends: [DVec3; 2],
}

/// Where an output triangle comes from: triangle `triangle` of solid
/// `solid` (0 = A, 1 = B) of the input meshes (its parameter-space
/// triangle: [`Boolean::emit_uv`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct FaceSource {
    /// 0 = A, 1 = B.
    pub solid: u32,
    /// Triangle of that solid's input mesh.
    pub triangle: u32,
}

/// A triangle of an input mesh in the parameter space of the patch it
/// was tessellated from: base face `face`, sub-face `sub`, and the
/// `(u, v)` of its three vertices (in the triangle's vertex order) in that
/// sub-face's domain `[0, 1]^2`. Input of [`Boolean::emit_uv`], one per
/// input triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct PatchTriangle {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// `u0 v0 u1 v1 u2 v2`.
    pub uv: [f64; 6],
}

/// The parameter-space provenance of an output triangle: solid `solid`
/// (0 = A, 1 = B), the `(face, sub)` of its source triangle, and the
/// `(u, v)` of its three vertices (in the output triangle's vertex order),
/// mapped by their barycentric coordinates in the source triangle (exact
/// for the inscribed mesh, whose triangles are linear in `(u, v)`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct UvTriangle {
    /// 0 = A, 1 = B.
    pub solid: u32,
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub sub: u32,
    /// Always 0 (explicit padding).
    pub reserved: u32,
    /// `u0 v0 u1 v1 u2 v2`.
    pub uv: [f64; 6],
}

/// Caller buffers of [`Boolean::emit`].
pub struct Output<'o> {
    /// `x y z` per vertex (`3 vertices`).
    pub positions: &'o mut [f64],
    /// Three indices per triangle (`3 triangles`).
    pub triangles: &'o mut [u32],
    /// Source of each triangle (`triangles`), optional.
    pub sources: Option<&'o mut [FaceSource]>,
    /// Points per curve loop (`curve_loops`).
    pub curve_sizes: &'o mut [u32],
    /// Output vertex indices of the loops, concatenated (`curve_points`).
    pub curve_indices: &'o mut [u32],
}

/// The tessellation tolerance for a target `eps` and an amplification `a`
/// (`eps / a`); `eps` must be positive and finite.
pub fn tessellation_tolerance(eps: f64, amplification: f64) -> Result<f64, Error> {
    if !(eps.is_finite() && eps > 0.0) {
        return Err(Error::InvalidArgument(
            "boolean: eps must be positive and finite",
        ));
    }
    Ok(eps / amplification.max(1.0))
}

#[cfg(test)]
mod tests;
