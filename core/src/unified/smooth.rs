//! The smoothing step for any `d`: k-ring averages on the linearly
//! subdivided mesh (MS §3.2.2, eqs. (22)–(24), Fig. 9).
//!
//! * `N_k(V)` — vertices reachable from `V` by traversing at most `k` faces
//!   (`N_0(V) = {V}`, `N_k` adds the vertices of every face incident to
//!   `N_{k-1}`); `F_k(V)` — the faces traversed, i.e. the faces incident to
//!   `N_{k-1}(V)`; `N_k(F) = ∪_{V in F} N_{k-1}(V)` (the printed subscript
//!   `k` is read as `k - 1`, a decision on \[MS01 §3.2\]: for `d = 2` a face
//!   must average its own vertices).
//! * odd `d`, `k = (d-1)/2`: eq. (22) `V := avg N_k(V)`, twice per pass;
//! * even `d`, `k = d/2`: eq. (23) `F := avg N_k(F)` (a face becomes a dual
//!   vertex), then eq. (24) `V := avg_{F in F_k(V)} F`.
//!
//! On a regular quad grid each average is a box of width `d`, so a pass is
//! the tensor mask `(1/d²)[1, 2, .., d, .., 2, 1]` of eq. (3) in each
//! direction. For `d = 2`, (23)+(24) is eq. (9) on quads ("simple
//! averaging": `1/4 V + 1/(2N) Σ⊕ + 1/(4N) Σ⊗`) and on triangles eq. (9)
//! divided by its weight sum 3/4 (`1/3 V + 2/(3N) Σ⊕` on an all-triangle
//! ring) — our choice for the triangle weights MS leaves open.
//!
//! The neighbourhoods are found by breadth-first search with visit stamps
//! (no recursion, no clearing between searches); queues and stamps are
//! caller memory.

use glam::DVec3;

/// Connectivity of the refined mesh: faces as corner ranges, and the faces
/// of each vertex.
#[derive(Clone, Copy)]
pub(crate) struct Adjacency<'w> {
    pub face_start: &'w [u32],
    pub idx: &'w [u32],
    pub vf_start: &'w [u32],
    pub vf: &'w [u32],
}

impl Adjacency<'_> {
    #[inline]
    fn faces_of(&self, v: usize) -> &[u32] {
        &self.vf[self.vf_start[v] as usize..self.vf_start[v + 1] as usize]
    }
    #[inline]
    fn verts_of(&self, f: usize) -> &[u32] {
        &self.idx[self.face_start[f] as usize..self.face_start[f + 1] as usize]
    }
    fn num_vertices(&self) -> usize {
        self.vf_start.len() - 1
    }
    fn num_faces(&self) -> usize {
        self.face_start.len() - 1
    }
}

/// Search scratch: a stamp per vertex and per face, and a vertex queue.
/// Every search takes a fresh stamp value, so nothing is cleared between
/// searches (only when the stamp values run out).
pub(crate) struct Search<'w> {
    pub vstamp: &'w mut [u32],
    pub fstamp: &'w mut [u32],
    pub queue: &'w mut [u32],
    /// Next stamp value (stamps start zeroed, so `1` on a fresh scratch).
    pub next: u32,
}

impl Search<'_> {
    /// A stamp value no vertex or face carries yet.
    #[inline]
    fn stamp(&mut self) -> u32 {
        if self.next == u32::MAX || self.next == 0 {
            self.vstamp.fill(0);
            self.fstamp.fill(0);
            self.next = 1;
        }
        self.next += 1;
        self.next - 1
    }

    /// Grows the vertex set `queue[..end]` (stamped `st`) by `levels` face
    /// rings starting from the frontier `queue[lo..end]`; every newly found
    /// vertex is passed to `found`. Returns the new end.
    #[inline]
    fn grow(
        &mut self,
        adj: &Adjacency,
        st: u32,
        mut lo: usize,
        mut end: usize,
        levels: usize,
        found: &mut impl FnMut(usize),
    ) -> usize {
        for _ in 0..levels {
            let hi = end;
            for q in lo..hi {
                let u = self.queue[q] as usize;
                for &f in adj.faces_of(u) {
                    let f = f as usize;
                    if self.fstamp[f] == st {
                        continue;
                    }
                    self.fstamp[f] = st;
                    for &w in adj.verts_of(f) {
                        let w = w as usize;
                        if self.vstamp[w] != st {
                            self.vstamp[w] = st;
                            self.queue[end] = w as u32;
                            end += 1;
                            found(w);
                        }
                    }
                }
            }
            lo = hi;
        }
        end
    }
}

/// Eq. (22): `dst[V] = avg_{W in N_k(V)} src[W]`, except for vertices
/// flagged `gen` in `done` (empty: none).
pub(crate) fn vertex_rings(
    adj: &Adjacency,
    k: usize,
    src: &[DVec3],
    dst: &mut [DVec3],
    s: &mut Search,
    done: &[u32],
    gen: u32,
) {
    for v in 0..adj.num_vertices() {
        if done.get(v).is_some_and(|&x| x == gen) {
            continue;
        }
        let st = s.stamp();
        s.vstamp[v] = st;
        s.queue[0] = v as u32;
        let mut sum = src[v];
        let mut cnt = 1usize;
        s.grow(adj, st, 0, 1, k, &mut |w| {
            sum += src[w];
            cnt += 1;
        });
        dst[v] = sum / cnt as f64;
    }
}

/// Eq. (23): `dst[F] = avg_{W in N_k(F)} src[W]` (`k >= 1`; for `k = 1` the
/// centroid of the face's own vertices), except for faces flagged `gen` in `done`.
pub(crate) fn face_rings(
    adj: &Adjacency,
    k: usize,
    src: &[DVec3],
    dst: &mut [DVec3],
    s: Option<&mut Search>,
    done: &[u32],
    gen: u32,
) {
    let s = match s {
        Some(s) if k > 1 => s,
        _ => {
            for (f, out) in dst.iter_mut().enumerate().take(adj.num_faces()) {
                let vs = adj.verts_of(f);
                let mut sum = DVec3::ZERO;
                for &v in vs {
                    sum += src[v as usize];
                }
                *out = sum / vs.len() as f64;
            }
            return;
        }
    };
    for f in 0..adj.num_faces() {
        if done.get(f).is_some_and(|&x| x == gen) {
            continue;
        }
        let st = s.stamp();
        s.fstamp[f] = st;
        let mut sum = DVec3::ZERO;
        let mut end = 0usize;
        for &v in adj.verts_of(f) {
            s.vstamp[v as usize] = st;
            s.queue[end] = v;
            end += 1;
            sum += src[v as usize];
        }
        let mut cnt = end;
        s.grow(adj, st, 0, end, k - 1, &mut |w| {
            sum += src[w];
            cnt += 1;
        });
        dst[f] = sum / cnt as f64;
    }
}

/// Eq. (24): `dst[V] = avg_{F in F_k(V)} src[F]` (`k >= 1`). Vertices
/// without faces keep their value, vertices flagged `gen` in `done` too.
pub(crate) fn vertex_face_rings(
    adj: &Adjacency,
    k: usize,
    src: &[DVec3],
    dst: &mut [DVec3],
    s: Option<&mut Search>,
    done: &[u32],
    gen: u32,
) {
    let s = match s {
        Some(s) if k > 1 => s,
        _ => {
            for (v, out) in dst.iter_mut().enumerate().take(adj.num_vertices()) {
                let fs = adj.faces_of(v);
                if fs.is_empty() {
                    continue;
                }
                let mut sum = DVec3::ZERO;
                for &f in fs {
                    sum += src[f as usize];
                }
                *out = sum / fs.len() as f64;
            }
            return;
        }
    };
    for v in 0..adj.num_vertices() {
        if adj.faces_of(v).is_empty() || done.get(v).is_some_and(|&x| x == gen) {
            continue;
        }
        let st = s.stamp();
        s.vstamp[v] = st;
        s.queue[0] = v as u32;
        // N_{k-1}(V): the vertices whose faces make up F_k(V).
        let end = s.grow(adj, st, 0, 1, k - 1, &mut |_| {});
        let st2 = s.stamp();
        let mut sum = DVec3::ZERO;
        let mut cnt = 0usize;
        for q in 0..end {
            let u = s.queue[q] as usize;
            for &f in adj.faces_of(u) {
                let f = f as usize;
                // Faces seen while growing carry the first stamp already;
                // a second one counts every face once.
                if s.fstamp[f] != st2 {
                    s.fstamp[f] = st2;
                    sum += src[f];
                    cnt += 1;
                }
            }
        }
        dst[v] = sum / cnt as f64;
    }
}

/// Eqs. (23)+(24) for `k = 1` (`d = 2`) without the vertex-to-face rows:
/// face centroids into `fv`, then every vertex becomes the average of its
/// faces' values (`counts` from the face counts; vertices without faces keep
/// their value).
pub(crate) fn centroid_average(
    face_start: &[u32],
    idx: &[u32],
    counts: &[u32],
    x: &mut [DVec3],
    fv: &mut [DVec3],
) {
    let nf = face_start.len() - 1;
    for (f, out) in fv.iter_mut().enumerate().take(nf) {
        let vs = &idx[face_start[f] as usize..face_start[f + 1] as usize];
        let mut sum = DVec3::ZERO;
        for &v in vs {
            sum += x[v as usize];
        }
        *out = sum / vs.len() as f64;
    }
    for (xv, &c) in x.iter_mut().zip(counts) {
        if c > 0 {
            *xv = DVec3::ZERO;
        }
    }
    for (f, &val) in fv.iter().enumerate().take(nf) {
        for &v in &idx[face_start[f] as usize..face_start[f + 1] as usize] {
            x[v as usize] += val;
        }
    }
    for (xv, &c) in x.iter_mut().zip(counts) {
        if c > 0 {
            *xv /= c as f64;
        }
    }
}
