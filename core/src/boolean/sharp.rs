//! A posteriori bound of one inscribed triangle ([`triangle_bound`]): a
//! certified `sup |S(x) - T(x)|` over the triangle that uses the actual
//! triangle, sharper than the cell's a-priori bound, for the error bound
//! of the crossings (module docs of [`super`], "sharpened bounds").
//!
//! **Lemma.** Let `T` be a triangle of a tessellation (exact limit points
//! at its three parameter corners `q_0, q_1, q_2`, affine in the
//! parameters over the parameter triangle `D = [q_0, q_1, q_2]`) lying in a
//! *polynomial* cell (`S` one bicubic over the cell) whose second
//! derivatives in cell coordinates (the cell scaled to `[0, 1]^2`) are
//! bounded by `|S_ss| <= a`, `|S_tt| <= b`, `|S_st| <= c`
//! ([`crate::bounds::cell_bound`]), so `|D^2 S[v, v]| <= M |v|^2` with
//! `M = lambda_max([[a, c], [c, b]])`. Split `D` into `n^2` similar
//! triangles (the grid of barycentric coordinates `k / n`) and let
//! `d = max |S(p) - T(p)|` over the grid points `p`, `h` the longest edge
//! of `D` in cell coordinates. Then for every `x` in `D`
//!
//! `|S(x) - T(x)| <= d + M (h / n)^2 / 6`.
//!
//! *Proof.* `x` lies in a grid triangle `D'` with corners `p_i`, barycentric
//! coordinates `l_i`; let `L` be the affine interpolant of `S` at the
//! `p_i` on `D'`. `S(x) - T(x) = (S(x) - L(x)) + (L(x) - T(x))`. `L - T` is
//! affine on `D'`, so its norm is at most its largest value at a corner,
//! `|S(p_i) - T(p_i)| <= d`. For the first term Taylor's theorem with
//! integral remainder at `x` gives `S(p_i) = S(x) + S'(x)(p_i - x) + R_i`,
//! `|R_i| <= M |p_i - x|^2 / 2`; since `sum l_i (p_i - x) = 0`,
//! `L(x) - S(x) = sum l_i R_i`, of norm at most
//! `M / 2 sum l_i |p_i - x|^2 <= M / 2 h'^2 / 3`, `h' = h / n` the longest
//! edge of `D'` (the same inequality as the cell bound of
//! [`crate::bounds`], there with `h'^2 = 2`). `□`
//!
//! So the bound holds in both directions of the Hausdorff distance between
//! `T` and `S(D)`: every point of `T` is `T(x)` for some `x` of `D`, and
//! every point `S(x)` of the cell lies over some triangle of its polygon.
//! The computed bound adds three times the cell's rounding term
//! ([`crate::bounds::rounding`]: the evaluation of the samples, of `T(p)`
//! and the computed output vertices; each is of the order of the term).
//! The parameter corners come from [`super::patch_triangles`]: exact for
//! vertices written in the cell's own sub-face, within `1e-13` in
//! parameter for vertices found on a sub-face border (a far smaller
//! displacement than the rounding term covers, measured in `d` at the
//! corners). Corner cells at extraordinary vertices (where the
//! parametrization is singular) and split cells keep the cell's a-priori
//! bound; the result is never larger than it.
//!
//! With `n = 4` the interpolation term is `1/16` of the a-priori bound, and
//! `d` is the actual deviation at 15 points: on the hands of
//! `bench/boolean_bench.sh` the crossing triangles' bounds come out at
//! about a third of their cells' a-priori bounds (`tests`:
//! `sharp_bound_holds_on_dense_samples` checks the lemma against dense
//! samples and reports the tightness).

use super::PatchTriangle;
use crate::bounds::{cell_bound, CellBound, CellKind};
use crate::error::Error;
use crate::eval::Evaluator;
use crate::tessellate::PolygonCell;
use glam::DVec3;

/// Grid subdivisions per edge of a parameter triangle in
/// [`triangle_bound`] (`(n + 1)(n + 2) / 2` samples): the first try.
pub const SHARP_SAMPLES: u32 = 4;

/// Grid subdivisions per edge for a second try where the bound with
/// [`SHARP_SAMPLES`] is not small enough for the caller: 45 samples and
/// an interpolation term of `1/64` of the a-priori bound instead of
/// `1/16`. On the torus-cube pair of `bench/boolean_bench.sh` (the cube's
/// strongly curved cells) the intersection's triangles go from 1,998 with
/// 4 everywhere to 1,652 with 6, 1,624 with 8 and 1,606 with 12 or 16.
pub const SHARP_SAMPLES_FINE: u32 = 8;

/// A bound of `sup |S(x) - T(x)|` over triangle `tri` (parameter corners
/// `tri.uv`, 3D corners `corners`, the exact limit points there) of the
/// tessellation cell `cell` of `ev`'s surface, from `n` subdivisions per
/// edge (module docs); at most the cell's a-priori
/// [`crate::bounds::CellBound::interpolation_bound`], which is returned
/// for corner and split cells and for `n = 0`.
pub fn triangle_bound(
    ev: &Evaluator,
    cell: &PolygonCell,
    tri: &PatchTriangle,
    corners: &[DVec3; 3],
    n: u32,
) -> Result<f64, Error> {
    let cb = cell_bound(ev, cell.face, cell.sub, cell.level, cell.i, cell.j)?;
    triangle_bound_in(ev, cell, &cb, tri, corners, n)
}

/// [`triangle_bound`] with the cell's bound `cb` already computed
/// ([`crate::bounds::cell_bound`] of `cell`): for callers that bound every
/// triangle of a polygon cell, one cell bound per cell.
pub fn triangle_bound_in(
    ev: &Evaluator,
    cell: &PolygonCell,
    cb: &CellBound,
    tri: &PatchTriangle,
    corners: &[DVec3; 3],
    n: u32,
) -> Result<f64, Error> {
    let prior = cb.interpolation_bound();
    if cb.kind != CellKind::Polynomial || n == 0 {
        return Ok(prior);
    }
    let [a, b, c] = cb.second;
    let m = 0.5 * (a + b) + libm::sqrt(0.25 * (a - b) * (a - b) + c * c);
    // Edges in cell coordinates: parameter differences times 2^level.
    let scale = libm::scalbn(1.0, cell.level as i32);
    let q = |k: usize| [tri.uv[2 * k], tri.uv[2 * k + 1]];
    let mut h2 = 0.0f64;
    for k in 0..3 {
        let (p0, p1) = (q(k), q((k + 1) % 3));
        let du = (p1[0] - p0[0]) * scale;
        let dv = (p1[1] - p0[1]) * scale;
        h2 = h2.max(du * du + dv * dv);
    }
    let nf = n as f64;
    let interp = m * h2 / (nf * nf) / 6.0;
    let mut d = 0.0f64;
    for i in 0..=n {
        for j in 0..=n - i {
            let l1 = i as f64 / nf;
            let l2 = j as f64 / nf;
            let l0 = 1.0 - l1 - l2;
            let u = l0 * tri.uv[0] + l1 * tri.uv[2] + l2 * tri.uv[4];
            let v = l0 * tri.uv[1] + l1 * tri.uv[3] + l2 * tri.uv[5];
            let t = corners[0] * l0 + corners[1] * l1 + corners[2] * l2;
            let s = ev.eval_derivs(cell.face, cell.sub, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))?;
            d = d.max((s.p - t).length());
        }
    }
    Ok((d + interp + 3.0 * cb.rounding).min(prior))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::boolean::{patch_triangles, TessellationUv};
    use crate::eigen::{BuildScratch, TableSet};
    use crate::eval::Query;
    use crate::mem::words_for;
    use crate::mesh::MeshInput;
    use crate::tessellate::cells::tests::righthanded;
    use crate::tessellate::{Options, Output, Scratch, Tessellation};
    use crate::Topology;
    use std::boxed::Box;
    use std::vec;
    use std::vec::Vec;

    /// Every triangle of an adaptive tessellation of the righthanded model
    /// (valences 3, 4, 5; polynomial and corner cells): the bound of
    /// [`triangle_bound`] with `n = 1, 2, 4` is at least the largest of
    /// `|S(x) - T(x)|` over a 24 x 24 grid of the triangle (every grid
    /// point evaluated exactly; the brute-force oracle), and at most the
    /// cell's a-priori bound; with `n = 4` it is much smaller than the
    /// a-priori bound on average (the point of the lemma). Prints the
    /// tightness (dense max / bound).
    #[test]
    #[cfg_attr(miri, ignore = "tessellates a 434-face model: minutes under Miri")]
    fn sharp_bound_holds_on_dense_samples() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let (p, idx) = righthanded();
        let sizes = vec![4u32; idx.len() / 4];
        let mesh = MeshInput {
            positions: &p,
            face_sizes: &sizes,
            indices: &idx,
        };
        let mut tm = vec![0u64; words_for(Topology::required_bytes(p.len() / 3, &sizes))];
        let topo = Topology::build(mesh, &mut tm).unwrap();
        let mut em = vec![0u64; words_for(Evaluator::required_bytes(&topo, &ts).unwrap())];
        let ev = Evaluator::build(&topo, &ts, &mut em).unwrap();
        // The model is about 4 units across: a coarse tolerance keeps the
        // test small (a few thousand triangles).
        let opts = Options::absolute(4e-3);
        let need =
            Tessellation::required_bytes(&topo, &ev, &opts, &mut Box::new(Scratch::ZERO)).unwrap();
        let mut mem = vec![0u64; words_for(need)];
        let mut t = Tessellation::build(&topo, &ev, opts, &mut mem).unwrap();
        let c = t.counts();
        let mut pos = vec![0.0; 3 * c.vertices];
        let mut params = vec![Query::default(); c.vertices];
        let mut psizes = vec![0u32; c.polygons];
        let mut pidx = vec![0u32; c.polygon_indices];
        let mut tris = vec![0u32; 3 * c.triangles];
        let mut cells = vec![PolygonCell::default(); c.polygons];
        t.emit(Output {
            positions: &mut pos,
            normals: None,
            params: Some(&mut params),
            polygon_sizes: &mut psizes,
            polygon_indices: &mut pidx,
            triangles: Some(&mut tris),
            cells: Some(&mut cells),
        })
        .unwrap();
        let mut uv = vec![PatchTriangle::default(); c.triangles];
        let tuv = TessellationUv {
            positions: &pos,
            params: &params,
            polygon_sizes: &psizes,
            cells: &cells,
            triangles: &tris,
        };
        patch_triangles(
            tuv,
            &mut |q| Ok(ev.eval(q.face, q.sub, q.u, q.v)?.p),
            &mut uv,
        )
        .unwrap();
        let cell_of: Vec<usize> = psizes
            .iter()
            .enumerate()
            .flat_map(|(k, &n)| (2..n).map(move |_| k))
            .collect();
        let point = |v: u32| DVec3::from_slice(&pos[3 * v as usize..3 * v as usize + 3]);
        const DENSE: u32 = 24;
        let (mut sum_ratio, mut worst_tight, mut polys) = (0.0, 0.0f64, 0usize);
        let (mut sum_fine, mut worst_fine) = (0.0, 0.0f64);
        // Every third triangle: all kinds of cells, bounded time.
        for k in (0..c.triangles).step_by(3) {
            let cell = &cells[cell_of[k]];
            let corners = [
                point(tris[3 * k]),
                point(tris[3 * k + 1]),
                point(tris[3 * k + 2]),
            ];
            let tri = &uv[k];
            let mut dense = 0.0f64;
            for i in 0..=DENSE {
                for j in 0..=DENSE - i {
                    let (l1, l2) = (i as f64 / DENSE as f64, j as f64 / DENSE as f64);
                    let l0 = 1.0 - l1 - l2;
                    let u = l0 * tri.uv[0] + l1 * tri.uv[2] + l2 * tri.uv[4];
                    let v = l0 * tri.uv[1] + l1 * tri.uv[3] + l2 * tri.uv[5];
                    let s = ev
                        .eval(cell.face, cell.sub, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
                        .unwrap()
                        .p;
                    let x = corners[0] * l0 + corners[1] * l1 + corners[2] * l2;
                    dense = dense.max((s - x).length());
                }
            }
            let prior = triangle_bound(&ev, cell, tri, &corners, 0).unwrap();
            assert!(prior <= 4e-3, "triangle {k}: a-priori {prior}");
            let cb = cell_bound(&ev, cell.face, cell.sub, cell.level, cell.i, cell.j).unwrap();
            let polynomial = cb.kind == CellKind::Polynomial;
            for n in [1, 2, SHARP_SAMPLES, SHARP_SAMPLES_FINE] {
                let b = triangle_bound(&ev, cell, tri, &corners, n).unwrap();
                assert!(
                    dense <= b,
                    "triangle {k}, n = {n}: dense max {dense:e} above the bound {b:e}"
                );
                assert!(b <= prior, "triangle {k}, n = {n}: {b:e} above {prior:e}");
                if polynomial && n == SHARP_SAMPLES {
                    sum_ratio += b / prior;
                    polys += 1;
                    worst_tight = worst_tight.max(dense / b);
                }
                if polynomial && n == SHARP_SAMPLES_FINE {
                    sum_fine += b / prior;
                    worst_fine = worst_fine.max(dense / b);
                }
            }
        }
        let mean = sum_ratio / polys as f64;
        let mean_fine = sum_fine / polys as f64;
        std::println!(
            "sharp bound: {polys} polynomial-cell triangles, mean bound / a-priori {mean:.3}, \
             largest dense max / bound {worst_tight:.3}; with {SHARP_SAMPLES_FINE} subdivisions \
             {mean_fine:.3} and {worst_fine:.3}"
        );
        assert!(
            mean_fine < mean,
            "finer grid: mean {mean_fine} not below {mean}"
        );
        assert!(polys > 500, "{polys} polynomial-cell triangles");
        assert!(mean < 0.6, "mean sharp / a-priori bound {mean}");
    }
}
