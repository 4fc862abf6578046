//! The rows of the extra requirements over the unknowns, their factored
//! Gram matrix and the check of the normals after the solve (see
//! [`super::requirements`]).

use super::interpolator::Interpolator;
use super::labels::patch_corner;
use super::requirements::{rows_of, Prescribed, Requirement, Rows, MAX_ROW};
use super::ring::{for_ring, get3};
use super::samples::{patch_weights, WeightRows, ROWS};
use crate::config::MAX_K;
use crate::error::Error;
use crate::eval::rot_param;
use glam::DVec3;

impl Interpolator<'_> {
    /// Fills the rows of `reqs` (over the unknowns) and their right-hand
    /// sides; `q0` is scratch of `3m` values.
    pub(crate) fn fill_rows(
        &self,
        tables: &crate::eigen::TableSet,
        reqs: &[Requirement],
        rows: &mut Rows,
        q0: &mut [f64],
    ) -> Result<(), Error> {
        // q0: the constant part of Q (Type II zero, Type I from P).
        q0.fill(0.0);
        super::ring::fill_type1(&self.g, self.coef, Some(self.target), q0);
        let mut c = 0usize;
        for (i, r) in reqs.iter().enumerate() {
            let bad = Error::ConflictingRequirement {
                requirement: i as u32,
            };
            let f = r.face as usize;
            if f >= self.valence.len() {
                return Err(Error::FaceOutOfRange { face: r.face });
            }
            if !(0.0..=1.0).contains(&r.u) || !(0.0..=1.0).contains(&r.v) {
                return Err(Error::ParameterOutOfRange);
            }
            let n = self.valence[f] as usize;
            if n == 0 {
                return Err(Error::InvalidArgument(
                    "a requirement lies on a face of G with two extraordinary corners (not supported)",
                ));
            }
            let (corner, _, _) = patch_corner(&self.g, f);
            let (x, y) = rot_param(corner as u8, r.u, r.v);
            let mut w: WeightRows = [[0.0; MAX_K]; ROWS];
            patch_weights(tables, n, x, y, &mut w)?;
            let (list, value): ([(usize, DVec3); 3], [f64; 3]) = match r.what {
                Prescribed::Position(p) => {
                    if !p.iter().all(|x| x.is_finite()) {
                        return Err(bad);
                    }
                    (
                        [(0, DVec3::X), (0, DVec3::Y), (0, DVec3::Z)],
                        [p[0], p[1], p[2]],
                    )
                }
                Prescribed::Normal(nv) => {
                    let nn = DVec3::from_array(nv);
                    if !(nn.is_finite() && nn.length() > 0.0) {
                        return Err(bad);
                    }
                    let nn = nn.normalize();
                    ([(1, nn), (2, nn), (0, DVec3::ZERO)], [0.0; 3])
                }
            };
            for (&(d, a), &val) in list.iter().zip(&value).take(rows_of(r)) {
                let k = 2 * n + 8;
                let lab = &self.labels[f * MAX_K..f * MAX_K + k];
                let o = c * MAX_ROW;
                let mut len = 0usize;
                let mut constant = 0.0;
                let mut magnitude = val.abs();
                {
                    let idx = &mut rows.idx[o..o + MAX_ROW];
                    let coef = &mut rows.coef[o..o + MAX_ROW];
                    let mut push = |v: usize, cf: f64| {
                        if cf == 0.0 {
                            return;
                        }
                        for t in 0..len {
                            if idx[t] as usize == v {
                                coef[t] += cf;
                                return;
                            }
                        }
                        if len < MAX_ROW {
                            idx[len] = v as u32;
                            coef[len] = cf;
                            len += 1;
                        }
                    };
                    for (&l, &wj) in lab.iter().zip(&w[d][..k]) {
                        let l = l as usize;
                        constant += wj * a.dot(get3(q0, l));
                        magnitude += (wj * a.dot(get3(q0, l))).abs();
                        if l >= self.n1 {
                            push(l, wj);
                        } else {
                            let (ce, cf) = (self.coef[3 * l + 1], self.coef[3 * l + 2]);
                            for_ring(&self.g, l, |e, fv| {
                                push(e, -wj * ce);
                                push(fv, -wj * cf);
                            });
                        }
                    }
                }
                // Cancellation noise (a row the interpolation conditions
                // fix, e.g. a position at a Type I vertex) becomes exact 0.
                let wmax = w[d][..k].iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let mut kept = 0usize;
                for t in 0..len {
                    let (vi, cf) = (rows.idx[o + t], rows.coef[o + t]);
                    if cf.abs() > 1e-12 * wmax {
                        rows.idx[o + kept] = vi;
                        rows.coef[o + kept] = cf;
                        kept += 1;
                    }
                }
                let len = kept;
                rows.len[c] = len as u32;
                rows.owner[c] = i as u32;
                rows.kind[c] = d as u32;
                rows.at[3 * c] = f as f64;
                rows.at[3 * c + 1] = x;
                rows.at[3 * c + 2] = y;
                super::ring::set3(rows.dir, c, a);
                rows.rhs[c] = val - constant;
                rows.size[c] = magnitude;
                c += 1;
            }
        }
        Ok(())
    }

    /// Factors `E M^-1 E^T` into `rows.ldl` (`z` is `3m` scratch). Zero
    /// pivots (dependent rows) are marked by a zero `D`.
    pub(crate) fn factor_rows(&self, rows: &mut Rows, z: &mut [f64], w: &mut [f64]) {
        let k = rows.count();
        if k == 0 {
            return;
        }
        // Column j of E M^-1 E^T: E M^-1 E_j^T.
        for j in 0..k {
            w.fill(0.0);
            rows.add_row(j, 1.0, w);
            self.precondition_block(w, z);
            for i in j..k {
                rows.ldl[i * k + j] = rows.row_dot(i, z);
            }
        }
        let mut max_diag = 0.0f64;
        for i in 0..k {
            max_diag = max_diag.max(rows.ldl[i * k + i]);
        }
        let eps = 1e-10 * max_diag;
        // In place LDL^T of the lower triangle.
        for j in 0..k {
            let mut d = rows.ldl[j * k + j];
            for p in 0..j {
                let l = rows.ldl[j * k + p];
                d -= l * l * rows.ldl[p * k + p];
            }
            let dead = d.is_nan() || d <= eps;
            rows.ldl[j * k + j] = if dead { 0.0 } else { d };
            for i in j + 1..k {
                if dead {
                    rows.ldl[i * k + j] = 0.0;
                    continue;
                }
                let mut s = rows.ldl[i * k + j];
                for p in 0..j {
                    s -= rows.ldl[i * k + p] * rows.ldl[j * k + p] * rows.ldl[p * k + p];
                }
                rows.ldl[i * k + j] = s / d;
            }
        }
    }
}

impl Interpolator<'_> {
    /// Checks the normal requirements on the solved control points `q`:
    /// their rows only make both tangents perpendicular to the normal, which
    /// two different normals at one point also allow by making the tangents
    /// parallel. A tangent plane that is degenerate or not perpendicular to
    /// the prescribed normal is [`Error::ConflictingRequirement`].
    pub(crate) fn check_normals(&self, q: &[f64]) -> Result<(), Error> {
        let rows = &self.rows;
        for c in 0..rows.count() {
            if rows.kind[c] != 1 {
                continue;
            }
            let f = rows.at[3 * c] as usize;
            let (x, y) = (rows.at[3 * c + 1], rows.at[3 * c + 2]);
            let n = self.valence[f] as usize;
            let k = 2 * n + 8;
            let mut w: WeightRows = [[0.0; MAX_K]; ROWS];
            patch_weights(self.tables, n, x, y, &mut w)?;
            let lab = &self.labels[f * MAX_K..f * MAX_K + k];
            let (mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO);
            for (j, &l) in lab.iter().enumerate() {
                du += get3(q, l as usize) * w[1][j];
                dv += get3(q, l as usize) * w[2][j];
            }
            let cross = du.cross(dv);
            let scale = du.length() * dv.length();
            let sine = cross.normalize_or_zero().cross(rows.dir(c)).length();
            if cross.length() <= 1e-6 * scale || sine.is_nan() || sine > 1e-8 {
                return Err(Error::ConflictingRequirement {
                    requirement: rows.owner[c],
                });
            }
        }
        Ok(())
    }
}
