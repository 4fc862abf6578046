//! Planar sections of a closed solid as closed, oriented polylines within
//! Hausdorff distance `eps` of the exact section curve.
//!
//! For the plane `n . p = h` let `g = n . S - h`; over a polynomial cell its
//! Bezier coefficients are `g_ab = n . P_ab - h` (\[CL-R ch. 7\] nets,
//! convex hull property). The walk over the cells of every slot
//! (`cell.rs`) drops a cell whose coefficients all have one sign
//! (values with `|g| <= 1e-13 scale` count as positive everywhere, a
//! consistent symbolic shift of the plane). A polynomial cell is a
//! **leaf** when
//!
//! 1. `g` is strictly monotone along s or along t over the cell (the
//!    derivative net `3 (g[a+1][b] - g[a][b])`, resp. along t, has one
//!    strict sign), and
//! 2. every side's cubic has at most one sign change of its Bernstein
//!    coefficients (so at most one root, Descartes' rule for Bernstein
//!    polynomials), and
//! 3. the chord of the section (below) is within `eps` of the plane's cut
//!    of the net's convex hull.
//!
//! With `g` monotone along s, each line `t = const` meets the section at
//! most once, so the section in the cell is a union of graphs over t whose
//! end points lie on the sides: with the sides' roots it is empty (no
//! root) or one arc joining the two roots. The leaf's segment (the chord)
//! joins the two exact limit points `a, b` at the roots (sides solved by
//! bisection to full precision, then evaluated exactly). The arc lies in
//! the net's convex hull and in the plane, i.e. in the convex polygon
//! `K` = hull of the plane's crossings of the segments between net points
//! on opposite sides; the distance to the chord is convex, so
//! `D = max over those crossings of dist(x, [a, b])` bounds the distance
//! of every arc point from the chord. Conversely the arc runs from `a` to
//! `b`, so its projection on the line `ab` covers the chord: every chord
//! point has an arc point within `D`. The Hausdorff distance is at most
//! `D`, and a cell is a leaf once `D <= eps`. `D` is second order in the
//! cell size where the plane crosses the surface transversally (the net's
//! deviation from its tangent plane), where the earlier rule (the net's
//! box below `eps`) was first order: far fewer and larger leaves
//! (measured in BENCHMARKS.md). A corner ball of an extraordinary vertex
//! (or, on feature meshes, a hull cell's ball) whose diameter is at most
//! `eps` is a **node**: the contours that end on it are joined through it
//! (the joining segment lies in the ball).
//!
//! Segments are oriented so that the solid lies on their left seen from
//! `+n` (with outward normals, i.e. counter-clockwise faces seen from
//! outside): outer contours run counter-clockwise, holes clockwise.
//! Segments are then chained by their end points (equal up to rounding)
//! into closed polylines.
//!
//! Cells where the section is present but none of the tests pass even at a
//! diameter below `eps` (the plane tangent to the surface) are counted in
//! [`SliceStats::unresolved`] and contribute nothing.
//!
//! Rounding (`rounding.rs`): the chord bound `D`, the node balls and the
//! hull cells' plane test are widened by the rounding term `r` of the
//! model and the plane offset, and the walk runs at `eps - 2 r`, so the
//! polylines (as computed) are within `eps` of the exact section where the
//! plane crosses the surface transversally (farther than `r` from
//! tangency, the exception above); `eps < 4 r` is
//! [`Error::CoordinateRange`].
//!
//! Work: each walk ([`super::slice_segment_count`], [`super::slice_layer`])
//! takes at most [`SliceOptions::max_cells`] cells from its stack (plus one
//! root per slot); more is [`Error::WorkLimitExceeded`]. Chaining is
//! `O(n log n)` in the `n` segments plus, for dangling ends, `O(n k)` with
//! `k` the extraordinary-vertex nodes.

use super::cell::{Bound, Cell, CellSurface, MAX_LEVEL};
use super::ray::QueryWork;
use crate::error::Error;
use glam::{DVec2, DVec3};

/// A plane `normal . p = offset` (the normal need not be unit; it is
/// normalised, and `offset` is taken in units of the normalised normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Normal (non-zero, finite).
    pub normal: DVec3,
    /// Signed distance of the plane from the origin along the unit normal.
    pub offset: f64,
}

impl Plane {
    /// The plane `z = z0`.
    pub fn z(z0: f64) -> Plane {
        Plane {
            normal: DVec3::Z,
            offset: z0,
        }
    }

    /// Unit normal and the in-plane axes `(e1, e2)`, `e1 x e2 = n`
    /// (`(x, y)` for the normal `+z`).
    pub fn frame(&self) -> Result<(DVec3, DVec3, DVec3), Error> {
        let l = self.normal.length();
        if !(l > 0.0 && l.is_finite() && self.offset.is_finite()) {
            return Err(Error::InvalidArgument(
                "plane normal must be non-zero and finite, offset finite",
            ));
        }
        let n = self.normal / l;
        let seed = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let e1 = (seed - seed.dot(n) * n).normalize();
        Ok((n, e1, n.cross(e1)))
    }
}

/// Options of a slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceOptions {
    /// Hausdorff bound between the polylines and the exact section (model
    /// units, > 0). Default 1e-3.
    pub eps: f64,
    /// Work budget: cells one walk may take from its stack before it stops
    /// with [`Error::WorkLimitExceeded`]. Default [`super::MAX_CELLS`].
    pub max_cells: u64,
}

impl Default for SliceOptions {
    fn default() -> Self {
        SliceOptions {
            eps: 1e-3,
            max_cells: super::ray::MAX_CELLS,
        }
    }
}

/// One segment of a section (scratch of [`super::slice_layer`]; points in the
/// plane's `(e1, e2)` coordinates).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SliceSegment {
    /// Start.
    pub a: [f64; 2],
    /// End.
    pub b: [f64; 2],
    pub(crate) next: u32,
    pub(crate) flags: u32,
    pub(crate) radius: f64,
}

/// One closed contour of a layer: `points[start .. start + len]`, the last
/// point joined to the first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Contour {
    /// First point.
    pub start: u32,
    /// Number of points.
    pub len: u32,
    /// Counter-clockwise seen from `+n` (an outer boundary); holes run
    /// clockwise.
    pub outer: bool,
}

/// What a layer produced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SliceStats {
    /// Points of the contours (what the write step needs).
    pub points: usize,
    /// Contours.
    pub contours: usize,
    /// Scratch entries used: section segments and extraordinary-vertex
    /// nodes.
    pub segments: usize,
    /// Cells below `eps` whose section could not be resolved (plane
    /// tangent to the surface there).
    pub unresolved: usize,
}

const NODE: u32 = 1;
const HAS_PRED: u32 = 2;
const VIA_NODE: u32 = 4;
const SEEN: u32 = 8;
const NONE: u32 = u32::MAX;

/// Sign class of a coefficient (`true` = positive or within `zero`).
#[inline]
fn pos(g: f64, zero: f64) -> bool {
    g >= -zero
}

/// Number of sign changes of a Bernstein coefficient list.
fn changes(c: [f64; 4], zero: f64) -> u32 {
    let mut n = 0;
    for k in 0..3 {
        if pos(c[k], zero) != pos(c[k + 1], zero) {
            n += 1;
        }
    }
    n
}

/// The root of a cubic in Bernstein form with one sign change between its
/// end values, to full precision: Newton steps kept inside a bracket that
/// every evaluation shrinks (bisection when a step would leave it), until
/// the step or the bracket is below `1e-16`.
fn root(c: [f64; 4], zero: f64) -> f64 {
    let f = |x: f64| {
        let b = super::krawczyk::bernstein(x);
        b[0] * c[0] + b[1] * c[1] + b[2] * c[2] + b[3] * c[3]
    };
    // Derivative: 3 times the quadratic of the differences.
    let df = |x: f64| {
        let r = 1.0 - x;
        3.0 * (r * r * (c[1] - c[0]) + 2.0 * x * r * (c[2] - c[1]) + x * x * (c[3] - c[2]))
    };
    let s0 = pos(c[0], zero);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let d = c[0] - c[3];
    let mut x = if d != 0.0 {
        (c[0] / d).clamp(0.0, 1.0)
    } else {
        0.5
    };
    for _ in 0..100 {
        if x <= lo || x >= hi {
            x = 0.5 * (lo + hi);
        }
        let v = f(x);
        if pos(v, zero) == s0 {
            lo = x;
        } else {
            hi = x;
        }
        if hi - lo <= 1e-16 {
            break;
        }
        let g = df(x);
        let step = if g != 0.0 { v / g } else { f64::INFINITY };
        if step.abs() <= 1e-16 {
            return x;
        }
        x -= step;
    }
    0.5 * (lo + hi)
}

/// Range of `n . p` over the box `[lo, hi]`.
fn box_range(n: DVec3, lo: DVec3, hi: DVec3) -> (f64, f64) {
    let (mut a, mut b) = (0.0, 0.0);
    for k in 0..3 {
        let (x, y) = (n[k] * lo[k], n[k] * hi[k]);
        a += x.min(y);
        b += x.max(y);
    }
    (a, b)
}

/// Layer context.
struct Layer {
    n: DVec3,
    e1: DVec3,
    e2: DVec3,
    h: f64,
    eps: f64,
    /// Rounding term (`rounding.rs`).
    r: f64,
    max_cells: u64,
}

/// A side of a cell: its Bernstein coefficients and the cell point of
/// its parameter.
type Side = ([f64; 4], fn(f64) -> (f64, f64));

/// What a cell whose section is one arc at most (see [`walk`]) holds.
enum Leaf {
    /// No section.
    Empty,
    /// One arc: its chord (oriented) and the certified bound of the
    /// distance between arc and chord.
    Chord(SliceSegment, f64),
    /// Not one arc (four side roots): split.
    Complex,
}

/// The chord of a cell whose section is at most one arc (`g` monotone
/// along s or t, at most one root per side): the two exact limit points
/// at the side roots, and the bound
/// `max { dist(x, chord) : x in hull(net) cut by the plane }` of the
/// distance between the arc and the chord (module docs).
fn leaf_segment<S: CellSurface + ?Sized>(
    surf: &S,
    c: &Cell,
    g: &[f64; 16],
    zero: f64,
    ly: &Layer,
) -> Result<Leaf, Error> {
    // Sides: (coefficients, cell point of parameter x).
    let sides: [Side; 4] = [
        ([g[0], g[4], g[8], g[12]], |x| (x, 0.0)),
        ([g[12], g[13], g[14], g[15]], |x| (1.0, x)),
        ([g[3], g[7], g[11], g[15]], |x| (x, 1.0)),
        ([g[0], g[1], g[2], g[3]], |x| (0.0, x)),
    ];
    let mut pts = [(DVec3::ZERO, DVec3::ZERO); 2];
    let mut k = 0;
    for (co, at) in sides {
        if pos(co[0], zero) == pos(co[3], zero) {
            continue;
        }
        if k == 2 {
            return Ok(Leaf::Complex);
        }
        let (s, t) = at(root(co, zero));
        let (u, v) = c.param(s, t);
        let e = surf.eval(c.face, c.sub, u, v)?;
        pts[k] = (e.p, e.normal);
        k += 1;
    }
    match k {
        0 => return Ok(Leaf::Empty),
        2 => {}
        _ => return Ok(Leaf::Complex),
    }
    let (mut a, mut b) = (pts[0].0, pts[1].0);
    // Solid on the left seen from +n: the tangent along n x N.
    let nn = pts[0].1 + pts[1].1;
    if (b - a).dot(ly.n.cross(nn)) < 0.0 {
        core::mem::swap(&mut a, &mut b);
    }
    let dev = chord_deviation(c, g, zero, a, b) + ly.r;
    let p2 = |p: DVec3| [p.dot(ly.e1), p.dot(ly.e2)];
    Ok(Leaf::Chord(
        SliceSegment {
            a: p2(a),
            b: p2(b),
            next: NONE,
            flags: 0,
            radius: 0.0,
        },
        dev,
    ))
}

/// Largest distance from the chord `[a, b]` of the points where the
/// plane cuts the convex hull of the net: that cut is the convex hull of
/// the net points on the plane and of the crossings of the segments
/// joining net points on opposite sides, and the distance to a segment
/// is convex, so its maximum over the cut is at one of these points.
/// Plus a rounding margin.
fn chord_deviation(c: &Cell, g: &[f64; 16], zero: f64, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let inv = if l2 > 0.0 { 1.0 / l2 } else { 0.0 };
    let dist2 = |x: DVec3| {
        let w = ((x - a).dot(ab) * inv).clamp(0.0, 1.0);
        (x - a - w * ab).length_squared()
    };
    let mut pts = [DVec3::ZERO; 16];
    let mut mag = a.abs().max(b.abs()).max_element();
    for (k, p) in pts.iter_mut().enumerate() {
        *p = c.point(k);
        mag = mag.max(p.abs().max_element());
    }
    let mut dev2 = 0.0f64;
    for i in 0..16 {
        if g[i].abs() <= zero {
            dev2 = dev2.max(dist2(pts[i]));
        }
        if g[i] >= -zero {
            continue;
        }
        for j in 0..16 {
            if g[j] <= zero {
                continue;
            }
            let w = g[i] / (g[i] - g[j]);
            dev2 = dev2.max(dist2(pts[i] + (pts[j] - pts[i]) * w));
        }
    }
    libm::sqrt(dev2) + 1e-13 * mag
}

/// Walks the cells and calls `emit` with every segment and node; returns
/// the number of unresolved cells.
fn walk<S: CellSurface + ?Sized>(
    surf: &S,
    ly: &Layer,
    work: &mut QueryWork,
    mut emit: impl FnMut(SliceSegment),
) -> Result<usize, Error> {
    let stack = &mut work.stack;
    let mut kids = [Cell::ZERO; 4];
    let mut unresolved = 0;
    let mut visited = 0u64;
    for face in 0..surf.faces() {
        for sub in 0..surf.subfaces(face) {
            stack.clear();
            stack.push(surf.root(face as u32, sub as u32));
            while let Some(c) = stack.pop() {
                visited += 1;
                if visited > ly.max_cells {
                    return Err(Error::WorkLimitExceeded {
                        limit: ly.max_cells,
                        what: "cells of a slice walk (SliceOptions::max_cells)",
                    });
                }
                match c.bound {
                    Bound::Ball { center, radius, .. } => {
                        let d = ly.n.dot(center) - ly.h;
                        if d.abs()
                            > radius * (1.0 + 1e-12) + 1e-15 * center.abs().max_element() + ly.r
                        {
                            continue;
                        }
                        if 2.0 * (radius + ly.r) <= ly.eps {
                            emit(SliceSegment {
                                a: [center.dot(ly.e1), center.dot(ly.e2)],
                                b: [center.dot(ly.e1), center.dot(ly.e2)],
                                next: NONE,
                                flags: NODE,
                                radius: radius + ly.r,
                            });
                            continue;
                        }
                    }
                    Bound::Net => {
                        let mut g = [0.0; 16];
                        let mut mag = ly.h.abs();
                        for (k, gk) in g.iter_mut().enumerate() {
                            let p = c.point(k);
                            mag = mag.max(p.abs().max_element());
                            *gk = ly.n.dot(p) - ly.h;
                        }
                        let zero = 1e-13 * mag;
                        let s0 = pos(g[0], zero);
                        if g.iter().all(|&x| pos(x, zero) == s0) {
                            continue;
                        }
                        let mono = |d: usize| {
                            let (mut p, mut m) = (true, true);
                            for a in 0..4 {
                                for b in 0..4 {
                                    let (na, nb) = if d == 0 { (a + 1, b) } else { (a, b + 1) };
                                    if na > 3 || nb > 3 {
                                        continue;
                                    }
                                    let x = g[na * 4 + nb] - g[a * 4 + b];
                                    p &= x > 0.0;
                                    m &= x < 0.0;
                                }
                            }
                            p || m
                        };
                        let sides_ok = || {
                            [
                                [g[0], g[4], g[8], g[12]],
                                [g[12], g[13], g[14], g[15]],
                                [g[3], g[7], g[11], g[15]],
                                [g[0], g[1], g[2], g[3]],
                            ]
                            .iter()
                            .all(|&s| changes(s, zero) <= 1)
                        };
                        if (mono(0) || mono(1)) && sides_ok() {
                            match leaf_segment(surf, &c, &g, zero, ly)? {
                                Leaf::Empty => continue,
                                Leaf::Chord(s, dev) if dev <= ly.eps => {
                                    emit(s);
                                    continue;
                                }
                                Leaf::Chord(..) | Leaf::Complex => {}
                            }
                        }
                        let (lo, hi) = c.aabb();
                        let small = (hi - lo).length() <= ly.eps;
                        if small && c.level >= MAX_LEVEL - 8 {
                            unresolved += 1;
                            continue;
                        }
                    }
                    Bound::Hull { lo, hi, radius } => {
                        let centre = 0.5 * (lo + hi);
                        let slack = 1e-15 * centre.abs().max_element() + ly.r;
                        let (gl, gh) = box_range(ly.n, lo, hi);
                        let d = ly.n.dot(centre) - ly.h;
                        if d.abs() > radius * (1.0 + 1e-12) + slack
                            || gl - ly.h > slack
                            || gh - ly.h < -slack
                        {
                            continue;
                        }
                        if 2.0 * (radius + ly.r) <= ly.eps {
                            emit(SliceSegment {
                                a: [centre.dot(ly.e1), centre.dot(ly.e2)],
                                b: [centre.dot(ly.e1), centre.dot(ly.e2)],
                                next: NONE,
                                flags: NODE,
                                radius: radius + ly.r,
                            });
                            continue;
                        }
                    }
                    Bound::None => {}
                }
                if c.level >= MAX_LEVEL || !stack.room(4) || surf.at_floor(&c) {
                    return Err(Error::InvalidArgument(
                        "slice reached the deepest cell level",
                    ));
                }
                surf.split(&c, &mut kids);
                for k in kids {
                    stack.push(k);
                }
            }
        }
    }
    Ok(unresolved)
}

fn layer<S: CellSurface + ?Sized>(
    surf: &S,
    plane: &Plane,
    opts: &SliceOptions,
) -> Result<Layer, Error> {
    let (n, e1, e2) = plane.frame()?;
    if !(opts.eps > 0.0 && opts.eps.is_finite()) {
        return Err(Error::InvalidArgument("eps must be positive"));
    }
    let r = super::rounding::term(surf, plane.offset.abs())?;
    Ok(Layer {
        n,
        e1,
        e2,
        h: plane.offset,
        eps: super::rounding::inner(opts.eps, r)?,
        r,
        max_cells: opts.max_cells,
    })
}

/// Number of segments (and nodes) of the section: the scratch length
/// [`super::slice_layer`] needs.
pub(crate) fn segment_count<S: CellSurface + ?Sized>(
    surf: &S,
    plane: &Plane,
    opts: &SliceOptions,
    work: &mut QueryWork,
) -> Result<usize, Error> {
    let ly = layer(surf, plane, opts)?;
    let mut n = 0;
    walk(surf, &ly, work, |_| n += 1)?;
    Ok(n)
}

#[inline]
fn d2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (DVec2::from_array(a) - DVec2::from_array(b)).length()
}

/// The section by `plane`, chained into closed contours in the scratch
/// `segs` (at least [`segment_count`] entries, else
/// [`Error::BufferTooSmall`] with that count); returns the exact numbers of
/// points and contours [`write_contours`] will write.
pub(crate) fn slice_layer<S: CellSurface + ?Sized>(
    surf: &S,
    plane: &Plane,
    opts: &SliceOptions,
    work: &mut QueryWork,
    segs: &mut [SliceSegment],
) -> Result<SliceStats, Error> {
    let ly = layer(surf, plane, opts)?;
    let mut n = 0usize;
    let unresolved = walk(surf, &ly, work, |s| {
        if let Some(d) = segs.get_mut(n) {
            *d = s;
        }
        n += 1;
    })?;
    if n > segs.len() {
        return Err(Error::BufferTooSmall { required: n });
    }
    let segs = &mut segs[..n];
    segs.sort_unstable_by(|a, b| a.a[0].total_cmp(&b.a[0]));
    let mag = segs
        .iter()
        .map(|s| s.a[0].abs().max(s.a[1].abs()))
        .fold(ly.h.abs(), f64::max);
    let stol = (1e-6 * ly.eps).max(1e-12 * mag);
    // Successors by equal end points.
    for i in 0..n {
        if segs[i].flags & NODE != 0 {
            continue;
        }
        let b = segs[i].b;
        let first = segs.partition_point(|s| s.a[0] < b[0] - stol);
        let mut best = (NONE, stol);
        for (j, s) in segs.iter().enumerate().skip(first) {
            if s.a[0] > b[0] + stol {
                break;
            }
            if s.flags & (NODE | HAS_PRED) == 0 && j != i {
                let d = d2(s.a, b);
                if d <= best.1 {
                    best = (j as u32, d);
                }
            }
        }
        if best.0 != NONE {
            segs[i].next = best.0;
            segs[best.0 as usize].flags |= HAS_PRED;
        }
    }
    // Dangling ends joined through an extraordinary-vertex node.
    for i in 0..n {
        if segs[i].flags & NODE != 0 || segs[i].next != NONE {
            continue;
        }
        let b = segs[i].b;
        let mut found = NONE;
        'nodes: for k in 0..n {
            let nd = segs[k];
            if nd.flags & NODE == 0 || d2(nd.a, b) > nd.radius + stol {
                continue;
            }
            for j in 0..n {
                let s = segs[j];
                if s.flags & (NODE | HAS_PRED) == 0 && d2(nd.a, s.a) <= nd.radius + stol {
                    found = j as u32;
                    break 'nodes;
                }
            }
        }
        if found == NONE {
            return Err(Error::InvalidArgument(
                "slice contour did not close (plane through a degenerate point): shift the plane",
            ));
        }
        segs[i].next = found;
        segs[i].flags |= VIA_NODE;
        segs[found as usize].flags |= HAS_PRED;
    }
    let (points, contours) = count(segs)?;
    Ok(SliceStats {
        points,
        contours,
        segments: n,
        unresolved,
    })
}

/// Points and contours of chained segments; checks that every chain is a
/// cycle.
fn count(segs: &mut [SliceSegment]) -> Result<(usize, usize), Error> {
    let n = segs.len();
    let np: usize = segs
        .iter()
        .filter(|s| s.flags & NODE == 0)
        .map(|s| 1 + (s.flags & VIA_NODE != 0) as usize)
        .sum();
    let mut nc = 0usize;
    for i in 0..n {
        if segs[i].flags & (NODE | SEEN) != 0 {
            continue;
        }
        nc += 1;
        let mut j = i;
        while segs[j].flags & SEEN == 0 {
            segs[j].flags |= SEEN;
            j = segs[j].next as usize;
            if j >= n {
                return Err(Error::InvalidArgument(
                    "slice scratch is not a chained layer",
                ));
            }
        }
        if j != i {
            return Err(Error::InvalidArgument("slice contours cross"));
        }
    }
    for s in segs.iter_mut() {
        s.flags &= !SEEN;
    }
    Ok((np, nc))
}

/// Writes the contours chained by [`super::slice_layer`] (`segs` = its scratch,
/// `stats.segments` entries): points (plane coordinates) and contours, via
/// `contour` for each contour. Short `points` or a `max_contours` below the
/// count is [`Error::BufferTooSmall`] with the exact count, nothing
/// written.
pub fn write_contours(
    segs: &mut [SliceSegment],
    points: &mut [[f64; 2]],
    max_contours: usize,
    mut contour: impl FnMut(usize, Contour),
) -> Result<(usize, usize), Error> {
    let n = segs.len();
    let (np, nc) = count(segs)?;
    if points.len() < np {
        return Err(Error::BufferTooSmall { required: np });
    }
    if max_contours < nc {
        return Err(Error::BufferTooSmall { required: nc });
    }
    let (mut at, mut ci) = (0usize, 0usize);
    for i in 0..n {
        if segs[i].flags & (NODE | SEEN) != 0 {
            continue;
        }
        let start = at;
        let mut j = i;
        loop {
            segs[j].flags |= SEEN;
            points[at] = segs[j].a;
            at += 1;
            if segs[j].flags & VIA_NODE != 0 {
                points[at] = segs[j].b;
                at += 1;
            }
            j = segs[j].next as usize;
            if j == i {
                break;
            }
        }
        let mut area = 0.0;
        for k in start..at {
            let (p, q) = (points[k], points[if k + 1 < at { k + 1 } else { start }]);
            area += p[0] * q[1] - p[1] * q[0];
        }
        contour(
            ci,
            Contour {
                start: start as u32,
                len: (at - start) as u32,
                outer: area > 0.0,
            },
        );
        ci += 1;
    }
    for s in segs.iter_mut() {
        s.flags &= !SEEN;
    }
    Ok((at, ci))
}
