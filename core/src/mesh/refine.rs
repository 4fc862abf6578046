//! One uniform Catmull-Clark step of a whole mesh into caller memory.
//!
//! Vertex numbering of the result: the `V` old vertices keep their index
//! (vertex points), then one edge point per edge in order of first appearance
//! when half-edges are scanned in order, then one face point per face.
//! Faces: for each old face `f` and corner `k`, the quad
//! `[vp(v_k), ep(v_k v_k+1), fp(f), ep(v_k-1 v_k)]`, which keeps orientation
//! and makes child `k` the corner-`k` quadrant of the parent's parameter
//! domain.

use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;
use crate::mesh::topology::{MeshInput, Topology};
use crate::mesh::weights::Weights;
use glam::DVec3;

/// Counts of the refined mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RefinedCounts {
    /// Vertices: V + E + F.
    pub vertices: usize,
    /// Faces (all quads): number of half-edges of the input.
    pub faces: usize,
}

/// Counts of one Catmull-Clark step of `t` (closed form).
pub fn refined_counts(t: &Topology) -> RefinedCounts {
    RefinedCounts {
        vertices: t.num_vertices() + t.num_edges() + t.num_faces(),
        faces: t.num_half_edges(),
    }
}

/// Bytes [`refine`] needs for the refined mesh arrays of `t` (positions,
/// face sizes, indices, plus an edge-numbering scratch), excluding the
/// refined mesh's own topology.
pub fn refine_bytes(t: &Topology) -> usize {
    layout(t).bytes()
}

fn layout(t: &Topology) -> Layout {
    let c = refined_counts(t);
    let mut l = Layout::default();
    l.f64s(3 * c.vertices);
    l.u32s(c.faces);
    l.u32s(4 * c.faces);
    l.u32s(t.num_half_edges());
    l
}

/// The refined mesh arrays (in caller memory) plus, per input half-edge, the
/// index of its edge point.
pub struct Refined<'a> {
    /// The refined mesh, ready for [`Topology::build`].
    pub mesh: MeshInput<'a>,
    /// Edge index (0-based, in first-appearance order) of each input half-edge.
    pub edge_of: &'a [u32],
}

/// One Catmull-Clark step of `t` with vertex rule `w`, into `mem`.
pub fn refine<'a>(t: &Topology, w: &Weights, mem: &'a mut [u64]) -> Result<Refined<'a>, Error> {
    let required = refine_bytes(t);
    if bytes_of(mem.len()) < required {
        return Err(Error::BufferTooSmall { required });
    }
    let c = refined_counts(t);
    let nv = t.num_vertices();
    let ne = t.num_edges();
    let nh = t.num_half_edges();
    let mut arena = Arena::new(mem);
    let pos = arena.f64s(3 * c.vertices);
    let sizes = arena.u32s(c.faces);
    let idx = arena.u32s(4 * c.faces);
    let edge_of = arena.u32s(nh);

    let mut next_edge = 0u32;
    for h in 0..nh {
        let tw = t.twin(h);
        if h < tw {
            edge_of[h] = next_edge;
            edge_of[tw] = next_edge;
            next_edge += 1;
        }
    }
    debug_assert_eq!(next_edge as usize, ne);
    let put = |pos: &mut [f64], i: usize, p: DVec3| {
        pos[3 * i] = p.x;
        pos[3 * i + 1] = p.y;
        pos[3 * i + 2] = p.z;
    };
    let get = |pos: &[f64], i: usize| DVec3::new(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    // Face points.
    let fbase = nv + ne;
    for f in 0..t.num_faces() {
        let vs = t.face_vertices(f);
        let mut s = DVec3::ZERO;
        for &v in vs {
            s += t.position(v as usize);
        }
        put(pos, fbase + f, s / vs.len() as f64);
    }
    // Edge points.
    for h in 0..nh {
        let tw = t.twin(h);
        if h < tw {
            let p = (t.position(t.origin(h))
                + t.position(t.origin(tw))
                + get(pos, fbase + t.face_of(h))
                + get(pos, fbase + t.face_of(tw)))
                * 0.25;
            put(pos, nv + edge_of[h] as usize, p);
        }
    }
    // Vertex points: V' = (a-g) V + (b-2g) avg(E) + 4g avg(F').
    for v in 0..nv {
        let n = t.valence(v);
        if n == 0 {
            put(pos, v, t.position(v));
            continue;
        }
        let (a, b, g) = w.get(n);
        let start = t.vertex_half_edge(v);
        let mut h = start;
        let mut se = DVec3::ZERO;
        let mut sf = DVec3::ZERO;
        loop {
            se += t.position(t.dest(h));
            sf += get(pos, fbase + t.face_of(h));
            h = t.rotate_ccw(h);
            if h == start {
                break;
            }
        }
        let nf = n as f64;
        let p = t.position(v) * (a - g) + se * ((b - 2.0 * g) / nf) + sf * (4.0 * g / nf);
        put(pos, v, p);
    }
    // Faces.
    let mut q = 0usize;
    for f in 0..t.num_faces() {
        let s = t.face_half_edge(f);
        let n = t.face_size(f);
        for k in 0..n {
            let h = s + k;
            let hp = s + (k + n - 1) % n;
            sizes[q] = 4;
            idx[4 * q] = t.origin(h) as u32;
            idx[4 * q + 1] = (nv + edge_of[h] as usize) as u32;
            idx[4 * q + 2] = (fbase + f) as u32;
            idx[4 * q + 3] = (nv + edge_of[hp] as usize) as u32;
            q += 1;
        }
    }
    Ok(Refined {
        mesh: MeshInput {
            positions: pos,
            face_sizes: sizes,
            indices: idx,
        },
        edge_of,
    })
}
