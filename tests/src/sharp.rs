//! Reference Catmull-Clark subdivision **with boundaries, creases, corners
//! and holes**, following OpenSubdiv's `Sdc` rules [OSD]; the oracle for
//! real-mesh support (issue #24). Like [`crate::reference`] it is
//! deliberately plain: `Vec`s rebuilt every level, no cleverness.
//!
//! # What it implements
//!
//! * Tags: per-edge sharpness (`t crease`), per-vertex sharpness
//!   (`t corner`), holes (`t hole`), boundary interpolation
//!   (`t interpolateboundary`: 0 none, 1 edge-and-corner, 2 edge-only, the
//!   numbering of OpenSubdiv's regression harness), crease tags as vertex
//!   pairs,
//!   creasing method (`t creasemethod chaikin|normal`) and
//!   `t smoothtriangles smooth|catmark`. Hierarchical edits are ignored
//!   with a warning, as OpenSubdiv's Far does.
//! * Base-level sharpening as Far's topology factory does it: boundary and
//!   non-manifold edges become infinitely sharp; in edge-and-corner mode a
//!   vertex with one face and two edges is an infinitely sharp corner;
//!   non-manifold vertices become infinitely sharp except on a pair of
//!   interior non-manifold edges; in mode `none` every face at a boundary
//!   vertex with an unsharpened boundary edge becomes a hole.
//! * Refinement masks: face points are centroids; edge points are smooth,
//!   sharp (midpoint) or, for sharpness below one, the blend of both; vertex
//!   points use the rule (smooth / dart / crease / corner) given by the vertex
//!   sharpness and the count of sharp incident edges, blended with the
//!   child's rule by OpenSubdiv's fractional weight when the rule changes.
//!   Sharpness decays by one per level (`uniform`) or after Chaikin
//!   averaging at each end vertex (`chaikin`), in `f32` as OpenSubdiv does.
//! * Numbering as OpenSubdiv's uniform refinement (default options), so
//!   that refined control points can be compared index by index: child
//!   vertices are the vertex points (same index as their parent), then one
//!   face point per face, then one edge point per edge; child faces are
//!   listed per parent face, `n` children for an `n`-gon; the child `j` of a
//!   quad keeps the parent's orientation (its corner `j` is the vertex point,
//!   so child `(s, t)` is parent `(c_j + (s, t)) / 2`); the child `j` of a
//!   non-quad is `[vertex point, next edge point, face point, previous edge
//!   point]`. Edges at level 0 appear in order of first use scanning faces;
//!   at later levels the edges inside each parent face come first (face
//!   order, one per face vertex), then the two halves of each parent edge.
//!
//! # Limit positions
//!
//! * [`Level::osd_limit`] applies OpenSubdiv's limit masks (smooth, crease
//!   `(1, 4, 1) / 6`, corner). They are exact except at darts and at smooth
//!   vertices of valence 2, where OpenSubdiv uses the smooth respectively the
//!   corner mask as an approximation.
//! * [`Level::exact_limit`] is exact everywhere: once the vertex and its
//!   incident edges have no semi-sharp values left (sharpness 0 or infinite;
//!   at most about ten levels), one subdivision step maps the vertex's
//!   one-ring (the vertex, the far end of each incident edge, the far corner
//!   of each incident quad) to the next level's one-ring by a fixed matrix
//!   `S`, and the limit position is `l · ring` with `l` the left eigenvector
//!   of `S` for eigenvalue 1 (found by power iteration, residual checked).
//!   `S` is assembled from the same masks as the refinement, so the limit is
//!   a consequence of the rules, not a second table of formulas.
// Index loops mirror OpenSubdiv's per-component loops.
#![allow(clippy::needless_range_loop)]

use std::collections::HashMap;
use std::path::Path;

/// Sharpness at or above which OpenSubdiv treats an edge or vertex as
/// infinitely sharp.
pub const INFINITE: f32 = 10.0;

/// Boundary interpolation (OpenSubdiv `VtxBoundaryInterpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// Faces at un-sharpened boundary vertices are holes.
    None,
    /// Boundary edges are infinitely sharp.
    EdgeOnly,
    /// Also vertices with one face and two edges are infinitely sharp.
    EdgeAndCorner,
}

/// Creasing method (OpenSubdiv `CreasingMethod`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Creasing {
    /// Sharpness decreases by one per level.
    Uniform,
    /// Chaikin averaging of the semi-sharp edges at each end, then minus one.
    Chaikin,
}

/// Scheme options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// Boundary interpolation; OpenSubdiv's regression harness defaults to
    /// edge-only.
    pub boundary: Boundary,
    /// Creasing method.
    pub creasing: Creasing,
    /// OpenSubdiv's `TRI_SUB_SMOOTH` edge weights at triangles.
    pub smooth_triangles: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            boundary: Boundary::EdgeOnly,
            creasing: Creasing::Uniform,
            smooth_triangles: false,
        }
    }
}

/// A polygon mesh with OpenSubdiv's tags, as read from an OBJ file.
#[derive(Clone, Debug, Default)]
pub struct TaggedMesh {
    /// Positions in `v` line order (unused vertices kept, as OpenSubdiv does).
    pub positions: Vec<[f64; 3]>,
    /// Faces (0-based vertex indices).
    pub faces: Vec<Vec<u32>>,
    /// `(a, b, sharpness)` per tagged edge.
    pub creases: Vec<(u32, u32, f32)>,
    /// `(vertex, sharpness)` per tagged vertex.
    pub corners: Vec<(u32, f32)>,
    /// Faces tagged as holes.
    pub holes: Vec<u32>,
    /// Scheme options from the tags (defaults where untagged).
    pub options: Options,
    /// Tags that were ignored, one line each.
    pub warnings: Vec<String>,
}

fn parse_f(s: &str, line: usize) -> Result<f64, String> {
    s.parse::<f64>()
        .map_err(|_| format!("line {line}: '{s}' is not a number"))
}

impl TaggedMesh {
    /// Reads an OBJ file with OpenSubdiv's `t` tags (see [`TaggedMesh::parse`]).
    pub fn from_obj(path: &Path) -> Result<TaggedMesh, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        TaggedMesh::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses OBJ text: `v` and `f` lines (`v/vt/vn` forms, negative indices),
    /// and `t name nint/nfloat/nstring ints floats strings` tags.
    pub fn parse(text: &str) -> Result<TaggedMesh, String> {
        let mut m = TaggedMesh::default();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let mut it = raw.split_whitespace();
            match it.next() {
                Some("v") => {
                    let mut p = [0.0; 3];
                    for c in &mut p {
                        let s = it
                            .next()
                            .ok_or(format!("line {line}: vertex needs 3 coordinates"))?;
                        *c = parse_f(s, line)?;
                    }
                    m.positions.push(p);
                }
                Some("f") => {
                    let mut face = Vec::new();
                    for tok in it {
                        let first = tok.split('/').next().unwrap_or("");
                        let k: i64 = first
                            .parse()
                            .map_err(|_| format!("line {line}: bad face index '{tok}'"))?;
                        let n = m.positions.len() as i64;
                        let idx = if k < 0 { n + k } else { k - 1 };
                        if idx < 0 {
                            return Err(format!("line {line}: face index {k} out of range"));
                        }
                        face.push(idx as u32);
                    }
                    if face.len() < 3 {
                        return Err(format!("line {line}: face with fewer than 3 vertices"));
                    }
                    m.faces.push(face);
                }
                Some("t") => m.parse_tag(&mut it, line)?,
                _ => {}
            }
        }
        let nv = m.positions.len() as u32;
        for (f, face) in m.faces.iter().enumerate() {
            if let Some(&v) = face.iter().find(|&&v| v >= nv) {
                return Err(format!("face {f} uses vertex {} of {nv}", v + 1));
            }
        }
        Ok(m)
    }

    fn parse_tag<'a>(
        &mut self,
        it: &mut impl Iterator<Item = &'a str>,
        line: usize,
    ) -> Result<(), String> {
        let name = it
            .next()
            .ok_or(format!("line {line}: tag without a name"))?;
        let counts = it
            .next()
            .ok_or(format!("line {line}: tag '{name}' without counts"))?;
        let c: Vec<usize> = counts
            .split('/')
            .map(|s| {
                s.parse()
                    .map_err(|_| format!("line {line}: bad tag counts"))
            })
            .collect::<Result<_, _>>()?;
        if c.len() != 3 {
            return Err(format!("line {line}: tag counts must be i/f/s"));
        }
        let rest: Vec<&str> = it.collect();
        if rest.len() < c[0] + c[1] + c[2] {
            return Err(format!("line {line}: tag '{name}' has too few values"));
        }
        let ints: Vec<i64> = rest[..c[0]]
            .iter()
            .map(|s| {
                s.parse()
                    .map_err(|_| format!("line {line}: bad tag integer"))
            })
            .collect::<Result<_, _>>()?;
        let floats: Vec<f64> = rest[c[0]..c[0] + c[1]]
            .iter()
            .map(|s| parse_f(s, line))
            .collect::<Result<_, _>>()?;
        let strings = &rest[c[0] + c[1]..c[0] + c[1] + c[2]];
        match name {
            "crease" => {
                if ints.len() < 2 || !ints.len().is_multiple_of(2) || floats.len() != 1 {
                    return Err(format!(
                        "line {line}: crease needs vertex pairs and 1 value"
                    ));
                }
                for w in ints.chunks_exact(2) {
                    self.creases
                        .push((w[0] as u32, w[1] as u32, floats[0] as f32));
                }
            }
            "corner" => {
                if floats.len() != 1 {
                    return Err(format!("line {line}: corner needs 1 value"));
                }
                for &v in &ints {
                    self.corners.push((v as u32, floats[0] as f32));
                }
            }
            "hole" => self.holes.extend(ints.iter().map(|&f| f as u32)),
            "interpolateboundary" => {
                self.options.boundary = match ints.first() {
                    Some(0) => Boundary::None,
                    Some(1) => Boundary::EdgeAndCorner,
                    Some(2) => Boundary::EdgeOnly,
                    _ => {
                        return Err(format!(
                            "line {line}: interpolateboundary must be 0, 1 or 2"
                        ))
                    }
                }
            }
            "creasemethod" => {
                self.options.creasing = match strings.first() {
                    Some(&"chaikin") => Creasing::Chaikin,
                    Some(&"normal") | Some(&"uniform") => Creasing::Uniform,
                    _ => return Err(format!("line {line}: unknown creasemethod")),
                }
            }
            "smoothtriangles" => {
                self.options.smooth_triangles = match strings.first() {
                    Some(&"smooth") => true,
                    Some(&"catmark") => false,
                    _ => return Err(format!("line {line}: unknown smoothtriangles value")),
                }
            }
            other => self
                .warnings
                .push(format!("line {line}: tag '{other}' ignored")),
        }
        Ok(())
    }

    /// Bounding-box diagonal of all positions.
    pub fn bbox_diagonal(&self) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.positions {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt()
    }
}

// ---------------------------------------------------------------------------
// Sharpness arithmetic, in f32 exactly as OpenSubdiv's Sdc::Crease.

fn is_sharp(s: f32) -> bool {
    s > 0.0
}
fn is_infinite(s: f32) -> bool {
    s >= INFINITE
}
fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < INFINITE
}
fn decrement(s: f32) -> f32 {
    if is_infinite(s) {
        INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// Vertex rule (OpenSubdiv `Crease::Rule`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// No sharp incident edge.
    Smooth,
    /// One sharp incident edge.
    Dart,
    /// Two sharp incident edges.
    Crease,
    /// Sharp vertex, or more than two sharp edges.
    Corner,
}

fn rule_of(vertex_sharpness: f32, edge_sharpness: &[f32]) -> Rule {
    if is_sharp(vertex_sharpness) {
        return Rule::Corner;
    }
    match edge_sharpness.iter().filter(|&&s| is_sharp(s)).count() {
        0 => Rule::Smooth,
        1 => Rule::Dart,
        2 => Rule::Crease,
        _ => Rule::Corner,
    }
}

/// Child sharpness of each incident edge at this vertex end.
fn subdivide_edges_at_vertex(creasing: Creasing, parent: &[f32]) -> Vec<f32> {
    if creasing == Creasing::Uniform || parent.len() < 2 {
        return parent.iter().map(|&s| decrement(s)).collect();
    }
    let semi: Vec<f32> = parent
        .iter()
        .copied()
        .filter(|&s| is_semi_sharp(s))
        .collect();
    let sum: f32 = semi.iter().sum();
    parent
        .iter()
        .map(|&s| {
            if !is_sharp(s) {
                0.0
            } else if is_infinite(s) {
                INFINITE
            } else if semi.len() == 1 {
                decrement(s)
            } else {
                let others = (sum - s) / (semi.len() - 1) as f32;
                let c = (0.75f32 * s + 0.25f32 * others) - 1.0f32;
                if is_sharp(c) {
                    c
                } else {
                    0.0
                }
            }
        })
        .collect()
}

fn fractional_weight(
    creasing: Creasing,
    parent_vertex: f32,
    child_vertex: f32,
    parent_edges: &[f32],
    child_edges: &[f32],
) -> f32 {
    let mut count = 0usize;
    let mut sum = 0.0f32;
    if is_sharp(parent_vertex) && !is_sharp(child_vertex) {
        count = 1;
        sum = parent_vertex;
    }
    for (i, &p) in parent_edges.iter().enumerate() {
        let transition = match creasing {
            Creasing::Uniform => is_sharp(p) && p <= 1.0,
            Creasing::Chaikin => is_sharp(p) && !is_sharp(child_edges[i]),
        };
        if transition {
            sum += p;
            count += 1;
        }
    }
    if count == 0 {
        return 0.0;
    }
    (sum / count as f32).min(1.0)
}

// ---------------------------------------------------------------------------
// Masks in local terms.

/// A vertex-point mask: weight of the vertex, of the far end of each
/// incident edge, and of the centroid of each incident face (in the order
/// of `Level::vert_edges` / `Level::vert_faces`).
#[derive(Clone, Debug, PartialEq)]
struct VertexMask {
    v: f64,
    edge: Vec<f64>,
    face: Vec<f64>,
}

impl VertexMask {
    fn corner(ne: usize, nf: usize) -> Self {
        VertexMask {
            v: 1.0,
            edge: vec![0.0; ne],
            face: vec![0.0; nf],
        }
    }
    fn smooth(ne: usize, nf: usize) -> Self {
        assert_eq!(
            ne, nf,
            "smooth rule at a vertex with {ne} edges and {nf} faces"
        );
        let n = nf as f64;
        VertexMask {
            v: (n - 2.0) / n,
            edge: vec![1.0 / (n * n); ne],
            face: vec![1.0 / (n * n); nf],
        }
    }
    fn crease(ne: usize, nf: usize, sharp: &[f32]) -> Self {
        let mut m = VertexMask {
            v: 0.75,
            edge: vec![0.0; ne],
            face: vec![0.0; nf],
        };
        let ends: Vec<usize> = (0..ne).filter(|&i| is_sharp(sharp[i])).take(2).collect();
        assert_eq!(ends.len(), 2, "crease rule without two sharp edges");
        for e in ends {
            m.edge[e] = 0.125;
        }
        m
    }
    fn for_rule(rule: Rule, ne: usize, nf: usize, sharp: &[f32]) -> Self {
        match rule {
            Rule::Smooth | Rule::Dart => VertexMask::smooth(ne, nf),
            Rule::Crease => VertexMask::crease(ne, nf, sharp),
            Rule::Corner => VertexMask::corner(ne, nf),
        }
    }
    fn blend(&self, pw: f64, child: &VertexMask) -> VertexMask {
        let cw = 1.0 - pw;
        VertexMask {
            v: pw * self.v + cw * child.v,
            edge: self
                .edge
                .iter()
                .zip(&child.edge)
                .map(|(a, b)| pw * a + cw * b)
                .collect(),
            face: self
                .face
                .iter()
                .zip(&child.face)
                .map(|(a, b)| pw * a + cw * b)
                .collect(),
        }
    }
}

/// An edge-point mask: weights of the two end vertices and of the centroid
/// of each face of the edge (in `Level::edge_faces` order).
#[derive(Clone, Debug, PartialEq)]
struct EdgeMask {
    v: [f64; 2],
    face: Vec<f64>,
}

/// One level of a refined tagged mesh.
#[derive(Clone, Debug)]
pub struct Level {
    /// Control points.
    pub positions: Vec<[f64; 3]>,
    /// Faces.
    pub faces: Vec<Vec<u32>>,
    /// Hole flag per face.
    pub hole: Vec<bool>,
    /// Edges as vertex pairs.
    pub edges: Vec<[u32; 2]>,
    /// Per face, its edges `(v_k, v_{k+1})`.
    pub face_edges: Vec<Vec<u32>>,
    /// Faces of each edge.
    pub edge_faces: Vec<Vec<u32>>,
    /// Edges of each vertex.
    pub vert_edges: Vec<Vec<u32>>,
    /// Faces of each vertex.
    pub vert_faces: Vec<Vec<u32>>,
    /// Edge sharpness.
    pub edge_sharpness: Vec<f32>,
    /// Vertex sharpness.
    pub vertex_sharpness: Vec<f32>,
    /// Scheme options.
    pub options: Options,
    /// A cut-out of a larger level ([`Level::around`]): vertices on its rim
    /// have incomplete neighbourhoods and get meaningless (never used)
    /// positions instead of failing the smooth rule's checks.
    pub partial: bool,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

impl Level {
    /// Builds the adjacency of `faces` given the edge list in its order.
    fn with_edges(
        positions: Vec<[f64; 3]>,
        faces: Vec<Vec<u32>>,
        edges: Vec<[u32; 2]>,
        options: Options,
    ) -> Level {
        let nv = positions.len();
        let index: HashMap<(u32, u32), u32> = edges
            .iter()
            .enumerate()
            .map(|(i, e)| (key(e[0], e[1]), i as u32))
            .collect();
        let mut face_edges = Vec::with_capacity(faces.len());
        let mut edge_faces = vec![Vec::new(); edges.len()];
        let mut vert_faces = vec![Vec::new(); nv];
        for (f, face) in faces.iter().enumerate() {
            let n = face.len();
            let fe: Vec<u32> = (0..n)
                .map(|k| index[&key(face[k], face[(k + 1) % n])])
                .collect();
            for &e in &fe {
                edge_faces[e as usize].push(f as u32);
            }
            for &v in face {
                vert_faces[v as usize].push(f as u32);
            }
            face_edges.push(fe);
        }
        let mut vert_edges = vec![Vec::new(); nv];
        for (e, ev) in edges.iter().enumerate() {
            vert_edges[ev[0] as usize].push(e as u32);
            vert_edges[ev[1] as usize].push(e as u32);
        }
        let nf = faces.len();
        let ne = edges.len();
        Level {
            positions,
            faces,
            hole: vec![false; nf],
            edges,
            face_edges,
            edge_faces,
            vert_edges,
            vert_faces,
            edge_sharpness: vec![0.0; ne],
            vertex_sharpness: vec![0.0; nv],
            options,
            partial: false,
        }
    }

    /// The base level of `m`, with Far's sharpening of boundary and
    /// non-manifold features. Errors name the face, edge or vertex; faces
    /// that repeat a vertex are not supported here.
    pub fn base(m: &TaggedMesh) -> Result<Level, String> {
        let mut edges = Vec::new();
        let mut seen = HashMap::new();
        for (f, face) in m.faces.iter().enumerate() {
            let n = face.len();
            for k in 0..n {
                let (a, b) = (face[k], face[(k + 1) % n]);
                if face[..k].contains(&face[k]) {
                    return Err(format!("face {f} repeats vertex {}", face[k]));
                }
                if let std::collections::hash_map::Entry::Vacant(e) = seen.entry(key(a, b)) {
                    e.insert(edges.len());
                    edges.push([a, b]);
                }
            }
        }
        let mut l = Level::with_edges(m.positions.clone(), m.faces.clone(), edges, m.options);
        for &(a, b, s) in &m.creases {
            let e = *seen
                .get(&key(a, b))
                .ok_or(format!("crease tag on ({a}, {b}), which is not an edge"))?;
            l.edge_sharpness[e] = s.max(0.0);
        }
        for &(v, s) in &m.corners {
            if v as usize >= l.positions.len() {
                return Err(format!("corner tag on vertex {v}, which does not exist"));
            }
            l.vertex_sharpness[v as usize] = s.max(0.0);
        }
        for &f in &m.holes {
            if f as usize >= l.faces.len() {
                return Err(format!("hole tag on face {f}, which does not exist"));
            }
            l.hole[f as usize] = true;
        }
        l.sharpen_base();
        Ok(l)
    }

    fn edge_is_nonmanifold(&self, e: usize) -> bool {
        let fs = &self.edge_faces[e];
        if fs.len() > 2 {
            return true;
        }
        if fs.len() == 2 {
            // Both faces traversing the edge the same way: misoriented.
            let dir = |f: u32| {
                let fv = &self.faces[f as usize];
                let k = self.face_edges[f as usize]
                    .iter()
                    .position(|&x| x as usize == e)
                    .unwrap();
                fv[k]
            };
            return dir(fs[0]) == dir(fs[1]);
        }
        false
    }

    fn vertex_is_nonmanifold(&self, v: usize, nm_edge: &[bool]) -> bool {
        let es = &self.vert_edges[v];
        let fs = &self.vert_faces[v];
        if es.iter().any(|&e| nm_edge[e as usize]) {
            return true;
        }
        if fs.is_empty() {
            return false;
        }
        // The faces must form one fan through the manifold edges at v.
        let mut reached = vec![false; fs.len()];
        let mut stack = vec![0usize];
        reached[0] = true;
        while let Some(i) = stack.pop() {
            let f = fs[i] as usize;
            for &e in &self.face_edges[f] {
                let ev = self.edges[e as usize];
                if ev[0] as usize != v && ev[1] as usize != v {
                    continue;
                }
                for &g in &self.edge_faces[e as usize] {
                    if let Some(j) = fs.iter().position(|&x| x == g) {
                        if !reached[j] {
                            reached[j] = true;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        let boundary = es
            .iter()
            .filter(|&&e| self.edge_faces[e as usize].len() == 1)
            .count();
        !reached.iter().all(|&r| r) || !(boundary == 0 || boundary == 2)
    }

    /// Far's `prepareComponentTagsAndSharpness` for the base level.
    fn sharpen_base(&mut self) {
        let ne = self.edges.len();
        let nm_edge: Vec<bool> = (0..ne).map(|e| self.edge_is_nonmanifold(e)).collect();
        let nm_vert: Vec<bool> = (0..self.positions.len())
            .map(|v| self.vertex_is_nonmanifold(v, &nm_edge))
            .collect();
        if self.options.boundary == Boundary::None {
            for v in 0..self.positions.len() {
                let es = &self.vert_edges[v];
                if es.len() == self.vert_faces[v].len() && !nm_vert[v] {
                    continue;
                }
                let exclude = es.iter().any(|&e| {
                    self.edge_faces[e as usize].len() == 1
                        && !is_infinite(self.edge_sharpness[e as usize])
                });
                if exclude {
                    for &f in &self.vert_faces[v] {
                        self.hole[f as usize] = true;
                    }
                }
            }
        }
        for e in 0..ne {
            if self.edge_faces[e].len() < 2 || nm_edge[e] {
                self.edge_sharpness[e] = INFINITE;
            }
        }
        for v in 0..self.positions.len() {
            let es = &self.vert_edges[v];
            let nf = self.vert_faces[v].len();
            let boundary = es
                .iter()
                .filter(|&&e| self.edge_faces[e as usize].len() < 2)
                .count();
            let nm_edges = es.iter().filter(|&&e| nm_edge[e as usize]).count();
            let topological_corner = nf == 1 && es.len() == 2;
            // A non-manifold vertex is sharpened unless it lies on a pair of
            // interior non-manifold edges (a crease with fins).
            let sharpened_corner =
                topological_corner && self.options.boundary == Boundary::EdgeAndCorner;
            let fin_crease = nm_edges == 2 && boundary == 0 && nf > es.len();
            if sharpened_corner || (nm_vert[v] && !fin_crease) {
                self.vertex_sharpness[v] = INFINITE;
            }
        }
    }

    fn edge_sharpness_at(&self, v: usize) -> Vec<f32> {
        self.vert_edges[v]
            .iter()
            .map(|&e| self.edge_sharpness[e as usize])
            .collect()
    }

    /// The vertex rule of `v` at this level.
    pub fn rule(&self, v: usize) -> Rule {
        rule_of(self.vertex_sharpness[v], &self.edge_sharpness_at(v))
    }

    /// The child sharpness, at `v`'s end, of each edge incident to `v`.
    fn child_edge_sharpness_at(&self, v: usize) -> Vec<f32> {
        subdivide_edges_at_vertex(self.options.creasing, &self.edge_sharpness_at(v))
    }

    fn vertex_mask(&self, v: usize) -> VertexMask {
        let ne = self.vert_edges[v].len();
        let nf = self.vert_faces[v].len();
        if nf == 0 {
            return VertexMask::corner(ne, nf);
        }
        let ps = self.edge_sharpness_at(v);
        let pv = self.vertex_sharpness[v];
        let prule = rule_of(pv, &ps);
        if self.partial && ne != nf && matches!(prule, Rule::Smooth | Rule::Dart) {
            return VertexMask::corner(ne, nf);
        }
        let pmask = VertexMask::for_rule(prule, ne, nf, &ps);
        if matches!(prule, Rule::Smooth | Rule::Dart) {
            return pmask;
        }
        let cs = self.child_edge_sharpness_at(v);
        let cv = decrement(pv);
        let crule = rule_of(cv, &cs);
        if crule == prule {
            return pmask;
        }
        if self.partial && ne != nf && matches!(crule, Rule::Smooth | Rule::Dart) {
            return VertexMask::corner(ne, nf);
        }
        let cmask = VertexMask::for_rule(crule, ne, nf, &cs);
        let w = fractional_weight(self.options.creasing, pv, cv, &ps, &cs) as f64;
        pmask.blend(w, &cmask)
    }

    /// Child sharpness of edge `e`'s two halves (at `edges[e][0]`, `[1]`).
    fn child_halves(&self, e: usize) -> [f32; 2] {
        let mut out = [0.0; 2];
        for (j, o) in out.iter_mut().enumerate() {
            let v = self.edges[e][j] as usize;
            let k = self.vert_edges[v]
                .iter()
                .position(|&x| x as usize == e)
                .unwrap();
            *o = self.child_edge_sharpness_at(v)[k];
        }
        out
    }

    fn edge_mask(&self, e: usize) -> EdgeMask {
        let fs = &self.edge_faces[e];
        let s = self.edge_sharpness[e];
        let smooth = || {
            let tri = |i: usize| self.faces[fs[i] as usize].len() == 3;
            if self.options.smooth_triangles && fs.len() == 2 && (tri(0) || tri(1)) {
                let w = |t: bool| if t { 0.47 } else { 0.25 };
                let fw = 0.5 * (w(tri(0)) + w(tri(1)));
                let vw = 0.5 * (1.0 - 2.0 * fw);
                EdgeMask {
                    v: [vw, vw],
                    face: vec![fw, fw],
                }
            } else {
                let fw = if fs.len() == 2 {
                    0.25
                } else {
                    0.5 / fs.len() as f64
                };
                EdgeMask {
                    v: [0.25, 0.25],
                    face: vec![fw; fs.len()],
                }
            }
        };
        if !is_sharp(s) {
            return smooth();
        }
        let halves = self.child_halves(e);
        let child_rule = rule_of(0.0, &halves);
        if child_rule == Rule::Crease {
            return EdgeMask {
                v: [0.5, 0.5],
                face: vec![0.0; fs.len()],
            };
        }
        let mut m = smooth();
        let pw = s as f64;
        let cw = 1.0 - pw;
        m.v = [pw * 0.5 + cw * m.v[0], pw * 0.5 + cw * m.v[1]];
        for w in &mut m.face {
            *w *= cw;
        }
        m
    }

    fn centroid(&self, f: usize) -> [f64; 3] {
        let fv = &self.faces[f];
        let mut c = [0.0; 3];
        for &v in fv {
            for (k, ck) in c.iter_mut().enumerate() {
                *ck += self.positions[v as usize][k];
            }
        }
        c.map(|x| x / fv.len() as f64)
    }

    /// One uniform refinement step, numbered as OpenSubdiv numbers it.
    pub fn refine(&self) -> Level {
        let nv = self.positions.len();
        let nf = self.faces.len();
        let ne = self.edges.len();
        let fv_index = |f: usize| (nv + f) as u32;
        let ev_index = |e: usize| (nv + nf + e) as u32;
        let centroids: Vec<[f64; 3]> = (0..nf).map(|f| self.centroid(f)).collect();
        let mut pos = vec![[0.0; 3]; nv + nf + ne];
        let add = |acc: &mut [f64; 3], p: [f64; 3], w: f64| {
            for k in 0..3 {
                acc[k] += w * p[k];
            }
        };
        for v in 0..nv {
            let m = self.vertex_mask(v);
            let mut acc = [0.0; 3];
            add(&mut acc, self.positions[v], m.v);
            for (i, &e) in self.vert_edges[v].iter().enumerate() {
                let ev = self.edges[e as usize];
                let other = if ev[0] as usize == v { ev[1] } else { ev[0] };
                add(&mut acc, self.positions[other as usize], m.edge[i]);
            }
            for (i, &f) in self.vert_faces[v].iter().enumerate() {
                add(&mut acc, centroids[f as usize], m.face[i]);
            }
            pos[v] = acc;
        }
        for f in 0..nf {
            pos[fv_index(f) as usize] = centroids[f];
        }
        for e in 0..ne {
            let m = self.edge_mask(e);
            let mut acc = [0.0; 3];
            add(&mut acc, self.positions[self.edges[e][0] as usize], m.v[0]);
            add(&mut acc, self.positions[self.edges[e][1] as usize], m.v[1]);
            for (i, &f) in self.edge_faces[e].iter().enumerate() {
                add(&mut acc, centroids[f as usize], m.face[i]);
            }
            pos[ev_index(e) as usize] = acc;
        }
        // Child faces and edges in OpenSubdiv's order.
        let mut faces = Vec::new();
        let mut hole = Vec::new();
        let mut edges = Vec::new();
        let mut sharp = Vec::new();
        for f in 0..nf {
            let fvs = &self.faces[f];
            let fes = &self.face_edges[f];
            let n = fvs.len();
            for j in 0..n {
                let jp = (j + n - 1) % n;
                let vv = fvs[j];
                let en = ev_index(fes[j] as usize);
                let fc = fv_index(f);
                let epv = ev_index(fes[jp] as usize);
                let mut q = [0u32; 4];
                if n == 4 {
                    q[j] = vv;
                    q[(j + 1) % 4] = en;
                    q[(j + 2) % 4] = fc;
                    q[(j + 3) % 4] = epv;
                } else {
                    q = [vv, en, fc, epv];
                }
                faces.push(q.to_vec());
                hole.push(self.hole[f]);
            }
            for &e in fes {
                edges.push([fv_index(f), ev_index(e as usize)]);
                sharp.push(0.0f32);
            }
        }
        for e in 0..ne {
            let halves = if is_sharp(self.edge_sharpness[e]) {
                self.child_halves(e)
            } else {
                [0.0; 2]
            };
            for j in 0..2 {
                edges.push([ev_index(e), self.edges[e][j]]);
                sharp.push(halves[j]);
            }
        }
        let mut child = Level::with_edges(pos, faces, edges, self.options);
        child.partial = self.partial;
        child.hole = hole;
        child.edge_sharpness = sharp;
        for v in 0..nv {
            child.vertex_sharpness[v] = decrement(self.vertex_sharpness[v]);
        }
        child
    }

    /// The faces within `rings` rings of vertex `v` (faces touching `v`,
    /// then faces touching their vertices, ...) as a level of their own,
    /// with this level's sharpness, holes and options (no base sharpening:
    /// the values already include it), and `v`'s index there. With three
    /// rings, one refinement step of the result computes the two-ring of
    /// `v`'s vertex point exactly (every rule it needs sees complete
    /// neighbourhoods), which keeps deep local refinement small.
    pub fn around(&self, v: usize, rings: usize) -> (Level, usize) {
        let mut inside = vec![false; self.positions.len()];
        inside[v] = true;
        let mut faces_in = vec![false; self.faces.len()];
        for _ in 0..rings {
            let verts: Vec<usize> = (0..inside.len()).filter(|&x| inside[x]).collect();
            for x in verts {
                for &f in &self.vert_faces[x] {
                    faces_in[f as usize] = true;
                }
            }
            for f in 0..self.faces.len() {
                if faces_in[f] {
                    for &x in &self.faces[f] {
                        inside[x as usize] = true;
                    }
                }
            }
        }
        let mut map = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut vsharp = Vec::new();
        for x in 0..self.positions.len() {
            if inside[x] {
                map[x] = positions.len() as u32;
                positions.push(self.positions[x]);
                vsharp.push(self.vertex_sharpness[x]);
            }
        }
        let mut faces = Vec::new();
        let mut hole = Vec::new();
        let mut edges = Vec::new();
        let mut esharp = Vec::new();
        let mut seen = HashMap::new();
        for f in 0..self.faces.len() {
            if !faces_in[f] {
                continue;
            }
            let fv: Vec<u32> = self.faces[f].iter().map(|&x| map[x as usize]).collect();
            for (k, &e) in self.face_edges[f].iter().enumerate() {
                let (a, b) = (fv[k], fv[(k + 1) % fv.len()]);
                if let std::collections::hash_map::Entry::Vacant(slot) = seen.entry(key(a, b)) {
                    slot.insert(edges.len());
                    edges.push([a, b]);
                    esharp.push(self.edge_sharpness[e as usize]);
                }
            }
            faces.push(fv);
            hole.push(self.hole[f]);
        }
        let mut l = Level::with_edges(positions, faces, edges, self.options);
        l.hole = hole;
        l.edge_sharpness = esharp;
        l.vertex_sharpness = vsharp;
        l.partial = true;
        (l, map[v] as usize)
    }

    /// True when `v` and its incident edges have no semi-sharp value, so
    /// that its one-ring subdivides by a fixed matrix from here on.
    pub fn is_stationary(&self, v: usize) -> bool {
        !is_semi_sharp(self.vertex_sharpness[v])
            && self.vert_edges[v]
                .iter()
                .all(|&e| !is_semi_sharp(self.edge_sharpness[e as usize]))
    }

    /// OpenSubdiv's limit position of `v` (`PrimvarRefiner::Limit`): exact
    /// except at darts and smooth vertices of valence 2.
    pub fn osd_limit(&self, v: usize) -> [f64; 3] {
        let p = self.positions[v];
        let rule = self.rule(v);
        let nf = self.vert_faces[v].len();
        let mut acc = [0.0; 3];
        let add = |acc: &mut [f64; 3], q: [f64; 3], w: f64| {
            for k in 0..3 {
                acc[k] += w * q[k];
            }
        };
        match rule {
            Rule::Corner => return p,
            Rule::Crease => {
                add(&mut acc, p, 2.0 / 3.0);
                let s = self.edge_sharpness_at(v);
                let ends: Vec<usize> = (0..s.len()).filter(|&i| is_sharp(s[i])).take(2).collect();
                for i in ends {
                    add(&mut acc, self.positions[self.far_end(v, i)], 1.0 / 6.0);
                }
            }
            Rule::Smooth | Rule::Dart => {
                if nf == 2 {
                    return p;
                }
                let n = nf as f64;
                let (fw, ew, vw) = if nf == 4 {
                    (1.0 / 36.0, 1.0 / 9.0, 4.0 / 9.0)
                } else {
                    let fw = 1.0 / (n * (n + 5.0));
                    (fw, 4.0 * fw, 1.0 - n * (5.0 * fw))
                };
                add(&mut acc, p, vw);
                for i in 0..self.vert_edges[v].len() {
                    add(&mut acc, self.positions[self.far_end(v, i)], ew);
                }
                for i in 0..nf {
                    add(&mut acc, self.positions[self.diagonal(v, i)], fw);
                }
            }
        }
        acc
    }

    fn far_end(&self, v: usize, i: usize) -> usize {
        let ev = self.edges[self.vert_edges[v][i] as usize];
        if ev[0] as usize == v {
            ev[1] as usize
        } else {
            ev[0] as usize
        }
    }

    /// The corner opposite `v` in its `i`-th incident face (a quad).
    fn diagonal(&self, v: usize, i: usize) -> usize {
        let f = &self.faces[self.vert_faces[v][i] as usize];
        assert_eq!(f.len(), 4, "limit mask needs quads around vertex {v}");
        let k = f.iter().position(|&x| x as usize == v).unwrap();
        f[(k + 2) % 4] as usize
    }

    /// Exact limit position of `v`, which must be stationary (see
    /// [`Level::is_stationary`]) with quads around it: the left eigenvector
    /// of the one-ring subdivision matrix for eigenvalue 1, applied to the
    /// ring. Returns the position and the eigen-residual.
    pub fn exact_limit(&self, v: usize) -> ([f64; 3], f64) {
        assert!(
            self.is_stationary(v),
            "vertex {v} still has semi-sharp features"
        );
        let es = &self.vert_edges[v];
        let fs = &self.vert_faces[v];
        let (ne, nf) = (es.len(), fs.len());
        if nf == 0 {
            return (self.positions[v], 0.0);
        }
        let m = 1 + ne + nf;
        // Slot of each vertex of incident face i: v -> 0, an edge neighbour
        // -> 1 + its edge position, the diagonal -> 1 + ne + i.
        let slot_in_face = |i: usize, x: usize| -> usize {
            if x == v {
                return 0;
            }
            let f = &self.faces[fs[i] as usize];
            assert_eq!(f.len(), 4, "exact limit needs quads around vertex {v}");
            let k = f.iter().position(|&y| y as usize == v).unwrap();
            let pos = f.iter().position(|&y| y as usize == x).unwrap();
            if (pos + 4 - k) % 4 == 2 {
                return 1 + ne + i;
            }
            let e = self.face_edges[fs[i] as usize][if (pos + 4 - k) % 4 == 1 {
                k
            } else {
                (k + 3) % 4
            }];
            1 + es.iter().position(|&y| y == e).unwrap()
        };
        let face_centre_row = |i: usize, w: f64, row: &mut [f64]| {
            let f = &self.faces[fs[i] as usize];
            for &x in f {
                row[slot_in_face(i, x as usize)] += w / 4.0;
            }
        };
        let mut s = vec![vec![0.0; m]; m];
        // Row 0: the vertex point.
        let vm = self.vertex_mask(v);
        s[0][0] += vm.v;
        for i in 0..ne {
            s[0][1 + i] += vm.edge[i];
        }
        for i in 0..nf {
            face_centre_row(i, vm.face[i], &mut s[0]);
        }
        // Rows 1..=ne: edge points of the incident edges.
        for (i, &e) in es.iter().enumerate() {
            let em = self.edge_mask(e as usize);
            let ev = self.edges[e as usize];
            for j in 0..2 {
                let slot = if ev[j] as usize == v { 0 } else { 1 + i };
                s[1 + i][slot] += em.v[j];
            }
            for (k, &f) in self.edge_faces[e as usize].iter().enumerate() {
                let fi = fs.iter().position(|&g| g == f).unwrap();
                let mut row = vec![0.0; m];
                face_centre_row(fi, em.face[k], &mut row);
                for c in 0..m {
                    s[1 + i][c] += row[c];
                }
            }
        }
        // Rows 1+ne..: face points.
        for i in 0..nf {
            let mut row = vec![0.0; m];
            face_centre_row(i, 1.0, &mut row);
            s[1 + ne + i] = row;
        }
        // Left eigenvector for eigenvalue 1 by power iteration.
        // The subdominant eigenvalues of these rules are at most about 0.7,
        // so a few hundred steps reach rounding; stop once a step changes
        // nothing beyond it.
        let mut l = vec![1.0 / m as f64; m];
        for _ in 0..5000 {
            let mut next = vec![0.0; m];
            for r in 0..m {
                for c in 0..m {
                    next[c] += l[r] * s[r][c];
                }
            }
            let sum: f64 = next.iter().sum();
            let change = next
                .iter()
                .zip(&l)
                .map(|(a, b)| (a / sum - b).abs())
                .fold(0.0, f64::max);
            l = next.into_iter().map(|x| x / sum).collect();
            if change < 1e-17 {
                break;
            }
        }
        let mut residual = 0.0f64;
        for c in 0..m {
            let lc: f64 = (0..m).map(|r| l[r] * s[r][c]).sum();
            residual = residual.max((lc - l[c]).abs());
        }
        let mut acc = [0.0; 3];
        let mut add = |x: usize, w: f64| {
            for k in 0..3 {
                acc[k] += w * self.positions[x][k];
            }
        };
        add(v, l[0]);
        for i in 0..ne {
            add(self.far_end(v, i), l[1 + i]);
        }
        for i in 0..nf {
            add(self.diagonal(v, i), l[1 + ne + i]);
        }
        (acc, residual)
    }
}

/// Lazily refined levels of a tagged mesh, for exact limit points at dyadic
/// parameters.
pub struct SharpRefiner {
    levels: Vec<Level>,
}

impl SharpRefiner {
    /// Starts from the base level of `m`.
    pub fn new(m: &TaggedMesh) -> Result<SharpRefiner, String> {
        Ok(SharpRefiner {
            levels: vec![Level::base(m)?],
        })
    }

    /// Level `k` (computed on first use).
    pub fn level(&mut self, k: usize) -> &Level {
        while self.levels.len() <= k {
            let next = self.levels.last().unwrap().refine();
            self.levels.push(next);
        }
        &self.levels[k]
    }

    /// Exact limit position of vertex `v` of level `k`: if `v` or its edges
    /// are still semi-sharp, the three rings around it are refined on their
    /// own (re-cut at every step, see [`Level::around`]) until they are not
    /// (at most 16 steps); vertex points keep their index. Panics if the
    /// eigen-residual exceeds 1e-13.
    pub fn exact_limit(&mut self, k: usize, v: u32) -> [f64; 3] {
        let l = self.level(k);
        let quads = |l: &Level, v: usize| {
            l.vert_faces[v]
                .iter()
                .all(|&f| l.faces[f as usize].len() == 4)
        };
        let finish = |l: &Level, v: usize| {
            let (p, r) = l.exact_limit(v);
            assert!(r < 1e-13, "eigen-residual {r} at vertex {v}");
            p
        };
        if quads(l, v as usize) && l.is_stationary(v as usize) {
            return finish(l, v as usize);
        }
        let (mut cur, mut i) = l.around(v as usize, 3);
        for _ in 0..16 {
            cur = cur.refine();
            if cur.is_stationary(i) && quads(&cur, i) {
                return finish(&cur, i);
            }
            let (next, j) = cur.around(i, 3);
            cur = next;
            i = j;
        }
        panic!("vertex {v} of level {k} not stationary after 16 local steps");
    }

    /// (level, vertex) at which the dyadic point `(i/2^k, j/2^k)` of base
    /// face `face` (sub-face `sub` of a non-quad) is a vertex.
    pub fn dyadic_vertex(
        &mut self,
        face: usize,
        sub: usize,
        i: u32,
        j: u32,
        k: u32,
    ) -> (usize, u32) {
        let n = self.level(0).faces[face].len();
        let (mut level, mut f) = if n == 4 {
            assert_eq!(sub, 0, "sub must be 0 on quad face {face}");
            (0usize, face)
        } else {
            assert!(sub < n);
            let off: usize = self.level(0).faces[..face].iter().map(|g| g.len()).sum();
            (1usize, off + sub)
        };
        let mut size: u64 = 1 << k;
        let (mut x, mut y) = (i as u64, j as u64);
        loop {
            let l = self.level(level);
            let corners = [(0, 0), (size, 0), (size, size), (0, size)];
            if let Some(c) = corners.iter().position(|&c| c == (x, y)) {
                return (level, l.faces[f][c]);
            }
            let half = size / 2;
            // Quadrant containing the point (ties go to the lower quadrant).
            let cx = u64::from(x > half);
            let cy = u64::from(y > half);
            let child = match (cx, cy) {
                (0, 0) => 0,
                (1, 0) => 1,
                (1, 1) => 2,
                _ => 3,
            };
            let off: usize = l.faces[..f].iter().map(|g| g.len()).sum();
            f = off + child;
            x -= cx * half;
            y -= cy * half;
            size = half;
            level += 1;
        }
    }

    /// Exact limit point at the dyadic parameter `(i/2^k, j/2^k)`.
    pub fn dyadic_limit_point(
        &mut self,
        face: usize,
        sub: usize,
        i: u32,
        j: u32,
        k: u32,
    ) -> [f64; 3] {
        let (level, v) = self.dyadic_vertex(face, sub, i, j, k);
        self.exact_limit(level, v)
    }
}
