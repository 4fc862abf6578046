//! The tessellation with single-precision vertices
//! ([`Tessellation::emit_f32`]) and its guarantee ([`Tessellation::bound_f32`]).
//!
//! The marking, the numbering, the polygons and the bounds are those of
//! [`Tessellation::emit`] (`f64`); only the vertices differ: each is
//! [`Evaluator::eval_f32`] at its parameters, written as `f32`.
//!
//! ## The guarantee in `f32`
//!
//! Let `T` be the piecewise-linear surface of the `f64` tessellation with
//! exact vertices `S(x_k)` and `T32` the same polygons with the `f32`
//! vertices `y_k`. `T32 - T` is the linear interpolant of the vertex
//! errors `y_k - S(x_k)`, so it is at most their largest norm `E`
//! everywhere, and both one-sided distances between `T32` and the limit
//! surface are at most `bound + E`, `bound` the `f64` guarantee
//! ([`super::Stats::bound`]). `bound_f32 = bound + E_32 + R` with:
//!
//! * `R` = [`crate::bounds::rounding::term`]`(M)`: the `f64` data of the
//!   evaluator differ from exact ones by less (the same term covers the
//!   `f64` tessellation's own vertices);
//! * `E_32 = sqrt(3) e M (1 + 2^-20)`, `M` the largest coordinate
//!   magnitude of the slots' control data (what the rounding term uses);
//!   the grids `eval_f32` reads are Catmull-Clark subdivisions of it
//!   (non-negative weights summing to 1), so no value exceeds `M` by more
//!   than the `f64` rounding the factor `1 + 2^-20` covers.
//!
//! `e` bounds the error of one coordinate relative to `M`. Every output
//! vertex is at a dyadic parameter `(i/2^l, j/2^l)`; for `l <= 24` it is
//! exact in `f32`, and so is every parameter the kernel derives from it
//! (`1 - s`, `2 s`, `f x`, `x - 1` on multiples of `2^-24` in `[0, 1]` or
//! `[0, 4]`): the kernel evaluates the bicubic piece at the exact point.
//! With `u = 2^-24` and `gamma_k = k u / (1 - k u)` \[Higham02 §3.1\]:
//!
//! * the 16 control points are rounded to `f32`: `|x^ - x| <= u |x|`;
//! * the basis values `b^_i` (`basis32`) differ from the exact ones by
//!   `sum_i |b^_i - b_i| <= beta`, for **every** `f32` parameter the
//!   kernel can receive (all multiples of `2^-24` in `[0, 1]`): the unit
//!   test `basis_error_exhaustive` of `eval/single.rs` checks all `2^24 + 1` of them against
//!   the exact basis (`f64`, exact for these inputs up to `2^-50`), so
//!   `F32_BASIS_ERR` (`eval/single.rs`) is proved by exhaustion, not sampled;
//! * `p^ = fl(sum_j bv_j fl(sum_i bu_i x^_ij))` is two dot products of
//!   length 4, each term through at most 8 roundings:
//!   `|p^ - sum bv_j bu_i x^_ij| <= gamma_8 sum |bv_j| |bu_i| |x^_ij|`.
//!
//! With `sum |b^| <= 1 + beta` (the exact B-spline basis is a partition of
//! unity):
//! `e = gamma_8 (1 + u)(1 + beta)^2 + u (1 + beta)^2 + 2 beta + beta^2`.
//! The other paths of `eval_f32` are `f64` results rounded once
//! (`|error| <= u M`, below `e M`): the eigen expansion at an
//! extraordinary vertex, and the vertices deeper than level 24, which
//! `emit_f32` evaluates in `f64` and rounds.
//!
//! `tests/tests/tessellate_f32.rs` checks every emitted vertex of the
//! corpus against the `f64` emission within `E_32 + 2 R` (zero
//! violations) and prints the tightness.

use super::plan::Surface;
use super::polygons::PolyOut;
use super::triangulate::Pos;
use super::vertices::{SingleOut, VertOut};
use super::{PolygonCell, Tessellation};
use crate::bounds::rounding;
use crate::error::Error;
use crate::eval::{Evaluator, Query};

/// Unit roundoff of `f32` (`2^-24`).
const U: f64 = 1.0 / 16_777_216.0;

/// `sqrt(3)` rounded up.
const SQRT3_UP: f64 = 1.732_050_807_568_878;

/// `beta` of the module docs.
const BASIS_ERR: f64 = crate::eval::F32_BASIS_ERR;

/// `e`: the `f32` error of one position coordinate relative to the
/// largest control-data magnitude `M` (module docs).
pub const COORD_ERR: f64 = {
    let g8 = 8.0 * U / (1.0 - 8.0 * U);
    let b = BASIS_ERR;
    let s = (1.0 + b) * (1.0 + b);
    g8 * (1.0 + U) * s + U * s + 2.0 * b + b * b
};

/// Caller buffers for [`Tessellation::emit_f32`], each at least the size
/// [`Tessellation::counts`] gives.
pub struct OutputF32<'o> {
    /// x y z per vertex (`3 * vertices`), by [`Evaluator::eval_f32`].
    pub positions: &'o mut [f32],
    /// Unit normal per vertex (`3 * vertices`), optional.
    pub normals: Option<&'o mut [f32]>,
    /// `(face, sub, u, v)` per vertex (`vertices`), optional.
    pub params: Option<&'o mut [Query]>,
    /// As [`super::Output::polygon_sizes`].
    pub polygon_sizes: &'o mut [u32],
    /// As [`super::Output::polygon_indices`].
    pub polygon_indices: &'o mut [u32],
    /// As [`super::Output::triangles`] (the diagonals measured on the
    /// `f32` positions).
    pub triangles: Option<&'o mut [u32]>,
    /// As [`super::Output::cells`].
    pub cells: Option<&'o mut [PolygonCell]>,
}

impl<'a> Tessellation<'a> {
    /// The largest coordinate magnitude of the slots' control data, and
    /// the smooth surface's evaluator; [`Error::InvalidArgument`] for a
    /// feature tessellation (no `f32` evaluation there yet).
    fn smooth(&self) -> Result<(&'a Evaluator<'a>, f64), Error> {
        let Surface::Smooth(ev) = self.surface else {
            return Err(Error::InvalidArgument(
                "f32 emission needs a tessellation of a mesh without features",
            ));
        };
        let m = (0..ev.num_slots()).fold(0.0f64, |m, s| m.max(rounding::slot_magnitude(ev, s)));
        Ok((ev, m))
    }

    /// The error of every vertex of [`Tessellation::emit_f32`] against the
    /// exact limit point (`E_32 + R` of the module docs).
    pub fn vertex_error_f32(&self) -> Result<f64, Error> {
        let (_, m) = self.smooth()?;
        Ok(SQRT3_UP * COORD_ERR * m * (1.0 + 1.0 / 1_048_576.0) + rounding::term(m)?)
    }

    /// The guarantee of the `f32` output: [`super::Stats::bound`] plus
    /// [`Tessellation::vertex_error_f32`] (module docs).
    pub fn bound_f32(&self) -> Result<f64, Error> {
        Ok(self.stats().bound + self.vertex_error_f32()?)
    }

    /// As [`Tessellation::emit`] with `f32` vertices by
    /// [`Evaluator::eval_f32`] (module docs); same polygons. A mesh with
    /// features: [`Error::InvalidArgument`].
    pub fn emit_f32(&mut self, out: OutputF32) -> Result<(), Error> {
        let (ev, _) = self.smooth()?;
        let c = self.counts;
        c.check_output_lengths([
            Some(out.positions.len()),
            out.normals.as_ref().map(|n| n.len()),
            out.params.as_ref().map(|p| p.len()),
            Some(out.polygon_sizes.len()),
            Some(out.polygon_indices.len()),
            out.triangles.as_ref().map(|t| t.len()),
            out.cells.as_ref().map(|t| t.len()),
        ])?;
        let mut vo = VertOut {
            positions: &mut [],
            normals: None,
            params: out.params,
            cuts: false,
            single: SingleOut {
                ev,
                positions: out.positions,
                normals: out.normals,
            },
        };
        self.vertex_positions(&mut vo)?;
        let so = vo.single;
        let mut po = PolyOut {
            sizes: out.polygon_sizes,
            indices: out.polygon_indices,
            triangles: out.triangles,
            cells: out.cells,
            positions: Pos::F32(so.positions),
            stream: None,
        };
        self.polygons(&mut po).map(|_| ())
    }
}
