//! The surface voxels against dense exact samples of the limit surface.
//!
//! * No holes (N = 6, the paper's eq. 3): the voxel containing each sample
//!   is a surface voxel (a sample within `TAU` of a voxel face may instead
//!   have its neighbour across that face black; the certification's
//!   tolerance, see `ccss_core::voxel::rasterize`).
//! * Minimality (eq. 4), all N: every surface voxel contains a limit-surface
//!   point, checked within the sampling resolution: a sample lies within
//!   `1.5 h` (max norm) of the voxel's cube, `h` the largest distance
//!   between neighbouring samples.
//! * Thin inside thick: the N = 18 and 26 surfaces are subsets of N = 6.

use ccss_core::voxel::{Adjacency, VoxelClass, VoxelGrid, VoxelParams, VoxelWork, TAU};
use ccss_core::{DVec3, Evaluator};
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use ccss_tests::reference::PolyMesh;
use ccss_tests::shapes::pretzel;
use std::collections::HashSet;
use std::path::Path;

/// Samples (voxel coordinates) on an `n x n` grid per slot, and the largest
/// distance between neighbouring samples.
fn samples(ev: &Evaluator, to_v: impl Fn(DVec3) -> DVec3, n: u32) -> (Vec<DVec3>, f64) {
    let mut out = vec![];
    let mut h = 0.0f64;
    for f in 0..ev.num_faces() {
        for s in 0..ev.num_subfaces(f) {
            let mut prev_row: Vec<DVec3> = vec![];
            for i in 0..=n {
                let mut row = vec![];
                for j in 0..=n {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let p = to_v(ev.eval(f as u32, s as u32, u, v).unwrap().p);
                    if let Some(q) = row.last() as Option<&DVec3> {
                        h = h.max((p - *q).length());
                    }
                    if let Some(q) = prev_row.get(j as usize) {
                        h = h.max((p - *q).length());
                    }
                    row.push(p);
                    out.push(p);
                }
                prev_row = row;
            }
        }
    }
    (out, h)
}

fn voxelize(
    ev: &Evaluator,
    res: [u32; 3],
    adj: Adjacency,
) -> (
    Vec<u64>,
    HashSet<[u32; 3]>,
    ccss_core::voxel::VoxelTransform,
) {
    let params = VoxelParams::new(res, adj);
    let mut mem = aligned(VoxelGrid::required_bytes(res).unwrap());
    let mut set = HashSet::new();
    let t;
    {
        let mut grid = VoxelGrid::new(res, &mut mem).unwrap();
        let mut work = Box::new(VoxelWork::ZERO);
        let st = grid.voxelize(ev, &params, None, &mut work).unwrap();
        assert_eq!(st.guard_hits, 0);
        t = grid.transform();
        for k in 0..res[2] {
            for j in 0..res[1] {
                for i in 0..res[0] {
                    if grid.class(i, j, k) == VoxelClass::Surface {
                        set.insert([i, j, k]);
                    }
                }
            }
        }
    }
    (mem, set, t)
}

fn meshes() -> Vec<(String, PolyMesh)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    let mut v: Vec<(String, PolyMesh)> = [
        "catmark_torus",
        "catmark_cube",
        "catmark_pyramid",
        "catmark_toroidal_tet",
    ]
    .iter()
    .map(|n| {
        (
            n.to_string(),
            PolyMesh::from_obj(&dir.join(format!("{n}.obj"))),
        )
    })
    .collect();
    v.push(("pretzel3".into(), pretzel(3)));
    v
}

#[test]
fn no_holes_minimality_and_thin_inside_thick() {
    for (name, m) in meshes() {
        with_evaluator(&m, standard_tables(), |_, ev| {
            for res in [[21, 21, 21], [40, 31, 26]] {
                let (_, thick, t) = voxelize(ev, res, Adjacency::Six);
                let (pts, h) = samples(ev, |p| t.to_voxel(p), 96);
                // No holes.
                let mut holes = 0;
                for p in &pts {
                    let v = p.map(|c| (c + 0.5).floor()).as_uvec3().to_array();
                    if thick.contains(&v) {
                        continue;
                    }
                    // Within TAU of a face: the neighbour across it may hold.
                    let mut ok = false;
                    for a in 0..3 {
                        let f = p[a] + 0.5 - (p[a] + 0.5).floor();
                        for (near, d) in [(f < TAU, -1i64), (f > 1.0 - TAU, 1)] {
                            if near {
                                let mut w = v.map(|x| x as i64);
                                w[a] += d;
                                if w.iter().all(|&x| x >= 0) && thick.contains(&w.map(|x| x as u32)) {
                                    ok = true;
                                }
                            }
                        }
                    }
                    if !ok {
                        holes += 1;
                    }
                }
                // Minimality, all adjacencies.
                let mut near: HashSet<[u32; 3]> = HashSet::new();
                let r = 1.5 * h;
                for p in &pts {
                    let lo = (*p - DVec3::splat(r) + DVec3::splat(0.5)).floor();
                    let hi = (*p + DVec3::splat(r) + DVec3::splat(0.5)).floor();
                    for k in lo.z.max(0.0) as u32..=hi.z as u32 {
                        for j in lo.y.max(0.0) as u32..=hi.y as u32 {
                            for i in lo.x.max(0.0) as u32..=hi.x as u32 {
                                near.insert([i, j, k]);
                            }
                        }
                    }
                }
                let far6 = thick.iter().filter(|v| !near.contains(*v)).count();
                let mut line = format!(
                    "{name} res={res:?} samples={} h={h:.3} N=6 surface={} holes={holes} unsupported={far6}",
                    pts.len(),
                    thick.len()
                );
                assert_eq!(holes, 0, "{line}");
                assert_eq!(far6, 0, "{line}");
                for adj in [Adjacency::Eighteen, Adjacency::TwentySix] {
                    let (_, thin, t2) = voxelize(ev, res, adj);
                    assert_eq!(t2, t);
                    let far = thin.iter().filter(|v| !near.contains(*v)).count();
                    let outside_thick = thin.iter().filter(|v| !thick.contains(*v)).count();
                    line += &format!(
                        " N={} surface={} unsupported={far} not_in_N6={outside_thick}",
                        adj.n(),
                        thin.len()
                    );
                    assert_eq!(far, 0, "{line}");
                    assert_eq!(outside_thick, 0, "{line}");
                    assert!(thin.len() <= thick.len());
                }
                println!("{line}");
            }
        })
        .unwrap();
    }
}
