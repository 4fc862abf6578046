//! Fold removal by orientation rows: the condition "the limit normal of
//! `S(Q)` points to the side of `S(G)`'s" linearised around the current
//! solution and re-linearised over a few rounds.
//!
//! At a point `(f, u, v)` of a face of `G` with `n` the unit limit normal
//! of `S(G)` there, the orientation `c(Q) = n . (Q_u x Q_v)` must stay
//! positive (a fold is `c <= 0`). `c` is quadratic in `Q`; around the
//! current control points `Q0` it is `c(Q) ~ a . Q_u + b . Q_v - c(Q0)` with
//! `a = Q0_v x n`, `b = n x Q0_u`, a linear row over the patch's labels (the
//! derivative weights of the point, \[CL-R eqs. 2.5, 2.6\]). Every point of
//! the [`super::samples::ORIENT_GRID`] (7 x 7) grid of a sampled face whose
//! orientation falls below the margin `delta = margin * n . (G_u x
//! G_v)` (a fraction of `G`'s own area element there) gets the penalty row
//! `w (a . Q_u + b . Q_v - c(Q0) - max(delta, c(Q0)))^2`, scaled like the
//! similarity rows (divided by the RMS of `G`'s first derivatives); rows
//! once set stay (re-linearised each round, target never below their
//! current orientation), and the weight of a point still below the margin
//! grows [`ORIENT_GROWTH`] times per round (at most [`ORIENT_CAP`] times
//! the first). Unlike the anchors of [`super::folds`], these rows ask
//! nothing of the tangents but their orientation.
//!
//! Schedule: the first solve runs to the full tolerance; if a grid point is
//! below the margin, rounds follow, each solved loosely ([`ROUND_TOLERANCE`])
//! from the previous solution, until no point is below the margin or the
//! round limit, then one solve to the full tolerance with the last rows.
//! Measured on `catmark_lefthanded` (a thin stepped plate with a 0.0044
//! edge beside 0.02-0.12 ones at a step corner, where the earlier anchors
//! left 1,732 reversed points of 140,616): 16 rounds (the default) leave
//! none on 9 x 9 or 17 x 17 points per face, nor do 12 or 20; 8 rounds
//! leave 74 (BENCHMARKS.md, "Folds and fold removal"). Memory: `8 * 49` values per face (the `7 * 49` row values are touched only at points with a row) of `G` and the grid
//! weights per valence.

use super::interpolator::Interpolator;
use super::ring::{add3, get3};
use super::samples::{gwrow, OG, OROW};
use crate::mesh::stencil::MAX_K;
use glam::DVec3;

/// The solves of the orientation rounds stop at this many times the
/// tolerance (at most 1e-2: 1e-2 at the default 1e-6); the solution after
/// the last round is solved to the full tolerance. Measured on
/// `catmark_lefthanded`, 20 rounds: 5,655 iterations at a round tolerance
/// of 1e-3, 3,539 at 1e-2, both without folds.
pub const ROUND_TOLERANCE: f64 = 1e4;

/// Growth of a point's weight per round it stays below the margin.
pub const ORIENT_GROWTH: f64 = 4.0;

/// Largest weight of a point, relative to the first.
pub const ORIENT_CAP: f64 = 1e5;

impl Interpolator<'_> {
    /// Gathers the labels' points of face `f`'s patch from `g` and `q`
    /// (all vertices) into `pg` and `pq`; returns the label count.
    #[inline]
    pub(crate) fn gather_pair(
        &self,
        f: usize,
        g: &[f64],
        q: &[f64],
        pg: &mut [DVec3; MAX_K],
        pq: &mut [DVec3; MAX_K],
    ) -> usize {
        let k = 2 * self.valence[f] as usize + 8;
        let lab = &self.labels[f * MAX_K..f * MAX_K + k];
        for ((&l, a), b) in lab.iter().zip(pg.iter_mut()).zip(pq.iter_mut()) {
            *a = get3(g, l as usize);
            *b = get3(q, l as usize);
        }
        k
    }

    /// `(G_u, G_v, Q_u, Q_v)` at orientation grid point `p` of a patch of
    /// valence `n` from its gathered points ([`Self::gather_pair`]).
    #[inline]
    pub(crate) fn pair_tangents(
        &self,
        n: usize,
        p: usize,
        pg: &[DVec3],
        pq: &[DVec3],
    ) -> (DVec3, DVec3, DVec3, DVec3) {
        let k = pg.len();
        let wu = &self.gweights[gwrow(n, p, 0)..][..k];
        let wv = &self.gweights[gwrow(n, p, 1)..][..k];
        let (mut gu, mut gv, mut qu, mut qv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (((x, y), &a), &b) in pg.iter().zip(pq).zip(wu).zip(wv) {
            gu += *x * a;
            gv += *x * b;
            qu += *y * a;
            qv += *y * b;
        }
        (gu, gv, qu, qv)
    }

    /// Re-linearises the orientation rows around `q` (all vertices) and
    /// adds rows at points below the margin. Returns `(points with c <=
    /// 0, points below the margin)` on the grid.
    pub(crate) fn mark_orientation(&mut self, q: &[f64]) -> (usize, usize) {
        let w0 = self.opts.fold_weight;
        let (mut folded, mut low) = (0usize, 0usize);
        let (mut pg, mut pq) = ([DVec3::ZERO; MAX_K], [DVec3::ZERO; MAX_K]);
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = self.gather_pair(f, self.g.positions(), q, &mut pg, &mut pq);
            for p in 0..OG {
                let (gu, gv, qu, qv) = self.pair_tangents(n, p, &pg[..k], &pq[..k]);
                let ng = gu.cross(gv);
                let qn = qu.cross(qv);
                // A fold as `super::folds` counts it (same expression).
                let d = ng.dot(qn);
                if d <= 0.0 || d.is_nan() {
                    folded += 1;
                }
                let area = ng.length();
                if area.is_nan() || area <= 0.0 {
                    continue;
                }
                let n = ng / area;
                let c0 = n.dot(qn);
                let delta = self.opts.fold_margin * area;
                let weight = &mut self.orient_weight[f * OG + p];
                let below = c0.is_nan() || c0 < delta;
                if below {
                    low += 1;
                    *weight = if *weight == 0.0 {
                        w0
                    } else {
                        (*weight * ORIENT_GROWTH).min(w0 * ORIENT_CAP)
                    };
                }
                if *weight == 0.0 {
                    continue;
                }
                let row = &mut self.orient[(f * OG + p) * OROW..][..OROW];
                let a = qv.cross(n);
                let b = n.cross(qu);
                let target = c0 + if c0 > delta { c0 } else { delta };
                let vals = [a.x, a.y, a.z, b.x, b.y, b.z, target];
                for (r, v) in row.iter_mut().zip(vals) {
                    *r = v.to_bits();
                }
                self.oriented = true;
            }
        }
        (folded, low)
    }

    /// Adds the orientation rows' half gradient at `q` (all vertices) to
    /// `y` (with `affine`; without, the linear part only) and returns their
    /// value.
    pub(crate) fn orient_terms(&self, q: &[f64], mut y: Option<&mut [f64]>, affine: bool) -> f64 {
        if !self.oriented {
            return 0.0;
        }
        // Face by face: the patch's points gathered once, the rows'
        // gradients summed per label, scattered once (a face holds up to
        // 49 rows).
        let inv = 1.0 / (self.rms[1] * self.rms[1]);
        let mut total = 0.0;
        let mut pts = [DVec3::ZERO; MAX_K];
        let mut acc = [DVec3::ZERO; MAX_K];
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let weights = &self.orient_weight[f * OG..][..OG];
            if weights.iter().all(|&w| w == 0.0) {
                continue;
            }
            let k = 2 * n + 8;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            for (p, &l) in pts.iter_mut().zip(lab) {
                *p = get3(q, l as usize);
            }
            acc[..k].fill(DVec3::ZERO);
            for (p, &w) in weights.iter().enumerate() {
                if w == 0.0 {
                    continue;
                }
                let w = w * inv;
                let row = &self.orient[(f * OG + p) * OROW..][..OROW];
                let a = vec_at(row, 0);
                let b = vec_at(row, 3);
                let wu = &self.gweights[gwrow(n, p, 0)..][..k];
                let wv = &self.gweights[gwrow(n, p, 1)..][..k];
                let (mut qu, mut qv) = (DVec3::ZERO, DVec3::ZERO);
                for ((x, &cu), &cv) in pts[..k].iter().zip(wu).zip(wv) {
                    qu += *x * cu;
                    qv += *x * cv;
                }
                let s = a.dot(qu) + b.dot(qv);
                let r = s - f64::from_bits(row[6]);
                total += w * r * r;
                let rr = w * if affine { r } else { s };
                let (ar, br) = (a * rr, b * rr);
                for ((acc, &cu), &cv) in acc[..k].iter_mut().zip(wu).zip(wv) {
                    *acc += ar * cu + br * cv;
                }
            }
            if let Some(y) = y.as_deref_mut() {
                for (a, &l) in acc[..k].iter().zip(lab) {
                    add3(y, l as usize, *a);
                }
            }
        }
        total
    }

    /// Calls `visit` for every orientation row of non-zero weight (none
    /// when the rows are off), in face and grid-point order.
    fn for_each_row<'s>(&'s self, mut visit: impl FnMut(OrientRow<'s>)) {
        if !self.oriented {
            return;
        }
        let inv = 1.0 / (self.rms[1] * self.rms[1]);
        for f in 0..self.valence.len() {
            let n = self.valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = 2 * n + 8;
            let labels = &self.labels[f * MAX_K..f * MAX_K + k];
            for p in 0..OG {
                let w = self.orient_weight[f * OG + p] * inv;
                if w == 0.0 {
                    continue;
                }
                let row = &self.orient[(f * OG + p) * OROW..][..OROW];
                visit(OrientRow {
                    w,
                    a: vec_at(row, 0),
                    b: vec_at(row, 3),
                    labels,
                    wu: &self.gweights[gwrow(n, p, 0)..][..k],
                    wv: &self.gweights[gwrow(n, p, 1)..][..k],
                });
            }
        }
    }

    /// Adds the orientation rows' 3x3 diagonal blocks of `T^T A T` to `out`
    /// (9 per vertex, row-major, not inverted). `vecs`/`verts` hold one row's
    /// coefficients per unknown (merged by a scan: rows are short).
    pub(crate) fn orient_blocks(&self, out: &mut [f64], verts: &mut [u32], vecs: &mut [DVec3]) {
        self.for_each_row(|row| {
            let (w, a, b, lab, wu, wv) = (row.w, row.a, row.b, row.labels, row.wu, row.wv);
            let mut len = 0usize;
            let mut push = |v: usize, c: DVec3, len: &mut usize| {
                for t in 0..*len {
                    if verts[t] as usize == v {
                        vecs[t] += c;
                        return;
                    }
                }
                if *len < verts.len() {
                    verts[*len] = v as u32;
                    vecs[*len] = c;
                    *len += 1;
                }
            };
            for ((&l, &cu), &cv) in lab.iter().zip(wu).zip(wv) {
                if cu == 0.0 && cv == 0.0 {
                    continue;
                }
                let c = a * cu + b * cv;
                let l = l as usize;
                if l >= self.n1 {
                    push(l, c, &mut len);
                } else {
                    let (ce, cf) = (self.coef[3 * l + 1], self.coef[3 * l + 2]);
                    super::ring::for_ring(&self.g, l, |e, fv| {
                        push(e, -c * ce, &mut len);
                        push(fv, -c * cf, &mut len);
                    });
                }
            }
            for t in 0..len {
                let c = vecs[t];
                let blk = &mut out[9 * verts[t] as usize..][..9];
                for r in 0..3 {
                    for s in 0..3 {
                        blk[3 * r + s] += w * c[r] * c[s];
                    }
                }
            }
        });
    }
}

/// One orientation row of [`Interpolator::orient_blocks`]: the
/// linearised condition's left side `a . Q_u + b . Q_v`, its weight `w`
/// (scaled by the derivative RMS), the face's unknown labels and the grid
/// point's derivative weights per label.
struct OrientRow<'s> {
    w: f64,
    a: DVec3,
    b: DVec3,
    labels: &'s [u32],
    wu: &'s [f64],
    wv: &'s [f64],
}

/// The vector stored (as `f64` bits) at `row[o..o + 3]`.
#[inline]
fn vec_at(row: &[u64], o: usize) -> DVec3 {
    DVec3::new(
        f64::from_bits(row[o]),
        f64::from_bits(row[o + 1]),
        f64::from_bits(row[o + 2]),
    )
}
