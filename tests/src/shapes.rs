//! Test solids for voxelization and an independent inside/outside oracle.
//!
//! * [`two_cubes`], [`cavity`] (a cube inside a larger, inverted cube: a
//!   solid with an internal void), [`pretzel`] (a thick plate with `h` holes:
//!   genus `h`).
//! * [`RefSurface`]: a closed triangle mesh of exact limit points (the
//!   vertices of the level-`k` uniform refinement pushed to the limit with
//!   the limit masks of [`crate::reference`]), with an estimate `delta` of
//!   its distance to the limit surface, and a ray-parity inside test of
//!   voxel centres along x-rows. Nothing here uses the library.

use crate::reference::{PolyMesh, Refiner};
use std::collections::HashMap;

/// Appends an axis-aligned cube (centre `c`, half side `h`) to `m`, outward
/// oriented, or inward (`inverted`) for the wall of a void.
pub fn push_cube(m: &mut PolyMesh, c: [f64; 3], h: f64, inverted: bool) {
    let base = m.positions.len() as u32;
    for k in 0..8u32 {
        let s = |b: u32| if k & b != 0 { 1.0 } else { -1.0 };
        m.positions
            .push([c[0] + h * s(1), c[1] + h * s(2), c[2] + h * s(4)]);
    }
    // Vertex k has x bit 1, y bit 2, z bit 4. Counter-clockwise from outside.
    let faces: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // z-
        [4, 5, 7, 6], // z+
        [0, 1, 5, 4], // y-
        [2, 6, 7, 3], // y+
        [0, 4, 6, 2], // x-
        [1, 3, 7, 5], // x+
    ];
    for f in faces {
        let mut f: Vec<u32> = f.iter().map(|&v| base + v).collect();
        if inverted {
            f.reverse();
        }
        m.faces.push(f);
    }
}

/// Two disjoint unit-ish cubes side by side along x (centres at -1.2 and
/// +1.2, half side 0.8): two solids.
pub fn two_cubes() -> PolyMesh {
    let mut m = PolyMesh {
        positions: vec![],
        faces: vec![],
    };
    push_cube(&mut m, [-1.2, 0.0, 0.0], 0.8, false);
    push_cube(&mut m, [1.2, 0.1, 0.0], 0.8, false);
    m
}

/// A cube of half side 2 with an inverted cube of half side 0.9 inside: a
/// solid shell with an internal void.
pub fn cavity() -> PolyMesh {
    let mut m = PolyMesh {
        positions: vec![],
        faces: vec![],
    };
    push_cube(&mut m, [0.0; 3], 2.0, false);
    push_cube(&mut m, [0.1, -0.05, 0.0], 0.9, true);
    m
}

/// A thick plate with `holes` square holes in a row: a quad mesh of genus
/// `holes`. The plate is a `(2 holes + 1) x 3` grid of unit cells (holes are
/// cells (2i+1, 1)), extruded to thickness 1; faces are the top and bottom
/// of every solid cell and the side walls along every boundary edge.
pub fn pretzel(holes: usize) -> PolyMesh {
    let nx = 2 * holes + 1;
    let ny = 3;
    let solid = |i: isize, j: isize| {
        i >= 0 && j >= 0 && (i as usize) < nx && (j as usize) < ny && !(j == 1 && i % 2 == 1)
    };
    let mut positions = vec![];
    let mut index = HashMap::new();
    let mut vid = |i: usize, j: usize, z: usize, positions: &mut Vec<[f64; 3]>| -> u32 {
        *index.entry((i, j, z)).or_insert_with(|| {
            positions.push([i as f64, j as f64, z as f64]);
            (positions.len() - 1) as u32
        })
    };
    let mut faces = vec![];
    for j in 0..ny {
        for i in 0..nx {
            if !solid(i as isize, j as isize) {
                continue;
            }
            let (a, b, c, d) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
            let top: Vec<u32> = [a, b, c, d]
                .iter()
                .map(|&(x, y)| vid(x, y, 1, &mut positions))
                .collect();
            let mut bot: Vec<u32> = [a, b, c, d]
                .iter()
                .map(|&(x, y)| vid(x, y, 0, &mut positions))
                .collect();
            bot.reverse();
            faces.push(top);
            faces.push(bot);
            // Side walls: edge (p, q) counter-clockwise around the cell; the
            // wall faces outward from the cell when its neighbour is empty.
            let edges = [
                (a, b, (0, -1)),
                (b, c, (1, 0)),
                (c, d, (0, 1)),
                (d, a, (-1, 0)),
            ];
            for (p, q, (di, dj)) in edges {
                if solid(i as isize + di, j as isize + dj) {
                    continue;
                }
                faces.push(vec![
                    vid(p.0, p.1, 0, &mut positions),
                    vid(q.0, q.1, 0, &mut positions),
                    vid(q.0, q.1, 1, &mut positions),
                    vid(p.0, p.1, 1, &mut positions),
                ]);
            }
        }
    }
    PolyMesh { positions, faces }
}

/// A closed triangle mesh of exact limit points (see module docs).
pub struct RefSurface {
    /// Triangles (model coordinates).
    pub tris: Vec<[[f64; 3]; 3]>,
    /// Estimated distance bound between the triangles and the limit surface:
    /// twice the largest distance between a level-`k+1` edge point's limit
    /// position and the midpoint of its level-`k` edge's limit chord.
    pub delta: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl RefSurface {
    /// The limit points of level `k` (k >= 1, all quads) triangulated.
    pub fn new(m: &PolyMesh, k: usize) -> RefSurface {
        let mut r = Refiner::new(m, None);
        let mesh = r.level(k).clone();
        let lim: Vec<[f64; 3]> = (0..mesh.positions.len() as u32)
            .map(|v| r.limit_position(k, v))
            .collect();
        let mut tris = vec![];
        for f in &mesh.faces {
            for t in 1..f.len() - 1 {
                tris.push([
                    lim[f[0] as usize],
                    lim[f[t] as usize],
                    lim[f[t + 1] as usize],
                ]);
            }
        }
        // Chord deviation: level k+1 numbers edge points after the
        // vertices; find each edge point as the vertex shared by the two
        // children of an edge's end points.
        let fine = r.level(k + 1).clone();
        let nv = mesh.positions.len();
        let mut adj: HashMap<u32, Vec<u32>> = HashMap::new();
        for f in &fine.faces {
            for t in 0..f.len() {
                adj.entry(f[t]).or_default().push(f[(t + 1) % f.len()]);
            }
        }
        let mut dev = 0.0f64;
        for f in &mesh.faces {
            for t in 0..f.len() {
                let (a, b) = (f[t], f[(t + 1) % f.len()]);
                // The edge point is a neighbour of both a and b at level k+1.
                let na = adj.get(&a).cloned().unwrap_or_default();
                let nb = adj.get(&b).cloned().unwrap_or_default();
                if let Some(&e) = na.iter().find(|x| nb.contains(x) && (**x as usize) >= nv) {
                    let p = r.limit_position(k + 1, e);
                    let (pa, pb) = (lim[a as usize], lim[b as usize]);
                    let mid = [
                        0.5 * (pa[0] + pb[0]),
                        0.5 * (pa[1] + pb[1]),
                        0.5 * (pa[2] + pb[2]),
                    ];
                    dev = dev.max(norm(sub(p, mid)));
                }
            }
        }
        RefSurface {
            tris,
            delta: 2.0 * dev,
        }
    }

    /// Inside (odd crossing count of the ray along +x) for every voxel centre
    /// of an `m1 x m2 x m3` grid whose voxel coordinates are
    /// `scale * p + offset`; index `i + m1 (j + m2 k)`.
    pub fn classify(&self, scale: f64, offset: [f64; 3], res: [u32; 3]) -> Vec<bool> {
        let [m1, m2, m3] = res.map(|x| x as usize);
        let to_v = |p: [f64; 3]| {
            [
                scale * p[0] + offset[0],
                scale * p[1] + offset[1],
                scale * p[2] + offset[2],
            ]
        };
        let tv: Vec<[[f64; 3]; 3]> = self.tris.iter().map(|t| t.map(to_v)).collect();
        // Perturbed row lines avoid hitting edges and vertices exactly.
        let (e1, e2) = (1.234_567e-7, 2.718_281e-7);
        let mut buckets: Vec<Vec<u32>> = vec![vec![]; m2 * m3];
        for (ti, t) in tv.iter().enumerate() {
            let ylo = t.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min) - e1;
            let yhi = t.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) - e1;
            let zlo = t.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min) - e2;
            let zhi = t.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max) - e2;
            let j0 = ylo.ceil().max(0.0) as usize;
            let k0 = zlo.ceil().max(0.0) as usize;
            let j1 = yhi.floor().min(m2 as f64 - 1.0);
            let k1 = zhi.floor().min(m3 as f64 - 1.0);
            if j1 < 0.0 || k1 < 0.0 {
                continue;
            }
            for k in k0..=k1 as usize {
                for j in j0..=j1 as usize {
                    buckets[j + m2 * k].push(ti as u32);
                }
            }
        }
        let mut out = vec![false; m1 * m2 * m3];
        for k in 0..m3 {
            for j in 0..m2 {
                let (y, z) = (j as f64 + e1, k as f64 + e2);
                let mut xs = vec![];
                for &ti in &buckets[j + m2 * k] {
                    let [a, b, c] = tv[ti as usize];
                    // Barycentric coordinates in the yz projection.
                    let d = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2]);
                    if d == 0.0 {
                        continue;
                    }
                    let l1 = ((y - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (z - a[2])) / d;
                    let l2 = ((b[1] - a[1]) * (z - a[2]) - (y - a[1]) * (b[2] - a[2])) / d;
                    let l0 = 1.0 - l1 - l2;
                    if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
                        continue;
                    }
                    xs.push(l0 * a[0] + l1 * b[0] + l2 * c[0]);
                }
                xs.sort_by(|a, b| a.partial_cmp(b).unwrap());
                for i in 0..m1 {
                    let ahead = xs.iter().filter(|&&x| x > i as f64).count();
                    out[i + m1 * (j + m2 * k)] = ahead % 2 == 1;
                }
            }
        }
        out
    }

    /// Distance from `p` to the triangles (brute force).
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        self.tris
            .iter()
            .map(|t| point_triangle(p, t))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Distance from a point to a triangle.
pub fn point_triangle(p: [f64; 3], t: &[[f64; 3]; 3]) -> f64 {
    let [a, b, c] = *t;
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return norm(ap);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return norm(bp);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return norm(sub(
            p,
            [a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]],
        ));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return norm(cp);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return norm(sub(
            p,
            [a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]],
        ));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        let bc = sub(c, b);
        return norm(sub(
            p,
            [b[0] + w * bc[0], b[1] + w * bc[1], b[2] + w * bc[2]],
        ));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    let q = [
        a[0] + ab[0] * v + ac[0] * w,
        a[1] + ab[1] * v + ac[1] * w,
        a[2] + ab[2] * v + ac[2] * w,
    ];
    norm(sub(p, q))
}
