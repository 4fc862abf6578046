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
//! joins the two exact limit points `a, b` at the roots (sides solved to
//! full precision by Newton steps inside a bisection bracket, then the
//! cell's net, which is the surface there, evaluated at them). The arc lies in
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
//! Segments are then chained by their end points into closed polylines:
//! an end and a start closer than `1e-3 eps` are one point (two cells
//! solve a shared side's root each from its own net; where the side is
//! nearly tangent to the plane the two roots differ by far more than
//! rounding, though both lie on the section), and the joining gap adds no
//! more than that to the distance.
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

use super::cell::{Bound, Cell, CellSurface, MAX_LEVEL, STACK_CAP};
use super::index::{self, Visit};
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

/// A family of parallel planes: layer `k` is `normal . p = offset + k *
/// step` (the normal normalised as in [`Plane`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneStack {
    /// Normal (non-zero, finite).
    pub normal: DVec3,
    /// Offset of layer 0 (units of the normalised normal).
    pub offset: f64,
    /// Distance between consecutive layers (finite; any sign).
    pub step: f64,
}

impl PlaneStack {
    /// The planes `z = z0 + k dz`.
    pub fn z(z0: f64, dz: f64) -> PlaneStack {
        PlaneStack {
            normal: DVec3::Z,
            offset: z0,
            step: dz,
        }
    }

    /// Layer `k`: the plane [`super::slice_layer`] would slice for it (the
    /// band slicer uses exactly these offsets).
    pub fn layer(&self, k: usize) -> Plane {
        Plane {
            normal: self.normal,
            offset: self.offset + k as f64 * self.step,
        }
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
/// the step or the bracket is below two ulps of 1 (`2.5e-16`).
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
        // Two ulps of the numbers below 1: a bracket of adjacent floats
        // cannot shrink further (the bound was 1e-16 once, below the
        // spacing of [0.5, 1), and such roots ran all 100 iterations).
        if hi - lo <= 2.5e-16 {
            break;
        }
        // Newton on `f + zero`, whose root is the bracket's limit (the
        // sign classes shift by `zero`): on `f` itself the steps aimed
        // outside the bracket and every step fell back to bisection.
        let g = df(x);
        let step = if g != 0.0 {
            (v + zero) / g
        } else {
            f64::INFINITY
        };
        if step.abs() <= 2.5e-16 {
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
#[derive(Clone, Copy)]
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

/// The sides of a cell (t = 0, s = 1, t = 1, s = 0): per Bezier
/// coefficient along the side (index `4 a + b`, `a` along s) the net point
/// on the side and its inner neighbour across it.
const SIDES: [[(usize, usize); 4]; 4] = [
    [(0, 1), (4, 5), (8, 9), (12, 13)],
    [(12, 8), (13, 9), (14, 10), (15, 11)],
    [(3, 2), (7, 6), (11, 10), (15, 14)],
    [(0, 4), (1, 5), (2, 6), (3, 7)],
];

/// Point and unit normal (`S_s x S_t`) of the cell's bicubic at parameter
/// `x` of side `side` ([`SIDES`]): the side's cubic, its derivative, and
/// the derivative across the side from the next row of the net (a quarter
/// of a full bicubic evaluation).
fn side_point(c: &Cell, side: usize, x: f64) -> (DVec3, DVec3) {
    let b = super::krawczyk::bernstein(x);
    let r = 1.0 - x;
    let q = [r * r, 2.0 * x * r, x * x];
    let sd = SIDES[side];
    let on: [DVec3; 4] = core::array::from_fn(|i| c.point(sd[i].0));
    let (mut p, mut along, mut out) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for i in 0..4 {
        p += on[i] * b[i];
        out += (on[i] - c.point(sd[i].1)) * b[i];
        if i < 3 {
            along += (on[i + 1] - on[i]) * q[i];
        }
    }
    // `out` points from the inner row to the side: +S_t on t = 1, -S_t on
    // t = 0, +S_s on s = 1, -S_s on s = 0.
    let normal = match side {
        0 => along.cross(-out),
        1 => out.cross(along),
        2 => along.cross(out),
        _ => (-out).cross(along),
    };
    (p, normal.normalize_or_zero())
}

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
fn leaf_segment(c: &Cell, g: &[f64; 16], zero: f64, dmag: f64, ly: &Layer) -> Leaf {
    // The sides whose end values differ in sign (one root each, by
    // `sides_ok`): none is no section, two are one arc, one or more than
    // two are not (split), decided before any root is solved.
    let mut sides = [0usize; 4];
    let mut k = 0;
    for side in 0..4 {
        let co = SIDES[side].map(|(i, _)| g[i]);
        if pos(co[0], zero) != pos(co[3], zero) {
            sides[k] = side;
            k += 1;
        }
    }
    match k {
        0 => return Leaf::Empty,
        2 => {}
        _ => return Leaf::Complex,
    }
    // The net is the surface over the cell: its point is the exact limit
    // point (up to the net's rounding), its normal the surface's.
    let pts = [sides[0], sides[1]].map(|side| {
        let co = SIDES[side].map(|(i, _)| g[i]);
        side_point(c, side, root(co, zero))
    });
    let (mut a, mut b) = (pts[0].0, pts[1].0);
    // Solid on the left seen from +n: the tangent along n x N.
    let nn = pts[0].1 + pts[1].1;
    if (b - a).dot(ly.n.cross(nn)) < 0.0 {
        core::mem::swap(&mut a, &mut b);
    }
    let dev = chord_deviation(c, g, zero, dmag, (a, b), ly) + ly.r;
    let p2 = |p: DVec3| [p.dot(ly.e1), p.dot(ly.e2)];
    Leaf::Chord(
        SliceSegment {
            a: p2(a),
            b: p2(b),
            next: NONE,
            flags: 0,
            radius: 0.0,
        },
        dev,
    )
}

/// Largest distance from the chord `[a, b]` of the points where the
/// plane cuts the convex hull of the net: that cut is the convex hull of
/// the net points on the plane and of the crossings of the segments
/// joining net points on opposite sides, and the distance to a segment
/// is convex, so its maximum over the cut is at one of these points.
/// Plus a rounding margin. Infinite once it exceeds `FAR eps`.
fn chord_deviation(
    c: &Cell,
    g: &[f64; 16],
    zero: f64,
    dmag: f64,
    (a, b): (DVec3, DVec3),
    ly: &Layer,
) -> f64 {
    let eps = ly.eps;
    let ab = b - a;
    let l2 = ab.length_squared();
    let inv = if l2 > 0.0 { 1.0 / l2 } else { 0.0 };
    // The crossings and the chord lie in the plane (unit normal `n`), so
    // a crossing is `a + t ab + rho v` with the in-plane normal
    // `v = n x ab / |n x ab|`; `t` and `rho` are affine in the point, so a
    // crossing's are the same combination of its two net points' (their
    // components along `n` cancel at the crossing, up to the roots'
    // rounding, which the margin covers). A degenerate chord keeps the
    // three-dimensional offset from the line.
    // `dmag` is the net's largest coordinate magnitude (the walk's).
    let mag = a.abs().max(b.abs()).max_element().max(dmag);
    let v = ly.n.cross(ab);
    let vl = v.length();
    let planar = l2 > 0.0 && vl > 0.0;
    let margin = 2e-13 * mag;
    // Past this the cell is far from a leaf: stop early (most cells above
    // the leaves fail at one of the first crossings).
    let stop = (FAR * eps - margin).max(0.0);
    let stop2 = stop * stop;
    if planar {
        let (tk, rk) = chord_coordinates(c, a, ab, inv, v / vl);
        return planar_deviation(g, zero, &tk, &rk, l2, stop2)
            .map_or(f64::INFINITY, |d2| libm::sqrt(d2) + margin);
    }
    let mut tk = [0.0f64; 16];
    let mut r3 = [DVec3::ZERO; 16];
    for k in 0..16 {
        let q = c.point(k) - a;
        tk[k] = q.dot(ab) * inv;
        r3[k] = q - tk[k] * ab;
    }
    pair_deviation(g, zero, &tk, &r3, l2, stop2).map_or(f64::INFINITY, |d2| libm::sqrt(d2) + margin)
}

/// A net point's offset across the chord: `rho`, the in-plane distance,
/// for a chord that spans a plane direction; the three-dimensional offset
/// from the line for a degenerate one.
trait Across: Copy {
    /// `self + (other - self) w`: the offset of a crossing.
    fn toward(self, other: Self, w: f64) -> Self;
    /// The squared length.
    fn sq(self) -> f64;
}

impl Across for f64 {
    #[inline]
    fn toward(self, other: f64, w: f64) -> f64 {
        self + (other - self) * w
    }
    #[inline]
    fn sq(self) -> f64 {
        self * self
    }
}

impl Across for DVec3 {
    #[inline]
    fn toward(self, other: DVec3, w: f64) -> DVec3 {
        self + (other - self) * w
    }
    #[inline]
    fn sq(self) -> f64 {
        self.length_squared()
    }
}

/// Squared distance from the chord (`l2` its squared length) of a point
/// at chord coordinate `t` whose offset across the chord has squared
/// length `r2`: beyond either end, the overshoot counts too.
#[inline(always)]
fn chord_dist2(t: f64, r2: f64, l2: f64) -> f64 {
    let over = if t < 0.0 {
        t
    } else if t > 1.0 {
        t - 1.0
    } else {
        0.0
    };
    r2 + over * over * l2
}

/// The squared deviation of [`chord_deviation`], one point and one
/// crossing at a time (chord coordinates `t` in `tk`, offsets across in
/// `rk`): the degenerate chords' path, and for planar chords the loop
/// [`planar_deviation`]'s vectors reproduce bit for bit. `None` (far, see
/// [`FAR`]) once the maximum before some point `i` exceeds `stop2`.
fn pair_deviation<R: Across>(
    g: &[f64; 16],
    zero: f64,
    tk: &[f64; 16],
    rk: &[R; 16],
    l2: f64,
    stop2: f64,
) -> Option<f64> {
    let mut dev2 = 0.0f64;
    for i in 0..16 {
        if dev2 > stop2 {
            return None;
        }
        if g[i].abs() <= zero {
            dev2 = dev2.max(chord_dist2(tk[i], rk[i].sq(), l2));
        }
        if g[i] >= -zero {
            continue;
        }
        for j in 0..16 {
            if g[j] <= zero {
                continue;
            }
            let w = g[i] / (g[i] - g[j]);
            let t = tk[i] + (tk[j] - tk[i]) * w;
            dev2 = dev2.max(chord_dist2(t, rk[i].toward(rk[j], w).sq(), l2));
        }
    }
    Some(dev2)
}

/// The chord coordinates of the 16 net points `P_k` (with the cell's
/// offset): `t_k = ((P_k - a) . ab) inv` along the chord and
/// `rho_k = (P_k - a) . v` across it, two points at a time with the
/// scalar formulas' operations in their order (`P + off - a` per
/// coordinate, dot products as `(x x') + (y y') + (z z')`), so the same
/// bits.
fn chord_coordinates(c: &Cell, a: DVec3, ab: DVec3, inv: f64, v: DVec3) -> ([f64; 16], [f64; 16]) {
    use crate::math::simd::F2;
    let (mut tk, mut rk) = ([0.0f64; 16], [0.0f64; 16]);
    let s = F2::splat;
    let (ox, oy, oz) = (s(c.off.x), s(c.off.y), s(c.off.z));
    let (ax, ay, az) = (s(a.x), s(a.y), s(a.z));
    for k in (0..16).step_by(2) {
        let qx = F2::ld(&c.net, k).add(ox).sub(ax);
        let qy = F2::ld(&c.net, 16 + k).add(oy).sub(ay);
        let qz = F2::ld(&c.net, 32 + k).add(oz).sub(az);
        let t = qx.mul(s(ab.x)).add(qy.mul(s(ab.y))).add(qz.mul(s(ab.z)));
        t.mul(s(inv)).st(&mut tk, k);
        let r = qx.mul(s(v.x)).add(qy.mul(s(v.y))).add(qz.mul(s(v.z)));
        r.st(&mut rk, k);
    }
    (tk, rk)
}

/// The squared deviation of [`chord_deviation`] for a chord that spans a
/// plane direction (`rho` in `rk`), several crossings at a time: the net
/// points with `g > zero` are packed first (padded to whole vectors with
/// copies of the last, which change no maximum), then each point with
/// `g < -zero` meets them all in two-lane steps, or four-lane ones where
/// the CPU runs AVX2, doing per lane the scalar loop's IEEE operations in
/// its order (`over` as `min(t, 0) + max(t - 1, 0)`, the same value), so
/// the maximum is the scalar one bit for bit. `None` (far, see [`FAR`])
/// exactly where the scalar loop stops: the maximum before some point `i`
/// exceeds `stop2`.
fn planar_deviation(
    g: &[f64; 16],
    zero: f64,
    tk: &[f64; 16],
    rk: &[f64; 16],
    l2: f64,
    stop2: f64,
) -> Option<f64> {
    #[cfg(target_arch = "x86_64")]
    if crate::math::simd::has_avx2() {
        // SAFETY: the CPU runs AVX2 (checked just above).
        return unsafe { planar_deviation_avx2(g, zero, tk, rk, l2, stop2) };
    }
    planar_body::<false>(g, zero, tk, rk, l2, stop2)
}

/// [`planar_deviation`] on four lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn planar_deviation_avx2(
    g: &[f64; 16],
    zero: f64,
    tk: &[f64; 16],
    rk: &[f64; 16],
    l2: f64,
    stop2: f64,
) -> Option<f64> {
    planar_body::<true>(g, zero, tk, rk, l2, stop2)
}

/// The body of [`planar_deviation`]: two lanes, or four with `WIDE` (only
/// in functions compiled for AVX2; elsewhere than x86_64 `WIDE` changes
/// nothing).
#[inline(always)]
fn planar_body<const WIDE: bool>(
    g: &[f64; 16],
    zero: f64,
    tk: &[f64; 16],
    rk: &[f64; 16],
    l2: f64,
    stop2: f64,
) -> Option<f64> {
    let lanes = if WIDE { 4 } else { 2 };
    let (mut pg, mut pt, mut pr) = ([0.0f64; 16], [0.0f64; 16], [0.0f64; 16]);
    let mut np = 0;
    for j in 0..16 {
        if g[j] > zero {
            (pg[np], pt[np], pr[np]) = (g[j], tk[j], rk[j]);
            np += 1;
        }
    }
    // At most 15 (a point with `g < -zero` exists when the pairs are
    // met), so the padding stays within the 16.
    while np % lanes != 0 && np > 0 && np < 16 {
        (pg[np], pt[np], pr[np]) = (pg[np - 1], pt[np - 1], pr[np - 1]);
        np += 1;
    }
    let mut dev2 = 0.0f64;
    for i in 0..16 {
        if dev2 > stop2 {
            return None;
        }
        if g[i].abs() <= zero {
            dev2 = dev2.max(chord_dist2(tk[i], rk[i] * rk[i], l2));
        }
        if g[i] >= -zero {
            continue;
        }
        let m = pairs_with::<WIDE>((g[i], tk[i], rk[i]), (&pg, &pt, &pr), np, l2);
        dev2 = dev2.max(m);
    }
    Some(dev2)
}

/// Largest squared distance of the crossings of point `i` (`g`, `t`,
/// `rho`) with the first `np` packed points (`np` a multiple of the lane
/// count): [`pairs4`] with `WIDE` on x86_64, else two lanes.
#[inline(always)]
fn pairs_with<const WIDE: bool>(
    (gi, ti, ri): (f64, f64, f64),
    (pg, pt, pr): (&[f64; 16], &[f64; 16], &[f64; 16]),
    np: usize,
    l2: f64,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        // SAFETY: WIDE is only set in functions compiled for AVX2, whose
        // callers checked the CPU.
        return unsafe { pairs4((gi, ti, ri), (pg, pt, pr), np, l2) };
    }
    use crate::math::simd::F2;
    let (z, one, l2v) = (F2::splat(0.0), F2::splat(1.0), F2::splat(l2));
    let (gi, ti, ri) = (F2::splat(gi), F2::splat(ti), F2::splat(ri));
    let mut acc = z;
    for j in (0..np).step_by(2) {
        let w = gi.div(gi.sub(F2::ld(pg, j)));
        let t = ti.add(F2::ld(pt, j).sub(ti).mul(w));
        let r = ri.add(F2::ld(pr, j).sub(ri).mul(w));
        let over = t.min_sel(z).add(t.sub(one).max_sel(z));
        acc = r.mul(r).add(over.mul(over).mul(l2v)).max_into(acc);
    }
    acc.lo().max(acc.hi())
}

/// [`pairs_with`] on four lanes (`np` a multiple of 4, at most 16).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn pairs4(
    (gi, ti, ri): (f64, f64, f64),
    (pg, pt, pr): (&[f64; 16], &[f64; 16], &[f64; 16]),
    np: usize,
    l2: f64,
) -> f64 {
    use core::arch::x86_64::*;
    let (z, one, l2v) = (_mm256_setzero_pd(), _mm256_set1_pd(1.0), _mm256_set1_pd(l2));
    let (gi, ti, ri) = (_mm256_set1_pd(gi), _mm256_set1_pd(ti), _mm256_set1_pd(ri));
    let mut acc = z;
    for j in (0..np.min(16)).step_by(4) {
        // SAFETY: j + 4 <= 16 (np a multiple of 4, at most 16).
        let (gj, tj, rj) = unsafe {
            (
                _mm256_loadu_pd(pg.as_ptr().add(j)),
                _mm256_loadu_pd(pt.as_ptr().add(j)),
                _mm256_loadu_pd(pr.as_ptr().add(j)),
            )
        };
        let w = _mm256_div_pd(gi, _mm256_sub_pd(gi, gj));
        let t = _mm256_add_pd(ti, _mm256_mul_pd(_mm256_sub_pd(tj, ti), w));
        let r = _mm256_add_pd(ri, _mm256_mul_pd(_mm256_sub_pd(rj, ri), w));
        // MINPD / MAXPD: the second operand on ties and NaNs, as
        // `F2::min_sel` / `F2::max_sel`.
        let over = _mm256_add_pd(_mm256_min_pd(t, z), _mm256_max_pd(_mm256_sub_pd(t, one), z));
        let v = _mm256_add_pd(
            _mm256_mul_pd(r, r),
            _mm256_mul_pd(_mm256_mul_pd(over, over), l2v),
        );
        // The new values first: a NaN lane keeps the maximum so far.
        acc = _mm256_max_pd(v, acc);
    }
    let mut lanes = [0.0f64; 4];
    // SAFETY: four values into four.
    unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), acc) };
    lanes[0].max(lanes[1]).max(lanes[2]).max(lanes[3])
}

/// What one layer makes of one cell.
enum Step {
    /// No section in the cell (or the cell is done for this layer).
    Done,
    /// A segment or node to emit.
    Emit(SliceSegment),
    /// Section present but unresolvable (tangent plane, cell below eps).
    Unresolved,
    /// Split the cell; `true` when a leaf attempt was far from passing
    /// (the children skip theirs, see [`FAR`]).
    Split(bool),
}

/// The decision of the walk for cell `c` and the layer `ly` at height
/// `h = ly.h` (for polynomial cells: `d[k] = n . P_k`, `dmag` the largest
/// coordinate magnitude of the net, `mono` whether `g = d - h` is
/// strictly monotone along s or t, which does not depend on `h`;
/// `try_leaf` false skips the leaf attempt, see [`FAR`]).
fn step(c: &Cell, ly: &Layer, d: &[f64; 16], dmag: f64, mono: bool, try_leaf: bool) -> Step {
    let h = ly.h;
    let mut far = false;
    match c.bound {
        Bound::Ball {
            center,
            radius,
            eigen,
            ..
        } => {
            let dd = ly.n.dot(center) - h;
            if dd.abs() > radius * (1.0 + 1e-12) + 1e-15 * center.abs().max_element() + ly.r {
                return Step::Done;
            }
            // A node only once the eigen ball is small: a ball that is
            // small only by the control-point hull is a coarse corner
            // region, which can hold several arcs (`Bound::Ball`).
            if 2.0 * (eigen + ly.r) <= ly.eps {
                return Step::Emit(node(ly, center, eigen + ly.r));
            }
        }
        Bound::Net => {
            let mut g = [0.0; 16];
            for (gk, dk) in g.iter_mut().zip(d) {
                *gk = dk - h;
            }
            let zero = 1e-13 * dmag.max(h.abs());
            let s0 = pos(g[0], zero);
            if g.iter().all(|&x| pos(x, zero) == s0) {
                return Step::Done;
            }
            if try_leaf && mono && sides_ok(&g, zero) {
                match leaf_segment(c, &g, zero, dmag, ly) {
                    Leaf::Empty => return Step::Done,
                    Leaf::Chord(s, dev) if dev <= ly.eps => return Step::Emit(s),
                    Leaf::Chord(_, dev) => far = dev == f64::INFINITY,
                    Leaf::Complex => {}
                }
            }
            let (lo, hi) = c.aabb();
            if (hi - lo).length() <= ly.eps && c.level >= MAX_LEVEL - 8 {
                return Step::Unresolved;
            }
        }
        Bound::Hull { lo, hi, radius } => {
            let centre = 0.5 * (lo + hi);
            let slack = 1e-15 * centre.abs().max_element() + ly.r;
            let (gl, gh) = box_range(ly.n, lo, hi);
            let dd = ly.n.dot(centre) - h;
            if dd.abs() > radius * (1.0 + 1e-12) + slack || gl - h > slack || gh - h < -slack {
                return Step::Done;
            }
            if 2.0 * (radius + ly.r) <= ly.eps {
                return Step::Emit(node(ly, centre, radius + ly.r));
            }
        }
        Bound::None => {}
    }
    Step::Split(far)
}

/// An extraordinary-vertex (or hull) node at `p` of radius `radius`.
fn node(ly: &Layer, p: DVec3, radius: f64) -> SliceSegment {
    let q = [p.dot(ly.e1), p.dot(ly.e2)];
    SliceSegment {
        a: q,
        b: q,
        next: NONE,
        flags: NODE,
        radius,
    }
}

/// Whether `g` (up to a constant) is strictly monotone along s (`dir` 0)
/// or t (`dir` 1) over the cell: its derivative net has one strict sign.
fn monotone(g: &[f64; 16], dir: usize) -> bool {
    let (mut p, mut m) = (true, true);
    for a in 0..4 {
        for b in 0..4 {
            let (na, nb) = if dir == 0 { (a + 1, b) } else { (a, b + 1) };
            if na > 3 || nb > 3 {
                continue;
            }
            let x = g[na * 4 + nb] - g[a * 4 + b];
            p &= x > 0.0;
            m &= x < 0.0;
        }
    }
    p || m
}

/// Every side's cubic has at most one sign change.
fn sides_ok(g: &[f64; 16], zero: f64) -> bool {
    [
        [g[0], g[4], g[8], g[12]],
        [g[12], g[13], g[14], g[15]],
        [g[3], g[7], g[11], g[15]],
        [g[0], g[1], g[2], g[3]],
    ]
    .iter()
    .all(|&s| changes(s, zero) <= 1)
}

/// A leaf attempt whose chord deviation exceeds `FAR eps` makes the
/// children skip theirs for that layer (they are split at once; the
/// grandchildren try again): the deviation is second order in the cell
/// size, so the children's is about a quarter of the parent's, still above
/// `eps`. A heuristic of work only: a skipped attempt can only make
/// leaves smaller, never wrong.
const FAR: f64 = 8.0;

/// Most layers one walk serves (one bit each in a cell's layer mask).
pub const MAX_BAND: usize = 64;

/// Walks the cells once for the layers `lys` (at most [`MAX_BAND`], one
/// plane normal; each with its height, eps and rounding term, the cell
/// budget of the first) and calls `emit(k, s)`
/// with every segment and node of layer `k`; adds each layer's unresolved
/// cells to `unresolved[k]`.
///
/// Every cell carries the mask of the layers that still need it: a layer
/// whose decision at a cell (drop, leaf, node, unresolved) is final leaves
/// the mask, the others go down to the four children, which are made once
/// for all of them. Each layer's decision at a cell is the one-layer
/// walk's, so each layer sees exactly the cells and produces exactly the
/// segments of its own walk; the shared part is the descent (splits and
/// nets) above the cells where the layers part.
fn walk_band<S: CellSurface + ?Sized>(
    surf: &S,
    lys: &[Layer],
    work: &mut QueryWork,
    unresolved: &mut [usize],
    mut emit: impl FnMut(usize, SliceSegment),
) -> Result<(), Error> {
    debug_assert!(!lys.is_empty() && lys.len() <= MAX_BAND && unresolved.len() >= lys.len());
    let ly = &lys[0];
    let stack = &mut work.stack;
    // Per pending cell: the layers that need it, and those of them whose
    // leaf attempt is skipped (see [`FAR`]).
    let mut masks = [0u64; STACK_CAP];
    let mut skips = [0u64; STACK_CAP];
    let full = if lys.len() == MAX_BAND {
        u64::MAX
    } else {
        (1u64 << lys.len()) - 1
    };
    // Whether the heights rise (or fall) with the layer index, as a
    // stack's do, and their largest magnitude: a net cell then skips the
    // layers outside its range of `d` at once (`crossing`).
    let hs = |k: usize| lys[k].h;
    let rising = (1..lys.len()).all(|k| hs(k - 1) <= hs(k));
    let falling = (1..lys.len()).all(|k| hs(k - 1) >= hs(k));
    let hmax = (0..lys.len()).fold(0.0f64, |m, k| m.max(hs(k).abs()));
    let crossing = |lo: f64, hi: f64, dmag: f64| -> u64 {
        // Layers with `h <= lo` have every `g >= 0`, layers with
        // `h > hi + z` every `g < -z / 2 <= -zero` (`z` twice the largest
        // `zero`); both are skipped by the exact test below, so only the
        // others need it.
        let z = 2e-13 * dmag.max(hmax);
        let top = hi + z;
        let (a, b) = if rising {
            (
                lys.partition_point(|l| l.h <= lo),
                lys.partition_point(|l| l.h <= top),
            )
        } else if falling {
            (
                lys.partition_point(|l| l.h > top),
                lys.partition_point(|l| l.h > lo),
            )
        } else {
            return u64::MAX;
        };
        let below = |i: usize| if i >= 64 { u64::MAX } else { (1u64 << i) - 1 };
        below(b) & !below(a)
    };
    let mut kids = [Cell::ZERO; 4];
    let mut d = [0.0; 16];
    let mut visited = 0u64;
    // The band's heights, for the slot index (`index.rs`): a slot whose
    // box lies beyond every layer by more than the walk's own margins
    // (eps, rounding, the `zero` of the sign tests) holds no section.
    let hlo = (0..lys.len()).fold(f64::INFINITY, |m, k| m.min(hs(k)));
    let hhi = (0..lys.len()).fold(f64::NEG_INFINITY, |m, k| m.max(hs(k)));
    let mut visit = |v: Visit| -> Result<Option<f64>, Error> {
        let (face, sub) = match v {
            Visit::Box(lo, hi) => {
                if !(lo.is_finite() && hi.is_finite()) {
                    return Ok(Some(0.0));
                }
                let (gl, gh) = box_range(ly.n, lo, hi);
                let mag = lo.abs().max(hi.abs()).max_element().max(hmax);
                let slack = ly.eps + ly.r + 1e-12 * mag;
                return Ok((gh >= hlo - slack && gl <= hhi + slack).then_some(0.0));
            }
            Visit::Slot(face, sub) => (face, sub),
        };
        stack.clear();
        masks[0] = full;
        skips[0] = 0;
        stack.push(surf.root(face, sub));
        while let Some(c) = stack.pop() {
            visited += 1;
            if visited > ly.max_cells {
                return Err(Error::WorkLimitExceeded {
                    limit: ly.max_cells,
                    what: "cells of a slice walk (SliceOptions::max_cells)",
                });
            }
            let mut mask = masks[stack.len()];
            let skip = skips[stack.len()];
            let mut dmag = 0.0f64;
            let mut mono = false;
            // The range of `d` over a net (`None` where a value is NaN),
            // for the layers that miss the cell (below).
            let mut range = None;
            if c.bound == Bound::Net {
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                let mut nan = false;
                for (k, dk) in d.iter_mut().enumerate() {
                    let p = c.point(k);
                    dmag = dmag.max(p.abs().max_element());
                    *dk = ly.n.dot(p);
                    nan |= dk.is_nan();
                    lo = lo.min(*dk);
                    hi = hi.max(*dk);
                }
                mono = monotone(&d, 0) || monotone(&d, 1);
                range = (!nan).then_some((lo, hi));
            }
            if let Some((lo, hi)) = range {
                mask &= crossing(lo, hi, dmag);
            }
            let (mut split, mut far) = (0u64, 0u64);
            while mask != 0 {
                let k = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                // `step`'s first test on a net, from the range: all
                // `g = d - h` on one side of `-zero` (rounding is
                // monotone, so the extreme `g` are `lo - h` and
                // `hi - h`): no section, the same decision.
                if let Some((lo, hi)) = range {
                    let h = lys[k].h;
                    let zero = 1e-13 * dmag.max(h.abs());
                    if lo - h >= -zero || hi - h < -zero {
                        continue;
                    }
                }
                let try_leaf = skip & (1 << k) == 0;
                match step(&c, &lys[k], &d, dmag, mono, try_leaf) {
                    Step::Done => {}
                    Step::Emit(s) => emit(k, s),
                    Step::Unresolved => unresolved[k] += 1,
                    Step::Split(f) => {
                        split |= 1 << k;
                        far |= (f as u64) << k;
                    }
                }
            }
            if split == 0 {
                continue;
            }
            if c.level >= MAX_LEVEL || !stack.room(4) || surf.at_floor(&c) {
                return Err(Error::InvalidArgument(
                    "slice reached the deepest cell level",
                ));
            }
            surf.split(&c, &mut kids);
            for k in kids {
                masks[stack.len()] = split;
                skips[stack.len()] = far;
                stack.push(k);
            }
        }
        Ok(None)
    };
    index::in_order(surf, &mut visit)
}

/// Walks the cells for one layer (a band of one).
fn walk<S: CellSurface + ?Sized>(
    surf: &S,
    ly: &Layer,
    work: &mut QueryWork,
    mut emit: impl FnMut(SliceSegment),
) -> Result<usize, Error> {
    let mut unresolved = [0usize; 1];
    walk_band(surf, &[*ly], work, &mut unresolved, |_, s| emit(s))?;
    Ok(unresolved[0])
}

fn layer<S: CellSurface + ?Sized>(
    surf: &S,
    plane: &Plane,
    opts: &SliceOptions,
) -> Result<Layer, Error> {
    layer_of(surf.magnitude(), plane, opts)
}

/// [`layer`] of a surface of magnitude `mag` ([`CellSurface::magnitude`]).
fn layer_of(mag: f64, plane: &Plane, opts: &SliceOptions) -> Result<Layer, Error> {
    let (n, e1, e2) = plane.frame()?;
    if !(opts.eps > 0.0 && opts.eps.is_finite()) {
        return Err(Error::InvalidArgument("eps must be positive"));
    }
    let r = super::rounding::term_of(mag, plane.offset.abs())?;
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
    segs.sort_unstable_by(order);
    let (points, contours) = chain(segs, &ly)?;
    Ok(SliceStats {
        points,
        contours,
        segments: n,
        unresolved,
    })
}

/// The order the chaining works in: by start point, then end point (a
/// total order on distinct segments, so the contours' first points do not
/// depend on the walk's emission order).
fn order(x: &SliceSegment, y: &SliceSegment) -> core::cmp::Ordering {
    x.a[0]
        .total_cmp(&y.a[0])
        .then(x.a[1].total_cmp(&y.a[1]))
        .then(x.b[0].total_cmp(&y.b[0]))
        .then(x.b[1].total_cmp(&y.b[1]))
}

/// Largest gap, as a share of eps, between a segment's end and the next
/// segment's start that chaining closes (see [`chain`]).
const JOIN: f64 = 1e-3;

/// Chains one layer's segments (sorted by [`order`]) into closed
/// contours; returns the numbers of points and contours.
fn chain(segs: &mut [SliceSegment], ly: &Layer) -> Result<(usize, usize), Error> {
    let n = segs.len();
    let mag = segs
        .iter()
        .map(|s| s.a[0].abs().max(s.a[1].abs()))
        .fold(ly.h.abs(), f64::max);
    // Two cells compute a shared side's root each from its own net: the
    // roots agree to rounding in `g`, which moves a root along the side by
    // rounding / |g'|, far more than rounding where the side is nearly
    // tangent to the plane (measured: 1e-11 apart at eps 8e-6 on
    // catmark_righthanded). Ends closer than `JOIN eps` are one point:
    // both are section points (up to the rounding term), so the short gap
    // between them stays within `JOIN eps` of the section.
    let stol = (JOIN * ly.eps).max(1e-12 * mag);
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
    count(segs)
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

/// The sections of the layers `first .. first + stats.len()` of `stack`
/// (at most [`MAX_BAND`]) in one walk: the segments of all of them go to
/// the scratch `segs`, grouped by layer in order and chained per layer as
/// [`super::slice_layer`] chains one; `stats[i]` receives layer
/// `first + i`'s numbers, and [`band_layer`] cuts its segments out of
/// `segs` for [`super::slice_write`]. Each layer's contours are those of
/// [`super::slice_layer`] on `stack.layer(first + i)` (the same cells,
/// segments and chaining). Returns the scratch entries used; a shorter
/// `segs` (an empty one is the size query) is [`Error::BufferTooSmall`]
/// with the exact count.
pub(crate) fn slice_band<S: CellSurface + ?Sized>(
    surf: &S,
    stack: &PlaneStack,
    first: usize,
    opts: &SliceOptions,
    work: &mut QueryWork,
    segs: &mut [SliceSegment],
    stats: &mut [SliceStats],
) -> Result<usize, Error> {
    let count = stats.len();
    if count == 0 || count > MAX_BAND {
        return Err(Error::InvalidArgument(
            "a band holds 1 to 64 layers (query::MAX_BAND)",
        ));
    }
    if !stack.step.is_finite() {
        return Err(Error::InvalidArgument("plane stack step must be finite"));
    }
    // Each layer with its own rounding term and inner eps (what its
    // one-layer walk uses), so every layer's decisions are its own.
    let mag = surf.magnitude();
    let mut lys = [layer_of(mag, &stack.layer(first), opts)?; MAX_BAND];
    for (i, l) in lys.iter_mut().take(count).enumerate().skip(1) {
        let plane = stack.layer(first + i);
        if !plane.offset.is_finite() {
            return Err(Error::InvalidArgument("plane stack offset must be finite"));
        }
        *l = layer_of(mag, &plane, opts)?;
    }
    let mut unresolved = [0usize; MAX_BAND];
    let mut per = [0usize; MAX_BAND];
    let mut n = 0usize;
    walk_band(surf, &lys[..count], work, &mut unresolved, |k, mut s| {
        if let Some(d) = segs.get_mut(n) {
            s.next = k as u32;
            *d = s;
        }
        per[k] += 1;
        n += 1;
    })?;
    if n > segs.len() {
        return Err(Error::BufferTooSmall { required: n });
    }
    let segs = &mut segs[..n];
    group_by_layer(segs, &per[..count]);
    let mut at = 0;
    for (k, st) in stats.iter_mut().enumerate() {
        let part = &mut segs[at..at + per[k]];
        for s in part.iter_mut() {
            s.next = NONE;
        }
        part.sort_unstable_by(order);
        let (points, contours) = chain(part, &lys[k])?;
        *st = SliceStats {
            points,
            contours,
            segments: per[k],
            unresolved: unresolved[k],
        };
        at += per[k];
    }
    Ok(n)
}

/// Puts the segments (layer index in `next`, `per[k]` of layer `k`) in
/// layer order, in place: a counting sort that swaps each segment to the
/// next free place of its layer's range (linear, no memory).
fn group_by_layer(segs: &mut [SliceSegment], per: &[usize]) {
    let mut start = [0usize; MAX_BAND];
    let mut fill = [0usize; MAX_BAND];
    let mut at = 0;
    for (k, &c) in per.iter().enumerate() {
        start[k] = at;
        fill[k] = at;
        at += c;
    }
    for k in 0..per.len() {
        let end = start[k] + per[k];
        while fill[k] < end {
            let i = fill[k];
            let l = segs[i].next as usize;
            if l == k {
                fill[k] += 1;
            } else {
                segs.swap(i, fill[l]);
                fill[l] += 1;
            }
        }
    }
}

/// Layer `i`'s part of the scratch [`super::slice_band`] filled (`stats` = its
/// statistics): the `segs` argument of [`super::slice_write`] for that
/// layer.
pub fn band_layer<'s>(
    segs: &'s mut [SliceSegment],
    stats: &[SliceStats],
    i: usize,
) -> &'s mut [SliceSegment] {
    let start: usize = stats[..i].iter().map(|s| s.segments).sum();
    &mut segs[start..start + stats[i].segments]
}

#[cfg(test)]
mod tests {
    use super::{pair_deviation, planar_body, planar_deviation};
    use crate::test_rng::XorShift;

    #[test]
    fn vector_pairs_are_the_scalar_loop_bit_for_bit() {
        let mut rng = XorShift(0x005a_1ce5);
        let cases = if cfg!(miri) { 300 } else { 200_000 };
        let (mut far, mut near) = (0, 0);
        for case in 0..cases {
            let zero = [0.0, 1e-13, 1e-3][case % 3];
            let mut g = [0.0; 16];
            for x in &mut g {
                // Signs of both kinds, some within `zero`, some exactly
                // zero or minus zero.
                *x = match rng.next_u64() % 8 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => zero * (2.0 * rng.unit() - 1.0),
                    _ => 2.0 * rng.unit() - 1.0,
                };
            }
            // `t` on both sides of [0, 1] and at its ends.
            let tk: [f64; 16] = core::array::from_fn(|_| match rng.next_u64() % 6 {
                0 => 0.0,
                1 => 1.0,
                _ => 3.0 * rng.unit() - 1.0,
            });
            let rk: [f64; 16] = core::array::from_fn(|_| 1e-2 * (2.0 * rng.unit() - 1.0));
            let l2 = rng.unit() * 4.0;
            let stop2 = [f64::INFINITY, 1e-5, 1e-4 * rng.unit()][case % 3];
            let want = pair_deviation(&g, zero, &tk, &rk, l2, stop2);
            let want = want.map(f64::to_bits);
            // The dispatched kernel (four lanes where the CPU runs AVX2)
            // and the two-lane one.
            let got = planar_deviation(&g, zero, &tk, &rk, l2, stop2);
            assert_eq!(got.map(f64::to_bits), want, "case {case}");
            let got = planar_body::<false>(&g, zero, &tk, &rk, l2, stop2);
            assert_eq!(got.map(f64::to_bits), want, "case {case}, two lanes");
            match want {
                None => far += 1,
                Some(_) => near += 1,
            }
        }
        // Both outcomes met (the stop is exercised).
        assert!(far > 0 && near > 0, "far {far} near {near}");
    }
}
