//! Reference Catmull-Clark subdivision: a deliberately plain implementation
//! used as a test oracle for the library.
//!
//! Everything here favours clarity over speed: meshes are `Vec`s of positions
//! and faces, adjacency is rebuilt with `HashMap`s whenever it is needed, and
//! every subdivision step processes the whole mesh.
//!
//! # Conventions (the contract the library under test follows, as OpenSubdiv)
//!
//! * **Face point** = centroid of the face.
//! * **Edge point** = average of the two end points and the two adjacent face
//!   points.
//! * **Vertex point** (standard rule) = `(Q + 2R + (n-3)V)/n`, with `Q` the
//!   average of the adjacent face points and `R` the average of the midpoints
//!   of the adjacent edges. For custom weights see [`Weights`].
//! * **Numbering of the refined mesh**: old vertices keep their index (vertex
//!   points), then one edge point per edge in order of first appearance when
//!   scanning faces in order and, within a face, its edges `(v_k, v_{k+1})` in
//!   order, then one face point per face in face order.
//! * **Refined faces**: for each old face `f` in order, for each corner
//!   `k = 0..N` in order, the quad
//!   `[vp(v_k), ep(v_k, v_{k+1}), fp(f), ep(v_{k-1}, v_k)]`. So the children of
//!   face `f` are the faces `offset(f) .. offset(f) + N` where `offset(f)` is
//!   the sum of the sizes of the faces before `f`.
//! * **Parameterization** of a quad `[v0 v1 v2 v3]`: `(u,v) = (0,0)` at `v0`,
//!   `(1,0)` at `v1`, `(1,1)` at `v2`, `(0,1)` at `v3`. With parametric corners
//!   `c0=(0,0), c1=(1,0), c2=(1,1), c3=(0,1)`, child `k` maps its own `(s,t)`
//!   to `c_k + s (mid(c_k, c_{k+1}) - c_k) + t (mid(c_{k-1}, c_k) - c_k)`.
//! * A non-quad face with `N` vertices has `N` sub-faces: sub-face `k` is
//!   exactly its level-1 child quad `k`, with that quad's own parameterization
//!   (`(0,0)` at `v_k`, `(1,0)` at the midpoint side towards `v_{k+1}`,
//!   `(1,1)` at the face centre, `(0,1)` towards `v_{k-1}`).

use std::collections::HashMap;
use std::path::Path;

/// Polygon mesh: positions and faces (vertex index lists, counter-clockwise
/// seen from outside).
#[derive(Clone, Debug)]
pub struct PolyMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Faces as lists of indices into `positions`, counter-clockwise seen from
    /// outside.
    pub faces: Vec<Vec<u32>>,
}

/// Vertex rule weights `(alpha, beta, gamma)` for valence `n`:
///
/// `V' = alpha V + beta/n sum(E_i) + gamma/n sum(F_i)`
///
/// where the `E_i` are the OLD edge-neighbour vertices of `V` and the `F_i`
/// the OLD "face-diagonal" points of `V`, one per face around `V`:
///
/// * for a quad face around `V`, `F_i` is the vertex of that face opposite `V`;
/// * for a non-quad face with centroid `C` in which `V` is preceded by `P`
///   and followed by `N`, `F_i = 4C - V - P - N`, i.e. the point that would
///   make `C` the centroid of the quad `[V N F_i P]`. (For a quad this *is*
///   the opposite vertex.) This choice makes [`standard_weights`] reproduce
///   the true Catmull-Clark rule `(n-2)/n V + 1/n² ΣE + 1/n² ΣC` on every
///   face type; using the plain centroid `C` as `F_i` would give the
///   centroid only the weight `1/(4n²)` instead of `1/n²` and would not be
///   Catmull-Clark on non-quad meshes.
///
/// Standard Catmull-Clark: `alpha = 1-7/(4n)`, `beta = 3/(2n)`,
/// `gamma = 1/(4n)` (see [`standard_weights`]).
pub type Weights = dyn Fn(usize) -> (f64, f64, f64);

/// Standard Catmull-Clark vertex weights for valence `n`:
/// `(1 - 7/(4n), 3/(2n), 1/(4n))`.
pub fn standard_weights(n: usize) -> (f64, f64, f64) {
    let n = n as f64;
    (1.0 - 7.0 / (4.0 * n), 3.0 / (2.0 * n), 1.0 / (4.0 * n))
}

// ---------------------------------------------------------------------------
// Small vector helpers.

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn sum_points(points: &[[f64; 3]]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for p in points {
        s = add(s, *p);
    }
    s
}

fn average(points: &[[f64; 3]]) -> [f64; 3] {
    assert!(!points.is_empty(), "average of no points");
    scale(sum_points(points), 1.0 / points.len() as f64)
}

// ---------------------------------------------------------------------------
// PolyMesh basics.

impl PolyMesh {
    /// Loads an OBJ file with `tobj` (`single_index = false`,
    /// `triangulate = false`, points and lines ignored) and merges all its
    /// models into one mesh. Panics with a clear message on failure.
    ///
    /// Notes:
    /// * faces keep the OBJ winding and vertex order;
    /// * vertex numbering is `tobj`'s: per model, vertices are renumbered in
    ///   order of first use by the faces, and vertices no face uses are
    ///   dropped, so indices need not match the `v` lines of the file;
    /// * positions are whatever precision `tobj` parses (`f32` unless its
    ///   `use_f64` feature is on), converted to `f64`;
    /// * since `tobj` renumbers each model separately, a vertex shared by two
    ///   models (`o`/`g` groups) would be duplicated; to keep such meshes
    ///   closed, a vertex of a later model whose position is bit-identical to
    ///   a vertex of an earlier model is mapped to that earlier vertex.
    pub fn from_obj(path: &Path) -> PolyMesh {
        // The struct update covers fields that only exist with optional tobj
        // features (`merging`, `reordering`), which another crate may enable.
        #[allow(clippy::needless_update)]
        let options = tobj::LoadOptions {
            single_index: false,
            triangulate: false,
            ignore_points: true,
            ignore_lines: true,
            ..Default::default()
        };
        let (models, _materials) = match tobj::load_obj(path, &options) {
            Ok(loaded) => loaded,
            Err(e) => panic!("failed to load OBJ file {}: {}", path.display(), e),
        };
        assert!(
            !models.is_empty(),
            "OBJ file {} contains no faces",
            path.display()
        );

        let mut positions: Vec<[f64; 3]> = Vec::new();
        let mut faces: Vec<Vec<u32>> = Vec::new();
        // Exact position bits -> merged index, filled with earlier models only.
        let mut earlier: HashMap<[u64; 3], u32> = HashMap::new();
        for model in &models {
            let mesh = &model.mesh;
            assert!(
                mesh.positions.len() % 3 == 0,
                "OBJ file {}: model {:?} has a position array of length {} (not a multiple of 3)",
                path.display(),
                model.name,
                mesh.positions.len()
            );
            let local_count = mesh.positions.len() / 3;
            let mut local_to_global: Vec<u32> = Vec::with_capacity(local_count);
            let mut new_keys: Vec<([u64; 3], u32)> = Vec::new();
            for i in 0..local_count {
                let p = [
                    mesh.positions[3 * i],
                    mesh.positions[3 * i + 1],
                    mesh.positions[3 * i + 2],
                ];
                let key = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
                match earlier.get(&key) {
                    Some(&g) => local_to_global.push(g),
                    None => {
                        let g = positions.len() as u32;
                        positions.push(p);
                        local_to_global.push(g);
                        new_keys.push((key, g));
                    }
                }
            }
            for (key, g) in new_keys {
                earlier.entry(key).or_insert(g);
            }

            // face_arities is empty when every face is a triangle.
            let arities: Vec<usize> = if mesh.face_arities.is_empty() {
                assert!(
                    mesh.indices.len() % 3 == 0,
                    "OBJ file {}: model {:?}: no face arities and {} indices",
                    path.display(),
                    model.name,
                    mesh.indices.len()
                );
                vec![3; mesh.indices.len() / 3]
            } else {
                mesh.face_arities.iter().map(|&a| a as usize).collect()
            };
            let mut start = 0usize;
            for arity in arities {
                assert!(
                    arity >= 3,
                    "OBJ file {}: model {:?} has a face with {} vertices",
                    path.display(),
                    model.name,
                    arity
                );
                let face: Vec<u32> = mesh.indices[start..start + arity]
                    .iter()
                    .map(|&i| local_to_global[i as usize])
                    .collect();
                faces.push(face);
                start += arity;
            }
            assert_eq!(
                start,
                mesh.indices.len(),
                "OBJ file {}: model {:?}: face arities do not cover the index list",
                path.display(),
                model.name
            );
        }
        assert!(
            !faces.is_empty(),
            "OBJ file {} contains no faces",
            path.display()
        );
        PolyMesh { positions, faces }
    }

    /// Length of the diagonal of the axis-aligned bounding box of all
    /// positions (0 for an empty mesh).
    pub fn bbox_diagonal(&self) -> f64 {
        if self.positions.is_empty() {
            return 0.0;
        }
        let mut lo = self.positions[0];
        let mut hi = self.positions[0];
        for p in &self.positions {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let d = sub(hi, lo);
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }

    /// Number of edges at vertex `v` (number of distinct edge neighbours;
    /// closed manifold assumed).
    pub fn valence(&self, v: u32) -> usize {
        one_ring(self, v).neighbours.len()
    }
}

/// Everything around one vertex, gathered by scanning all faces.
struct OneRing {
    /// Distinct edge-neighbour vertices.
    neighbours: Vec<u32>,
    /// Incident corners: (face index, corner index within the face).
    corners: Vec<(usize, usize)>,
}

/// The 1-rings of all vertices, gathered in one pass over the faces.
fn all_rings(m: &PolyMesh) -> Vec<OneRing> {
    let mut rings: Vec<OneRing> = (0..m.positions.len())
        .map(|_| OneRing {
            neighbours: Vec::new(),
            corners: Vec::new(),
        })
        .collect();
    for (fi, face) in m.faces.iter().enumerate() {
        let n = face.len();
        for k in 0..n {
            let ring = &mut rings[face[k] as usize];
            ring.corners.push((fi, k));
            ring.neighbours.push(face[(k + 1) % n]);
            ring.neighbours.push(face[(k + n - 1) % n]);
        }
    }
    for ring in &mut rings {
        ring.neighbours.sort_unstable();
        ring.neighbours.dedup();
    }
    rings
}

/// The 1-ring of one vertex (scans all faces).
fn one_ring(m: &PolyMesh, v: u32) -> OneRing {
    let mut neighbours = Vec::new();
    let mut corners = Vec::new();
    for (fi, face) in m.faces.iter().enumerate() {
        let n = face.len();
        for k in 0..n {
            if face[k] == v {
                corners.push((fi, k));
                neighbours.push(face[(k + 1) % n]);
                neighbours.push(face[(k + n - 1) % n]);
            }
        }
    }
    neighbours.sort_unstable();
    neighbours.dedup();
    OneRing {
        neighbours,
        corners,
    }
}

fn centroid(m: &PolyMesh, face: &[u32]) -> [f64; 3] {
    let pts: Vec<[f64; 3]> = face.iter().map(|&i| m.positions[i as usize]).collect();
    average(&pts)
}

/// The "face-diagonal" point of corner `k` of `face` (see [`Weights`]):
/// the opposite vertex for a quad, `4C - V - next - prev` otherwise.
fn face_diagonal(m: &PolyMesh, face: &[u32], k: usize) -> [f64; 3] {
    let n = face.len();
    if n == 4 {
        m.positions[face[(k + 2) % 4] as usize]
    } else {
        let c = centroid(m, face);
        let v = m.positions[face[k] as usize];
        let next = m.positions[face[(k + 1) % n] as usize];
        let prev = m.positions[face[(k + n - 1) % n] as usize];
        sub(sub(sub(scale(c, 4.0), v), next), prev)
    }
}

/// Sum of the sizes of the faces before `f`: index of the first child of
/// face `f` in the refined mesh.
fn child_offset(m: &PolyMesh, f: usize) -> usize {
    m.faces[..f].iter().map(|face| face.len()).sum()
}

// ---------------------------------------------------------------------------
// Subdivision.

/// Edge table of a mesh, in order of first appearance.
struct Edges {
    /// End points in the orientation of their first appearance.
    ends: Vec<(u32, u32)>,
    /// Unordered key (min, max) -> edge index.
    index: HashMap<(u32, u32), usize>,
    /// The two faces of each edge (closed manifold checked).
    faces: Vec<[usize; 2]>,
}

fn edge_key(a: u32, b: u32) -> (u32, u32) {
    if a < b {
        (a, b)
    } else {
        (b, a)
    }
}

/// Builds the edge table and checks that the mesh is a closed, consistently
/// oriented manifold: every edge used by exactly two faces, once in each
/// direction. Panics otherwise.
fn build_edges(m: &PolyMesh) -> Edges {
    let mut ends: Vec<(u32, u32)> = Vec::new();
    let mut index: HashMap<(u32, u32), usize> = HashMap::new();
    // Per edge: the uses (face, directed from->to).
    let mut uses: Vec<Vec<(usize, u32, u32)>> = Vec::new();
    for (fi, face) in m.faces.iter().enumerate() {
        let n = face.len();
        assert!(n >= 3, "face {} has only {} vertices", fi, n);
        for k in 0..n {
            let a = face[k];
            let b = face[(k + 1) % n];
            assert!(
                (a as usize) < m.positions.len() && (b as usize) < m.positions.len(),
                "face {} refers to a vertex out of range",
                fi
            );
            assert!(a != b, "face {} has a degenerate edge ({}, {})", fi, a, b);
            let key = edge_key(a, b);
            let e = match index.get(&key) {
                Some(&e) => e,
                None => {
                    let e = ends.len();
                    ends.push((a, b));
                    uses.push(Vec::new());
                    index.insert(key, e);
                    e
                }
            };
            uses[e].push((fi, a, b));
        }
    }
    let mut faces = Vec::with_capacity(ends.len());
    for (e, u) in uses.iter().enumerate() {
        let (a, b) = ends[e];
        assert!(
            u.len() != 1,
            "boundary edge ({}, {}) (only used by face {}): the reference subdivider handles closed meshes only",
            a,
            b,
            u[0].0
        );
        assert!(
            u.len() == 2,
            "non-manifold edge ({}, {}) used by {} faces",
            a,
            b,
            u.len()
        );
        assert!(
            u[0].1 == u[1].2 && u[0].2 == u[1].1,
            "edge ({}, {}) is used in the same direction by faces {} and {} (inconsistent orientation)",
            a,
            b,
            u[0].0,
            u[1].0
        );
        faces.push([u[0].0, u[1].0]);
    }
    Edges { ends, index, faces }
}

/// A vertex-point rule: `(mesh, v, ring of v, face points) -> vertex point`.
type VertexRule<'a> = dyn Fn(&PolyMesh, u32, &OneRing, &[[f64; 3]]) -> [f64; 3] + 'a;

/// The shared part of both subdivision functions: face points, edge points
/// and the new faces; vertex points come from `vertex_point(mesh, v, ring of
/// v, face points)`.
fn subdivide_with(m: &PolyMesh, vertex_point: &VertexRule<'_>) -> PolyMesh {
    let edges = build_edges(m);
    let nv = m.positions.len();
    let ne = edges.ends.len();

    let face_points: Vec<[f64; 3]> = m.faces.iter().map(|f| centroid(m, f)).collect();

    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(nv + ne + m.faces.len());
    let rings = all_rings(m);
    for (v, ring) in rings.iter().enumerate() {
        positions.push(vertex_point(m, v as u32, ring, &face_points));
    }
    for e in 0..ne {
        let (a, b) = edges.ends[e];
        let [f0, f1] = edges.faces[e];
        let p = average(&[
            m.positions[a as usize],
            m.positions[b as usize],
            face_points[f0],
            face_points[f1],
        ]);
        positions.push(p);
    }
    positions.extend_from_slice(&face_points);

    let ep = |a: u32, b: u32| -> u32 { (nv + edges.index[&edge_key(a, b)]) as u32 };
    let mut faces = Vec::new();
    for (fi, face) in m.faces.iter().enumerate() {
        let n = face.len();
        let fp = (nv + ne + fi) as u32;
        for k in 0..n {
            let v = face[k];
            let next = face[(k + 1) % n];
            let prev = face[(k + n - 1) % n];
            faces.push(vec![v, ep(v, next), fp, ep(prev, v)]);
        }
    }
    PolyMesh { positions, faces }
}

/// One Catmull-Clark step (closed manifold polygon meshes only; panics on
/// boundary or non-manifold edges and on inconsistent orientation).
///
/// Vertex points use the textbook rule `(Q + 2R + (n-3)V)/n`, computed
/// independently of [`catmull_clark_weighted`] (so that comparing the two is
/// a meaningful check).
pub fn catmull_clark(m: &PolyMesh) -> PolyMesh {
    let rule = |m: &PolyMesh, v: u32, ring: &OneRing, face_points: &[[f64; 3]]| -> [f64; 3] {
        let p = m.positions[v as usize];
        if ring.corners.is_empty() {
            return p; // isolated vertex: nothing to average
        }
        let n = ring.neighbours.len();
        assert_eq!(
            n,
            ring.corners.len(),
            "vertex {} has {} edges but {} faces (non-manifold vertex)",
            v,
            n,
            ring.corners.len()
        );
        let fps: Vec<[f64; 3]> = ring.corners.iter().map(|&(f, _)| face_points[f]).collect();
        let q = average(&fps);
        let mids: Vec<[f64; 3]> = ring
            .neighbours
            .iter()
            .map(|&e| scale(add(p, m.positions[e as usize]), 0.5))
            .collect();
        let r = average(&mids);
        let nf = n as f64;
        scale(add(add(q, scale(r, 2.0)), scale(p, nf - 3.0)), 1.0 / nf)
    };
    subdivide_with(m, &rule)
}

/// One Catmull-Clark step with a custom vertex rule (see [`Weights`] for the
/// meaning of the weights and of the face-diagonal points of non-quads);
/// edge and face points stay standard. Closed manifold meshes only.
pub fn catmull_clark_weighted(m: &PolyMesh, w: &Weights) -> PolyMesh {
    let rule = |m: &PolyMesh, v: u32, ring: &OneRing, _face_points: &[[f64; 3]]| -> [f64; 3] {
        let p = m.positions[v as usize];
        if ring.corners.is_empty() {
            return p;
        }
        let n = ring.neighbours.len();
        assert_eq!(
            n,
            ring.corners.len(),
            "vertex {} has {} edges but {} faces (non-manifold vertex)",
            v,
            n,
            ring.corners.len()
        );
        let (alpha, beta, gamma) = w(n);
        let es: Vec<[f64; 3]> = ring
            .neighbours
            .iter()
            .map(|&e| m.positions[e as usize])
            .collect();
        let fs: Vec<[f64; 3]> = ring
            .corners
            .iter()
            .map(|&(f, k)| face_diagonal(m, &m.faces[f], k))
            .collect();
        let nf = n as f64;
        add(
            add(scale(p, alpha), scale(sum_points(&es), beta / nf)),
            scale(sum_points(&fs), gamma / nf),
        )
    };
    subdivide_with(m, &rule)
}

// ---------------------------------------------------------------------------
// Limit positions.

/// The 1-ring of `v` when every face around it is a quad: (valence, sum of
/// edge neighbours, sum of diagonal vertices). Panics otherwise.
fn quad_ring_sums(m: &PolyMesh, v: u32) -> (usize, [f64; 3], [f64; 3]) {
    let ring = one_ring(m, v);
    let n = ring.neighbours.len();
    assert!(n > 0, "vertex {} is not used by any face", v);
    assert_eq!(
        n,
        ring.corners.len(),
        "vertex {} has {} edges but {} faces (not a closed manifold vertex)",
        v,
        n,
        ring.corners.len()
    );
    for &(f, _) in &ring.corners {
        assert_eq!(
            m.faces[f].len(),
            4,
            "limit mask of vertex {} needs all faces around it to be quads, face {} has {} vertices",
            v,
            f,
            m.faces[f].len()
        );
    }
    let es: Vec<[f64; 3]> = ring
        .neighbours
        .iter()
        .map(|&e| m.positions[e as usize])
        .collect();
    let fs: Vec<[f64; 3]> = ring
        .corners
        .iter()
        .map(|&(f, k)| m.positions[m.faces[f][(k + 2) % 4] as usize])
        .collect();
    (n, sum_points(&es), sum_points(&fs))
}

fn ring_is_all_quads(m: &PolyMesh, v: u32) -> bool {
    one_ring(m, v)
        .corners
        .iter()
        .all(|&(f, _)| m.faces[f].len() == 4)
}

/// Limit position of vertex `v` of a closed mesh whose faces around `v` are
/// all quads (panics otherwise), standard mask:
/// `(n² V + 4 ΣE + ΣF)/(n(n+5))`.
pub fn limit_position(m: &PolyMesh, v: u32) -> [f64; 3] {
    let (n, sum_e, sum_f) = quad_ring_sums(m, v);
    let p = m.positions[v as usize];
    let nf = n as f64;
    let num = add(add(scale(p, nf * nf), scale(sum_e, 4.0)), sum_f);
    scale(num, 1.0 / (nf * (nf + 5.0)))
}

/// General-weights limit mask for vertex `v` (faces around `v` must be
/// quads): `(5V + (12b+8g) Ebar + (2b+8g) Fbar)/(5+14b+16g)` with
/// `(_, b, g) = w(n)` and `Ebar`/`Fbar` the averages of the edge neighbours
/// and of the face-diagonal vertices. This is the left eigenvector for
/// eigenvalue 1 of the (rotationally averaged) local subdivision matrix.
pub fn limit_position_weighted(m: &PolyMesh, v: u32, w: &Weights) -> [f64; 3] {
    let (n, sum_e, sum_f) = quad_ring_sums(m, v);
    let (_alpha, b, g) = w(n);
    let p = m.positions[v as usize];
    let nf = n as f64;
    let ebar = scale(sum_e, 1.0 / nf);
    let fbar = scale(sum_f, 1.0 / nf);
    let num = add(
        add(scale(p, 5.0), scale(ebar, 12.0 * b + 8.0 * g)),
        scale(fbar, 2.0 * b + 8.0 * g),
    );
    scale(num, 1.0 / (5.0 + 14.0 * b + 16.0 * g))
}

// ---------------------------------------------------------------------------
// Refiner and dyadic limit points.

/// Lazily computed sequence of uniformly refined meshes (level 0 = base), so
/// that many dyadic limit points can be evaluated without redoing
/// subdivisions.
pub struct Refiner<'w> {
    levels: Vec<PolyMesh>,
    weights: Option<&'w Weights>,
}

impl<'w> Refiner<'w> {
    /// Starts from `base`. With `weights == None` every step is
    /// [`catmull_clark`] and limit positions use [`limit_position`]; with
    /// `Some(w)` they are [`catmull_clark_weighted`] and
    /// [`limit_position_weighted`] with `w`.
    pub fn new(base: &PolyMesh, weights: Option<&'w Weights>) -> Refiner<'w> {
        Refiner {
            levels: vec![base.clone()],
            weights,
        }
    }

    /// The mesh after `k` subdivision steps (computed on first use).
    pub fn level(&mut self, k: usize) -> &PolyMesh {
        while self.levels.len() <= k {
            let last = self.levels.last().expect("refiner has a base level");
            let next = match self.weights {
                None => catmull_clark(last),
                Some(w) => catmull_clark_weighted(last, w),
            };
            self.levels.push(next);
        }
        &self.levels[k]
    }

    /// Limit position of vertex `v` of level `k` (with this refiner's rule).
    /// If a face around `v` is not a quad (only possible at level 0), the
    /// mask is applied at level `k + 1`, where `v` keeps its index.
    pub fn limit_position(&mut self, k: usize, v: u32) -> [f64; 3] {
        let k = if ring_is_all_quads(self.level(k), v) {
            k
        } else {
            k + 1
        };
        let weights = self.weights;
        let mesh = self.level(k);
        match weights {
            None => limit_position(mesh, v),
            Some(w) => limit_position_weighted(mesh, v, w),
        }
    }

    /// Exact limit point at the dyadic parameter `(i/2^k, j/2^k)` of base
    /// face `face`; for a non-quad face, of its sub-face `sub` (see the module
    /// docs); `sub` must be 0 for quads. Points on the face boundary
    /// (`i` or `j` equal to 0 or `2^k`) are allowed. Cost grows like `4^k`
    /// in the mesh size; intended for `k <= 6`.
    ///
    /// Method: descend with exact integer arithmetic through the child quads
    /// containing the point until it is a corner of the current face, then
    /// apply the limit mask to that vertex.
    pub fn dyadic_limit_point(
        &mut self,
        face: usize,
        sub: usize,
        i: u32,
        j: u32,
        k: u32,
    ) -> [f64; 3] {
        let (level, v) = self.dyadic_vertex_index(face, sub, i, j, k);
        self.limit_position(level, v)
    }

    /// Control-point position, in the mesh after `steps` uniform steps of the
    /// base mesh, of the vertex at dyadic parameter `(i/2^k, j/2^k)` of base
    /// face `face` (sub-face `sub`). That vertex must exist at level `steps`
    /// (i.e. `steps >= k` for quads, `steps >= k + 1` for n-gon sub-faces).
    pub fn dyadic_vertex(
        &mut self,
        face: usize,
        sub: usize,
        i: u32,
        j: u32,
        k: u32,
        steps: usize,
    ) -> [f64; 3] {
        let (level, v) = self.dyadic_vertex_index(face, sub, i, j, k);
        assert!(
            level <= steps,
            "vertex appears only at level {level} > {steps}"
        );
        self.level(steps).positions[v as usize]
    }

    /// (level, vertex index) of the first level at which the dyadic point
    /// `(i/2^k, j/2^k)` of (face, sub) is a mesh vertex; vertex indices
    /// persist through later levels.
    fn dyadic_vertex_index(
        &mut self,
        face: usize,
        sub: usize,
        i: u32,
        j: u32,
        k: u32,
    ) -> (usize, u32) {
        assert!(k <= 24, "dyadic level k = {} is unreasonably large", k);
        let base = self.level(0);
        assert!(
            face < base.faces.len(),
            "face {} out of range (mesh has {} faces)",
            face,
            base.faces.len()
        );
        let n = base.faces[face].len();
        let (mut level, mut f) = if n == 4 {
            assert_eq!(sub, 0, "sub-face must be 0 for quad face {}", face);
            (0usize, face)
        } else {
            assert!(
                sub < n,
                "sub-face {} out of range for face {} with {} vertices",
                sub,
                face,
                n
            );
            let offset = child_offset(base, face);
            (1usize, offset + sub)
        };
        let mut size: i64 = 1 << k;
        assert!(
            (i as i64) <= size && (j as i64) <= size,
            "dyadic parameter ({}, {})/2^{} outside [0,1]^2",
            i,
            j,
            k
        );
        let mut p: [i64; 2] = [i as i64, j as i64];

        loop {
            let mesh = self.level(level);
            assert_eq!(
                mesh.faces[f].len(),
                4,
                "internal: descended into a non-quad"
            );
            // Parametric corners of the current face scaled by `size`.
            let corners: [[i64; 2]; 4] = [[0, 0], [size, 0], [size, size], [0, size]];
            if let Some(c) = corners.iter().position(|&c| c == p) {
                return (level, mesh.faces[f][c]);
            }
            assert!(size > 1, "internal: point not a corner at the finest level");
            let half = size / 2;
            let mut chosen = None;
            for c in 0..4 {
                let origin = corners[c];
                // Unit axis directions of the child's s and t.
                let ds = [
                    (corners[(c + 1) % 4][0] - origin[0]) / size,
                    (corners[(c + 1) % 4][1] - origin[1]) / size,
                ];
                let dt = [
                    (corners[(c + 3) % 4][0] - origin[0]) / size,
                    (corners[(c + 3) % 4][1] - origin[1]) / size,
                ];
                let rel = [p[0] - origin[0], p[1] - origin[1]];
                let s = rel[0] * ds[0] + rel[1] * ds[1];
                let t = rel[0] * dt[0] + rel[1] * dt[1];
                if (0..=half).contains(&s) && (0..=half).contains(&t) {
                    chosen = Some((c, [s, t]));
                    break;
                }
            }
            let (c, child_p) = chosen.expect("internal: no child quad contains the point");
            f = child_offset(mesh, f) + c;
            p = child_p;
            size = half;
            level += 1;
        }
    }
}

/// Exact limit point at the dyadic parameter `(i/2^k, j/2^k)` of base face
/// `face` (sub-face `sub` for non-quads; `sub` must be 0 for quads), standard
/// rules. See [`Refiner::dyadic_limit_point`]; use a [`Refiner`] directly to
/// evaluate many points.
pub fn dyadic_limit_point(
    m: &PolyMesh,
    face: usize,
    sub: usize,
    i: u32,
    j: u32,
    k: u32,
) -> [f64; 3] {
    Refiner::new(m, None).dyadic_limit_point(face, sub, i, j, k)
}

/// Like [`dyadic_limit_point`] with the custom vertex rule `w`.
pub fn dyadic_limit_point_weighted(
    m: &PolyMesh,
    face: usize,
    sub: usize,
    i: u32,
    j: u32,
    k: u32,
    w: &Weights,
) -> [f64; 3] {
    Refiner::new(m, Some(w)).dyadic_limit_point(face, sub, i, j, k)
}

// ---------------------------------------------------------------------------
// Test mesh generators.

/// Closed `n`-gonal prism (`n >= 3`), radius 1, height 1, centred at the
/// origin. Vertices: bottom ring `0..n` at `z = -0.5`, top ring `n..2n` at
/// `z = 0.5`, vertex `k` of a ring at angle `2πk/n`. Faces: 0 = bottom cap
/// (`[n-1, ..., 1, 0]`), 1 = top cap (`[n, ..., 2n-1]`), then side quad `k`
/// (face `2 + k`) = `[k, k+1, n+k+1, n+k]` (indices mod `n` within a ring).
/// All faces oriented outward.
pub fn drum(n: usize) -> PolyMesh {
    assert!(n >= 3, "drum needs n >= 3, got {}", n);
    let mut positions = Vec::with_capacity(2 * n);
    for z in [-0.5, 0.5] {
        for k in 0..n {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            positions.push([a.cos(), a.sin(), z]);
        }
    }
    let n32 = n as u32;
    let mut faces = Vec::with_capacity(n + 2);
    faces.push((0..n32).rev().collect());
    faces.push((n32..2 * n32).collect());
    for k in 0..n32 {
        let k1 = (k + 1) % n32;
        faces.push(vec![k, k1, n32 + k1, n32 + k]);
    }
    PolyMesh { positions, faces }
}

/// All-quad closed mesh with two vertices of valence `n`:
/// `catmull_clark(&drum(n))` (`2n` vertex points, `3n` edge points, `n+2`
/// face points; the valence-`n` vertices are the cap face points `5n` and
/// `5n+1`) with every vertex moved by a deterministic
/// pseudo-random offset with coordinates in `[-0.05, 0.05]` (fixed-seed LCG),
/// so tests are not symmetric.
pub fn pole_mesh(n: usize) -> PolyMesh {
    let mut m = catmull_clark(&drum(n));
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || -> f64 {
        // Knuth's MMIX LCG; the top 53 bits give a uniform value in [0, 1).
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for p in &mut m.positions {
        for c in p.iter_mut() {
            *c += 0.1 * (next() - 0.5);
        }
    }
    m
}

/// All-quad regular torus around the z axis, outward orientation.
/// Vertex `i * nv + j` (`i < nu` around the major circle, `j < nv` around the
/// minor one) is at `((R + r cos φ) cos θ, (R + r cos φ) sin θ, r sin φ)` with
/// `θ = 2πi/nu`, `φ = 2πj/nv`. Face `i * nv + j` is
/// `[(i,j), (i+1,j), (i+1,j+1), (i,j+1)]` (indices wrap), so its parameter
/// `u` runs along `i` and `v` along `j`. Needs `nu, nv >= 3`.
pub fn torus(nu: usize, nv: usize, r_major: f64, r_minor: f64) -> PolyMesh {
    assert!(
        nu >= 3 && nv >= 3,
        "torus needs nu, nv >= 3, got {} x {}",
        nu,
        nv
    );
    let tau = 2.0 * std::f64::consts::PI;
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let theta = tau * i as f64 / nu as f64;
        for j in 0..nv {
            let phi = tau * j as f64 / nv as f64;
            let ring = r_major + r_minor * phi.cos();
            positions.push([ring * theta.cos(), ring * theta.sin(), r_minor * phi.sin()]);
        }
    }
    let idx = |i: usize, j: usize| -> u32 { ((i % nu) * nv + (j % nv)) as u32 };
    let mut faces = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            faces.push(vec![
                idx(i, j),
                idx(i + 1, j),
                idx(i + 1, j + 1),
                idx(i, j + 1),
            ]);
        }
    }
    PolyMesh { positions, faces }
}
