//! The mesh Boolean: edge twins, a hierarchy over B, every crossing
//! triangle pair by exact predicates, the crossing points named by
//! (edge, triangle) and merged by sorting their names, inside/outside of
//! every piece (segment side, then flooding over uncut edges, then an exact
//! ray parity for untouched components), counting and emission.

use super::adjacency::build_twins;
use super::bvh::{node_capacity, Bvh};
use super::pairs::{intersect, Contact};
use super::pieces::{degenerate, split, Cut, Scratch, Seg, SidePoint, MAX_SEGS, POINT};
use super::predicates::orient3d;
use super::{
    Counts, Crossing, FaceSource, Op, Options, Output, PatchTriangle, SolidMesh, Stats, UvTriangle,
};
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use glam::DVec3;

const UNKNOWN: u32 = 0;
const INSIDE: u32 = 1;
const OUTSIDE: u32 = 2;
const CUT: u32 = 3;
const KIND_B_EDGE: u64 = 1 << 63;

/// Working arrays of one cut triangle (its segments, side points and the
/// splitting scratch), made once per pass over the triangles and reused:
/// every triangle writes the prefix it reads.
struct TriScratch {
    segs: [Seg; MAX_SEGS],
    sps: [SidePoint; 2 * MAX_SEGS],
    split: Scratch,
}

impl TriScratch {
    fn new() -> Self {
        Self {
            segs: [Seg::default(); MAX_SEGS],
            sps: [SidePoint::default(); 2 * MAX_SEGS],
            split: Scratch::new(),
        }
    }
}

/// One solid's arrays.
struct Side<'a> {
    twin: &'a mut [u32],
    class: &'a mut [u32],
    start: &'a mut [u32],
    vmap: &'a mut [u32],
}

/// The Boolean of two closed triangle meshes, built in a caller block.
pub struct Boolean<'a> {
    a: SolidMesh<'a>,
    b: SolidMesh<'a>,
    op: Op,
    sa: Side<'a>,
    sb: Side<'a>,
    pair_a: &'a mut [u32],
    pair_b: &'a mut [u32],
    pair_pt: &'a mut [u32],
    b_perm: &'a mut [u32],
    end_key: &'a mut [u64],
    end_pos: &'a mut [f64],
    end_t: &'a mut [f64],
    pt_first: &'a mut [u32],
    pt_ends: &'a mut [u32],
    pt_seen: &'a mut [u32],
    pairs: usize,
    points: usize,
    counts: Counts,
    stats: Stats,
}

fn base_layout(a: &SolidMesh, b: &SolidMesh) -> Layout {
    let (ta, tb) = (a.triangles.len() / 3, b.triangles.len() / 3);
    let tm = ta.max(tb);
    let nodes = node_capacity(tb);
    let mut l = Layout::default();
    for (t, v) in [(ta, a.positions.len() / 3), (tb, b.positions.len() / 3)] {
        l.u32s(3 * t); // twin
        l.u32s(t); // class
        l.u32s(t + 1); // start
        l.u32s(v); // vmap
    }
    l.raw(8 * 3 * tm); // twin keys, then B's triangle centres
    l.u32s(3 * tm); // twin order, later the flood queue
    l.u32s(tb); // bvh perm
    l.f64s(6 * nodes);
    l.u32s(nodes);
    l.u32s(nodes);
    l
}

fn pair_layout(l: &mut Layout, p: usize) {
    l.u32s(p); // pair_a
    l.u32s(p); // pair_b
    l.u32s(2 * p); // pair_pt
    l.u32s(p); // b_perm
    l.raw(8 * 2 * p); // end_key
    l.f64s(6 * p); // end_pos
    l.f64s(2 * p); // end_t
    l.u32s(2 * p); // pt_first
    l.u32s(4 * p); // pt_ends
    l.u32s(2 * p); // pt_seen
}

fn check_mesh(m: &SolidMesh) -> Result<(), Error> {
    let nv = m.positions.len() / 3;
    if nv == 0 || m.triangles.is_empty() {
        return Err(Error::EmptyMesh);
    }
    if !m.positions.len().is_multiple_of(3)
        || !m.triangles.len().is_multiple_of(3)
        || nv >= POINT as usize
    {
        return Err(Error::InvalidArgument(
            "boolean: positions and triangles must come in triples",
        ));
    }
    if let Some(v) = (0..nv).find(|&v| !m.positions[3 * v..3 * v + 3].iter().all(|x| x.is_finite()))
    {
        return Err(Error::NonFiniteCoordinate { vertex: v as u32 });
    }
    for (i, &v) in m.triangles.iter().enumerate() {
        if v as usize >= nv {
            return Err(Error::IndexOutOfRange {
                face: (i / 3) as u32,
                vertex: v,
            });
        }
    }
    Ok(())
}

impl<'a> Boolean<'a> {
    /// Bytes of the block before the crossings are known (the block must
    /// hold at least these; [`Boolean::build`] then reports the exact total
    /// through [`Error::BufferTooSmall`] if the crossings need more).
    pub fn required_bytes_base(a: &SolidMesh, b: &SolidMesh) -> usize {
        base_layout(a, b).bytes()
    }

    /// Exact bytes of [`Boolean::build`] when `a` and `b` have `pairs`
    /// crossing triangle pairs ([`Counts::crossing_pairs`]): a caller that
    /// knows the count, or an upper bound of it (e.g. from a previous
    /// Boolean of nearby tessellations), builds once; with fewer pairs the
    /// block is larger than needed, with more `build` reports the exact
    /// size.
    pub fn required_bytes_with_pairs(a: &SolidMesh, b: &SolidMesh, pairs: usize) -> usize {
        let mut l = base_layout(a, b);
        pair_layout(&mut l, pairs);
        l.bytes()
    }

    /// Builds the Boolean `op` of `a` and `b` (closed, consistently
    /// oriented triangle meshes, counter-clockwise seen from outside) in
    /// `mem`. A block shorter than needed is `BufferTooSmall { required }`
    /// with the exact size for these inputs.
    pub fn build(
        a: SolidMesh<'a>,
        b: SolidMesh<'a>,
        op: Op,
        opts: Options,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        check_mesh(&a)?;
        check_mesh(&b)?;
        if opts.max_amplification.is_nan() || opts.max_amplification < 1.0 {
            return Err(Error::InvalidArgument(
                "boolean: max_amplification must be at least 1",
            ));
        }
        let base = base_layout(&a, &b);
        if mem.len() * 8 < base.bytes() {
            return Err(Error::BufferTooSmall {
                required: base.bytes(),
            });
        }
        let (ta, tb) = (a.triangles.len() / 3, b.triangles.len() / 3);
        let tm = ta.max(tb);
        let nodes = node_capacity(tb);
        let have = mem.len() * 8;
        let mut ar = Arena::new(mem);
        let side = |ar: &mut Arena<'a>, t: usize, v: usize| Side {
            twin: ar.u32s(3 * t),
            class: ar.u32s(t),
            start: ar.u32s(t + 1),
            vmap: ar.u32s(v),
        };
        let mut sa = side(&mut ar, ta, a.positions.len() / 3);
        let mut sb = side(&mut ar, tb, b.positions.len() / 3);
        let keys = ar.words(8 * 3 * tm);
        let order = ar.u32s(3 * tm);
        build_twins(&a, sa.twin, keys, order)?;
        build_twins(&b, sb.twin, keys, order)?;
        let mut bvh = Bvh {
            perm: ar.u32s(tb),
            boxes: ar.f64s(6 * nodes),
            first: ar.u32s(nodes),
            count: ar.u32s(nodes),
            nodes: 0,
        };
        // The twin keys are free again: the centres of B's triangles.
        bvh.build(&b, keys);
        // Count the crossing pairs.
        let mut p = 0usize;
        for_pairs(&a, &b, &bvh, &mut |_, _, _| {
            p += 1;
            Ok(())
        })?;
        let mut full = base;
        pair_layout(&mut full, p);
        if have < full.bytes() {
            return Err(Error::BufferTooSmall {
                required: full.bytes(),
            });
        }
        let pair_a = ar.u32s(p);
        let pair_b = ar.u32s(p);
        let pair_pt = ar.u32s(2 * p);
        let b_perm = ar.u32s(p);
        let end_key = ar.words(8 * 2 * p);
        let end_pos = ar.f64s(6 * p);
        let end_t = ar.f64s(2 * p);
        let pt_first = ar.u32s(2 * p);
        let pt_ends = ar.u32s(4 * p);
        let pt_seen = ar.u32s(2 * p);
        let mut i = 0usize;
        let mut stats = Stats::default();
        for_pairs(&a, &b, &bvh, &mut |ia, ib, ends| {
            pair_a[i] = ia as u32;
            pair_b[i] = ib as u32;
            let (ta3, tb3) = (a.tri(ia), b.tri(ib));
            for (e, pe) in ends.iter().enumerate() {
                let (own, tri, twin, other) = if pe.edge_of_a {
                    (ia, &ta3, &*sa.twin, ib)
                } else {
                    (ib, &tb3, &*sb.twin, ia)
                };
                let s = 3 * own + pe.side;
                let c = s.min(twin[s] as usize);
                let kind = if pe.edge_of_a { 0 } else { KIND_B_EDGE };
                let k = 2 * i + e;
                end_key[k] = kind | ((c as u64) << 32) | other as u64;
                end_t[k] = if s == c { pe.t } else { 1.0 - pe.t };
                let (p0, p1) = (tri[pe.side], tri[(pe.side + 1) % 3]);
                let x = p0 + (p1 - p0) * pe.t;
                end_pos[3 * k..3 * k + 3].copy_from_slice(&x.to_array());
            }
            let amp = amplification(&a, &b, ia, ib, op);
            if amp > stats.amplification {
                stats.amplification = amp;
                stats.worst = [ia as u32, ib as u32];
            }
            i += 1;
            Ok(())
        })?;
        if stats.amplification > opts.max_amplification {
            return Err(Error::NearTangential {
                face_a: u32::MAX,
                face_b: u32::MAX,
                triangle_a: stats.worst[0],
                triangle_b: stats.worst[1],
            });
        }
        // Merge the ends into points by their names.
        for (k, o) in pt_seen.iter_mut().enumerate().take(2 * p) {
            *o = k as u32;
        }
        pt_seen[..2 * p].sort_unstable_by_key(|&k| end_key[k as usize]);
        let mut q = 0usize;
        let mut j = 0;
        while j < 2 * p {
            let k0 = pt_seen[j] as usize;
            let mut m = j;
            while m < 2 * p && end_key[pt_seen[m] as usize] == end_key[k0] {
                pair_pt[pt_seen[m] as usize] = q as u32;
                m += 1;
            }
            if m - j != 2 {
                let pr = k0 / 2;
                return Err(degenerate(
                    pair_a[pr],
                    pair_b[pr],
                    "the intersection curve does not close up",
                ));
            }
            pt_first[q] = k0 as u32;
            pt_ends[2 * q] = pt_seen[j];
            pt_ends[2 * q + 1] = pt_seen[j + 1];
            q += 1;
            j = m;
        }
        // Pairs per triangle: A in order, B by a counting sort.
        for &t in pair_a.iter() {
            sa.start[t as usize + 1] += 1;
        }
        for &t in pair_b.iter() {
            sb.start[t as usize + 1] += 1;
        }
        for s in [&mut sa, &mut sb] {
            for t in 1..s.start.len() {
                s.start[t] += s.start[t - 1];
            }
        }
        for (i, &t) in pair_b.iter().enumerate() {
            let t = t as usize;
            b_perm[sb.start[t] as usize] = i as u32;
            sb.start[t] += 1;
        }
        for t in (1..=tb).rev() {
            sb.start[t] = sb.start[t - 1];
        }
        sb.start[0] = 0;
        let mut me = Boolean {
            a,
            b,
            op,
            sa,
            sb,
            pair_a,
            pair_b,
            pair_pt,
            b_perm,
            end_key,
            end_pos,
            end_t,
            pt_first,
            pt_ends,
            pt_seen,
            pairs: p,
            points: q,
            counts: Counts::default(),
            stats,
        };
        me.classify(true, order)?;
        me.classify(false, order)?;
        me.count()?;
        Ok(me)
    }

    /// Sizes of the output.
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// Crossing statistics.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Every crossing triangle pair (one curve segment each), with its
    /// amplification and the segment's ends: for error bounds that vary
    /// along the curve (per-triangle tessellation bounds, see the module
    /// docs).
    pub fn crossings(&self, f: &mut impl FnMut(Crossing)) {
        for i in 0..self.pairs {
            let (ia, ib) = (self.pair_a[i] as usize, self.pair_b[i] as usize);
            let end = |k: usize| DVec3::from_slice(&self.end_pos[3 * k..3 * k + 3]);
            f(Crossing {
                triangle_a: ia as u32,
                triangle_b: ib as u32,
                amplification: amplification(&self.a, &self.b, ia, ib, self.op),
                ends: [end(2 * i), end(2 * i + 1)],
            });
        }
    }

    fn mesh(&self, is_a: bool) -> &SolidMesh<'a> {
        if is_a {
            &self.a
        } else {
            &self.b
        }
    }

    fn point_pos(&self, q: usize) -> DVec3 {
        let k = self.pt_first[q] as usize;
        DVec3::from_slice(&self.end_pos[3 * k..3 * k + 3])
    }

    /// Segments and side points of triangle `t` of A (`is_a`) or B.
    fn cut_of(
        &self,
        is_a: bool,
        t: usize,
        segs: &mut [Seg; MAX_SEGS],
        sps: &mut [SidePoint; 2 * MAX_SEGS],
    ) -> Result<(usize, usize), Error> {
        let s = if is_a { &self.sa } else { &self.sb };
        let (lo, hi) = (s.start[t] as usize, s.start[t + 1] as usize);
        let mut ns = 0;
        let mut np = 0;
        for j in lo..hi {
            let pr = if is_a { j } else { self.b_perm[j] as usize };
            let other = if is_a {
                self.pair_b[pr]
            } else {
                self.pair_a[pr]
            };
            if ns == MAX_SEGS {
                let (ta, tb) = if is_a {
                    (t as u32, other)
                } else {
                    (other, t as u32)
                };
                return Err(degenerate(ta, tb, "too many crossings in one triangle"));
            }
            let r0 = POINT | self.pair_pt[2 * pr];
            let r1 = POINT | self.pair_pt[2 * pr + 1];
            segs[ns] = Seg { p: [r0, r1], other };
            ns += 1;
            for e in 0..2 {
                let k = 2 * pr + e;
                let key = self.end_key[k];
                if ((key & KIND_B_EDGE) == 0) != is_a {
                    continue;
                }
                let c = ((key >> 32) & 0x7fff_ffff) as usize;
                let Some(side) = (0..3).find(|&j| {
                    let sd = 3 * t + j;
                    sd.min(s.twin[sd] as usize) == c
                }) else {
                    continue;
                };
                let canonical = 3 * t + side == c;
                let r = POINT | self.pair_pt[k];
                let tt = self.end_t[self.pt_first[(r & !POINT) as usize] as usize];
                sps[np] = SidePoint {
                    r,
                    side: side as u8,
                    t: if canonical { tt } else { -tt },
                    tie: if canonical { r } else { !r },
                };
                np += 1;
            }
        }
        Ok((ns, np))
    }

    /// Runs the split of a cut triangle.
    fn split_tri(
        &self,
        is_a: bool,
        t: usize,
        scratch: &mut TriScratch,
        emit: &mut impl FnMut([u32; 3], bool),
    ) -> Result<[Option<bool>; 3], Error> {
        let TriScratch {
            segs,
            sps,
            split: work,
        } = scratch;
        let (ns, np) = self.cut_of(is_a, t, segs, sps)?;
        let m = self.mesh(is_a);
        let other = self.mesh(!is_a);
        let normal = m.normal(t);
        let cut = Cut {
            corners: [
                m.triangles[3 * t],
                m.triangles[3 * t + 1],
                m.triangles[3 * t + 2],
            ],
            segs: &segs[..ns],
            side_points: &sps[..np],
        };
        let pos = |r: u32| {
            if r & POINT != 0 {
                self.point_pos((r & !POINT) as usize)
            } else {
                m.point(r)
            }
        };
        let outside = |g: &Seg, u: u32, v: u32| {
            let d = pos(v) - pos(u);
            normal.cross(d).dot(other.normal(g.other as usize)) > 0.0
        };
        split(&cut, normal, &pos, &outside, work, emit).map_err(|w| {
            let o = segs[0].other;
            if is_a {
                degenerate(t as u32, o, w)
            } else {
                degenerate(o, t as u32, w)
            }
        })
    }

    /// Inside/outside of every triangle of one solid.
    fn classify(&mut self, is_a: bool, queue: &mut [u32]) -> Result<(), Error> {
        let nt = self.mesh(is_a).triangles.len() / 3;
        let mut head = 0;
        let mut tail = 0;
        let mut scratch = TriScratch::new();
        for t in 0..nt {
            let s = if is_a { &self.sa } else { &self.sb };
            if s.start[t] == s.start[t + 1] {
                continue;
            }
            let sides = self.split_tri(is_a, t, &mut scratch, &mut |_, _| {})?;
            let s = if is_a { &mut self.sa } else { &mut self.sb };
            s.class[t] = CUT;
            for (k, c) in sides.iter().enumerate() {
                let Some(out) = c else { continue };
                let n = s.twin[3 * t + k] as usize / 3;
                let want = if *out { OUTSIDE } else { INSIDE };
                if s.start[n] != s.start[n + 1] {
                    continue;
                }
                if s.class[n] == UNKNOWN {
                    s.class[n] = want;
                    queue[tail] = n as u32;
                    tail += 1;
                } else if s.class[n] != want {
                    return Err(self.inconsistent(is_a, t));
                }
            }
        }
        let mut next_seed = 0;
        loop {
            while head < tail {
                let t = queue[head] as usize;
                head += 1;
                let s = if is_a { &mut self.sa } else { &mut self.sb };
                let c = s.class[t];
                for k in 0..3 {
                    let n = s.twin[3 * t + k] as usize / 3;
                    if s.class[n] == UNKNOWN {
                        s.class[n] = c;
                        queue[tail] = n as u32;
                        tail += 1;
                    } else if s.class[n] != c && s.class[n] != CUT {
                        return Err(self.inconsistent(is_a, t));
                    }
                }
            }
            // A component the other surface does not cross: ray parity.
            let s = if is_a { &self.sa } else { &self.sb };
            while next_seed < nt && s.class[next_seed] != UNKNOWN {
                next_seed += 1;
            }
            if next_seed == nt {
                return Ok(());
            }
            let m = self.mesh(is_a);
            let v = m.point(m.triangles[3 * next_seed]);
            let inside = ray_parity(v, self.mesh(!is_a));
            let s = if is_a { &mut self.sa } else { &mut self.sb };
            s.class[next_seed] = if inside { INSIDE } else { OUTSIDE };
            queue[tail] = next_seed as u32;
            tail += 1;
        }
    }

    fn inconsistent(&self, is_a: bool, t: usize) -> Error {
        let (ta, tb) = if is_a {
            (t as u32, u32::MAX)
        } else {
            (u32::MAX, t as u32)
        };
        degenerate(ta, tb, "inconsistent inside/outside classification")
    }

    /// Keep rule and orientation of a piece.
    fn keep(&self, is_a: bool, outside: bool) -> (bool, bool) {
        match (self.op, is_a) {
            (Op::Union, _) => (outside, false),
            (Op::Intersection, _) => (!outside, false),
            (Op::Difference, true) => (outside, false),
            (Op::Difference, false) => (!outside, true),
        }
    }

    /// Calls `f(is_a, source triangle, triangle, reversed)` for every kept
    /// triangle.
    fn for_kept(&self, f: &mut impl FnMut(bool, usize, [u32; 3], bool)) -> Result<(), Error> {
        let mut scratch = TriScratch::new();
        for is_a in [true, false] {
            let m = self.mesh(is_a);
            let s = if is_a { &self.sa } else { &self.sb };
            for t in 0..m.triangles.len() / 3 {
                let c = s.class[t];
                if c == CUT {
                    self.split_tri(is_a, t, &mut scratch, &mut |tri, out| {
                        let (k, rev) = self.keep(is_a, out);
                        if k {
                            f(is_a, t, tri, rev);
                        }
                    })?;
                } else {
                    let (k, rev) = self.keep(is_a, c == OUTSIDE);
                    if k {
                        let tri = [
                            m.triangles[3 * t],
                            m.triangles[3 * t + 1],
                            m.triangles[3 * t + 2],
                        ];
                        f(is_a, t, tri, rev);
                    }
                }
            }
        }
        Ok(())
    }

    fn count(&mut self) -> Result<(), Error> {
        let mut tris = 0usize;
        // Mark used vertices (vmap = 1), then number them.
        let mut marks: [&mut [u32]; 2] = [&mut [], &mut []];
        {
            let (va, vb) = (
                core::mem::take(&mut self.sa.vmap),
                core::mem::take(&mut self.sb.vmap),
            );
            marks[0] = va;
            marks[1] = vb;
        }
        let res = self.for_kept(&mut |is_a, _, tri, _| {
            tris += 1;
            let mk = &mut marks[if is_a { 0 } else { 1 }];
            for r in tri {
                if r & POINT == 0 {
                    mk[r as usize] = 1;
                }
            }
        });
        let [va, vb] = marks;
        self.sa.vmap = va;
        self.sb.vmap = vb;
        res?;
        let mut n = 0u32;
        for s in [&mut self.sa, &mut self.sb] {
            for x in s.vmap.iter_mut() {
                if *x == 1 {
                    *x = n;
                    n += 1;
                } else {
                    *x = u32::MAX;
                }
            }
        }
        // Curve loops.
        let mut loops = 0;
        self.walk_curve(&mut |_, first| {
            if first {
                loops += 1;
            }
        });
        self.counts = Counts {
            vertices: n as usize + self.points,
            triangles: tris,
            curve_loops: loops,
            curve_points: self.points,
            crossing_pairs: self.pairs,
        };
        Ok(())
    }

    /// Calls `f(point, starts_a_loop)` along every closed curve.
    fn walk_curve(&mut self, f: &mut impl FnMut(usize, bool)) {
        self.pt_seen[..self.points].fill(0);
        for q0 in 0..self.points {
            if self.pt_seen[q0] != 0 {
                continue;
            }
            let mut q = q0;
            let mut via = self.pt_ends[2 * q0] as usize / 2; // arriving pair
            let mut first = true;
            while self.pt_seen[q] == 0 {
                self.pt_seen[q] = 1;
                f(q, first);
                first = false;
                let e0 = self.pt_ends[2 * q] as usize;
                let e1 = self.pt_ends[2 * q + 1] as usize;
                let out = if e0 / 2 == via { e1 } else { e0 };
                let pr = out / 2;
                let other_end = 2 * pr + (1 - out % 2);
                via = pr;
                q = self.pair_pt[other_end] as usize;
            }
        }
    }

    /// Writes the output; each buffer must hold at least the counted size
    /// (else `BufferTooSmall { required }` in elements of the first short
    /// buffer, and nothing is written).
    pub fn emit(&mut self, out: Output) -> Result<(), Error> {
        let c = self.counts;
        let checks = [
            (out.positions.len(), 3 * c.vertices),
            (out.triangles.len(), 3 * c.triangles),
            (out.curve_sizes.len(), c.curve_loops),
            (out.curve_indices.len(), c.curve_points),
            (
                out.sources.as_ref().map_or(usize::MAX, |s| s.len()),
                c.triangles,
            ),
        ];
        for (have, need) in checks {
            if have < need {
                return Err(Error::BufferTooSmall { required: need });
            }
        }
        for (is_a, s) in [(true, &self.sa), (false, &self.sb)] {
            let m = self.mesh(is_a);
            for (v, &o) in s.vmap.iter().enumerate() {
                if o != u32::MAX {
                    let o = o as usize;
                    out.positions[3 * o..3 * o + 3].copy_from_slice(&m.positions[3 * v..3 * v + 3]);
                }
            }
        }
        let base = c.vertices - self.points;
        for q in 0..self.points {
            let o = base + q;
            out.positions[3 * o..3 * o + 3].copy_from_slice(&self.point_pos(q).to_array());
        }
        let mut i = 0usize;
        let (tris, mut sources) = (out.triangles, out.sources);
        let (vma, vmb) = (&*self.sa.vmap, &*self.sb.vmap);
        self.for_kept(&mut |is_a, src, tri, rev| {
            let map = |r: u32| {
                if r & POINT != 0 {
                    (base + (r & !POINT) as usize) as u32
                } else if is_a {
                    vma[r as usize]
                } else {
                    vmb[r as usize]
                }
            };
            let t = if rev {
                [map(tri[0]), map(tri[2]), map(tri[1])]
            } else {
                [map(tri[0]), map(tri[1]), map(tri[2])]
            };
            tris[3 * i..3 * i + 3].copy_from_slice(&t);
            if let Some(s) = sources.as_deref_mut() {
                s[i] = FaceSource {
                    solid: if is_a { 0 } else { 1 },
                    triangle: src as u32,
                };
            }
            i += 1;
        })?;
        let (sizes, idx) = (out.curve_sizes, out.curve_indices);
        let mut nl = 0usize;
        let mut np = 0usize;
        self.walk_curve(&mut |q, first| {
            if first {
                sizes[nl] = 0;
                nl += 1;
            }
            sizes[nl - 1] += 1;
            idx[np] = (base + q) as u32;
            np += 1;
        });
        Ok(())
    }
}

impl Boolean<'_> {
    /// Writes the parameter-space provenance of every output triangle
    /// (same order as the triangles of [`Boolean::emit`]) into `out`
    /// (at least [`Counts::triangles`] entries, else `BufferTooSmall`,
    /// nothing written). `a_uv` and `b_uv` hold one [`PatchTriangle`] per
    /// input triangle of A and B (shorter: `InvalidArgument`). A kept
    /// tessellation vertex takes its source triangle's `(u, v)`; a curve
    /// point takes the barycentric combination of the source triangle's
    /// three `(u, v)`, its barycentric coordinates computed from its
    /// position in the triangle's plane.
    pub fn emit_uv(
        &self,
        a_uv: &[PatchTriangle],
        b_uv: &[PatchTriangle],
        out: &mut [UvTriangle],
    ) -> Result<(), Error> {
        if a_uv.len() < self.a.triangles.len() / 3 || b_uv.len() < self.b.triangles.len() / 3 {
            return Err(Error::InvalidArgument(
                "boolean: one parameter triangle per input triangle needed",
            ));
        }
        let need = self.counts.triangles;
        if out.len() < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        let mut i = 0usize;
        self.for_kept(&mut |is_a, src, tri, rev| {
            let m = self.mesh(is_a);
            let pt = if is_a { &a_uv[src] } else { &b_uv[src] };
            let corners = m.tri(src);
            let uv_of = |r: u32| -> [f64; 2] {
                let w = if r & POINT == 0 {
                    let mut w = [0.0; 3];
                    if let Some(k) = (0..3).find(|&k| m.triangles[3 * src + k] == r) {
                        w[k] = 1.0;
                    }
                    w
                } else {
                    barycentric(self.point_pos((r & !POINT) as usize), &corners)
                };
                let mut uv = [0.0; 2];
                for (k, wk) in w.iter().enumerate() {
                    uv[0] += wk * pt.uv[2 * k];
                    uv[1] += wk * pt.uv[2 * k + 1];
                }
                uv
            };
            let order = if rev { [0, 2, 1] } else { [0, 1, 2] };
            let mut uv = [0.0; 6];
            for (k, &o) in order.iter().enumerate() {
                let p = uv_of(tri[o]);
                uv[2 * k] = p[0];
                uv[2 * k + 1] = p[1];
            }
            // Counted by `count`: `i < need`.
            if let Some(d) = out.get_mut(i) {
                *d = UvTriangle {
                    solid: if is_a { 0 } else { 1 },
                    face: pt.face,
                    sub: pt.sub,
                    reserved: 0,
                    uv,
                };
            }
            i += 1;
        })
    }
}

/// Barycentric coordinates of `x` (projected to the plane of `t`) in `t`,
/// clamped to the triangle's closure (the curve points lie on its edges
/// or inside, up to rounding).
/// `1 / cos(gamma / 2)`, `gamma` the angle between the kept sheets'
/// outward normals at crossing triangles `ia` of A and `ib` of B.
fn amplification(a: &SolidMesh, b: &SolidMesh, ia: usize, ib: usize, op: Op) -> f64 {
    let na = a.normal(ia).normalize_or_zero();
    let mut nb = b.normal(ib).normalize_or_zero();
    if op == Op::Difference {
        nb = -nb;
    }
    let cos_half = libm::sqrt(((1.0 + na.dot(nb)) * 0.5).max(0.0));
    if cos_half > 0.0 {
        1.0 / cos_half
    } else {
        f64::INFINITY
    }
}

fn barycentric(x: DVec3, t: &[DVec3; 3]) -> [f64; 3] {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let nn = n.length_squared();
    if nn == 0.0 {
        return [1.0 / 3.0; 3];
    }
    let w1 = (x - t[0]).cross(t[2] - t[0]).dot(n) / nn;
    let w2 = (t[1] - t[0]).cross(x - t[0]).dot(n) / nn;
    let w = [(1.0 - w1 - w2).max(0.0), w1.max(0.0), w2.max(0.0)];
    let s = w[0] + w[1] + w[2];
    [w[0] / s, w[1] / s, w[2] / s]
}

/// Calls `f(a, b, ends)` for every crossing pair, A's triangles in order.
fn for_pairs(
    a: &SolidMesh,
    b: &SolidMesh,
    bvh: &Bvh,
    f: &mut impl FnMut(usize, usize, [super::pairs::Pierce; 2]) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut hits = [0u32; 512];
    for ia in 0..a.triangles.len() / 3 {
        let (lo, hi) = super::bvh::tri_box(a, ia);
        let ta = a.tri(ia);
        let mut n = 0;
        let mut overflow = false;
        bvh.query(lo, hi, |ib| {
            if n < hits.len() {
                hits[n] = ib as u32;
                n += 1;
            } else {
                overflow = true;
            }
        });
        if overflow {
            return Err(degenerate(
                ia as u32,
                u32::MAX,
                "too many crossings in one triangle",
            ));
        }
        // B's triangles in index order, so that the pairs are deterministic.
        hits[..n].sort_unstable();
        for &ib in &hits[..n] {
            let ib = ib as usize;
            match intersect(&ta, &b.tri(ib)) {
                Contact::None => {}
                Contact::Segment(ends) => f(ia, ib, ends)?,
                Contact::Degenerate(w) => return Err(degenerate(ia as u32, ib as u32, w)),
            }
        }
    }
    Ok(())
}

/// Is `p` inside the closed mesh `m`? Parity of the crossings of a
/// segment from `p` to far outside, by exact predicates; a direction whose
/// segment touches an edge or vertex exactly is replaced by the next one.
fn ray_parity(p: DVec3, m: &SolidMesh) -> bool {
    const DIRS: [[f64; 3]; 4] = [
        [0.5773, 0.5119, 0.6361],
        [-0.3341, 0.8231, 0.4592],
        [0.7093, -0.3124, -0.6318],
        [-0.2167, -0.6133, 0.7597],
    ];
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for v in 0..m.positions.len() / 3 {
        lo = lo.min(m.point(v as u32));
        hi = hi.max(m.point(v as u32));
    }
    let reach = (hi - lo).length() + (p - lo).length() + (p - hi).length() + 1.0;
    'dirs: for d in DIRS {
        let q = p + DVec3::from_array(d) * reach;
        let (slo, shi) = (p.min(q), p.max(q));
        let mut crossings = 0u32;
        for t in 0..m.triangles.len() / 3 {
            let (blo, bhi) = super::bvh::tri_box(m, t);
            if blo.x > shi.x
                || blo.y > shi.y
                || blo.z > shi.z
                || bhi.x < slo.x
                || bhi.y < slo.y
                || bhi.z < slo.z
            {
                continue;
            }
            let tri = m.tri(t);
            let sp = orient3d(tri[0], tri[1], tri[2], p).0;
            let sq = orient3d(tri[0], tri[1], tri[2], q).0;
            if sp == 0 || sq == 0 {
                continue 'dirs;
            }
            if sp == sq {
                continue;
            }
            let s0 = orient3d(p, q, tri[0], tri[1]).0;
            let s1 = orient3d(p, q, tri[1], tri[2]).0;
            let s2 = orient3d(p, q, tri[2], tri[0]).0;
            if s0 == 0 || s1 == 0 || s2 == 0 {
                let mixed =
                    [s0, s1, s2].iter().any(|&s| s > 0) && [s0, s1, s2].iter().any(|&s| s < 0);
                if mixed {
                    continue;
                }
                continue 'dirs;
            }
            if s0 == s1 && s1 == s2 {
                crossings += 1;
            }
        }
        return crossings % 2 == 1;
    }
    false
}
