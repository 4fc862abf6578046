//! The unified subdivision scheme of Maillot & Stam, "A unified subdivision
//! scheme for polygonal modeling" (\[MS01\]): level of
//! detail that does not shrink (push-back `a`, rounding `b`), any number `d`
//! of pieces per edge (faces grow by `d²` per step), odd degree `p`, and a
//! Catmull-Clark correction `g` at extraordinary vertices. Allocation-free:
//! every result goes to caller memory with an exact size query.
//!
//! * [`refine_curve`] — closed and open polylines (MS §3.1, eqs. (1)–(7)).
//! * [`refine_unified`] — one step on a closed mesh of triangles, quads and
//!   n-gons (MS §3.2–3.4, eqs. (8)–(24)); [`unified_bytes`] sizes it,
//!   [`unified_counts`] gives the refined counts in closed form.
//! * [`refine_unified_levels`] — several steps, per-level parameters.
//!
//! ```
//! use ccss_core::unified::{refine_unified, unified_bytes, UnifiedParams};
//! use ccss_core::mem::words_for;
//! use ccss_core::{MeshInput, Topology};
//! # fn main() -> Result<(), ccss_core::Error> {
//! let p = [-1.,-1.,-1., 1.,-1.,-1., 1.,1.,-1., -1.,1.,-1., -1.,-1.,1., 1.,-1.,1., 1.,1.,1., -1.,1.,1.];
//! let sizes = [4u32; 6];
//! let idx = [0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7];
//! let mesh = MeshInput { positions: &p, face_sizes: &sizes, indices: &idx };
//! let mut tmem = vec![0u64; words_for(Topology::required_bytes(8, &sizes))];
//! let topo = Topology::build(mesh, &mut tmem)?;
//! // Three pieces per edge, half push-back, half rounding (the paper's tool).
//! let params = UnifiedParams::default().with_d(3);
//! let mut mem = vec![0u64; words_for(unified_bytes(&topo, &params)?)];
//! let lod = refine_unified(&topo, &params, &mut mem)?;
//! assert_eq!(lod.mesh.face_sizes.len(), 6 * 9); // d^2 faces per quad
//! # Ok(())
//! # }
//! ```
//!
//! With `a = b = 0`, `g = 1`, `d = 2`, `p = 3` and triangles as polygons
//! ([`UnifiedParams::CATMULL_CLARK`]) a step is one Catmull-Clark step on
//! any polygon mesh, with the numbering of [`crate::mesh::refine`]. With `a = 0`
//! the regular part of a quad mesh is refined as the uniform B-spline of
//! degree `p` (bicubic for `p = 3`) for every `d`.
//!
//! # Decisions where the paper is silent (\[MS01\])
//!
//! * **Triangle weights** (eq. (9) sums to 3/4 on triangles): the smoothing
//!   is the k-ring average of eqs. (22)–(24) for every `d`, which for
//!   `d = 2` is eq. (9) on quads and eq. (9) normalised by its weight sum on
//!   triangles ([`smooth`]).
//! * **n-gons for `d > 2`**: sectors around the centroid, concentric rings
//!   of quads; even `d` leaves a centroid vertex of valence `n`, odd `d` a
//!   central `n`-gon of edge length `1/d` ([`layout`]). This is
//!   Catmull-Clark's split for `d = 2` and the `d x d` grid for quads.
//! * **D(F) for non-quads**: eq. (17), the average of the corners' `D`;
//!   inside each sector `D` is bilinear ([`interp`]).
//! * **Zero-length D vectors** in (18)–(19): renormalisation is skipped when
//!   `|L(D)| <= 1e-12 L(|D|)` ([`interp`]).
//! * **Catmull-Clark weights for general `d`**: the bilinear interpolant of
//!   the step-1 table, `w = (1-2s)(1-2t)` near the vertex ([`correction`]).
//!   Applied at old vertices all of whose faces use the polygon layout.
//! * **Catmull-Clark on non-quads** (our extension): simple averaging misses
//!   Catmull-Clark at edge points of non-quad faces by `(c - q)/8`; the
//!   correction adds it, so `g = 1`, `d = 2` is Catmull-Clark on every
//!   polygon mesh ([`correction`]).
//! * **Order within a pass** for `p > 3`: smoothing, correction, push-back,
//!   repeated ([`surface`]).
//! * **Triangles** are split into `d²` triangles by default (the paper's
//!   choice); [`TriangleRule::Polygon`] treats them as polygons instead.
//! * **Curve ends**: odd reflection, end points fixed ([`curve`]).
//!
//! # How it is computed
//!
//! The k-ring sets are found by breadth-first search ([`smooth`]), `O(d²)`
//! work per value. Two exact shortcuts give the same sets with `O(1)` work:
//! for `d = 2` the first pass is fused with the linear subdivision, as a
//! Catmull-Clark step computes its points; for `3 <= d <= 64` every quad
//! whose neighbourhood is a grid uses separable box sums on a local chart,
//! and in the first pass the `d`-ary B-spline weights of its 4 x 4 input
//! vertices ([`fast`]). The search handles what is left (near
//! extraordinary vertices, triangles, n-gons).
//!
//! # Layer
//!
//! Layer 7 by position (see the crate docs), but it imports only `config`,
//! `error`, `mem` and `mesh`: it could sit right above `mesh`.

mod binary;
pub mod correction;
pub mod curve;
mod faces;
pub mod fast;
mod general;
pub mod interp;
pub mod layout;
mod levels;
mod params;
pub mod smooth;
pub mod surface;

pub use curve::{curve_buffer_len, curve_len, refine_curve};
pub use layout::{unified_counts, UnifiedCounts};
pub use levels::{refine_unified_levels, unified_levels_bytes, UnifiedLevels, MAX_LEVELS};
pub use params::{TriangleRule, UnifiedParams, MAX_D, MAX_P};
pub use surface::{refine_unified, unified_bytes, UnifiedRefined};
