//! One triangle cut by its intersection segments: the chains of segments
//! from boundary point to boundary point split the triangle's boundary
//! cycle (corners and the points on its sides, in order along each side)
//! into polygons; each polygon is classified by the chain segment on its
//! boundary (inside or outside the other solid, from the other triangle's
//! normal) and triangulated by ear clipping in the triangle's plane. No
//! new vertices: every polygon edge is a piece of a side (whose points are
//! shared with the neighbouring triangle) or a chain segment (shared with
//! the other solid), so the pieces of all triangles close up.

use crate::error::Error;
use glam::DVec3;

/// Flag of a point reference (else a vertex of the mesh).
pub const POINT: u32 = 1 << 31;
/// Segments per triangle.
pub const MAX_SEGS: usize = 96;
/// Polygon vertex references per triangle (all polygons together).
const MAX_REFS: usize = 8 * MAX_SEGS + 16;
/// Polygons per triangle.
const MAX_POLYS: usize = MAX_SEGS + 2;

/// Working arrays of [`split`], made once by the caller and reused for
/// every cut triangle (each call writes before it reads, only the prefix it
/// uses), so a triangle costs no zero-filling of the full capacities.
pub struct Scratch {
    refs: [u32; MAX_REFS],
    polys: [(usize, usize); MAX_POLYS],
    alive: [bool; MAX_POLYS],
    order: [usize; 2 * MAX_SEGS + 4],
    used: [bool; MAX_SEGS],
    chain: [u32; MAX_SEGS + 1],
    idx: [usize; MAX_REFS],
}

impl Scratch {
    /// Fresh working arrays (about 13 KB).
    pub const fn new() -> Self {
        Self {
            refs: [0; MAX_REFS],
            polys: [(0, 0); MAX_POLYS],
            alive: [false; MAX_POLYS],
            order: [0; 2 * MAX_SEGS + 4],
            used: [false; MAX_SEGS],
            chain: [0; MAX_SEGS + 1],
            idx: [0; MAX_REFS],
        }
    }
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

/// A segment inside the triangle: two point references and the other
/// triangle's index and normal.
#[derive(Clone, Copy, Debug, Default)]
pub struct Seg {
    /// Point references (with [`POINT`]).
    pub p: [u32; 2],
    /// The other triangle.
    pub other: u32,
}

/// A point on one of the triangle's sides.
#[derive(Clone, Copy, Debug, Default)]
pub struct SidePoint {
    /// Point reference.
    pub r: u32,
    /// Side (0..3).
    pub side: u8,
    /// Sort key along the side from its first corner: the edge's
    /// canonical parameter, negated on the side running against the
    /// canonical direction (negation is exact, so both triangles of the
    /// edge see the same order, reversed).
    pub t: f64,
    /// Tie break in the same sense (`r` or `!r`).
    pub tie: u32,
}

/// What the caller provides about the triangle.
pub struct Cut<'s> {
    /// Vertex references of the corners.
    pub corners: [u32; 3],
    /// The segments.
    pub segs: &'s [Seg],
    /// The points on the sides.
    pub side_points: &'s [SidePoint],
}

/// Splits and classifies: `outside(seg, from, to)` says whether the
/// polygon left of the directed chain segment lies outside the other
/// solid; `pos(ref)` gives positions; `emit(tri, outside)` receives each
/// triangle (counter-clockwise as the input triangle) with its class.
/// Returns the class of the polygon holding each side with no points
/// (`None` for sides with points).
pub fn split(
    cut: &Cut,
    normal: DVec3,
    pos: &impl Fn(u32) -> DVec3,
    outside: &impl Fn(&Seg, u32, u32) -> bool,
    scratch: &mut Scratch,
    emit: &mut impl FnMut([u32; 3], bool),
) -> Result<[Option<bool>; 3], &'static str> {
    let Scratch {
        refs,
        polys,
        alive,
        order,
        used,
        chain,
        idx,
    } = scratch;
    alive[0] = true;
    let mut npoly = 1;
    // Boundary cycle: corner k, then the points of side k by parameter.
    let mut n = 0;
    let nsp = cut.side_points.len();
    if nsp > order.len() {
        return Err("too many crossings in one triangle");
    }
    for (i, o) in order.iter_mut().enumerate().take(nsp) {
        *o = i;
    }
    order[..nsp].sort_unstable_by(|&x, &y| {
        let (a, b) = (&cut.side_points[x], &cut.side_points[y]);
        (a.side, a.t, a.tie)
            .partial_cmp(&(b.side, b.t, b.tie))
            .unwrap_or(core::cmp::Ordering::Equal)
    });
    let mut j = 0;
    for k in 0..3u8 {
        refs[n] = cut.corners[k as usize];
        n += 1;
        while j < nsp && cut.side_points[order[j]].side == k {
            refs[n] = cut.side_points[order[j]].r;
            n += 1;
            j += 1;
        }
    }
    polys[0] = (0, n);
    let is_side_point = |r: u32| cut.side_points.iter().any(|p| p.r == r);
    // Chains: from each side point along unused segments to another.
    let segs = cut.segs;
    if segs.len() > MAX_SEGS {
        return Err("too many crossings in one triangle");
    }
    used[..segs.len()].fill(false);
    for sp in cut.side_points {
        let start = sp.r;
        if segs
            .iter()
            .enumerate()
            .all(|(i, s)| used[i] || !s.p.contains(&start))
        {
            continue; // already the end of a chain
        }
        let mut len = 0;
        chain[len] = start;
        len += 1;
        let mut at = start;
        loop {
            let Some(i) = (0..segs.len()).find(|&i| !used[i] && segs[i].p.contains(&at)) else {
                return Err("an intersection chain ends inside a triangle");
            };
            used[i] = true;
            at = if segs[i].p[0] == at {
                segs[i].p[1]
            } else {
                segs[i].p[0]
            };
            if len > MAX_SEGS {
                return Err("too many crossings in one triangle");
            }
            chain[len] = at;
            len += 1;
            if is_side_point(at) {
                break;
            }
        }
        let end = at;
        // The polygon holding both ends on its boundary.
        let Some(pi) = (0..npoly).find(|&p| {
            alive[p] && {
                let (s, l) = polys[p];
                refs[s..s + l].contains(&start) && refs[s..s + l].contains(&end)
            }
        }) else {
            return Err("intersection chains cross inside a triangle");
        };
        let (s, l) = polys[pi];
        let is = (0..l).find(|&i| refs[s + i] == start).unwrap_or(0);
        let ie = (0..l).find(|&i| refs[s + i] == end).unwrap_or(0);
        if n + 2 * (l + len) > MAX_REFS || npoly + 2 > MAX_POLYS {
            return Err("too many crossings in one triangle");
        }
        // First: start .. end along the polygon, then the chain back.
        let s1 = n;
        let mut i = is;
        loop {
            refs[n] = refs[s + i];
            n += 1;
            if i == ie {
                break;
            }
            i = (i + 1) % l;
        }
        for c in (1..len - 1).rev() {
            refs[n] = chain[c];
            n += 1;
        }
        polys[npoly] = (s1, n - s1);
        // Second: end .. start along the polygon, then the chain forward.
        let s2 = n;
        let mut i = ie;
        loop {
            refs[n] = refs[s + i];
            n += 1;
            if i == is {
                break;
            }
            i = (i + 1) % l;
        }
        for c in chain.iter().take(len - 1).skip(1) {
            refs[n] = *c;
            n += 1;
        }
        polys[npoly + 1] = (s2, n - s2);
        alive[npoly] = true;
        alive[npoly + 1] = true;
        alive[pi] = false;
        npoly += 2;
    }
    // Closed loops inside the triangle: the disk, and the polygon around it
    // cut into two by two bridges.
    let p2 = projector(normal, pos);
    while let Some(s0) = (0..segs.len()).find(|&i| !used[i]) {
        let mut len = 0;
        let mut at = segs[s0].p[0];
        while let Some(i) = (0..segs.len()).find(|&i| !used[i] && segs[i].p.contains(&at)) {
            used[i] = true;
            if len >= MAX_SEGS {
                return Err("too many crossings in one triangle");
            }
            chain[len] = at;
            len += 1;
            at = if segs[i].p[0] == at {
                segs[i].p[1]
            } else {
                segs[i].p[0]
            };
        }
        if at != chain[0] || len < 3 {
            return Err("an intersection chain ends inside a triangle");
        }
        let lp = &mut chain[..len];
        if signed_area(lp, &p2) < 0.0 {
            lp.reverse();
        }
        let Some(pi) = (0..npoly).find(|&p| {
            alive[p] && {
                let (s, l) = polys[p];
                contains(&refs[s..s + l], p2(lp[0]), &p2)
            }
        }) else {
            return Err("a closed intersection loop lies outside every piece");
        };
        let (s, l) = polys[pi];
        if n + 2 * (l + len) + len + 8 > MAX_REFS || npoly + 3 > MAX_POLYS {
            return Err("too many crossings in one triangle");
        }
        let (poly, rest) = refs.split_at_mut(n);
        let outer = &poly[s..s + l];
        let Some((i1, j1)) = bridge(outer, lp, None, &p2) else {
            return Err("no bridge to a closed intersection loop");
        };
        let Some((i2, j2)) = bridge(outer, lp, Some((i1, j1)), &p2) else {
            return Err("no bridge to a closed intersection loop");
        };
        let mut w = 0;
        // Disk.
        let d0 = n + w;
        for &r in lp.iter() {
            rest[w] = r;
            w += 1;
        }
        polys[npoly] = (d0, len);
        // Outer from i1 to i2, loop backwards from j2 to j1.
        for (from, to, lf, lt, slot) in [(i1, i2, j2, j1, 1), (i2, i1, j1, j2, 2)] {
            let st = n + w;
            let mut i = from;
            loop {
                rest[w] = outer[i];
                w += 1;
                if i == to {
                    break;
                }
                i = (i + 1) % l;
            }
            let mut j = lf;
            loop {
                rest[w] = lp[j];
                w += 1;
                if j == lt {
                    break;
                }
                j = (j + len - 1) % len;
            }
            polys[npoly + slot] = (st, n + w - st);
        }
        n += w;
        alive[npoly..npoly + 3].fill(true);
        alive[pi] = false;
        npoly += 3;
    }
    // Classify, triangulate, and record the sides' classes.
    let mut side_class = [None; 3];
    for p in 0..npoly {
        if !alive[p] {
            continue;
        }
        let (s, l) = polys[p];
        let poly = &refs[s..s + l];
        let mut class = None;
        let mut best = -1.0;
        for i in 0..l {
            let (u, v) = (poly[i], poly[(i + 1) % l]);
            if let Some(seg) = segs.iter().find(|g| g.p == [u, v] || g.p == [v, u]) {
                let len = (pos(v) - pos(u)).length();
                if len > best {
                    best = len;
                    class = Some(outside(seg, u, v));
                }
            }
        }
        let Some(class) = class else {
            return Err("a piece of a cut triangle touches no intersection segment");
        };
        for k in 0..3 {
            let (c0, c1) = (cut.corners[k], cut.corners[(k + 1) % 3]);
            if (0..l).any(|i| poly[i] == c0 && poly[(i + 1) % l] == c1) {
                side_class[k] = Some(class);
            }
        }
        ear_clip(poly, normal, pos, idx, &mut |t| emit(t, class));
    }
    Ok(side_class)
}

/// Ear clipping of a simple polygon (counter-clockwise about `normal`),
/// `l - 2` triangles over its own vertices.
fn ear_clip(
    poly: &[u32],
    normal: DVec3,
    pos: &impl Fn(u32) -> DVec3,
    idx: &mut [usize; MAX_REFS],
    emit: &mut impl FnMut([u32; 3]),
) {
    let l = poly.len();
    for (i, x) in idx.iter_mut().enumerate().take(l) {
        *x = i;
    }
    let p2 = projector(normal, pos);
    let mut m = l;
    while m > 3 {
        let mut pick = None;
        let mut best = (f64::NEG_INFINITY, 0);
        for i in 0..m {
            let (ip, ic, inx) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            let (a, b, c) = (p2(poly[ip]), p2(poly[ic]), p2(poly[inx]));
            let cr = cross(a, b, c);
            if cr > best.0 {
                best = (cr, i);
            }
            if cr <= 0.0 {
                continue;
            }
            let blocked = (0..m).any(|j| {
                let q = idx[j];
                if q == ip || q == ic || q == inx {
                    return false;
                }
                let p = p2(poly[q]);
                cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0
            });
            if !blocked {
                pick = Some(i);
                break;
            }
        }
        // No strict ear (rounding on near-degenerate pieces): clip the most
        // convex corner; the topology stays closed either way.
        let i = pick.unwrap_or(best.1);
        emit([
            poly[idx[(i + m - 1) % m]],
            poly[idx[i]],
            poly[idx[(i + 1) % m]],
        ]);
        for j in i..m - 1 {
            idx[j] = idx[j + 1];
        }
        m -= 1;
    }
    emit([poly[idx[0]], poly[idx[1]], poly[idx[2]]]);
}

/// Maps a splitting failure of triangle `t` to the error.
pub fn degenerate(ta: u32, tb: u32, what: &'static str) -> Error {
    Error::DegenerateContact {
        triangle_a: ta,
        triangle_b: tb,
        what,
    }
}

type P2 = (f64, f64);

fn cross(o: P2, a: P2, b: P2) -> f64 {
    (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
}

/// Projection to the plane by dropping the dominant axis of `normal`,
/// counter-clockwise about `normal` staying counter-clockwise.
fn projector<'p>(normal: DVec3, pos: &'p impl Fn(u32) -> DVec3) -> impl Fn(u32) -> P2 + 'p {
    let a = normal.abs();
    let (ax, ay, flip) = if a.z >= a.x && a.z >= a.y {
        (0, 1, normal.z < 0.0)
    } else if a.x >= a.y {
        (1, 2, normal.x < 0.0)
    } else {
        (2, 0, normal.y < 0.0)
    };
    move |r: u32| {
        let p = pos(r);
        let (x, y) = (p[ax], p[ay]);
        if flip {
            (x, -y)
        } else {
            (x, y)
        }
    }
}

fn signed_area(poly: &[u32], p2: &impl Fn(u32) -> P2) -> f64 {
    let l = poly.len();
    (0..l)
        .map(|i| {
            let (a, b) = (p2(poly[i]), p2(poly[(i + 1) % l]));
            a.0 * b.1 - a.1 * b.0
        })
        .sum::<f64>()
}

/// Point in polygon by crossing parity.
fn contains(poly: &[u32], q: P2, p2: &impl Fn(u32) -> P2) -> bool {
    let l = poly.len();
    let mut inside = false;
    for i in 0..l {
        let (a, b) = (p2(poly[i]), p2(poly[(i + 1) % l]));
        if (a.1 > q.1) != (b.1 > q.1) {
            let x = a.0 + (q.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if x > q.0 {
                inside = !inside;
            }
        }
    }
    inside
}

/// Do segments `a b` and `c d` cross properly?
fn crosses(a: P2, b: P2, c: P2, d: P2) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
}

/// The shortest segment from a vertex of `outer` to a vertex of the loop
/// `lp` that crosses no edge of either (nor the first bridge, whose ends it
/// must not share) and whose midpoint lies between them.
fn bridge(
    outer: &[u32],
    lp: &[u32],
    first: Option<(usize, usize)>,
    p2: &impl Fn(u32) -> P2,
) -> Option<(usize, usize)> {
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..outer.len() {
        for j in 0..lp.len() {
            if let Some((fi, fj)) = first {
                if fi == i || fj == j {
                    continue;
                }
            }
            let (a, b) = (p2(outer[i]), p2(lp[j]));
            let d = (a.0 - b.0) * (a.0 - b.0) + (a.1 - b.1) * (a.1 - b.1);
            if best.is_some_and(|x| x.0 <= d) {
                continue;
            }
            let hits = |poly: &[u32]| {
                let l = poly.len();
                (0..l).any(|k| {
                    let (c, e) = (p2(poly[k]), p2(poly[(k + 1) % l]));
                    crosses(a, b, c, e)
                })
            };
            if hits(outer) || hits(lp) {
                continue;
            }
            if let Some((fi, fj)) = first {
                if crosses(a, b, p2(outer[fi]), p2(lp[fj])) {
                    continue;
                }
            }
            let mid = ((a.0 + b.0) * 0.5, (a.1 + b.1) * 0.5);
            if !contains(outer, mid, p2) || contains(lp, mid, p2) {
                continue;
            }
            best = Some((d, i, j));
        }
    }
    best.map(|(_, i, j)| (i, j))
}
