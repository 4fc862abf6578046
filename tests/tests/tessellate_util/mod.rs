//! Shared helpers of the `tessellate_*` tests: run a tessellation into
//! `Vec`s, load corpus shapes, and independent mesh checks.
#![allow(dead_code)]

use ccss_core::eval::Query;
use ccss_core::tessellate::{Counts, Options, Output, PolygonCell, Scratch, Stats, Tessellation};
use ccss_core::{Error, Evaluator, Topology};
use ccss_tests::harness::aligned;
use ccss_tests::reference::PolyMesh;
use std::collections::HashMap;
use std::path::Path;

/// Everything one tessellation emits.
pub struct Tess {
    pub counts: Counts,
    pub stats: Stats,
    pub pos: Vec<f64>,
    pub nrm: Vec<f64>,
    pub params: Vec<Query>,
    pub sizes: Vec<u32>,
    pub idx: Vec<u32>,
    pub tris: Vec<u32>,
    pub cells: Vec<PolygonCell>,
}

impl Tess {
    pub fn p(&self, v: u32) -> [f64; 3] {
        let i = 3 * v as usize;
        [self.pos[i], self.pos[i + 1], self.pos[i + 2]]
    }
    /// Polygons as index slices.
    pub fn polygons(&self) -> Vec<&[u32]> {
        let mut out = Vec::with_capacity(self.sizes.len());
        let mut o = 0usize;
        for &s in &self.sizes {
            out.push(&self.idx[o..o + s as usize]);
            o += s as usize;
        }
        out
    }
}

/// Tessellates with `opts` (single-threaded core path).
pub fn tessellate(topo: &Topology, ev: &Evaluator, opts: Options) -> Result<Tess, Error> {
    let mut scratch = Box::new(Scratch::ZERO);
    let need = Tessellation::required_bytes(topo, ev, &opts, &mut scratch)?;
    let mut mem = aligned(need);
    let mut t = Tessellation::build(topo, ev, opts, &mut mem)?;
    let c = t.counts();
    let mut r = Tess {
        counts: c,
        stats: t.stats(),
        pos: vec![0.0; 3 * c.vertices],
        nrm: vec![0.0; 3 * c.vertices],
        params: vec![Query::default(); c.vertices],
        sizes: vec![0; c.polygons],
        idx: vec![0; c.polygon_indices],
        tris: vec![0; 3 * c.triangles],
        cells: vec![PolygonCell::default(); c.polygons],
    };
    t.emit(Output {
        positions: &mut r.pos,
        normals: Some(&mut r.nrm),
        params: Some(&mut r.params),
        polygon_sizes: &mut r.sizes,
        polygon_indices: &mut r.idx,
        triangles: Some(&mut r.tris),
        cells: Some(&mut r.cells),
    })?;
    Ok(r)
}

pub fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/osd")
            .join(name),
    )
}

/// Checks that `faces` (vertex index lists) form a closed, consistently
/// oriented 2-manifold over `nv` vertices: every directed edge once, its
/// reverse once, every vertex used and its faces one fan; no face repeats a
/// vertex. Returns the number of undirected edges.
pub fn check_closed_manifold(what: &str, nv: usize, faces: &[&[u32]]) -> usize {
    let mut next: HashMap<(u32, u32), usize> = HashMap::new();
    let mut out_deg = vec![0usize; nv];
    for (fi, f) in faces.iter().enumerate() {
        assert!(f.len() >= 3, "{what}: face {fi} has {} vertices", f.len());
        let mut seen = f.to_vec();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(
            seen.len(),
            f.len(),
            "{what}: face {fi} repeats a vertex: {f:?}"
        );
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            assert!(
                (a as usize) < nv && (b as usize) < nv,
                "{what}: index out of range"
            );
            let prev = next.insert((a, b), fi);
            assert!(
                prev.is_none(),
                "{what}: directed edge {a}->{b} in faces {prev:?} and {fi}"
            );
            out_deg[a as usize] += 1;
        }
    }
    for &(a, b) in next.keys() {
        assert!(
            next.contains_key(&(b, a)),
            "{what}: edge {a}->{b} has no opposite (open or inconsistently oriented)"
        );
    }
    // One fan per vertex: rotate around v through (prev edge of the face) twins.
    let mut prev_in_face: HashMap<(u32, u32), u32> = HashMap::new(); // (v, w) -> u with u->v->w in a face
    for f in faces {
        for k in 0..f.len() {
            let u = f[(k + f.len() - 1) % f.len()];
            prev_in_face.insert((f[k], f[(k + 1) % f.len()]), u);
        }
    }
    let mut first_out: Vec<Option<u32>> = vec![None; nv];
    for &(a, b) in next.keys() {
        first_out[a as usize].get_or_insert(b);
    }
    for v in 0..nv {
        let Some(w0) = first_out[v] else {
            panic!("{what}: vertex {v} is not used");
        };
        let mut w = w0;
        let mut steps = 0;
        loop {
            let u = prev_in_face[&(v as u32, w)];
            w = u; // edge v->u is the next outgoing one
            steps += 1;
            if w == w0 || steps > out_deg[v] {
                break;
            }
        }
        assert_eq!(steps, out_deg[v], "{what}: vertex {v} is not a single fan");
    }
    next.len() / 2
}

/// Euler characteristic of a base mesh.
pub fn euler(m: &PolyMesh) -> i64 {
    let mut edges = std::collections::HashSet::new();
    for f in &m.faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    let used: std::collections::HashSet<u32> = m.faces.iter().flatten().copied().collect();
    used.len() as i64 - edges.len() as i64 + m.faces.len() as i64
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Distance from `p` to triangle (a, b, c) (`ccss_tests::shapes`).
pub fn point_triangle_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    ccss_tests::shapes::point_triangle(p, &[a, b, c])
}
