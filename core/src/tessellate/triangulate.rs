//! Triangulation of one output polygon without new vertices.
//!
//! The polygon is a cell's boundary in parameter space: four corners and
//! any number of extra points on the four sides (collinear with their
//! side). A fan from a corner would make zero-area triangles with the points
//! of the corner's own sides, so instead the cell is cut by a diagonal (the
//! shorter one in 3D) into two corner regions, each bounded by two sides
//! and the diagonal, and each region is filled by a zig-zag strip between
//! its two sides, always adding the shorter of the two possible new edges
//! (in 3D). In parameter space every triangle then has two vertices on one
//! side and the third off that side's line, so none is degenerate, and all
//! are counter-clockwise (outward). A polygon of m vertices gives m - 2
//! triangles.

/// The vertex positions the diagonals are measured on: those of
/// [`super::Tessellation::emit`] (`f64`) or of
/// [`super::Tessellation::emit_f32`] (`f32`).
#[derive(Clone, Copy)]
pub(crate) enum Pos<'p> {
    /// `x y z` per vertex in `f64`.
    F64(&'p [f64]),
    /// `x y z` per vertex in `f32`.
    F32(&'p [f32]),
}

/// Position of vertex `v`.
#[inline]
fn pos(positions: Pos, v: u32) -> [f64; 3] {
    let i = 3 * v as usize;
    match positions {
        Pos::F64(ps) => match ps.get(i..i + 3) {
            Some(p) => [p[0], p[1], p[2]],
            None => [f64::NAN; 3],
        },
        Pos::F32(ps) => match ps.get(i..i + 3) {
            Some(p) => [p[0] as f64, p[1] as f64, p[2] as f64],
            None => [f64::NAN; 3],
        },
    }
}

/// Squared distance of two points.
#[inline(always)]
fn sq_dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Squared distance of vertices `a` and `b`.
#[inline]
fn dist2(positions: Pos, a: u32, b: u32) -> f64 {
    sq_dist(pos(positions, a), pos(positions, b))
}

/// Whether a quad with corner positions `p` (counter-clockwise) is cut
/// along its corners 1-3: that diagonal is not longer than 0-2.
#[inline(always)]
pub(crate) fn cut13(p: [[f64; 3]; 4]) -> bool {
    sq_dist(p[1], p[3]) <= sq_dist(p[0], p[2])
}

/// A plain quad: split along the shorter diagonal (2 triangles).
#[inline(always)]
pub(crate) fn quad(poly: &[u32; 4], positions: Pos, out: &mut [u32]) -> Option<usize> {
    let p = poly.map(|v| pos(positions, v));
    quad_cut(poly, cut13(p), out)
}

/// A plain quad cut along corners 1-3 (`c13`) or 0-2 (2 triangles).
#[inline(always)]
pub(crate) fn quad_cut(poly: &[u32; 4], c13: bool, out: &mut [u32]) -> Option<usize> {
    let d = out.get_mut(..6)?;
    if c13 {
        d.copy_from_slice(&[poly[0], poly[1], poly[3], poly[2], poly[3], poly[1]]);
    } else {
        d.copy_from_slice(&[poly[1], poly[2], poly[0], poly[3], poly[0], poly[2]]);
    }
    Some(2)
}

/// Triangulates `poly` (counter-clockwise; its corners at offsets `at`,
/// `at[0] == 0`) into `out` (3 indices per triangle). Returns the number of
/// triangles written (`poly.len() - 2`), or `None` if `out` is too small.
pub(crate) fn triangulate(
    poly: &[u32],
    at: [usize; 4],
    positions: Pos,
    out: &mut [u32],
) -> Option<usize> {
    let m = poly.len();
    if m < 3 {
        return Some(0);
    }
    if let Ok(q) = <&[u32; 4]>::try_from(poly) {
        return quad(q, positions, out);
    }
    let mut nt = 0usize;
    let mut put = |a: u32, b: u32, c: u32, nt: &mut usize| -> Option<()> {
        let d = out.get_mut(3 * *nt..3 * *nt + 3)?;
        d.copy_from_slice(&[a, b, c]);
        *nt += 1;
        Some(())
    };
    // Diagonal c1-c3 (regions at corners 0 and 2) or c0-c2 (1 and 3).
    let d13 = dist2(positions, poly[at[1]], poly[at[3]]);
    let d02 = dist2(positions, poly[at[0]], poly[at[2]]);
    let first = if d13 <= d02 || d02.is_nan() { 0 } else { 1 };
    // Offsets below 2m: one conditional subtraction instead of a division.
    let v = |k: usize| poly[if k >= m { k - m } else { k }];
    for corner in [first, first + 2] {
        // Offsets are unwrapped: chain A runs forward from the corner to
        // the next corner (offset m stands for 0), chain B backward from
        // the corner (offset start + m) to the previous corner.
        let start = at[corner];
        let end_a = if corner == 3 { m } else { at[corner + 1] };
        let stop_b = at[(corner + 3) & 3] + if corner == 0 { 0 } else { m };
        let (mut a, mut b) = (start + 1, start + m - 1);
        put(v(start), v(a), v(b), &mut nt)?;
        while a != end_a || b != stop_b {
            let adv_a = if a == end_a {
                false
            } else if b == stop_b {
                true
            } else {
                dist2(positions, v(a + 1), v(b)) <= dist2(positions, v(a), v(b - 1))
            };
            if adv_a {
                put(v(a), v(a + 1), v(b), &mut nt)?;
                a += 1;
            } else {
                put(v(a), v(b - 1), v(b), &mut nt)?;
                b -= 1;
            }
        }
    }
    Some(nt)
}
