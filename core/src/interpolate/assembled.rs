//! The normal matrix `S = T^T A T` of \[CL-R eq. 4.6\] assembled once, as
//! 3x3 blocks in compressed rows over the Type II unknowns, and the
//! symmetric Gauss-Seidel preconditioner it allows.
//!
//! The pattern: unknowns `u` and `w` are coupled when one face of `G` has
//! both in its expanded stencil `E(f)` (its 2n+8 labels, each Type I label
//! replaced by its ring, eq. 4.1). A label set of a face with at most one
//! extraordinary corner is the set of vertices of the faces sharing a
//! corner with it, so the faces whose `E(f)` holds `u` are found by three
//! face-vertex hops around `u`; stamps (one per vertex and face of `G`,
//! carved at build) remove repeats. The count is taken at build, so
//! [`Interpolator::assembled_bytes`] is exact.
//!
//! Values: per face the element blocks `K_jk = sum_r w_rj w_rk (|g_r|^2 I -
//! (1 - mu) g_r g_r^T)` over its labels (`r` the sample rows), then the
//! labels expanded through `T` (entries `(vertex, label, coefficient)`),
//! sorted by vertex: per distinct vertex `a` the row `sum c_a K_j.` over
//! its entries, added times `c_b` onto the blocks `S_ab`, `b >= a`, found
//! by one merge walk along the sorted row `a` (each block update of the
//! upper triangle done once, no search).
//!
//! Products cost about 18 flops per block instead of the matrix-free
//! gather and scatter per sample row; the symmetric Gauss-Seidel sweep
//! (`M = (D + L) D^-1 (D + U)`, blocks `D` the 3x3 diagonal) needs the
//! rows, which the matrix-free path does not have.

use super::blocks::Matrix;
use super::interpolator::{nzrow, wrow, Interpolator, NS};
use super::ring::{for_ring, get3};
use super::samples::ROWS;
use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;
use crate::mesh::stencil::MAX_K;

/// Largest expansion of one face's labels: every label a ring.
const MAX_EXP: usize = MAX_K * 2 * MAX_VALENCE;

fn layout(rows: usize, blocks: usize) -> Layout {
    let mut l = Layout::default();
    l.u32s(rows + 1);
    l.u32s(blocks);
    l.f64s(6 * blocks);
    l.f64s(6 * tri_len(MAX_K));
    l.u32s(MAX_EXP);
    l.f64s(MAX_EXP);
    l.u32s(MAX_EXP);
    l.raw(8 * MAX_EXP);
    l.f64s(6 * MAX_K);
    l
}

/// Block `(j, l)`, `j <= l`, of the packed upper triangle of a `k x k`
/// block matrix sits at `tri(j, k) + l`.
#[inline]
fn tri(j: usize, k: usize) -> usize {
    j * k - j * (j + 1) / 2
}

/// Blocks of the packed upper triangle of a `k x k` block matrix.
const fn tri_len(k: usize) -> usize {
    k * (k + 1) / 2
}

impl<'a> Interpolator<'a> {
    /// Calls `visit(w)` once for every unknown `w` coupled with unknown `u`
    /// (`u` included). `tag` must differ from every earlier call's.
    fn row_pattern(&self, u: usize, tag: u32, stamps: &mut [u32], mut visit: impl FnMut(usize)) {
        let m = self.m;
        let g = &self.g;
        let (vst, fst) = stamps.split_at_mut(m);
        let seen = |w: usize, vst: &mut [u32], visit: &mut dyn FnMut(usize)| {
            if vst[w] != tag {
                vst[w] = tag;
                visit(w);
            }
        };
        // The diagonal block, present even when no sampled face holds u.
        seen(u, vst, &mut visit);
        // c = u, then every Type I corner of a face at u (u is in their
        // rings).
        let h0 = g.vertex_half_edge(u);
        let mut hc = h0;
        let mut first = true;
        // Type I corners already walked (an edge point meets each of its
        // two twice); a full list only repeats walks, which is harmless.
        let mut walked = [u32::MAX; 8];
        let mut nwalked = 0usize;
        loop {
            // Candidates: u itself once, then the corners of this face.
            let face_u = g.face_of(hc);
            let fh = g.face_half_edge(face_u);
            let size = g.face_size(face_u);
            for ci in 0..=size {
                let c = if ci == size {
                    if !first {
                        continue;
                    }
                    u
                } else {
                    g.origin(fh + ci)
                };
                if ci < size {
                    if c == u || c >= self.n1 || walked[..nwalked].contains(&(c as u32)) {
                        continue;
                    }
                    if nwalked < walked.len() {
                        walked[nwalked] = c as u32;
                        nwalked += 1;
                    }
                }
                // Faces f with c among their labels: faces at a corner x of
                // a face h at c.
                let s1 = g.vertex_half_edge(c);
                let mut h1 = s1;
                loop {
                    let fa = g.face_of(h1);
                    let fah = g.face_half_edge(fa);
                    for xi in 0..g.face_size(fa) {
                        let x = g.origin(fah + xi);
                        let s2 = g.vertex_half_edge(x);
                        let mut h2 = s2;
                        loop {
                            let f = g.face_of(h2);
                            if fst[f] != tag {
                                fst[f] = tag;
                                let n = self.valence[f] as usize;
                                if n != 0 {
                                    let lab = &self.labels[f * MAX_K..f * MAX_K + 2 * n + 8];
                                    for &l in lab {
                                        let l = l as usize;
                                        if l >= self.n1 {
                                            seen(l, vst, &mut visit);
                                        } else if vst[l] != tag {
                                            // A Type I label (never visited
                                            // itself) is expanded once per
                                            // row: its stamp marks that.
                                            vst[l] = tag;
                                            for_ring(g, l, |e, fv| {
                                                seen(e, vst, &mut visit);
                                                seen(fv, vst, &mut visit);
                                            });
                                        }
                                    }
                                }
                            }
                            h2 = g.rotate_ccw(h2);
                            if h2 == s2 {
                                break;
                            }
                        }
                    }
                    h1 = g.rotate_ccw(h1);
                    if h1 == s1 {
                        break;
                    }
                }
            }
            first = false;
            hc = g.rotate_ccw(hc);
            if hc == h0 {
                break;
            }
        }
    }

    /// Number of blocks of the upper triangle of the assembled matrix;
    /// `stamps` (`m + faces`) is scratch.
    pub(crate) fn count_blocks(&self, stamps: &mut [u32]) -> usize {
        stamps.fill(0);
        let mut total = 0usize;
        for u in self.n1..self.m {
            self.row_pattern(u, u as u32 + 1, stamps, |w| {
                if w >= u {
                    total += 1
                }
            });
        }
        total
    }

    /// Bytes of caller memory [`Interpolator::assemble`] needs (exact,
    /// counted at build).
    pub fn assembled_bytes(&self) -> usize {
        layout(self.m - self.n1, self.blocks).bytes()
    }

    /// Assembles the normal matrix into `mem` (see [`super::assembled`]):
    /// later solves multiply with it, and
    /// [`super::Preconditioner::SymmetricGaussSeidel`] becomes available.
    /// The solution is that of the matrix-free path to the convergence
    /// tolerance.
    ///
    /// Errors: [`Error::BufferTooSmall`] (bytes).
    pub fn assemble(&mut self, mem: &'a mut [u64]) -> Result<(), Error> {
        let required = self.assembled_bytes();
        if bytes_of(mem.len()) < required {
            return Err(Error::BufferTooSmall { required });
        }
        let rows = self.m - self.n1;
        let mut arena = Arena::new(mem);
        let start = arena.u32s(rows + 1);
        let cols = arena.u32s(self.blocks);
        let vals = arena.f64s(6 * self.blocks);
        let elem = arena.f64s(6 * tri_len(MAX_K));
        let exp_v = arena.u32s(MAX_EXP);
        let exp_c = arena.f64s(MAX_EXP);
        let exp_j = arena.u32s(MAX_EXP);
        let keys = arena.words(8 * MAX_EXP);
        let row_k = arena.f64s(6 * MAX_K);

        // Pattern, sorted rows.
        let stamps = core::mem::take(&mut self.stamps);
        stamps.fill(0);
        let mut at = 0usize;
        for u in self.n1..self.m {
            let r = u - self.n1;
            start[r] = at as u32;
            let row_start = at;
            self.row_pattern(u, u as u32 + 1, stamps, |w| {
                if w < u {
                    return;
                }
                if at < cols.len() {
                    cols[at] = w as u32;
                }
                at += 1;
            });
            if at > cols.len() {
                self.stamps = stamps;
                return Err(Error::InvalidArgument(
                    "internal: interpolation matrix pattern changed",
                ));
            }
            cols[row_start..at].sort_unstable();
        }
        start[rows] = at as u32;
        self.stamps = stamps;

        // Values.
        vals.fill(0.0);
        let kinds = self.opts.derivatives;
        let mu = self.opts.parallel_weight;
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = 2 * n + 8;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            let el = &mut elem[..6 * tri_len(k)];
            el.fill(0.0);
            for s in 0..NS {
                for d in 1..ROWS {
                    if kinds & (1 << d) == 0 {
                        continue;
                    }
                    let g = get3(&self.dirs[super::interpolator::drow(f, s, 0)..], d);
                    let g2 = g.length_squared();
                    if g2 == 0.0 {
                        continue;
                    }
                    let c = 1.0 - mu;
                    let b = [
                        g2 - c * g.x * g.x,
                        -c * g.x * g.y,
                        -c * g.x * g.z,
                        g2 - c * g.y * g.y,
                        -c * g.y * g.z,
                        g2 - c * g.z * g.z,
                    ];
                    let w = &self.weights[wrow(n, s, d)..][..MAX_K];
                    let z = &self.nonzero[nzrow(n, s, d)..][..MAX_K + 1];
                    let nz = &z[1..1 + z[0] as usize];
                    for (a, &j) in nz.iter().enumerate() {
                        let j = j as usize;
                        // nz ascends: j <= l.
                        let base = tri(j, k);
                        for &l in &nz[a..] {
                            let l = l as usize;
                            let ww = w[j] * w[l];
                            let e = &mut el[6 * (base + l)..][..6];
                            for (e, bv) in e.iter_mut().zip(&b) {
                                *e += ww * bv;
                            }
                        }
                    }
                }
            }
            // Expansion of each label through T.
            let mut ne = 0usize;
            for (j, &l) in lab.iter().enumerate() {
                let l = l as usize;
                if l >= self.n1 {
                    exp_v[ne] = l as u32;
                    exp_c[ne] = 1.0;
                    exp_j[ne] = j as u32;
                    ne += 1;
                } else {
                    let (ce, cf) = (self.coef[3 * l + 1], self.coef[3 * l + 2]);
                    for_ring(&self.g, l, |e, fv| {
                        exp_v[ne] = e as u32;
                        exp_c[ne] = -ce;
                        exp_j[ne] = j as u32;
                        exp_v[ne + 1] = fv as u32;
                        exp_c[ne + 1] = -cf;
                        exp_j[ne + 1] = j as u32;
                        ne += 2;
                    });
                }
            }
            // The entries sorted by vertex (then entry): each distinct
            // vertex a of E(f) is one group; its row's blocks S_ab, b >= a,
            // are the entries from its group on.
            let keys = &mut keys[..ne];
            for (i, key) in keys.iter_mut().enumerate() {
                *key = (u64::from(exp_v[i]) << 32) | i as u64;
            }
            keys.sort_unstable();
            let mut g0 = 0usize;
            while g0 < ne {
                let va = (keys[g0] >> 32) as u32;
                let mut g1 = g0 + 1;
                while g1 < ne && (keys[g1] >> 32) as u32 == va {
                    g1 += 1;
                }
                // row_k[l] = sum over the group's entries (j, c_a) of
                // c_a K_jl.
                let rk = &mut row_k[..6 * k];
                rk.fill(0.0);
                for &key in &keys[g0..g1] {
                    let ia = key as u32 as usize;
                    let (j, ca) = (exp_j[ia] as usize, exp_c[ia]);
                    for (l, r) in rk.chunks_exact_mut(6).enumerate() {
                        let (lo, hi) = if j <= l { (j, l) } else { (l, j) };
                        let e = &el[6 * (tri(lo, k) + hi)..][..6];
                        for (r, e) in r.iter_mut().zip(e) {
                            *r += ca * e;
                        }
                    }
                }
                // S_ab += c_b row_k[l] for the entries (l, c_b) of every
                // b >= a, found by one merge walk along the sorted row a
                // (every such b is in it by construction; a mismatch is an
                // internal error, not a silent drop).
                let a = va as usize - self.n1;
                let (r0, r1) = (start[a] as usize, start[a + 1] as usize);
                let mut p = r0;
                for &key in &keys[g0..] {
                    let vb = (key >> 32) as u32;
                    let ib = key as u32 as usize;
                    while p < r1 && cols[p] < vb {
                        p += 1;
                    }
                    if p >= r1 || cols[p] != vb {
                        return Err(Error::InvalidArgument(
                            "internal: interpolation matrix pattern misses a block",
                        ));
                    }
                    let (l, cb) = (exp_j[ib] as usize, exp_c[ib]);
                    let r = &rk[6 * l..6 * l + 6];
                    let v = &mut vals[6 * p..6 * p + 6];
                    for (v, r) in v.iter_mut().zip(r) {
                        *v += cb * r;
                    }
                }
                g0 = g1;
            }
        }
        // The block-Jacobi blocks are the inverted diagonal blocks.
        if !self.precond_ready {
            self.precond[..9 * self.n1].fill(0.0);
            for r in 0..rows {
                let a = &vals[6 * start[r] as usize..][..6];
                let b = &mut self.precond[9 * (self.n1 + r)..][..9];
                b.copy_from_slice(&[a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5]]);
                super::system::invert3(b);
            }
            self.precond_ready = true;
        }
        self.matrix = Some(Matrix { start, cols, vals });
        Ok(())
    }
}
