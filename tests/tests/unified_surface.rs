//! The unified scheme ([MS01]) on meshes: Catmull-Clark as a
//! special case, d-ary bicubic B-splines on regular grids, counts, Euler
//! characteristic, push-back and renormalisation properties, several levels,
//! exact size queries and parameter errors.
// Index loops mirror the matrix and grid formulas they check.
#![allow(clippy::needless_range_loop)]
use ccss_core::unified::{
    refine_unified, refine_unified_levels, unified_bytes, unified_counts, unified_levels_bytes,
    TriangleRule, UnifiedCounts, UnifiedParams,
};
use ccss_core::{mesh::refine, Error, MeshInput, Topology, Weights};
use ccss_tests::harness::{aligned, flatten};
use ccss_tests::reference::{catmull_clark, drum, pole_mesh, torus, PolyMesh};
use std::path::Path;

fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/osd")
            .join(name),
    )
}

/// Closed corpus meshes (quads; triangles + quads) and generated ones
/// (triangles only; pentagons/heptagons + quads).
const CLOSED: [&str; 9] = [
    "catmark_cube.obj",
    "catmark_pyramid.obj",
    "catmark_torus.obj",
    "catmark_toroidal_tet.obj",
    "catmark_righthanded.obj",
    "icosahedron",
    "octahedron",
    "drum5",
    "drum7",
];

fn mesh(name: &str) -> PolyMesh {
    match name {
        "icosahedron" => icosahedron(),
        "octahedron" => octahedron(),
        "drum5" => drum(5),
        "drum7" => drum(7),
        _ => corpus(name),
    }
}

/// Orients every triangle outward (the shapes are star-shaped about 0).
fn outward(positions: Vec<[f64; 3]>, mut faces: Vec<Vec<u32>>) -> PolyMesh {
    for f in &mut faces {
        let p: Vec<[f64; 3]> = f.iter().map(|&v| positions[v as usize]).collect();
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        if n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2] < 0.0 {
            f.reverse();
        }
    }
    PolyMesh { positions, faces }
}

fn octahedron() -> PolyMesh {
    let positions = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut faces = Vec::new();
    for x in [0, 1] {
        for y in [2, 3] {
            for z in [4, 5] {
                faces.push(vec![x, y, z]);
            }
        }
    }
    outward(positions, faces)
}

fn icosahedron() -> PolyMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let positions = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    outward(positions, faces.iter().map(|f| f.to_vec()).collect())
}

/// An owned refined mesh.
#[derive(Clone, Debug)]
struct Out {
    positions: Vec<f64>,
    sizes: Vec<u32>,
    indices: Vec<u32>,
}

impl Out {
    fn point(&self, v: usize) -> [f64; 3] {
        [
            self.positions[3 * v],
            self.positions[3 * v + 1],
            self.positions[3 * v + 2],
        ]
    }
    fn to_poly(&self) -> PolyMesh {
        let mut faces = Vec::new();
        let mut c = 0;
        for &s in &self.sizes {
            faces.push(self.indices[c..c + s as usize].to_vec());
            c += s as usize;
        }
        PolyMesh {
            positions: (0..self.positions.len() / 3)
                .map(|v| self.point(v))
                .collect(),
            faces,
        }
    }
}

fn own(m: MeshInput) -> Out {
    Out {
        positions: m.positions.to_vec(),
        sizes: m.face_sizes.to_vec(),
        indices: m.indices.to_vec(),
    }
}

/// Runs `f` with the topology of `m`.
fn with_topo<R>(m: &PolyMesh, f: impl FnOnce(&Topology) -> R) -> R {
    let (p, s, i) = flatten(m);
    let mut tmem = aligned(Topology::required_bytes(p.len() / 3, &s));
    let topo = Topology::build(
        MeshInput {
            positions: &p,
            face_sizes: &s,
            indices: &i,
        },
        &mut tmem,
    )
    .expect("valid test mesh");
    f(&topo)
}

fn unified(m: &PolyMesh, p: &UnifiedParams) -> Out {
    with_topo(m, |t| {
        let mut mem = aligned(unified_bytes(t, p).unwrap());
        own(refine_unified(t, p, &mut mem).unwrap().mesh)
    })
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn catmull_clark_is_a_special_case() {
    // a = 0, b = 0, g = 1, d = 2 (triangles as polygons): one CC step, same
    // numbering as the reference subdivider and `refine::refine`.
    for name in CLOSED {
        let m = mesh(name);
        let scale = m.bbox_diagonal();
        let want = catmull_clark(&m);
        let got = unified(&m, &UnifiedParams::CATMULL_CLARK);
        let (_, ws, wi) = flatten(&want);
        assert_eq!(got.sizes, ws, "{name}: face sizes");
        assert_eq!(got.indices, wi, "{name}: indices");
        let mut worst = 0.0f64;
        for (v, &p) in want.positions.iter().enumerate() {
            worst = worst.max(dist(got.point(v), p));
        }
        assert!(worst <= 1e-13 * scale, "{name}: max deviation {worst:e}");
        // The library's own CC step agrees too.
        with_topo(&m, |t| {
            let mut mem = aligned(refine::refine_bytes(t));
            let r = refine::refine(t, &Weights::STANDARD, &mut mem).unwrap();
            assert_eq!(r.mesh.indices, &got.indices[..]);
            let dev = r
                .mesh
                .positions
                .iter()
                .zip(&got.positions)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(dev <= 1e-13 * scale, "{name}: vs refine::refine {dev:e}");
        });
    }
    // Also on an all-quad mesh with two high-valence poles.
    for n in [3, 5, 7, 12] {
        let m = pole_mesh(n);
        let want = catmull_clark(&m);
        let got = unified(&m, &UnifiedParams::CATMULL_CLARK);
        for (v, &p) in want.positions.iter().enumerate() {
            assert!(dist(got.point(v), p) < 1e-13, "pole {n}, vertex {v}");
        }
    }
}

#[test]
fn g_zero_is_simple_averaging_and_g_blends() {
    // Eq. (13): only old extraordinary vertices move, linearly in g.
    let m = corpus("catmark_cube.obj");
    let cc = UnifiedParams::CATMULL_CLARK;
    let s0 = unified(&m, &UnifiedParams { g: 0.0, ..cc });
    let s1 = unified(&m, &cc);
    let sh = unified(&m, &UnifiedParams { g: 0.5, ..cc });
    for v in 0..s0.positions.len() / 3 {
        let (a, b, h) = (s0.point(v), s1.point(v), sh.point(v));
        if v < 8 {
            // Valence 3: d_i = (3-4)/3 (V̄ - V) != 0.
            assert!(dist(a, b) > 1e-3);
            for c in 0..3 {
                assert!((h[c] - 0.5 * (a[c] + b[c])).abs() < 1e-15);
            }
        } else {
            assert_eq!(a, b, "new vertex {v} must not take the correction");
        }
    }
    // Eq. (9) at an old cube corner: 1/4 V + 1/(2N) Σ⊕ + 1/(4N) Σ⊗ over the
    // linearly subdivided neighbours (edge midpoints, face centres).
    let p = |v: usize| m.positions[v];
    let v0 = p(0);
    let mut want = [0.0; 3];
    let n = 3.0;
    for f in &m.faces {
        if let Some(k) = f.iter().position(|&x| x == 0) {
            let c: Vec<f64> = (0..3)
                .map(|a| f.iter().map(|&x| p(x as usize)[a]).sum::<f64>() / 4.0)
                .collect();
            let nx = p(f[(k + 1) % 4] as usize);
            for a in 0..3 {
                want[a] += c[a] / (4.0 * n) + (v0[a] + nx[a]) / 2.0 / (2.0 * n);
            }
        }
    }
    for a in 0..3 {
        want[a] += v0[a] / 4.0;
    }
    assert!(dist(s0.point(0), want) < 1e-15);
}

/// The periodic d-ary refinement matrix of the cubic B-spline:
/// `S[A][a] = mask[A - d a]`, mask = (box_d)^{*4} / d^3.
fn bspline_matrix(n: usize, d: usize, p: usize) -> Vec<Vec<f64>> {
    let mut mask = vec![1.0];
    for _ in 0..p + 1 {
        let mut next = vec![0.0; mask.len() + d - 1];
        for (i, &x) in mask.iter().enumerate() {
            for t in 0..d {
                next[i + t] += x;
            }
        }
        mask = next;
    }
    let norm = (d as f64).powi(p as i32);
    let half = (mask.len() - 1) / 2;
    let big = n * d;
    let mut s = vec![vec![0.0; n]; big];
    for a in 0..n {
        for (o, &w) in mask.iter().enumerate() {
            let row = (d * a + big * 4 + o - half) % big;
            s[row][a] += w / norm;
        }
    }
    s
}

/// Vertex at global grid point (I, J) of a refined `torus(nu, nv)` with
/// split `d`: face (I/d, J/d), frame 0 point (I%d, J%d).
fn torus_vertex(
    r: &ccss_core::unified::UnifiedRefined,
    t: &Topology,
    nv: usize,
    d: usize,
    gi: usize,
    gj: usize,
) -> usize {
    let f = (gi / d) * nv + gj / d;
    r.frame_vertex(t, f, 0, gi % d, gj % d).unwrap() as usize
}

#[test]
fn regular_grids_refine_as_bicubic_bsplines_for_every_d() {
    // a = 0 on a regular quad grid: the refined net is the d-ary refinement
    // of the same tensor-product B-spline (degree p), so the limit is the
    // uniform B-spline surface of the input, for every d. b and g have no
    // effect there (D = 0; no extraordinary vertices).
    let (nu, nv) = (5, 6);
    let mut m = torus(nu, nv, 2.0, 0.7);
    let mut state = 7u64;
    for p in &mut m.positions {
        for c in p.iter_mut() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            *c += ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.2;
        }
    }
    for (d, p) in [
        (2, 3),
        (3, 3),
        (4, 3),
        (5, 3),
        (6, 3),
        (7, 3),
        (2, 5),
        (3, 5),
        (4, 1),
    ] {
        let params = UnifiedParams {
            a: 0.0,
            b: 0.5,
            g: 1.0,
            d,
            p,
            triangles: TriangleRule::Split,
        };
        let su = bspline_matrix(nu, d as usize, p as usize);
        let sv = bspline_matrix(nv, d as usize, p as usize);
        with_topo(&m, |t| {
            let mut mem = aligned(unified_bytes(t, &params).unwrap());
            let r = refine_unified(t, &params, &mut mem).unwrap();
            let out = own(r.mesh);
            let d = d as usize;
            let mut worst = 0.0f64;
            for gi in 0..nu * d {
                for gj in 0..nv * d {
                    let mut want = [0.0; 3];
                    for a in 0..nu {
                        for b in 0..nv {
                            let w = su[gi][a] * sv[gj][b];
                            if w != 0.0 {
                                for c in 0..3 {
                                    want[c] += w * m.positions[a * nv + b][c];
                                }
                            }
                        }
                    }
                    let v = torus_vertex(&r, t, nv, d, gi, gj);
                    worst = worst.max(dist(out.point(v), want));
                }
            }
            assert!(worst < 1e-13, "d={d} p={p}: {worst:e}");
        });
    }
}

#[test]
fn two_levels_on_a_regular_grid_compose_bspline_refinements() {
    let (nu, nv) = (4, 5);
    let m = torus(nu, nv, 2.0, 0.6);
    let levels = [
        UnifiedParams::default().with_d(3).with_a(0.0),
        UnifiedParams::default().with_d(2).with_a(0.0),
    ];
    with_topo(&m, |t| {
        let mut mem = aligned(unified_levels_bytes(t, &levels).unwrap());
        let l = refine_unified_levels(t, &levels, &mut mem).unwrap();
        assert_eq!(l.len(), 2);
        let fine = own(l.finest().unwrap());
        // Control points of the composed refinement (6-ary overall).
        let (su, sv) = (bspline_matrix(nu, 6, 3), bspline_matrix(nv, 6, 3));
        // The 6-ary refined net has nu*6 x nv*6 points; each of them is a
        // vertex of the two-level mesh. Match as sets (numbering of level 2
        // is relative to level 1's topology).
        let mut want: Vec<[f64; 3]> = Vec::new();
        for gi in 0..nu * 6 {
            for gj in 0..nv * 6 {
                let mut w3 = [0.0; 3];
                for a in 0..nu {
                    for b in 0..nv {
                        let w = su[gi][a] * sv[gj][b];
                        for c in 0..3 {
                            w3[c] += w * m.positions[a * nv + b][c];
                        }
                    }
                }
                want.push(w3);
            }
        }
        assert_eq!(fine.positions.len() / 3, want.len());
        for v in 0..want.len() {
            let p = fine.point(v);
            let best = want.iter().map(|&w| dist(w, p)).fold(f64::MAX, f64::min);
            assert!(
                best < 1e-12,
                "vertex {v} is not a 6-ary B-spline point ({best:e})"
            );
        }
    });
}

fn euler(c: &UnifiedCounts) -> i64 {
    c.vertices as i64 - c.edges as i64 + c.faces as i64
}

#[test]
fn counts_grow_by_d_squared_and_keep_euler() {
    for name in CLOSED {
        let m = mesh(name);
        for tri in [TriangleRule::Split, TriangleRule::Polygon] {
            for d in 2..=7u32 {
                let params = UnifiedParams {
                    d,
                    triangles: tri,
                    ..Default::default()
                };
                with_topo(&m, |t| {
                    let base = UnifiedCounts {
                        vertices: t.num_vertices(),
                        edges: t.num_edges(),
                        faces: t.num_faces(),
                        corners: t.num_half_edges(),
                    };
                    let c = unified_counts(t, &params).unwrap();
                    let mut mem = aligned(unified_bytes(t, &params).unwrap());
                    let r = refine_unified(t, &params, &mut mem).unwrap();
                    assert_eq!(r.counts(), c, "{name} d={d}: closed form vs built");
                    assert_eq!(euler(&c), euler(&base), "{name} d={d}: Euler");
                    let d = d as usize;
                    let quads = m.faces.iter().filter(|f| f.len() == 4).count();
                    let tris = m.faces.iter().filter(|f| f.len() == 3).count();
                    if quads == m.faces.len() {
                        assert_eq!(c.faces, d * d * t.num_faces(), "{name}: d^2 per quad");
                    }
                    if tri == TriangleRule::Split && tris == m.faces.len() {
                        assert_eq!(c.faces, d * d * t.num_faces(), "{name}: d^2 per triangle");
                    }
                    // Each input face's children are contiguous and of the
                    // documented number.
                    assert_eq!(*r.child_start.last().unwrap() as usize, c.faces);
                    // The refined mesh is a valid closed, consistently oriented
                    // manifold (the input of the next level).
                    let mut tm = aligned(Topology::required_bytes(c.vertices, r.mesh.face_sizes));
                    let rt = Topology::build(r.mesh, &mut tm).expect("refined mesh valid");
                    assert_eq!(rt.num_edges(), c.edges);
                });
            }
        }
    }
}

#[test]
fn push_back_one_interpolates_and_zero_shrinks() {
    // a = 1: the old vertices stay at their original positions (interpolating
    // scheme), for every d, b and p.
    for name in ["catmark_cube.obj", "catmark_pyramid.obj", "drum5"] {
        let m = mesh(name);
        for d in 2..=5 {
            for (b, p) in [(0.0, 3), (0.5, 3), (1.0, 5)] {
                let out = unified(
                    &m,
                    &UnifiedParams {
                        a: 1.0,
                        b,
                        g: 0.0,
                        d,
                        p,
                        triangles: TriangleRule::Split,
                    },
                );
                for (v, &q) in m.positions.iter().enumerate() {
                    assert!(dist(out.point(v), q) < 1e-14, "{name} d={d} vertex {v}");
                }
            }
        }
    }
}

#[test]
fn push_back_reduces_shrinking_on_the_cube() {
    // The cube's vertices lie on the sphere of radius sqrt(3) * h; the mean
    // distance of refined vertices from the centre grows with a.
    let m = corpus("catmark_cube.obj");
    let mean_r = |o: &Out| {
        let n = o.positions.len() / 3;
        (0..n).map(|v| dist(o.point(v), [0.0; 3])).sum::<f64>() / n as f64
    };
    for d in [2, 3, 4] {
        let mut last = 0.0;
        for a in [0.0, 0.5, 0.7, 1.0] {
            let r = mean_r(&unified(&m, &UnifiedParams::default().with_d(d).with_a(a)));
            assert!(r > last, "d={d} a={a}: {r} <= {last}");
            last = r;
        }
    }
}

#[test]
fn renormalisation_interpolates_lengths() {
    // Cube (g = 0, p = 3): after smoothing, all eight corners have push-back
    // vectors of equal length L. With b = 1 every new vertex's push-back
    // vector also has length L (eqs. (18)-(21)); with b = 0 it is shorter
    // (bilinear interpolation of differently directed vectors).
    let m = corpus("catmark_cube.obj");
    for d in [2, 3, 4, 5] {
        let base = UnifiedParams {
            a: 0.0,
            b: 0.0,
            g: 0.0,
            d,
            p: 3,
            triangles: TriangleRule::Split,
        };
        let s = unified(&m, &base);
        let plain = unified(&m, &UnifiedParams { a: 0.6, ..base });
        let round = unified(
            &m,
            &UnifiedParams {
                a: 0.6,
                b: 1.0,
                ..base
            },
        );
        let half = unified(
            &m,
            &UnifiedParams {
                a: 0.6,
                b: 0.5,
                ..base
            },
        );
        let l = dist(plain.point(0), s.point(0));
        for v in 0..s.positions.len() / 3 {
            let lp = dist(plain.point(v), s.point(v));
            let lr = dist(round.point(v), s.point(v));
            let lh = dist(half.point(v), s.point(v));
            assert!((lr - l).abs() < 1e-12 * l, "d={d} v={v}: {lr} vs {l}");
            assert!(lp <= l * (1.0 + 1e-12));
            assert!(
                (lh - 0.5 * (lp + lr)).abs() < 1e-12,
                "d={d} v={v}: b=1/2 is the mean"
            );
        }
    }
}

#[test]
fn correction_is_local_to_extraordinary_vertices() {
    // d = 3..6 on the cube: the correction (g = 1) only moves the corners
    // and points within half an edge of them, with weights (1-2s)(1-2t).
    let m = corpus("catmark_cube.obj");
    for d in 3..=6u32 {
        let base = UnifiedParams {
            a: 0.0,
            b: 0.0,
            g: 0.0,
            d,
            p: 3,
            triangles: TriangleRule::Split,
        };
        let s0 = unified(&m, &base);
        let s1 = unified(&m, &UnifiedParams { g: 1.0, ..base });
        with_topo(&m, |t| {
            let mut mem = aligned(unified_bytes(t, &base).unwrap());
            let r = refine_unified(t, &base, &mut mem).unwrap();
            let d = d as usize;
            for f in 0..6 {
                for k in 0..4 {
                    let corner = r.frame_vertex(t, f, k, 0, 0).unwrap() as usize;
                    let c = [
                        s1.point(corner)[0] - s0.point(corner)[0],
                        s1.point(corner)[1] - s0.point(corner)[1],
                        s1.point(corner)[2] - s0.point(corner)[2],
                    ];
                    assert!(dist(c, [0.0; 3]) > 1e-3);
                    for i in 0..=d / 2 {
                        for j in 0..=d / 2 {
                            let v = r.frame_vertex(t, f, k, i, j).unwrap() as usize;
                            let w = (1.0 - 2.0 * i as f64 / d as f64).max(0.0)
                                * (1.0 - 2.0 * j as f64 / d as f64).max(0.0);
                            for a in 0..3 {
                                let moved = s1.point(v)[a] - s0.point(v)[a];
                                assert!(
                                    (moved - w * c[a]).abs() < 1e-14,
                                    "d={d} f={f} k={k} ({i},{j})"
                                );
                            }
                        }
                    }
                }
            }
        });
    }
}

#[test]
fn frames_of_a_face_agree() {
    // The same grid point addressed from each corner frame is one vertex.
    for name in [
        "catmark_cube.obj",
        "catmark_pyramid.obj",
        "drum5",
        "icosahedron",
    ] {
        let m = mesh(name);
        for d in 2..=6u32 {
            for tri in [TriangleRule::Split, TriangleRule::Polygon] {
                let params = UnifiedParams {
                    d,
                    triangles: tri,
                    ..Default::default()
                };
                with_topo(&m, |t| {
                    let mut mem = aligned(unified_bytes(t, &params).unwrap());
                    let r = refine_unified(t, &params, &mut mem).unwrap();
                    let d = d as usize;
                    for f in 0..t.num_faces() {
                        let n = t.face_size(f);
                        for k in 0..n {
                            let k1 = (k + 1) % n;
                            for i in 0..=d {
                                for j in 0..=d / 2 {
                                    let a = r.frame_vertex(t, f, k, i, j);
                                    // Same point from frame k+1: (j, d - i).
                                    let b = r.frame_vertex(t, f, k1, j, d - i);
                                    if n == 3 && tri == TriangleRule::Split {
                                        if i + j <= d {
                                            // Frame k+1 of a triangle: (j, d-i-j).
                                            let b = r.frame_vertex(t, f, k1, j, d - i - j);
                                            assert_eq!(a, b, "{name} tri f={f} k={k} ({i},{j})");
                                        }
                                    } else {
                                        assert_eq!(a, b, "{name} d={d} f={f} k={k} ({i},{j})");
                                    }
                                }
                            }
                        }
                    }
                });
            }
        }
    }
}

#[test]
fn levels_equal_repeated_steps() {
    let m = corpus("catmark_pyramid.obj");
    let levels = [
        UnifiedParams::default().with_d(3),
        UnifiedParams {
            a: 0.7,
            b: 0.0,
            g: 1.0,
            d: 2,
            p: 3,
            triangles: TriangleRule::Polygon,
        },
        UnifiedParams::default().with_d(2),
    ];
    let mut step = m.clone();
    let mut singles = Vec::new();
    for p in &levels {
        let o = unified(&step, p);
        step = o.to_poly();
        singles.push(o);
    }
    with_topo(&m, |t| {
        let need = unified_levels_bytes(t, &levels).unwrap();
        let mut mem = aligned(need);
        let l = refine_unified_levels(t, &levels, &mut mem).unwrap();
        assert_eq!(l.len(), 3);
        for (a, b) in l.meshes().iter().zip(&singles) {
            assert_eq!(a.indices, &b.indices[..]);
            assert_eq!(a.positions, &b.positions[..]);
        }
        // Exact size: 8 bytes (one word) short fails with the same requirement.
        let mut small = aligned(need - 8);
        assert_eq!(
            refine_unified_levels(t, &levels, &mut small[..need / 8 - 1]).err(),
            Some(Error::BufferTooSmall { required: need })
        );
        // No levels: nothing to do.
        assert!(refine_unified_levels(t, &[], &mut []).unwrap().is_empty());
    });
}

#[test]
fn size_query_is_exact_and_errors_are_clear() {
    let m = mesh("drum5");
    with_topo(&m, |t| {
        for d in [2, 3, 4] {
            let p = UnifiedParams::default().with_d(d);
            let need = unified_bytes(t, &p).unwrap();
            let mut mem = aligned(need);
            assert!(refine_unified(t, &p, &mut mem[..need / 8]).is_ok());
            assert_eq!(
                refine_unified(t, &p, &mut mem[..need / 8 - 1]).err(),
                Some(Error::BufferTooSmall { required: need })
            );
        }
        let bad = |p: UnifiedParams| unified_bytes(t, &p).err();
        let ok = UnifiedParams::default();
        assert!(matches!(
            bad(UnifiedParams { d: 1, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            bad(UnifiedParams { p: 4, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            bad(UnifiedParams { a: f64::NAN, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            bad(UnifiedParams {
                b: f64::INFINITY,
                ..ok
            }),
            Some(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            bad(UnifiedParams { g: f64::NAN, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            bad(UnifiedParams { d: 5000, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        // Too large a result: a clear error, no overflow.
        assert!(matches!(
            bad(UnifiedParams { d: 4096, ..ok }),
            Some(Error::InvalidArgument(_))
        ));
        let deep = [UnifiedParams::default(); 17];
        assert!(matches!(
            unified_levels_bytes(t, &deep),
            Err(Error::InvalidArgument(_))
        ));
        let many = [UnifiedParams::default().with_d(9); 12];
        assert!(matches!(
            unified_levels_bytes(t, &many),
            Err(Error::InvalidArgument(_))
        ));
    });
}

#[test]
fn extreme_parameters_stay_finite() {
    // Large but finite a, b, g and p: no panic, finite output on a mesh
    // with triangles, quads and pentagons.
    for name in ["catmark_pyramid.obj", "drum5", "icosahedron"] {
        let m = mesh(name);
        for (a, b, g, d, p) in [
            (5.0, -3.0, 7.0, 3, 7),
            (-2.0, 10.0, -4.0, 4, 5),
            (1.0, 1.0, 1.0, 9, 3),
            (0.5, 0.5, 0.0, 2, 1),
        ] {
            for tri in [TriangleRule::Split, TriangleRule::Polygon] {
                let out = unified(
                    &m,
                    &UnifiedParams {
                        a,
                        b,
                        g,
                        d,
                        p,
                        triangles: tri,
                    },
                );
                assert!(out.positions.iter().all(|x| x.is_finite()), "{name}");
            }
        }
    }
}
