//! Independent checks of the evaluator away from dyadic points:
//! regular patches equal the bicubic B-spline (derivatives included),
//! neighbouring patches agree along shared edges (positions and normals),
//! derivatives agree with central finite differences, and the limit
//! tangent plane at an extraordinary vertex is the limit of nearby normals.
use ccss_core::math::bspline::eval_points as eval_grid;
use ccss_core::{DVec3, Evaluator};
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, torus, PolyMesh};
use std::path::Path;

fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/osd")
            .join(name),
    )
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn v3(p: [f64; 3]) -> DVec3 {
    DVec3::new(p[0], p[1], p[2])
}

#[test]
fn regular_patches_equal_bicubic_bspline_with_derivatives() {
    let (nu, nv) = (8, 6);
    let m = torus(nu, nv, 2.0, 0.6);
    let mut rng = Rng(1);
    with_evaluator(&m, standard_tables(), |_, ev| {
        assert_eq!(ev.patch_counts(), (nu * nv, 0));
        let mut worst = 0.0f64;
        for i in 0..nu {
            for j in 0..nv {
                let f = i * nv + j;
                let mut grid = [DVec3::ZERO; 16];
                for b in 0..4 {
                    for a in 0..4 {
                        let vi = ((i + nu + a - 1) % nu) * nv + (j + nv + b - 1) % nv;
                        grid[b * 4 + a] = v3(m.positions[vi]);
                    }
                }
                for _ in 0..20 {
                    let (u, v) = (rng.next(), rng.next());
                    let want = eval_grid::<true>(&grid, u, v);
                    let got = ev.eval_second(f as u32, 0, u, v).unwrap();
                    for (g, w) in [
                        (got.p, want.p),
                        (got.du, want.du),
                        (got.dv, want.dv),
                        (got.duu, want.duu),
                        (got.duv, want.duv),
                        (got.dvv, want.dvv),
                    ] {
                        worst = worst.max((g - w).length());
                    }
                }
            }
        }
        assert!(worst < 1e-13, "worst {worst}");
    })
    .unwrap();
}

/// (sub, u, v) of the point at fraction `t` along edge `k` (v_k -> v_k+1) of face `f`.
fn edge_param(m: &PolyMesh, f: usize, k: usize, t: f64) -> (u32, f64, f64) {
    let n = m.faces[f].len();
    if n == 4 {
        let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let (a, b) = (c[k], c[(k + 1) % 4]);
        (0, a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
    } else if t <= 0.5 {
        (k as u32, 2.0 * t, 0.0)
    } else {
        (((k + 1) % n) as u32, 0.0, 2.0 * (1.0 - t))
    }
}

/// For every edge, points from both adjacent faces coincide and their
/// normals agree (G1 across patch boundaries); also across the internal
/// edges between sub-faces of n-gons.
fn check_edges(name: &str, m: &PolyMesh) {
    let diag = m.bbox_diagonal();
    let mut rng = Rng(7);
    let mut owner = std::collections::HashMap::new();
    for (f, face) in m.faces.iter().enumerate() {
        for k in 0..face.len() {
            owner.insert((face[k], face[(k + 1) % face.len()]), (f, k));
        }
    }
    with_evaluator(m, standard_tables(), |_, ev: &Evaluator| {
        let (mut wp, mut wn) = (0.0f64, 0.0f64);
        for (f, face) in m.faces.iter().enumerate() {
            let n = face.len();
            for k in 0..n {
                let (a, b) = (face[k], face[(k + 1) % n]);
                let &(g, j) = owner.get(&(b, a)).unwrap();
                for _ in 0..8 {
                    let t = 0.02 + 0.96 * rng.next();
                    let (s1, u1, v1) = edge_param(m, f, k, t);
                    let (s2, u2, v2) = edge_param(m, g, j, 1.0 - t);
                    let e1 = ev.eval(f as u32, s1, u1, v1).unwrap();
                    let e2 = ev.eval(g as u32, s2, u2, v2).unwrap();
                    wp = wp.max((e1.p - e2.p).length() / diag);
                    wn = wn.max((e1.normal - e2.normal).length());
                }
            }
            if n != 4 {
                // Internal edges: sub k's v-edge (u=0) is sub k-1's u-edge reversed... (0,t) of
                // sub k equals (t,0)... : sub k edge (1,0)->(1,1) meets sub k+1 edge (0,1)->(1,1).
                for k in 0..n {
                    let t = rng.next();
                    let e1 = ev.eval(f as u32, k as u32, 1.0, t).unwrap();
                    let e2 = ev.eval(f as u32, ((k + 1) % n) as u32, t, 1.0).unwrap();
                    wp = wp.max((e1.p - e2.p).length() / diag);
                    wn = wn.max((e1.normal - e2.normal).length());
                }
            }
        }
        eprintln!("{name}: max position gap/diag {wp:.2e}, max normal gap {wn:.2e}");
        assert!(wp < 1e-13, "{name}: position gap {wp:e}");
        assert!(wn < 1e-9, "{name}: normal gap {wn:e}");
    })
    .unwrap();
}

#[test]
fn neighbouring_patches_agree_along_shared_edges() {
    for name in [
        "catmark_cube.obj",
        "catmark_pyramid.obj",
        "catmark_toroidal_tet.obj",
        "catmark_righthanded.obj",
    ] {
        check_edges(name, &corpus(name));
    }
    for n in [3, 5, 7, 12] {
        check_edges(&format!("pole_mesh({n})"), &pole_mesh(n));
    }
    for n in [5, 8] {
        check_edges(&format!("drum({n})"), &drum(n));
    }
}

#[test]
fn derivatives_match_central_finite_differences() {
    let mut rng = Rng(3);
    for (name, m) in [
        ("pole_mesh(5)", pole_mesh(5)),
        ("pole_mesh(3)", pole_mesh(3)),
        ("drum(6)", drum(6)),
        ("righthanded", corpus("catmark_righthanded.obj")),
    ] {
        with_evaluator(&m, standard_tables(), |_, ev| {
            let mut worst1 = 0.0f64;
            let mut worst2 = 0.0f64;
            for f in 0..m.faces.len().min(120) {
                for sub in 0..ev.num_subfaces(f) {
                    for _ in 0..4 {
                        let u = 0.05 + 0.9 * rng.next();
                        let v = 0.05 + 0.9 * rng.next();
                        let h = 1e-5;
                        let (f32_, s) = (f as u32, sub as u32);
                        let e = ev.eval_second(f32_, s, u, v).unwrap();
                        let pu = ev.eval_second(f32_, s, u + h, v).unwrap();
                        let mu = ev.eval_second(f32_, s, u - h, v).unwrap();
                        let pv = ev.eval_second(f32_, s, u, v + h).unwrap();
                        let mv = ev.eval_second(f32_, s, u, v - h).unwrap();
                        let scale = 1.0 + e.du.length() + e.dv.length();
                        worst1 = worst1.max(((pu.p - mu.p) / (2.0 * h) - e.du).length() / scale);
                        worst1 = worst1.max(((pv.p - mv.p) / (2.0 * h) - e.dv).length() / scale);
                        let scale2 = 1.0 + e.duu.length() + e.duv.length() + e.dvv.length();
                        worst2 =
                            worst2.max(((pu.du - mu.du) / (2.0 * h) - e.duu).length() / scale2);
                        worst2 =
                            worst2.max(((pv.du - mv.du) / (2.0 * h) - e.duv).length() / scale2);
                        worst2 =
                            worst2.max(((pu.dv - mu.dv) / (2.0 * h) - e.duv).length() / scale2);
                        worst2 =
                            worst2.max(((pv.dv - mv.dv) / (2.0 * h) - e.dvv).length() / scale2);
                    }
                }
            }
            eprintln!("{name}: FD relative error first {worst1:.2e}, second {worst2:.2e}");
            assert!(worst1 < 1e-7, "{name}: first derivatives {worst1:e}");
            assert!(worst2 < 1e-6, "{name}: second derivatives {worst2:e}");
        })
        .unwrap();
    }
}

#[test]
fn limit_tangent_plane_at_extraordinary_vertices() {
    for n in [3usize, 5, 6, 8, 12] {
        let m = pole_mesh(n);
        let pole = 5 * n as u32;
        with_evaluator(&m, standard_tables(), |_, ev| {
            let mut checked = 0;
            for (f, face) in m.faces.iter().enumerate() {
                let Some(k) = face.iter().position(|&v| v == pole) else {
                    continue;
                };
                // Parameters of corner k.
                let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k];
                let at = ev.eval(f as u32, 0, c.0, c.1).unwrap();
                let want = ccss_tests::reference::limit_position(&m, pole);
                assert!((at.p - v3(want)).length() < 1e-13, "n={n}: limit position");
                // Normal at the EV is the limit of normals approaching it.
                // Normals converge like (lambda_3/lambda_2)^m (slow for n = 8: 0.82^m), so go deep.
                let eps = 1e-150;
                let nu = if c.0 == 0.0 { eps } else { 1.0 - eps };
                let nv = if c.1 == 0.0 { eps } else { 1.0 - eps };
                let near = ev.eval(f as u32, 0, nu, nv).unwrap();
                let d = (near.normal - at.normal).length();
                assert!(
                    d < 1e-9,
                    "n={n} face {f}: normal at EV {:?} vs near {:?}",
                    at.normal,
                    near.normal
                );
                assert!((at.normal.length() - 1.0).abs() < 1e-12);
                checked += 1;
                // du at the EV is the limit direction of dS/du along the u edge
                // (likewise dv along the v edge).
                let d = 2f64.powi(-600);
                let su = if c.0 == 0.0 { d } else { 1.0 - d };
                let sv = if c.1 == 0.0 { d } else { 1.0 - d };
                let along_u = ev.eval(f as u32, 0, su, c.1).unwrap();
                let along_v = ev.eval(f as u32, 0, c.0, sv).unwrap();
                let cu = at.du.normalize().dot(along_u.du.normalize());
                let cv = at.dv.normalize().dot(along_v.dv.normalize());
                assert!(
                    cu > 1.0 - 1e-9 && cv > 1.0 - 1e-9,
                    "n={n}: tangent directions {cu} {cv}"
                );
            }
            assert_eq!(checked, n);
        })
        .unwrap();
    }
}
