//! The cells of a slot's quadtree, top down: what each cell is (one bicubic
//! piece with its Bezier net, a corner cell at an extraordinary vertex, or
//! the level-0 cell of an internally split slot) and how its four children
//! are made.
//!
//! Frames: a cell's Bezier net is kept in the *slot* orientation (its s, t
//! along the slot's u, v). A patch whose own frame is rotated by `r`
//! (evaluator `rot_param`) is seen rotated by `rho = r` from an unsplit
//! slot, and by `rho = (r + c) mod 4` from quadrant `c` of a split slot
//! (the quadrant map is itself the rotation `rot_param(c, .)` followed by a
//! scaling). The extraordinary vertex of a patch (its patch-frame corner
//! (0,0)) is the cell-local corner `rho`, so the corner child of a corner
//! cell is its quadrant `rho` and quadrant `q != rho` is the region
//! `Omega_{k+1, b}` with `b = (q - rho) mod 4` (\[CL-R §2.1\]). These regions
//! are exactly one bicubic piece each, so every cell that does not touch the
//! extraordinary vertex is one polynomial, as in [`crate::bounds::cell`].
//!
//! Nets of regions of level `m > 2` are computed without the limit-point
//! term (the table's `sub_patch(.., with_limit = false)`) and carry the limit
//! point as a separate offset, which keeps full relative precision deep near
//! the vertex; positions are `net + offset`.

use super::record::AT;
use crate::eval::Evaluator;
use crate::math::bezier::{self, Net};
use crate::math::bspline::{eval_grid, Grid};
use glam::DVec3;

/// Cell kind tags.
pub(crate) const POLY: u32 = 0;
pub(crate) const CORNER: u32 = 1;
pub(crate) const SPLIT: u32 = 2;

/// What a cell is. Plain integers so that any bit pattern is valid (it
/// lives in caller memory).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub(crate) struct Kind {
    /// POLY, CORNER or SPLIT.
    pub tag: u32,
    /// Corner cells: the patch index.
    pub patch: u32,
    /// Corner cells: the cell-local corner of the extraordinary vertex.
    pub rho: u32,
    /// Corner cells: the cell is `[0, 2^-k]^2` of its patch.
    pub k: u32,
}

/// A cell's kind, net (valid for POLY) and offset.
#[derive(Clone, Copy)]
pub(crate) struct Cell {
    pub kind: Kind,
    pub net: Net,
    pub off: DVec3,
}

impl Cell {
    const fn of(kind: Kind) -> Cell {
        Cell {
            kind,
            net: [0.0; 48],
            off: DVec3::ZERO,
        }
    }
}

/// A grid of zeros (what a missing grid reads as).
const ZERO_GRID: Grid = [0.0; 48];

/// The grid stored at `data[o..o + 48]` (zeros if out of range).
fn grid_ref(data: &[f64], o: usize) -> &Grid {
    data.get(o..o + 48)
        .and_then(|s| <&Grid>::try_from(s).ok())
        .unwrap_or(&ZERO_GRID)
}

/// The whole patch `pi` seen with orientation `rho`.
fn patch_cell(ev: &Evaluator, pi: usize, rho: u32) -> Cell {
    let n = (ev.patch_meta[pi] & 0xff) as usize;
    if n == 4 {
        let g = grid_ref(ev.data, ev.patch_data[pi] as usize);
        Cell {
            kind: Kind::default(),
            net: {
                let mut n = [0.0; 48];
                bezier::from_grid_rotated(g, rho as u8, &mut n);
                n
            },
            off: DVec3::ZERO,
        }
    } else {
        Cell::of(Kind {
            tag: CORNER,
            patch: pi as u32,
            rho,
            k: 0,
        })
    }
}

/// The level-0 cell of `slot`.
pub(crate) fn root(ev: &Evaluator, slot: usize) -> Cell {
    let p0 = ev.slot_patch[slot] as usize;
    if ev.slot_split[slot] != 0 {
        Cell::of(Kind {
            tag: SPLIT,
            patch: p0 as u32,
            rho: 0,
            k: 0,
        })
    } else {
        let r = (ev.patch_meta[p0] >> 8) & 3;
        patch_cell(ev, p0, r)
    }
}

/// Bound `2 E_k` of a corner cell (see [`crate::bounds::cell`];
/// [`crate::eigen::ValenceTable::corner_flatness`], precomputed by the evaluator).
#[inline]
pub(crate) fn corner_bound(ev: &Evaluator, kind: &Kind) -> f64 {
    match ev.corner_flatness(kind.patch as usize, kind.k) {
        Some(e) => 2.0 * e,
        None => f64::INFINITY,
    }
}

/// Whether the split of corner cell `kind` is *light* under absolute
/// flatness `eps`: its three ring-region children are accepted by the
/// ring-region bound alone ([`Evaluator::ring_bound`], returned), so their
/// nets are never made and its five points come from
/// [`store_corner_light`]. The marking and `fill_corners` decide with this
/// one function, so they save the same values.
#[inline]
pub(crate) fn light_split(ev: &Evaluator, kind: &Kind, eps: f64) -> Option<f64> {
    if kind.tag != CORNER {
        return None;
    }
    ev.ring_bound(kind.patch as usize, kind.k)
        .filter(|&b| b <= eps)
}

/// Saves, as [`store_corner`] does for a corner cell none of whose
/// ring-region children is split ([`corner_len`] = 31 values), its five
/// points with their unit normals, evaluated from the eigen expansion
/// ([`crate::eigen::ValenceTable::ring_points`]: the limit point plus the
/// expansion's sum; normals `normalize(S_u x S_v)`, which is the slot
/// frame's `S_s x S_t` direction since the slot frame is the patch frame
/// rotated by `rho`). Point `w` of the cell (slot frame: centre, sides
/// 0..4) is patch-frame point `w` for the centre and side
/// `(k - rho) mod 4` for side `k`. False (nothing written) where the
/// table has no ring points.
#[inline(never)]
pub(crate) fn store_corner_light(ev: &Evaluator, kind: &Kind, dst: &mut [f64]) -> bool {
    let Some((tab, lay)) = ev.ev_patch(kind.patch as usize) else {
        return false;
    };
    let Some(ghat) = ev.data.get(lay.ghat()) else {
        return false;
    };
    let mut pts = [[DVec3::ZERO; 3]; 5];
    if dst.len() < 31 || !tab.ring_points(ghat, kind.k, &mut pts) {
        return false;
    }
    let lim = DVec3::new(ghat[0], ghat[1], ghat[2]);
    let mut found = 0u64;
    for w in 0..5 {
        let pw = if w == 0 {
            0
        } else {
            1 + ((w - 1 + 4 - (kind.rho as usize & 3)) & 3)
        };
        let [p, du, dv] = pts[pw];
        if let Some(n) = bezier::normal_of(du, dv) {
            dst[6 * w..6 * w + 3].copy_from_slice(&(p + lim).to_array());
            dst[6 * w + 3..6 * w + 6].copy_from_slice(&n.to_array());
            found |= 1 << w;
        }
    }
    dst[30] = f64::from_bits(found);
    true
}

/// The five points of a light split of corner cell `kind` as
/// [`store_corner_light`] saves them, into `pts` (those found; the
/// header's found mask returned), for an emission that kept no saved
/// expansions (out of line: the values are on the stack only here).
#[inline(never)]
pub(crate) fn light_points(
    ev: &Evaluator,
    kind: &Kind,
    pts: &mut [(DVec3, DVec3); 5],
) -> Option<u64> {
    let mut e = [0.0; 31];
    if !store_corner_light(ev, kind, &mut e) {
        return None;
    }
    let h = e[30].to_bits();
    for (w, p) in pts.iter_mut().enumerate() {
        if let Some(x) = saved_point(&e, h, w) {
            *p = x;
        }
    }
    Some(h & 0x1f)
}

/// The four children (quadrant order) of the cell (`kind`, `net`, `off`),
/// written in place.
pub(crate) fn expand(
    ev: &Evaluator,
    kind: &Kind,
    net_in: &Net,
    off: [f64; 3],
    kinds: &mut [Kind; 4],
    nets: &mut [Net; 4],
    offs: &mut [[f64; 3]; 4],
) {
    expand_ex(ev, kind, net_in, off, kinds, nets, offs, None);
}

/// As [`expand`]; with `ring`, a corner cell (with a valence table) also
/// gives the limit points at the corners its corner child shares with the
/// ring regions: `ring[b - 1]` = `S` at the local (0, 0) corner of region
/// `Omega_{m, b}` (patch coordinates `(2^-m, 0)`, `(2^-m, 2^-m)`,
/// `(0, 2^-m)`), bit for bit what [`Evaluator::eval`] gives there: it
/// evaluates the same grid (the table's `sub_patch(m, b)`, or the cached
/// grids for `m <= 2`) at the same local parameters (0, 0) with the same
/// kernel, adding the limit point for `m > 2` in the same way. `ring` is
/// left alone otherwise (false returned).
#[allow(clippy::too_many_arguments)]
pub(crate) fn expand_ex(
    ev: &Evaluator,
    kind: &Kind,
    net_in: &Net,
    off: [f64; 3],
    kinds: &mut [Kind; 4],
    nets: &mut [Net; 4],
    offs: &mut [[f64; 3]; 4],
    ring: Option<&mut [DVec3; 3]>,
) -> bool {
    match kind.tag {
        POLY => {
            bezier::split4(net_in, nets);
            *kinds = [*kind; 4];
            *offs = [off; 4];
            false
        }
        SPLIT => {
            let p0 = kind.patch as usize;
            for c in 0..4 {
                let r = (ev.patch_meta[p0 + c] >> 8) & 3;
                let cell = patch_cell(ev, p0 + c, (r + c as u32) & 3);
                kinds[c] = cell.kind;
                nets[c] = cell.net;
                offs[c] = cell.off.to_array();
            }
            false
        }
        _ => expand_corner(ev, kind, kinds, nets, offs, ring),
    }
}

/// The corner-cell arm of [`expand_ex`], out of line: its three grids
/// (1,152 bytes) are then on the stack only while a corner cell is
/// expanded, not in every caller's frame.
#[inline(never)]
fn expand_corner(
    ev: &Evaluator,
    kind: &Kind,
    kinds: &mut [Kind; 4],
    nets: &mut [Net; 4],
    offs: &mut [[f64; 3]; 4],
    ring: Option<&mut [DVec3; 3]>,
) -> bool {
    let kd = *kind;
    let m = kd.k + 1;
    let ep = ev.ev_patch(kd.patch as usize);
    // The three ring regions' grids (b = 1, 2, 3), all at once:
    // read in place from the evaluator's cache for m <= 2 and its deep
    // grids for 3 <= m <= deep_levels.
    // Made (and zeroed) only when not read in place.
    let mut local: [Grid; 3];
    let mut o = [0.0; 3];
    let grids: [&Grid; 3] = match ep {
        Some((_, lay)) if m <= 2 && lay.grid(1, 1).is_some() => core::array::from_fn(|b| {
            grid_ref(ev.data, lay.grid(m as usize, b + 1).map_or(0, |r| r.start))
        }),
        Some((tab, lay)) if m <= 2 => {
            // Not stored: the grids the build would have stored,
            // bit for bit (with the limit term).
            local = [[0.0; 48]; 3];
            tab.sub_patches3(&ev.data[lay.ghat()], m, true, &mut local);
            [&local[0], &local[1], &local[2]]
        }
        Some((tab, lay)) => {
            let ghat = &ev.data[lay.ghat()];
            o = [ghat[0], ghat[1], ghat[2]];
            // Levels 3.. the evaluator keeps (`EvaluatorOptions::deep_levels`)
            // are read in place: made by `ValenceTable::deep_grid`, bit for
            // bit `sub_patch` without the limit term, as `sub_patches3` is
            // (their unit tests; `lean_memory` compares tessellations with
            // and without them bit for bit).
            let deep = lay.deep();
            let at = deep.start + 144 * (m as usize - 3);
            if at + 144 <= deep.end {
                core::array::from_fn(|b| grid_ref(ev.data, at + 48 * b))
            } else {
                local = [[0.0; 48]; 3];
                tab.sub_patches3(ghat, m, false, &mut local);
                [&local[0], &local[1], &local[2]]
            }
        }
        None => [&ZERO_GRID; 3],
    };
    for q in 0..4u32 {
        let qi = q as usize;
        let corner = Kind { k: m, ..kd };
        if ep.is_none() || q == kd.rho {
            kinds[qi] = corner;
            offs[qi] = [0.0; 3];
            continue;
        }
        let b = ((q + 4 - kd.rho) & 3) as usize;
        kinds[qi] = Kind::default();
        bezier::from_grid_rotated(grids[b - 1], kd.rho as u8, &mut nets[qi]);
        offs[qi] = o;
    }
    match (ring, ep) {
        (Some(r), Some(_)) => {
            for (pb, g) in r.iter_mut().zip(grids.iter()) {
                let p = eval_grid::<false>(g, 0.0, 0.0).p;
                *pb = if m <= 2 { p } else { p + DVec3::from_array(o) };
            }
            true
        }
        _ => false,
    }
}

/// f64 values of the saved expansion of a corner cell whose children
/// `internal` (bit q: child q is split) are split ([`store_corner`]).
#[inline]
pub(crate) fn corner_len(rho: u32, internal: u32) -> usize {
    let ring = (internal & 0xf & !(1 << (rho & 3))).count_ones() as usize;
    if ring > 0 {
        48 * ring + 3 + 31
    } else {
        31
    }
}

/// Saves what the emission needs of the expansion (`kinds`, `nets`,
/// `offs`, as [`expand`] made it) of the corner cell `kind` into `dst`
/// ([`corner_len`] values): its five points as the emission reads them
/// from the children (the first polynomial child with the point as a
/// corner and a non-degenerate normal there; position + offset and unit
/// normal), and the nets and offset of its split ring-region children, so
/// that the emission does not redo the eigen expansion. Layout: split ring
/// nets (quadrant order), their offset, then per point (x, y, z, nx, ny,
/// nz), then a header (bit w: point w found; bit 8 + q: child q split).
pub(crate) fn store_corner(
    kind: &Kind,
    internal: u32,
    kinds: &[Kind; 4],
    nets: &[Net; 4],
    offs: &[[f64; 3]; 4],
    dst: &mut [f64],
) {
    let ring = internal & 0xf & !(1 << (kind.rho & 3));
    let mut at = 0;
    for q in 0..4 {
        if ring & (1 << q) != 0 {
            dst[at..at + 48].copy_from_slice(&nets[q]);
            at += 48;
        }
    }
    if ring != 0 {
        let q = ring.trailing_zeros() as usize;
        dst[at..at + 3].copy_from_slice(&offs[q]);
        at += 3;
    }
    let mut found = 0u64;
    for (w, pairs) in AT.iter().enumerate() {
        for &(c, k) in pairs {
            if kinds[c].tag == POLY {
                if let Some(n) = bezier::corner_normal(&nets[c], k) {
                    let p = bezier::corner(&nets[c], k) + DVec3::from_array(offs[c]);
                    dst[at + 6 * w..at + 6 * w + 3].copy_from_slice(&p.to_array());
                    dst[at + 6 * w + 3..at + 6 * w + 6].copy_from_slice(&n.to_array());
                    found |= 1 << w;
                    break;
                }
            }
        }
    }
    dst[at + 30] = f64::from_bits(found | (ring as u64) << 8);
}

/// The saved expansion ending at `end` in `cache` (see [`store_corner`]):
/// `(start, header)`, or `None` if it is not there.
#[inline]
pub(crate) fn saved_corner(cache: &[f64], end: usize, rho: u32) -> Option<(usize, u64)> {
    let h = cache.get(end.checked_sub(1)?)?.to_bits();
    let len = corner_len(rho, ((h >> 8) & 0xf) as u32);
    Some((end.checked_sub(len)?, h))
}

/// Point `w` of a saved corner expansion `e` with header `h` (position,
/// normal), if it was found among the children.
#[inline]
pub(crate) fn saved_point(e: &[f64], h: u64, w: usize) -> Option<(DVec3, DVec3)> {
    if h & (1 << w) == 0 {
        return None;
    }
    let at = e.len() - 31 + 6 * w;
    let v = e.get(at..at + 6)?;
    Some((DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5])))
}

/// The children of the corner cell `kind` as [`expand`] makes them, from a
/// saved expansion `e` with header `h`: bit for bit the same kinds, and the
/// same nets and offsets for the split ring-region children (the others,
/// leaves, are not needed).
pub(crate) fn load_corner(
    ev: &Evaluator,
    kind: &Kind,
    e: &[f64],
    h: u64,
    kinds: &mut [Kind; 4],
    nets: &mut [Net; 4],
    offs: &mut [[f64; 3]; 4],
) {
    let kd = *kind;
    let has = ev.ev_patch(kd.patch as usize).is_some();
    let ring = ((h >> 8) & 0xf) as u32;
    let nring = ring.count_ones() as usize;
    let off = if nring > 0 {
        let o = &e[48 * nring..48 * nring + 3];
        [o[0], o[1], o[2]]
    } else {
        [0.0; 3]
    };
    let mut at = 0;
    for q in 0..4u32 {
        let qi = q as usize;
        if !has || q == kd.rho {
            kinds[qi] = Kind { k: kd.k + 1, ..kd };
            offs[qi] = [0.0; 3];
            continue;
        }
        kinds[qi] = Kind::default();
        offs[qi] = off;
        if ring & (1 << q) != 0 {
            nets[qi].copy_from_slice(&e[at..at + 48]);
            at += 48;
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    extern crate std;
    use super::*;
    use crate::eigen::{BuildScratch, TableSet};
    use crate::eval::evaluator::corner_flatness_tests::{with_evaluator, with_mesh};
    use std::boxed::Box;
    use std::vec::Vec;

    /// The bundled righthanded model (valences 3, 4 and 5), positions
    /// and quad indices.
    pub(crate) fn righthanded() -> (Vec<f64>, Vec<u32>) {
        let text = include_str!("../../../tests/data/osd/catmark_righthanded.obj");
        let (mut p, mut idx) = (Vec::new(), Vec::new());
        for line in text.lines() {
            let mut w = line.split_whitespace();
            match w.next() {
                Some("v") => p.extend(w.map(|x| x.parse::<f64>().unwrap())),
                Some("f") => {
                    let f: Vec<u32> = w
                        .map(|x| x.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                        .collect();
                    assert_eq!(f.len(), 4);
                    idx.extend(f);
                }
                _ => {}
            }
        }
        (p, idx)
    }

    /// A prism over a wavy `n`-gon (two `n`-gon caps, `n` side quads): the
    /// caps' centres are extraordinary vertices of valence `n`.
    fn prism(n: u32) -> (Vec<f64>, Vec<u32>, Vec<u32>) {
        let (mut p, mut sizes, mut idx) = (Vec::new(), Vec::new(), Vec::new());
        for z in [-1.0, 1.0] {
            for i in 0..n {
                let a = 2.0 * core::f64::consts::PI * i as f64 / n as f64;
                let r = 1.0 + 0.2 * libm::cos(3.0 * a) + 0.1 * z;
                p.extend([
                    r * libm::cos(a),
                    r * libm::sin(a),
                    z * (1.0 + 0.1 * libm::sin(a)),
                ]);
            }
        }
        sizes.extend([n, n]);
        idx.extend((0..n).rev());
        idx.extend(n..2 * n);
        for i in 0..n {
            let j = (i + 1) % n;
            sizes.push(4);
            idx.extend([i, j, n + j, n + i]);
        }
        (p, sizes, idx)
    }

    /// At every corner cell of every extraordinary patch of righthanded
    /// (valences 3 and 5) and of prisms with valence 6..=16 caps (levels
    /// 0..=12 and 30..=32, the four orientations): the ring bound is at
    /// least the bound of each ring-region child's Bezier net, and the
    /// light split's points and normals are those read from the children's
    /// nets (1e-12 relative, same found bits).
    #[test]
    #[cfg_attr(
        miri,
        ignore = "builds eigen tables for every valence: minutes under Miri"
    )]
    fn ring_bound_covers_nets_and_light_points_match() {
        let mut ts = Box::new(TableSet::ZERO);
        ts.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let (p, idx) = righthanded();
        with_evaluator(&ts, &p, &idx, |ev| check_corner_cells(ev, 400));
        for n in 6..=16 {
            let (p, sizes, idx) = prism(n);
            with_mesh(&ts, &p, &sizes, &idx, |ev| {
                check_corner_cells(ev, 2 * n as usize)
            });
        }
        // General vertex weights: the standard ones with 0.05 moved from
        // alpha to beta (real eigenvalues), and weights whose tables have a
        // 2x2 block, where there is no ring bound (no light split).
        let (mut moved, mut complex) = (
            crate::mesh::Weights::STANDARD,
            crate::mesh::Weights::STANDARD,
        );
        for n in (3..=crate::config::MAX_VALENCE).filter(|&n| n != 4) {
            let (a, b, g) = crate::mesh::weights::standard(n);
            moved.set(n, a - 0.05, b + 0.05, g).unwrap();
            complex.set(n, 0.5, 0.3, 0.2).unwrap();
        }
        for (w, light) in [(moved, true), (complex, false)] {
            ts.build_into(&w, &mut Box::new(BuildScratch::ZERO))
                .unwrap();
            for n in [5u32, 7, 10] {
                assert_eq!(ts.get(n as usize).unwrap().has_complex_pair(), !light);
                let (p, sizes, idx) = prism(n);
                with_mesh(&ts, &p, &sizes, &idx, |ev| {
                    if light {
                        check_corner_cells(ev, 2 * n as usize);
                    } else {
                        let ev_patch =
                            (0..ev.patch_meta.len()).find(|&pi| ev.patch_meta[pi] & 0xff == n);
                        assert_eq!(ev.ring_bound(ev_patch.unwrap(), 2), None);
                    }
                });
            }
        }
    }

    /// The checks of [`ring_bound_covers_nets_and_light_points_match`] on
    /// one evaluator (at least `min_patches` extraordinary patches).
    fn check_corner_cells(ev: &Evaluator, min_patches: usize) {
        let (mut cells, mut worst, mut sum_ratio) = (0usize, 0.0f64, 0.0f64);
        let mut best = f64::INFINITY;
        let mut worst_pt = 0.0f64;
        for pi in 0..ev.patch_meta.len() {
            if ev.patch_meta[pi] & 0xff == 4 {
                continue;
            }
            for k in (0..=12).chain(30..=32) {
                let rb = ev.ring_bound(pi, k).unwrap();
                for rho in 0..4 {
                    let kind = Kind {
                        tag: CORNER,
                        patch: pi as u32,
                        rho,
                        k,
                    };
                    let mut kinds = [Kind::default(); 4];
                    let mut nets = [[0.0; 48]; 4];
                    let mut offs = [[0.0; 3]; 4];
                    expand(
                        ev, &kind, &[0.0; 48], [0.0; 3], &mut kinds, &mut nets, &mut offs,
                    );
                    let mut most = 0.0f64;
                    for q in (0..4).filter(|&q| q != rho as usize) {
                        let b = bezier::bound(&nets[q]);
                        assert!(b <= rb, "patch {pi} k {k}: net {b} > ring {rb}");
                        most = most.max(b);
                    }
                    worst = worst.max(most / rb);
                    best = best.min(most / rb);
                    sum_ratio += most / rb;
                    cells += 1;
                    let (mut full, mut light) = ([0.0; 31], [0.0; 31]);
                    store_corner(&kind, 0, &kinds, &nets, &offs, &mut full);
                    assert!(store_corner_light(ev, &kind, &mut light));
                    assert_eq!(full[30].to_bits(), light[30].to_bits());
                    let scale = DVec3::from_slice(&full[0..3]).length().max(1.0);
                    for w in 0..5 {
                        let (a, b) = (&full[6 * w..6 * w + 6], &light[6 * w..6 * w + 6]);
                        let d = (DVec3::from_slice(a) - DVec3::from_slice(b)).length();
                        let n = DVec3::from_slice(&a[3..]).dot(DVec3::from_slice(&b[3..]));
                        worst_pt = worst_pt.max(d / scale);
                        assert!(d <= 1e-12 * scale, "patch {pi} k {k} point {w}: {d}");
                        assert!(n >= 1.0 - 1e-9, "patch {pi} k {k} normal {w}: {n}");
                    }
                }
            }
        }
        std::println!(
            "{cells} corner cells: net bound / ring bound min {best:.3}, mean {:.3}, max {worst:.3}; points within {worst_pt:.1e}",
            sum_ratio / cells as f64
        );
        assert!(cells >= 4 * 15 * min_patches);
    }
}
