//! The tolerance field of the local Boolean scheme ([`crate::solid_boolean`]):
//! where a solid's tessellation needs a tolerance below `eps`, from the
//! other solid's previous tessellation and the previous pass's crossings.
//!
//! For a cell of solid X whose surface lies in box `C`:
//! * **far** (no triangle of Y's previous tessellation `T_Y`, bound `b_Y`,
//!   within `2 eps + b_Y` of `C`, by bounding boxes): the exact surface of
//!   the cell is farther than `2 eps` from Y's surface, so with both
//!   tessellations within `eps` the cell's triangles cross nothing and
//!   keep the class of the exact surface (core `boolean` module docs:
//!   away from the curve the error is the tessellation's); tolerance
//!   `eps`;
//! * **near the curve** (`C` within the *reach* `r_c` of some crossing
//!   segment `c` of the previous pass, by bounding boxes, `r_c = h_c + 2
//!   eps` with `h_c = crossing_bound(a_c, t_A, t_B)` its error bound, `a_c`
//!   its amplification and `t_A, t_B` the bounds of its two triangles): `eps / q`, `q` the largest *divisor* of
//!   the crossings within `R` of `C`, `R` = the largest reach (= the
//!   previous pass's error bound + `2 eps`). The caller sets each
//!   crossing's divisor ([`crate::solid_boolean`]: `1.05 e_c` times the
//!   expected ratio of the a-posteriori bound to the tolerance, or
//!   `1.05 e_c k` once its certificate failed, `e_c = h_c / max(t_A, t_B)`
//!   its effective amplification, at most `a_c`). The
//!   exact curve lies within `h_c` of segment `c` (the
//!   wedge lemma of the core `boolean` module, applied to that crossing
//!   alone, to first order) and the new curve within `eps` of the exact
//!   one, so cells farther than every `r_c` from the previous curve are
//!   not crossed by the new one (first order) and keep `eps`. The
//!   divisor is still the largest within `R` (not within the
//!   cell's own reaches), a margin for the facet amplification changing
//!   from one pass to the next (with the cell's own reaches the hands'
//!   union needs a third pass). Earlier fields used `R` for every
//!   crossing: on the hands (`bench/boolean_bench.sh`) the per-crossing
//!   reach takes the union from 68,236 to 65,546 triangles and the
//!   difference from 20,782 to 20,016, passes unchanged (bench-log
//!   2026-11-27, `booldiff2`);
//! * **near the other solid only**: `eps` (before the a-posteriori
//!   bounds: `eps / 1.05`).
//!
//! **Spending the slack** ([`crate::solid_boolean`] module docs): with
//! every triangle's a-posteriori bound, the tolerance where no rule above
//! asks for less is `base = SLACK eps` instead of `eps`, the crossings'
//! `eps / q_c` are capped at `base`, and cells meeting the centroid of a
//! triangle whose bound was above `eps` in an earlier pass ([`TightBox`])
//! get at most the tolerance asked for there.
//!
//! The field only steers the refinement: the pipeline accepts a pass only
//! when its bound (every triangle's bound, every crossing's
//! `crossing_bound(a, t_A, t_B)` with the crossing triangles' a-posteriori bounds) is
//! at most `eps` ([`crate::solid_boolean`]), and refines again otherwise.
//!
//! All tests only grow with `C`, so the field is monotone as
//! [`ToleranceField`] requires. The queries run on bounding-volume
//! hierarchies of boxes ([`BoxTree`]).

use ccss_core::tessellate::ToleranceField;
use ccss_core::DVec3;

/// A bounding-volume hierarchy over boxes with a value each, for "largest
/// value of a box meeting this one" (0 when none).
pub struct BoxTree {
    /// Per node: lo, hi (6), largest value below.
    nodes: Vec<([f64; 6], f64)>,
    /// Per node: left child (internal) or first item (leaf), item count
    /// (0: internal).
    links: Vec<(u32, u32)>,
    /// Per node: right child (internal nodes).
    right: Vec<u32>,
    items: Vec<([f64; 6], f64)>,
}

const LEAF: usize = 4;

fn union(a: &[f64; 6], b: &[f64; 6]) -> [f64; 6] {
    [
        a[0].min(b[0]),
        a[1].min(b[1]),
        a[2].min(b[2]),
        a[3].max(b[3]),
        a[4].max(b[4]),
        a[5].max(b[5]),
    ]
}

fn meets(a: &[f64; 6], lo: DVec3, hi: DVec3) -> bool {
    a[0] <= hi.x && a[1] <= hi.y && a[2] <= hi.z && a[3] >= lo.x && a[4] >= lo.y && a[5] >= lo.z
}

impl BoxTree {
    /// The tree of `items` (box `lo x y z, hi x y z`, value).
    pub fn new(mut items: Vec<([f64; 6], f64)>) -> Self {
        let mut t = BoxTree {
            nodes: Vec::new(),
            links: Vec::new(),
            right: Vec::new(),
            items: Vec::new(),
        };
        if !items.is_empty() {
            let n = items.len();
            t.build(&mut items, 0, n);
        }
        t.items = items;
        t
    }

    /// Builds the node of `items[a..b]` (median split on the longest axis
    /// of the centres), returns its index.
    fn build(&mut self, items: &mut [([f64; 6], f64)], a: usize, b: usize) -> usize {
        let me = self.nodes.len();
        let mut bx = items[a].0;
        let mut v = items[a].1;
        for it in &items[a + 1..b] {
            bx = union(&bx, &it.0);
            v = v.max(it.1);
        }
        self.nodes.push((bx, v));
        self.links.push((a as u32, (b - a) as u32));
        self.right.push(0);
        if b - a <= LEAF {
            return me;
        }
        let ext = [bx[3] - bx[0], bx[4] - bx[1], bx[5] - bx[2]];
        let ax = (0..3)
            .max_by(|&i, &j| ext[i].total_cmp(&ext[j]))
            .unwrap_or(0);
        let m = (a + b) / 2;
        items[a..b].select_nth_unstable_by(m - a, |x, y| {
            (x.0[ax] + x.0[ax + 3]).total_cmp(&(y.0[ax] + y.0[ax + 3]))
        });
        let l = self.build(items, a, m);
        let r = self.build(items, m, b);
        self.links[me] = (l as u32, 0);
        self.right[me] = r as u32;
        me
    }

    /// The largest value of a box meeting `[lo, hi]` (0 when none);
    /// subtrees that cannot beat the best so far are skipped.
    pub fn max_meeting(&self, lo: DVec3, hi: DVec3) -> f64 {
        let mut best = 0.0f64;
        if self.nodes.is_empty() {
            return best;
        }
        // Median splits: depth below 64, so at most 64 pending siblings.
        let mut stack = [0u32; 128];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top] as usize;
            let (bx, v) = &self.nodes[n];
            if *v <= best || !meets(bx, lo, hi) {
                continue;
            }
            let (x, y) = self.links[n];
            if y == 0 {
                stack[top] = x;
                stack[top + 1] = self.right[n];
                top += 2;
            } else {
                for it in &self.items[x as usize..(x + y) as usize] {
                    if it.1 > best && meets(&it.0, lo, hi) {
                        best = it.1;
                    }
                }
            }
        }
        best
    }
}

/// A crossing of the previous pass as the field sees it.
#[derive(Clone, Copy, Debug)]
pub struct CrossingReach {
    /// The ends of its curve segment.
    pub ends: [DVec3; 2],
    /// The divisor `q_c` it asks for near it: cells within `R` of it get
    /// at most `eps / q_c` (module docs).
    pub divisor: f64,
    /// Its reach `r_c = crossing_bound(a_c, t_A, t_B) + 2 eps` (module docs).
    pub reach: f64,
}

/// The field of one solid (module docs).
pub struct Field {
    /// The other solid's previous triangles, value 1.
    other: BoxTree,
    /// `2 eps + b_Y`.
    near: f64,
    /// The previous crossings' segment boxes grown by their reach `r_c`,
    /// value = divisor.
    reaches: BoxTree,
    /// The previous crossings' segment boxes, value = divisor.
    crossings: BoxTree,
    /// `R`, the largest reach.
    reach: f64,
    eps: f64,
    /// The tolerance of cells no other rule lowers (`eps`, or more when
    /// every triangle gets an a-posteriori bound: module docs, "spending
    /// the slack").
    base: f64,
    /// Boxes of triangles whose bound was above `eps` in an earlier pass,
    /// value = 1 / the tolerance asked for there.
    tight: BoxTree,
}

/// A region a pass found above `eps` (a triangle's box) and the tolerance
/// asked for there (module docs, "spending the slack").
#[derive(Clone, Copy, Debug)]
pub struct TightBox {
    /// `lo x y z, hi x y z`.
    pub bounds: [f64; 6],
    /// The tolerance of cells meeting the box (at most).
    pub tolerance: f64,
}

impl Field {
    /// The field of a solid from the other solid's previous tessellation
    /// (`positions`, `triangles`, bound `bound`) and the previous crossings
    /// (segment ends, divisor, reach: module docs): tolerance `base >= eps`
    /// where no rule asks for less (`eps` without slack), the crossings'
    /// `eps / q_c` capped at `base`, and at most `tolerance` in cells
    /// meeting a box of `tight` (module docs, "spending the slack").
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        eps: f64,
        base: f64,
        positions: &[f64],
        triangles: &[u32],
        bound: f64,
        crossings: &[CrossingReach],
        tight: &[TightBox],
    ) -> Self {
        let floor = eps / base.max(eps);
        let p = |v: u32| DVec3::from_slice(&positions[3 * v as usize..3 * v as usize + 3]);
        let tris = triangles
            .chunks_exact(3)
            .map(|t| {
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                let lo = a.min(b).min(c);
                let hi = a.max(b).max(c);
                ([lo.x, lo.y, lo.z, hi.x, hi.y, hi.z], 1.0)
            })
            .collect();
        let segment = |x: &CrossingReach, r: f64| {
            let r = DVec3::splat(r);
            let lo = x.ends[0].min(x.ends[1]) - r;
            let hi = x.ends[0].max(x.ends[1]) + r;
            ([lo.x, lo.y, lo.z, hi.x, hi.y, hi.z], x.divisor.max(floor))
        };
        Field {
            other: BoxTree::new(tris),
            near: 2.0 * eps + bound,
            reaches: BoxTree::new(crossings.iter().map(|x| segment(x, x.reach)).collect()),
            crossings: BoxTree::new(crossings.iter().map(|x| segment(x, 0.0)).collect()),
            reach: crossings.iter().map(|x| x.reach).fold(0.0, f64::max),
            eps,
            base: base.max(eps),
            tight: BoxTree::new(
                tight
                    .iter()
                    .filter(|t| t.tolerance > 0.0)
                    .map(|t| (t.bounds, 1.0 / t.tolerance))
                    .collect(),
            ),
        }
    }

    /// The smallest tolerance the field gives.
    pub fn min_tolerance(&self) -> f64 {
        self.tolerance(DVec3::NEG_INFINITY, DVec3::INFINITY)
    }
}

impl ToleranceField for Field {
    fn tolerance(&self, lo: DVec3, hi: DVec3) -> f64 {
        let inv = self.tight.max_meeting(lo, hi);
        let t = if inv > 0.0 {
            self.base.min(1.0 / inv)
        } else {
            self.base
        };
        let d = DVec3::splat(self.near);
        if self.other.max_meeting(lo - d, hi + d) == 0.0 {
            return t;
        }
        if self.reaches.max_meeting(lo, hi) == 0.0 {
            return t;
        }
        let r = DVec3::splat(self.reach);
        let q = self
            .crossings
            .max_meeting(lo - r, hi + r)
            .max(self.eps / self.base);
        t.min(self.eps / q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree's answer is the brute-force one on random boxes.
    #[test]
    fn box_tree_matches_brute_force() {
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [0usize, 1, 3, 4, 5, 17, 100, 1000] {
            let items: Vec<([f64; 6], f64)> = (0..n)
                .map(|_| {
                    let c = [rnd(), rnd(), rnd()];
                    let w = 0.05 * rnd();
                    (
                        [c[0], c[1], c[2], c[0] + w, c[1] + w, c[2] + w],
                        1.0 + 9.0 * rnd(),
                    )
                })
                .collect();
            let t = BoxTree::new(items.clone());
            for _ in 0..200 {
                let lo = DVec3::new(rnd(), rnd(), rnd());
                let hi = lo + DVec3::splat(0.2 * rnd());
                let want = items
                    .iter()
                    .filter(|it| meets(&it.0, lo, hi))
                    .map(|it| it.1)
                    .fold(0.0, f64::max);
                assert_eq!(t.max_meeting(lo, hi), want, "n = {n}");
            }
        }
    }
}
