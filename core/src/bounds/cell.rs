//! Guaranteed error bounds over dyadic parameter cells, for adaptive
//! tessellation with a certified tolerance (\[CL-R ch. 7\]).
//!
//! A cell of a slot (base face, sub-face) at level `l` is
//! `[i/2^l, (i+1)/2^l] x [j/2^l, (j+1)/2^l]`. Tessellations emit, per
//! accepted cell, a polygon whose vertices are exact limit points on the
//! cell's boundary (its corners plus the points neighbours created), split
//! into triangles. [`CellBound::interpolation_bound`] bounds
//! `||S(x) - T(x)||` for **every** such triangulation T, where T(x) is the
//! linear interpolant of S on the triangle containing x:
//!
//! * **Polynomial cells** (regular patches, and cells of an extraordinary
//!   patch away from its corner, which lie in one region Omega_{m,b}, report
//!   §2.1): S is bicubic on the cell. In cell coordinates (s,t) in `[0, 1]^2`
//!   we compute its Bezier net P (exact conversion from the B-spline grid)
//!   and bound the second derivatives by the convex hull property:
//!   `|S_ss| <= 6 max|D_ss P| = a`, `|S_tt| <= b`, `|S_st| <= 9 max|D_st P| = c`.
//!   For a triangle with vertices p_i and barycentric coordinates l_i,
//!   Taylor's theorem gives `T(x) - S(x) = sum_i l_i R_i`,
//!   `|R_i| <= M |p_i - x|^2 / 2`, `M = lambda_max([[a, c], [c, b]])`, and
//!   `sum_i l_i |p_i - x|^2 <= h^2/3` (h = longest edge <= sqrt 2): the
//!   bound is `M / 3`.
//! * **Corner cells** `[0, 2^-k]^2` at an extraordinary vertex: there is an
//!   affine function A of the patch parameters within `E_k` of every limit
//!   point of the cell ([`crate::eigen::ValenceTable::corner_flatness`], from the
//!   eigen expansion, [`crate::eigen::corner_fit`]). T reproduces A and T(x) - A(x)
//!   is a convex combination of values of S - A, so the bound is `2 E_k`.
//!   The report's bound ("both within eps/2 of S(0,0)", every limit point
//!   within the radius `R_k` of the limit point L,
//!   [`crate::eigen::ValenceTable::corner_radius`]) is this with A = L; `E_k` is
//!   never larger and, since it leaves out the tangent-plane part of the
//!   expansion, usually 10 to 20 times smaller.
//! * **Rounding**: [`CellBound::interpolation_bound`] adds the rounding
//!   term of [`crate::bounds::rounding`] (patch data, de Casteljau nets and
//!   the bound's own arithmetic); out-of-range data is
//!   [`Error::CoordinateRange`].
//! * Level-0 cells of slots that are split internally (quads with several
//!   extraordinary vertices, n-gon sub-faces next to one) are not one patch:
//!   their bound is infinite, so they are always split.

use crate::error::Error;
use crate::eval::{quadrant, rot_param, Evaluator};
use crate::math::bezier::{grid_second_bounds, second_bound};
use crate::math::bspline::Grid;

/// Kind of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// The limit surface is one bicubic polynomial over the cell.
    Polynomial,
    /// The cell touches an extraordinary vertex.
    Corner,
    /// The cell spans several patches (must be split).
    Split,
}

/// Guaranteed bounds over one cell (see module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellBound {
    /// Kind of cell.
    pub kind: CellKind,
    /// Upper bounds of |S_ss|, |S_tt|, |S_st| in cell coordinates
    /// (polynomial cells).
    pub second: [f64; 3],
    /// Radius around the limit point (corner cells): every limit point of
    /// the cell is within it.
    pub radius: f64,
    /// Corner cells: the distance `E_k` of the surface from an affine
    /// function of the parameters over the cell (at most `radius`).
    pub flatness: f64,
    /// Rounding term added by [`CellBound::interpolation_bound`]
    /// ([`crate::bounds::rounding::term`] of the slot's control data):
    /// the other fields are exact-arithmetic quantities.
    pub rounding: f64,
}

impl CellBound {
    /// Upper bound of `||S(x) - T(x)||` over the cell for any triangulation
    /// T of a polygon of limit points on the cell boundary.
    pub fn interpolation_bound(&self) -> f64 {
        match self.kind {
            CellKind::Polynomial => second_bound(self.second) + self.rounding,
            CellKind::Corner => 2.0 * self.flatness + self.rounding,
            CellKind::Split => f64::INFINITY,
        }
    }
}

/// Guaranteed bounds over the cell `(level, i, j)` of sub-face `sub` of
/// base face `face` (see module docs). Errors: bad face/sub, `i` or `j`
/// not below `2^level`, `level > 52`.
pub fn cell_bound(
    ev: &Evaluator,
    face: u32,
    sub: u32,
    level: u32,
    i: u32,
    j: u32,
) -> Result<CellBound, Error> {
    let f = face as usize;
    if f >= ev.num_faces() {
        return Err(Error::FaceOutOfRange { face });
    }
    if sub as usize >= ev.num_subfaces(f) {
        return Err(Error::SubFaceOutOfRange { face, sub });
    }
    if level > 52 || (i as u64) >= (1u64 << level) || (j as u64) >= (1u64 << level) {
        return Err(Error::InvalidArgument(
            "cell outside the sub-face or level above 52",
        ));
    }
    let slot = ev.slot_start(f) + sub as usize;
    let size = libm::scalbn(1.0, -(level as i32));
    let (mut s1, mut t1) = (i as f64 * size, j as f64 * size);
    let (mut s2, mut t2) = (s1 + size, t1 + size);
    let mut pi = ev.slot_patch[slot] as usize;
    if ev.slot_split[slot] != 0 {
        if level == 0 {
            return Ok(CellBound {
                kind: CellKind::Split,
                second: [0.0; 3],
                radius: 0.0,
                flatness: 0.0,
                rounding: 0.0,
            });
        }
        // The cell lies in one quadrant; map to the child patch (x2 scale).
        let c = quadrant(0.5 * (s1 + s2), 0.5 * (t1 + t2));
        let (a1, b1) = rot_param(c, s1, t1);
        let (a2, b2) = rot_param(c, s2, t2);
        s1 = 2.0 * a1.min(a2);
        s2 = 2.0 * a1.max(a2);
        t1 = 2.0 * b1.min(b2);
        t2 = 2.0 * b1.max(b2);
        pi += c as usize;
    }
    let meta = ev.patch_meta[pi];
    let n = (meta & 0xff) as usize;
    let rounding = super::rounding::term(super::rounding::slot_magnitude(ev, slot))?;
    let r = ((meta >> 8) & 3) as u8;
    let (a1, b1) = rot_param(r, s1, t1);
    let (a2, b2) = rot_param(r, s2, t2);
    let (x1, x2, y1, y2) = (a1.min(a2), a1.max(a2), b1.min(b2), b1.max(b2));
    let o = ev.patch_data[pi] as usize;
    if n == 4 {
        let g = <&Grid>::try_from(&ev.data[o..o + 48])
            .map_err(|_| Error::InvalidArgument("patch data"))?;
        return Ok(CellBound {
            kind: CellKind::Polynomial,
            second: grid_second_bounds(g, x1, x2, y1, y2),
            radius: 0.0,
            flatness: 0.0,
            rounding,
        });
    }
    let tab = ev
        .tables
        .get(n)
        .ok_or(Error::MissingTable { valence: n as u32 })?;
    let lay = ev.ev_layout(o, n);
    let ghat = &ev.data[lay.ghat()];
    if x1 == 0.0 && y1 == 0.0 {
        // Corner cell [0, 2^-kk]^2.
        let (_, e) = libm::frexp(x2 - x1); // x2 - x1 = 2^-kk exactly
        let kk = (1 - e).max(0) as u32;
        return Ok(CellBound {
            kind: CellKind::Corner,
            second: [0.0; 3],
            radius: tab.corner_radius(ghat, kk),
            flatness: ev.corner_flatness(pi, kk).unwrap_or(f64::INFINITY),
            rounding,
        });
    }
    // One region Omega_{m,b}: the one containing the cell centre.
    let (xc, yc) = (0.5 * (x1 + x2), 0.5 * (y1 + y2));
    let (_, e) = libm::frexp(xc.max(yc));
    let m = (1 - e).max(1);
    let scale = libm::scalbn(1.0, m);
    let (ub, vb) = (xc * scale, yc * scale);
    let (b, du, dv) = if ub >= 1.0 {
        if vb >= 1.0 {
            (2usize, 1.0, 1.0)
        } else {
            (1, 1.0, 0.0)
        }
    } else {
        (3, 0.0, 1.0)
    };
    let mut g = [0.0; 48];
    if let Some(at) = lay.grid(m as usize, b).filter(|_| m <= 2) {
        g.copy_from_slice(&ev.data[at]);
    } else {
        tab.sub_patch(ghat, m as u32, b, true, &mut g);
    }
    let (u1, u2) = (x1 * scale - du, x2 * scale - du);
    let (v1, v2) = (y1 * scale - dv, y2 * scale - dv);
    Ok(CellBound {
        kind: CellKind::Polynomial,
        second: grid_second_bounds(&g, u1, u2, v1, v2),
        radius: 0.0,
        flatness: 0.0,
        rounding,
    })
}
