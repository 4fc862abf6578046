//! Adaptive tessellation of meshes with features (`Tessellation::
//! build_feature`) on creased, cornered, open, holed and non-manifold
//! corpus shapes, against exact evaluation:
//!
//! 1. **Parametric bound**: every vertex of every output polygon is placed
//!    in the polygon's own parameter cell (its own slot's parameters, or,
//!    for a vertex another slot made, found by bisection of the cell's
//!    side: the midpoint's exact limit point must be one of the polygon's
//!    vertices, which also proves the side's points are the surface's at
//!    dyadic parameters, no T-junction); then a jittered grid of samples
//!    `x` of the cell gives `|S(x) - T(x)|`, `T` the emitted triangles'
//!    piecewise-linear interpolant in the cell's parameters. Zero samples
//!    beyond the stated bound (`Stats::bound`, at most eps for absolute
//!    flatness); tightness = worst / bound reported.
//! 2. **Topology**: every output edge lies in as many polygons as its base
//!    edge has faces that are not holes (two, with opposite directions,
//!    inside faces and on manifold edges): closed inputs give a closed,
//!    consistently oriented 2-manifold; every edge of an open output with
//!    one polygon lies on a boundary or hole border of the input, and the
//!    boundary loops close (in-degree = out-degree at every vertex). No two
//!    vertices at the same place; every vertex used.
//! 3. **Counts**: the size queries are exact (buffers of exactly the
//!    counted sizes are filled, nothing left unwritten).
use ccss_core::mem::words_for;
use ccss_core::tessellate::{Criterion, Options, Output, PolygonCell, Scratch, Tessellation};
use ccss_core::DVec3;
use ccss_core::{FeatureEvaluator, Query};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, workspace_root, XorShift};
use ccss_tests::sharp::TaggedMesh;
use std::collections::HashMap;

/// Everything one feature tessellation emits.
struct Out {
    p: Vec<f64>,
    params: Vec<Query>,
    sizes: Vec<u32>,
    idx: Vec<u32>,
    tris: Vec<u32>,
    cells: Vec<PolygonCell>,
    bound: f64,
}

fn tessellate(fev: &FeatureEvaluator, opts: Options) -> Out {
    let need =
        Tessellation::required_bytes_feature(fev, &opts, &mut Box::new(Scratch::ZERO)).unwrap();
    let mut mem = vec![0u64; words_for(need)];
    let mut t = Tessellation::build_feature(fev, opts, &mut mem).unwrap();
    // One word less is refused with the exact size.
    let c = t.counts();
    let mut o = Out {
        p: vec![f64::NAN; 3 * c.vertices],
        params: vec![Query::default(); c.vertices],
        sizes: vec![0; c.polygons],
        idx: vec![u32::MAX; c.polygon_indices],
        tris: vec![u32::MAX; 3 * c.triangles],
        cells: vec![PolygonCell::default(); c.polygons],
        bound: t.stats().bound,
    };
    let mut normals = vec![f64::NAN; 3 * c.vertices];
    t.emit(Output {
        positions: &mut o.p,
        normals: Some(&mut normals),
        params: Some(&mut o.params),
        polygon_sizes: &mut o.sizes,
        polygon_indices: &mut o.idx,
        triangles: Some(&mut o.tris),
        cells: Some(&mut o.cells),
    })
    .unwrap();
    assert!(o.p.iter().all(|x| x.is_finite()), "a vertex not written");
    assert!(o.idx.iter().all(|&x| (x as usize) < c.vertices));
    assert!(o.tris.iter().all(|&x| (x as usize) < c.vertices));
    assert_eq!(
        o.sizes.iter().map(|&s| s as usize).sum::<usize>(),
        c.polygon_indices
    );
    assert_eq!(c.triangles, c.polygon_indices - 2 * c.polygons);
    o
}

impl Out {
    fn pos(&self, v: u32) -> DVec3 {
        DVec3::from_slice(&self.p[3 * v as usize..3 * v as usize + 3])
    }
}

/// Parameters in the polygon's own cell of the polygon's vertices `poly`
/// (see the module docs), in the cell's order: corner 0, side 0, corner 1,
/// side 1, corner 2, side 2 (decreasing u), corner 3, side 3 (decreasing v).
fn own_params(
    fev: &FeatureEvaluator,
    o: &Out,
    c: &PolygonCell,
    poly: &[u32],
    tol: f64,
) -> Vec<(f64, f64)> {
    let h = 0.5f64.powi(c.level as i32);
    let (u0, v0) = (c.i as f64 * h, c.j as f64 * h);
    let corner = [(u0, v0), (u0 + h, v0), (u0 + h, v0 + h), (u0, v0 + h)];
    let s = |(u, v): (f64, f64)| fev.eval(c.face, c.sub, u, v).unwrap().p;
    let close = |v: u32, p: DVec3| o.pos(v).distance(p) <= tol;
    // Corner k's place in the polygon.
    let mut at = [0usize; 5];
    let mut from = 0;
    for k in 0..4 {
        let p = s(corner[k]);
        let i = (from..poly.len())
            .find(|&i| close(poly[i], p))
            .unwrap_or_else(|| panic!("{c:?}: corner {k} not among the polygon's vertices"));
        at[k] = i;
        from = i + 1;
    }
    assert_eq!(at[0], 0, "{c:?}: the polygon does not start at corner 0");
    at[4] = poly.len();
    let mut uv = vec![(f64::NAN, f64::NAN); poly.len()];
    for k in 0..4 {
        uv[at[k]] = corner[k];
        let (a, b) = (corner[k], corner[(k + 1) % 4]);
        // Bisection: the points strictly between the corners, in order.
        let mut stack = vec![(at[k] + 1, at[k + 1], 0.0f64, 1.0f64)];
        while let Some((lo, hi, t0, t1)) = stack.pop() {
            if lo >= hi {
                continue;
            }
            let t = 0.5 * (t0 + t1);
            let x = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            let p = s(x);
            let m = (lo..hi).find(|&i| close(poly[i], p)).unwrap_or_else(|| {
                panic!("{c:?}: side {k}: the limit point at {x:?} is not a polygon vertex")
            });
            uv[m] = x;
            stack.push((lo, m, t0, t));
            stack.push((m + 1, hi, t, t1));
        }
    }
    uv
}

/// Barycentric coordinates of `x` in the parameter triangle (a, b, c).
fn bary(x: (f64, f64), a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> [f64; 3] {
    let d = (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1);
    let l1 = ((x.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (x.1 - a.1)) / d;
    let l2 = ((b.0 - a.0) * (x.1 - a.1) - (x.0 - a.0) * (b.1 - a.1)) / d;
    [1.0 - l1 - l2, l1, l2]
}

/// Facts of one run.
struct Run {
    secs: f64,
    polygons: usize,
    vertices: usize,
    samples: usize,
    worst: f64,
    bound: f64,
    boundary_edges: usize,
}

fn check(name: &str, crit: Criterion, samples_per_poly: usize) -> Run {
    let path = workspace_root().join("tests/data/osd").join(name);
    let m = TaggedMesh::from_obj(&path).unwrap();
    let diag = m.bbox_diagonal();
    let crit = match crit {
        Criterion::Absolute(e) => Criterion::Absolute(e * diag),
        c => c,
    };
    let what = format!("{name} {crit:?}");
    let f = flat(&m);
    with_feature_mesh(&f, Some(standard_tables()), |fev| {
        let t0 = std::time::Instant::now();
        let o = tessellate(
            fev,
            Options {
                criterion: crit,
                max_level: 30,
            },
        );
        let secs = t0.elapsed().as_secs_f64();
        if let Criterion::Absolute(eps) = crit {
            assert!(o.bound <= eps, "{what}: bound {} > eps {eps}", o.bound);
        }
        let base = &fev.mesh().base;
        let fm = fev.mesh();
        let hole = |f: usize| fm.hole[fm.child_face(f, 0)] != 0;
        let tol = 1e-10 * diag;
        // 1. Parametric bound.
        let mut rng = XorShift(0x7e55_e11a);
        let k = (samples_per_poly as f64).sqrt().ceil() as usize;
        let (mut n, mut worst) = (0usize, 0.0f64);
        let (mut at, mut t_at) = (0usize, 0usize);
        let mut on_base: HashMap<(u32, u32), Option<usize>> = HashMap::new();
        for (p, &size) in o.sizes.iter().enumerate() {
            let poly = &o.idx[at..at + size as usize];
            let tris = &o.tris[3 * t_at..3 * (t_at + size as usize - 2)];
            at += size as usize;
            t_at += size as usize - 2;
            let c = o.cells[p];
            assert!(
                !hole(c.face as usize),
                "{what}: a polygon on hole face {}",
                c.face
            );
            let uv = own_params(fev, &o, &c, poly, tol);
            // The base edge each polygon edge lies on (slot sides on the
            // face's boundary), from the parameters in the polygon's cell.
            let es = base.face_edges(c.face as usize);
            for e in 0..poly.len() {
                let (x, y) = (uv[e], uv[(e + 1) % poly.len()]);
                let side = [
                    x.1 == 0.0 && y.1 == 0.0,
                    x.0 == 1.0 && y.0 == 1.0,
                    x.1 == 1.0 && y.1 == 1.0,
                    x.0 == 0.0 && y.0 == 0.0,
                ];
                let n = es.len();
                let be = if n == 4 {
                    (0..4).find(|&s| side[s]).map(|s| es[s] as usize)
                } else if side[0] {
                    Some(es[c.sub as usize] as usize)
                } else if side[3] {
                    Some(es[(c.sub as usize + n - 1) % n] as usize)
                } else {
                    None
                };
                let key = (
                    poly[e].min(poly[(e + 1) % poly.len()]),
                    poly[e].max(poly[(e + 1) % poly.len()]),
                );
                let old = on_base.insert(key, be);
                assert!(
                    old.is_none() || old == Some(be),
                    "{what}: edge {key:?} on base edges {old:?} and {be:?}"
                );
            }
            let local = |v: u32| uv[poly.iter().position(|&x| x == v).unwrap()];
            let h = 0.5f64.powi(c.level as i32);
            for a in 0..k {
                for b in 0..k {
                    let x = (
                        (c.i as f64 + (a as f64 + rng.unit()) / k as f64) * h,
                        (c.j as f64 + (b as f64 + rng.unit()) / k as f64) * h,
                    );
                    // The triangle holding x (largest smallest coordinate).
                    let (w, tr) = tris
                        .chunks(3)
                        .map(|tr| (bary(x, local(tr[0]), local(tr[1]), local(tr[2])), tr))
                        .max_by(|p, q| {
                            let m = |w: &[f64; 3]| w[0].min(w[1]).min(w[2]);
                            m(&p.0).total_cmp(&m(&q.0))
                        })
                        .unwrap();
                    assert!(
                        w.iter().all(|&l| l >= -1e-9),
                        "{what}: {x:?} in no triangle of {c:?}"
                    );
                    let t = o.pos(tr[0]) * w[0] + o.pos(tr[1]) * w[1] + o.pos(tr[2]) * w[2];
                    let s = fev.eval(c.face, c.sub, x.0, x.1).unwrap().p;
                    let d = s.distance(t);
                    assert!(
                        d <= o.bound * (1.0 + 1e-9) + 1e-13 * diag,
                        "{what}: |S - T| = {d:e} at {x:?} of {c:?} beyond the bound {:e}",
                        o.bound
                    );
                    worst = worst.max(d);
                    n += 1;
                }
            }
        }
        // 2. Topology.
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        let mut at = 0;
        let mut used = vec![false; o.params.len()];
        for &size in &o.sizes {
            let poly = &o.idx[at..at + size as usize];
            at += size as usize;
            for e in 0..poly.len() {
                let (a, b) = (poly[e], poly[(e + 1) % poly.len()]);
                used[a as usize] = true;
                assert_ne!(a, b, "{what}: a repeated vertex");
                *edges.entry((a, b)).or_default() += 1;
            }
        }
        assert!(used.iter().all(|&u| u), "{what}: an unused vertex");
        let live = |e: usize| {
            base.edge_faces(e)
                .iter()
                .filter(|&&f| !hole(f as usize))
                .count()
        };
        let mut boundary_edges = 0usize;
        let mut degree: HashMap<u32, i32> = HashMap::new();
        let mut parity: HashMap<u32, u32> = HashMap::new();
        let oriented = (0..base.num_edges()).all(|e| !base_nonmanifold(base, e));
        for (&(a, b), &cnt) in &edges {
            let rev = edges.get(&(b, a)).copied().unwrap_or(0);
            let total = (cnt + rev) as usize;
            if a > b && rev > 0 {
                continue; // counted from the other direction
            }
            let be = on_base[&(a.min(b), a.max(b))];
            // Polygons expected: 2 inside a face; k on a base edge with k
            // faces that are not holes.
            let want = be.map_or(2, live);
            assert_eq!(
                total, want,
                "{what}: edge {a}-{b} in {total} polygons, base edge {be:?}"
            );
            if want == 2 && !be.is_some_and(|e| base_nonmanifold(base, e)) {
                assert_eq!(
                    (cnt, rev),
                    (1, 1),
                    "{what}: edge {a}-{b} not oppositely oriented"
                );
            }
            if total == 1 {
                boundary_edges += 1;
                *degree.entry(a).or_default() += 1;
                *degree.entry(b).or_default() -= 1;
                *parity.entry(a).or_default() += 1;
                *parity.entry(b).or_default() += 1;
            }
        }
        // Boundary loops close: an even number of boundary edges at every
        // vertex; and, when the input is consistently oriented, as many
        // leaving as entering.
        assert!(
            parity.values().all(|&d| d % 2 == 0),
            "{what}: a boundary loop does not close"
        );
        if oriented {
            assert!(
                degree.values().all(|&d| d == 0),
                "{what}: a boundary loop is not oriented"
            );
        }
        // No two vertices at one place (vertex identity), by a grid hash
        // (inputs with coincident vertices left out).
        let distinct = {
            let mut ps: Vec<[u64; 3]> = m.positions.iter().map(|p| p.map(f64::to_bits)).collect();
            ps.sort();
            ps.windows(2).all(|w| w[0] != w[1])
        };
        let cell = 1e-9 * diag;
        let mut seen: HashMap<[i64; 3], u32> = HashMap::new();
        for v in 0..o.params.len() as u32 {
            let p = o.pos(v);
            let key = [p.x, p.y, p.z].map(|x| (x / cell).round() as i64);
            // (Faces that coincide, as in back-to-back pairs, may put two
            // points inside different faces at one place.)
            let inside = |q: &Query| q.u > 0.0 && q.u < 1.0 && q.v > 0.0 && q.v < 1.0;
            if let Some(w) = seen.insert(key, v).filter(|_| distinct) {
                let (a, b) = (&o.params[w as usize], &o.params[v as usize]);
                if a.face != b.face && inside(a) && inside(b) {
                    continue;
                }
                panic!(
                    "{what}: vertices {w} and {v} at one place {p}: {:?} {:?}",
                    o.params[w as usize], o.params[v as usize]
                );
            }
        }
        Run {
            secs,
            polygons: o.sizes.len(),
            vertices: o.params.len(),
            samples: n,
            worst,
            bound: o.bound,
            boundary_edges,
        }
    })
    .unwrap()
}

/// Non-manifold base edge: more than two faces, or two in one direction.
fn base_nonmanifold(base: &ccss_core::mesh::features::Adjacency, e: usize) -> bool {
    base.edge_nonmanifold(e)
}

/// (shape, absolute eps / diagonal, relative r or 0, samples per polygon):
/// smoke sizes for CI.
const SHAPES: [(&str, f64, f64, usize); 17] = [
    ("catmark_cube_creases0.obj", 2e-3, 0.05, 16),
    ("catmark_cube_creases1.obj", 5e-3, 0.0, 9),
    ("catmark_cube_corner0.obj", 2e-3, 0.05, 16),
    ("catmark_cube_corner3.obj", 2e-3, 0.05, 16),
    ("catmark_edgeonly.obj", 2e-3, 0.05, 64),
    ("catmark_edgecorner.obj", 2e-3, 0.05, 16),
    ("catmark_hole_test1.obj", 2e-3, 0.05, 16),
    ("catmark_hole_test2.obj", 2e-3, 0.05, 16),
    ("catmark_nonman_edge100.obj", 5e-2, 0.0, 4),
    ("catmark_val2_nonman.obj", 2e-3, 0.0, 16),
    ("catmark_nonman_bareverts.obj", 2e-3, 0.05, 16),
    ("catmark_nonman_verts.obj", 2e-3, 0.0, 16),
    ("catmark_chaikin1.obj", 5e-3, 0.0, 9),
    ("catmark_car.obj", 5e-2, 0.0, 4),
    ("catmark_bishop.obj", 5e-2, 0.0, 4),
    ("catmark_dart_edgeonly.obj", 2e-3, 0.05, 16),
    ("catmark_tent_creases1.obj", 2e-3, 0.05, 16),
];

#[test]
fn feature_tessellation_meets_the_bound_and_the_topology() {
    let only = std::env::var("FTESS_ONLY").ok();
    let mut total = 0usize;
    for (name, eps, r, k) in SHAPES {
        if only.as_deref().is_some_and(|o| !name.contains(o)) {
            continue;
        }
        let mut crits = vec![Criterion::Absolute(eps)];
        if r > 0.0 {
            crits.push(Criterion::Relative(r));
        }
        for crit in crits {
            let t0 = std::time::Instant::now();
            let r = check(name, crit, k);
            total += r.samples;
            println!(
                "[{:.2} s, tessellation {:.3} s] {name} {crit:?}: {} polygons, {} vertices, {} boundary edges, {} samples, bound {:.3e}, worst {:.3e} (tightness {:.3})",
                t0.elapsed().as_secs_f64(),
                r.secs,
                r.polygons,
                r.vertices,
                r.boundary_edges,
                r.samples,
                r.bound,
                r.worst,
                r.worst / r.bound
            );
        }
    }
    println!("{total} samples, zero beyond the bound");
}
