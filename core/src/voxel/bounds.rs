//! A guaranteed, tight axis-aligned box of the limit surface, and the
//! normalisation of the model into the voxel grid (algorithm Voxelization,
//! step 1).

use super::cells::{
    corner_children, corner_corners, for_each_root, limit_point, net_box, net_corners, split4,
    Affine, Cell, Net, Patch,
};
use super::stack::{Entry, VoxelWork};
use super::{Surface, VoxelTransform};
use crate::error::Error;
use glam::DVec3;

/// Extra levels below the 4x4 pre-split cells for cells that reach beyond
/// the box found so far.
const BOX_DEPTH: u32 = 12;

/// A box `[lo, hi]` that contains every point of the limit surface
/// (model coordinates), tight to about `2^-24` of its size: the union of
/// Bezier-net boxes (convex hull property) and corner balls
/// ([`crate::eigen::ValenceTable::corner_radius`]) of the cells that reach beyond
/// the box of the exact limit points found so far, refined up to 12 levels
/// below a 4x4 pre-split.
/// On a feature mesh, cells that are not polynomial are bounded by the box
/// of their control points' hull, split the same way.
pub fn limit_bounds<S: Surface + ?Sized>(
    ev: &S,
    work: &mut VoxelWork,
) -> Result<(DVec3, DVec3), Error> {
    let np = ev.patch_count();
    if np == 0 {
        return Err(Error::EmptyMesh);
    }
    let id = Affine::IDENTITY;
    // Non-finite patch data (coordinates that overflowed in subdivision)
    // would make every cell test fail and the recursions run to their depth
    // limits: refuse it here, for every voxel entry point.
    for pi in 0..np {
        let p = ev
            .patch_at(pi)
            .ok_or(Error::InvalidArgument("patch table"))?;
        // (finite control data, has a hull: hole faces of a feature mesh
        // have none)
        let (finite, has_hull) = match p {
            Patch::Regular(g) => (g.iter().all(|x| x.is_finite()), true),
            Patch::Extra {
                ghat, cache, ctrl, ..
            } => (
                [ghat, cache, ctrl]
                    .iter()
                    .all(|d| d.iter().all(|x| x.is_finite())),
                true,
            ),
            // A feature patch's root box is built from its control points:
            // non-finite data shows in the hull below.
            Patch::Feature(fp) => (true, !fp.is_hole()),
        };
        let (hl, hh) = super::cells::patch_hull(&p);
        if !(finite && (!has_hull || (hh - hl).is_finite())) {
            return Err(Error::CoordinateRange(
                "the patch data is not finite (coordinates overflow in subdivision)",
            ));
        }
    }
    // Exact points: the corners of the 4x4 cells and the EV limit points.
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    // Set by a non-finite candidate (see `grow`).
    let mut bad = false;
    for pi in 0..np {
        let p = ev
            .patch_at(pi)
            .ok_or(Error::InvalidArgument("patch table"))?;
        for_each_root(&p, 4, &id, |c| match c {
            Cell::Poly(n) => {
                for q in net_corners(&n) {
                    grow(&mut lo, &mut hi, &mut bad, q, q);
                }
            }
            Cell::Corner(_) => {
                if let Patch::Extra { ghat, .. } = p {
                    let q = limit_point(ghat);
                    grow(&mut lo, &mut hi, &mut bad, q, q);
                }
            }
            Cell::Hull(h) => {
                for q in h.corners {
                    grow(&mut lo, &mut hi, &mut bad, q, q);
                }
            }
        });
    }
    if bad || !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::CoordinateRange(
            "the limit surface's box is not finite (coordinates overflow)",
        ));
    }
    let inside = |a: DVec3, b: DVec3, lo: DVec3, hi: DVec3| a.cmpge(lo).all() && b.cmple(hi).all();
    for pi in 0..np {
        let p = ev
            .patch_at(pi)
            .ok_or(Error::InvalidArgument("patch table"))?;
        let (hl, hh) = super::cells::patch_hull(&p);
        if inside(hl, hh, lo, hi) {
            continue;
        }
        work.len = 0;
        for_each_root(&p, 4, &id, |c| {
            work.push(Entry::new(c, 0, 2, 0));
        });
        while let Some(e) = work.pop() {
            match e.cell() {
                Cell::Poly(n) => {
                    let (a, b) = net_box(&n);
                    if inside(a, b, lo, hi) {
                        continue;
                    }
                    for q in net_corners(&n) {
                        grow(&mut lo, &mut hi, &mut bad, q, q);
                    }
                    if e.depth >= BOX_DEPTH || work.len + 4 > super::stack::STACK_CAP {
                        grow(&mut lo, &mut hi, &mut bad, a, b);
                        continue;
                    }
                    let mut kids: [Net; 4] = [[0.0; 48]; 4];
                    split4(&n, &mut kids);
                    for k in kids {
                        work.push(Entry::new(Cell::Poly(k), e.depth + 1, e.level + 1, 0));
                    }
                }
                Cell::Corner(l) => {
                    let Patch::Extra {
                        tab, ghat, cache, ..
                    } = p
                    else {
                        continue;
                    };
                    let c = limit_point(ghat);
                    let r = tab.corner_radius(ghat, l);
                    let (a, b) = (c - DVec3::splat(r), c + DVec3::splat(r));
                    if inside(a, b, lo, hi) {
                        continue;
                    }
                    if e.depth >= BOX_DEPTH + 8 || work.len + 4 > super::stack::STACK_CAP {
                        grow(&mut lo, &mut hi, &mut bad, a, b);
                        continue;
                    }
                    let kids = corner_children(tab, ghat, cache, l, &id);
                    for q in corner_corners(c, &kids) {
                        grow(&mut lo, &mut hi, &mut bad, q, q);
                    }
                    work.push(Entry::new(Cell::Corner(l + 1), e.depth + 1, l + 1, 0));
                    for k in kids {
                        work.push(Entry::new(Cell::Poly(k), e.depth + 1, l + 1, 0));
                    }
                }
                Cell::Hull(h) => {
                    let Patch::Feature(fp) = &p else {
                        continue;
                    };
                    if inside(h.lo, h.hi, lo, hi) {
                        continue;
                    }
                    if e.depth >= BOX_DEPTH + 8 || work.len + 4 > super::stack::STACK_CAP {
                        grow(&mut lo, &mut hi, &mut bad, h.lo, h.hi);
                        continue;
                    }
                    for c in h.children(fp, &id) {
                        match &c {
                            Cell::Poly(n) => {
                                for x in net_corners(n) {
                                    grow(&mut lo, &mut hi, &mut bad, x, x);
                                }
                            }
                            Cell::Hull(k) => {
                                for x in k.corners {
                                    grow(&mut lo, &mut hi, &mut bad, x, x);
                                }
                            }
                            Cell::Corner(_) => {}
                        }
                        work.push(Entry::new(c, e.depth + 1, e.level + 1, 0));
                    }
                }
            }
        }
    }
    if bad || !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::CoordinateRange(
            "the limit surface's box is not finite (coordinates overflow)",
        ));
    }
    Ok((lo, hi))
}

/// Grows `[lo, hi]` by the box `[a, b]`; a non-finite corner sets `bad`.
/// (`f64::min` and `max` drop a NaN operand, so without the flag a NaN
/// from overflowing subdivision data would vanish, or turn the box into
/// NaN that later candidates silently replace: a box that misses part of
/// the surface, and a voxelization that never ends.)
#[inline]
fn grow(lo: &mut DVec3, hi: &mut DVec3, bad: &mut bool, a: DVec3, b: DVec3) {
    *bad |= !(a.is_finite() && b.is_finite());
    *lo = lo.min(a);
    *hi = hi.max(b);
}

/// The paper's normalisation: uniform scale and translation that put the
/// guaranteed limit box `[lo, hi]` into `[0, M1-1] x [0, M2-1] x [0, M3-1]`
/// (voxel centres at integers), touching both ends on the tightest axis and
/// centred on the others. The aspect ratio is kept (one scale), so that
/// voxels are cubes in model space.
pub fn fit_box(lo: DVec3, hi: DVec3, res: [u32; 3]) -> Result<VoxelTransform, Error> {
    let ext = hi - lo;
    let mut scale = f64::INFINITY;
    for a in 0..3 {
        if ext[a] > 0.0 {
            scale = scale.min((res[a] as f64 - 1.0) / ext[a]);
        }
    }
    if !scale.is_finite() || scale <= 0.0 {
        return Err(Error::InvalidArgument("degenerate limit surface box"));
    }
    let mid = (lo + hi) * 0.5;
    let mut offset = [0.0; 3];
    for (a, o) in offset.iter_mut().enumerate() {
        *o = (res[a] as f64 - 1.0) * 0.5 - scale * mid[a];
    }
    Ok(VoxelTransform { scale, offset })
}
