//! Certified ray intersection: every crossing of the ray `o + t d`
//! (`t >= t_min`) with the limit surface, or the first one.
//!
//! The walk is depth first over the dyadic cells of every slot
//! (`cell.rs`). A cell is dropped only when it is proven to hold no
//! crossing: its guaranteed bound (Bezier net hull, the corner ball of an
//! extraordinary vertex, \[CL-R ch. 7\], or on feature meshes the box and
//! ball of a hull cell's control points, \[OSD\]) misses the ray or lies behind
//! `t_min` (or, for the first hit, beyond the best hit so far plus the
//! tolerance), or the Krawczyk operator on the net projected along the ray
//! excludes a zero (`krawczyk.rs`). The projection is
//! `F(s, t) = (e1 . (S - o), e2 . (S - o))` with `e1, e2` orthonormal and
//! perpendicular to `d`: its zeros are the crossings.
//!
//! A cell where the Krawczyk contraction holds (`rho < 1`: at most one
//! crossing, a fixed orientation) is narrowed to a parameter box of side
//! `tol / (4 V)`, `V` the net's bound of `|S_s| + |S_t|`; its centre is
//! evaluated exactly and reported as a [`HitKind::Transversal`] hit when it
//! lies within `tol / 2` of the ray (a crossing in the box would put it
//! within `tol / 4`, so a farther centre proves there is none). A cell
//! whose whole box is at most `tol / 4` across (or a corner ball of radius
//! at most `tol / 4`, or a hull cell at most `tol / 4` across) is reported
//! as a [`HitKind::Tangent`] hit without splitting further. Hits within `tol / 2` of each other along the ray
//! (with the same orientation) are one hit (a crossing on the common edge
//! of two cells is found in both).
//!
//! Rounding (`rounding.rs`): every exclusion test above widens its bound
//! by the rounding term `r` of the model and the ray origin, and the walk
//! runs at `tol - 2 r`; so the guarantee below holds for the computed hits,
//! rounding included. `tol < 4 r` is [`Error::CoordinateRange`].
//!
//! Work: at most [`RayOptions::max_cells`] cells (each one split: four
//! Bezier nets by de Casteljau, or four feature cells), plus one root per
//! slot; more is [`Error::WorkLimitExceeded`].
//!
//! The guarantee, with `tol` in model units:
//!
//! * **no crossing missed**: every exact crossing `o + t* d` has a reported
//!   hit with `|t - t*| |d| <= tol`;
//! * **every hit is real to within tol**: its point is the exact limit
//!   point `S(face, sub, u, v)` (evaluated) and lies within `tol` of the
//!   ray, at `t = d . (p - o) / |d|^2`.

use super::cell::{Bound, Cell, CellStack, CellSurface, MAX_LEVEL};
use super::index::{self, Visit};
use super::krawczyk::{solve, Solve};
use crate::error::Error;
use glam::DVec3;

/// A ray `origin + t * dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Direction (need not be unit; must be finite and non-zero).
    pub dir: DVec3,
}

/// How a hit was certified.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum HitKind {
    /// The ray crosses the surface transversally: the cell around the hit
    /// holds at most one crossing and the orientation `sign(d . n)` is
    /// fixed there.
    Transversal = 0,
    /// The surface comes within `tol` of the ray here (grazing, tangent,
    /// or through an extraordinary vertex): no uniqueness is claimed.
    Tangent = 1,
}

/// One hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter: the hit point is `origin + t * dir` (within `tol`).
    pub t: f64,
    /// Base face.
    pub face: u32,
    /// Sub-face.
    pub sub: u32,
    /// Sub-face parameter u.
    pub u: f64,
    /// Sub-face parameter v.
    pub v: f64,
    /// The exact limit point `S(face, sub, u, v)`.
    pub point: DVec3,
    /// Unit normal there (zero where degenerate, e.g. at an extraordinary
    /// vertex reached from a corner ball).
    pub normal: DVec3,
    /// How it was certified.
    pub kind: HitKind,
}

impl Hit {
    /// A zero hit (buffer filler).
    pub const ZERO: Hit = Hit {
        t: 0.0,
        face: 0,
        sub: 0,
        u: 0.0,
        v: 0.0,
        point: DVec3::ZERO,
        normal: DVec3::ZERO,
        kind: HitKind::Tangent,
    };
}

/// Options of the ray queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayOptions {
    /// Tolerance in model units (> 0): see the module docs. Default 1e-9.
    pub tol: f64,
    /// Hits with `t < t_min` are not reported. Default 0.
    pub t_min: f64,
    /// Work budget: cells one query may visit before it stops with
    /// [`Error::WorkLimitExceeded`] (a ray running inside the surface would
    /// otherwise split for ever). Default [`MAX_CELLS`].
    pub max_cells: u64,
}

impl Default for RayOptions {
    fn default() -> Self {
        RayOptions {
            tol: 1e-9,
            t_min: 0.0,
            max_cells: MAX_CELLS,
        }
    }
}

/// Hits one ray query keeps (before they are copied out).
pub const MAX_HITS: usize = 1024;

/// Default work budget of one query ([`RayOptions::max_cells`],
/// [`super::ClosestOptions::max_cells`], [`super::SliceOptions::max_cells`]):
/// `2^22` cells, a few seconds at most (`docs/WORST_CASE.md`).
pub const MAX_CELLS: u64 = 1 << 22;

/// Fixed-size work memory of the queries (box it: about 90 KB).
pub struct QueryWork {
    pub(crate) stack: CellStack,
    pub(crate) hits: [Hit; MAX_HITS],
    pub(crate) nhits: usize,
}

impl QueryWork {
    /// Empty work memory.
    pub const ZERO: QueryWork = QueryWork {
        stack: CellStack::ZERO,
        hits: [Hit::ZERO; MAX_HITS],
        nhits: 0,
    };

    /// The hits of the last ray query, sorted by `t` (also when its output
    /// buffer was too small: a caller can copy them from here instead of
    /// casting the ray again).
    pub fn last_hits(&self) -> &[Hit] {
        &self.hits[..self.nhits.min(MAX_HITS)]
    }
}

/// The ray in its own frame: unit direction and two unit normals.
struct Frame {
    o: DVec3,
    d: DVec3,
    len: f64,
    e1: DVec3,
    e2: DVec3,
    tol: f64,
    /// `|o|_inf`, for rounding margins.
    mag: f64,
    /// Rounding term of the model and the origin (`rounding.rs`).
    r: f64,
}

impl Frame {
    fn new<S: CellSurface + ?Sized>(surf: &S, ray: &Ray, tol: f64) -> Result<Frame, Error> {
        if !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return Err(Error::InvalidArgument("ray origin or direction not finite"));
        }
        // Length without underflow or overflow of the squares.
        let dm = ray.dir.abs().max_element();
        let len = if dm > 0.0 {
            (ray.dir / dm).length() * dm
        } else {
            0.0
        };
        if !(len > 0.0 && len.is_finite()) {
            return Err(Error::InvalidArgument("ray direction is zero"));
        }
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(Error::InvalidArgument("tolerance must be positive"));
        }
        let mag = ray.origin.abs().max_element();
        let r = super::rounding::term(surf, mag)?;
        let tol = super::rounding::inner(tol, r)?;
        let d = ray.dir / len;
        let e1 = d.any_orthonormal_vector();
        let e2 = d.cross(e1);
        Ok(Frame {
            o: ray.origin,
            d,
            len,
            e1,
            e2,
            tol,
            mag,
            r,
        })
    }

    /// Distance along the unit direction, and distance from the ray line.
    #[inline]
    fn locate(&self, p: DVec3) -> (f64, f64) {
        let r = p - self.o;
        let w = r.dot(self.d);
        (w, (r - w * self.d).length())
    }
}

/// The part of the ray's line inside the box `[lo, hi]` grown by `slack`,
/// as unit-direction distances narrowed from `(t0, t1)`; `None` when the
/// line misses the box along an axis it runs parallel to (an empty part
/// is `t0 > t1`).
fn slab(
    f: &Frame,
    lo: DVec3,
    hi: DVec3,
    slack: f64,
    (mut t0, mut t1): (f64, f64),
) -> Option<(f64, f64)> {
    for a in 0..3 {
        let (l, h) = (lo[a] - slack, hi[a] + slack);
        if f.d[a] == 0.0 {
            if f.o[a] < l || f.o[a] > h {
                return None;
            }
            continue;
        }
        let (x, y) = ((l - f.o[a]) / f.d[a], (h - f.o[a]) / f.d[a]);
        t0 = t0.max(x.min(y));
        t1 = t1.min(x.max(y));
    }
    Some((t0, t1))
}

/// Whether the ray's line meets the box `[lo, hi]` grown by `slack`
/// (slab test on the whole line: the along-ray range is checked apart).
fn ray_meets_box(f: &Frame, lo: DVec3, hi: DVec3, slack: f64) -> bool {
    slab(f, lo, hi, slack, (f64::NEG_INFINITY, f64::INFINITY))
        .is_some_and(|(t0, t1)| t0 <= t1 + slack)
}

/// The index's question (`index.rs`) for the ray: the entry distance
/// along the unit direction into the box `[lo, hi]` grown by the
/// tolerance, the rounding term and a relative margin, or `None` when the
/// grown box misses the ray's part `[w_min, w_max]`. Every hit the walk
/// reports is an exact limit point of the slot within `tol` of the ray at
/// such a distance, so a slot whose box gives `None` would report none.
fn box_key(f: &Frame, lo: DVec3, hi: DVec3, w_min: f64, w_max: f64) -> Option<f64> {
    let slack = f.tol + f.r + 1e-14 * (f.mag + lo.abs().max(hi.abs()).max_element());
    let (t0, t1) = slab(f, lo, hi, slack, (w_min - slack, w_max + slack))?;
    (t0 <= t1).then_some(t0)
}

/// Where hits go: all (deduplicated), or only the first.
struct Sink<'w> {
    hits: &'w mut [Hit; MAX_HITS],
    n: usize,
    first_only: bool,
    tol_t: f64,
}

impl Sink<'_> {
    /// Largest unit-direction distance still worth visiting.
    fn w_limit(&self, f: &Frame) -> f64 {
        if self.first_only && self.n > 0 {
            self.hits[0].t * f.len + f.tol
        } else {
            f64::INFINITY
        }
    }

    fn add(&mut self, h: Hit, f: &Frame) -> Result<(), Error> {
        let sign = |h: &Hit| match h.kind {
            HitKind::Transversal => h.normal.dot(f.d).signum(),
            HitKind::Tangent => 0.0,
        };
        let sh = sign(&h);
        for k in 0..self.n {
            let o = &mut self.hits[k];
            let so = sign(o);
            if (o.t - h.t).abs() <= self.tol_t && (so == sh || so == 0.0 || sh == 0.0) {
                // The same crossing: keep a transversal one.
                if o.kind == HitKind::Tangent && h.kind == HitKind::Transversal {
                    *o = h;
                }
                return Ok(());
            }
        }
        if self.first_only {
            if self.n == 0 || h.t < self.hits[0].t {
                self.hits[0] = h;
                self.n = 1;
            }
            return Ok(());
        }
        if self.n >= MAX_HITS {
            return Err(Error::InvalidArgument(
                "more than MAX_HITS hits: the ray runs along the surface",
            ));
        }
        self.hits[self.n] = h;
        self.n += 1;
        Ok(())
    }
}

/// Reports the hit at slot parameters of cell `c` at cell coordinates
/// `(s, t)` when the exact point is within `reach` of the ray.
#[allow(clippy::too_many_arguments)]
fn report<S: CellSurface + ?Sized>(
    surf: &S,
    c: &Cell,
    (s, t): (f64, f64),
    kind: HitKind,
    reach: f64,
    f: &Frame,
    t_min: f64,
    sink: &mut Sink,
) -> Result<(), Error> {
    let (u, v) = c.param(s, t);
    let e = surf.eval(c.face, c.sub, u, v)?;
    let (w, dist) = f.locate(e.p);
    if dist > reach || w / f.len < t_min - f.tol / f.len {
        return Ok(());
    }
    sink.add(
        Hit {
            t: w / f.len,
            face: c.face,
            sub: c.sub,
            u,
            v,
            point: e.p,
            normal: e.normal,
            kind,
        },
        f,
    )
}

/// The walk of one ray (see module docs).
fn walk<S: CellSurface + ?Sized>(
    surf: &S,
    ray: &Ray,
    opts: &RayOptions,
    first_only: bool,
    work: &mut QueryWork,
) -> Result<usize, Error> {
    let f = Frame::new(surf, ray, opts.tol)?;
    if opts.t_min.is_nan() {
        return Err(Error::InvalidArgument("t_min is NaN"));
    }
    let quarter = f.tol * 0.25;
    let w_min = opts.t_min * f.len - f.tol;
    let QueryWork { stack, hits, .. } = work;
    let mut sink = Sink {
        hits,
        n: 0,
        first_only,
        tol_t: 0.5 * f.tol / f.len,
    };
    let mut visited = 0u64;
    let mut kids = [Cell::ZERO; 4];
    let mut visit = |v: Visit| -> Result<Option<f64>, Error> {
        let (face, sub) = match v {
            Visit::Box(lo, hi) => return Ok(box_key(&f, lo, hi, w_min, sink.w_limit(&f))),
            Visit::Slot(face, sub) => (face, sub),
        };
        stack.clear();
        stack.push(surf.root(face, sub));
        while let Some(c) = stack.pop() {
            visited += 1;
            if visited > opts.max_cells {
                return Err(Error::WorkLimitExceeded {
                    limit: opts.max_cells,
                    what: "cells of a ray query (RayOptions::max_cells)",
                });
            }
            let w_max = sink.w_limit(&f);
            match c.bound {
                Bound::Ball {
                    center,
                    radius,
                    corner,
                    ..
                } => {
                    let (w, dist) = f.locate(center);
                    let slack = 1e-14 * (f.mag + center.abs().max_element()) + f.r;
                    if dist > radius + slack
                        || w + radius + slack < w_min
                        || w - radius - slack > w_max
                    {
                        continue;
                    }
                    if radius <= quarter {
                        let (cs, ct) = super::cell::QUADRANT[corner as usize];
                        report(
                            surf,
                            &c,
                            (cs as f64, ct as f64),
                            HitKind::Tangent,
                            f.tol * 0.5,
                            &f,
                            opts.t_min,
                            &mut sink,
                        )?;
                        continue;
                    }
                }
                Bound::Net => {
                    // Projected net and along-ray range.
                    let mut g = [[0.0; 16]; 2];
                    let (mut wl, mut wh) = (f64::INFINITY, f64::NEG_INFINITY);
                    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                    let mut pmag = 0.0f64;
                    for k in 0..16 {
                        let p = c.point(k);
                        pmag = pmag.max(p.abs().max_element());
                        let r = p - f.o;
                        let w = r.dot(f.d);
                        wl = wl.min(w);
                        wh = wh.max(w);
                        g[0][k] = r.dot(f.e1);
                        g[1][k] = r.dot(f.e2);
                        for a in 0..2 {
                            lo[a] = lo[a].min(g[a][k]);
                            hi[a] = hi[a].max(g[a][k]);
                        }
                    }
                    let err = 4e-15 * (f.mag + pmag) + f.r;
                    if lo[0] > err || hi[0] < -err || lo[1] > err || hi[1] < -err {
                        continue;
                    }
                    if wh + err < w_min || wl - err > w_max {
                        continue;
                    }
                    let (blo, bhi) = c.aabb();
                    let across = (bhi - blo).length();
                    if across <= quarter {
                        report(
                            surf,
                            &c,
                            (0.5, 0.5),
                            HitKind::Tangent,
                            f.tol * 0.5,
                            &f,
                            opts.t_min,
                            &mut sink,
                        )?;
                        continue;
                    }
                    // |S_s| + |S_t| <= 3 (max |dP_s| + max |dP_t|); the
                    // largest length is the root of the largest square
                    // (the square root is monotone and correctly rounded).
                    let (mut ss, mut tt) = (0.0f64, 0.0f64);
                    for k in 0..16 {
                        let p = c.point(k);
                        if k % 4 < 3 {
                            ss = ss.max((c.point(k + 1) - p).length_squared());
                        }
                        if k < 12 {
                            tt = tt.max((c.point(k + 4) - p).length_squared());
                        }
                    }
                    let speed = 3.0 * (libm::sqrt(ss) + libm::sqrt(tt));
                    let width = if speed > 0.0 { quarter / speed } else { 1.0 };
                    match solve(&g, width, err) {
                        Solve::Empty => continue,
                        Solve::Narrowed { s0, s1, t0, t1 } => {
                            report(
                                surf,
                                &c,
                                (0.5 * (s0 + s1), 0.5 * (t0 + t1)),
                                HitKind::Transversal,
                                f.tol * 0.5,
                                &f,
                                opts.t_min,
                                &mut sink,
                            )?;
                            continue;
                        }
                        Solve::Unknown => {}
                    }
                }
                Bound::Hull { lo, hi, radius } => {
                    let centre = 0.5 * (lo + hi);
                    let (w, dist) = f.locate(centre);
                    let slack = 1e-14 * (f.mag + centre.abs().max_element()) + f.r;
                    if dist > radius + slack
                        || w + radius + slack < w_min
                        || w - radius - slack > w_max
                        || !ray_meets_box(&f, lo, hi, slack)
                    {
                        continue;
                    }
                    // Any two points of the cell are within `across`.
                    if (2.0 * radius).min((hi - lo).length()) <= quarter {
                        report(
                            surf,
                            &c,
                            (0.5, 0.5),
                            HitKind::Tangent,
                            f.tol * 0.5,
                            &f,
                            opts.t_min,
                            &mut sink,
                        )?;
                        continue;
                    }
                }
                Bound::None => {}
            }
            if c.level >= MAX_LEVEL || !stack.room(4) || surf.at_floor(&c) {
                return Err(Error::InvalidArgument(
                    "ray query reached the deepest cell level without a certificate",
                ));
            }
            surf.split(&c, &mut kids);
            // Nearest last, so that it is visited first.
            let key = |k: &Cell| {
                let (lo, hi) = k.aabb();
                let (a, _) = f.locate(0.5 * (lo + hi));
                if a.is_finite() {
                    a
                } else {
                    f64::INFINITY
                }
            };
            let keys = kids.each_ref().map(key);
            let mut order = [0usize, 1, 2, 3];
            order.sort_unstable_by(|&a, &b| keys[b].total_cmp(&keys[a]));
            for i in order {
                stack.push(kids[i]);
            }
        }
        Ok(None)
    };
    if first_only {
        index::nearest(surf, &mut visit)?;
    } else {
        index::in_order(surf, &mut visit)?;
    }
    let n = sink.n;
    // Sorted by t (insertion sort: few hits).
    for a in 1..n {
        let mut b = a;
        while b > 0 && hits[b - 1].t > hits[b].t {
            hits.swap(b - 1, b);
            b -= 1;
        }
    }
    work.nhits = n;
    Ok(n)
}

/// The first hit of `ray` (smallest `t >= t_min`, within `tol`), or None
/// when the ray misses the surface (see module docs for the guarantee).
pub(crate) fn first_hit<S: CellSurface + ?Sized>(
    surf: &S,
    ray: &Ray,
    opts: &RayOptions,
    work: &mut QueryWork,
) -> Result<Option<Hit>, Error> {
    let n = walk(surf, ray, opts, true, work)?;
    Ok((n > 0).then(|| work.hits[0]))
}

/// All hits of `ray`, sorted by `t`, left in `work.hits`; their number.
pub(crate) fn all_hits_in_work<S: CellSurface + ?Sized>(
    surf: &S,
    ray: &Ray,
    opts: &RayOptions,
    work: &mut QueryWork,
) -> Result<usize, Error> {
    walk(surf, ray, opts, false, work)
}

/// All hits of `ray`, sorted by `t`, into `out`; returns their number.
/// `out` too short (including empty: the size query) is
/// [`Error::BufferTooSmall`] with the exact count, nothing written.
pub(crate) fn all_hits<S: CellSurface + ?Sized>(
    surf: &S,
    ray: &Ray,
    opts: &RayOptions,
    work: &mut QueryWork,
    out: &mut [Hit],
) -> Result<usize, Error> {
    let n = walk(surf, ray, opts, false, work)?;
    if out.len() < n {
        return Err(Error::BufferTooSmall { required: n });
    }
    out[..n].copy_from_slice(&work.hits[..n]);
    Ok(n)
}
