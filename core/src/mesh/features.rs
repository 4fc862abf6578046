//! Meshes with boundaries, creases, corners, holes and non-manifold parts:
//! adjacency in caller memory, OpenSubdiv's base-level sharpening, and one
//! uniform refinement step with the sharp rules of [`super::sharpness`]
//! \[OSD\], after which every face is a quad.
//!
//! [`FeatureMesh::build`] takes the polygon mesh, the tags and the options
//! and keeps, in one caller block ([`FeatureMesh::required_bytes`] is the
//! exact size):
//!
//! * level 0: the adjacency of the input (edges, edge faces, vertex edges
//!   and faces, all as compressed lists), the sharpness after Far's
//!   sharpening (boundary and non-manifold edges infinitely sharp; in
//!   edge-and-corner mode a vertex with one face and two edges infinitely
//!   sharp; non-manifold vertices infinitely sharp unless on a pair of
//!   interior non-manifold edges; in mode `none`, faces at boundary vertices
//!   with an un-sharpened boundary edge become holes);
//! * level 1: the refined control points, quads and their adjacency and
//!   sharpness. Child `k` of base face `f` is level-1 face
//!   `offset(f) + k` (`offset` = sum of the sizes of the faces before `f`);
//!   a quad's child `k` keeps the parent's orientation (its corner `k` is
//!   the vertex point), a non-quad's child `k` is `[vertex point, next edge
//!   point, face point, previous edge point]`, as in OpenSubdiv.
//!
//! Faces that use a vertex twice are refused ([`Error::RepeatedVertex`]);
//! OpenSubdiv accepts them as degenerate non-manifold edges.
//!
//! Layer 3 (with the rest of `mesh/`): imports `error`, `mem` and the
//! sibling `sharpness`.

use super::sharpness::{
    decay_at, decrement, edge_mask, is_infinite, vertex_mask, Around, Boundary, Creasing, EndStats,
    FeatureOptions, INFINITE,
};
use super::MeshInput;
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;

/// Tags of a mesh: creases (edge sharpness), corners (vertex sharpness) and
/// holes, with the scheme options. Sharpness values are OpenSubdiv's: 0
/// smooth, 10 or more infinitely sharp, in between semi-sharp (decaying by
/// about one per level).
#[derive(Clone, Copy, Debug, Default)]
pub struct FeatureInput<'a> {
    /// Vertex pairs `a0 b0 a1 b1 ...`, one pair per sharp edge.
    pub crease_vertices: &'a [u32],
    /// Sharpness per pair.
    pub crease_sharpness: &'a [f32],
    /// Sharp vertices.
    pub corner_vertices: &'a [u32],
    /// Sharpness per sharp vertex.
    pub corner_sharpness: &'a [f32],
    /// Faces that are holes: no surface, but they shape their neighbours.
    pub holes: &'a [u32],
    /// Boundary mode, creasing method, triangle rule.
    pub options: FeatureOptions,
}

/// Compressed adjacency of a polygon mesh (all slices in caller memory).
/// Edges are numbered in increasing order of `(min, max)` vertex pair, so
/// [`Adjacency::find_edge`] is a binary search.
#[derive(Clone, Copy, Debug)]
pub struct Adjacency<'a> {
    /// Face `f`'s corners are `face_vert[face_off[f]..face_off[f + 1]]`.
    pub face_off: &'a [u32],
    /// Corner vertices of all faces.
    pub face_vert: &'a [u32],
    /// Per corner, the edge from it to the next corner of its face.
    pub face_edge: &'a [u32],
    /// Edge `e` joins `edge_vert[2e]` and `edge_vert[2e + 1]`, in the
    /// direction of the first face that uses it.
    pub edge_vert: &'a [u32],
    /// Faces of edge `e`: `edge_face[edge_face_off[e]..edge_face_off[e + 1]]`.
    pub edge_face_off: &'a [u32],
    /// See `edge_face_off`.
    pub edge_face: &'a [u32],
    /// Edges of vertex `v`: `vert_edge[vert_edge_off[v]..vert_edge_off[v + 1]]`.
    pub vert_edge_off: &'a [u32],
    /// See `vert_edge_off`.
    pub vert_edge: &'a [u32],
    /// Faces of vertex `v`: `vert_face[vert_face_off[v]..vert_face_off[v + 1]]`.
    pub vert_face_off: &'a [u32],
    /// See `vert_face_off`.
    pub vert_face: &'a [u32],
}

fn key(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

fn range(off: &[u32], i: usize) -> core::ops::Range<usize> {
    off[i] as usize..off[i + 1] as usize
}

impl<'a> Adjacency<'a> {
    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.vert_edge_off.len() - 1
    }
    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_off.len() - 1
    }
    /// Number of edges.
    pub fn num_edges(&self) -> usize {
        self.edge_face_off.len() - 1
    }
    /// Corners of face `f`.
    pub fn face(&self, f: usize) -> &'a [u32] {
        &self.face_vert[range(self.face_off, f)]
    }
    /// Edges of face `f` (`k`-th from corner `k` to `k + 1`).
    pub fn face_edges(&self, f: usize) -> &'a [u32] {
        &self.face_edge[range(self.face_off, f)]
    }
    /// Faces of edge `e`.
    pub fn edge_faces(&self, e: usize) -> &'a [u32] {
        &self.edge_face[range(self.edge_face_off, e)]
    }
    /// Edges of vertex `v`.
    pub fn vertex_edges(&self, v: usize) -> &'a [u32] {
        &self.vert_edge[range(self.vert_edge_off, v)]
    }
    /// Faces of vertex `v`.
    pub fn vertex_faces(&self, v: usize) -> &'a [u32] {
        &self.vert_face[range(self.vert_face_off, v)]
    }
    /// The end of edge `e` that is not `v`.
    pub fn far_end(&self, e: usize, v: u32) -> u32 {
        let (a, b) = (self.edge_vert[2 * e], self.edge_vert[2 * e + 1]);
        if a == v {
            b
        } else {
            a
        }
    }
    /// The edge joining `a` and `b`, if any.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<usize> {
        let k = key(a, b);
        let (mut lo, mut hi) = (0usize, self.num_edges());
        while lo < hi {
            let mid = (lo + hi) / 2;
            let km = key(self.edge_vert[2 * mid], self.edge_vert[2 * mid + 1]);
            if km < k {
                lo = mid + 1;
            } else if km > k {
                hi = mid;
            } else {
                return Some(mid);
            }
        }
        None
    }

    /// Memory requests of [`Adjacency::build`] for `nv` vertices, `nf`
    /// faces, `nc` corners and at most `ne_cap` edges.
    fn layout(l: &mut Layout, nv: usize, nc: usize, ne_cap: usize) {
        l.u32s(nc); // face_edge
        l.u32s(2 * ne_cap); // edge_vert
        l.u32s(ne_cap + 1); // edge_face_off
        l.u32s(nc); // edge_face
        l.u32s(nv + 1); // vert_edge_off
        l.u32s(2 * ne_cap); // vert_edge
        l.u32s(nv + 1); // vert_face_off
        l.u32s(nc); // vert_face
    }

    /// Sorted distinct edge keys of the faces into `scratch` (`nc` words);
    /// returns their count.
    fn edge_keys(face_off: &[u32], face_vert: &[u32], scratch: &mut [u64]) -> usize {
        let nf = face_off.len() - 1;
        let nc = face_vert.len();
        for f in 0..nf {
            let fv = &face_vert[range(face_off, f)];
            for k in 0..fv.len() {
                scratch[face_off[f] as usize + k] = key(fv[k], fv[(k + 1) % fv.len()]);
            }
        }
        scratch[..nc].sort_unstable();
        let mut distinct = 0;
        for i in 0..nc {
            if i == 0 || scratch[i] != scratch[distinct - 1] {
                scratch[distinct] = scratch[i];
                distinct += 1;
            }
        }
        distinct
    }

    /// Builds the adjacency of the faces `face_off` / `face_vert` (already
    /// in the arena) over `nv` vertices; `scratch` holds `nc` words and
    /// `ne_cap` bounds the number of edges (the arena reserves that many).
    fn build(
        arena: &mut Arena<'a>,
        nv: usize,
        face_off: &'a [u32],
        face_vert: &'a [u32],
        ne_cap: usize,
        scratch: &mut [u64],
    ) -> Adjacency<'a> {
        let nf = face_off.len() - 1;
        let nc = face_vert.len();
        let ne = Self::edge_keys(face_off, face_vert, scratch);
        let keys = &scratch[..ne];
        let face_edge = arena.u32s(nc);
        let edge_vert = &mut arena.u32s(2 * ne_cap)[..2 * ne];
        let edge_face_off = &mut arena.u32s(ne_cap + 1)[..ne + 1];
        for f in 0..nf {
            let fv = &face_vert[range(face_off, f)];
            for k in 0..fv.len() {
                let (a, b) = (fv[k], fv[(k + 1) % fv.len()]);
                // Every corner's key is among the distinct keys.
                let e = keys.binary_search(&key(a, b)).unwrap_or(0);
                face_edge[face_off[f] as usize + k] = e as u32;
                if edge_face_off[e + 1] == 0 {
                    edge_vert[2 * e] = a;
                    edge_vert[2 * e + 1] = b;
                }
                edge_face_off[e + 1] += 1;
            }
        }
        for e in 0..ne {
            edge_face_off[e + 1] += edge_face_off[e];
        }
        let edge_face = arena.u32s(nc);
        let vert_edge_off = arena.u32s(nv + 1);
        let vert_edge = &mut arena.u32s(2 * ne_cap)[..2 * ne];
        let vert_face_off = arena.u32s(nv + 1);
        let vert_face = arena.u32s(nc);
        edge_face.fill(u32::MAX);
        vert_edge.fill(u32::MAX);
        vert_face.fill(u32::MAX);
        // Appends x to list i of a compressed list whose unused slots hold
        // u32::MAX (each list is filled in order, so a scan finds the end).
        fn put(list: &mut [u32], off: &[u32], i: usize, x: u32) {
            for s in off[i] as usize..off[i + 1] as usize {
                if list[s] == u32::MAX {
                    list[s] = x;
                    return;
                }
            }
        }
        for f in 0..nf {
            for &e in &face_edge[range(face_off, f)] {
                put(edge_face, edge_face_off, e as usize, f as u32);
            }
        }
        for e in 0..ne {
            vert_edge_off[edge_vert[2 * e] as usize + 1] += 1;
            vert_edge_off[edge_vert[2 * e + 1] as usize + 1] += 1;
        }
        for f in 0..nf {
            for &v in &face_vert[range(face_off, f)] {
                vert_face_off[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            vert_edge_off[v + 1] += vert_edge_off[v];
            vert_face_off[v + 1] += vert_face_off[v];
        }
        for e in 0..ne {
            put(
                vert_edge,
                vert_edge_off,
                edge_vert[2 * e] as usize,
                e as u32,
            );
            put(
                vert_edge,
                vert_edge_off,
                edge_vert[2 * e + 1] as usize,
                e as u32,
            );
        }
        for f in 0..nf {
            for &v in &face_vert[range(face_off, f)] {
                put(vert_face, vert_face_off, v as usize, f as u32);
            }
        }
        Adjacency {
            face_off,
            face_vert,
            face_edge,
            edge_vert,
            edge_face_off,
            edge_face,
            vert_edge_off,
            vert_edge,
            vert_face_off,
            vert_face,
        }
    }

    /// True when edge `e` has more than two faces, or two faces that run
    /// along it in the same direction.
    pub fn edge_nonmanifold(&self, e: usize) -> bool {
        let fs = self.edge_faces(e);
        if fs.len() > 2 {
            return true;
        }
        if fs.len() == 2 {
            let from = |f: u32| {
                let f = f as usize;
                let k = self
                    .face_edges(f)
                    .iter()
                    .position(|&x| x as usize == e)
                    .unwrap_or(0);
                self.face(f)[k]
            };
            return from(fs[0]) == from(fs[1]);
        }
        false
    }

    /// True when vertex `v` is non-manifold: a non-manifold incident edge,
    /// other than zero or two boundary edges, or faces that do not form one
    /// fan (walked through the edges at `v`).
    pub fn vertex_nonmanifold(&self, v: usize) -> bool {
        let es = self.vertex_edges(v);
        let fs = self.vertex_faces(v);
        if es.iter().any(|&e| self.edge_nonmanifold(e as usize)) {
            return true;
        }
        let boundary = es
            .iter()
            .filter(|&&e| self.edge_faces(e as usize).len() == 1)
            .count();
        if !(boundary == 0 || boundary == 2) {
            return true;
        }
        if fs.is_empty() {
            return false;
        }
        let step = |f: usize, forward: bool| -> Option<usize> {
            let fv = self.face(f);
            let n = fv.len();
            let k = fv.iter().position(|&x| x as usize == v)?;
            let e = if forward {
                self.face_edges(f)[k]
            } else {
                self.face_edges(f)[(k + n - 1) % n]
            } as usize;
            self.edge_faces(e)
                .iter()
                .find(|&&g| g as usize != f)
                .map(|&g| g as usize)
        };
        let start = fs[0] as usize;
        let mut count = 1;
        let mut f = start;
        let mut closed = false;
        for _ in 0..fs.len() {
            match step(f, true) {
                Some(g) if g == start => {
                    closed = true;
                    break;
                }
                Some(g) => {
                    f = g;
                    count += 1;
                }
                None => break,
            }
        }
        if !closed {
            f = start;
            for _ in 0..fs.len() {
                match step(f, false) {
                    Some(g) if g != start => {
                        f = g;
                        count += 1;
                    }
                    _ => break,
                }
            }
        }
        count != fs.len()
    }
}

/// Edge and vertex sharpness of one level (`f32` values held in `f64`).
#[derive(Clone, Copy, Debug)]
pub struct Sharpness<'a> {
    /// Per edge.
    pub edge: &'a [f64],
    /// Per vertex.
    pub vertex: &'a [f64],
}

impl Sharpness<'_> {
    /// Sharpness of edge `e`.
    #[inline]
    pub fn edge(&self, e: usize) -> f32 {
        self.edge[e] as f32
    }
    /// Sharpness of vertex `v`.
    #[inline]
    pub fn vertex(&self, v: usize) -> f32 {
        self.vertex[v] as f32
    }
    /// Semi-sharp statistics of the edges at `v`.
    pub fn end_stats(&self, adj: &Adjacency, v: usize) -> EndStats {
        EndStats::of(adj.vertex_edges(v).iter().map(|&e| self.edge(e as usize)))
    }
}

/// A mesh with features, refined once: see the module documentation.
#[derive(Clone, Copy, Debug)]
pub struct FeatureMesh<'a> {
    /// Options it was built with.
    pub options: FeatureOptions,
    /// Level-0 adjacency.
    pub base: Adjacency<'a>,
    /// Level-0 sharpness after the base sharpening.
    pub base_sharpness: Sharpness<'a>,
    /// Level-1 adjacency (all quads).
    pub level1: Adjacency<'a>,
    /// Level-1 sharpness.
    pub sharpness: Sharpness<'a>,
    /// Level-1 control points, `x y z` per vertex.
    pub points: &'a [f64],
    /// Per level-1 face: 1 for a hole.
    pub hole: &'a [u32],
}

/// Sharpness around one vertex of a level, for the masks.
struct AroundVertex<'m, 'a> {
    adj: &'m Adjacency<'a>,
    sharp: &'m Sharpness<'a>,
    v: usize,
    creasing: Creasing,
    stats: EndStats,
}

impl Around for AroundVertex<'_, '_> {
    fn edges(&self) -> usize {
        self.adj.vertex_edges(self.v).len()
    }
    fn faces(&self) -> usize {
        self.adj.vertex_faces(self.v).len()
    }
    fn sharpness(&self, i: usize) -> f32 {
        self.sharp.edge(self.adj.vertex_edges(self.v)[i] as usize)
    }
    fn child_sharpness(&self, i: usize) -> f32 {
        decay_at(self.creasing, self.sharpness(i), self.stats)
    }
}

impl<'a> FeatureMesh<'a> {
    /// Exact bytes [`FeatureMesh::build`] uses for this mesh (validated
    /// first, with the errors `build` would give for its faces).
    pub fn required_bytes(mesh: &MeshInput) -> Result<usize, Error> {
        let (nv, nf, nc) = check_mesh(mesh)?;
        Ok(layout(nv, nf, nc).bytes())
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.base.num_faces()
    }

    /// Level-1 face of sub-face `k` of base face `f` (for a quad, its child
    /// at corner `k`).
    pub fn child_face(&self, f: usize, k: usize) -> usize {
        self.base.face_off[f] as usize + k
    }

    /// Level-1 control point `v`.
    pub fn point(&self, v: usize) -> glam::DVec3 {
        glam::DVec3::new(
            self.points[3 * v],
            self.points[3 * v + 1],
            self.points[3 * v + 2],
        )
    }

    /// Builds the mesh in `mem` (see [`FeatureMesh::required_bytes`]).
    /// Errors name the face, vertex or edge: bad indices, repeated vertices,
    /// non-finite coordinates, tags on missing edges/vertices/faces, NaN or
    /// negative sharpness.
    pub fn build(
        mesh: &MeshInput,
        features: &FeatureInput,
        mem: &'a mut [u64],
    ) -> Result<FeatureMesh<'a>, Error> {
        let (nv, nf, nc) = check_mesh(mesh)?;
        let need = layout(nv, nf, nc).bytes();
        if bytes_of(mem.len()) < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        if features.crease_vertices.len() != 2 * features.crease_sharpness.len() {
            return Err(Error::InvalidArgument(
                "crease_vertices must hold two vertices per crease_sharpness value",
            ));
        }
        if features.corner_vertices.len() != features.corner_sharpness.len() {
            return Err(Error::InvalidArgument(
                "corner_vertices and corner_sharpness differ in length",
            ));
        }
        let opts = features.options;
        let mut arena = Arena::new(mem);
        // Level 0.
        let face_off0 = arena.u32s(nf + 1);
        for (f, &s) in mesh.face_sizes.iter().enumerate() {
            face_off0[f + 1] = face_off0[f] + s;
        }
        let face_vert0 = arena.u32s(nc);
        face_vert0.copy_from_slice(mesh.indices);
        let scratch = arena.words(32 * nc);
        let base = Adjacency::build(&mut arena, nv, face_off0, face_vert0, nc, scratch);
        let ne0 = base.num_edges();
        let esharp0 = &mut arena.f64s(nc)[..ne0];
        let vsharp0 = arena.f64s(nv);
        let hole0 = arena.u32s(nf);
        for (i, &s) in features.crease_sharpness.iter().enumerate() {
            let (a, b) = (
                features.crease_vertices[2 * i],
                features.crease_vertices[2 * i + 1],
            );
            let e = base
                .find_edge(a, b)
                .ok_or(Error::NotAnEdge { v0: a, v1: b })?;
            if s.is_nan() || s < 0.0 {
                return Err(Error::InvalidSharpness { v0: a, v1: b });
            }
            esharp0[e] = s as f64;
        }
        for (i, &s) in features.corner_sharpness.iter().enumerate() {
            let v = features.corner_vertices[i];
            if v as usize >= nv {
                return Err(Error::VertexOutOfRange { vertex: v });
            }
            if s.is_nan() || s < 0.0 {
                return Err(Error::InvalidSharpness { v0: v, v1: v });
            }
            vsharp0[v as usize] = s as f64;
        }
        for &f in features.holes {
            if f as usize >= nf {
                return Err(Error::FaceOutOfRange { face: f });
            }
            hole0[f as usize] = 1;
        }
        sharpen_base(&base, esharp0, vsharp0, hole0, opts.boundary);
        let base_sharpness = Sharpness {
            edge: esharp0,
            vertex: vsharp0,
        };
        // Level-1 faces, OpenSubdiv's child order and orientation.
        let (nv1, nf1, nc1) = (nv + nf + ne0, nc, 4 * nc);
        let face_off1 = arena.u32s(nf1 + 1);
        let face_vert1 = arena.u32s(nc1);
        let fv_of = |f: usize| (nv + f) as u32;
        let ev_of = |e: u32| (nv + nf) as u32 + e;
        for f in 0..nf {
            let fv = base.face(f);
            let fe = base.face_edges(f);
            let n = fv.len();
            for j in 0..n {
                let c = base.face_off[f] as usize + j;
                face_off1[c + 1] = 4 * (c as u32 + 1);
                let q = &mut face_vert1[4 * c..4 * c + 4];
                let (vv, en, fc, ep) = (fv[j], ev_of(fe[j]), fv_of(f), ev_of(fe[(j + n - 1) % n]));
                let r = if n == 4 { j } else { 0 };
                q[r] = vv;
                q[(r + 1) % 4] = en;
                q[(r + 2) % 4] = fc;
                q[(r + 3) % 4] = ep;
            }
        }
        let ne1_cap = 3 * nc;
        let nv1_cap = nv + nf + nc;
        let level1 = Adjacency::build(&mut arena, nv1, face_off1, face_vert1, ne1_cap, scratch);
        let esharp1 = &mut arena.f64s(ne1_cap)[..level1.num_edges()];
        let vsharp1 = &mut arena.f64s(nv1_cap)[..nv1];
        let hole1 = arena.u32s(nf1);
        let points = &mut arena.f64s(3 * nv1_cap)[..3 * nv1];
        for f in 0..nf {
            for c in range(base.face_off, f) {
                hole1[c] = hole0[f];
            }
        }
        for v in 0..nv {
            vsharp1[v] = decrement(base_sharpness.vertex(v)) as f64;
        }
        for e in 0..level1.num_edges() {
            let (a, b) = (level1.edge_vert[2 * e], level1.edge_vert[2 * e + 1]);
            let (lo, hi) = (a.min(b) as usize, a.max(b) as usize);
            if lo < nv {
                // Half of base edge `hi - nv - nf` at its end `lo`.
                let pe = hi - nv - nf;
                let stats = base_sharpness.end_stats(&base, lo);
                esharp1[e] = decay_at(opts.creasing, base_sharpness.edge(pe), stats) as f64;
            }
        }
        // Control points: face points, edge points, vertex points.
        let p0 = |v: usize| glam::DVec3::from_slice(&mesh.positions[3 * v..3 * v + 3]);
        let mut set = |i: usize, p: glam::DVec3| {
            points[3 * i] = p.x;
            points[3 * i + 1] = p.y;
            points[3 * i + 2] = p.z;
        };
        let centroid = |f: usize| {
            let fv = base.face(f);
            let mut c = glam::DVec3::ZERO;
            for &v in fv {
                c += p0(v as usize);
            }
            c / fv.len() as f64
        };
        for f in 0..nf {
            set(nv + f, centroid(f));
        }
        for e in 0..ne0 {
            let (a, b) = (base.edge_vert[2 * e], base.edge_vert[2 * e + 1]);
            let s = base_sharpness.edge(e);
            let half = |x: u32| {
                decay_at(
                    opts.creasing,
                    s,
                    base_sharpness.end_stats(&base, x as usize),
                )
            };
            let fs = base.edge_faces(e);
            let tri = |k: usize| fs.get(k).is_some_and(|&f| base.face(f as usize).len() == 3);
            let m = edge_mask(&opts, s, [half(a), half(b)], fs.len(), [tri(0), tri(1)]);
            let mut p = (p0(a as usize) + p0(b as usize)) * m.end;
            for (k, &f) in fs.iter().enumerate() {
                p += centroid(f as usize) * m.face[k.min(1)];
            }
            set(nv + nf + e, p);
        }
        for v in 0..nv {
            let around = AroundVertex {
                adj: &base,
                sharp: &base_sharpness,
                v,
                creasing: opts.creasing,
                stats: base_sharpness.end_stats(&base, v),
            };
            let m = vertex_mask(opts.creasing, base_sharpness.vertex(v), &around);
            let mut p = p0(v) * m.vertex;
            for (i, &e) in base.vertex_edges(v).iter().enumerate() {
                p += p0(base.far_end(e as usize, v as u32) as usize) * m.edge_weight(i);
            }
            if m.each_face != 0.0 {
                for &f in base.vertex_faces(v) {
                    p += centroid(f as usize) * m.each_face;
                }
            }
            set(v, p);
        }
        Ok(FeatureMesh {
            options: opts,
            base,
            base_sharpness,
            level1,
            sharpness: Sharpness {
                edge: esharp1,
                vertex: vsharp1,
            },
            points,
            hole: hole1,
        })
    }
}

/// Far's base-level sharpening (see the module documentation).
fn sharpen_base(
    adj: &Adjacency,
    edge: &mut [f64],
    vertex: &mut [f64],
    hole: &mut [u32],
    boundary: Boundary,
) {
    let nv = adj.num_vertices();
    if boundary == Boundary::None {
        for v in 0..nv {
            let es = adj.vertex_edges(v);
            if es.len() == adj.vertex_faces(v).len() && !adj.vertex_nonmanifold(v) {
                continue;
            }
            let exclude = es.iter().any(|&e| {
                adj.edge_faces(e as usize).len() == 1 && !is_infinite(edge[e as usize] as f32)
            });
            if exclude {
                for &f in adj.vertex_faces(v) {
                    hole[f as usize] = 1;
                }
            }
        }
    }
    // Vertex tags read the edge tags of the input, before sharpening.
    for v in 0..nv {
        let es = adj.vertex_edges(v);
        let nf = adj.vertex_faces(v).len();
        let boundary_edges = es
            .iter()
            .filter(|&&e| adj.edge_faces(e as usize).len() < 2)
            .count();
        let nm_edges = es
            .iter()
            .filter(|&&e| adj.edge_nonmanifold(e as usize))
            .count();
        let topological_corner = nf == 1 && es.len() == 2;
        let sharpened_corner = topological_corner && boundary == Boundary::EdgeAndCorner;
        let fin_crease = nm_edges == 2 && boundary_edges == 0 && nf > es.len();
        if sharpened_corner || (adj.vertex_nonmanifold(v) && !fin_crease) {
            vertex[v] = INFINITE as f64;
        }
    }
    for e in 0..adj.num_edges() {
        if adj.edge_faces(e).len() < 2 || adj.edge_nonmanifold(e) {
            edge[e] = INFINITE as f64;
        }
    }
}

fn check_mesh(mesh: &MeshInput) -> Result<(usize, usize, usize), Error> {
    if !mesh.positions.len().is_multiple_of(3) {
        return Err(Error::InvalidArgument(
            "positions length is not a multiple of 3",
        ));
    }
    let nv = mesh.positions.len() / 3;
    let nf = mesh.face_sizes.len();
    if nv == 0 || nf == 0 {
        return Err(Error::EmptyMesh);
    }
    let mut nc = 0usize;
    for (f, &s) in mesh.face_sizes.iter().enumerate() {
        if s < 3 {
            return Err(Error::FaceTooSmall {
                face: f as u32,
                size: s,
            });
        }
        nc = nc.saturating_add(s as usize);
    }
    if nc != mesh.indices.len() {
        return Err(Error::IndexCountMismatch {
            expected: nc,
            got: mesh.indices.len(),
        });
    }
    if nc > (u32::MAX / 8) as usize || nv > (u32::MAX / 8) as usize {
        return Err(Error::InvalidArgument("mesh too large for 32-bit indices"));
    }
    let mut start = 0usize;
    for (f, &s) in mesh.face_sizes.iter().enumerate() {
        let fv = &mesh.indices[start..start + s as usize];
        for (k, &v) in fv.iter().enumerate() {
            if v as usize >= nv {
                return Err(Error::IndexOutOfRange {
                    face: f as u32,
                    vertex: v,
                });
            }
            if fv[..k].contains(&v) {
                return Err(Error::RepeatedVertex {
                    face: f as u32,
                    vertex: v,
                });
            }
        }
        start += s as usize;
    }
    for v in 0..nv {
        if !mesh.positions[3 * v..3 * v + 3]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(Error::NonFiniteCoordinate { vertex: v as u32 });
        }
    }
    Ok((nv, nf, nc))
}

/// The arena requests of [`FeatureMesh::build`], in its order, with the
/// edge counts at their upper bounds (`ne0 <= nc`, `ne1 <= 3 nc`).
fn layout(nv: usize, nf: usize, nc: usize) -> Layout {
    let mut l = Layout::default();
    l.u32s(nf + 1);
    l.u32s(nc);
    l.f64s(4 * nc); // sort scratch (words), used by both levels
    Adjacency::layout(&mut l, nv, nc, nc);
    l.f64s(nc);
    l.f64s(nv);
    l.u32s(nf);
    let (nf1, nc1, ne1_cap, nv1_cap) = (nc, 4 * nc, 3 * nc, nv + nf + nc);
    l.u32s(nf1 + 1);
    l.u32s(nc1);
    // The level-1 vertex count is exact only once the edges are known;
    // its lists are sized by the cap (unused tails stay zero).
    Adjacency::layout(&mut l, nv1_cap, nc1, ne1_cap);
    l.f64s(ne1_cap);
    l.f64s(nv1_cap);
    l.u32s(nf1);
    l.f64s(3 * nv1_cap);
    l
}
