//! Local refinement of one quad patch of a [`FeatureMesh`], with fixed
//! capacity on the stack: the exact evaluation of patches next to
//! boundaries, creases, corners, darts and extraordinary vertices by
//! subdividing until the query point lies in a polynomial piece \[OSD\].
//!
//! A [`LocalPatch`] holds a quad (local face 0, its corners in parameter
//! order) and every face around its four corners, with their edges'
//! sharpness, the corners' sharpness and, for every vertex, the semi-sharp
//! statistics of all its edges (what the Chaikin rule needs). That set is
//! closed under "subdivide once and keep one quadrant": the children of the
//! faces around the old corners contain every face around the new corners.
//! So [`LocalPatch::child`] is one Catmull-Clark step with the sharp rules of
//! [`super::sharpness`], restricted to what the chosen quadrant needs.
//! The patch keeps its adjacency indexed: the edge of every face side and,
//! as linked lists in index order, the edges and faces at every vertex and
//! the faces on every edge, so each lookup costs the local degree and one
//! step is linear in the patch size; [`LocalPatch::child_into`] and
//! [`LocalPatch::gather_into`] refill an existing patch instead of building
//! (and zeroing) a new one.
//!
//! [`LocalPatch::regular_grid`] recognises when the patch is a bicubic
//! B-spline: each corner smooth with four faces, or a straight crease or
//! boundary whose side has two faces, or a sharp corner with the patch alone
//! in its sector, with no semi-sharp value at the corners; across an
//! infinitely sharp side the missing control points are the phantoms
//! `2 P_edge - P_inner` (boundary B-spline patches, exact for these rules).
//! Near an irregular corner every step halves the distance to it, so a
//! point at distance `d` needs about `log2(1/d)` steps (at most 1,100 for
//! any `f64` in `[0, 1]`); at the corner itself [`LocalPatch::corner_limit`]
//! applies the exact limit mask (the left eigenvector for eigenvalue 1 of
//! the corner's one-ring subdivision matrix).
//!
//! Layer 3 (with the rest of `mesh/`): imports `config`, `error`, `math`
//! and the siblings `sharpness` and `features`.

use super::features::FeatureMesh;
use super::sharpness::{
    decay_at, decrement, edge_mask, is_infinite, is_semi_sharp, is_sharp, vertex_mask, Around,
    EndStats, FeatureOptions,
};
use crate::config::MAX_K;
use crate::error::Error;
use glam::DVec3;

/// A quad patch and the faces around its corners (see the module docs),
/// for at most `NF` faces, `NV` vertices and `NE` edges.
#[derive(Clone)]
pub struct LocalPatch<const NF: usize, const NV: usize, const NE: usize> {
    nv: usize,
    nf: usize,
    ne: usize,
    pos: [DVec3; NV],
    vsharp: [f32; NV],
    stats: [EndStats; NV],
    face: [[u16; 4]; NF],
    edge: [[u16; 2]; NE],
    esharp: [f32; NE],
    /// Per face, the edge of each side (`face[k]` to `face[k + 1]`).
    side: [[u16; 4]; NF],
    /// Per vertex, its first and last incident edge (index order; [`NONE`]
    /// if none): with `edge_next` a list, so lookups at a vertex cost its
    /// degree, not the patch size.
    edge_ends: [[u16; 2]; NV],
    /// Per edge and end, the next edge at that end's vertex ([`NONE`] last).
    edge_next: [[u16; 2]; NE],
    /// Per vertex, its first incident face (index order; [`NONE`] if none).
    face_first: [u16; NV],
    /// Per face and corner, the next face at that corner's vertex (kept at
    /// the first corner holding the vertex).
    face_next: [[u16; 4]; NF],
    /// Per edge, its first face (index order; [`NONE`] if none).
    edge_face: [u16; NE],
    /// Per face and side, the next face on that side's edge (kept at the
    /// first side on the edge).
    side_next: [[u16; 4]; NF],
}

/// The capacity that serves valences up to about 16 around a patch: 64
/// faces (about 20 KiB).
pub type SmallPatch = LocalPatch<64, 196, 256>;

/// The capacity for high valences and many-faced edges: 400 faces (one
/// vertex of valence 360 next to three ordinary ones; about 120 KiB).
pub type LargePatch = LocalPatch<400, 1204, 1600>;

/// A local patch ran out of capacity (or met topology it cannot hold);
/// the evaluator retries with the larger capacity, then reports
/// [`Error::NeighbourhoodTooLarge`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Full;

/// Marker for "none" in small index lists.
const NONE: u16 = u16::MAX;

impl<const NF: usize, const NV: usize, const NE: usize> LocalPatch<NF, NV, NE> {
    /// A patch with nothing in it (for [`LocalPatch::gather_into`] and
    /// [`LocalPatch::child_into`]).
    pub fn empty() -> Self {
        LocalPatch {
            nv: 0,
            nf: 0,
            ne: 0,
            pos: [DVec3::ZERO; NV],
            vsharp: [0.0; NV],
            stats: [EndStats::default(); NV],
            face: [[0; 4]; NF],
            edge: [[0; 2]; NE],
            esharp: [0.0; NE],
            side: [[0; 4]; NF],
            edge_ends: [[NONE; 2]; NV],
            edge_next: [[NONE; 2]; NE],
            face_first: [NONE; NV],
            face_next: [[NONE; 4]; NF],
            edge_face: [NONE; NE],
            side_next: [[NONE; 4]; NF],
        }
    }

    /// Forgets the contents (the arrays are overwritten as they fill).
    fn clear(&mut self) {
        self.nv = 0;
        self.nf = 0;
        self.ne = 0;
    }

    /// Corners of the patch in parameter order (`(0,0)`, `(1,0)`, `(1,1)`,
    /// `(0,1)`).
    #[inline]
    pub fn corners(&self) -> [u16; 4] {
        self.face[0]
    }

    /// Position of local vertex `v`.
    #[inline]
    pub fn position(&self, v: u16) -> DVec3 {
        self.pos[v as usize]
    }

    /// Every control point of the patch: the quad's corners and those of
    /// the faces around them, which is every point the limit surface over
    /// the quad depends on (so that surface lies in their convex hull: all
    /// the rules of [`super::sharpness`] are convex combinations).
    #[inline]
    pub fn points(&self) -> &[DVec3] {
        &self.pos[..self.nv]
    }

    fn add_vertex(&mut self, p: DVec3, vs: f32, st: EndStats) -> Result<u16, Full> {
        if self.nv >= NV {
            return Err(Full);
        }
        self.pos[self.nv] = p;
        self.vsharp[self.nv] = vs;
        self.stats[self.nv] = st;
        self.edge_ends[self.nv] = [NONE; 2];
        self.face_first[self.nv] = NONE;
        self.nv += 1;
        Ok((self.nv - 1) as u16)
    }

    fn add_face(&mut self, q: [u16; 4]) -> Result<(), Full> {
        if self.nf >= NF {
            return Err(Full);
        }
        self.face[self.nf] = q;
        self.nf += 1;
        Ok(())
    }

    /// The edges at `v` in index order.
    #[inline]
    fn edges_of(&self, v: u16) -> EdgesAt<'_, NF, NV, NE> {
        EdgesAt {
            lp: self,
            v,
            next: self.edge_ends[v as usize][0],
        }
    }

    /// The faces at `v` in index order.
    #[inline]
    fn faces_of(&self, v: u16) -> FacesAt<'_, NF, NV, NE> {
        FacesAt {
            lp: self,
            v,
            next: self.face_first[v as usize],
        }
    }

    fn find_edge(&self, a: u16, b: u16) -> Option<usize> {
        self.edges_of(a).find(|&e| {
            let [x, y] = self.edge[e];
            (x == a && y == b) || (x == b && y == a)
        })
    }

    /// Adds the edge `a`-`b` unless it exists; returns its index.
    fn add_edge(&mut self, a: u16, b: u16, s: f32) -> Result<u16, Full> {
        if let Some(e) = self.find_edge(a, b) {
            return Ok(e as u16);
        }
        if self.ne >= NE {
            return Err(Full);
        }
        let e = self.ne as u16;
        self.edge[self.ne] = [a, b];
        self.esharp[self.ne] = s;
        self.edge_next[self.ne] = [NONE; 2];
        self.edge_face[self.ne] = NONE;
        self.ne += 1;
        // Append to both ends' lists (once when both ends are one vertex).
        for (end, v) in [a, b].into_iter().enumerate() {
            if end == 1 && a == b {
                break;
            }
            let [first, last] = self.edge_ends[v as usize];
            if first == NONE {
                self.edge_ends[v as usize] = [e, e];
            } else {
                let k = usize::from(self.edge[last as usize][0] != v);
                self.edge_next[last as usize][k] = e;
                self.edge_ends[v as usize][1] = e;
            }
        }
        Ok(e)
    }

    /// The faces on edge `e` in index order.
    #[inline]
    fn faces_on(&self, e: usize) -> FacesOn<'_, NF, NV, NE> {
        FacesOn {
            lp: self,
            e: e as u16,
            next: self.edge_face[e],
        }
    }

    /// Builds the per-vertex and per-edge face lists (index order) once
    /// every face and its sides are in place.
    fn link_faces(&mut self) {
        let mut last = [NONE; NV];
        let mut last_on = [NONE; NE];
        for v in 0..self.nv {
            self.face_first[v] = NONE;
        }
        for e in 0..self.ne {
            self.edge_face[e] = NONE;
        }
        for f in 0..self.nf {
            let q = self.face[f];
            let sides = self.side[f];
            self.face_next[f] = [NONE; 4];
            self.side_next[f] = [NONE; 4];
            for k in 0..4 {
                let e = sides[k] as usize;
                if sides[..k].contains(&sides[k]) {
                    continue;
                }
                if last_on[e] == NONE {
                    self.edge_face[e] = f as u16;
                } else {
                    let g = last_on[e] as usize;
                    let kg = self.side[g]
                        .iter()
                        .position(|&x| x as usize == e)
                        .unwrap_or(0);
                    self.side_next[g][kg] = f as u16;
                }
                last_on[e] = f as u16;
            }
            for k in 0..4 {
                let v = q[k] as usize;
                if q[..k].contains(&q[k]) {
                    continue;
                }
                if last[v] == NONE {
                    self.face_first[v] = f as u16;
                } else {
                    let g = last[v] as usize;
                    let kg = self.face[g]
                        .iter()
                        .position(|&x| x as usize == v)
                        .unwrap_or(0);
                    self.face_next[g][kg] = f as u16;
                }
                last[v] = f as u16;
            }
        }
    }

    /// Gathers level-1 face `face1` of `fm` and the faces around its corners.
    /// `base_face` names the face in errors.
    pub fn gather(fm: &FeatureMesh, face1: usize, base_face: u32) -> Result<Self, Error> {
        let mut lp = LocalPatch::empty();
        lp.gather_into(fm, face1, base_face)?;
        Ok(lp)
    }

    /// [`LocalPatch::gather`] into this patch (its contents replaced).
    pub fn gather_into(
        &mut self,
        fm: &FeatureMesh,
        face1: usize,
        base_face: u32,
    ) -> Result<(), Error> {
        let too_large = |_| Error::NeighbourhoodTooLarge { face: base_face };
        let adj = &fm.level1;
        let lp = self;
        lp.clear();
        // Global ids of the local vertices and faces, found through
        // open-addressing tables of local indices.
        let mut global = [u32::MAX; NV];
        let mut vertex_slots = [NONE; NV];
        let corners = adj.face(face1);
        let mut faces = [u32::MAX; NF];
        let mut face_slots = [NONE; NF];
        let mut nfaces = 0;
        let mut push_face = |f: u32, faces: &mut [u32; NF]| -> Result<(), Error> {
            match probe(&mut face_slots, f, |i| faces[i as usize]) {
                Probe::Found(_) => Ok(()),
                Probe::Empty(slot) if nfaces < NF => {
                    faces[nfaces] = f;
                    face_slots[slot] = nfaces as u16;
                    nfaces += 1;
                    Ok(())
                }
                _ => Err(Error::NeighbourhoodTooLarge { face: base_face }),
            }
        };
        push_face(face1 as u32, &mut faces)?;
        for &c in corners {
            for &f in adj.vertex_faces(c as usize) {
                push_face(f, &mut faces)?;
            }
        }
        for &f in &faces[..nfaces] {
            let fv = adj.face(f as usize);
            let mut q = [0u16; 4];
            for (k, &v) in fv.iter().enumerate() {
                let local = match probe(&mut vertex_slots, v, |i| global[i as usize]) {
                    Probe::Found(i) => i,
                    Probe::Full => return Err(Error::NeighbourhoodTooLarge { face: base_face }),
                    Probe::Empty(slot) => {
                        let i = lp
                            .add_vertex(
                                fm.point(v as usize),
                                fm.sharpness.vertex(v as usize),
                                fm.sharpness.end_stats(adj, v as usize),
                            )
                            .map_err(too_large)?;
                        global[i as usize] = v;
                        vertex_slots[slot] = i;
                        i
                    }
                };
                q[k] = local;
            }
            lp.add_face(q).map_err(too_large)?;
            let fi = lp.nf - 1;
            for (k, &e) in adj.face_edges(f as usize).iter().enumerate() {
                lp.side[fi][k] = lp
                    .add_edge(q[k], q[(k + 1) % 4], fm.sharpness.edge(e as usize))
                    .map_err(too_large)?;
            }
        }
        lp.link_faces();
        Ok(())
    }

    /// Local edges at vertex `v` (into `out`, returns the count).
    fn edges_at(&self, v: u16, out: &mut [u16]) -> usize {
        let mut n = 0;
        for e in self.edges_of(v) {
            if n < out.len() {
                out[n] = e as u16;
            }
            n += 1;
        }
        n
    }

    /// Local faces at vertex `v` (into `out`, returns the count).
    fn faces_at(&self, v: u16, out: &mut [u16]) -> usize {
        let mut n = 0;
        for f in self.faces_of(v) {
            if n < out.len() {
                out[n] = f as u16;
            }
            n += 1;
        }
        n
    }

    /// Faces on edge `e` (into `out`, returns the count).
    fn faces_of_edge(&self, e: usize, out: &mut [u16]) -> usize {
        let mut n = 0;
        for f in self.faces_on(e) {
            if n < out.len() {
                out[n] = f as u16;
            }
            n += 1;
        }
        n
    }

    fn far(&self, e: usize, v: u16) -> u16 {
        let [a, b] = self.edge[e];
        if a == v {
            b
        } else {
            a
        }
    }

    fn centroid(&self, f: usize) -> DVec3 {
        let q = self.face[f];
        (self.pos[q[0] as usize]
            + self.pos[q[1] as usize]
            + self.pos[q[2] as usize]
            + self.pos[q[3] as usize])
            * 0.25
    }

    fn half(&self, opts: &FeatureOptions, e: usize, end: u16) -> f32 {
        decay_at(opts.creasing, self.esharp[e], self.stats[end as usize])
    }

    /// Vertex point of local vertex `v` (all its edges and faces local).
    fn vertex_point(&self, opts: &FeatureOptions, v: u16) -> DVec3 {
        let mut es = [0u16; NE];
        let mut fs = [0u16; NE];
        let ne = self.edges_at(v, &mut es).min(es.len());
        let nf = self.faces_at(v, &mut fs).min(fs.len());
        let around = LocalAround {
            lp: self,
            v,
            es: &es[..ne],
            nf,
            opts,
        };
        let m = vertex_mask(opts.creasing, self.vsharp[v as usize], &around);
        let mut p = self.pos[v as usize] * m.vertex;
        for (i, &e) in es[..ne].iter().enumerate() {
            p += self.pos[self.far(e as usize, v) as usize] * m.edge_weight(i);
        }
        if m.each_face != 0.0 {
            for &f in &fs[..nf] {
                p += self.centroid(f as usize) * m.each_face;
            }
        }
        p
    }

    /// Edge point of local edge `e` (both ends' statistics known, all its
    /// faces local).
    fn edge_point(&self, opts: &FeatureOptions, e: usize) -> DVec3 {
        let [a, b] = self.edge[e];
        let mut fs = [0u16; NF];
        let nf = self.faces_of_edge(e, &mut fs);
        let halves = [self.half(opts, e, a), self.half(opts, e, b)];
        let m = edge_mask(opts, self.esharp[e], halves, nf, [false, false]);
        let mut p = (self.pos[a as usize] + self.pos[b as usize]) * m.end;
        for (k, &f) in fs[..nf].iter().enumerate() {
            p += self.centroid(f as usize) * m.face[k.min(1)];
        }
        p
    }

    /// One refinement step, keeping quadrant `q` (the child at corner `q`)
    /// and the faces around its corners.
    pub fn child(&self, opts: &FeatureOptions, q: usize) -> Result<Self, Full> {
        let mut out = LocalPatch::empty();
        self.child_into(opts, q, &mut out)?;
        Ok(out)
    }

    /// [`LocalPatch::child`] into `out` (its contents replaced), without
    /// a fresh patch per step.
    pub fn child_into(&self, opts: &FeatureOptions, q: usize, out: &mut Self) -> Result<(), Full> {
        let corners = self.corners();
        out.clear();
        // New vertex ids: per old vertex (vertex point), per old edge (edge
        // point), per old face (face point); NONE until created.
        let mut vv = [NONE; NV];
        let mut ev = [NONE; NE];
        let mut fv = [NONE; NF];
        out.nf = 1; // slot 0: the kept quadrant
        let child_corners = {
            let f0 = self.face[0];
            let e_next = self.side[0][q] as usize;
            let e_prev = self.side[0][(q + 3) % 4] as usize;
            (f0[q], e_next, e_prev)
        };
        for f in 0..self.nf {
            let k4 = self.face[f];
            for j in 0..4 {
                if !corners.contains(&k4[j]) {
                    continue;
                }
                let c = k4[j];
                let en = self.side[f][j] as usize;
                let ep = self.side[f][(j + 3) % 4] as usize;
                // Keep the child only if it touches a child corner.
                let touches = c == child_corners.0
                    || en == child_corners.1
                    || en == child_corners.2
                    || ep == child_corners.1
                    || ep == child_corners.2
                    || f == 0;
                if !touches {
                    continue;
                }
                let a = self.vertex_id(opts, out, &mut vv, c)?;
                let b = self.edge_id(opts, out, &mut ev, en)?;
                let m = self.face_id(out, &mut fv, f)?;
                let d = self.edge_id(opts, out, &mut ev, ep)?;
                let mut quad = [0u16; 4];
                quad[j] = a;
                quad[(j + 1) % 4] = b;
                quad[(j + 2) % 4] = m;
                quad[(j + 3) % 4] = d;
                // The kept quadrant of the patch is face 0 (reserved).
                let fi = if f == 0 && j == q {
                    out.face[0] = quad;
                    0
                } else {
                    out.add_face(quad)?;
                    out.nf - 1
                };
                // Sides from corner j of the quad: a-b, b-m, m-d, d-a.
                let sides = [
                    out.add_edge(a, b, self.half(opts, en, c))?,
                    out.add_edge(b, m, 0.0)?,
                    out.add_edge(m, d, 0.0)?,
                    out.add_edge(d, a, self.half(opts, ep, c))?,
                ];
                for (k, &e) in sides.iter().enumerate() {
                    out.side[fi][(j + k) % 4] = e;
                }
            }
        }
        out.link_faces();
        Ok(())
    }

    fn vertex_id(
        &self,
        opts: &FeatureOptions,
        out: &mut Self,
        vv: &mut [u16; NV],
        v: u16,
    ) -> Result<u16, Full> {
        if vv[v as usize] != NONE {
            return Ok(vv[v as usize]);
        }
        let st = EndStats::of(self.edges_of(v).map(|e| self.half(opts, e, v)));
        let id = out.add_vertex(
            self.vertex_point(opts, v),
            decrement(self.vsharp[v as usize]),
            st,
        )?;
        vv[v as usize] = id;
        Ok(id)
    }

    fn edge_id(
        &self,
        opts: &FeatureOptions,
        out: &mut Self,
        ev: &mut [u16; NE],
        e: usize,
    ) -> Result<u16, Full> {
        if ev[e] != NONE {
            return Ok(ev[e]);
        }
        let [a, b] = self.edge[e];
        let nf = self.faces_on(e).count();
        let halves = [self.half(opts, e, a), self.half(opts, e, b)];
        // Edges at the new edge point: the two halves and one per face.
        let mut st = EndStats::of(halves.iter().copied());
        st.edges += nf as u32;
        let id = out.add_vertex(self.edge_point(opts, e), 0.0, st)?;
        ev[e] = id;
        Ok(id)
    }

    fn face_id(&self, out: &mut Self, fv: &mut [u16; NF], f: usize) -> Result<u16, Full> {
        if fv[f] != NONE {
            return Ok(fv[f]);
        }
        let st = EndStats {
            edges: 4,
            ..EndStats::default()
        };
        let id = out.add_vertex(self.centroid(f), 0.0, st)?;
        fv[f] = id;
        Ok(id)
    }

    /// Whether corner `v` of face 0 lets the patch be a B-spline: no
    /// semi-sharp value at it, and smooth with four faces, or a crease whose
    /// sector containing face 0 has two faces, or a corner whose sector is
    /// face 0 alone.
    pub fn corner_is_regular(&self, v: u16) -> bool {
        if is_semi_sharp(self.vsharp[v as usize]) {
            return false;
        }
        let (mut ne, mut sharp) = (0, 0);
        for e in self.edges_of(v) {
            ne += 1;
            let s = self.esharp[e];
            if is_semi_sharp(s) {
                return false;
            }
            if is_infinite(s) {
                sharp += 1;
            }
        }
        let corner = is_infinite(self.vsharp[v as usize]) || sharp > 2;
        let sector = self.sector_size(v);
        if corner {
            return sector == 1;
        }
        match sharp {
            0 => ne == 4 && self.faces_of(v).count() == 4,
            2 => sector == 2,
            _ => false,
        }
    }

    /// Number of faces reachable from face 0 around `v` across non-sharp
    /// edges at `v`.
    fn sector_size(&self, v: u16) -> usize {
        let mut count = 1;
        for dir in 0..2 {
            let mut f = 0usize;
            for _ in 0..NF {
                let q = self.face[f];
                let k = match q.iter().position(|&x| x == v) {
                    Some(k) => k,
                    None => return 0,
                };
                // The edge from v to the next (dir 0) or previous corner.
                let e = self.side[f][if dir == 0 { k } else { (k + 3) % 4 }] as usize;
                if is_sharp(self.esharp[e]) {
                    break;
                }
                let mut fs = [0u16; 4];
                let n = self.faces_of_edge(e, &mut fs);
                if n != 2 {
                    break;
                }
                let g = if fs[0] as usize == f { fs[1] } else { fs[0] } as usize;
                if g == 0 {
                    // Went all the way round: a smooth fan.
                    return count;
                }
                f = g;
                count += 1;
            }
        }
        count
    }

    /// The face other than face 0 across the edge from `a` to `b` (corners
    /// of face 0): the two vertices following `a` in it, i.e. the outer
    /// neighbours of `a` and `b`.
    fn across(&self, a: u16, b: u16) -> Option<(u16, u16)> {
        for f in self.faces_of(a).filter(|&f| f != 0) {
            let q = self.face[f];
            for k in 0..4 {
                if q[k] == b && q[(k + 1) % 4] == a {
                    return Some((q[(k + 2) % 4], q[(k + 3) % 4]));
                }
            }
        }
        None
    }

    /// The corner opposite `c` in the face that contains `c`, `x` and `y`
    /// (other than face 0).
    fn diagonal(&self, c: u16, x: u16, y: u16) -> Option<u16> {
        for f in self.faces_of(c).filter(|&f| f != 0) {
            let q = self.face[f];
            if q.contains(&c) && q.contains(&x) && q.contains(&y) {
                let k = q.iter().position(|&z| z == c)?;
                return Some(q[(k + 2) % 4]);
            }
        }
        None
    }

    /// The 16 B-spline control points of face 0 (row by row, `i` along u)
    /// when every corner is regular, with phantoms across sharp sides.
    pub fn regular_grid(&self) -> Option<[DVec3; 16]> {
        let c = self.corners();
        if !c.iter().all(|&v| self.corner_is_regular(v)) {
            return None;
        }
        let mut sharp = [false; 4];
        for (s, sh) in sharp.iter_mut().enumerate() {
            let e = self.find_edge(c[s], c[(s + 1) % 4])?;
            *sh = is_sharp(self.esharp[e]);
        }
        let ids = self.grid_ids(sharp)?;
        let mut g = [DVec3::ZERO; 16];
        for (p, &id) in g.iter_mut().zip(&ids) {
            if id != NONE {
                *p = self.pos[id as usize];
            }
        }
        // Phantoms: columns first (rows 1, 2 and any real outer row), then
        // rows (all four columns).
        let p = |g: &[DVec3; 16], i: usize, j: usize| g[j * 4 + i];
        for j in 0..4 {
            if (j == 0 && sharp[0]) || (j == 3 && sharp[2]) {
                continue;
            }
            if sharp[3] {
                g[j * 4] = 2.0 * p(&g, 1, j) - p(&g, 2, j);
            }
            if sharp[1] {
                g[j * 4 + 3] = 2.0 * p(&g, 2, j) - p(&g, 1, j);
            }
        }
        for i in 0..4 {
            if sharp[0] {
                g[i] = 2.0 * p(&g, i, 1) - p(&g, i, 2);
            }
            if sharp[2] {
                g[12 + i] = 2.0 * p(&g, i, 2) - p(&g, i, 1);
            }
        }
        Some(g)
    }

    /// The local vertices of face 0's 4 x 4 control grid (row by row, `i`
    /// along u; [`NONE`] where a phantom goes): the corners, and across
    /// every side not marked `sharp` the two outer points of the face
    /// there, and at a corner between two such sides the diagonal point.
    fn grid_ids(&self, sharp: [bool; 4]) -> Option<[u16; 16]> {
        let c = self.corners();
        let mut g = [NONE; 16];
        // Corners at (1,1), (2,1), (2,2), (1,2).
        let at = [(1, 1), (2, 1), (2, 2), (1, 2)];
        for k in 0..4 {
            g[at[k].1 * 4 + at[k].0] = c[k];
        }
        // Sides: (from, to, outer point next to from, outer next to to).
        let sides = [
            ((1, 0), (2, 0)), // bottom: below c0, below c1
            ((3, 1), (3, 2)), // right
            ((2, 3), (1, 3)), // top
            ((0, 2), (0, 1)), // left
        ];
        let mut outer = [(NONE, NONE); 4];
        for s in 0..4 {
            if !sharp[s] {
                let (x, y) = self.across(c[s], c[(s + 1) % 4])?;
                outer[s] = (x, y);
                g[sides[s].0 .1 * 4 + sides[s].0 .0] = x;
                g[sides[s].1 .1 * 4 + sides[s].1 .0] = y;
            }
        }
        // Diagonal points where both adjacent sides are smooth: at corner k
        // between side k-1 (ending at k) and side k (starting at k).
        let diag = [(0, 0), (3, 0), (3, 3), (0, 3)];
        for k in 0..4 {
            let prev = (k + 3) % 4;
            if !sharp[prev] && !sharp[k] {
                let x = outer[k].0; // next to corner k on side k
                let y = outer[prev].1; // next to corner k on side k-1
                g[diag[k].1 * 4 + diag[k].0] = self.diagonal(c[k], x, y)?;
            }
        }
        Some(g)
    }

    /// When face 0 is a piece of a straight, uniformly semi-sharp crease
    /// (the tensor product of a B-spline along the crease and the
    /// one-dimensional crease rule across it, see [`super::strip`]): one
    /// side `s` of sharpness `0 < sigma < INFINITE`; its two corners each
    /// with four faces and four edges, no vertex sharpness, the side and
    /// the edge opposite it at that corner (the crease going on) of
    /// sharpness `sigma` bit for bit, the other two edges smooth; the
    /// other two corners smooth with four faces. Returns the side, `sigma`
    /// and the 4 x 4 control points (as for a B-spline: row by row, `i`
    /// along u; the crease runs along the grid line through the side).
    pub fn crease_strip(&self) -> Option<super::strip::CreaseStrip> {
        let c = self.corners();
        let mut found = None;
        for s in 0..4 {
            let x = self.esharp[self.find_edge(c[s], c[(s + 1) % 4])?];
            if is_sharp(x) {
                if found.is_some() || !is_semi_sharp(x) {
                    return None;
                }
                found = Some((s, x));
            }
        }
        let (side, sigma) = found?;
        for k in [(side + 2) % 4, (side + 3) % 4] {
            if self.corner_is_smooth(c[k]) != Some(4) {
                return None;
            }
        }
        let ids = self.grid_ids([false; 4])?;
        // The crease line through the side, in grid order: (before, first
        // corner, second corner, after).
        let line: [usize; 4] = match side {
            0 => [4, 5, 6, 7],
            1 => [2, 6, 10, 14],
            2 => [11, 10, 9, 8],
            _ => [13, 9, 5, 1],
        };
        let stats = EndStats {
            edges: 4,
            semi: 2,
            sum: sigma + sigma,
        };
        for (corner, next) in [(line[1], line[0]), (line[2], line[3])] {
            let v = ids[corner];
            let (mut ne, mut sharp) = (0, 0);
            for e in self.edges_of(v) {
                ne += 1;
                let x = self.esharp[e];
                if x.to_bits() == sigma.to_bits() {
                    sharp += 1;
                } else if x != 0.0 {
                    return None;
                }
            }
            let on = |w: usize| {
                self.find_edge(v, ids[w])
                    .is_some_and(|e| self.esharp[e].to_bits() == sigma.to_bits())
            };
            if ne != 4
                || sharp != 2
                || !on(next)
                || is_sharp(self.vsharp[v as usize])
                || self.faces_of(v).count() != 4
                || self.stats[v as usize] != stats
            {
                return None;
            }
        }
        let mut grid = [DVec3::ZERO; 16];
        for (p, &id) in grid.iter_mut().zip(&ids) {
            *p = self.pos[id as usize];
        }
        Some(super::strip::CreaseStrip { side, sigma, grid })
    }

    /// The largest semi-sharp value at the corners of face 0 (vertex or
    /// incident edge; 0 if none): the number of levels before every corner
    /// can be regular.
    pub fn corner_semi_sharpness(&self) -> f32 {
        let mut m = 0.0f32;
        for &v in &self.corners() {
            if is_semi_sharp(self.vsharp[v as usize]) {
                m = m.max(self.vsharp[v as usize]);
            }
            for e in self.edges_of(v) {
                if is_semi_sharp(self.esharp[e]) {
                    m = m.max(self.esharp[e]);
                }
            }
        }
        m
    }

    /// Whether corner `v` is smooth: vertex and incident edges not sharp at
    /// all, as many faces as edges (an interior manifold vertex).
    fn corner_is_smooth(&self, v: u16) -> Option<usize> {
        if is_sharp(self.vsharp[v as usize]) {
            return None;
        }
        let mut ne = 0;
        for e in self.edges_of(v) {
            if is_sharp(self.esharp[e]) {
                return None;
            }
            ne += 1;
        }
        (self.faces_of(v).count() == ne).then_some(ne)
    }

    /// When face 0 is a smooth extraordinary patch (Stam's case): one corner
    /// `r` smooth of valence `n != 4` (3..=`max_n`), the three others smooth
    /// of valence 4, no sharp value at any corner. Returns `r`, `n` and the
    /// 2n+8 control points in the label order of [`super::stencil`] (EV
    /// first, sectors counter-clockwise from face 0, outer points last), for
    /// the eigen-table kernel.
    pub fn stam_patch(&self, max_n: usize) -> Option<(usize, usize, [DVec3; MAX_K])> {
        let c = self.corners();
        let mut ev = None;
        for (k, &v) in c.iter().enumerate() {
            match self.corner_is_smooth(v)? {
                4 => {}
                n if (3..=max_n).contains(&n) && ev.is_none() => ev = Some((k, n)),
                _ => return None,
            }
        }
        let (r, n) = ev?;
        let mut pts = [DVec3::ZERO; MAX_K];
        let mut ids = [0u16; MAX_K];
        let v = c[r];
        pts[0] = self.pos[v as usize];
        // Sector i is the face with the directed edge V -> E_i.
        let mut e_i = c[(r + 1) % 4];
        for i in 0..n {
            // The first such face after face 0, else face 0.
            let sector = |f: usize| {
                let q = self.face[f];
                let kv = q.iter().position(|&z| z == v)?;
                (q[(kv + 1) % 4] == e_i).then_some((q[(kv + 2) % 4], q[(kv + 3) % 4]))
            };
            let (f_i, e_next) = self
                .faces_of(v)
                .filter(|&f| f != 0)
                .find_map(sector)
                .or_else(|| sector(0))?;
            pts[1 + 2 * i] = self.pos[e_i as usize];
            pts[2 + 2 * i] = self.pos[f_i as usize];
            ids[1 + 2 * i] = e_i;
            ids[2 + 2 * i] = f_i;
            e_i = e_next;
        }
        if e_i != c[(r + 1) % 4] {
            return None; // the fan did not close
        }
        // Outer points O_0..O_6 at (2,-1) (2,0) (2,1) (2,2) (1,2) (0,2) (-1,2).
        let (e0, f0, e1) = (c[(r + 1) % 4], c[(r + 2) % 4], c[(r + 3) % 4]);
        let (o1, o2) = self.across(e0, f0)?; // (2,0), (2,1)
        let (o4, o5) = self.across(f0, e1)?; // (1,2), (0,2)
        let o3 = self.diagonal(f0, o2, o4)?; // (2,2)
        let f_last = ids[2 + 2 * (n - 1)]; // (1,-1)
        let f_1 = ids[4]; // (-1,1)
        let o0 = self.diagonal(e0, o1, f_last)?; // (2,-1)
        let o6 = self.diagonal(e1, o5, f_1)?; // (-1,2)
        for (k, o) in [o0, o1, o2, o3, o4, o5, o6].iter().enumerate() {
            pts[2 * n + 1 + k] = self.pos[*o as usize];
        }
        Some((r, n, pts))
    }

    /// True when corner `v` and its edges carry no semi-sharp value (its
    /// one-ring then subdivides by a fixed matrix).
    pub fn corner_is_stationary(&self, v: u16) -> bool {
        if is_semi_sharp(self.vsharp[v as usize]) {
            return false;
        }
        self.edges_of(v).all(|e| !is_semi_sharp(self.esharp[e]))
    }

    /// Exact limit position of corner `k` of face 0 (which must be
    /// stationary). Smooth (valence 3 or more), crease and corner rules have
    /// closed-form limit masks (the left eigenvectors for eigenvalue 1 of
    /// their one-ring matrices: `(n^2 V + 4 sum E + sum F) / (n (n + 5))`,
    /// `(E_a + 4 V + E_b) / 6`, `V`); other configurations (darts, valence
    /// 2) iterate the corner's vertex point, which converges geometrically
    /// (ratio at most the subdominant eigenvalue), until it stops moving.
    pub fn corner_limit(&self, opts: &FeatureOptions, k: usize) -> Result<DVec3, Full> {
        let v = self.corners()[k];
        let mut es = [0u16; NE];
        let mut fs = [0u16; NF];
        let ne = self.edges_at(v, &mut es).min(NE);
        let nf = self.faces_at(v, &mut fs).min(NF);
        let p = self.pos[v as usize];
        if nf == 0 {
            return Ok(p);
        }
        let sharp = es[..ne]
            .iter()
            .filter(|&&e| is_sharp(self.esharp[e as usize]))
            .count();
        let vs = self.vsharp[v as usize];
        if is_sharp(vs) || sharp > 2 {
            return Ok(p);
        }
        if sharp == 2 {
            let mut acc = p * (2.0 / 3.0);
            for &e in &es[..ne] {
                if is_sharp(self.esharp[e as usize]) {
                    acc += self.pos[self.far(e as usize, v) as usize] * (1.0 / 6.0);
                }
            }
            return Ok(acc);
        }
        if sharp == 0 && nf == ne && nf >= 3 {
            let n = nf as f64;
            let mut acc = p * (n * n);
            for &e in &es[..ne] {
                acc += self.pos[self.far(e as usize, v) as usize] * 4.0;
            }
            for &f in &fs[..nf] {
                let q = self.face[f as usize];
                let kv = q.iter().position(|&z| z == v).unwrap_or(0);
                acc += self.pos[q[(kv + 2) % 4] as usize];
            }
            return Ok(acc / (n * (n + 5.0)));
        }
        // Darts and valence 2: iterate the vertex point to its fixed point.
        let mut cur = self.clone();
        let mut last = p;
        let scale = (0..self.nv)
            .map(|i| (self.pos[i] - p).length())
            .fold(0.0f64, f64::max)
            .max(p.length());
        let mut calm = 0;
        for _ in 0..4000 {
            cur = cur.child(opts, k)?;
            let now = cur.pos[cur.corners()[k] as usize];
            if (now - last).length() <= 1e-17 * scale {
                calm += 1;
                if calm == 3 {
                    return Ok(now);
                }
            } else {
                calm = 0;
            }
            last = now;
        }
        Ok(last)
    }
}

/// Sharpness around a local vertex, for [`vertex_mask`].
struct LocalAround<'p, const NF: usize, const NV: usize, const NE: usize> {
    lp: &'p LocalPatch<NF, NV, NE>,
    v: u16,
    es: &'p [u16],
    nf: usize,
    opts: &'p FeatureOptions,
}

impl<const NF: usize, const NV: usize, const NE: usize> Around for LocalAround<'_, NF, NV, NE> {
    fn edges(&self) -> usize {
        self.es.len()
    }
    fn faces(&self) -> usize {
        self.nf
    }
    fn sharpness(&self, i: usize) -> f32 {
        self.lp.esharp[self.es[i] as usize]
    }
    fn child_sharpness(&self, i: usize) -> f32 {
        self.lp.half(self.opts, self.es[i] as usize, self.v)
    }
}

/// The edges at one vertex of a [`LocalPatch`], in index order.
struct EdgesAt<'p, const NF: usize, const NV: usize, const NE: usize> {
    lp: &'p LocalPatch<NF, NV, NE>,
    v: u16,
    next: u16,
}

impl<const NF: usize, const NV: usize, const NE: usize> Iterator for EdgesAt<'_, NF, NV, NE> {
    type Item = usize;
    #[inline]
    fn next(&mut self) -> Option<usize> {
        if self.next == NONE {
            return None;
        }
        let e = self.next as usize;
        let k = usize::from(self.lp.edge[e][0] != self.v);
        self.next = self.lp.edge_next[e][k];
        Some(e)
    }
}

/// The faces at one vertex of a [`LocalPatch`], in index order.
struct FacesAt<'p, const NF: usize, const NV: usize, const NE: usize> {
    lp: &'p LocalPatch<NF, NV, NE>,
    v: u16,
    next: u16,
}

impl<const NF: usize, const NV: usize, const NE: usize> Iterator for FacesAt<'_, NF, NV, NE> {
    type Item = usize;
    #[inline]
    fn next(&mut self) -> Option<usize> {
        if self.next == NONE {
            return None;
        }
        let f = self.next as usize;
        let q = self.lp.face[f];
        let k = q.iter().position(|&x| x == self.v).unwrap_or(0);
        self.next = self.lp.face_next[f][k];
        Some(f)
    }
}

/// The faces on one edge of a [`LocalPatch`], in index order.
struct FacesOn<'p, const NF: usize, const NV: usize, const NE: usize> {
    lp: &'p LocalPatch<NF, NV, NE>,
    e: u16,
    next: u16,
}

impl<const NF: usize, const NV: usize, const NE: usize> Iterator for FacesOn<'_, NF, NV, NE> {
    type Item = usize;
    #[inline]
    fn next(&mut self) -> Option<usize> {
        if self.next == NONE {
            return None;
        }
        let f = self.next as usize;
        let k = self.lp.side[f]
            .iter()
            .position(|&x| x == self.e)
            .unwrap_or(0);
        self.next = self.lp.side_next[f][k];
        Some(f)
    }
}

/// The outcome of looking a key up in an open-addressing table of local
/// indices.
enum Probe {
    /// The key's local index.
    Found(u16),
    /// Not there; this free slot takes it.
    Empty(usize),
    /// Not there and no free slot.
    Full,
}

/// Looks `key` up in `table` (slots hold local indices or [`NONE`]; `key_of`
/// gives the key of a local index), by linear probing from a
/// multiplicative hash.
#[inline]
fn probe<const N: usize>(table: &mut [u16; N], key: u32, key_of: impl Fn(u16) -> u32) -> Probe {
    let start = ((key.wrapping_mul(0x9E37_79B9) as u64 * N as u64) >> 32) as usize;
    for i in 0..N {
        let slot = (start + i) % N;
        match table[slot] {
            NONE => return Probe::Empty(slot),
            id if key_of(id) == key => return Probe::Found(id),
            _ => {}
        }
    }
    Probe::Full
}
