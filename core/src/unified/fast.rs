//! Fast path of the k-ring averages (eqs. (22)–(24)) on the regular parts
//! of the mesh: separable box sums on a local grid chart, and in the first
//! pass the `d`-ary B-spline weights.
//!
//! Every quad of the input gets a chart: its frame 0, extended over the
//! 3 x 3 block of input faces around it (coordinates `(-d, 2d)^2`). The
//! chart is cut into nine blocks (the face, four edge bands, four corner
//! blocks); a block is **valid** when it is a grid continuing the face's:
//! an edge band when the face across that edge is a quad, a corner block
//! when that corner has valence 4 with four quads around it; all faces of
//! valid blocks must be distinct (the block does not wrap onto itself).
//!
//! A refined vertex or face of the quad whose neighbourhood box — `N_k(V)`:
//! `(2k+1)^2` vertices, `N_k(F)`: `(2k)^2` vertices, `F_k(V)`: `(2k)^2`
//! cells — lies in valid blocks has exactly that box as its neighbourhood:
//! a path of at most `k` faces can only leave the box through an
//! extraordinary vertex or a non-quad, and reaching one needs a box point in
//! an invalid block (a box touching a corner block contains points beyond
//! the corner). Such boxes are summed separably (rows, then columns): `O(1)`
//! work per value instead of `O(d^2)`.
//!
//! On a **full** quad (all nine blocks valid) the first pass is even simpler:
//! linear subdivision and both averages are tensor products of 1-D rules on
//! the bilinear interpolant of the 4 x 4 input vertices around it, i.e. the
//! `d`-ary refinement of the uniform B-spline
//! (`first_pass_weights`); intermediate values there are only computed
//! where other paths read them (faces sharing a vertex with a face that is
//! not full).
//!
//! The same sets are averaged as by the search in [`super::smooth`], so the
//! results agree up to rounding; the values written here are flagged in
//! `done`, the search does the rest. Used for `3 <= d <= FAST_MAX_D` (the
//! per-face windows take `O(d^2)` scratch).

use super::layout::{FaceFrame, Numbering};
use crate::mesh::topology::Topology;
use glam::DVec3;

/// Largest `d` with the fast path (scratch grows with `d^2`).
pub const FAST_MAX_D: usize = 64;

/// Element counts of the fast-path memory of a level (`vertices` and
/// `faces` of the input, at most `quads` of them quads).
pub(crate) struct Sizes {
    /// `(d+1)^2` vertex indices per quad.
    pub grid: u64,
    /// Per input face: grid slot, block mask; per input vertex: flags.
    pub slot: u64,
    pub mask: u64,
    pub vflag: u64,
    /// Child offset per frame-0 cell of a quad.
    pub cell: u64,
    /// 4 x 4 input vertices per quad.
    pub base16: u64,
    /// First-pass weights (`f64`).
    pub tables: u64,
    /// Grid offsets of the corners of a quad's children in emission order.
    pub etab: u64,
    /// Grid offsets of a quad's interior vertices in numbering order.
    pub itab: u64,
    /// The rigid maps of the nine chart blocks per quad (4 words each).
    pub blocks: u64,
    /// Window indices, values (points) and row sums (points).
    pub win_idx: u64,
    pub win_val: u64,
    pub rows: u64,
}

/// Sizes of the fast-path memory (see [`Sizes`]).
pub(crate) fn sizes(d: usize, vertices: u64, faces: u64, quads: u64) -> Sizes {
    let d64 = d as u64;
    let w = 2 * d64 + 1;
    Sizes {
        grid: quads * (d64 + 1) * (d64 + 1),
        slot: faces,
        mask: faces,
        vflag: vertices,
        cell: d64 * d64,
        base16: 16 * quads,
        tables: 8 * (d64 + 1),
        etab: 4 * d64 * d64,
        itab: (d64 - 1) * (d64 - 1),
        blocks: 36 * quads,
        win_idx: w * w,
        win_val: w * w,
        rows: (d64 + 1) * w,
    }
}

/// Per-level tables: the refined vertex grid of every quad, the valid
/// blocks of its chart and the child order of a quad's cells.
pub(crate) struct Charts<'w> {
    d: usize,
    /// Per input face: slot of its grid (quads) or `NONE`.
    slot: &'w [u32],
    /// Per input face: valid blocks, bit `3 by + bx` for block `(bx, by)`
    /// (`0`: below / left of the face, `1`: the face's range, `2`: above /
    /// right).
    mask: &'w [u32],
    /// `(d+1)^2` vertex indices per quad, frame 0, row-major (`j` outer).
    grid: &'w [u32],
    /// Child offset of frame-0 cell `(ci, cj)` of any quad, `cj * d + ci`.
    cell: &'w [u32],
    child_start: &'w [u32],
    /// Per quad with all blocks valid: the 4 x 4 input vertices at chart
    /// points `(a d, b d)`, `a, b = -1..=2`, row-major (`b` outer).
    base16: &'w [u32],
    /// Grid offsets of the corners of a quad's children, emission order
    /// (for odd `d` the central face last).
    etab: &'w [u32],
    /// Per quad and valid block `3 by + bx`: `[face, packed rotation, o_x,
    /// o_y]` of the block's rigid map (see [`Block`]).
    blocks: &'w [u32],
}

const NONE: u32 = u32::MAX;
/// All nine blocks valid.
const ALL: u32 = 0x1ff;
/// Mask flag: the face shares a vertex with a face that is not full (or is
/// not full itself), so its first-pass intermediate values and its linear
/// subdivision are read by the box sums or the search.
const NEED: u32 = 1 << 9;

#[inline]
fn bit(bx: usize, by: usize) -> u32 {
    1 << (3 * by + bx)
}

/// Chart scratch of a level (see [`sizes`]).
pub(crate) struct ChartMem<'w> {
    pub slot: &'w mut [u32],
    pub mask: &'w mut [u32],
    pub vflag: &'w mut [u32],
    pub grid: &'w mut [u32],
    pub cell: &'w mut [u32],
    pub base16: &'w mut [u32],
    pub etab: &'w mut [u32],
    pub itab: &'w mut [u32],
    pub blocks: &'w mut [u32],
}

/// Builds the charts into the given scratch.
pub(crate) fn build<'w>(
    t: &Topology,
    num: &Numbering,
    child_start: &'w [u32],
    mem: ChartMem<'w>,
) -> Charts<'w> {
    let ChartMem {
        slot,
        mask,
        vflag,
        grid,
        cell,
        base16,
        etab,
        itab,
        blocks,
    } = mem;
    let sh = num.shape;
    let (d, m) = (sh.d, sh.m);
    let d1 = d + 1;
    let g = d1 * d1;
    // Per-d tables: frame-0 grid offsets of a quad's interior vertices (in
    // numbering order) and of its children's corners (in emission order).
    let to0 = |k: usize, i: usize, j: usize| -> usize {
        let (mut a, mut b) = (i, j);
        for _ in 0..k {
            (a, b) = (d - b, a); // frame k -> k-1
        }
        b * d1 + a
    };
    let (jmax, centre) = if sh.odd { (m, 0) } else { (m - 1, 1) };
    if !sh.odd {
        itab[0] = to0(0, m, m) as u32;
    }
    let mut o = centre;
    for k in 0..4 {
        for j in 1..=jmax {
            for i in 1..=m {
                itab[o] = to0(k, i, j) as u32;
                o += 1;
            }
        }
    }
    let (ci_n, cj_n) = sh.sector_cells();
    let mut e = 0;
    for k in 0..4 {
        for j in 0..cj_n {
            for i in 0..ci_n {
                for (a, b) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)] {
                    etab[e] = to0(k, a, b) as u32;
                    e += 1;
                }
            }
        }
    }
    if sh.odd {
        for k in 0..4 {
            etab[e] = to0(k, m, m) as u32;
            e += 1;
        }
    }
    let mut frame = FaceFrame::new(sh);
    let mut q = 0usize;
    for f in 0..t.num_faces() {
        if t.face_size(f) != 4 {
            slot[f] = NONE;
            continue;
        }
        // The face's grid in frame 0: corners, edges, then each sector's
        // own interior points rotated from frame k to frame 0.
        frame.load(t, num, f);
        let out = &mut grid[q * g..(q + 1) * g];
        for (k, &(i, j)) in [(0, 0), (d, 0), (d, d), (0, d)].iter().enumerate() {
            out[j * d1 + i] = frame.point(k, 0, 0) as u32;
        }
        for s in 1..d {
            out[s] = frame.point(0, s, 0) as u32; // edge 0: j = 0
            out[s * d1 + d] = frame.point(1, s, 0) as u32; // edge 1: i = d
            out[d * d1 + d - s] = frame.point(2, s, 0) as u32; // edge 2: j = d
            out[(d - s) * d1] = frame.point(3, s, 0) as u32; // edge 3: i = 0
        }
        let base = num.interior_start[f] as usize;
        for (o, &at) in itab.iter().enumerate() {
            out[at as usize] = (base + o) as u32;
        }
        slot[f] = q as u32;
        q += 1;
    }
    let slot: &[u32] = slot;
    // Vertex flags: a corner is regular with valence 4 and four quads around
    // it; `TOUCHES`: the vertex belongs to a face that is not full (set
    // below).
    const REG: u32 = 1;
    const TOUCHES: u32 = 2;
    for (v, fl) in vflag.iter_mut().enumerate() {
        *fl = 0;
        if t.valence(v) != 4 {
            continue;
        }
        let start = t.vertex_half_edge(v);
        let mut h = start;
        let mut quads = true;
        loop {
            quads &= slot[t.face_of(h)] != NONE;
            h = t.rotate_ccw(h);
            if h == start {
                break;
            }
        }
        if quads {
            *fl = REG;
        }
    }
    let regular_corner = |v: usize| vflag[v] & REG != 0;
    let edge_block = [(1, 0), (2, 1), (1, 2), (0, 1)];
    let corner_block = [(0, 0), (2, 0), (2, 2), (0, 2)];
    // Corner c's position in the 4 x 4 input lattice and the frame-0 steps
    // of its frame's axes (u along edge c, v towards corner c - 1).
    let lattice = [(1isize, 1isize), (2, 1), (2, 2), (1, 2)];
    let u = [(1isize, 0isize), (0, 1), (-1, 0), (0, -1)];
    let v = [(0isize, 1isize), (-1, 0), (0, -1), (1, 0)];
    for f in 0..t.num_faces() {
        if slot[f] == NONE {
            mask[f] = 0;
            continue;
        }
        let fs = t.face_half_edge(f);
        let mut mk = bit(1, 1);
        // Faces of the valid blocks (the face itself first); must be distinct.
        let mut seen = [usize::MAX; 9];
        seen[0] = f;
        let mut n = 1;
        let mut distinct = true;
        let mut note = |g: usize| {
            if seen[..n].contains(&g) {
                distinct = false;
            } else if n < 9 {
                seen[n] = g;
                n += 1;
            }
        };
        for e in 0..4 {
            let across = t.face_of(t.twin(fs + e));
            if slot[across] != NONE {
                mk |= bit(edge_block[e].0, edge_block[e].1);
                note(across);
            }
        }
        for c in 0..4 {
            if regular_corner(t.origin(fs + c)) {
                mk |= bit(corner_block[c].0, corner_block[c].1);
                // The diagonal face: across edge c, then around the corner.
                note(t.face_of(t.twin(t.next(t.twin(fs + c)))));
            }
        }
        mask[f] = if distinct { mk } else { bit(1, 1) };
        // Cache the rigid map of every valid block.
        let (s, d2) = (slot[f] as usize, 2 * d as isize);
        let rep = [-1, d as isize, d2 + 1];
        for by in 0..3 {
            for bx in 0..3 {
                if mask[f] & bit(bx, by) == 0 {
                    continue;
                }
                let w = &mut blocks[36 * s + 4 * (3 * by + bx)..36 * s + 4 * (3 * by + bx) + 4];
                match walk(t, d, slot, f, rep[bx], rep[by]) {
                    Some(b) => {
                        w[0] = b.g as u32;
                        w[1] = ((b.m[0][0] + 1) | ((b.m[0][1] + 1) << 2)) as u32;
                        w[2] = b.o[0] as i32 as u32;
                        w[3] = b.o[1] as i32 as u32;
                    }
                    None => mask[f] &= !bit(bx, by),
                }
            }
        }
        if mask[f] == ALL {
            // The 16 input vertices: per corner c, the corner, its neighbours
            // across edge c (-v) and across edge c - 1 (-u), and the
            // diagonal (-u - v).
            let s = slot[f] as usize;
            for c in 0..4 {
                let h = fs + c;
                let hp = fs + (c + 3) % 4;
                let below = t.next(t.twin(h)); // v_c -> (-v)
                let w = t.dest(below);
                let w2 = t.origin(t.prev(t.twin(hp))); // (-u) -> v_c
                let z = t.origin(t.prev(t.twin(below))); // diagonal
                let (a, b) = lattice[c];
                let mut put = |da: isize, db: isize, x: usize| {
                    base16[16 * s + 4 * (b + db) as usize + (a + da) as usize] = x as u32;
                };
                put(0, 0, t.origin(h));
                put(-v[c].0, -v[c].1, w);
                put(-u[c].0, -u[c].1, w2);
                put(-u[c].0 - v[c].0, -u[c].1 - v[c].1, z);
            }
        }
    }
    // NEED: every face sharing a vertex with a face that is not full.
    for f in 0..t.num_faces() {
        if slot[f] == NONE || mask[f] & ALL != ALL {
            for &v in t.face_vertices(f) {
                vflag[v as usize] |= TOUCHES;
            }
        }
    }
    for f in 0..t.num_faces() {
        if t.face_vertices(f)
            .iter()
            .any(|&v| vflag[v as usize] & TOUCHES != 0)
        {
            mask[f] |= NEED;
        }
    }
    // Cells of a quad in emission order (sector k, then row-major), mapped to
    // frame 0; for odd d the central face is cell (m, m).
    let (ci_n, cj_n) = sh.sector_cells();
    let mut off = 0u32;
    for k in 0..4 {
        for j in 0..cj_n {
            for i in 0..ci_n {
                let (mut a, mut b) = (i, j);
                for _ in 0..k {
                    (a, b) = (d - 1 - b, a); // cell of frame k -> frame k-1
                }
                cell[b * d + a] = off;
                off += 1;
            }
        }
    }
    if sh.odd {
        cell[sh.m * d + sh.m] = off;
    }
    let (mask, grid, cell): (&[u32], &[u32], &[u32]) = (mask, grid, cell);
    let (base16, etab, blocks): (&[u32], &[u32], &[u32]) = (base16, etab, blocks);
    Charts {
        d,
        slot,
        mask,
        grid,
        cell,
        child_start,
        base16,
        etab,
        blocks,
    }
}

/// Walks the doubled chart coordinates `(i2, j2)` of quad `f`'s frame 0
/// (vertices at even, cell centres at odd values) into the face holding
/// them and returns that face with the rigid map taking `f`'s doubled chart
/// coordinates to the face's doubled frame-0 coordinates (the same map for
/// every point of the chart block the point lies in), or `None` if a face
/// on the way is not a quad.
fn walk(t: &Topology, d: usize, slot: &[u32], f: usize, i2: isize, j2: isize) -> Option<Block> {
    let d2 = 2 * d as isize;
    // p_current = m p_chart + o, tracked through every rotation/crossing.
    let mut b = Block {
        g: f,
        m: [[1, 0], [0, 1]],
        o: [0, 0],
    };
    let mut c = 0usize;
    // Apply p -> (r p + s) to the tracked map.
    let apply = |b: &mut Block, r: [[isize; 2]; 2], s: [isize; 2]| {
        let m = b.m;
        b.m = [
            [
                r[0][0] * m[0][0] + r[0][1] * m[1][0],
                r[0][0] * m[0][1] + r[0][1] * m[1][1],
            ],
            [
                r[1][0] * m[0][0] + r[1][1] * m[1][0],
                r[1][0] * m[0][1] + r[1][1] * m[1][1],
            ],
        ];
        b.o = [
            r[0][0] * b.o[0] + r[0][1] * b.o[1] + s[0],
            r[1][0] * b.o[0] + r[1][1] * b.o[1] + s[1],
        ];
    };
    // (i, j) -> (d - j, i): frame c -> c - 1; (i, j) -> (j, d - i):
    // frame c -> c + 1; crossing: (i, j) -> (d - i, -j).
    let down = ([[0, -1], [1, 0]], [d2, 0]);
    let up = ([[0, 1], [-1, 0]], [0, d2]);
    let half = ([[-1, 0], [0, -1]], [d2, d2]);
    let cross = ([[-1, 0], [0, -1]], [d2, 0]);
    for _ in 0..4 {
        let (i, j) = b.at(i2, j2);
        if (0..=d2).contains(&i) && (0..=d2).contains(&j) {
            for _ in 0..c {
                apply(&mut b, down.0, down.1);
            }
            return Some(b);
        }
        if i < 0 {
            apply(&mut b, down.0, down.1);
            c = (c + 3) % 4;
        } else if i > d2 {
            apply(&mut b, up.0, up.1);
            c = (c + 1) % 4;
        } else if j > d2 {
            apply(&mut b, half.0, half.1);
            c = (c + 2) % 4;
        }
        let h = t.face_half_edge(b.g) + c;
        let tw = t.twin(h);
        let ng = t.face_of(tw);
        if slot[ng] == NONE {
            return None;
        }
        apply(&mut b, cross.0, cross.1);
        b.g = ng;
        c = tw - t.face_half_edge(ng);
    }
    None
}

/// The blocks of the ranges `[lo, lo + n)` along one axis: `(block, first,
/// last)` with blocks split at `0` and at `end` (`d` for vertices, `d - 1`
/// for cells).
#[inline]
fn ranges(lo: isize, n: usize, end: isize) -> [(usize, isize, isize); 3] {
    let hi = lo + n as isize - 1;
    [
        (0, lo, hi.min(-1)),
        (1, lo.max(0), hi.min(end)),
        (2, lo.max(end + 1), hi),
    ]
}

impl Charts<'_> {
    /// The cached rigid map of valid block `(bx, by)` of quad `f`.
    #[inline]
    fn block(&self, f: usize, bx: usize, by: usize) -> Block {
        let at = 36 * self.slot[f] as usize + 4 * (3 * by + bx);
        let w = &self.blocks[at..at + 4];
        let (c, s) = ((w[1] & 3) as isize - 1, ((w[1] >> 2) & 3) as isize - 1);
        Block {
            g: w[0] as usize,
            m: [[c, s], [-s, c]],
            o: [w[2] as i32 as isize, w[3] as i32 as isize],
        }
    }

    /// Whether input face `f` is a quad (has a chart).
    #[inline]
    pub fn has_chart(&self, f: usize) -> bool {
        self.slot[f] != NONE
    }

    /// Calls `push` with the corners of each child of quad `f` in emission
    /// order (without the central face of odd `d`, see
    /// [`Charts::centre_quad`]).
    #[inline]
    pub fn emit_quad(&self, f: usize, mut push: impl FnMut([u32; 4])) {
        let d1 = self.d + 1;
        let q = self.slot[f] as usize;
        let grid = &self.grid[q * d1 * d1..(q + 1) * d1 * d1];
        let cells = 4 * (self.d / 2) * self.d.div_ceil(2) * 4;
        for c in self.etab[..cells].chunks_exact(4) {
            push([
                grid[c[0] as usize],
                grid[c[1] as usize],
                grid[c[2] as usize],
                grid[c[3] as usize],
            ]);
        }
    }

    /// The central face of quad `f` (odd `d`).
    #[inline]
    pub fn centre_quad(&self, f: usize) -> [u32; 4] {
        let d1 = self.d + 1;
        let q = self.slot[f] as usize;
        let grid = &self.grid[q * d1 * d1..(q + 1) * d1 * d1];
        let c = &self.etab[self.etab.len() - 4..];
        [
            grid[c[0] as usize],
            grid[c[1] as usize],
            grid[c[2] as usize],
            grid[c[3] as usize],
        ]
    }

    /// Whether all nine blocks of `f`'s chart are valid.
    #[inline]
    pub fn full(&self, f: usize) -> bool {
        self.slot[f] != NONE && self.mask[f] & ALL == ALL
    }

    /// Whether the intermediate first-pass values and the linear
    /// subdivision of face `f` are read by other paths (see `NEED`).
    #[inline]
    pub fn needed(&self, f: usize) -> bool {
        self.mask[f] & NEED != 0
    }

    /// Whether the box with chart ranges `x0..=x1`, `y0..=y1` (vertices:
    /// `end = d`, cells: `end = d - 1`) lies in valid blocks of face `f`.
    #[inline]
    fn clean(&self, f: usize, x0: isize, x1: isize, y0: isize, y1: isize, end: isize) -> bool {
        let m = self.mask[f] & ALL;
        if m == ALL {
            return true;
        }
        let xs = [x0 < 0, true, x1 > end];
        let ys = [y0 < 0, true, y1 > end];
        for by in 0..3 {
            for bx in 0..3 {
                if xs[bx] && ys[by] && m & bit(bx, by) == 0 {
                    return false;
                }
            }
        }
        true
    }

    /// Calls `out(x, y, r)` for every chart vertex `(lo + x, lo + y)`,
    /// `0 <= x, y < n`, in a valid block of face `f`, with its refined
    /// vertex `r`.
    #[inline]
    fn vertices(&self, f: usize, lo: isize, n: usize, mut out: impl FnMut(usize, usize, u32)) {
        let d = self.d as isize;
        let d1 = (d + 1) as usize;
        let m = self.mask[f];
        for (by, j0, j1) in ranges(lo, n, d) {
            for (bx, i0, i1) in ranges(lo, n, d) {
                if i0 > i1 || j0 > j1 || m & bit(bx, by) == 0 {
                    continue;
                }
                let b = self.block(f, bx, by);
                let q = self.slot[b.g] as usize;
                let grid = &self.grid[q * d1 * d1..(q + 1) * d1 * d1];
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let (x, y) = b.at(2 * i, 2 * j);
                        let r = grid[(y / 2) as usize * d1 + (x / 2) as usize];
                        out((i - lo) as usize, (j - lo) as usize, r);
                    }
                }
            }
        }
    }

    /// Calls `out(x, y, r)` for every chart cell `(lo + x, lo + y)`,
    /// `0 <= x, y < n`, in a valid block of face `f`, with its refined face
    /// `r`.
    #[inline]
    fn cells(&self, f: usize, lo: isize, n: usize, mut out: impl FnMut(usize, usize, u32)) {
        let d = self.d as isize;
        let du = self.d;
        let m = self.mask[f];
        for (by, j0, j1) in ranges(lo, n, d - 1) {
            for (bx, i0, i1) in ranges(lo, n, d - 1) {
                if i0 > i1 || j0 > j1 || m & bit(bx, by) == 0 {
                    continue;
                }
                let b = self.block(f, bx, by);
                let cs = self.child_start[b.g];
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let (x, y) = b.at(2 * i + 1, 2 * j + 1);
                        let r = cs + self.cell[(y / 2) as usize * du + (x / 2) as usize];
                        out((i - lo) as usize, (j - lo) as usize, r);
                    }
                }
            }
        }
    }
}

/// A rigid map of doubled chart coordinates into face `g`'s doubled frame 0.
#[derive(Clone, Copy)]
struct Block {
    g: usize,
    m: [[isize; 2]; 2],
    o: [isize; 2],
}

impl Block {
    #[inline]
    fn at(&self, i: isize, j: isize) -> (isize, isize) {
        (
            self.m[0][0] * i + self.m[0][1] * j + self.o[0],
            self.m[1][0] * i + self.m[1][1] * j + self.o[1],
        )
    }
}

/// Where the fast path records what it wrote: `done[i] = gen`.
pub(crate) struct Marks<'m> {
    pub done: &'m mut [u32],
    pub gen: u32,
}

/// Window scratch.
pub(crate) struct Window<'w> {
    pub idx: &'w mut [u32],
    pub val: &'w mut [DVec3],
    pub rows: &'w mut [DVec3],
}

/// Box sums of width `w` over a `n x n` window of `val` (row-major), for the
/// `m x m` outputs starting at offset `(0, 0)` (output `(a, b)` sums
/// `val[b..b+w][a..a+w]`); calls `out(a, b, sum)`.
#[inline]
fn box_sums(
    val: &[DVec3],
    rows: &mut [DVec3],
    n: usize,
    w: usize,
    m: usize,
    mut out: impl FnMut(usize, usize, DVec3),
) {
    // Horizontal sums: rows[y * m + a] = Σ_{x=a}^{a+w-1} val[y][x].
    for y in 0..n {
        let r = &val[y * n..y * n + n];
        let mut s = DVec3::ZERO;
        for x in 0..w {
            s += r[x];
        }
        rows[y * m] = s;
        for a in 1..m {
            s += r[a + w - 1] - r[a - 1];
            rows[y * m + a] = s;
        }
    }
    // Vertical sums.
    for a in 0..m {
        let mut s = DVec3::ZERO;
        for y in 0..w {
            s += rows[y * m + a];
        }
        out(a, 0, s);
        for b in 1..m {
            s += rows[(b + w - 1) * m + a] - rows[(b - 1) * m + a];
            out(a, b, s);
        }
    }
}

/// Eq. (22) (odd `d`, `k = (d-1)/2`): `dst[V] = avg of src over the
/// (2k+1)^2 box` for the vertices of quads whose box is clean; marks them
/// `gen` in `done`.
pub(crate) fn vertex_boxes(
    t: &Topology,
    ch: &Charts,
    src: &[DVec3],
    dst: &mut [DVec3],
    marks: Marks,
    win: &mut Window,
    skip_full: bool,
) {
    let Marks { done, gen } = marks;
    let d = ch.d;
    let k = (d - 1) / 2;
    let ki = k as isize;
    let n = d + 1 + 2 * k;
    let w = 2 * k + 1;
    let norm = 1.0 / (w * w) as f64;
    for f in 0..t.num_faces() {
        if !ch.has_chart(f) || (skip_full && ch.full(f)) {
            continue;
        }
        let (idx, val) = (&mut *win.idx, &mut *win.val);
        if ch.mask[f] & ALL != ALL {
            val[..n * n].fill(DVec3::ZERO);
        }
        ch.vertices(f, -ki, n, |x, y, r| {
            idx[y * n + x] = r;
            val[y * n + x] = src[r as usize];
        });
        let idx = &win.idx;
        box_sums(win.val, win.rows, n, w, d + 1, |a, b, s| {
            let (ai, bi) = (a as isize, b as isize);
            if ch.clean(f, ai - ki, ai + ki, bi - ki, bi + ki, d as isize) {
                let r = idx[(b + k) * n + a + k] as usize;
                dst[r] = s * norm;
                done[r] = gen;
            }
        });
    }
}

/// Eq. (23) (even `d`, `k = d/2`): the value of each refined face of a quad
/// whose `(2k)^2` vertex box is clean is the box average; marks them `gen`
/// in `done`.
pub(crate) fn face_boxes(
    t: &Topology,
    ch: &Charts,
    src: &[DVec3],
    dst: &mut [DVec3],
    marks: Marks,
    win: &mut Window,
    skip_full: bool,
) {
    let Marks { done, gen } = marks;
    let d = ch.d;
    let k = d / 2;
    let ki = k as isize;
    // Cell (ci, cj) averages vertices ci-k+1 ..= ci+k: window from -(k-1).
    let n = d + 2 * k - 1;
    let w = 2 * k;
    let norm = 1.0 / (w * w) as f64;
    for f in 0..t.num_faces() {
        if !ch.has_chart(f) || (skip_full && ch.full(f)) {
            continue;
        }
        let val = &mut *win.val;
        if ch.mask[f] & ALL != ALL {
            val[..n * n].fill(DVec3::ZERO);
        }
        ch.vertices(f, 1 - ki, n, |x, y, r| val[y * n + x] = src[r as usize]);
        let cs = ch.child_start[f] as usize;
        let cell = ch.cell;
        box_sums(win.val, win.rows, n, w, d, |a, b, s| {
            let (ai, bi) = (a as isize, b as isize);
            if ch.clean(f, ai - ki + 1, ai + ki, bi - ki + 1, bi + ki, d as isize) {
                let r = cs + cell[b * d + a] as usize;
                dst[r] = s * norm;
                done[r] = gen;
            }
        });
    }
}

/// Eq. (24) (even `d`, `k = d/2`): each vertex of a quad whose `(2k)^2`
/// cell box is clean becomes the box average; marks them `gen` in `done`.
pub(crate) fn vertex_cell_boxes(
    t: &Topology,
    ch: &Charts,
    src: &[DVec3],
    dst: &mut [DVec3],
    marks: Marks,
    win: &mut Window,
    skip_full: bool,
) {
    let Marks { done, gen } = marks;
    let d = ch.d;
    let k = d / 2;
    let ki = k as isize;
    // Vertex (i, j) averages cells i-k ..= i+k-1: window of cells from -k.
    let n = d + 2 * k;
    let w = 2 * k;
    let norm = 1.0 / (w * w) as f64;
    for f in 0..t.num_faces() {
        if !ch.has_chart(f) || (skip_full && ch.full(f)) {
            continue;
        }
        let val = &mut *win.val;
        if ch.mask[f] & ALL != ALL {
            val[..n * n].fill(DVec3::ZERO);
        }
        ch.cells(f, -ki, n, |x, y, r| val[y * n + x] = src[r as usize]);
        let q = ch.slot[f] as usize;
        let d1 = (d + 1) * (d + 1);
        let grid = &ch.grid[q * d1..(q + 1) * d1];
        box_sums(win.val, win.rows, n, w, d + 1, |a, b, s| {
            let (ai, bi) = (a as isize, b as isize);
            if ch.clean(
                f,
                ai - ki,
                ai + ki - 1,
                bi - ki,
                bi + ki - 1,
                d as isize - 1,
            ) {
                let r = grid[b * (d + 1) + a] as usize;
                dst[r] = s * norm;
                done[r] = gen;
            }
        });
    }
}

/// First-pass weights on regular parts. On a face whose nine chart blocks
/// are valid, the first pass is the tensor product of the 1-D rules applied
/// to the bilinear interpolant of the 4 x 4 input vertices around it: 1-D
/// weights of the input points `a = -1..=2` (positions `a d`) at each
/// refined position. `w1`: after the first average, at vertices `0..=d` (odd
/// `d`, box of width `d` centred) or cells `0..d` (even `d`, the `d`
/// vertices `c-k+1 ..= c+k`); `w2`: after the second one, at vertices
/// `0..=d` (the `d`-ary cubic B-spline mask `(box_d)^{*4}/d^3`). Each row
/// has 4 entries.
pub(crate) fn first_pass_weights(d: usize, w1: &mut [f64], w2: &mut [f64]) {
    let di = d as isize;
    let hat = |q: isize, a: isize| -> f64 { (1.0 - (q - a * di).abs() as f64 / d as f64).max(0.0) };
    let inv = 1.0 / d as f64;
    if d % 2 == 1 {
        let k = (di - 1) / 2;
        let r1 = |q: isize, a: isize| -> f64 { (-k..=k).map(|s| hat(q + s, a)).sum::<f64>() * inv };
        for i in 0..=di {
            for a in -1..=2isize {
                w1[i as usize * 4 + (a + 1) as usize] = r1(i, a);
                w2[i as usize * 4 + (a + 1) as usize] =
                    (-k..=k).map(|s| r1(i + s, a)).sum::<f64>() * inv;
            }
        }
    } else {
        let k = di / 2;
        let r1 = |c: isize, a: isize| -> f64 {
            (c - k + 1..=c + k).map(|q| hat(q, a)).sum::<f64>() * inv
        };
        for a in -1..=2isize {
            for c in 0..di {
                w1[c as usize * 4 + (a + 1) as usize] = r1(c, a);
            }
            for i in 0..=di {
                w2[i as usize * 4 + (a + 1) as usize] =
                    (i - k..i + k).map(|c| r1(c, a)).sum::<f64>() * inv;
            }
        }
    }
}

/// Tensor-product evaluation on the faces with all nine blocks valid: calls
/// `out(face, x, y, value)` for `0 <= x, y < rows` with `value = Σ_ab w[x][a]
/// w[y][b] P_ab` over the face's 4 x 4 input vertices (`None` for faces
/// skipped by `only_needed`: their values are never read).
#[inline]
fn tensor(
    t: &Topology,
    ch: &Charts,
    w: &[f64],
    rows: usize,
    only_needed: bool,
    mut out: impl FnMut(usize, usize, usize, Option<DVec3>),
) {
    let mut q = [[DVec3::ZERO; 4]; 4];
    let mut col = [DVec3::ZERO; 4];
    for f in 0..t.num_faces() {
        if !ch.full(f) {
            continue;
        }
        if only_needed && !ch.needed(f) {
            // Nothing reads these values: flag them without computing.
            for y in 0..rows {
                for x in 0..rows {
                    out(f, x, y, None);
                }
            }
            continue;
        }
        let s = ch.slot[f] as usize;
        for b in 0..4 {
            for a in 0..4 {
                q[b][a] = t.position(ch.base16[16 * s + 4 * b + a] as usize);
            }
        }
        for y in 0..rows {
            let wy = &w[4 * y..4 * y + 4];
            for a in 0..4 {
                col[a] = q[0][a] * wy[0] + q[1][a] * wy[1] + q[2][a] * wy[2] + q[3][a] * wy[3];
            }
            for x in 0..rows {
                let wx = &w[4 * x..4 * x + 4];
                out(
                    f,
                    x,
                    y,
                    Some(col[0] * wx[0] + col[1] * wx[1] + col[2] * wx[2] + col[3] * wx[3]),
                );
            }
        }
    }
}

/// First pass, vertex values with weights `w` (`d + 1` rows) on faces with
/// all blocks valid (`only_needed`: just those whose values other paths
/// read); marks them `gen` in `done`.
pub(crate) fn tensor_vertices(
    t: &Topology,
    ch: &Charts,
    w: &[f64],
    dst: &mut [DVec3],
    done: &mut [u32],
    gen: u32,
    only_needed: bool,
) {
    let d1 = ch.d + 1;
    tensor(t, ch, w, d1, only_needed, |f, x, y, v| {
        let q = ch.slot[f] as usize;
        let r = ch.grid[q * d1 * d1 + y * d1 + x] as usize;
        if let Some(v) = v {
            dst[r] = v;
        }
        done[r] = gen;
    });
}

/// First pass, cell values (eq. (23), even `d`) with weights `w` (`d` rows)
/// on the full faces whose cells other paths read; marks them `gen` in
/// `done`.
pub(crate) fn tensor_cells(
    t: &Topology,
    ch: &Charts,
    w: &[f64],
    dst: &mut [DVec3],
    done: &mut [u32],
    gen: u32,
) {
    let d = ch.d;
    tensor(t, ch, w, d, true, |f, x, y, v| {
        let r = ch.child_start[f] as usize + ch.cell[y * d + x] as usize;
        if let Some(v) = v {
            dst[r] = v;
        }
        done[r] = gen;
    });
}
