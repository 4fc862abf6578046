//! Builds the refined connectivity of a level: edge numbering, interior
//! vertex offsets, the refined faces (see [`super::layout`] for the
//! numbering) and the vertex-to-face adjacency used by the k-ring averages.

use super::fast::Charts;
use super::layout::{FaceFrame, Numbering, Shape};
use crate::mesh::topology::Topology;

/// Numbers the edges (first appearance over half-edges, as
/// [`crate::mesh::refine`]) into `edge_of` (`H` entries), and fills
/// `interior_start` (first interior vertex of each face) and `child_start`
/// (first refined face of each face), both with `F + 1` entries.
pub(crate) fn number(
    t: &Topology,
    shape: &Shape,
    edge_of: &mut [u32],
    interior_start: &mut [u32],
    child_start: &mut [u32],
) {
    let mut next = 0u32;
    for h in 0..t.num_half_edges() {
        let tw = t.twin(h);
        if h < tw {
            edge_of[h] = next;
            edge_of[tw] = next;
            next += 1;
        }
    }
    let mut r = t.num_vertices() + next as usize * (shape.d - 1);
    let mut c = 0usize;
    for f in 0..t.num_faces() {
        interior_start[f] = r as u32;
        child_start[f] = c as u32;
        r += shape.interior(t.face_size(f));
        c += shape.children(t.face_size(f));
    }
    interior_start[t.num_faces()] = r as u32;
    child_start[t.num_faces()] = c as u32;
}

/// Writes the refined faces: `sizes` (`F'`), `idx` (corners) and
/// `face_start` (`F' + 1` offsets into `idx`), in the order `child_start`
/// announces. Quads with a chart ([`super::fast`]) are emitted from their
/// vertex grid.
pub(crate) fn emit(
    t: &Topology,
    num: &Numbering,
    sizes: &mut [u32],
    idx: &mut [u32],
    face_start: &mut [u32],
    charts: Option<&Charts>,
) {
    let sh = num.shape;
    let d = sh.d;
    let mut out = Emitter {
        sizes,
        idx,
        face_start,
        fq: 0,
        c: 0,
    };
    let mut frame = FaceFrame::new(sh);
    let mut local = [0u32; LOCAL];
    for f in 0..t.num_faces() {
        let n = t.face_size(f);
        if let Some(ch) = charts.filter(|ch| ch.has_chart(f)) {
            ch.emit_quad(f, |q| out.push32(q));
            if sh.odd {
                out.push32(ch.centre_quad(f));
            }
            continue;
        }
        if sh.is_split_tri(n) {
            for j in 0..d {
                for i in 0..d - j {
                    let a = num.tri_point(t, f, i, j);
                    let b = num.tri_point(t, f, i + 1, j);
                    let e = num.tri_point(t, f, i, j + 1);
                    out.push(&[a, b, e]);
                    if i + j + 2 <= d {
                        let g = num.tri_point(t, f, i + 1, j + 1);
                        out.push(&[b, g, e]);
                    }
                }
            }
            continue;
        }
        if d == 2 {
            // Sector k is [v_k, e_k, centre, e_{k-1}], as in `refine`.
            let fs = t.face_half_edge(f);
            let centre = num.interior_start[f];
            let ep = |h: usize| (num.nv + num.edge_of[h] as usize) as u32;
            let mut prev = ep(fs + n - 1);
            for k in 0..n {
                let e = ep(fs + k);
                out.push32([t.origin(fs + k) as u32, e, centre, prev]);
                prev = e;
            }
            continue;
        }
        frame.load(t, num, f);
        let (ci, cj) = sh.sector_cells();
        if (ci + 1) * (cj + 1) <= LOCAL {
            // Resolve each sector point once, then emit the cells from it.
            let w = ci + 1;
            for k in 0..n {
                for j in 0..=cj {
                    for i in 0..=ci {
                        local[j * w + i] = frame.point(k, i, j) as u32;
                    }
                }
                for j in 0..cj {
                    for i in 0..ci {
                        let a = j * w + i;
                        out.push32([local[a], local[a + 1], local[a + w + 1], local[a + w]]);
                    }
                }
            }
            if sh.odd {
                let mut centre = [0usize; crate::config::MAX_VALENCE];
                for (k, x) in centre[..n].iter_mut().enumerate() {
                    *x = frame.point(k, sh.m, sh.m);
                }
                out.push(&centre[..n]);
            }
            continue;
        }
        for k in 0..n {
            for j in 0..cj {
                for i in 0..ci {
                    let q = [
                        frame.point(k, i, j),
                        frame.point(k, i + 1, j),
                        frame.point(k, i + 1, j + 1),
                        frame.point(k, i, j + 1),
                    ];
                    out.push(&q);
                }
            }
        }
        if sh.odd {
            let mut centre = [0usize; crate::config::MAX_VALENCE];
            for (k, x) in centre[..n].iter_mut().enumerate() {
                *x = frame.point(k, sh.m, sh.m);
            }
            out.push(&centre[..n]);
        }
    }
    out.face_start[out.fq] = out.c as u32;
    debug_assert_eq!(out.fq, out.sizes.len());
    debug_assert_eq!(out.c, out.idx.len());
}

/// Sector points resolved at once when they fit (`d` up to about 64).
const LOCAL: usize = 34 * 33;

struct Emitter<'o> {
    sizes: &'o mut [u32],
    idx: &'o mut [u32],
    face_start: &'o mut [u32],
    fq: usize,
    c: usize,
}

impl Emitter<'_> {
    #[inline]
    fn push32(&mut self, q: [u32; 4]) {
        self.sizes[self.fq] = 4;
        self.face_start[self.fq] = self.c as u32;
        self.idx[self.c..self.c + 4].copy_from_slice(&q);
        self.c += 4;
        self.fq += 1;
    }

    #[inline]
    fn push(&mut self, vs: &[usize]) {
        self.sizes[self.fq] = vs.len() as u32;
        self.face_start[self.fq] = self.c as u32;
        for &v in vs {
            self.idx[self.c] = v as u32;
            self.c += 1;
        }
        self.fq += 1;
    }
}

/// Number of faces of each refined vertex (`counts` has `V'` entries).
pub(crate) fn face_counts(idx: &[u32], counts: &mut [u32]) {
    counts.fill(0);
    for &v in idx {
        if let Some(c) = counts.get_mut(v as usize) {
            *c += 1;
        }
    }
}

/// Vertex-to-face adjacency of the refined mesh in compressed rows:
/// the faces of vertex `r` are `vf[vf_start[r]..vf_start[r + 1]]`.
pub(crate) fn vertex_faces(face_start: &[u32], idx: &[u32], vf_start: &mut [u32], vf: &mut [u32]) {
    let (first, rest) = vf_start.split_at_mut(1);
    first[0] = 0;
    face_counts(idx, rest);
    let mut acc = 0u32;
    for s in rest.iter_mut() {
        acc += *s;
        *s = acc;
    }
    // vf_start[r + 1] is the end of row r; filling back to front moves it
    // to the start of row r and keeps each row in increasing face order.
    for f in (0..face_start.len() - 1).rev() {
        for &v in idx[face_start[f] as usize..face_start[f + 1] as usize]
            .iter()
            .rev()
        {
            let s = &mut vf_start[v as usize + 1];
            *s -= 1;
            vf[*s as usize] = f as u32;
        }
    }
    // Now vf_start[r + 1] holds the start of row r: shift down by one.
    for r in 0..vf_start.len() - 1 {
        vf_start[r] = vf_start[r + 1];
    }
    if let Some(last) = vf_start.last_mut() {
        *last = idx.len() as u32;
    }
}
