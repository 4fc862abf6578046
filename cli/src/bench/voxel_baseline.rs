//! The conventional voxelization that `ccss bench voxelize` compares
//! against, on the same grid and the same normalisation:
//!
//! * uniform Catmull-Clark refinement (ccss-core's `refine`, the control
//!   mesh, not limit points) until every edge is at most one voxel long;
//! * triangle voxelization: each quad split into two triangles, each
//!   triangle marks the voxels its box overlaps by the separating-axis test
//!   (Akenine-Möller), a conservative 26-connected surface;
//! * scanline fill: per (y, z) row, the crossings of the line through the
//!   voxel centres with the triangles (bucketed per row), sorted, parity.

use super::voxelize::best;
use crate::io::mesh_in::Mesh;
use crate::mem::words;
use ccss_core::mesh::refine::{refine, refine_bytes, refined_counts};
use ccss_core::voxel::VoxelTransform;
use ccss_core::{DVec3, MeshInput, Topology, Weights};

/// Positions, face sizes, indices.
type Flat = (Vec<f64>, Vec<u32>, Vec<u32>);

/// Refined control mesh (positions and quads) of `mesh` after `levels`
/// uniform Catmull-Clark steps.
fn refine_levels(mesh: &Mesh, levels: u32) -> Result<Flat, ccss_core::Error> {
    let (mut pos, mut sizes, mut idx) = (
        mesh.positions.clone(),
        mesh.face_sizes.clone(),
        mesh.indices.clone(),
    );
    for _ in 0..levels {
        let input = MeshInput {
            positions: &pos,
            face_sizes: &sizes,
            indices: &idx,
        };
        let mut tm = words(Topology::required_bytes(pos.len() / 3, &sizes));
        let t = Topology::build(input, &mut tm)?;
        let mut rm = words(refine_bytes(&t));
        let c = refined_counts(&t);
        let r = refine(&t, &Weights::STANDARD, &mut rm)?;
        let (p, s, i) = (
            r.mesh.positions.to_vec(),
            r.mesh.face_sizes.to_vec(),
            r.mesh.indices.to_vec(),
        );
        debug_assert_eq!(s.len(), c.faces);
        pos = p;
        sizes = s;
        idx = i;
    }
    Ok((pos, sizes, idx))
}

/// Separating-axis test of a triangle (relative to the box centre) against
/// the box `[-h, h]^3`.
fn tri_box(v: [DVec3; 3], h: f64) -> bool {
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
    if lo.max_element() > h || hi.min_element() < -h {
        return false;
    }
    let n = e[0].cross(e[1]);
    let d = n.dot(v[0]);
    let r = h * (n.x.abs() + n.y.abs() + n.z.abs());
    if d.abs() > r {
        return false;
    }
    for ei in e {
        for a in 0..3 {
            let mut ax = DVec3::ZERO;
            ax[a] = 1.0;
            let axis = ax.cross(ei);
            let p = [axis.dot(v[0]), axis.dot(v[1]), axis.dot(v[2])];
            let r = h * (axis.x.abs() + axis.y.abs() + axis.z.abs());
            let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            if lo > r || hi < -r {
                return false;
            }
        }
    }
    true
}

/// What the baseline did and found, and its best times (seconds).
pub struct Baseline {
    /// Refinement level reached.
    pub level: u32,
    /// Triangles voxelized.
    pub triangles: usize,
    /// Refinement time.
    pub refine_s: f64,
    /// Triangle voxelization time.
    pub voxelize_s: f64,
    /// Scanline fill time.
    pub fill_s: f64,
    /// Surface voxels.
    pub surface: u64,
    /// Interior voxels (not surface).
    pub interior: u64,
}

/// Refines `mesh` until edges are at most one voxel of `t`, voxelizes its
/// triangles and fills the grid of resolution `n`; times are the best of
/// `reps` runs.
pub fn baseline(
    mesh: &Mesh,
    t: &VoxelTransform,
    n: u32,
    reps: u32,
) -> Result<Baseline, ccss_core::Error> {
    // Level: edges of at most one voxel.
    let mut level = 0;
    let (mut refine_s, (mut pos, mut sizes, mut idx)) = (
        0.0,
        (
            mesh.positions.clone(),
            mesh.face_sizes.clone(),
            mesh.indices.clone(),
        ),
    );
    loop {
        let mut longest = 0.0f64;
        let mut k = 0;
        for &s in &sizes {
            for a in 0..s as usize {
                let (i, j) = (idx[k + a] as usize, idx[k + (a + 1) % s as usize] as usize);
                let d = DVec3::new(
                    pos[3 * i] - pos[3 * j],
                    pos[3 * i + 1] - pos[3 * j + 1],
                    pos[3 * i + 2] - pos[3 * j + 2],
                );
                longest = longest.max(d.length() * t.scale);
            }
            k += s as usize;
        }
        if longest <= 1.0 || level >= 9 {
            break;
        }
        level += 1;
        let (s, r) = best(reps, || refine_levels(mesh, level));
        refine_s = s;
        (pos, sizes, idx) = r?;
    }
    let v = |i: u32| {
        t.to_voxel(DVec3::new(
            pos[3 * i as usize],
            pos[3 * i as usize + 1],
            pos[3 * i as usize + 2],
        ))
    };
    let mut tris = vec![];
    let mut k = 0;
    for &s in &sizes {
        for a in 1..s as usize - 1 {
            tris.push([v(idx[k]), v(idx[k + a]), v(idx[k + a + 1])]);
        }
        k += s as usize;
    }
    let nn = n as usize;
    let wpr = nn.div_ceil(64);
    let (voxelize_s, surface) = best(reps, || {
        let mut surf = vec![0u64; nn * nn * wpr];
        for tr in &tris {
            let lo = tr[0].min(tr[1]).min(tr[2]);
            let hi = tr[0].max(tr[1]).max(tr[2]);
            let r = |x: f64| ((x + 0.5).floor().max(0.0) as usize).min(nn - 1);
            for z in r(lo.z)..=r(hi.z) {
                for y in r(lo.y)..=r(hi.y) {
                    for x in r(lo.x)..=r(hi.x) {
                        let c = DVec3::new(x as f64, y as f64, z as f64);
                        if tri_box([tr[0] - c, tr[1] - c, tr[2] - c], 0.5) {
                            surf[(z * nn + y) * wpr + x / 64] |= 1u64 << (x % 64);
                        }
                    }
                }
            }
        }
        surf
    });
    let (fill_s, interior) = best(reps, || {
        let (e1, e2) = (1.234_567e-7, 2.718_281e-7);
        let mut buckets: Vec<Vec<u32>> = vec![vec![]; nn * nn];
        for (ti, tr) in tris.iter().enumerate() {
            let lo = tr[0].min(tr[1]).min(tr[2]);
            let hi = tr[0].max(tr[1]).max(tr[2]);
            let (j0, j1) = (
                (lo.y - e1).ceil().max(0.0),
                (hi.y - e1).floor().min(nn as f64 - 1.0),
            );
            let (k0, k1) = (
                (lo.z - e2).ceil().max(0.0),
                (hi.z - e2).floor().min(nn as f64 - 1.0),
            );
            if j1 < j0 || k1 < k0 {
                continue;
            }
            for z in k0 as usize..=k1 as usize {
                for y in j0 as usize..=j1 as usize {
                    buckets[z * nn + y].push(ti as u32);
                }
            }
        }
        let mut count = 0u64;
        let mut xs = vec![];
        for z in 0..nn {
            for y in 0..nn {
                xs.clear();
                let (py, pz) = (y as f64 + e1, z as f64 + e2);
                for &ti in &buckets[z * nn + y] {
                    let [a, b, c] = tris[ti as usize];
                    let d = (b.y - a.y) * (c.z - a.z) - (c.y - a.y) * (b.z - a.z);
                    if d == 0.0 {
                        continue;
                    }
                    let l1 = ((py - a.y) * (c.z - a.z) - (c.y - a.y) * (pz - a.z)) / d;
                    let l2 = ((b.y - a.y) * (pz - a.z) - (py - a.y) * (b.z - a.z)) / d;
                    let l0 = 1.0 - l1 - l2;
                    if l0 >= 0.0 && l1 >= 0.0 && l2 >= 0.0 {
                        xs.push(l0 * a.x + l1 * b.x + l2 * c.x);
                    }
                }
                xs.sort_by(|p, q| p.total_cmp(q));
                for pair in xs.chunks_exact(2) {
                    let x0 = pair[0].ceil().max(0.0) as usize;
                    let x1 = (pair[1].floor() as i64).min(nn as i64 - 1);
                    for x in x0 as i64..=x1 {
                        let x = x as usize;
                        if surface[(z * nn + y) * wpr + x / 64] >> (x % 64) & 1 == 0 {
                            count += 1;
                        }
                    }
                }
            }
        }
        count
    });
    Ok(Baseline {
        level,
        triangles: tris.len(),
        refine_s,
        voxelize_s,
        fill_s,
        surface: surface.iter().map(|w| w.count_ones() as u64).sum(),
        interior,
    })
}
