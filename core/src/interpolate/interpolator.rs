//! The interpolator object: layout of its caller memory, the build (one
//! Catmull-Clark step of `P`, patch labels, weight tables, similarity
//! directions, preconditioner) and the solve driver.

use super::blocks::Matrix;
use super::labels::{patch_corner, patch_labels};
use super::options::{FoldRemoval, InterpolationOptions, SolveStats};
use super::requirements::{num_rows, solve_rows, Requirement, Rows};
use super::ring::{fill_type1, fold_type1, get3, limit_coefficients, set3};
use super::samples::{
    grid_point, gwrow, patch_weights, WeightRows, OG, ORIENT_GRID, OROW, ROWS, SAMPLES,
};
use super::solver::{pcg, Work};
use crate::config::MAX_VALENCE;
use crate::eigen::TableSet;
use crate::error::Error;
use crate::mem::arena::{Arena, Layout};
use crate::mem::bytes_of;
use crate::mesh::refine::{refine, refine_bytes, refined_counts};
use crate::mesh::stencil::MAX_K;
use crate::mesh::topology::Topology;

/// Number of sample points per face.
pub(crate) const NS: usize = SAMPLES.len();

/// Offset of the weight row `(n, sample, row)` in the weight table.
#[inline]
pub(crate) fn wrow(n: usize, s: usize, d: usize) -> usize {
    ((n * NS + s) * ROWS + d) * MAX_K
}

/// Offset of the non-zero list of the weight row `(n, sample, row)`.
#[inline]
pub(crate) fn nzrow(n: usize, s: usize, d: usize) -> usize {
    ((n * NS + s) * ROWS + d) * (MAX_K + 1)
}

/// Offset of the direction `(face, sample, row)` (3 values, scaled
/// derivative of `G`).
#[inline]
pub(crate) fn drow(f: usize, s: usize, d: usize) -> usize {
    ((f * NS + s) * ROWS + d) * 3
}

/// Similarity-based interpolation of a closed mesh `P` (\[CL-R ch. 4\]) in
/// caller memory.
///
/// `Q` has the topology of `G`, one Catmull-Clark step of `P` (vertex
/// numbering of [`crate::mesh::refine`]: the first `n` vertices are the
/// Type I vertices in `P`'s order, and `Q` and `G` share one face
/// numbering). Build with [`Interpolator::build`], then
/// [`Interpolator::solve`].
pub struct Interpolator<'a> {
    pub(crate) g: Topology<'a>,
    pub(crate) tables: &'a TableSet,
    pub(crate) opts: InterpolationOptions,
    /// Type I vertices (vertices of `P`).
    pub(crate) n1: usize,
    /// Vertices of `G`.
    pub(crate) m: usize,
    /// Per face of `G`: valence of its patch (0: face not sampled).
    pub(crate) valence: &'a [u32],
    /// Per face of `G`: `MAX_K` labels.
    pub(crate) labels: &'a [u32],
    /// Weight rows per (valence, sample, row), `MAX_K` each.
    pub(crate) weights: &'a [f64],
    /// Per weight row, `MAX_K + 1` entries: the number of non-zero weights,
    /// then their label positions (a regular patch's rows at the knots
    /// `{0, 1}` are about half zeros; the products skip them).
    pub(crate) nonzero: &'a [u32],
    /// Scaled derivatives of `G` per (face, sample, row).
    pub(crate) dirs: &'a [f64],
    /// `(1/a0, a1/a0, a2/a0)` per Type I vertex.
    pub(crate) coef: &'a [f64],
    /// Points of `P`.
    pub(crate) target: &'a [f64],
    /// Inverse 3x3 diagonal blocks (row-major) per vertex of `G`.
    pub(crate) precond: &'a mut [f64],
    /// Whether `precond` holds the blocks (built at the first solve or
    /// [`Interpolator::assemble`] unless requirements need them at build).
    pub(crate) precond_ready: bool,
    /// Per-axis scale of the parallel target (see [`super::system`]).
    pub(crate) scale: glam::DVec3,
    /// Per row kind: the RMS the stored derivatives of `G` were divided by.
    pub(crate) rms: [f64; ROWS],
    pub(crate) work: Work<'a>,
    /// The extra requirements' rows.
    pub(crate) rows: Rows<'a>,
    /// Scratch stamps, one per vertex then one per face of `G` (the
    /// pattern walks of [`super::assembled`]).
    pub(crate) stamps: &'a mut [u32],
    /// Blocks of the assembled normal matrix (counted at build).
    pub(crate) blocks: usize,
    /// The assembled normal matrix, once [`Interpolator::assemble`] ran.
    pub(crate) matrix: Option<Matrix<'a>>,
    /// Per face of `G`: weight of its anchor rows ([`super::folds`]; 0:
    /// none).
    pub(crate) anchor: &'a mut [f64],
    /// Whether any face has anchor rows.
    pub(crate) anchored: bool,
    /// Derivative weights (du, dv) per (valence, orientation grid point),
    /// `MAX_K` each ([`super::orient`]).
    pub(crate) gweights: &'a [f64],
    /// Orientation rows per (face, grid point) ([`super::orient`]): `a`,
    /// `b`, target as `f64` bits; meaningful only where `orient_weight` is
    /// set (raw words, never zeroed: pages of points without rows stay
    /// untouched).
    pub(crate) orient: &'a mut [u64],
    /// Weight of the orientation row per (face, grid point) (0: none).
    pub(crate) orient_weight: &'a mut [f64],
    /// Whether any orientation row is set.
    pub(crate) oriented: bool,
    /// Whether the current solve is an orientation round, stopped at
    /// [`super::orient::ROUND_TOLERANCE`].
    pub(crate) loose: bool,
    /// Residual norm at the start of the first solve (the naive solution,
    /// before any fold row; 0 until that solve ran): the solve after the
    /// fold rounds also stops once its residual is `tolerance` times this
    /// ([`super::solver`]).
    pub(crate) first_residual: f64,
}

fn layout(p: &Topology, rows: usize) -> Layout {
    let c = refined_counts(p);
    let (m, nf) = (c.vertices, c.faces);
    let mut l = Layout::default();
    l.raw(refine_bytes(p));
    l.raw(Topology::layout(m, nf, 4 * nf).bytes());
    l.u32s(nf);
    l.u32s(nf * MAX_K);
    l.f64s((MAX_VALENCE + 1) * NS * ROWS * MAX_K);
    l.u32s((MAX_VALENCE + 1) * NS * ROWS * (MAX_K + 1));
    l.f64s(nf * NS * ROWS * 3);
    l.f64s(3 * p.num_vertices());
    l.f64s(3 * p.num_vertices());
    l.f64s(9 * m);
    for _ in 0..Work::VECTORS {
        l.f64s(3 * m);
    }
    l.f64s(rows);
    Rows::layout(&mut l, rows);
    l.u32s(m + nf);
    l.f64s(nf);
    l.f64s((MAX_VALENCE + 1) * OG * 2 * MAX_K);
    l.raw(8 * nf * OG * OROW);
    l.f64s(nf * OG);
    l
}

impl<'a> Interpolator<'a> {
    /// Bytes of caller memory [`Interpolator::build`] needs for `p` and
    /// the requirements `reqs`.
    pub fn required_bytes(p: &Topology, reqs: &[Requirement]) -> usize {
        layout(p, num_rows(reqs)).bytes()
    }

    /// Vertices of `Q` (and `G`): `V + E + F` of `P`.
    pub fn num_vertices_for(p: &Topology) -> usize {
        refined_counts(p).vertices
    }

    /// Subdivides `p` once with the rule of `tables`, and prepares the
    /// similarity system.
    ///
    /// Errors: [`Error::BufferTooSmall`] (bytes), [`Error::MissingTable`],
    /// [`Error::InvalidArgument`] for options out of range or a degenerate
    /// `P` (all vertices at one point).
    pub fn build(
        p: &Topology,
        tables: &'a TableSet,
        opts: InterpolationOptions,
        reqs: &[Requirement],
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        let required = Self::required_bytes(p, reqs);
        if bytes_of(mem.len()) < required {
            return Err(Error::BufferTooSmall { required });
        }
        if !(opts.tolerance.is_finite() && opts.tolerance > 0.0 && opts.tolerance < 1.0) {
            return Err(Error::InvalidArgument(
                "interpolation tolerance must be in (0, 1)",
            ));
        }
        if !(opts.parallel_weight.is_finite() && opts.parallel_weight >= 0.0) {
            return Err(Error::InvalidArgument(
                "interpolation parallel weight must be finite and >= 0",
            ));
        }
        if !(opts.fold_weight.is_finite() && opts.fold_weight > 0.0) {
            return Err(Error::InvalidArgument(
                "interpolation fold weight must be finite and > 0",
            ));
        }
        if !(opts.fold_margin.is_finite() && opts.fold_margin >= 0.0) {
            return Err(Error::InvalidArgument(
                "interpolation fold margin must be finite and >= 0",
            ));
        }
        if opts.fold_grid < 2 {
            return Err(Error::InvalidArgument(
                "interpolation fold grid needs at least 2 points per side",
            ));
        }
        if opts.derivatives & super::options::derivative::ALL == 0 {
            return Err(Error::InvalidArgument(
                "interpolation needs at least one sampled derivative",
            ));
        }
        let (lo, hi) = p.bounding_box();
        if (hi - lo).length().is_nan() || (hi - lo).length() <= 0.0 {
            return Err(Error::InvalidArgument(
                "degenerate mesh: all vertices are at one point",
            ));
        }
        let c = refined_counts(p);
        let (m, nf) = (c.vertices, c.faces);
        let n1 = p.num_vertices();
        let mut arena = Arena::new(mem);
        let rmem = arena.words(refine_bytes(p));
        let gmem = arena.words(Topology::layout(m, nf, 4 * nf).bytes());
        let valence = arena.u32s(nf);
        let labels = arena.u32s(nf * MAX_K);
        let weights = arena.f64s((MAX_VALENCE + 1) * NS * ROWS * MAX_K);
        let nonzero = arena.u32s((MAX_VALENCE + 1) * NS * ROWS * (MAX_K + 1));
        let dirs = arena.f64s(nf * NS * ROWS * 3);
        let coef = arena.f64s(3 * n1);
        let target = arena.f64s(3 * n1);
        let precond = arena.f64s(9 * m);
        let nrows = num_rows(reqs);
        let work = Work::carve(&mut arena, 3 * m, nrows);
        let rows = Rows::carve(&mut arena, nrows);
        let stamps = arena.u32s(m + nf);
        let anchor = arena.f64s(nf);
        anchor.fill(0.0);
        let gweights = arena.f64s((MAX_VALENCE + 1) * OG * 2 * MAX_K);
        let orient = arena.words(8 * nf * OG * OROW);
        let orient_weight = arena.f64s(nf * OG);
        orient_weight.fill(0.0);

        let w = tables.weights();
        let refined = refine(p, w, rmem)?;
        let g = Topology::build(refined.mesh, gmem)?;

        // Patch labels and the weight tables of the valences present.
        let mut present = [false; MAX_VALENCE + 1];
        for f in 0..nf {
            let (r, n, evs) = patch_corner(&g, f);
            if evs > 1 {
                // A face of G with two extraordinary corners (an n-gon of P
                // next to an extraordinary vertex) is no single patch of G's
                // vertices; it is left unsampled (valence 0).
                continue;
            }
            valence[f] = n as u32;
            let lab: &mut [u32; MAX_K] = (&mut labels[f * MAX_K..(f + 1) * MAX_K])
                .try_into()
                .map_err(|_| Error::InvalidArgument("internal: label slice"))?;
            patch_labels(&g, f, r, n, lab);
            if !present[n] {
                present[n] = true;
                for (s, &(u, v)) in SAMPLES.iter().enumerate() {
                    let mut rows: WeightRows = [[0.0; MAX_K]; ROWS];
                    patch_weights(tables, n, u, v, &mut rows)?;
                    for (d, row) in rows.iter().enumerate() {
                        let o = wrow(n, s, d);
                        weights[o..o + MAX_K].copy_from_slice(row);
                        let z = &mut nonzero[nzrow(n, s, d)..][..MAX_K + 1];
                        let mut cnt = 0;
                        for (j, &wj) in row.iter().enumerate().take(2 * n + 8) {
                            if wj != 0.0 {
                                cnt += 1;
                                z[cnt] = j as u32;
                            }
                        }
                        z[0] = cnt as u32;
                    }
                }
                for p in 0..OG {
                    let (u, v) = grid_point(p);
                    let mut rows: WeightRows = [[0.0; MAX_K]; ROWS];
                    patch_weights(tables, n, u, v, &mut rows)?;
                    for d in 0..2 {
                        gweights[gwrow(n, p, d)..][..MAX_K].copy_from_slice(&rows[d + 1]);
                    }
                }
            }
        }

        // Derivatives of G at the samples, each kind scaled by its RMS (du
        // and dv always: the anchor targets of `super::folds`).
        let gpos = g.positions();
        let mut sum_sq = [0.0f64; ROWS];
        let mut count = [0usize; ROWS];
        for f in 0..nf {
            let n = valence[f] as usize;
            if n == 0 {
                continue;
            }
            let k = 2 * n + 8;
            let lab = &labels[f * MAX_K..f * MAX_K + k];
            for s in 0..NS {
                for d in 1..ROWS {
                    if opts.derivatives & (1 << d) == 0 && d > 2 {
                        continue;
                    }
                    let wr = &weights[wrow(n, s, d)..wrow(n, s, d) + k];
                    let mut q = glam::DVec3::ZERO;
                    for (&l, &wt) in lab.iter().zip(wr) {
                        q += get3(gpos, l as usize) * wt;
                    }
                    set3(&mut dirs[drow(f, s, 0)..], d, q);
                    sum_sq[d] += q.length_squared();
                    count[d] += 1;
                }
            }
        }
        // One scale per group (du and dv; duu and dvv; duv), so that the
        // objective does not depend on which corner a patch frame starts
        // at (a quarter turn swaps u and v).
        let group = |d: usize| match d {
            1 | 2 => [1, 2],
            3 | 5 => [3, 5],
            _ => [d, d],
        };
        let mut scale = [0.0f64; ROWS];
        let mut rms = [0.0f64; ROWS];
        for d in 1..ROWS {
            let [a, b] = group(d);
            let (sq, cnt) = if a == b {
                (sum_sq[a], count[a])
            } else {
                (sum_sq[a] + sum_sq[b], count[a] + count[b])
            };
            if cnt > 0 && sq > 0.0 {
                rms[d] = libm::sqrt(sq / cnt as f64);
                scale[d] = 1.0 / rms[d];
            }
        }
        for f in 0..nf {
            for s in 0..NS {
                for d in 1..ROWS {
                    let o = drow(f, s, d);
                    for x in &mut dirs[o..o + 3] {
                        *x *= scale[d];
                    }
                }
            }
        }

        for i in 0..n1 {
            let (a0, a1, a2) = limit_coefficients(w, g.valence(i));
            coef[3 * i] = 1.0 / a0;
            coef[3 * i + 1] = a1 / a0;
            coef[3 * i + 2] = a2 / a0;
            set3(target, i, p.position(i));
        }

        // Per-axis scale: bounding box of P over that of the limit points
        // of G's Type I vertices.
        let (mut llo, mut lhi) = (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN));
        for i in 0..n1 {
            let (a0, a1, a2) = limit_coefficients(w, g.valence(i));
            let mut l = get3(gpos, i) * a0;
            super::ring::for_ring(&g, i, |e, fv| {
                l += get3(gpos, e) * a1 + get3(gpos, fv) * a2;
            });
            llo = llo.min(l);
            lhi = lhi.max(l);
        }
        let ext_p = hi - lo;
        let ext_l = lhi - llo;
        let mut axis_scale = glam::DVec3::ONE;
        for a in 0..3 {
            if ext_l[a] > 0.0 && ext_p[a] > 0.0 {
                axis_scale[a] = ext_p[a] / ext_l[a];
            }
        }
        let mut me = Interpolator {
            tables,
            rms,
            scale: axis_scale,
            g,
            opts,
            n1,
            m,
            valence,
            labels,
            weights,
            nonzero,
            dirs,
            coef,
            target,
            precond: &mut [],
            precond_ready: false,
            work,
            rows: Rows::empty(),
            stamps: &mut [],
            blocks: 0,
            matrix: None,
            anchor,
            anchored: false,
            gweights,
            orient,
            orient_weight,
            oriented: false,
            loose: false,
            first_residual: 0.0,
        };
        me.blocks = me.count_blocks(stamps);
        me.stamps = stamps;
        me.precond = precond;
        if !reqs.is_empty() {
            // The requirement rows are factored in the block-Jacobi metric.
            me.ensure_preconditioner();
        }
        let mut rows = rows;
        let work = core::mem::replace(&mut me.work, Work::empty());
        me.fill_rows(tables, reqs, &mut rows, work.tmp)?;
        me.factor_rows(&mut rows, work.z, work.p);
        me.work = work;
        me.rows = rows;
        Ok(me)
    }

    /// The subdivided mesh `G` (positions, face sizes, indices): the
    /// topology of `Q`.
    pub fn subdivided(&self) -> &Topology<'a> {
        &self.g
    }

    /// Number of vertices of `Q`.
    pub fn num_vertices(&self) -> usize {
        self.m
    }

    /// Number of Type I vertices (the vertices of `P`, first in `Q`).
    pub fn num_type1(&self) -> usize {
        self.n1
    }

    /// The naive solution into `out` (`3 * num_vertices()` values): `G`'s
    /// Type II vertices with the Type I vertices of \[CL-R eq. 4.1\].
    pub fn naive_into(&self, out: &mut [f64]) -> Result<(), Error> {
        let len = 3 * self.m;
        if out.len() < len {
            return Err(Error::BufferTooSmall { required: len });
        }
        out[..len].copy_from_slice(&self.g.positions()[..len]);
        fill_type1(&self.g, self.coef, Some(self.target), &mut out[..len]);
        Ok(())
    }

    /// The similarity objective (\[CL-R eq. 4.5\], see
    /// [`SolveStats::objective`]) of the control points `q` (`3 *
    /// num_vertices()` values, `Q`'s numbering).
    pub fn objective(&self, q: &[f64]) -> Result<f64, Error> {
        let len = 3 * self.m;
        if q.len() < len {
            return Err(Error::BufferTooSmall { required: len });
        }
        Ok(self.similarity(&q[..len], None, false))
    }

    /// Solves the least-squares system by preconditioned conjugate
    /// gradients from the naive solution and writes `Q`'s control points
    /// into `out` (`3 * num_vertices()` values). `progress(iteration,
    /// relative_residual)` is called after every iteration.
    ///
    /// Errors: [`Error::BufferTooSmall`] (values) for a short `out`,
    /// [`Error::NotConverged`] when `max_iterations` pass first (nothing
    /// is written then).
    pub fn solve(
        &mut self,
        out: &mut [f64],
        progress: &mut dyn FnMut(u32, f64),
    ) -> Result<SolveStats, Error> {
        let len = 3 * self.m;
        if out.len() < len {
            return Err(Error::BufferTooSmall { required: len });
        }
        if self.anchored || self.oriented {
            // A previous solve's fold rows: start afresh.
            self.anchor.fill(0.0);
            self.anchored = false;
            self.orient_weight.fill(0.0);
            self.oriented = false;
            self.precond_ready = false;
        }
        self.ensure_preconditioner();
        let mut stats = SolveStats::default();
        let mut work = core::mem::replace(&mut self.work, Work::empty());
        // x: G's Type II vertices (Type I entries stay 0).
        work.x.copy_from_slice(&self.g.positions()[..len]);
        work.x[..3 * self.n1].fill(0.0);
        let outcome = self.solve_rounds(&mut work, &mut stats, progress);
        let outcome = outcome.map(|()| {
            stats.objective = self.similarity(work.tmp, None, false);
            out[..len].copy_from_slice(work.tmp);
            stats
        });
        self.work = work;
        outcome
    }

    /// The first solve from `work.x` and the fold-removal rounds of
    /// [`super::folds`]; leaves `Q` (all vertices) in `work.tmp`.
    fn solve_rounds(
        &mut self,
        work: &mut Work,
        stats: &mut SolveStats,
        progress: &mut dyn FnMut(u32, f64),
    ) -> Result<(), Error> {
        self.meet_requirements(work)?;
        let mut round = 0u32;
        let orientation =
            self.opts.fold_removal == FoldRemoval::Orientation && self.opts.fold_rounds > 0;
        // The first solve is full; orientation rounds after it solve
        // loosely, and one full solve follows them.
        let mut last = false;
        loop {
            self.loose = orientation && round > 0 && !last;
            // r = -(A x - c): the negative half gradient at x.
            work.tmp.copy_from_slice(work.x);
            fill_type1(&self.g, self.coef, Some(self.target), work.tmp);
            let naive = self.similarity(work.tmp, Some(&mut *work.r), true);
            self.anchor_terms(work.tmp, Some(&mut *work.r), true);
            self.orient_terms(work.tmp, Some(&mut *work.r), true);
            if round == 0 {
                stats.naive_objective = naive;
            }
            fold_type1(&self.g, self.coef, work.r);
            for v in work.r.iter_mut() {
                *v = -*v;
            }
            if round == 0 {
                self.first_residual = 0.0;
            }
            let (it, r0, r1) = pcg(self, work, progress)?;
            if round == 0 {
                self.first_residual = r0;
            }
            // Back onto the requirements exactly: CG keeps its directions
            // on them, this removes what rounding left over.
            self.meet_requirements(work)?;
            stats.iterations += it;
            if round == 0 {
                stats.initial_residual = r0;
            }
            stats.final_residual = r1;
            work.tmp.copy_from_slice(work.x);
            fill_type1(&self.g, self.coef, Some(self.target), work.tmp);
            // Conflicting normal requirements are an error before any
            // fold round (their degenerate tangents also look folded).
            self.check_normals(work.tmp)?;
            if self.opts.fold_rounds == 0 {
                break;
            }
            if last {
                stats.folds = self.count_folds(work.tmp)? as u32;
                break;
            }
            let (folds, more) = match self.opts.fold_removal {
                FoldRemoval::Anchors => {
                    let folds = self.mark_folds(work.tmp)?;
                    (folds, folds)
                }
                FoldRemoval::Orientation => {
                    // On the default check grid (the orientation grid) the
                    // marking pass counts the folds too.
                    let (folded, low) = self.mark_orientation(work.tmp);
                    if self.opts.fold_grid as usize == ORIENT_GRID {
                        (folded, low)
                    } else {
                        (self.count_folds(work.tmp)?, low)
                    }
                }
            };
            stats.folds = folds as u32;
            if more == 0 || round == self.opts.fold_rounds {
                if !orientation || round == 0 {
                    break;
                }
                last = true;
            } else {
                round += 1;
            }
            self.precond_ready = false;
            self.ensure_preconditioner();
        }
        stats.fold_rounds = round;
        stats.anchored_faces = self.anchor.iter().filter(|&&a| a > 0.0).count() as u32;
        stats.orientation_rows = self.orient_weight.iter().filter(|&&w| w > 0.0).count() as u32;
        Ok(())
    }
}

impl Interpolator<'_> {
    /// Builds the block-Jacobi blocks face by face unless they are there.
    pub(crate) fn ensure_preconditioner(&mut self) {
        if !self.precond_ready {
            let out = core::mem::take(&mut self.precond);
            match &self.matrix {
                Some(mat) if !self.anchored => self.preconditioner_from_matrix(mat, out),
                _ => self.build_preconditioner(out),
            }
            self.precond = out;
            self.precond_ready = true;
        }
    }

    /// Moves `work.x` onto the requirement rows by the least change in the
    /// preconditioner's metric, and checks every row afterwards.
    fn meet_requirements(&self, work: &mut Work) -> Result<(), Error> {
        let rows = &self.rows;
        let k = rows.count();
        if k == 0 {
            return Ok(());
        }
        let t = &mut work.small[..k];
        for (c, t) in t.iter_mut().enumerate() {
            *t = rows.rhs[c] - rows.row_dot(c, work.x);
        }
        solve_rows(rows.ldl, t);
        work.ap.fill(0.0);
        for (c, &y) in t.iter().enumerate() {
            rows.add_row(c, y, work.ap);
        }
        // x += M^-1 E^T y (precondition_sub subtracts: negate first).
        for v in work.ap.iter_mut() {
            *v = -*v;
        }
        self.precondition_sub(work.ap, work.x);
        let xmax = work.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for c in 0..k {
            let o = c * super::requirements::MAX_ROW;
            let mut size = rows.rhs[c].abs() + rows.size[c];
            for e in 0..rows.len[c] as usize {
                size += rows.coef[o + e].abs() * xmax;
            }
            let miss = (rows.row_dot(c, work.x) - rows.rhs[c]).abs();
            if miss.is_nan() || miss > 1e-9 * size.max(f64::MIN_POSITIVE) {
                return Err(Error::ConflictingRequirement {
                    requirement: rows.owner[c],
                });
            }
        }
        Ok(())
    }
}
