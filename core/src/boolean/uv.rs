//! The parameter-space triangles of a tessellation ([`patch_triangles`]),
//! the input of [`super::Boolean::emit_uv`].
//!
//! Every triangle of a [`crate::tessellate::Tessellation`] lies in one
//! polygon, whose parameter cell ([`PolygonCell`]) is a dyadic square of
//! one sub-face; all its vertices lie in that cell's closure. A vertex's
//! `(face, sub, u, v)` (the tessellation's `params`) names **one** of the
//! sub-faces it belongs to: a vertex on a sub-face border (shared by two
//! or more sub-faces) may be written in a neighbour's parameters. Such a
//! vertex lies on a side of the cell on the sub-face border; its `(u, v)`
//! in the cell's sub-face is found on those sides as the point whose
//! exact surface point is nearest to the vertex (coarse samples, then a
//! golden-section search down to a parameter step of `1e-13`), so all
//! three `(u, v)` of a triangle are in the same domain.

use super::PatchTriangle;
use crate::error::Error;
use crate::eval::Query;
use crate::tessellate::PolygonCell;
use glam::DVec3;

/// A tessellation's emitted arrays (all from one
/// [`crate::tessellate::Tessellation::emit`] with `params`, `cells` and
/// `triangles`).
#[derive(Clone, Copy, Debug)]
pub struct TessellationUv<'a> {
    /// `x y z` per vertex.
    pub positions: &'a [f64],
    /// `(face, sub, u, v)` per vertex.
    pub params: &'a [Query],
    /// Vertex count of each polygon.
    pub polygon_sizes: &'a [u32],
    /// Parameter cell of each polygon.
    pub cells: &'a [PolygonCell],
    /// Three indices per triangle (polygon `p` gives `size(p) - 2`).
    pub triangles: &'a [u32],
}

/// Coarse samples per cell side before the golden-section search.
const COARSE: usize = 8;

/// Writes one [`PatchTriangle`] per triangle of `t` into `out` (at least
/// `triangles / 3` entries, else `BufferTooSmall`). `eval` is the exact
/// surface the tessellation was built from (used only for vertices written
/// in a neighbouring sub-face's parameters).
pub fn patch_triangles(
    t: TessellationUv,
    eval: &mut impl FnMut(Query) -> Result<DVec3, Error>,
    out: &mut [PatchTriangle],
) -> Result<(), Error> {
    let nt = t.triangles.len() / 3;
    if out.len() < nt {
        return Err(Error::BufferTooSmall { required: nt });
    }
    let bad = Error::InvalidArgument("boolean: tessellation arrays do not match");
    if t.cells.len() < t.polygon_sizes.len() {
        return Err(bad);
    }
    let mut k = 0usize;
    for (p, &n) in t.polygon_sizes.iter().enumerate() {
        let cell = t.cells[p];
        for _ in 2..n {
            if k >= nt {
                return Err(bad);
            }
            let mut qs = [Query::default(); 3];
            let mut xs = [DVec3::ZERO; 3];
            for c in 0..3 {
                let v = t.triangles[3 * k + c] as usize;
                match (t.params.get(v), t.positions.get(3 * v..3 * v + 3)) {
                    (Some(q), Some(x)) => (qs[c], xs[c]) = (*q, DVec3::from_slice(x)),
                    _ => return Err(bad),
                }
            }
            out[k] = patch_triangle(&cell, &qs, &xs, eval)?;
            k += 1;
        }
    }
    if k != nt {
        return Err(bad);
    }
    Ok(())
}

/// The [`PatchTriangle`] of one triangle of polygon cell `cell`, from its
/// vertices' `params` (as the tessellation wrote them) and positions
/// (module docs; `eval` as in [`patch_triangles`]).
pub fn patch_triangle(
    cell: &PolygonCell,
    params: &[Query; 3],
    positions: &[DVec3; 3],
    eval: &mut impl FnMut(Query) -> Result<DVec3, Error>,
) -> Result<PatchTriangle, Error> {
    let mut uv = [0.0; 6];
    for c in 0..3 {
        let q = &params[c];
        let (u, w) = if (q.face, q.sub) == (cell.face, cell.sub) {
            (q.u, q.v)
        } else {
            on_border(cell, positions[c], eval)?
        };
        uv[2 * c] = u;
        uv[2 * c + 1] = w;
    }
    Ok(PatchTriangle {
        face: cell.face,
        sub: cell.sub,
        uv,
    })
}

/// `(u, v)` on the sides of `cell` on its sub-face's border whose surface
/// point is nearest to `x`.
fn on_border(
    cell: &PolygonCell,
    x: DVec3,
    eval: &mut impl FnMut(Query) -> Result<DVec3, Error>,
) -> Result<(f64, f64), Error> {
    let h = libm::scalbn(1.0, -(cell.level as i32));
    let (u0, v0) = (cell.i as f64 * h, cell.j as f64 * h);
    let (u1, v1) = (u0 + h, v0 + h);
    // Sides as segments (start, end) in (u, v).
    let sides = [
        ((u0, v0), (u1, v0)),
        ((u1, v0), (u1, v1)),
        ((u0, v1), (u1, v1)),
        ((u0, v0), (u0, v1)),
    ];
    let on_border = [v0 == 0.0, u1 == 1.0, v1 == 1.0, u0 == 0.0];
    let mut best = (f64::INFINITY, (u0, v0));
    for (side, &((a0, b0), (a1, b1))) in sides.iter().enumerate() {
        if !on_border[side] {
            continue;
        }
        let at = |s: f64| (a0 + (a1 - a0) * s, b0 + (b1 - b0) * s);
        let mut dist = |s: f64| -> Result<f64, Error> {
            let (u, v) = at(s);
            let p = eval(Query {
                face: cell.face,
                sub: cell.sub,
                u,
                v,
            })?;
            Ok((p - x).length())
        };
        let mut sb = (f64::INFINITY, 0.0);
        for k in 0..=COARSE {
            let s = k as f64 / COARSE as f64;
            let d = dist(s)?;
            if d < sb.0 {
                sb = (d, s);
            }
        }
        let step = 1.0 / COARSE as f64;
        let (mut lo, mut hi) = ((sb.1 - step).max(0.0), (sb.1 + step).min(1.0));
        let g = 0.5 * (libm::sqrt(5.0) - 1.0);
        let (mut c, mut d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut fc, mut fd) = (dist(c)?, dist(d)?);
        while hi - lo > 1e-13 {
            if fc <= fd {
                hi = d;
                d = c;
                fd = fc;
                c = hi - g * (hi - lo);
                fc = dist(c)?;
            } else {
                lo = c;
                c = d;
                fc = fd;
                d = lo + g * (hi - lo);
                fd = dist(d)?;
            }
        }
        for (f, s) in [(fc, c), (fd, d)] {
            if f < sb.0 {
                sb = (f, s);
            }
        }
        if sb.0 < best.0 {
            best = (sb.0, at(sb.1));
        }
    }
    if best.0.is_infinite() {
        return Err(Error::InvalidArgument(
            "boolean: a vertex of another sub-face inside a cell",
        ));
    }
    Ok(best.1)
}
