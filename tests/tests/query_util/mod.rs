//! Brute-force oracles for the query tests: a dense grid of exact limit
//! points per slot, triangulated, with a plain ray-triangle caster whose
//! hits are refined by Newton's method on the exact evaluation; dense
//! sampling for closest points.

#![allow(dead_code)]

use ccss_core::{DVec3, Evaluator};
use ccss_tests::reference::PolyMesh;

/// One slot's grid: `(n+1)^2` exact points, row-major in u.
pub struct SlotGrid {
    pub face: u32,
    pub sub: u32,
    pub n: usize,
    pub pts: Vec<DVec3>,
    pub lo: DVec3,
    pub hi: DVec3,
}

/// Dense grids of every slot (`n` intervals per side).
pub fn grids(ev: &Evaluator, n: usize) -> Vec<SlotGrid> {
    let mut out = vec![];
    for f in 0..ev.num_faces() {
        for s in 0..ev.num_subfaces(f) {
            let mut pts = Vec::with_capacity((n + 1) * (n + 1));
            for a in 0..=n {
                for b in 0..=n {
                    let e = ev
                        .eval(f as u32, s as u32, a as f64 / n as f64, b as f64 / n as f64)
                        .unwrap();
                    pts.push(e.p);
                }
            }
            let lo = pts
                .iter()
                .fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
            let hi = pts
                .iter()
                .fold(DVec3::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
            // Culling margin: the surface bulges out of its point box by far
            // less than a tenth of the box.
            let m = DVec3::splat(0.1 * (hi - lo).length());
            out.push(SlotGrid {
                face: f as u32,
                sub: s as u32,
                n,
                pts,
                lo: lo - m,
                hi: hi + m,
            });
        }
    }
    out
}

/// Whether the ray meets the box `[lo, hi]` at some `t >= 0`.
fn ray_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        if d[a].abs() < 1e-300 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return false;
            }
            continue;
        }
        let (x, y) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        t0 = t0.max(x.min(y));
        t1 = t1.min(x.max(y));
    }
    t0 <= t1
}

/// Moller-Trumbore with a small barycentric slack: `(t, b1, b2)`.
fn ray_tri(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    let slack = 1e-6;
    if u < -slack || v < -slack || u + v > 1.0 + slack {
        return None;
    }
    Some((e2.dot(q) * inv, u, v))
}

/// An exact crossing found by the oracle.
#[derive(Clone, Copy, Debug)]
pub struct Crossing {
    pub t: f64,
    pub face: u32,
    pub sub: u32,
    pub u: f64,
    pub v: f64,
    /// |n . d| / |d|: how transversal.
    pub cos: f64,
}

/// Newton on `S(u, v) - o - t d = 0` from a start in slot `(f, s)`.
#[allow(clippy::too_many_arguments)]
pub fn refine(
    ev: &Evaluator,
    f: u32,
    s: u32,
    o: DVec3,
    d: DVec3,
    mut u: f64,
    mut v: f64,
    mut t: f64,
    scale: f64,
) -> Option<Crossing> {
    for _ in 0..40 {
        let e = ev.eval(f, s, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)).ok()?;
        let g = e.p - o - t * d;
        // Roots on a slot's side may sit a rounding error outside it.
        let inside = |x: f64| (-1e-7..=1.0 + 1e-7).contains(&x);
        if g.length() < 1e-12 * scale && inside(u) && inside(v) {
            let cos = e.normal.dot(d).abs() / d.length();
            return Some(Crossing {
                t,
                face: f,
                sub: s,
                u,
                v,
                cos,
            });
        }
        // Solve [du dv -d] x = -g.
        let (c0, c1, c2) = (e.du, e.dv, -d);
        let det = c0.dot(c1.cross(c2));
        if det.abs() < 1e-300 {
            return None;
        }
        let x0 = -g.dot(c1.cross(c2)) / det;
        let x1 = -c0.dot(g.cross(c2)) / det;
        let x2 = -c0.dot(c1.cross(g)) / det;
        u += x0;
        v += x1;
        t += x2;
        if !(-0.05..=1.05).contains(&u) || !(-0.05..=1.05).contains(&v) {
            return None;
        }
    }
    None
}

/// Every exact crossing of the ray `o + t d`, `t >= 0`, the oracle finds:
/// triangle hits of the dense grids refined by Newton (hits whose Newton
/// leaves the slot are dropped: a neighbour's triangle finds them), with
/// crossings closer than `1e-10 scale` merged.
pub fn crossings(ev: &Evaluator, gs: &[SlotGrid], o: DVec3, d: DVec3, scale: f64) -> Vec<Crossing> {
    let mut out: Vec<Crossing> = vec![];
    for g in gs {
        if !ray_box(o, d, g.lo, g.hi) {
            continue;
        }
        let n = g.n;
        let p = |a: usize, b: usize| g.pts[a * (n + 1) + b];
        for a in 0..n {
            for b in 0..n {
                let (p00, p10, p11, p01) = (p(a, b), p(a + 1, b), p(a + 1, b + 1), p(a, b + 1));
                for (tri, map) in [
                    ([p00, p10, p11], [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]),
                    ([p00, p11, p01], [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0)]),
                ] {
                    if let Some((t, b1, b2)) = ray_tri(o, d, tri[0], tri[1], tri[2]) {
                        let w0 = 1.0 - b1 - b2;
                        let cu = w0 * map[0].0 + b1 * map[1].0 + b2 * map[2].0;
                        let cv = w0 * map[0].1 + b1 * map[1].1 + b2 * map[2].1;
                        let (u, v) = ((a as f64 + cu) / n as f64, (b as f64 + cv) / n as f64);
                        if let Some(c) = refine(ev, g.face, g.sub, o, d, u, v, t, scale) {
                            if c.t >= 0.0
                                && !out
                                    .iter()
                                    .any(|x| ((x.t - c.t) * d.length()).abs() < 1e-10 * scale)
                            {
                                out.push(c);
                            }
                        }
                    }
                }
            }
        }
    }
    out.sort_by(|a, b| a.t.total_cmp(&b.t));
    out
}

/// Diagonal of the box of all grid points.
pub fn diagonal(gs: &[SlotGrid]) -> f64 {
    let lo = gs
        .iter()
        .flat_map(|g| g.pts.iter())
        .fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
    let hi = gs
        .iter()
        .flat_map(|g| g.pts.iter())
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
    (hi - lo).length()
}

/// Centre of the box of all grid points.
pub fn centre(gs: &[SlotGrid]) -> DVec3 {
    let lo = gs
        .iter()
        .flat_map(|g| g.pts.iter())
        .fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
    let hi = gs
        .iter()
        .flat_map(|g| g.pts.iter())
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
    0.5 * (lo + hi)
}

/// A prism over a wavy `n`-gon: two `n`-gon caps (valence-`n` centres
/// after one step) and `n` side quads.
pub fn prism(n: u32) -> PolyMesh {
    let mut positions = vec![];
    let mut faces = vec![];
    for z in [-1.0f64, 1.0] {
        for i in 0..n {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            let r = 1.0 + 0.2 * (3.0 * a).cos() + 0.1 * z;
            positions.push([r * a.cos(), r * a.sin(), z * (1.0 + 0.1 * a.sin())]);
        }
    }
    faces.push((0..n).rev().collect());
    faces.push((n..2 * n).collect());
    for i in 0..n {
        let j = (i + 1) % n;
        faces.push(vec![i, j, n + j, n + i]);
    }
    PolyMesh { positions, faces }
}

/// The closed test meshes: corpus shapes with extraordinary vertices of
/// valences 3, 5, 6 and n-gons, and prisms with valence 7 and 9 caps.
pub fn meshes() -> Vec<(String, PolyMesh)> {
    let root = ccss_tests::harness::workspace_root().join("tests/data/osd");
    let mut v: Vec<(String, PolyMesh)> = [
        "catmark_cube",
        "catmark_righthanded",
        "catmark_torus",
        "catmark_pyramid",
        "catmark_toroidal_tet",
    ]
    .iter()
    .map(|n| {
        (
            n.to_string(),
            PolyMesh::from_obj(&root.join(format!("{n}.obj"))),
        )
    })
    .collect();
    v.push(("prism7".into(), prism(7)));
    v.push(("prism9".into(), prism(9)));
    v
}
