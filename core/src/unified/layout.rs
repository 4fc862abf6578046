//! Linear subdivision into `d` pieces per edge: the combinatorics (counts,
//! vertex numbering, refined faces) of MS §3.2.2 / Fig. 8.
//!
//! # Face layouts
//!
//! Every face is described in its **corner frames**: frame `k` has its origin
//! at corner `v_k`, `i` counts steps of `1/d` along the edge `v_k -> v_{k+1}`
//! and `j` steps along the edge `v_k -> v_{k-1}`, so `(i, j)` is
//! counter-clockwise like the face.
//!
//! * **Triangles** with [`TriangleRule::Split`]: the barycentric grid
//!   `v_0 + i/d (v_1 - v_0) + j/d (v_2 - v_0)`, `d^2` triangles (MS Fig. 5).
//! * **Quads, n-gons** (and triangles with [`TriangleRule::Polygon`]): the
//!   face is cut into `n` sectors `[v_k, mid(v_k v_{k+1}), centroid,
//!   mid(v_{k-1} v_k)]`, each carrying a grid in frame `k` (a quad's sectors
//!   together are exactly its `d x d` grid). With `m = floor(d/2)`:
//!   - even `d`: sector `k` holds the `m x m` cells `0 <= i, j < m`; the
//!     centroid is a vertex of valence `n` (for `d = 2` this is
//!     Catmull-Clark's split);
//!   - odd `d`: sector `k` holds the `(m+1) x m` cells `0 <= i <= m`,
//!     `0 <= j < m` (a pinwheel), and one central `n`-gon with corners
//!     `(m, m)` of every frame remains. Its sides have length `1/d`, like
//!     every other refined edge, so its rings of quads are concentric.
//!
//!   The grid point `(i, j)` of sector `k` (`i, j <= d/2`) lies at
//!   `(s, t) = (2i/d, 2j/d)` of the sector's bilinear patch.
//!
//! # Numbering of the refined mesh
//!
//! * vertices `0..V`: the old vertices (same index);
//! * then `d - 1` points per edge, edges in order of first appearance when
//!   half-edges are scanned in order (as in [`crate::mesh::refine`]), each edge's
//!   points ordered from the origin of its first half-edge;
//! * then the interior points of each face, faces in order: triangles row by
//!   row (`j = 1..d-2`, `i = 1..d-1-j`); polygons: for even `d` the centroid
//!   first, then per sector `k` the points `1 <= i <= m`, `1 <= j < m`
//!   (row-major, `j` outer); for odd `d` per sector `1 <= i, j <= m`.
//! * faces: per input face in order; triangles row by row, each row
//!   alternating "up" `[(i,j), (i+1,j), (i,j+1)]` and "down"
//!   `[(i+1,j), (i+1,j+1), (i,j+1)]` triangles; polygons sector by sector,
//!   cells row-major, quad `[(i,j), (i+1,j), (i+1,j+1), (i,j+1)]`, then (odd
//!   `d`) the central face.
//!
//! For `d = 2` with polygons this is exactly the numbering of one
//! [`crate::mesh::refine`] step.
//!
//! [`TriangleRule::Split`]: super::TriangleRule::Split
//! [`TriangleRule::Polygon`]: super::TriangleRule::Polygon

use super::params::{TriangleRule, UnifiedParams};
use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::mesh::topology::Topology;

/// Element counts of a refined mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct UnifiedCounts {
    /// Vertices.
    pub vertices: usize,
    /// Edges (half the number of corners: the mesh is closed).
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// Face corners, i.e. the length of the index array.
    pub corners: usize,
}

/// What the refinement of a mesh depends on: vertex and edge counts and the
/// face sizes, split into triangles and other polygons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub(crate) struct MeshStats {
    pub vertices: u64,
    pub edges: u64,
    pub tris: u64,
    /// Faces with 4 or more corners.
    pub polys: u64,
    /// Their corners.
    pub poly_corners: u64,
}

/// Largest refined count accepted (refined meshes must be valid inputs of
/// [`Topology::build`] for the next level).
const MAX_COUNT: u64 = (u32::MAX / 16) as u64;

impl MeshStats {
    pub fn of(t: &Topology) -> MeshStats {
        let mut s = MeshStats {
            vertices: t.num_vertices() as u64,
            edges: t.num_edges() as u64,
            ..Default::default()
        };
        for &n in t.face_sizes() {
            if n == 3 {
                s.tris += 1;
            } else {
                s.polys += 1;
                s.poly_corners += n as u64;
            }
        }
        s
    }

    /// The counts of the mesh itself.
    pub fn counts(&self) -> UnifiedCounts {
        UnifiedCounts {
            vertices: self.vertices as usize,
            edges: self.edges as usize,
            faces: (self.tris + self.polys) as usize,
            corners: (3 * self.tris + self.poly_corners) as usize,
        }
    }

    /// Statistics of the refined mesh (closed form). Errors when a count
    /// exceeds `u32::MAX / 16`.
    pub fn refined(&self, p: &UnifiedParams) -> Result<MeshStats, Error> {
        let too_large = Error::InvalidArgument("unified: refined mesh too large");
        let d = p.d as u64;
        let m = d / 2;
        let (tris, polys, pc) = match p.triangles {
            TriangleRule::Split => (self.tris, self.polys, self.poly_corners),
            TriangleRule::Polygon => (0, self.polys + self.tris, self.poly_corners + 3 * self.tris),
        };
        // Products below stay under 2^64: inputs are < 2^28 and d <= 2^12.
        let (new_polys, new_pc, poly_interior) = if d.is_multiple_of(2) {
            (pc * m * m, 4 * pc * m * m, polys + pc * m * (m - 1))
        } else {
            (
                pc * m * (m + 1) + polys,
                4 * pc * m * (m + 1) + pc,
                pc * m * m,
            )
        };
        let tri_interior = tris * ((d - 1) * (d - 2) / 2);
        let new_tris = tris * d * d;
        let vertices = self.vertices + self.edges * (d - 1) + tri_interior + poly_interior;
        let corners = 3 * new_tris + new_pc;
        let faces = new_tris + new_polys;
        if vertices > MAX_COUNT || corners > MAX_COUNT || faces > MAX_COUNT {
            return Err(too_large);
        }
        Ok(MeshStats {
            vertices,
            edges: corners / 2,
            tris: new_tris,
            polys: new_polys,
            poly_corners: new_pc,
        })
    }
}

/// Counts of one step of the unified scheme on `t` with `params` (closed
/// form, nothing is built).
///
/// With `m = floor(d/2)`, per input face with `n` corners: a split triangle
/// gives `d^2` triangles and `(d-1)(d-2)/2` interior vertices; a polygon
/// gives `n m^2` quads and `1 + n m (m-1)` interior vertices for even `d`,
/// `n m (m+1)` quads plus one `n`-gon and `n m^2` interior vertices for odd
/// `d` (a quad: `d^2` faces, `(d-1)^2` interior vertices). Every edge gets
/// `d - 1` new vertices.
///
/// Errors: invalid parameters, or a refined count above `u32::MAX / 16`
/// ([`Error::InvalidArgument`]).
pub fn unified_counts(t: &Topology, params: &UnifiedParams) -> Result<UnifiedCounts, Error> {
    params.validate()?;
    Ok(MeshStats::of(t).refined(params)?.counts())
}

/// The shape of the refinement of one level: `d`, `m = floor(d/2)`, parity
/// and the triangle rule.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub d: usize,
    pub m: usize,
    pub odd: bool,
    pub split_tris: bool,
}

impl Shape {
    pub fn new(p: &UnifiedParams) -> Shape {
        let d = p.d as usize;
        Shape {
            d,
            m: d / 2,
            odd: d % 2 == 1,
            split_tris: p.triangles == TriangleRule::Split,
        }
    }

    /// Whether a face with `n` corners uses the triangle grid.
    #[inline]
    pub fn is_split_tri(&self, n: usize) -> bool {
        self.split_tris && n == 3
    }

    /// Interior vertices of a face with `n` corners.
    pub fn interior(&self, n: usize) -> usize {
        let (d, m) = (self.d, self.m);
        if self.is_split_tri(n) {
            (d - 1) * (d - 2) / 2
        } else if self.odd {
            n * m * m
        } else {
            1 + n * m * (m - 1)
        }
    }

    /// Refined faces of a face with `n` corners.
    pub fn children(&self, n: usize) -> usize {
        let (d, m) = (self.d, self.m);
        if self.is_split_tri(n) {
            d * d
        } else if self.odd {
            n * m * (m + 1) + 1
        } else {
            n * m * m
        }
    }

    /// Cells per sector of a polygon: `(cells along i, cells along j)`.
    #[inline]
    pub fn sector_cells(&self) -> (usize, usize) {
        if self.odd {
            (self.m + 1, self.m)
        } else {
            (self.m, self.m)
        }
    }
}

/// Refined vertex numbering of one level (borrows the per-edge and per-face
/// offset arrays).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Numbering<'n> {
    pub shape: Shape,
    /// Number of old vertices.
    pub nv: usize,
    /// Edge index of each half-edge (first-appearance order).
    pub edge_of: &'n [u32],
    /// First interior vertex of each face (`F + 1` entries).
    pub interior_start: &'n [u32],
}

impl Numbering<'_> {
    /// The refined vertex at `q/d` along half-edge `h` (`0 < q < d`).
    #[inline]
    pub fn edge_point(&self, t: &Topology, h: usize, q: usize) -> usize {
        let d = self.shape.d;
        let base = self.nv + self.edge_of[h] as usize * (d - 1);
        if h < t.twin(h) {
            base + q - 1
        } else {
            base + d - q - 1
        }
    }

    /// The refined vertex at grid point `(i, j)` of corner frame `k` of face
    /// `f` (see the module docs), or `None` outside the face's grid.
    pub fn frame_point(
        &self,
        t: &Topology,
        f: usize,
        k: usize,
        i: usize,
        j: usize,
    ) -> Option<usize> {
        let n = t.face_size(f);
        let d = self.shape.d;
        if k >= n || i > d || j > d {
            return None;
        }
        if self.shape.is_split_tri(n) {
            if i + j > d {
                return None;
            }
            let (i0, j0) = match k {
                0 => (i, j),
                1 => (d - i - j, i),
                _ => (j, d - i - j),
            };
            return Some(self.tri_point(t, f, i0, j0));
        }
        if n != 4 && i > self.shape.m && j > self.shape.m {
            return None;
        }
        self.poly_point(t, f, n, k, i, j)
    }

    /// Grid point `(i0, j0)` (frame 0, `i0 + j0 <= d`) of a split triangle.
    #[inline]
    pub fn tri_point(&self, t: &Topology, f: usize, i0: usize, j0: usize) -> usize {
        let d = self.shape.d;
        let h0 = t.face_half_edge(f);
        if j0 == 0 {
            if i0 == 0 {
                t.origin(h0)
            } else if i0 == d {
                t.origin(h0 + 1)
            } else {
                self.edge_point(t, h0, i0)
            }
        } else if i0 == 0 {
            if j0 == d {
                t.origin(h0 + 2)
            } else {
                self.edge_point(t, h0 + 2, d - j0)
            }
        } else if i0 + j0 == d {
            self.edge_point(t, h0 + 1, j0)
        } else {
            self.interior_start[f] as usize + (j0 - 1) * (d - 1) - (j0 - 1) * j0 / 2 + (i0 - 1)
        }
    }

    /// Grid point `(i, j)` of frame `k` of a polygon with `n` corners; points
    /// owned by a neighbouring sector are moved to its frame (at most twice).
    #[inline]
    pub fn poly_point(
        &self,
        t: &Topology,
        f: usize,
        n: usize,
        mut k: usize,
        mut i: usize,
        mut j: usize,
    ) -> Option<usize> {
        let Shape { d, m, odd, .. } = self.shape;
        let fs = t.face_half_edge(f);
        for _ in 0..3 {
            if i > d || j > d {
                return None;
            }
            if j == 0 {
                let h = fs + k;
                return Some(if i == 0 {
                    t.origin(h)
                } else if i == d {
                    t.dest(h)
                } else {
                    self.edge_point(t, h, i)
                });
            }
            if i == 0 {
                let h = fs + if k == 0 { n - 1 } else { k - 1 };
                return Some(if j == d {
                    t.origin(h)
                } else {
                    self.edge_point(t, h, d - j)
                });
            }
            let base = self.interior_start[f] as usize;
            if odd {
                if i <= m && j <= m {
                    return Some(base + k * m * m + (j - 1) * m + (i - 1));
                }
            } else {
                if i == m && j == m {
                    return Some(base);
                }
                if i <= m && j < m {
                    return Some(base + 1 + k * m * (m - 1) + (j - 1) * m + (i - 1));
                }
            }
            if i > m {
                (k, i, j) = (if k + 1 == n { 0 } else { k + 1 }, j, d - i);
            } else {
                (k, i, j) = (if k == 0 { n - 1 } else { k - 1 }, d - j, i);
            }
        }
        None
    }
}

/// The boundary of one polygon face, loaded once so that grid points can be
/// resolved without topology lookups (same rules as
/// [`Numbering::poly_point`]).
pub(crate) struct FaceFrame {
    shape: Shape,
    n: usize,
    base: usize,
    /// Corner vertices.
    v: [u32; MAX_VALENCE],
    /// Index of the point at `q = 1` of edge `k` when walked from `v_k`,
    /// and the step (+1 or -1) to the next point.
    e: [u32; MAX_VALENCE],
    fwd: [bool; MAX_VALENCE],
}

impl FaceFrame {
    pub fn new(shape: Shape) -> FaceFrame {
        FaceFrame {
            shape,
            n: 0,
            base: 0,
            v: [0; MAX_VALENCE],
            e: [0; MAX_VALENCE],
            fwd: [true; MAX_VALENCE],
        }
    }

    /// Loads face `f` (a polygon-layout face).
    #[inline]
    pub fn load(&mut self, t: &Topology, num: &Numbering, f: usize) {
        let n = t.face_size(f);
        let fs = t.face_half_edge(f);
        let d = self.shape.d;
        self.n = n;
        self.base = num.interior_start[f] as usize;
        for k in 0..n {
            let h = fs + k;
            self.v[k] = t.origin(h) as u32;
            let first = num.nv + num.edge_of[h] as usize * (d - 1);
            let fwd = h < t.twin(h);
            self.fwd[k] = fwd;
            self.e[k] = if fwd { first } else { first + d - 2 } as u32;
        }
    }

    #[inline]
    fn edge(&self, k: usize, q: usize) -> usize {
        let e = self.e[k] as usize;
        if self.fwd[k] {
            e + q - 1
        } else {
            e + 1 - q
        }
    }

    /// Grid point `(i, j)` of frame `k` (`i <= d`, `j <= d`, within the
    /// ranges documented at [`Numbering::frame_point`]).
    #[inline]
    pub fn point(&self, mut k: usize, mut i: usize, mut j: usize) -> usize {
        let Shape { d, m, odd, .. } = self.shape;
        let n = self.n;
        for _ in 0..3 {
            if j == 0 {
                return if i == 0 {
                    self.v[k] as usize
                } else if i == d {
                    self.v[if k + 1 == n { 0 } else { k + 1 }] as usize
                } else {
                    self.edge(k, i)
                };
            }
            if i == 0 {
                let kp = if k == 0 { n - 1 } else { k - 1 };
                return if j == d {
                    self.v[kp] as usize
                } else {
                    self.edge(kp, d - j)
                };
            }
            if odd {
                if i <= m && j <= m {
                    return self.base + k * m * m + (j - 1) * m + (i - 1);
                }
            } else {
                if i == m && j == m {
                    return self.base;
                }
                if i <= m && j < m {
                    return self.base + 1 + k * m * (m - 1) + (j - 1) * m + (i - 1);
                }
            }
            if i > m {
                (k, i, j) = (if k + 1 == n { 0 } else { k + 1 }, j, d - i.min(d));
            } else {
                (k, i, j) = (if k == 0 { n - 1 } else { k - 1 }, d - j.min(d), i);
            }
        }
        self.base
    }
}
