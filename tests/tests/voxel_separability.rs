//! Voxelization and flooding against an independent inside test.
//!
//! For every corpus mesh the library accepts, all three adjacencies and
//! several resolutions (cubes and non-cubes): voxelize, flood, then compare
//! every white voxel's class with the ray parity of its centre against a
//! closed triangle mesh of exact limit points from the reference subdivider
//! (`shapes::RefSurface`). A voxel classified outside whose centre is inside
//! is a leak; one classified interior whose centre is outside is a wrong
//! fill. Centres closer to the reference triangles than their error estimate
//! are skipped (ambiguous); the test reports how many.
//!
//! Also: the genus-3 plate, two disjoint cubes and a cube with a cavity, where
//! the number of enclosed components classified inside is known.

use ccss_core::voxel::{Adjacency, VoxelClass, VoxelGrid, VoxelParams, VoxelWork};
use ccss_core::Evaluator;
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use ccss_tests::reference::PolyMesh;
use ccss_tests::shapes::{cavity, pretzel, two_cubes, RefSurface};
use std::path::Path;

struct Outcome {
    leaks: usize,
    wrong_fill: usize,
    ambiguous: usize,
    checked: usize,
    inside_components: u32,
    interior: u64,
}

/// Voxelizes and floods `ev` and compares with `rs`.
fn check(ev: &Evaluator, rs: &RefSurface, res: [u32; 3], adj: Adjacency, stack: usize) -> Outcome {
    let params = VoxelParams::new(res, adj);
    let mut mem = aligned(VoxelGrid::required_bytes(res).unwrap());
    let mut grid = VoxelGrid::new(res, &mut mem).unwrap();
    let mut work = Box::new(VoxelWork::ZERO);
    let st = grid.voxelize(ev, &params, None, &mut work).unwrap();
    assert_eq!(st.guard_hits, 0, "{st:?}");
    let mut stk = vec![0u32; stack];
    let fs = grid.flood(ev, &mut stk, &mut work).unwrap();
    assert_eq!(fs.unresolved, 0, "{fs:?}");
    let t = grid.transform();
    let inside = rs.classify(t.scale, t.offset, res);
    let delta_v = rs.delta * t.scale;
    let mut o = Outcome {
        leaks: 0,
        wrong_fill: 0,
        ambiguous: 0,
        checked: 0,
        inside_components: fs.inside_components,
        interior: grid.counts().interior,
    };
    for k in 0..res[2] {
        for j in 0..res[1] {
            for i in 0..res[0] {
                let c = grid.class(i, j, k);
                if c == VoxelClass::Surface {
                    continue;
                }
                let idx = (i + res[0] * (j + res[1] * k)) as usize;
                let ref_in = inside[idx];
                let ours_in = c == VoxelClass::Interior;
                if ref_in == ours_in {
                    o.checked += 1;
                    continue;
                }
                let p = t.to_model(ccss_core::DVec3::new(i as f64, j as f64, k as f64));
                let d = rs.distance(p.to_array()) * t.scale;
                if d <= delta_v.max(1e-9) {
                    o.ambiguous += 1;
                } else if ref_in {
                    o.leaks += 1;
                    eprintln!("leak at ({i},{j},{k}), distance {d} voxels");
                } else {
                    o.wrong_fill += 1;
                    eprintln!("wrong fill at ({i},{j},{k}), distance {d} voxels");
                }
            }
        }
    }
    o
}

fn corpus() -> Vec<(String, PolyMesh)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    let mut v = vec![];
    for name in [
        "catmark_torus",
        "catmark_cube",
        "catmark_pyramid",
        "catmark_fan",
        "catmark_toroidal_tet",
        "catmark_gregory_test8",
        "catmark_smoothtris0",
        "catmark_tent",
        "catmark_righthanded",
    ] {
        let m = PolyMesh::from_obj(&dir.join(format!("{name}.obj")));
        if ccss_tests::harness::validate(&m).is_ok() {
            v.push((name.to_string(), m));
        }
    }
    v
}

#[test]
fn no_leaks_on_the_corpus_for_all_adjacencies_and_resolutions() {
    let corpus = corpus();
    assert!(
        corpus.len() >= 5,
        "only {} corpus meshes build",
        corpus.len()
    );
    let mut total = (0usize, 0usize);
    for (name, m) in &corpus {
        let level = if m.faces.len() > 100 { 2 } else { 3 };
        let rs = RefSurface::new(m, level);
        with_evaluator(m, standard_tables(), |_, ev| {
            let resolutions: &[[u32; 3]] = if m.faces.len() > 100 {
                &[[24, 24, 24]]
            } else if name == "catmark_torus" {
                &[[17, 17, 17], [32, 32, 32], [24, 19, 30]]
            } else {
                &[[17, 17, 17], [24, 19, 30]]
            };
            for &res in resolutions {
                for adj in [Adjacency::Six, Adjacency::Eighteen, Adjacency::TwentySix] {
                    let o = check(ev, &rs, res, adj, 4096);
                    println!(
                        "{name} res={res:?} N={} checked={} ambiguous={} leaks={} wrong_fill={}",
                        adj.n(),
                        o.checked,
                        o.ambiguous,
                        o.leaks,
                        o.wrong_fill
                    );
                    assert_eq!(o.leaks, 0, "{name} {res:?} N={}", adj.n());
                    assert_eq!(o.wrong_fill, 0, "{name} {res:?} N={}", adj.n());
                    total.0 += o.checked;
                    total.1 += o.ambiguous;
                }
            }
        })
        .unwrap();
    }
    println!("total checked={} ambiguous={}", total.0, total.1);
    assert!(total.1 * 100 < total.0, "too many ambiguous centres");
}

#[test]
fn interior_of_genus_3_two_solids_and_a_cavity() {
    // (mesh, expected inside components at every resolution)
    let cases = [
        ("pretzel3", pretzel(3), 1u32),
        ("two_cubes", two_cubes(), 2),
        ("cavity", cavity(), 1),
    ];
    for (name, m, want) in cases {
        let rs = RefSurface::new(&m, 3);
        with_evaluator(&m, standard_tables(), |_, ev| {
            let runs = [
                ([36, 36, 36], Adjacency::Six, 1usize),
                ([36, 36, 36], Adjacency::TwentySix, 1 << 16),
                ([44, 26, 33], Adjacency::Eighteen, 7),
            ];
            for (res, adj, stack) in runs {
                {
                    {
                        let o = check(ev, &rs, res, adj, stack);
                        println!(
                            "{name} res={res:?} N={} stack={stack} interior={} inside_components={} checked={} ambiguous={}",
                            adj.n(),
                            o.interior,
                            o.inside_components,
                            o.checked,
                            o.ambiguous
                        );
                        assert_eq!(o.leaks, 0, "{name}");
                        assert_eq!(o.wrong_fill, 0, "{name}");
                        assert_eq!(o.inside_components, want, "{name}");
                        assert!(o.interior > 0, "{name}");
                    }
                }
            }
        })
        .unwrap();
    }
}

#[test]
fn the_cavity_is_outside_and_the_shell_inside() {
    let m = cavity();
    with_evaluator(&m, standard_tables(), |_, ev| {
        let res = [32, 32, 32];
        let params = VoxelParams::new(res, Adjacency::Six);
        let mut mem = aligned(VoxelGrid::required_bytes(res).unwrap());
        let mut grid = VoxelGrid::new(res, &mut mem).unwrap();
        let mut work = Box::new(VoxelWork::ZERO);
        grid.voxelize(ev, &params, None, &mut work).unwrap();
        let mut stk = vec![0u32; 64];
        grid.flood(ev, &mut stk, &mut work).unwrap();
        let t = grid.transform();
        let v = |p: [f64; 3]| {
            let q = t.to_voxel(ccss_core::DVec3::from_array(p)).round();
            grid.class(q.x as u32, q.y as u32, q.z as u32)
        };
        // The void's centre (inner cube centred at (0.1, -0.05, 0)).
        assert_eq!(v([0.1, -0.05, 0.0]), VoxelClass::Outside);
        // Inside the shell, between the walls.
        assert_eq!(v([1.2, 0.0, 0.0]), VoxelClass::Interior);
        assert_eq!(v([0.0, 0.0, -1.2]), VoxelClass::Interior);
    })
    .unwrap();
}

/// Naive oracle for the bit-parallel flood on rows of several words: a
/// byte-per-voxel 6-connected BFS from the grid border through white
/// voxels. For a solid without cavities every white voxel it does not reach
/// is interior and every one it reaches is outside. Resolutions along x are
/// chosen so that rows span 2-4 words with a partial last word, where the
/// carries across words (upward add, downward smear) matter; stacks of 1 and
/// of every row exercise the sweep and the stack paths.
#[test]
fn flood_equals_a_naive_bfs_on_multi_word_rows() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    let corpus = [
        (
            "catmark_torus",
            PolyMesh::from_obj(&dir.join("catmark_torus.obj")),
        ),
        ("pretzel3", pretzel(3)),
    ];
    for (name, m) in &corpus {
        with_evaluator(m, standard_tables(), |_, ev| {
            for (res, adj) in [
                ([160u32, 40u32, 150u32], Adjacency::TwentySix),
                ([200, 23, 17], Adjacency::Six),
                ([129, 64, 48], Adjacency::Eighteen),
            ] {
                let params = VoxelParams::new(res, adj);
                let mut mem = aligned(VoxelGrid::required_bytes(res).unwrap());
                let mut grid = VoxelGrid::new(res, &mut mem).unwrap();
                let mut work = Box::new(VoxelWork::ZERO);
                grid.voxelize(ev, &params, None, &mut work).unwrap();
                let [m1, m2, m3] = res.map(|x| x as usize);
                let idx = |i: usize, j: usize, k: usize| (k * m2 + j) * m1 + i;
                let mut reached = vec![false; m1 * m2 * m3];
                let mut queue = Vec::new();
                for k in 0..m3 {
                    for j in 0..m2 {
                        for i in 0..m1 {
                            let border = i == 0
                                || j == 0
                                || k == 0
                                || i + 1 == m1
                                || j + 1 == m2
                                || k + 1 == m3;
                            let white =
                                grid.class(i as u32, j as u32, k as u32) != VoxelClass::Surface;
                            if border && white {
                                reached[idx(i, j, k)] = true;
                                queue.push([i, j, k]);
                            }
                        }
                    }
                }
                while let Some([i, j, k]) = queue.pop() {
                    let nb = [
                        [i.wrapping_sub(1), j, k],
                        [i + 1, j, k],
                        [i, j.wrapping_sub(1), k],
                        [i, j + 1, k],
                        [i, j, k.wrapping_sub(1)],
                        [i, j, k + 1],
                    ];
                    for [a, b, c] in nb {
                        if a >= m1 || b >= m2 || c >= m3 || reached[idx(a, b, c)] {
                            continue;
                        }
                        if grid.class(a as u32, b as u32, c as u32) == VoxelClass::Surface {
                            continue;
                        }
                        reached[idx(a, b, c)] = true;
                        queue.push([a, b, c]);
                    }
                }
                for stack in [1usize, m2 * m3] {
                    let mut stk = vec![0u32; stack];
                    grid.flood(ev, &mut stk, &mut work).unwrap();
                    let mut differ = 0usize;
                    let mut interior = 0usize;
                    for k in 0..m3 {
                        for j in 0..m2 {
                            for i in 0..m1 {
                                let c = grid.class(i as u32, j as u32, k as u32);
                                if c == VoxelClass::Surface {
                                    continue;
                                }
                                let want = if reached[idx(i, j, k)] {
                                    VoxelClass::Outside
                                } else {
                                    VoxelClass::Interior
                                };
                                interior += (c == VoxelClass::Interior) as usize;
                                differ += (c != want) as usize;
                            }
                        }
                    }
                    println!(
                        "{name} res={res:?} N={} stack={stack} interior={interior} differ={differ}",
                        adj.n()
                    );
                    assert!(interior > 0, "{name} {res:?}");
                    assert_eq!(differ, 0, "{name} {res:?} N={} stack={stack}", adj.n());
                }
            }
        })
        .unwrap();
    }
}
