//! Volume flooding: inside/outside classification of the white voxels.
//!
//! ## Which voxels are inside (the seed question, answered without seeds)
//!
//! The paper picks an inside seed next to a surface voxel by its stored
//! normal and floods from it. That needs a normal per voxel, fails near
//! multi-sheet voxels (which it therefore marks and avoids), and one seed
//! per connected interior region. We classify instead, with proofs:
//!
//! 1. **Exterior.** The grid holds the whole surface (the normalisation maps
//!    a guaranteed box of it into `[0, M-1]^3`), so a white voxel on the
//!    border of the grid has its centre outside the solid (a centre on the
//!    border plane cannot be interior to a solid lying on one side of it,
//!    and a centre on the surface would make the voxel black). Everything
//!    6-connected to the border through white voxels is outside as well:
//!    the surface voxels are 6-separating ([`super::rasterize`]: a surface
//!    point on the segment between two 6-adjacent centres makes one of the
//!    two voxels black).
//! 2. **Enclosed components.** By the same argument the inside/outside
//!    status is constant on every 6-connected white component. Each
//!    component not reached from the border gets one certified ray test
//!    (`ray.rs`: the winding number of the exact limit surface around a
//!    voxel centre, as a sum of degrees over Bezier cells) and is flooded
//!    into the interior plane (inside) or the work plane (outside: a cavity,
//!    the hole of a torus closed off by the grid border, the gap between two
//!    solids). This is right for several components, any genus, and internal
//!    voids, and never leaks through a separating surface. If every ray of a
//!    component is degenerate (it passes within rounding of a cell edge or
//!    an extraordinary vertex's projection in all tries), the component is
//!    taken as outside and counted in [`FloodStats::unresolved`].
//!
//! ## Flooding (FloodingXYZ + GRAYSTACK + linear scan, bit-parallel)
//!
//! The unit of work is a whole row of voxels along x (one bit each):
//! processing a row fills along x within its white runs that contain
//! reached bits (an add-with-carry across the row's words fills upward, the
//! same on bit-reversed words downward — the paper's `FloodingXYZ` along x
//! for 64 voxels per instruction), then passes the reached bits to the four
//! neighbouring rows (y +- 1, z +- 1), which become dirty. Dirty rows go on
//! the caller's stack of row numbers (the paper's `GRAYSTACK`, with the
//! caller's capacity: memory stays bounded). When it is full the row stays
//! marked in the one-bit-per-row dirty set, and when the stack runs empty a
//! linear sweep over the dirty set (alternating direction) processes them:
//! the paper's linear scan, but over rows that need it only. The stack
//! holds `u32` row numbers; `M2 * (z1 - z0)` entries make overflow
//! impossible, and any capacity >= 1 is correct.

use super::cells::Affine;
use super::grid::VoxelGrid;
use super::ray;
use super::stack::VoxelWork;
use super::GridState;
use crate::error::Error;
use glam::DVec3;

/// What a flood did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FloodStats {
    /// White components not reached from the grid border (each got a ray
    /// test).
    pub enclosed_components: u32,
    /// Of those, components classified inside.
    pub inside_components: u32,
    /// Rays cast (including degenerate ones retried).
    pub rays: u32,
    /// Components whose every ray was degenerate (taken as outside).
    pub unresolved: u32,
    /// Linear sweeps run because the stack overflowed.
    pub sweeps: u32,
    /// Rows processed.
    pub row_visits: u64,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Target {
    Work,
    Interior,
}

/// Valid bits of word `w` of a row of `wpr` words whose last word has the
/// valid bits `last` (all others are full).
#[inline(always)]
fn valid_bits(w: usize, wpr: usize, last: u64) -> u64 {
    if w + 1 == wpr {
        last
    } else {
        !0
    }
}

struct Flood<'g, 'a, 's> {
    g: &'g mut VoxelGrid<'a>,
    stack: &'s mut [u32],
    sp: usize,
    overflow: bool,
    r0: usize,
    r1: usize,
    m2: usize,
    wpr: usize,
    /// Valid bits of the last word of a row.
    last_valid: u64,
    /// The interior plane is still all clear (exterior phase): skip it.
    no_interior: bool,
    stats: FloodStats,
}

impl Flood<'_, '_, '_> {
    #[inline(always)]
    fn dirty(&self, r: usize) -> bool {
        self.g.dirty[r / 64] & (1u64 << (r % 64)) != 0
    }
    #[inline(always)]
    fn set_dirty(&mut self, r: usize, on: bool) {
        if on {
            self.g.dirty[r / 64] |= 1u64 << (r % 64);
        } else {
            self.g.dirty[r / 64] &= !(1u64 << (r % 64));
        }
    }

    /// Mask of the valid bits of word `w` of a row.
    #[inline(always)]
    fn valid(&self, w: usize) -> u64 {
        valid_bits(w, self.wpr, self.last_valid)
    }

    /// Fills row `r` of the target along x within its white runs: upward
    /// by an add-with-carry across the row's words (a carry runs through a
    /// run of free bits from its lowest reached bit), then downward by an
    /// occluded "smear" (shifts by 1, 2, 4, ..., 32 within the free mask,
    /// bit 63 fed from the word above).
    #[inline]
    fn fill_row(&mut self, r: usize, t: Target) {
        let base = r * self.wpr;
        let wpr = self.wpr;
        let last = self.last_valid;
        let skip_op = self.no_interior && t == Target::Work;
        let g = &mut *self.g;
        let (tp, op) = match t {
            Target::Work => (&mut g.work[base..base + wpr], &g.interior[base..base + wpr]),
            Target::Interior => (&mut g.interior[base..base + wpr], &g.work[base..base + wpr]),
        };
        let s = &g.surface[base..base + wpr];
        let valid = |w: usize| valid_bits(w, wpr, last);
        let free = |w: usize| {
            if skip_op {
                valid(w) & !s[w]
            } else {
                valid(w) & !s[w] & !op[w]
            }
        };
        // Fast path: a row without surface or other-class voxels is one run.
        let mut blocked = 0u64;
        let mut seeds = 0u64;
        for w in 0..wpr {
            blocked |= s[w];
            if !skip_op {
                blocked |= op[w];
            }
            seeds |= tp[w];
        }
        if blocked == 0 {
            if seeds != 0 {
                for (w, x) in tp.iter_mut().enumerate() {
                    *x = valid(w);
                }
            }
            return;
        }
        if seeds == 0 {
            return;
        }
        let mut carry = false;
        for w in 0..wpr {
            let m = free(w);
            let seed = tp[w] & m;
            let (x, c1) = m.overflowing_add(seed);
            let (x, c2) = x.overflowing_add(carry as u64);
            tp[w] = ((x ^ m) & m) | seed;
            carry = c1 | c2;
        }
        let mut down = false;
        for w in (0..wpr).rev() {
            let mut m = free(w);
            let mut d = tp[w] & m;
            if down {
                d |= m & (1u64 << 63);
            }
            // Only words with a free, unreached bit right below a reached
            // one grow downward.
            if (d >> 1) & m & !d != 0 {
                d |= (d >> 1) & m;
                m &= m >> 1;
                d |= (d >> 2) & m;
                m &= m >> 2;
                d |= (d >> 4) & m;
                m &= m >> 4;
                d |= (d >> 8) & m;
                m &= m >> 8;
                d |= (d >> 16) & m;
                m &= m >> 16;
                d |= (d >> 32) & m;
            }
            tp[w] |= d;
            down = d & 1 != 0;
        }
    }

    /// Passes row `r`'s reached bits to row `n` (`n != r`); true if `n`
    /// gained bits. (Reached bits are valid and free in `r`; `n`'s free bits
    /// are those in neither the surface nor a class plane.) Branch-free over
    /// disjoint row slices, so the loop vectorises.
    #[inline]
    fn pass(&mut self, r: usize, n: usize, t: Target) -> bool {
        let wpr = self.wpr;
        let skip_op = self.no_interior && t == Target::Work;
        let g = &mut *self.g;
        let (tp, op) = match t {
            Target::Work => (&mut *g.work, &*g.interior),
            Target::Interior => (&mut *g.interior, &*g.work),
        };
        let (src, dst) = if r < n {
            let (a, b) = tp.split_at_mut(n * wpr);
            (&a[r * wpr..r * wpr + wpr], &mut b[..wpr])
        } else {
            let (a, b) = tp.split_at_mut(r * wpr);
            (&b[..wpr], &mut a[n * wpr..n * wpr + wpr])
        };
        let s = &g.surface[n * wpr..n * wpr + wpr];
        let mut any = 0u64;
        if skip_op {
            for ((d, &tv), &sv) in dst.iter_mut().zip(src).zip(s) {
                let c = tv & !(sv | *d);
                any |= c;
                *d |= c;
            }
        } else {
            let o = &op[n * wpr..n * wpr + wpr];
            for (((d, &tv), &sv), &ov) in dst.iter_mut().zip(src).zip(s).zip(o) {
                let c = tv & !(sv | *d | ov);
                any |= c;
                *d |= c;
            }
        }
        any != 0
    }

    /// Processes row `r`; in a sweep, rows at or past `ahead` (in the sweep
    /// direction) are left for the sweep instead of being pushed.
    fn process(&mut self, r: usize, t: Target, sweep: Option<(bool, usize)>) {
        self.stats.row_visits += 1;
        self.fill_row(r, t);
        let y = (r - self.r0) % self.m2;
        let mut nb = [usize::MAX; 4];
        if y > 0 {
            nb[0] = r - 1;
        }
        if y + 1 < self.m2 {
            nb[1] = r + 1;
        }
        if r >= self.r0 + self.m2 {
            nb[2] = r - self.m2;
        }
        if r + self.m2 < self.r1 {
            nb[3] = r + self.m2;
        }
        for n in nb {
            if n == usize::MAX || !self.pass(r, n, t) || self.dirty(n) {
                continue;
            }
            self.set_dirty(n, true);
            let later = match sweep {
                Some((true, _)) => n > r,
                Some((false, _)) => n < r,
                None => false,
            };
            if later {
                continue;
            }
            if self.sp < self.stack.len() {
                self.stack[self.sp] = n as u32;
                self.sp += 1;
            } else {
                self.overflow = true;
            }
        }
    }

    /// Floods until no row is dirty.
    fn run(&mut self, t: Target) {
        let mut forward = true;
        loop {
            while self.sp > 0 {
                self.sp -= 1;
                let r = self.stack[self.sp] as usize;
                self.set_dirty(r, false);
                self.process(r, t, None);
            }
            if !self.overflow {
                return;
            }
            self.overflow = false;
            self.stats.sweeps += 1;
            let (r0, r1) = (self.r0, self.r1);
            let visit = |f: &mut Self, r: usize| {
                if f.dirty(r) {
                    f.set_dirty(r, false);
                    f.process(r, t, Some((forward, r)));
                }
            };
            if forward {
                let mut r = r0;
                while r < r1 {
                    if self.g.dirty[r / 64] == 0 && r % 64 == 0 && r + 64 <= r1 {
                        r += 64;
                        continue;
                    }
                    visit(self, r);
                    r += 1;
                }
            } else {
                let mut r = r1;
                while r > r0 {
                    r -= 1;
                    visit(self, r);
                }
            }
            forward = !forward;
        }
    }

    /// Free (white, unclassified) bits of word `w` of row `r`.
    #[inline]
    fn free(&self, r: usize, w: usize) -> u64 {
        let i = r * self.wpr + w;
        self.valid(w) & !self.g.surface[i] & !self.g.work[i] & !self.g.interior[i]
    }

    /// The first free bit of row `r` (over row slices, no per-word index).
    #[inline]
    fn first_free(&self, r: usize) -> Option<usize> {
        let rows = r * self.wpr..(r + 1) * self.wpr;
        let (s, wk, it) = (
            &self.g.surface[rows.clone()],
            &self.g.work[rows.clone()],
            &self.g.interior[rows],
        );
        for (w, ((&a, &b), &c)) in s.iter().zip(wk).zip(it).enumerate() {
            let fr = self.valid(w) & !(a | b | c);
            if fr != 0 {
                return Some(w * 64 + fr.trailing_zeros() as usize);
            }
        }
        None
    }
}

impl VoxelGrid<'_> {
    /// Classifies every white voxel of the slab as interior or outside (see
    /// the module docs of [`super::flood`]). `ev` must be the evaluator the
    /// grid was voxelized from (the ray tests use its exact surface).
    /// `stack` is the row stack (any length >= 1; longer is faster, up to
    /// `M2 * (z1 - z0)`). Re-flooding a flooded grid starts over.
    ///
    /// Errors: `InvalidArgument` (grid not voxelized, empty stack).
    pub fn flood<S: super::Surface + ?Sized>(
        &mut self,
        ev: &S,
        stack: &mut [u32],
        work: &mut VoxelWork,
    ) -> Result<FloodStats, Error> {
        if self.state == GridState::Empty {
            return Err(Error::InvalidArgument("grid is not voxelized"));
        }
        if stack.is_empty() {
            return Err(Error::InvalidArgument("flood stack has no room"));
        }
        ev.check_solid()?;
        if self.state == GridState::Flooded {
            // The voxelizer leaves both planes clear.
            self.interior.fill(0);
            self.work.fill(0);
        }
        self.dirty.fill(0);
        let (r0, r1) = self.slab_rows();
        let sh = self.shape;
        let aff = Affine {
            scale: self.transform.scale,
            offset: DVec3::from_array(self.transform.offset),
        };
        let thin = self.thin;
        let mut f = Flood {
            g: self,
            stack,
            sp: 0,
            overflow: false,
            r0,
            r1,
            m2: sh.res[1] as usize,
            wpr: sh.wpr,
            last_valid: sh.valid(sh.wpr - 1),
            no_interior: true,
            stats: FloodStats::default(),
        };
        // Exterior: seeds on the border of the grid.
        let m1 = sh.res[0];
        for r in r0..r1 {
            let y = ((r - r0) % f.m2) as u32;
            let z = sh.z0 + ((r - r0) / f.m2) as u32;
            let border = y == 0 || y + 1 == sh.res[1] || z == 0 || z + 1 == sh.res[2];
            let mut any = false;
            let last_w = ((m1 - 1) / 64) as usize;
            let mut seed = |f: &mut Flood, w: usize, mask: u64| {
                let s = f.free(r, w) & mask;
                if s != 0 {
                    f.g.work[r * f.wpr + w] |= s;
                    any = true;
                }
            };
            if border {
                for w in 0..f.wpr {
                    seed(&mut f, w, !0);
                }
            } else {
                seed(&mut f, 0, 1);
                seed(&mut f, last_w, 1u64 << ((m1 - 1) % 64));
            }
            if any {
                f.set_dirty(r, true);
                f.overflow = true;
            }
        }
        f.run(Target::Work);
        f.no_interior = false;
        // Enclosed components.
        let mut r = r0;
        while r < r1 {
            let Some(x) = f.first_free(r) else {
                r += 1;
                continue;
            };
            f.stats.enclosed_components += 1;
            let y = ((r - r0) % f.m2) as u32;
            let z = sh.z0 + ((r - r0) / f.m2) as u32;
            let mut status = None;
            // Candidates: the first voxels of this white run (same component).
            for xi in (x as u32..).take(8) {
                if xi >= m1 || f.free(r, (xi / 64) as usize) & (1u64 << (xi % 64)) == 0 {
                    break;
                }
                f.stats.rays += 1;
                let c = DVec3::new(xi as f64, y as f64, z as f64);
                status = ray::inside(ev, &aff, c, thin, work);
                if status.is_some() {
                    break;
                }
            }
            let t = match status {
                Some(true) => {
                    f.stats.inside_components += 1;
                    Target::Interior
                }
                Some(false) => Target::Work,
                None => {
                    f.stats.unresolved += 1;
                    Target::Work
                }
            };
            let i = r * f.wpr + x / 64;
            match t {
                Target::Work => f.g.work[i] |= 1u64 << (x % 64),
                Target::Interior => f.g.interior[i] |= 1u64 << (x % 64),
            }
            f.set_dirty(r, true);
            f.stack[0] = r as u32;
            f.sp = 1;
            f.run(t);
        }
        let stats = f.stats;
        self.state = GridState::Flooded;
        Ok(stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `fill_row` against a plain per-bit fill: every maximal run of free
    /// bits (valid, not surface, not the other class) that holds a reached
    /// bit becomes reached, nothing else changes. Random rows of 1-5 words
    /// with a partial last word, so the carries across words are exercised.
    #[test]
    fn fill_row_fills_exactly_the_runs_holding_a_seed() {
        let mut rng = crate::test_rng::XorShift(0x9e37_79b9_7f4a_7c15);
        let mut rnd = move || rng.next_u64();
        let mut mem = [0u64; 4 * 5 * 4 + 1];
        let trials = if cfg!(miri) { 8 } else { 4000 };
        for trial in 0..trials {
            let m1 = 2 + (rnd() % 300) as u32;
            let res = [m1, 2, 2];
            let bytes = VoxelGrid::required_bytes(res).unwrap();
            let mut g = VoxelGrid::new(res, &mut mem[..bytes.div_ceil(8)]).unwrap();
            let wpr = g.shape.wpr;
            let last_valid = g.shape.valid(wpr - 1);
            // Density of walls varies per trial; runs can span words.
            let walls = 1 + rnd() % 40;
            let other = trial % 3 == 0;
            for w in 0..wpr {
                let v = g.shape.valid(w);
                let mut s = 0u64;
                let mut o = 0u64;
                let mut seed = 0u64;
                for b in 0..64 {
                    match rnd() % 64 {
                        x if x < walls => s |= 1 << b,
                        x if other && x < walls + 3 => o |= 1 << b,
                        x if x >= 62 => seed |= 1 << b,
                        _ => {}
                    }
                }
                g.surface[w] = s & v;
                g.interior[w] = o & v;
                g.work[w] = seed & v & !s & !o;
            }
            let free = |g: &VoxelGrid, i: u32| {
                let (w, b) = ((i / 64) as usize, 1u64 << (i % 64));
                g.surface[w] & b == 0 && g.interior[w] & b == 0
            };
            let mut want = [0u64; 5];
            let mut i = 0;
            while i < m1 {
                if !free(&g, i) {
                    i += 1;
                    continue;
                }
                let start = i;
                let mut hit = false;
                while i < m1 && free(&g, i) {
                    hit |= g.work[(i / 64) as usize] >> (i % 64) & 1 != 0;
                    i += 1;
                }
                if hit {
                    for x in start..i {
                        want[(x / 64) as usize] |= 1 << (x % 64);
                    }
                }
            }
            let mut stack = [0u32; 4];
            let mut f = Flood {
                g: &mut g,
                stack: &mut stack,
                sp: 0,
                overflow: false,
                r0: 0,
                r1: 4,
                m2: 2,
                wpr,
                last_valid,
                no_interior: !other,
                stats: FloodStats::default(),
            };
            f.fill_row(0, Target::Work);
            for w in 0..wpr {
                assert_eq!(g.work[w], want[w], "trial {trial} m1 {m1} word {w}");
            }
        }
    }
}
