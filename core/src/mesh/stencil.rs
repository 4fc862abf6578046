//! The local subdivision matrices of one extraordinary patch.
//!
//! Control points of a patch whose extraordinary vertex (EV) of valence `n` is
//! at its corner (0,0) are labelled (K = 2n+8 points):
//!
//! * `0`: the EV `V`;
//! * `1 + 2i`: edge neighbour `E_i`, `2 + 2i`: face-diagonal vertex `F_i`
//!   (sector `i` is the face `V E_i F_i E_(i+1)`, sectors run counter-clockwise
//!   and sector 0 is the patch itself);
//! * `2n+1 .. 2n+8`: the seven outer points `O_0..O_6` at grid positions
//!   (2,-1) (2,0) (2,1) (2,2) (1,2) (0,2) (-1,2).
//!
//! Grid positions (x along u, y along v): `V`=(0,0), `E_0`=(1,0), `F_0`=(1,1),
//! `E_1`=(0,1), `F_1`=(-1,1), `E_2`=(-1,0), `E_(n-1)`=(0,-1), `F_(n-1)`=(1,-1).
//! For n = 4 this is the regular 4x4 grid with `F_2` at (-1,-1).
//!
//! [`Stencils`] holds, as dense rows over these labels, one Catmull-Clark step
//! (\[CL-R ch. 2\], \[Stam98\]): `A` (K x K, new labels from old)
//! and the pickers `P_b A_bar` (16 x K) giving the B-spline control grids of
//! the three regular sub-patches Omega_{1,b}, b = 1, 2, 3.

pub use crate::config::MAX_K;
pub use crate::math::linalg::{Mat, Row};

/// Label of the outer point `O_k`.
#[inline]
pub const fn outer(n: usize, k: usize) -> usize {
    2 * n + 1 + k
}

/// Grid positions of the outer points `O_0..O_6`.
pub const OUTER_POS: [(i32, i32); 7] = [(2, -1), (2, 0), (2, 1), (2, 2), (1, 2), (0, 2), (-1, 2)];

/// Old label at grid position (x, y) of the chart, if the chart has it.
pub fn label_at(n: usize, x: i32, y: i32) -> Option<usize> {
    let e = |i: usize| 1 + 2 * (i % n);
    let f = |i: usize| 2 + 2 * (i % n);
    Some(match (x, y) {
        (0, 0) => 0,
        (1, 0) => e(0),
        (1, 1) => f(0),
        (0, 1) => e(1),
        (-1, 1) => f(1),
        (-1, 0) => e(2),
        (0, -1) => e(n - 1),
        (1, -1) => f(n - 1),
        (-1, -1) if n == 4 => f(2),
        _ => {
            let k = OUTER_POS.iter().position(|&p| p == (x, y))?;
            outer(n, k)
        }
    })
}

/// Builder of the local stencils for valence `n`.
struct Chart {
    n: usize,
    /// EV rule (alpha, beta, gamma).
    ev: (f64, f64, f64),
    /// Rule of the regular (valence-4) vertices.
    reg: (f64, f64, f64),
}

fn unit(i: usize) -> Row {
    let mut r = [0.0; MAX_K];
    r[i] = 1.0;
    r
}

fn axpy(acc: &mut Row, a: f64, x: &Row) {
    for (o, v) in acc.iter_mut().zip(x.iter()) {
        *o += a * v;
    }
}

impl Chart {
    fn old(&self, x: i32, y: i32) -> Row {
        // All positions requested by the rules below exist in the chart.
        unit(label_at(self.n, x, y).unwrap_or(0))
    }

    /// Face point of ring face `i` (`V E_i F_i E_(i+1)`).
    fn ring_face(&self, i: usize) -> Row {
        let n = self.n;
        let mut r = [0.0; MAX_K];
        r[0] += 0.25;
        r[1 + 2 * (i % n)] += 0.25;
        r[2 + 2 * (i % n)] += 0.25;
        r[1 + 2 * ((i + 1) % n)] += 0.25;
        r
    }

    /// New edge point on the spoke `V E_i`.
    fn ring_edge(&self, i: usize) -> Row {
        let n = self.n;
        let mut r = [0.0; MAX_K];
        r[0] += 0.25;
        r[1 + 2 * (i % n)] += 0.25;
        axpy(&mut r, 0.25, &self.ring_face(i + n - 1));
        axpy(&mut r, 0.25, &self.ring_face(i));
        r
    }

    /// New vertex point of the EV (general rule, eq. 1.1).
    fn ring_vertex(&self) -> Row {
        let n = self.n;
        let (a, b, g) = self.ev;
        let mut r = [0.0; MAX_K];
        r[0] = a;
        for i in 0..n {
            r[1 + 2 * i] += b / n as f64;
            r[2 + 2 * i] += g / n as f64;
        }
        r
    }

    /// Face point of the unit square with lower-left corner (x, y).
    fn face(&self, x: i32, y: i32) -> Row {
        let mut r = [0.0; MAX_K];
        for (dx, dy) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
            axpy(&mut r, 0.25, &self.old(x + dx, y + dy));
        }
        r
    }

    /// New point at position (X, Y) of the refined grid (half spacing).
    fn new_point(&self, gx: i32, gy: i32) -> Row {
        let n = self.n;
        // Points of the refined 1-ring use the ring rules (they may involve
        // sectors outside the chart).
        match (gx, gy) {
            (0, 0) => return self.ring_vertex(),
            (1, 0) => return self.ring_edge(0),
            (1, 1) => return self.ring_face(0),
            (0, 1) => return self.ring_edge(1),
            (-1, 1) => return self.ring_face(1),
            (-1, 0) => return self.ring_edge(2),
            (0, -1) => return self.ring_edge(n - 1),
            (1, -1) => return self.ring_face(n - 1),
            _ => {}
        }
        let (ex, ey) = (gx.rem_euclid(2) == 0, gy.rem_euclid(2) == 0);
        let (x, y) = (gx.div_euclid(2), gy.div_euclid(2));
        match (ex, ey) {
            (false, false) => self.face(x, y),
            (false, true) => {
                // Horizontal edge (x,y)-(x+1,y) between squares (x,y-1) and (x,y).
                let mut r = [0.0; MAX_K];
                axpy(&mut r, 0.25, &self.old(x, y));
                axpy(&mut r, 0.25, &self.old(x + 1, y));
                axpy(&mut r, 0.25, &self.face(x, y - 1));
                axpy(&mut r, 0.25, &self.face(x, y));
                r
            }
            (true, false) => {
                // Vertical edge (x,y)-(x,y+1) between squares (x-1,y) and (x,y).
                let mut r = [0.0; MAX_K];
                axpy(&mut r, 0.25, &self.old(x, y));
                axpy(&mut r, 0.25, &self.old(x, y + 1));
                axpy(&mut r, 0.25, &self.face(x - 1, y));
                axpy(&mut r, 0.25, &self.face(x, y));
                r
            }
            (true, true) => {
                // Regular (valence-4) vertex point, general rule with n = 4.
                let (a, b, g) = self.reg;
                let mut r = [0.0; MAX_K];
                axpy(&mut r, a, &self.old(x, y));
                for (dx, dy) in [(1, 0), (0, 1), (-1, 0), (0, -1)] {
                    axpy(&mut r, b / 4.0, &self.old(x + dx, y + dy));
                }
                for (dx, dy) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
                    axpy(&mut r, g / 4.0, &self.old(x + dx, y + dy));
                }
                r
            }
        }
    }
}

/// Grid positions (X, Y) of the refined grid forming the 4x4 B-spline control
/// grid of sub-patch b (1, 2, 3) of the first level; entry `j*4 + i` is the
/// point with `i` along u and `j` along v.
pub fn sub_patch_grid(b: usize) -> [(i32, i32); 16] {
    let (x0, y0) = match b {
        1 => (0, -1),
        2 => (0, 0),
        _ => (-1, 0),
    };
    let mut g = [(0, 0); 16];
    for j in 0..4 {
        for i in 0..4 {
            g[j * 4 + i] = (x0 + i as i32, y0 + j as i32);
        }
    }
    g
}

/// The local subdivision matrices of valence `n`.
pub struct Stencils {
    /// Valence.
    pub n: usize,
    /// Number of labels, `2n + 8`.
    pub k: usize,
    /// `A`: row `r` gives new label `r` from the old labels.
    pub a: Mat,
    /// `P_b A_bar` for b = 1, 2, 3 (index b-1): 16 rows over old labels.
    pub pick: [[Row; 16]; 3],
}

impl Stencils {
    /// Fills `self` for valence `n` (3..=MAX_VALENCE), EV rule `ev` and rule
    /// `reg` for the valence-4 vertices around it.
    pub fn fill(&mut self, n: usize, ev: (f64, f64, f64), reg: (f64, f64, f64)) {
        let c = Chart { n, ev, reg };
        let k = 2 * n + 8;
        self.n = n;
        self.k = k;
        for row in self.a.iter_mut() {
            *row = [0.0; MAX_K];
        }
        self.a[0] = c.ring_vertex();
        for i in 0..n {
            self.a[1 + 2 * i] = c.ring_edge(i);
            self.a[2 + 2 * i] = c.ring_face(i);
        }
        for (j, &(x, y)) in OUTER_POS.iter().enumerate() {
            self.a[outer(n, j)] = c.new_point(x, y);
        }
        for b in 1..=3 {
            for (r, &(x, y)) in sub_patch_grid(b).iter().enumerate() {
                self.pick[b - 1][r] = c.new_point(x, y);
            }
        }
    }

    /// An all-zero value, to be filled by [`Stencils::fill`].
    pub const ZERO: Stencils = Stencils {
        n: 0,
        k: 0,
        a: [[0.0; MAX_K]; MAX_K],
        pick: [[[0.0; MAX_K]; 16]; 3],
    };
}
