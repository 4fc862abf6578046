//! The smoothing pass for `d >= 3` (eqs. (22)–(24)): on quads whose
//! neighbourhood is a grid, the first pass from `d`-ary B-spline weights and
//! later passes by box sums ([`super::fast`]); everything else by the k-ring
//! search ([`super::smooth`]), whose adjacency and scratch are set up only
//! when some value is left to it.

use super::faces;
use super::fast::{self, Charts, Marks, Window};
use super::smooth::{self, Adjacency, Search};
use crate::mem::arena::Arena;
use crate::mesh::topology::Topology;
use glam::DVec3;

/// Fast-path state of a level.
pub(crate) struct Fast<'a> {
    pub charts: Charts<'a>,
    pub win: Window<'a>,
    /// First-pass weights (see [`fast::first_pass_weights`]).
    pub w1: &'a [f64],
    pub w2: &'a [f64],
    /// Written-by-the-fast-path flags (generation numbers).
    pub vdone: &'a mut [u32],
    pub fdone: &'a mut [u32],
}

/// The search adjacency and scratch, carved from `rest` on first use.
pub(crate) struct LazySearch<'a> {
    pub face_start: &'a [u32],
    pub idx: &'a [u32],
    pub num_vertices: usize,
    /// The last part of the level's working memory.
    pub rest: Arena<'a>,
    pub ready: Option<(Adjacency<'a>, Search<'a>)>,
}

impl<'a> LazySearch<'a> {
    fn get(&mut self) -> &mut (Adjacency<'a>, Search<'a>) {
        let (nv, nf) = (self.num_vertices, self.face_start.len() - 1);
        let (face_start, idx) = (self.face_start, self.idx);
        let rest = &mut self.rest;
        self.ready.get_or_insert_with(|| {
            let vf_start = rest.u32s(nv + 1);
            let vf = rest.u32s(idx.len());
            faces::vertex_faces(face_start, idx, vf_start, vf);
            let adj = Adjacency {
                face_start,
                idx,
                vf_start,
                vf,
            };
            let s = Search {
                vstamp: rest.u32s(nv),
                fstamp: rest.u32s(nf),
                queue: rest.u32s(nv),
                next: 1,
            };
            (adj, s)
        })
    }
}

/// Whether some value is not flagged `gen` in `done` (`None`: no fast path,
/// so all of them).
fn left(done: Option<&[u32]>, gen: u32) -> bool {
    match done {
        Some(d) => d.iter().any(|&x| x != gen),
        None => true,
    }
}

/// The smoother of one level with `d >= 3`.
pub(crate) struct General<'a> {
    /// `(d-1)/2` (odd `d`) or `d/2` (even `d`).
    pub k: usize,
    pub odd: bool,
    pub fast: Option<Fast<'a>>,
    pub search: LazySearch<'a>,
    /// Generation of the `done` flags (they start zeroed).
    pub gen: u32,
}

impl General<'_> {
    /// One smoothing pass (`pass` counts from 0): `x` in and out, `buf` the
    /// Jacobi copy (vertices, odd `d`) or the dual values (faces, even `d`).
    pub fn pass(&mut self, t: &Topology, pass: u32, x: &mut [DVec3], buf: &mut [DVec3]) {
        let first = pass == 0;
        let k = self.k;
        let General {
            fast: fs, search, ..
        } = self;
        if self.odd {
            // Eq. (22) twice.
            for round in 0..2 {
                let (src, dst): (&[DVec3], &mut [DVec3]) = if round == 0 {
                    (&*x, &mut *buf)
                } else {
                    (&*buf, &mut *x)
                };
                self.gen += 1;
                let gen = self.gen;
                if let Some(f) = fs.as_mut() {
                    if first {
                        // Intermediate values only where other paths read
                        // them.
                        let w = if round == 0 { f.w1 } else { f.w2 };
                        fast::tensor_vertices(t, &f.charts, w, dst, f.vdone, gen, round == 0);
                    }
                    fast::vertex_boxes(
                        t,
                        &f.charts,
                        src,
                        dst,
                        Marks { done: f.vdone, gen },
                        &mut f.win,
                        first,
                    );
                }
                let done = fs.as_ref().map(|f| &*f.vdone);
                if left(done, gen) {
                    let (adj, s) = search.get();
                    smooth::vertex_rings(adj, k, src, dst, s, done.unwrap_or(&[]), gen);
                }
            }
        } else {
            // Eq. (23): every face becomes a dual vertex.
            self.gen += 1;
            let gen = self.gen;
            if let Some(f) = fs.as_mut() {
                if first {
                    fast::tensor_cells(t, &f.charts, f.w1, buf, f.fdone, gen);
                }
                fast::face_boxes(
                    t,
                    &f.charts,
                    x,
                    buf,
                    Marks { done: f.fdone, gen },
                    &mut f.win,
                    first,
                );
            }
            let done = fs.as_ref().map(|f| &*f.fdone);
            if left(done, gen) {
                let (adj, s) = search.get();
                smooth::face_rings(adj, k, x, buf, Some(s), done.unwrap_or(&[]), gen);
            }
            // Eq. (24): back to the vertices.
            if let Some(f) = fs.as_mut() {
                if first {
                    fast::tensor_vertices(t, &f.charts, f.w2, x, f.vdone, gen, false);
                }
                fast::vertex_cell_boxes(
                    t,
                    &f.charts,
                    buf,
                    x,
                    Marks { done: f.vdone, gen },
                    &mut f.win,
                    first,
                );
            }
            let done = fs.as_ref().map(|f| &*f.vdone);
            if left(done, gen) {
                let (adj, s) = search.get();
                smooth::vertex_face_rings(adj, k, buf, x, Some(s), done.unwrap_or(&[]), gen);
            }
        }
    }
}
