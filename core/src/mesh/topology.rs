//! Half-edge topology of a closed 2-manifold polygon mesh, built into caller
//! memory, with validation that names the offending element.
//!
//! Half-edge `h` of face `f` at corner `k` is stored at index
//! `face_start[f] + k` and runs from `indices[h]` to the face's next vertex;
//! so the caller's index array doubles as the half-edge origin array.

use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;
use glam::DVec3;

/// An indexed polygon mesh in caller buffers.
#[derive(Clone, Copy, Debug)]
pub struct MeshInput<'a> {
    /// `3 * num_vertices` coordinates, x y z per vertex.
    pub positions: &'a [f64],
    /// Number of vertices of each face (3 or more).
    pub face_sizes: &'a [u32],
    /// Vertex indices of all faces, concatenated in face order,
    /// counter-clockwise seen from outside.
    pub indices: &'a [u32],
}

/// Validated half-edge topology (borrows the input and caller memory).
#[derive(Clone, Copy, Debug)]
pub struct Topology<'a> {
    positions: &'a [f64],
    face_sizes: &'a [u32],
    indices: &'a [u32],
    face_start: &'a [u32],
    he_face: &'a [u32],
    twin: &'a [u32],
    vert_he: &'a [u32],
    valence: &'a [u32],
}

fn total_indices(face_sizes: &[u32]) -> usize {
    face_sizes.iter().map(|&s| s as usize).sum()
}

impl<'a> Topology<'a> {
    /// Bytes of caller memory [`Topology::build`] needs for a mesh with
    /// `num_vertices` vertices and these face sizes (closed form:
    /// `8*ceil((F+1)/2) + 3*8*ceil(H/2) + 2*8*ceil(V/2)` with H = sum of sizes).
    pub fn required_bytes(num_vertices: usize, face_sizes: &[u32]) -> usize {
        Self::layout(num_vertices, face_sizes.len(), total_indices(face_sizes)).bytes()
    }

    pub(crate) fn layout(nv: usize, nf: usize, nh: usize) -> Layout {
        let mut l = Layout::default();
        l.u32s(nf + 1); // face_start
        l.u32s(nh); // he_face
        l.u32s(nh); // twin
        l.u32s(nh); // sort scratch / kept for reuse
        l.u32s(nv); // vert_he
        l.u32s(nv); // valence
        l
    }

    /// Validates `mesh` and builds its topology into `mem`.
    ///
    /// Errors: see [`Error`]; a too-small `mem` gives
    /// [`Error::BufferTooSmall`] with the byte count required.
    pub fn build(mesh: MeshInput<'a>, mem: &'a mut [u64]) -> Result<Self, Error> {
        let nv = mesh.positions.len() / 3;
        let nf = mesh.face_sizes.len();
        if nv == 0 || nf == 0 {
            return Err(Error::EmptyMesh);
        }
        if !mesh.positions.len().is_multiple_of(3) {
            return Err(Error::InvalidArgument(
                "positions length is not a multiple of 3",
            ));
        }
        if nv > u32::MAX as usize / 2 {
            return Err(Error::InvalidArgument("too many vertices"));
        }
        // Face sizes first (so that the index count is meaningful).
        let mut nh: usize = 0;
        for (f, &s) in mesh.face_sizes.iter().enumerate() {
            if s < 3 {
                return Err(Error::FaceTooSmall {
                    face: f as u32,
                    size: s,
                });
            }
            if s as usize > MAX_VALENCE {
                return Err(Error::FaceTooLarge {
                    face: f as u32,
                    size: s,
                });
            }
            nh += s as usize;
        }
        if nh != mesh.indices.len() {
            return Err(Error::IndexCountMismatch {
                expected: nh,
                got: mesh.indices.len(),
            });
        }
        if nh >= u32::MAX as usize / 16 {
            return Err(Error::InvalidArgument("mesh too large"));
        }
        for v in 0..nv {
            let p = &mesh.positions[3 * v..3 * v + 3];
            if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
                return Err(Error::NonFiniteCoordinate { vertex: v as u32 });
            }
        }
        let required = Self::layout(nv, nf, nh).bytes();
        if bytes_of(mem.len()) < required {
            return Err(Error::BufferTooSmall { required });
        }
        let mut arena = Arena::new(mem);
        let face_start = arena.u32s(nf + 1);
        let he_face = arena.u32s(nh);
        let twin = arena.u32s(nh);
        let order = arena.u32s(nh);
        let vert_he = arena.u32s(nv);
        let valence = arena.u32s(nv);

        let mut h = 0u32;
        for (f, &s) in mesh.face_sizes.iter().enumerate() {
            face_start[f] = h;
            let idx = &mesh.indices[h as usize..(h + s) as usize];
            for (k, &v) in idx.iter().enumerate() {
                if v as usize >= nv {
                    return Err(Error::IndexOutOfRange {
                        face: f as u32,
                        vertex: v,
                    });
                }
                if idx[..k].contains(&v) {
                    return Err(Error::RepeatedVertex {
                        face: f as u32,
                        vertex: v,
                    });
                }
                he_face[(h as usize) + k] = f as u32;
            }
            h += s;
        }
        face_start[nf] = h;

        // Pair half-edges: sort by undirected edge key.
        let dest = |h: usize| -> u32 {
            let f = he_face[h] as usize;
            let s = face_start[f] as usize;
            let n = face_start[f + 1] as usize - s;
            mesh.indices[s + (h - s + 1) % n]
        };
        for (i, o) in order.iter_mut().enumerate() {
            *o = i as u32;
        }
        let key = |h: u32| -> u64 {
            let a = mesh.indices[h as usize];
            let b = dest(h as usize);
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            ((lo as u64) << 32) | hi as u64
        };
        order.sort_unstable_by_key(|&h| (key(h), h));
        let mut i = 0;
        while i < nh {
            let k0 = key(order[i]);
            let mut j = i + 1;
            while j < nh && key(order[j]) == k0 {
                j += 1;
            }
            let (h0, a, b) = {
                let h0 = order[i] as usize;
                (h0, mesh.indices[h0], dest(h0))
            };
            match j - i {
                1 => return Err(Error::BoundaryEdge { v0: a, v1: b }),
                2 => {
                    let h1 = order[i + 1] as usize;
                    if mesh.indices[h1] == a {
                        return Err(Error::InconsistentOrientation { v0: a, v1: b });
                    }
                    twin[h0] = h1 as u32;
                    twin[h1] = h0 as u32;
                }
                _ => return Err(Error::NonManifoldEdge { v0: a, v1: b }),
            }
            i = j;
        }

        // Outgoing half-edge and valence per vertex.
        vert_he.fill(u32::MAX);
        for hh in 0..nh {
            let v = mesh.indices[hh] as usize;
            valence[v] += 1;
            vert_he[v] = hh as u32;
        }
        let prev = |h: usize| -> usize {
            let f = he_face[h] as usize;
            let s = face_start[f] as usize;
            let n = face_start[f + 1] as usize - s;
            s + (h - s + n - 1) % n
        };
        for v in 0..nv {
            let n = valence[v];
            if n == 0 {
                continue; // isolated vertex: ignored
            }
            // Walk the fan: h -> twin(prev(h)) must visit all n outgoing half-edges.
            let start = vert_he[v] as usize;
            let mut hh = start;
            let mut steps = 0u32;
            loop {
                hh = twin[prev(hh)] as usize;
                steps += 1;
                if hh == start || steps > n {
                    break;
                }
            }
            if steps != n {
                return Err(Error::NonManifoldVertex { vertex: v as u32 });
            }
            if n < 3 || n as usize > MAX_VALENCE {
                return Err(Error::UnsupportedValence {
                    vertex: v as u32,
                    valence: n,
                });
            }
        }
        Ok(Topology {
            positions: mesh.positions,
            face_sizes: mesh.face_sizes,
            indices: mesh.indices,
            face_start,
            he_face,
            twin,
            vert_he,
            valence,
        })
    }

    /// Number of vertices (including isolated ones).
    pub fn num_vertices(&self) -> usize {
        self.positions.len() / 3
    }
    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_sizes.len()
    }
    /// Number of half-edges (twice the number of edges).
    pub fn num_half_edges(&self) -> usize {
        self.indices.len()
    }
    /// Number of vertices of face `f`.
    #[inline]
    pub fn face_size(&self, f: usize) -> usize {
        self.face_sizes[f] as usize
    }
    /// First half-edge of face `f` (the one leaving its vertex 0).
    #[inline]
    pub fn face_half_edge(&self, f: usize) -> usize {
        self.face_start[f] as usize
    }
    /// Vertex indices of face `f`.
    #[inline]
    pub fn face_vertices(&self, f: usize) -> &'a [u32] {
        let s = self.face_start[f] as usize;
        &self.indices[s..s + self.face_sizes[f] as usize]
    }
    /// Origin vertex of half-edge `h`.
    #[inline]
    pub fn origin(&self, h: usize) -> usize {
        self.indices[h] as usize
    }
    /// Face of half-edge `h`.
    #[inline]
    pub fn face_of(&self, h: usize) -> usize {
        self.he_face[h] as usize
    }
    /// Opposite half-edge of `h`.
    #[inline]
    pub fn twin(&self, h: usize) -> usize {
        self.twin[h] as usize
    }
    /// Next half-edge in the same face.
    #[inline]
    pub fn next(&self, h: usize) -> usize {
        let f = self.he_face[h] as usize;
        let s = self.face_start[f] as usize;
        let n = self.face_sizes[f] as usize;
        let k = h - s + 1;
        s + if k == n { 0 } else { k }
    }
    /// Previous half-edge in the same face.
    #[inline]
    pub fn prev(&self, h: usize) -> usize {
        let f = self.he_face[h] as usize;
        let s = self.face_start[f] as usize;
        let n = self.face_sizes[f] as usize;
        let k = h - s;
        s + if k == 0 { n - 1 } else { k - 1 }
    }
    /// Destination vertex of half-edge `h`.
    #[inline]
    pub fn dest(&self, h: usize) -> usize {
        self.origin(self.next(h))
    }
    /// The next outgoing half-edge counter-clockwise around `origin(h)`.
    #[inline]
    pub fn rotate_ccw(&self, h: usize) -> usize {
        self.twin(self.prev(h))
    }
    /// One outgoing half-edge of vertex `v` (`usize::MAX` for isolated vertices).
    #[inline]
    pub fn vertex_half_edge(&self, v: usize) -> usize {
        let h = self.vert_he[v];
        if h == u32::MAX {
            usize::MAX
        } else {
            h as usize
        }
    }
    /// Valence (number of edges) of vertex `v`.
    #[inline]
    pub fn valence(&self, v: usize) -> usize {
        self.valence[v] as usize
    }
    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: usize) -> DVec3 {
        DVec3::new(
            self.positions[3 * v],
            self.positions[3 * v + 1],
            self.positions[3 * v + 2],
        )
    }
    /// All coordinates, x y z per vertex.
    pub fn positions(&self) -> &'a [f64] {
        self.positions
    }
    /// Face sizes as given.
    pub fn face_sizes(&self) -> &'a [u32] {
        self.face_sizes
    }
    /// Face vertex indices as given.
    pub fn indices(&self) -> &'a [u32] {
        self.indices
    }
    /// Number of undirected edges.
    pub fn num_edges(&self) -> usize {
        self.indices.len() / 2
    }
    /// Axis-aligned bounding box (min, max) of the used vertices.
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for v in 0..self.num_vertices() {
            if self.valence[v] > 0 {
                let p = self.position(v);
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        (lo, hi)
    }
}
