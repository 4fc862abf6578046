//! A bounding-volume hierarchy over the triangles of one mesh, in caller
//! memory (at most `2 T` nodes, leaves of at most [`LEAF`] triangles),
//! built top down by median splits with an explicit stack.

use super::SolidMesh;
use glam::DVec3;

/// Largest leaf.
pub const LEAF: usize = 4;
/// Depth of the explicit stacks (median splits: `log2(T) + 1 < 64`).
const STACK: usize = 64;

/// The hierarchy's arrays (node `i`: box `6 i ..`, `first[i]`, `count[i]`;
/// a leaf has `count > 0` and holds `perm[first .. first + count]`, an
/// inner node has children `first` and `first + 1`).
pub struct Bvh<'a> {
    /// Triangle order.
    pub perm: &'a mut [u32],
    /// `min.x min.y min.z max.x max.y max.z` per node.
    pub boxes: &'a mut [f64],
    /// First triangle (leaf) or first child (inner node).
    pub first: &'a mut [u32],
    /// Triangles of a leaf, 0 for an inner node.
    pub count: &'a mut [u32],
    /// Nodes used.
    pub nodes: usize,
}

/// Nodes to reserve for `t` triangles.
pub fn node_capacity(t: usize) -> usize {
    2 * t.max(1)
}

/// The box of triangle `t`.
pub fn tri_box(m: &SolidMesh, t: usize) -> (DVec3, DVec3) {
    let p = |k: usize| m.point(m.triangles[3 * t + k]);
    let (a, b, c) = (p(0), p(1), p(2));
    (a.min(b).min(c), a.max(b).max(c))
}

impl Bvh<'_> {
    /// Builds over all triangles of `m`; `centres` (at least `3 T` words)
    /// is work memory for the triangles' box centres (as `f64` bits), so
    /// that the median splits compare stored keys.
    pub fn build(&mut self, m: &SolidMesh, centres: &mut [u64]) {
        let t = m.triangles.len() / 3;
        for (i, p) in self.perm.iter_mut().enumerate().take(t) {
            *p = i as u32;
            let (a, b) = tri_box(m, i);
            let c = (a + b) * 0.5;
            for k in 0..3 {
                centres[3 * i + k] = c[k].to_bits();
            }
        }
        let centre = |x: u32, axis: usize| f64::from_bits(centres[3 * x as usize + axis]);
        self.nodes = 1;
        let mut stack = [(0u32, 0u32, 0u32); STACK];
        stack[0] = (0, 0, t as u32);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (node, lo, hi) = stack[top];
            let (lo, hi, node) = (lo as usize, hi as usize, node as usize);
            if hi - lo <= LEAF || top + 2 > STACK {
                let mut bmin = DVec3::splat(f64::INFINITY);
                let mut bmax = DVec3::splat(f64::NEG_INFINITY);
                for &tri in &self.perm[lo..hi] {
                    let (a, b) = tri_box(m, tri as usize);
                    bmin = bmin.min(a);
                    bmax = bmax.max(b);
                }
                self.boxes[6 * node..6 * node + 3].copy_from_slice(&bmin.to_array());
                self.boxes[6 * node + 3..6 * node + 6].copy_from_slice(&bmax.to_array());
                self.first[node] = lo as u32;
                self.count[node] = (hi - lo) as u32;
                continue;
            }
            let mut cmin = DVec3::splat(f64::INFINITY);
            let mut cmax = DVec3::splat(f64::NEG_INFINITY);
            for &tri in &self.perm[lo..hi] {
                let c = DVec3::new(centre(tri, 0), centre(tri, 1), centre(tri, 2));
                cmin = cmin.min(c);
                cmax = cmax.max(c);
            }
            let ext = cmax - cmin;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = (lo + hi) / 2;
            self.perm[lo..hi].select_nth_unstable_by(mid - lo, |&x, &y| {
                centre(x, axis).total_cmp(&centre(y, axis))
            });
            let child = self.nodes;
            self.nodes += 2;
            self.first[node] = child as u32;
            self.count[node] = 0;
            stack[top] = (child as u32, lo as u32, mid as u32);
            stack[top + 1] = (child as u32 + 1, mid as u32, hi as u32);
            top += 2;
        }
        // Inner boxes bottom up: children come after their parent.
        for n in (0..self.nodes).rev() {
            if self.count[n] == 0 {
                let c = self.first[n] as usize;
                for k in 0..3 {
                    self.boxes[6 * n + k] = self.boxes[6 * c + k].min(self.boxes[6 * c + 6 + k]);
                    self.boxes[6 * n + 3 + k] =
                        self.boxes[6 * c + 3 + k].max(self.boxes[6 * c + 9 + k]);
                }
            }
        }
    }

    /// Calls `f` with every triangle whose box overlaps `[lo, hi]`.
    pub fn query(&self, lo: DVec3, hi: DVec3, mut f: impl FnMut(usize)) {
        let mut stack = [0u32; STACK * 2];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top] as usize;
            let b = &self.boxes[6 * n..6 * n + 6];
            if b[0] > hi.x
                || b[1] > hi.y
                || b[2] > hi.z
                || b[3] < lo.x
                || b[4] < lo.y
                || b[5] < lo.z
            {
                continue;
            }
            let c = self.count[n] as usize;
            let first = self.first[n] as usize;
            if c > 0 {
                for &t in &self.perm[first..first + c] {
                    f(t as usize);
                }
            } else {
                stack[top] = first as u32;
                stack[top + 1] = first as u32 + 1;
                top += 2;
            }
        }
    }
}
