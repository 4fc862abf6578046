//! Self-tests of the reference Catmull-Clark oracle (`ccss_tests::reference`)
//! against independent computations: hand-computed values, uniform bicubic
//! B-spline evaluation on a regular torus, topological invariants, and
//! continuity of the dyadic parameterization across shared edges.

use std::collections::HashMap;
use std::path::PathBuf;

use ccss_tests::reference::{
    catmull_clark, catmull_clark_weighted, drum, dyadic_limit_point, dyadic_limit_point_weighted,
    limit_position, limit_position_weighted, pole_mesh, standard_weights, torus, PolyMesh, Refiner,
    Weights,
};

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn assert_close(a: [f64; 3], b: [f64; 3], tol: f64, what: &str) {
    let d = dist(a, b);
    assert!(
        d <= tol,
        "{what}: {a:?} vs {b:?} differ by {d:e} (tolerance {tol:e})"
    );
}

fn custom_weights(_n: usize) -> (f64, f64, f64) {
    (0.5, 0.3, 0.2)
}

/// Unit cube [-1,1]^3 with outward faces.
fn cube() -> PolyMesh {
    let mut positions = Vec::new();
    for i in 0..8u32 {
        let c = |bit: u32| if i & bit != 0 { 1.0 } else { -1.0 };
        positions.push([c(1), c(2), c(4)]);
    }
    // Vertex index = x + 2y + 4z (bits).
    let faces = vec![
        vec![0, 2, 3, 1], // z = -1
        vec![4, 5, 7, 6], // z = +1
        vec![0, 1, 5, 4], // y = -1
        vec![2, 6, 7, 3], // y = +1
        vec![0, 4, 6, 2], // x = -1
        vec![1, 3, 7, 5], // x = +1
    ];
    PolyMesh { positions, faces }
}

/// Independent closed-manifold check: every directed edge used exactly once
/// and its reverse exactly once. Returns the number of undirected edges.
fn check_closed_oriented(m: &PolyMesh) -> usize {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for f in &m.faces {
        for k in 0..f.len() {
            *directed.entry((f[k], f[(k + 1) % f.len()])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(count, 1, "directed edge ({a},{b}) used {count} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge ({a},{b}) has no opposite half-edge"
        );
    }
    directed.len() / 2
}

// ---------------------------------------------------------------------------
// 1. Regular torus: dyadic limit points == uniform bicubic B-spline.

fn bspline_basis(t: f64) -> [f64; 4] {
    [
        (1.0 - t).powi(3) / 6.0,
        (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t.powi(3) / 6.0,
    ]
}

/// Evaluates the bicubic B-spline patch of torus face (fi, fj) directly from
/// the generator's grid: vertex (i, j) has index i * nv + j, face (i, j)
/// spans grid cell [i, i+1] x [j, j+1] with u along i and v along j.
fn torus_bspline(
    m: &PolyMesh,
    nu: usize,
    nv: usize,
    fi: usize,
    fj: usize,
    u: f64,
    v: f64,
) -> [f64; 3] {
    let bu = bspline_basis(u);
    let bv = bspline_basis(v);
    let mut p = [0.0; 3];
    for (a, wu) in bu.iter().enumerate() {
        for (b, wv) in bv.iter().enumerate() {
            let i = (fi + nu + a - 1) % nu;
            let j = (fj + nv + b - 1) % nv;
            let q = m.positions[i * nv + j];
            let w = wu * wv;
            for c in 0..3 {
                p[c] += w * q[c];
            }
        }
    }
    p
}

#[test]
fn torus_dyadic_points_match_bicubic_bspline() {
    let (nu, nv) = (8, 6);
    let m = torus(nu, nv, 2.0, 0.6);
    check_closed_oriented(&m);
    for v in 0..m.positions.len() as u32 {
        assert_eq!(m.valence(v), 4);
    }
    let mut refiner = Refiner::new(&m, None);
    let faces = [(0usize, 0usize), (3, 2), (7, 5), (5, 1)];
    let mut count = 0;
    for &(fi, fj) in &faces {
        let face = fi * nv + fj;
        assert_eq!(
            m.faces[face][0] as usize,
            fi * nv + fj,
            "generator grid layout"
        );
        for k in 0..=4u32 {
            let n = 1u32 << k;
            // A spread of points including the boundary and corners.
            for i in (0..=n).step_by(((n / 4).max(1)) as usize) {
                for j in (0..=n).step_by(((n / 2).max(1)) as usize) {
                    let got = refiner.dyadic_limit_point(face, 0, i, j, k);
                    let u = i as f64 / n as f64;
                    let v = j as f64 / n as f64;
                    let want = torus_bspline(&m, nu, nv, fi, fj, u, v);
                    assert_close(
                        got,
                        want,
                        1e-12,
                        &format!("face ({fi},{fj}) at ({i},{j})/2^{k}"),
                    );
                    count += 1;
                }
            }
        }
        // Some odd interior points at the finest level.
        for &(i, j) in &[(1u32, 1u32), (3, 7), (13, 5), (15, 15), (9, 0), (16, 11)] {
            let got = refiner.dyadic_limit_point(face, 0, i, j, 4);
            let want = torus_bspline(&m, nu, nv, fi, fj, i as f64 / 16.0, j as f64 / 16.0);
            assert_close(
                got,
                want,
                1e-12,
                &format!("face ({fi},{fj}) at ({i},{j})/16"),
            );
            count += 1;
        }
    }
    assert!(count > 100);
    // The free function agrees with the refiner.
    let face = 3 * nv + 2;
    assert_eq!(
        dyadic_limit_point(&m, face, 0, 5, 3, 3),
        refiner.dyadic_limit_point(face, 0, 5, 3, 3)
    );
}

// ---------------------------------------------------------------------------
// 2. Topology and numbering of one step.

#[test]
fn drum_step_topology() {
    let base = drum(5);
    let (v0, f0) = (base.positions.len(), base.faces.len());
    let e0 = check_closed_oriented(&base);
    assert_eq!((v0, e0, f0), (10, 15, 7));
    assert_eq!(v0 as i64 - e0 as i64 + f0 as i64, 2);
    let corners: usize = base.faces.iter().map(|f| f.len()).sum();
    assert_eq!(corners, 30);

    let m = catmull_clark(&base);
    assert_eq!(m.positions.len(), v0 + e0 + f0);
    assert_eq!(m.faces.len(), corners);
    assert!(m.faces.iter().all(|f| f.len() == 4));
    let e1 = check_closed_oriented(&m);
    assert_eq!(e1, 2 * e0 + corners);
    assert_eq!(
        m.positions.len() as i64 - e1 as i64 + m.faces.len() as i64,
        2
    );

    // Numbering: child k of face f is [v_k, ep, fp(f), ep], first face's edges
    // get the first edge points in order.
    let mut child = 0;
    for (fi, f) in base.faces.iter().enumerate() {
        let n = f.len();
        for (k, &vk) in f.iter().enumerate() {
            let c = &m.faces[child];
            assert_eq!(c[0], vk);
            assert_eq!(c[2] as usize, v0 + e0 + fi);
            // Edge point of (v_k, v_{k+1}) is shared with the next child's last.
            let next = &m.faces[child - k + (k + 1) % n];
            assert_eq!(c[1], next[3]);
            child += 1;
        }
    }
    for k in 0..base.faces[0].len() {
        assert_eq!(
            m.faces[k][1] as usize,
            v0 + k,
            "first face's edges numbered first"
        );
    }
    // Face points are centroids; edge points by definition.
    assert_close(
        m.positions[v0 + e0 + 1],
        [0.0, 0.0, 0.5],
        1e-15,
        "top cap face point",
    );
    assert_close(
        m.positions[v0 + e0],
        [0.0, 0.0, -0.5],
        1e-15,
        "bottom cap face point",
    );

    // Second step keeps Euler characteristic too.
    let m2 = catmull_clark(&m);
    let e2 = check_closed_oriented(&m2);
    assert_eq!(
        m2.positions.len() as i64 - e2 as i64 + m2.faces.len() as i64,
        2
    );
}

#[test]
fn cube_step_hand_computed() {
    let c = cube();
    check_closed_oriented(&c);
    let m = catmull_clark(&c);
    // Corner (1,1,1) = vertex 7 moves to (5/9, 5/9, 5/9).
    assert_close(m.positions[7], [5.0 / 9.0; 3], 1e-15, "cube vertex point");
    assert_close(m.positions[0], [-5.0 / 9.0; 3], 1e-15, "cube vertex point");
    // Face points of the z=+1 face (face 1) = (0,0,1).
    assert_close(
        m.positions[8 + 12 + 1],
        [0.0, 0.0, 1.0],
        1e-15,
        "cube face point",
    );
    // Edge (0,2) (first edge of face 0): between (-1,-1,-1) and (-1,1,-1),
    // faces z=-1 and x=-1: ((-1,-1,-1)+(-1,1,-1)+(0,0,-1)+(-1,0,0))/4.
    assert_close(
        m.positions[8],
        [-0.75, 0.0, -0.75],
        1e-15,
        "cube edge point",
    );
    // Weighted rule with standard weights gives the same values.
    let mw = catmull_clark_weighted(&c, &standard_weights);
    assert_close(
        mw.positions[7],
        [5.0 / 9.0; 3],
        1e-15,
        "cube weighted vertex point",
    );
    // Limit position of a cube corner: (9V + 4ΣE + ΣF)/24 with V=(1,1,1),
    // ΣE=(1,1,1), ΣF=(-1,-1,-1): (9+4-1)/24 = 1/2.
    assert_close(limit_position(&c, 7), [0.5; 3], 1e-15, "cube corner limit");
}

// ---------------------------------------------------------------------------
// 3. Weighted rule with standard weights == standard rule.

#[test]
fn weighted_standard_equals_standard() {
    for base in [
        drum(5),
        drum(3),
        pole_mesh(6),
        torus(5, 4, 2.0, 0.5),
        cube(),
    ] {
        let mut a = base.clone();
        let mut b = base.clone();
        for _ in 0..2 {
            a = catmull_clark(&a);
            b = catmull_clark_weighted(&b, &standard_weights);
            assert_eq!(a.faces, b.faces);
            let scale = a.bbox_diagonal();
            for (pa, pb) in a.positions.iter().zip(&b.positions) {
                assert_close(*pa, *pb, 1e-14 * scale, "weighted(standard) vs standard");
            }
        }
    }
    // And non-standard weights really change vertex points (only those).
    let base = drum(5);
    let a = catmull_clark(&base);
    let b = catmull_clark_weighted(&base, &custom_weights);
    assert_eq!(a.faces, b.faces);
    let nv = base.positions.len();
    for (idx, (pa, pb)) in a.positions.iter().zip(&b.positions).enumerate() {
        if idx < nv {
            assert!(dist(*pa, *pb) > 1e-3, "vertex point {idx} should change");
        } else {
            assert_eq!(pa, pb, "edge/face point {idx} must not depend on weights");
        }
    }
}

// ---------------------------------------------------------------------------
// 4. Limit positions: invariant across levels, and approached by the
//    subdivided vertex positions.

fn check_limits(w: Option<&Weights>) {
    let base = pole_mesh(5);
    let mut refiner = Refiner::new(&base, w);
    let limit_at = |m: &PolyMesh, v: u32| match w {
        None => limit_position(m, v),
        Some(w) => limit_position_weighted(m, v, w),
    };
    let nv = base.positions.len() as u32;
    let levels = 6;
    for k in 0..levels {
        refiner.level(k);
    }
    let meshes: Vec<PolyMesh> = (0..levels).map(|k| refiner.level(k).clone()).collect();
    let valences: Vec<usize> = (0..nv).map(|v| base.valence(v)).collect();
    assert!(valences.contains(&3) && valences.contains(&4) && valences.contains(&5));
    for v in 0..nv {
        let limit = limit_at(&meshes[0], v);
        // Invariance: the same vertex index has the same limit at every level.
        for (k, mk) in meshes.iter().enumerate().skip(1) {
            assert_close(
                limit_at(mk, v),
                limit,
                1e-13,
                &format!(
                    "limit of vertex {v} (valence {}) at level {k} vs level 0",
                    valences[v as usize]
                ),
            );
        }
        // Convergence: distance from the limit shrinks geometrically.
        let d: Vec<f64> = meshes
            .iter()
            .map(|mk| dist(mk.positions[v as usize], limit))
            .collect();
        assert!(d[0] > 1e-3, "vertex {v} starts away from its limit");
        // (Over two steps: with custom weights the subdominant eigenvalues of
        // the vertex's local subdivision matrix can be complex, so the
        // distance need not shrink at every single step.)
        for k in 0..levels - 2 {
            assert!(
                d[k + 2] <= 0.5 * d[k],
                "vertex {v}: distances to limit {d:?}"
            );
        }
        assert!(
            d[levels - 1] <= 1e-2 * d[0],
            "vertex {v}: distances to limit {d:?}"
        );
    }
    // The refiner's own limit_position agrees with the free functions.
    assert_eq!(refiner.limit_position(2, 7), limit_at(&meshes[2], 7));
}

#[test]
fn limit_positions_standard() {
    check_limits(None);
}

#[test]
fn limit_positions_weighted() {
    check_limits(Some(&custom_weights));
}

#[test]
fn limit_weighted_with_standard_weights_equals_standard_mask() {
    let m = pole_mesh(7);
    for v in 0..m.positions.len() as u32 {
        let a = limit_position(&m, v);
        let b = limit_position_weighted(&m, v, &standard_weights);
        assert_close(a, b, 1e-14, "limit masks");
    }
}

// ---------------------------------------------------------------------------
// 5. Continuity: dyadic points on a shared edge agree from both faces.

/// Parameter (in units of 2^-k) of the point at fraction m/2^k along the edge
/// from corner c to corner c+1 of a quad, plus the sub-face (always 0).
fn quad_edge_param(c: usize, m: u32, k: u32) -> (usize, u32, u32) {
    let n = 1u32 << k;
    let corners = [(0, 0), (n, 0), (n, n), (0, n)];
    let (a, b) = (corners[c], corners[(c + 1) % 4]);
    // a + m/n (b - a) in integer units: a*n + m*(b-a) over n, scaled by n.
    let lerp = |x: u32, y: u32| (x as i64 + (m as i64) * (y as i64 - x as i64) / n as i64) as u32;
    (0, lerp(a.0, b.0), lerp(a.1, b.1))
}

/// 3D point at fraction m/2^k along the edge from face[c] to face[c+1].
fn edge_point(r: &mut Refiner, face: usize, c: usize, m: u32, k: u32) -> [f64; 3] {
    let n_face = r.level(0).faces[face].len();
    if n_face == 4 {
        let (sub, i, j) = quad_edge_param(c, m, k);
        r.dyadic_limit_point(face, sub, i, j, k)
    } else {
        // Sub-face c covers the first half of the edge along its s axis,
        // sub-face c+1 covers the second half along its t axis (from v_{c+1}).
        let half = 1u32 << (k - 1);
        if m <= half {
            r.dyadic_limit_point(face, c, m, 0, k - 1)
        } else {
            r.dyadic_limit_point(face, (c + 1) % n_face, 0, (1u32 << k) - m, k - 1)
        }
    }
}

fn check_shared_edges(base: &PolyMesh, w: Option<&Weights>, k: u32) {
    let mut r = Refiner::new(base, w);
    let scale = base.bbox_diagonal();
    let n = 1u32 << k;
    // Map directed edge -> (face, corner).
    let mut half_edges: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for (fi, f) in base.faces.iter().enumerate() {
        for c in 0..f.len() {
            half_edges.insert((f[c], f[(c + 1) % f.len()]), (fi, c));
        }
    }
    let mut checked = 0;
    for (fi, f) in base.faces.iter().enumerate() {
        for c in 0..f.len() {
            let (a, b) = (f[c], f[(c + 1) % f.len()]);
            let (g, gc) = half_edges[&(b, a)];
            for m in 0..=n {
                let p = edge_point(&mut r, fi, c, m, k);
                let q = edge_point(&mut r, g, gc, n - m, k);
                assert_close(
                    p,
                    q,
                    1e-12 * scale,
                    &format!("edge ({a},{b}) faces {fi}/{g} at {m}/{n}"),
                );
                checked += 1;
            }
            // The end points are the limit positions of the edge's vertices.
            let pa = edge_point(&mut r, fi, c, 0, k);
            let la = r.limit_position(1, a);
            assert_close(pa, la, 1e-12 * scale, "edge start == vertex limit");
        }
    }
    assert!(checked > 0);
}

#[test]
fn shared_edges_agree_drum() {
    // Includes the pentagon caps (sub-face parameterization) vs side quads.
    let base = drum(5);
    check_shared_edges(&base, None, 3);
    check_shared_edges(&base, Some(&custom_weights), 3);
}

#[test]
fn shared_edges_agree_pole_mesh() {
    let base = pole_mesh(5);
    check_shared_edges(&base, None, 3);
    check_shared_edges(&base, Some(&custom_weights), 2);
}

#[test]
fn subfaces_of_a_non_quad_agree_inside_the_face() {
    // Within a pentagon, sub-face k's side t = 1 (from the midpoint of edge
    // (v_{k-1}, v_k) at s = 0 to the centre at s = 1) is sub-face k-1's side
    // s = 1 (midpoint at t = 0, centre at t = 1): (s, 1) in k == (1, s) in k-1.
    let base = drum(5);
    let mut r = Refiner::new(&base, None);
    let mut rw = Refiner::new(&base, Some(&custom_weights));
    let k = 3;
    let n = 1u32 << k;
    for face in 0..2 {
        let centre = r.dyadic_limit_point(face, 0, n, n, k);
        for sub in 0..5 {
            let prev = (sub + 4) % 5;
            for s in 0..=n {
                let a = r.dyadic_limit_point(face, sub, s, n, k);
                let b = r.dyadic_limit_point(face, prev, n, s, k);
                assert_close(a, b, 1e-12, "sub-face seam");
                let a = rw.dyadic_limit_point(face, sub, s, n, k);
                let b = rw.dyadic_limit_point(face, prev, n, s, k);
                assert_close(a, b, 1e-12, "sub-face seam (weighted)");
            }
            assert_close(
                r.dyadic_limit_point(face, sub, n, n, k),
                centre,
                1e-12,
                "centre",
            );
        }
        // By symmetry the limit centre of a cap lies on the axis.
        assert!(centre[0].abs() < 1e-12 && centre[1].abs() < 1e-12);
    }
    // Free weighted function agrees with the refiner.
    assert_eq!(
        dyadic_limit_point_weighted(&base, 0, 2, 3, 5, 3, &custom_weights),
        rw.dyadic_limit_point(0, 2, 3, 5, 3)
    );
}

// ---------------------------------------------------------------------------
// OBJ loading.

fn osd(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/osd")
        .join(name)
}

#[test]
fn from_obj_loads_closed_meshes() {
    let cube = PolyMesh::from_obj(&osd("catmark_cube.obj"));
    assert_eq!(cube.positions.len(), 8);
    assert_eq!(cube.faces.len(), 6);
    assert!(cube.faces.iter().all(|f| f.len() == 4));
    assert_eq!(check_closed_oriented(&cube), 12);
    // 2.828428 x 2.828428 x 2 box.
    let expected = (2.0f64 * 2.828428 * 2.828428 + 2.0 * 2.0).sqrt();
    assert!((cube.bbox_diagonal() - expected).abs() < 1e-5);
    let _ = catmull_clark(&cube);

    let pyramid = PolyMesh::from_obj(&osd("catmark_pyramid.obj"));
    assert_eq!(pyramid.positions.len(), 5);
    let sizes: Vec<usize> = pyramid.faces.iter().map(|f| f.len()).collect();
    assert_eq!(sizes, vec![3, 3, 3, 3, 4]);
    assert_eq!(check_closed_oriented(&pyramid), 8);
    let m = catmull_clark(&pyramid);
    assert_eq!(m.faces.len(), 16);
}

#[test]
#[should_panic(expected = "boundary edge")]
fn catmull_clark_rejects_open_meshes() {
    let mut m = cube();
    m.faces.pop();
    let _ = catmull_clark(&m);
}
