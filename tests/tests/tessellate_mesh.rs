//! Adaptive tessellation, mesh properties: for closed input the output
//! polygons and triangles form a closed, consistently oriented 2-manifold
//! (every edge in exactly two faces, opposite directions; every vertex one
//! fan) with the input's Euler characteristic; no duplicate vertices (no
//! two closer than 1e-9 of the bounding-box diagonal), no polygon repeats a
//! vertex, no zero-area triangle; every vertex is the exact limit point at
//! its reported (face, sub, u, v), with the limit normal there; counts match
//! what was emitted; triangles are counter-clockwise (outward normals).
mod tessellate_util;

use ccss_core::tessellate::{Criterion, Options};
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, PolyMesh};
use std::collections::HashMap;
use tessellate_util::*;

fn check_mesh(name: &str, m: &PolyMesh, opts: Options) -> (usize, usize, u32) {
    let diag = m.bbox_diagonal();
    let what = format!("{name} {:?}", opts.criterion);
    with_evaluator(m, standard_tables(), |topo, ev| {
        let t = tessellate(topo, ev, opts).unwrap_or_else(|e| panic!("{what}: {e}"));
        let c = t.counts;
        assert_eq!(c.triangles, c.polygon_indices - 2 * c.polygons);
        let polys = t.polygons();
        let edges = check_closed_manifold(&what, c.vertices, &polys);
        assert_eq!(
            c.vertices as i64 - edges as i64 + c.polygons as i64,
            euler(m),
            "{what}: Euler characteristic"
        );
        let tris: Vec<&[u32]> = t.tris.chunks(3).collect();
        check_closed_manifold(&format!("{what} triangles"), c.vertices, &tris);
        // Vertices: exact limit points, limit normals, distinct.
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let cellsz = 1e-9 * diag;
        for v in 0..c.vertices as u32 {
            let q = t.params[v as usize];
            let e = ev.eval(q.face, q.sub, q.u, q.v).unwrap();
            let p = t.p(v);
            let d = norm(sub(p, e.p.to_array()));
            assert!(
                d <= 1e-12 * diag,
                "{what}: vertex {v} at {q:?} is {d:e} off the surface"
            );
            let n = [
                t.nrm[3 * v as usize],
                t.nrm[3 * v as usize + 1],
                t.nrm[3 * v as usize + 2],
            ];
            let dn = norm(sub(n, e.normal.to_array()));
            assert!(
                dn <= 1e-7,
                "{what}: vertex {v} at {q:?}: normal off by {dn:e}"
            );
            let key = p.map(|x| (x / cellsz).floor() as i64);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = grid.get(&[key[0] + dx, key[1] + dy, key[2] + dz]) {
                            for &w in list {
                                let dd = norm(sub(p, t.p(w)));
                                assert!(
                                    dd > cellsz,
                                    "{what}: vertices {v} and {w} coincide ({dd:e})"
                                );
                            }
                        }
                    }
                }
            }
            grid.entry(key).or_default().push(v);
        }
        // Quads are cut along their shorter 3D diagonal (up to rounding:
        // the cut may be chosen from the points as the node's own net gives
        // them, a few ulps from the emitted ones).
        let mut at = 0usize;
        let mut tri = 0usize;
        for poly in &polys {
            if let [a, b, cc, d] = **poly {
                let cut = &t.tris[3 * tri..3 * tri + 6];
                // The diagonal: the two vertices both triangles hold.
                let both = |v: u32| cut[..3].contains(&v) && cut[3..].contains(&v);
                let (p, q) = match (both(a) && both(cc), both(b) && both(d)) {
                    (true, false) => ((a, cc), (b, d)),
                    (false, true) => ((b, d), (a, cc)),
                    _ => panic!("{what}: quad {poly:?} triangles {cut:?} share no diagonal"),
                };
                let len = |(x, y): (u32, u32)| norm(sub(t.p(x), t.p(y)));
                assert!(
                    len(p) <= len(q) * (1.0 + 1e-12),
                    "{what}: quad {poly:?} cut along its longer diagonal ({:e} > {:e})",
                    len(p),
                    len(q)
                );
            }
            tri += poly.len() - 2;
            at += poly.len();
        }
        assert_eq!(at, c.polygon_indices);
        // Triangles: positive area, facing like the surface normal.
        for (k, tr) in t.tris.chunks(3).enumerate() {
            let (a, b, cc) = (t.p(tr[0]), t.p(tr[1]), t.p(tr[2]));
            let n = cross(sub(b, a), sub(cc, a));
            let area2 = norm(n);
            assert!(
                area2 > 1e-14 * diag * diag,
                "{what}: triangle {k} {tr:?} has area {area2:e}"
            );
            let vn: [f64; 3] = (0..3)
                .map(|i| tr.iter().map(|&v| t.nrm[3 * v as usize + i]).sum::<f64>())
                .collect::<Vec<_>>()
                .try_into()
                .unwrap();
            assert!(dot(n, vn) > 0.0, "{what}: triangle {k} faces inward");
        }
        (c.polygons, c.vertices, t.stats.max_level)
    })
    .unwrap()
}

/// Orients every face of a convex polyhedron counter-clockwise seen from
/// outside (its centroid at the origin).
fn outward(positions: Vec<[f64; 3]>, mut faces: Vec<Vec<u32>>) -> PolyMesh {
    for f in &mut faces {
        let p = |k: usize| positions[f[k] as usize];
        let c: [f64; 3] =
            core::array::from_fn(|i| f.iter().map(|&v| positions[v as usize][i]).sum::<f64>());
        let n = cross(sub(p(1), p(0)), sub(p(2), p(0)));
        if dot(n, c) < 0.0 {
            f.reverse();
        }
    }
    PolyMesh { positions, faces }
}

/// Triangles only (valence 3): tetrahedron.
fn tetrahedron() -> PolyMesh {
    let p = vec![
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    outward(
        p,
        vec![vec![0, 1, 2], vec![0, 1, 3], vec![0, 2, 3], vec![1, 2, 3]],
    )
}

/// Triangles around valence-4 vertices: octahedron.
fn octahedron() -> PolyMesh {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut f = Vec::new();
    for x in [0u32, 1] {
        for y in [2u32, 3] {
            for z in [4u32, 5] {
                f.push(vec![x, y, z]);
            }
        }
    }
    outward(p, f)
}

/// Pentagons only: the dual of the icosahedron.
fn dodecahedron() -> PolyMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut ico = Vec::new();
    for a in [-1.0, 1.0] {
        for b in [-g, g] {
            ico.push([0.0, a, b]);
            ico.push([a, b, 0.0]);
            ico.push([b, 0.0, a]);
        }
    }
    let d2 = |a: [f64; 3], b: [f64; 3]| norm(sub(a, b));
    let mut tris = Vec::new();
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if d2(ico[i], ico[j]) < 2.1 && d2(ico[j], ico[k]) < 2.1 && d2(ico[i], ico[k]) < 2.1
                {
                    tris.push([i, j, k]);
                }
            }
        }
    }
    let centre = |t: &[usize; 3]| -> [f64; 3] {
        core::array::from_fn(|c| t.iter().map(|&v| ico[v][c]).sum::<f64>() / 3.0)
    };
    let positions: Vec<[f64; 3]> = tris.iter().map(centre).collect();
    let mut faces = Vec::new();
    for v in 0..12 {
        // The five triangles around icosahedron vertex v, in cyclic order.
        let around: Vec<usize> = (0..tris.len()).filter(|&t| tris[t].contains(&v)).collect();
        let mut ring = vec![around[0]];
        while ring.len() < around.len() {
            let last = tris[*ring.last().unwrap()];
            let next = around
                .iter()
                .copied()
                .find(|&t| {
                    !ring.contains(&t) && tris[t].iter().filter(|x| last.contains(x)).count() == 2
                })
                .unwrap();
            ring.push(next);
        }
        faces.push(ring.iter().map(|&t| t as u32).collect());
    }
    outward(positions, faces)
}

#[test]
fn watertight_manifold_exact_vertices() {
    let shapes: Vec<(&str, PolyMesh)> = vec![
        ("cube", corpus("catmark_cube.obj")),
        ("pyramid", corpus("catmark_pyramid.obj")),
        ("toroidal_tet", corpus("catmark_toroidal_tet.obj")),
        ("torus", corpus("catmark_torus.obj")),
        ("righthanded", corpus("catmark_righthanded.obj")),
        ("pole_mesh(5)", pole_mesh(5)),
        ("drum(6)", drum(6)),
        ("tetrahedron", tetrahedron()),
        ("octahedron", octahedron()),
        ("dodecahedron", dodecahedron()),
    ];
    for (name, m) in &shapes {
        let diag = m.bbox_diagonal();
        for crit in [
            Criterion::Absolute(0.01 * diag),
            Criterion::Absolute(0.002 * diag),
            Criterion::Relative(0.05),
            Criterion::Uniform(2),
        ] {
            let (p, v, l) = check_mesh(
                name,
                m,
                Options {
                    criterion: crit,
                    max_level: 30,
                },
            );
            eprintln!("{name} {crit:?}: {p} polygons, {v} vertices, max level {l}");
        }
    }
}
