//! The unified scheme against a plain oracle written from the paper's
//! definitions ([MS01 eqs. (14)–(24)]): the k-ring sets
//! `N_k(V)`, `F_k(V)`, `N_k(F)` are found with `HashSet`s on the linearly
//! subdivided mesh (the library's `p = 1` output), then the averages, the
//! push-back and the renormalisation are applied by hand. Meshes with
//! extraordinary vertices, triangles (both rules), pentagons and heptagons,
//! d = 2..6.
// Index loops mirror the matrix and grid formulas they check.
#![allow(clippy::needless_range_loop)]
use ccss_core::unified::{refine_unified, unified_bytes, TriangleRule, UnifiedParams};
use ccss_core::{MeshInput, Topology};
use ccss_tests::harness::{aligned, flatten};
use ccss_tests::reference::{catmull_clark, drum, pole_mesh, torus, PolyMesh};
use std::collections::{HashMap, HashSet};
use std::path::Path;

type P = [f64; 3];

fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/osd")
            .join(name),
    )
}

fn refine(m: &PolyMesh, p: &UnifiedParams) -> (Vec<P>, Vec<Vec<u32>>) {
    let (pos, s, i) = flatten(m);
    let mut tmem = aligned(Topology::required_bytes(pos.len() / 3, &s));
    let t = Topology::build(
        MeshInput {
            positions: &pos,
            face_sizes: &s,
            indices: &i,
        },
        &mut tmem,
    )
    .unwrap();
    let mut mem = aligned(unified_bytes(&t, p).unwrap());
    let r = refine_unified(&t, p, &mut mem).unwrap();
    let pts = r
        .mesh
        .positions
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let mut faces = Vec::new();
    let mut c = 0;
    for &n in r.mesh.face_sizes {
        faces.push(r.mesh.indices[c..c + n as usize].to_vec());
        c += n as usize;
    }
    (pts, faces)
}

fn with_positions(m: &PolyMesh, f: impl Fn(usize) -> P) -> PolyMesh {
    PolyMesh {
        positions: (0..m.positions.len()).map(f).collect(),
        faces: m.faces.clone(),
    }
}

fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: P, s: f64) -> P {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn norm(a: P) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
fn avg(points: impl Iterator<Item = P>) -> P {
    let mut s = [0.0; 3];
    let mut n = 0;
    for p in points {
        s = add(s, p);
        n += 1;
    }
    scale(s, 1.0 / n as f64)
}

struct Rings {
    faces: Vec<Vec<u32>>,
    vf: HashMap<u32, Vec<usize>>,
}

impl Rings {
    fn new(faces: &[Vec<u32>]) -> Rings {
        let mut vf: HashMap<u32, Vec<usize>> = HashMap::new();
        for (f, vs) in faces.iter().enumerate() {
            for &v in vs {
                vf.entry(v).or_default().push(f);
            }
        }
        Rings {
            faces: faces.to_vec(),
            vf,
        }
    }
    /// N_k of a vertex set: vertices reachable by traversing at most k faces.
    fn grow(&self, start: HashSet<u32>, k: usize) -> HashSet<u32> {
        let mut set = start;
        for _ in 0..k {
            let mut next = set.clone();
            for v in &set {
                for &f in &self.vf[v] {
                    next.extend(self.faces[f].iter().copied());
                }
            }
            set = next;
        }
        set
    }
    /// F_k(V): faces incident to N_{k-1}(V).
    fn faces_k(&self, v: u32, k: usize) -> HashSet<usize> {
        let n = self.grow(HashSet::from([v]), k - 1);
        n.iter().flat_map(|u| self.vf[u].iter().copied()).collect()
    }
}

/// One smoothing pass by the definitions: (22) twice for odd d, (23)+(24)
/// for even d.
fn smooth(r: &Rings, d: usize, x: &[P]) -> Vec<P> {
    if d % 2 == 1 {
        let k = (d - 1) / 2;
        let once = |x: &[P]| -> Vec<P> {
            (0..x.len() as u32)
                .map(|v| {
                    let n = r.grow(HashSet::from([v]), k);
                    avg(n.iter().map(|&u| x[u as usize]))
                })
                .collect()
        };
        once(&once(x))
    } else {
        let k = d / 2;
        let fv: Vec<P> = (0..r.faces.len())
            .map(|f| {
                let n = r.grow(r.faces[f].iter().copied().collect(), k - 1);
                avg(n.iter().map(|&u| x[u as usize]))
            })
            .collect();
        (0..x.len() as u32)
            .map(|v| avg(r.faces_k(v, k).iter().map(|&f| fv[f])))
            .collect()
    }
}

/// Renormalised push-back vector at a new vertex (eqs. (18)-(21)).
fn renorm(ld: P, ll: f64, b: f64) -> P {
    let n = norm(ld);
    if n > 1e-12 * ll && n > 0.0 {
        scale(ld, (1.0 - b) + b * ll / n)
    } else {
        ld
    }
}

#[test]
fn smoothing_and_push_back_match_the_definitions() {
    // Quads with extraordinary vertices, triangles, n-gons, and meshes mixing
    // regular faces (box-sum fast path) with irregular ones (search).
    let meshes = [
        ("cube", corpus("catmark_cube.obj")),
        ("pyramid", corpus("catmark_pyramid.obj")),
        ("toroidal_tet", corpus("catmark_toroidal_tet.obj")),
        ("drum5", drum(5)),
        ("drum7", drum(7)),
        ("pole5", pole_mesh(5)),
        ("pole3", pole_mesh(3)),
        ("torus", torus(4, 5, 2.0, 0.7)),
        // Large regular regions (B-spline weights, values nobody reads are
        // skipped) next to extraordinary vertices.
        ("pole5cc", catmull_clark(&pole_mesh(5))),
    ];
    for (name, m) in &meshes {
        let nv = m.positions.len();
        let diag = m.bbox_diagonal();
        for d in 2..=6u32 {
            for tri in [TriangleRule::Split, TriangleRule::Polygon] {
                let base = UnifiedParams {
                    a: 0.0,
                    b: 0.0,
                    g: 0.0,
                    d,
                    p: 1,
                    triangles: tri,
                };
                // Linear subdivision L (p = 1) of positions.
                let (lin, faces) = refine(m, &base);
                let rings = Rings::new(&faces);
                // L(D) and L(|D|): linear subdivision of D and |D| as positions.
                let interp = |dv: &[P]| {
                    let (ld, _) = refine(&with_positions(m, |v| dv[v]), &base);
                    let (ll, _) = refine(&with_positions(m, |v| [norm(dv[v]), 0.0, 0.0]), &base);
                    (ld, ll)
                };
                for (a, b, p) in [
                    (0.0, 0.0, 3),
                    (0.5, 0.0, 3),
                    (0.7, 0.5, 3),
                    (1.0, 1.0, 3),
                    (0.6, 0.5, 5),
                ] {
                    // By hand: per pass, smoothing then push-back.
                    let mut x = lin.clone();
                    for _ in 0..(p - 1) / 2 {
                        let s = smooth(&rings, d as usize, &x);
                        let dv: Vec<P> = (0..nv)
                            .map(|v| scale(sub(m.positions[v], s[v]), a))
                            .collect();
                        let (ld, ll) = interp(&dv);
                        x = (0..lin.len())
                            .map(|v| {
                                let push = if v < nv {
                                    dv[v]
                                } else {
                                    renorm(ld[v], ll[v][0], b)
                                };
                                add(s[v], push)
                            })
                            .collect();
                    }
                    let (got, _) = refine(m, &UnifiedParams { a, b, p, ..base });
                    for v in 0..lin.len() {
                        assert!(
                            norm(sub(got[v], x[v])) < 1e-13 * diag,
                            "{name} d={d} {tri:?} a={a} b={b} p={p}: vertex {v}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn linear_subdivision_is_bilinear_on_quads_and_barycentric_on_triangles() {
    // p = 1 on a cube with random vertices: every refined vertex of a quad
    // lies at the bilinear point of its grid coordinates; the pyramid's
    // triangles (Split) at barycentric points.
    let mut m = corpus("catmark_pyramid.obj");
    m.positions[0][0] += 0.3;
    m.positions[2][2] -= 0.4;
    let p = UnifiedParams {
        a: 0.0,
        b: 0.0,
        g: 0.0,
        d: 5,
        p: 1,
        triangles: TriangleRule::Split,
    };
    let (pts, faces) = refine(&m, &p);
    let d = 5.0;
    // Face children: 4 triangles * 25, then the quad's 25 cells.
    for (f, face) in m.faces.iter().enumerate() {
        let q = |k: usize| m.positions[face[k] as usize];
        let kids = &faces[f * 25..(f + 1) * 25];
        for kid in kids {
            for &v in kid {
                let x = pts[v as usize];
                // The point must be an exact grid point of the face.
                let mut best = f64::MAX;
                for i in 0..=5 {
                    for j in 0..=5 {
                        let (s, t) = (i as f64 / d, j as f64 / d);
                        let want = if face.len() == 3 {
                            if i + j > 5 {
                                continue;
                            }
                            add(
                                add(scale(q(0), 1.0 - s - t), scale(q(1), s)),
                                scale(q(2), t),
                            )
                        } else {
                            add(
                                add(
                                    scale(q(0), (1.0 - s) * (1.0 - t)),
                                    scale(q(1), s * (1.0 - t)),
                                ),
                                add(scale(q(2), s * t), scale(q(3), (1.0 - s) * t)),
                            )
                        };
                        best = best.min(norm(sub(x, want)));
                    }
                }
                assert!(best < 1e-14, "face {f}: {best:e}");
            }
        }
    }
}
