//! Combinatorial statistics of a mesh, computed from the raw face lists so
//! that they are available even when the core rejects the mesh.

use crate::io::mesh_in::Mesh;
use std::collections::{BTreeMap, HashMap};

/// Counts and histograms of a polygon mesh.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    /// Vertices used by faces.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Edges with exactly one face.
    pub boundary_edges: usize,
    /// Edges with more than two faces.
    pub nonmanifold_edges: usize,
    /// Face size -> number of faces.
    pub face_sizes: BTreeMap<u32, usize>,
    /// Valence (number of edges) -> number of vertices.
    pub valences: BTreeMap<u32, usize>,
    /// Connected components (through edges).
    pub components: usize,
}

impl Stats {
    /// Computes the statistics of `mesh`.
    pub fn of(mesh: &Mesh) -> Stats {
        let nv = mesh.num_vertices();
        let mut s = Stats {
            vertices: nv,
            faces: mesh.num_faces(),
            ..Default::default()
        };
        let mut edge_use: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.indices.len());
        let mut start = 0usize;
        for &n in &mesh.face_sizes {
            *s.face_sizes.entry(n).or_default() += 1;
            let f = &mesh.indices[start..start + n as usize];
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                *edge_use.entry((a.min(b), a.max(b))).or_default() += 1;
            }
            start += n as usize;
        }
        s.edges = edge_use.len();
        let mut valence = vec![0u32; nv];
        let mut uf = UnionFind::new(nv);
        for (&(a, b), &c) in &edge_use {
            if c == 1 {
                s.boundary_edges += 1;
            } else if c > 2 {
                s.nonmanifold_edges += 1;
            }
            valence[a as usize] += 1;
            valence[b as usize] += 1;
            uf.union(a as usize, b as usize);
        }
        for &v in &valence {
            *s.valences.entry(v).or_default() += 1;
        }
        s.components = (0..nv).filter(|&v| uf.find(v) == v).count();
        s
    }

    /// Euler characteristic V - E + F.
    pub fn euler(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.faces as i64
    }

    /// Total genus of a closed orientable surface, `(2 c - chi) / 2`.
    pub fn genus(&self) -> i64 {
        (2 * self.components as i64 - self.euler()) / 2
    }
}

/// Union-find with path halving.
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind((0..n).collect())
    }
    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}
