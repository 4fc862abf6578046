//! Fold removal: outer rounds that find faces where the limit normal of
//! `S(Q)` is reversed against that of `S(G)` and anchor their first
//! derivatives.
//!
//! The similarity rows `|q x g|^2` of \[CL-R eq. 4.5\] are homogeneous in
//! `q`: a reversed or shrunk derivative (`q = -g`, `q -> 0`) costs nothing,
//! so on thin features (the fingers of `catmark_lefthanded`) the least
//! squares solution turns patches over where the Type I vertices moved far.
//! After a solve, the normals of `Q` and `G` are compared on a
//! `fold_grid x fold_grid` grid of every sampled face (more points than the
//! nine similarity samples); each face with a point where `n_Q . n_G <= 0`
//! gets the anchor term `a_f sum |S_d(Q) - S ∘ S_d(G)|^2` over its nine
//! samples and `d = u, v` (`S`: the per-axis scale of \[CL-R §4\]'s initial
//! guess, see [`super::system`]), which pulls both tangents towards `G`'s,
//! same orientation. The problem stays linear; it is re-solved from the
//! previous solution, and faces still folded get four times their weight,
//! for at most [`super::InterpolationOptions::fold_rounds`] rounds.

use super::interpolator::{drow, wrow, Interpolator, NS};
use super::ring::{add3, get3};
use super::samples::{OG, ORIENT_GRID};
use crate::error::Error;
use crate::math::bspline::eval_grid;
use crate::mesh::stencil::{label_at, MAX_K};
use glam::DVec3;

/// Growth of a face's anchor weight per round it stays folded.
pub(crate) const ANCHOR_GROWTH: f64 = 4.0;

impl Interpolator<'_> {
    /// The limit normal (not normalised) of face `f`'s patch at (u, v)
    /// (patch frame) for the control points `q` (all vertices).
    fn patch_normal(&self, q: &[f64], f: usize, u: f64, v: f64) -> Result<DVec3, Error> {
        let n = self.valence[f] as usize;
        let k = 2 * n + 8;
        let lab = &self.labels[f * MAX_K..f * MAX_K + k];
        let e = if n == 4 {
            let mut grid = [0.0; 48];
            for y in -1..=2i32 {
                for x in -1..=2i32 {
                    let l = label_at(4, x, y).unwrap_or(0);
                    let p = get3(q, lab[l] as usize);
                    let s = ((x + 1) * 4 + (y + 1)) as usize;
                    grid[s] = p.x;
                    grid[s + 16] = p.y;
                    grid[s + 32] = p.z;
                }
            }
            eval_grid::<false>(&grid, u, v)
        } else {
            let table = self
                .tables
                .get(n)
                .ok_or(Error::MissingTable { valence: n as u32 })?;
            let mut pts = [DVec3::ZERO; MAX_K];
            for (p, &l) in pts.iter_mut().zip(lab) {
                *p = get3(q, l as usize);
            }
            table.eval_patch(&pts[..k], u, v, false)?
        };
        Ok(e.du.cross(e.dv))
    }

    /// Counts the grid points (`fold_grid` per side, every sampled face)
    /// where the normals of `q` and `G` disagree (`n_Q . n_G <= 0`), and
    /// anchors each face that has one (first weight
    /// [`super::InterpolationOptions::fold_weight`], then
    /// [`ANCHOR_GROWTH`] times more per round). Returns the number of such
    /// points.
    pub(crate) fn mark_folds(&mut self, q: &[f64]) -> Result<usize, Error> {
        let mut folded = 0usize;
        for f in 0..self.valence.len() {
            let here = self.face_folds(q, f)?;
            if here > 0 {
                self.anchored = true;
                let a = &mut self.anchor[f];
                *a = if *a == 0.0 {
                    self.opts.fold_weight
                } else {
                    *a * ANCHOR_GROWTH
                };
                folded += here;
            }
        }
        Ok(folded)
    }

    /// The grid points (`fold_grid` per side) of face `f` where the normals
    /// of `q` and `G` disagree (0 for an unsampled face).
    fn face_folds(&self, q: &[f64], f: usize) -> Result<usize, Error> {
        if self.valence[f] == 0 {
            return Ok(0);
        }
        let k = self.opts.fold_grid.max(2) as usize;
        if k == ORIENT_GRID {
            // The orientation grid (the default), whose derivative weights
            // are tabulated: both tangent pairs in one pass over the
            // labels (the count of `mark_orientation`, same expression).
            let n = self.valence[f] as usize;
            let (mut pg, mut pq) = ([DVec3::ZERO; MAX_K], [DVec3::ZERO; MAX_K]);
            let kk = self.gather_pair(f, self.g.positions(), q, &mut pg, &mut pq);
            let mut here = 0usize;
            for p in 0..OG {
                let (gu, gv, qu, qv) = self.pair_tangents(n, p, &pg[..kk], &pq[..kk]);
                let d = gu.cross(gv).dot(qu.cross(qv));
                if d <= 0.0 || d.is_nan() {
                    here += 1;
                }
            }
            return Ok(here);
        }
        let step = 1.0 / (k - 1) as f64;
        let mut here = 0usize;
        for i in 0..k {
            for j in 0..k {
                let (u, v) = (i as f64 * step, j as f64 * step);
                let nq = self.patch_normal(q, f, u, v)?;
                let ng = self.patch_normal(self.g.positions(), f, u, v)?;
                if nq.dot(ng) <= 0.0 || nq.dot(ng).is_nan() {
                    here += 1;
                }
            }
        }
        Ok(here)
    }

    /// Counts the grid points (`fold_grid` per side, every sampled face)
    /// where the normals of `q` and `G` disagree (`n_Q . n_G <= 0`).
    pub(crate) fn count_folds(&self, q: &[f64]) -> Result<usize, Error> {
        let mut folded = 0usize;
        for f in 0..self.valence.len() {
            folded += self.face_folds(q, f)?;
        }
        Ok(folded)
    }

    /// Anchor target of derivative `d` (1: u, 2: v) at sample `s` of face
    /// `f`: `G`'s derivative scaled per axis by `S`.
    #[inline]
    fn anchor_target(&self, f: usize, s: usize, d: usize) -> DVec3 {
        get3(&self.dirs[drow(f, s, 0)..], d) * self.rms[d] * self.scale
    }

    /// Adds the anchor term's half gradient at `q` (all vertices) to `y`
    /// (with `affine`; without, its linear part only) and returns its
    /// value `sum a_f |S_d(q) - S ∘ S_d(G)|^2`.
    pub(crate) fn anchor_terms(&self, q: &[f64], mut y: Option<&mut [f64]>, affine: bool) -> f64 {
        if !self.anchored {
            return 0.0;
        }
        let mut total = 0.0;
        for (f, &a) in self.anchor.iter().enumerate() {
            if a == 0.0 {
                continue;
            }
            let n = self.valence[f] as usize;
            let k = 2 * n + 8;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            for s in 0..NS {
                for d in 1..=2 {
                    let w = &self.weights[wrow(n, s, d)..][..k];
                    let mut qv = DVec3::ZERO;
                    for (&l, &wj) in lab.iter().zip(w) {
                        qv += get3(q, l as usize) * wj;
                    }
                    let t = self.anchor_target(f, s, d);
                    total += a * (qv - t).length_squared();
                    if let Some(y) = y.as_deref_mut() {
                        let r = if affine { qv - t } else { qv } * a;
                        for (&l, &wj) in lab.iter().zip(w) {
                            if wj != 0.0 {
                                add3(y, l as usize, r * wj);
                            }
                        }
                    }
                }
            }
        }
        total
    }
}
