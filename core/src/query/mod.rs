//! Certified queries on the limit surface: ray intersection (all hits or
//! the first), inside/outside of closed solids, closest points.
//!
//! Everything is built on exact evaluation and the guaranteed bounds over
//! dyadic parameter cells (\[CL-R ch. 7\]: Bezier nets by the convex hull
//! property, corner balls at extraordinary vertices from the eigen
//! expansion), walked depth first with an explicit stack
//! ([`QueryWork`], fixed size, no heap). Cell access goes through a small
//! sealed trait ([`QuerySurface`]: root cells, children, exact evaluation),
//! implemented for the smooth closed [`Evaluator`] and for the
//! [`FeatureEvaluator`] (creases, corners, semi-sharp edges, boundaries,
//! holes: its cells are bicubic pieces or convex hulls of control points,
//! `feature.rs`). Rays and closest points work on any of them, open
//! meshes included; [`inside`](fn@inside) and the slices need a closed solid
//! ([`Error::NotClosedSolid`] names the boundary edge, hole or
//! non-manifold part otherwise).
//!
//! * [`SlotIndex`] + [`Indexed`]: a box tree over the slots, built once
//!   into a caller slice; every query below accepts `Indexed` in place of
//!   the surface and then visits only the slots it can reach (the same
//!   answers, `index.rs`).
//! * [`ray_first`], [`ray_all`], [`ray_first_batch`]: see [`ray`] for the
//!   guarantee (no crossing missed; every hit within `tol`).
//! * [`inside`]: parity of certified transversal crossings.
//! * [`closest`](fn@closest), [`closest_batch`]: branch and bound to the global
//!   minimum distance, see [`closest`](mod@closest).
//! * [`slice_segment_count`], [`slice_layer`], [`slice_write`]: planar sections as closed,
//!   oriented polylines within Hausdorff `eps`, one layer at a time into
//!   caller buffers, see [`slice`](mod@slice); [`slice_band`] +
//!   [`band_layer`]: up to [`MAX_BAND`] layers of a [`PlaneStack`] in one
//!   walk (the same contours, the descent shared).
//!
//! Floating point: every tolerance holds for the computed outputs,
//! rounding included (`rounding.rs`: the rounding term `r = 4096 eps M` of
//! the model's and the query's coordinates widens every exclusion test, and
//! the walks run at `tol - 2 r`); a tolerance below `4 r` (`64 r` for
//! [`inside`](fn@inside)) or coordinates outside `2^-200..2^200` are
//! [`Error::CoordinateRange`]. Work: every query takes a cell budget
//! (`max_cells` in its options, default [`MAX_CELLS`]) and stops with
//! [`Error::WorkLimitExceeded`] past it (`docs/WORST_CASE.md`).
//!
//! ```
//! use ccss_core::mem::words_for;
//! use ccss_core::query::{ray_all, Hit, QueryWork, Ray, RayOptions};
//! use ccss_core::{BuildScratch, DVec3, Evaluator, MeshInput, TableSet, Topology};
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
//! let mut work = Box::new(QueryWork::ZERO);
//! let ray = Ray { origin: DVec3::new(0.1, 0.2, -5.0), dir: DVec3::Z };
//! let mut hits = [Hit::ZERO; 4];
//! let n = ray_all(&ev, &ray, &RayOptions::default(), &mut work, &mut hits)?;
//! assert_eq!(n, 2); // in through the bottom, out through the top
//! assert!(hits[0].t < hits[1].t);
//! # Ok(())
//! # }
//! ```
//!
//! ## Layer
//!
//! Layer 8: over `tessellate` (its cell quadtree), `bounds` (the rounding
//! term) and the layers below.

pub(crate) mod cell;
pub mod closest;
mod feature;
mod index;
mod inside;
mod krawczyk;
pub mod ray;
mod rounding;
pub mod slice;
mod slots;
mod taylor;

pub use cell::MAX_LEVEL;
pub use closest::{Closest, ClosestOptions};
pub use index::{IndexNode, Indexed, SlotIndex};
pub use ray::{Hit, HitKind, QueryWork, Ray, RayOptions, MAX_CELLS, MAX_HITS};
pub use slice::{
    band_layer, Contour, Plane, PlaneStack, SliceOptions, SliceSegment, SliceStats, MAX_BAND,
};

use crate::error::Error;
use crate::eval::{Evaluator, FeatureEvaluator};
use glam::DVec3;

/// A surface the queries accept: the smooth [`Evaluator`] (a closed
/// manifold mesh) or a [`FeatureEvaluator`] (see the module docs). Sealed.
pub trait QuerySurface: cell::CellSurface {}

impl QuerySurface for Evaluator<'_> {}
impl QuerySurface for FeatureEvaluator<'_, '_> {}
impl<S: QuerySurface + ?Sized> QuerySurface for Indexed<'_, S> {}

/// The first hit of `ray` with the limit surface of `ev` (smallest
/// `t >= t_min`), or `None` if it misses (see [`ray`] for the guarantee).
pub fn ray_first<S: QuerySurface + ?Sized>(
    ev: &S,
    ray: &Ray,
    opts: &RayOptions,
    work: &mut QueryWork,
) -> Result<Option<Hit>, Error> {
    ray::first_hit(ev, ray, opts, work)
}

/// All hits of `ray`, sorted by `t`, written to `out`; returns their
/// number. An `out` shorter than that (an empty one is the size query) is
/// [`Error::BufferTooSmall`] with the exact count and nothing written.
pub fn ray_all<S: QuerySurface + ?Sized>(
    ev: &S,
    ray: &Ray,
    opts: &RayOptions,
    work: &mut QueryWork,
    out: &mut [Hit],
) -> Result<usize, Error> {
    ray::all_hits(ev, ray, opts, work, out)
}

/// [`ray_first`] for many rays: `out[i]` is ray `i`'s first hit.
/// `out.len() < rays.len()` is [`Error::BufferTooSmall`]; the first failing
/// ray stops the batch with its index.
pub fn ray_first_batch<S: QuerySurface + ?Sized>(
    ev: &S,
    rays: &[Ray],
    opts: &RayOptions,
    work: &mut QueryWork,
    out: &mut [Option<Hit>],
) -> Result<(), (usize, Error)> {
    if out.len() < rays.len() {
        return Err((
            0,
            Error::BufferTooSmall {
                required: rays.len(),
            },
        ));
    }
    for (i, (r, o)) in rays.iter().zip(out.iter_mut()).enumerate() {
        *o = ray::first_hit(ev, r, opts, work).map_err(|e| (i, e))?;
    }
    Ok(())
}

/// Whether `p` lies inside the closed solid bounded by the limit surface
/// of `ev`: the parity of the certified transversal crossings of a ray from
/// `p` (tolerance `tol`, model units). A point within `tol` of the surface
/// (or with every ray tried degenerate) is an error; so is a surface that
/// bounds no solid ([`Error::NotClosedSolid`]).
pub fn inside<S: QuerySurface + ?Sized>(
    ev: &S,
    p: DVec3,
    tol: f64,
    work: &mut QueryWork,
) -> Result<bool, Error> {
    ev.check_solid()?;
    inside::inside(ev, p, tol, work)
}

/// The closest point of the limit surface of `ev` to `p` (global minimum,
/// within `opts.tol`; see [`closest`](mod@closest)).
pub fn closest<S: QuerySurface + ?Sized>(
    ev: &S,
    p: DVec3,
    opts: &ClosestOptions,
    work: &mut QueryWork,
) -> Result<Closest, Error> {
    closest::closest_point(ev, p, opts, work)
}

/// [`closest`](fn@closest) for many points: `out[i]` for `points[i]`.
pub fn closest_batch<S: QuerySurface + ?Sized>(
    ev: &S,
    points: &[DVec3],
    opts: &ClosestOptions,
    work: &mut QueryWork,
    out: &mut [Closest],
) -> Result<(), (usize, Error)> {
    if out.len() < points.len() {
        return Err((
            0,
            Error::BufferTooSmall {
                required: points.len(),
            },
        ));
    }
    for (i, (p, o)) in points.iter().zip(out.iter_mut()).enumerate() {
        *o = closest::closest_point(ev, *p, opts, work).map_err(|e| (i, e))?;
    }
    Ok(())
}

/// Scratch length [`slice_layer`] needs for the section of `ev` by `plane`
/// (the number of section segments and extraordinary-vertex nodes).
pub fn slice_segment_count<S: QuerySurface + ?Sized>(
    ev: &S,
    plane: &Plane,
    opts: &SliceOptions,
    work: &mut QueryWork,
) -> Result<usize, Error> {
    ev.check_solid()?;
    slice::segment_count(ev, plane, opts, work)
}

/// The section of the solid bounded by `ev` with `plane`, within Hausdorff
/// distance `opts.eps` of the exact section (see [`slice`](mod@slice)), chained into
/// closed contours in the scratch `segs` (at least
/// [`slice_segment_count`] entries, else [`Error::BufferTooSmall`] with
/// that count). The returned [`SliceStats`] hold the exact numbers of
/// points and contours; [`slice_write`] writes them.
pub fn slice_layer<S: QuerySurface + ?Sized>(
    ev: &S,
    plane: &Plane,
    opts: &SliceOptions,
    work: &mut QueryWork,
    segs: &mut [SliceSegment],
) -> Result<SliceStats, Error> {
    ev.check_solid()?;
    slice::slice_layer(ev, plane, opts, work, segs)
}

/// The layers `first .. first + stats.len()` (1 to [`MAX_BAND`]) of the
/// plane family `stack` in one walk of the cells, for slicing a whole
/// stack in bands: the layers share the descent from the root cells down
/// to where their sections part, and each layer's contours are exactly
/// those of [`slice_layer`] on `stack.layer(k)` (see
/// [`slice`](mod@slice)). `segs` is the scratch of all the band's layers
/// (an empty one is the size query: [`Error::BufferTooSmall`] with the
/// exact count, as is any shorter one); `stats[i]` receives layer
/// `first + i`'s numbers and [`band_layer`]`(segs, stats, i)` its part
/// of the scratch for [`slice_write`]. Returns the scratch entries used.
///
/// Buffer size against work: a band of `B` layers needs the segments of
/// `B` layers at once (about `B` times a layer's), and a stack of `L`
/// layers takes `ceil(L / B)` walks from the root cells.
pub fn slice_band<S: QuerySurface + ?Sized>(
    ev: &S,
    stack: &PlaneStack,
    first: usize,
    opts: &SliceOptions,
    work: &mut QueryWork,
    segs: &mut [SliceSegment],
    stats: &mut [SliceStats],
) -> Result<usize, Error> {
    ev.check_solid()?;
    slice::slice_band(ev, stack, first, opts, work, segs, stats)
}

/// Writes the contours [`slice_layer`] chained (`segs` = its scratch cut
/// to `stats.segments` entries): points in the plane's frame
/// ([`Plane::frame`]) and the contours (outer counter-clockwise seen from
/// `+n`, holes clockwise). Short buffers are [`Error::BufferTooSmall`]
/// with the exact count (points first), nothing written. Returns the
/// numbers written.
pub fn slice_write(
    segs: &mut [SliceSegment],
    points: &mut [[f64; 2]],
    contours: &mut [Contour],
) -> Result<(usize, usize), Error> {
    let cap = contours.len();
    slice::write_contours(segs, points, cap, |i, c| contours[i] = c)
}
