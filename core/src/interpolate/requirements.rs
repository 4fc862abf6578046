//! Extra hard requirements (\[CL-R §4\], "extra requirements"): a position
//! or a normal prescribed at any (face, u, v) of `Q`.
//!
//! Each requirement is a few linear equations in `Q`'s control points:
//! a position `S(Q)(u, v) = T` three, a normal `N` the two rows
//! `S_u . N = 0`, `S_v . N = 0` (4.7). After the substitution of (4.1) they
//! are rows `E x = f` over the Type II unknowns. The solve keeps them
//! exactly: the start is moved onto them by the least change in the
//! preconditioner's metric, and every search direction is projected onto
//! their null space with the same metric (projected PCG), which needs the
//! small dense matrix `E M^-1 E^T`, factored once (`LDL^T`, in caller
//! memory). A row that the earlier rows and the interpolation conditions
//! already determine (a zero pivot) is dropped when its value agrees and is
//! [`crate::Error::ConflictingRequirement`] when it does not.

use super::ring::get3;
use crate::config::{MAX_K, MAX_VALENCE};
use glam::DVec3;

/// What a requirement prescribes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Prescribed {
    /// The limit position.
    Position([f64; 3]),
    /// The limit normal direction (any non-zero length).
    Normal([f64; 3]),
}

/// A requirement at parameter (u, v) of face `face` of `Q` (`G`'s faces
/// and parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Requirement {
    /// Face of `Q`.
    pub face: u32,
    /// Parameter u in `[0, 1]`.
    pub u: f64,
    /// Parameter v in `[0, 1]`.
    pub v: f64,
    /// Position or normal.
    pub what: Prescribed,
}

/// Most unknowns one requirement row touches after the (4.1) substitution.
pub(crate) const MAX_ROW: usize = MAX_K * (1 + 2 * MAX_VALENCE);

/// Rows of a requirement.
pub(crate) fn rows_of(r: &Requirement) -> usize {
    match r.what {
        Prescribed::Position(_) => 3,
        Prescribed::Normal(_) => 2,
    }
}

/// Total rows of `reqs`.
pub fn num_rows(reqs: &[Requirement]) -> usize {
    reqs.iter().map(rows_of).sum()
}

/// The requirement rows in caller memory.
pub struct Rows<'a> {
    /// Per row: number of entries.
    pub(crate) len: &'a mut [u32],
    /// Per row: requirement index.
    pub(crate) owner: &'a mut [u32],
    /// Per row: weight row used (0 position, 1 du, 2 dv) and face.
    pub(crate) kind: &'a mut [u32],
    /// Per row: face of `G`, and (u, v) in the patch frame.
    pub(crate) at: &'a mut [f64],
    /// Per row, `MAX_ROW` vertex indices.
    pub(crate) idx: &'a mut [u32],
    /// Per row, `MAX_ROW` scalar coefficients.
    pub(crate) coef: &'a mut [f64],
    /// Per row: direction `a` (3) and right-hand side `f` over `x`.
    pub(crate) dir: &'a mut [f64],
    /// Per row: right-hand side.
    pub(crate) rhs: &'a mut [f64],
    /// Per row: magnitude of the terms that formed the right-hand side
    /// (for the check after the solve).
    pub(crate) size: &'a mut [f64],
    /// `E M^-1 E^T` factored: `L` (unit lower, below the diagonal) and `D`
    /// on the diagonal, `k x k`.
    pub(crate) ldl: &'a mut [f64],
}

impl<'a> Rows<'a> {
    pub(crate) fn carve(arena: &mut crate::mem::arena::Arena<'a>, k: usize) -> Self {
        Rows {
            len: arena.u32s(k),
            owner: arena.u32s(k),
            kind: arena.u32s(k),
            at: arena.f64s(3 * k),
            idx: arena.u32s(k * MAX_ROW),
            coef: arena.f64s(k * MAX_ROW),
            dir: arena.f64s(3 * k),
            rhs: arena.f64s(k),
            size: arena.f64s(k),
            ldl: arena.f64s(k * k),
        }
    }

    pub(crate) fn layout(l: &mut crate::mem::arena::Layout, k: usize) {
        l.u32s(k);
        l.u32s(k);
        l.u32s(k);
        l.f64s(3 * k);
        l.u32s(k * MAX_ROW);
        l.f64s(k * MAX_ROW);
        l.f64s(3 * k);
        l.f64s(k);
        l.f64s(k);
        l.f64s(k * k);
    }

    pub(crate) fn empty() -> Self {
        Rows {
            len: &mut [],
            owner: &mut [],
            kind: &mut [],
            at: &mut [],
            idx: &mut [],
            coef: &mut [],
            dir: &mut [],
            rhs: &mut [],
            size: &mut [],
            ldl: &mut [],
        }
    }

    /// Number of rows.
    pub(crate) fn count(&self) -> usize {
        self.len.len()
    }

    pub(crate) fn dir(&self, c: usize) -> DVec3 {
        get3(self.dir, c)
    }

    /// `(E v)_c` for a vector `v` over the unknowns (full numbering).
    pub(crate) fn row_dot(&self, c: usize, v: &[f64]) -> f64 {
        let a = self.dir(c);
        let o = c * MAX_ROW;
        let mut s = 0.0;
        for e in 0..self.len[c] as usize {
            s += self.coef[o + e] * a.dot(get3(v, self.idx[o + e] as usize));
        }
        s
    }

    /// `v += y E_c^T`.
    pub(crate) fn add_row(&self, c: usize, y: f64, v: &mut [f64]) {
        let a = self.dir(c) * y;
        let o = c * MAX_ROW;
        for e in 0..self.len[c] as usize {
            super::ring::add3(v, self.idx[o + e] as usize, a * self.coef[o + e]);
        }
    }
}

/// `t = (E M^-1 E^T)^+ t` in place, from the factors `ldl` (`k x k`);
/// dependent rows get 0.
pub(crate) fn solve_rows(ldl: &[f64], t: &mut [f64]) {
    let k = t.len();
    for i in 0..k {
        let mut s = t[i];
        for p in 0..i {
            s -= ldl[i * k + p] * t[p];
        }
        t[i] = s;
    }
    for i in 0..k {
        let d = ldl[i * k + i];
        t[i] = if d > 0.0 { t[i] / d } else { 0.0 };
    }
    for i in (0..k).rev() {
        let mut s = t[i];
        for p in i + 1..k {
            s -= ldl[p * k + i] * t[p];
        }
        t[i] = s;
    }
}
