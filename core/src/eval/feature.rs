//! Exact evaluation of meshes with boundaries, creases, corners, holes and
//! non-manifold parts ([`FeatureEvaluator`]), by local refinement until the
//! query point lies in a bicubic piece \[OSD\].
//!
//! The parameterisation is the one of [`crate::Evaluator`]: a quad face has
//! one sub-face with `(0,0)` at its first corner, `(1,0)` at the second; an
//! `N`-gon has `N` sub-faces, sub-face `k` being its level-1 child at corner
//! `k`. On a closed smooth mesh both evaluators give the same surface.
//!
//! Cost: one gather of the patch neighbourhood plus one local refinement
//! step per halving of the distance to the nearest irregular corner
//! (`log2(1/d)` steps; bounded by 1,100 for any `f64` parameter). At an
//! irregular corner itself the position is the exact limit (eigenvector of
//! the corner's one-ring matrix); `du` and `dv` there are unit vectors along
//! the two parameter lines' tangents (chords at parameter distance 2^-40;
//! their lengths carry no meaning), second derivatives zero.
//!
//! Layer 5 (with the rest of `eval/`): imports `math` and `mesh`.

use crate::error::Error;
use crate::eval::Query;
use crate::math::{bspline, Eval};
use crate::mem::arena::{Arena, Layout};
use crate::mesh::features::FeatureMesh;
use crate::mesh::local::LocalPatch;

/// Most local refinement steps of one evaluation: every halving of the
/// distance to an irregular corner is one step, and an `f64` in `(0, 1]`
/// halves at most 1,075 times before it is zero.
pub const MAX_STEPS: usize = 1100;

/// Evaluates a [`FeatureMesh`]. [`FeatureEvaluator::build`] finds, once,
/// every level-1 patch that is already a B-spline (most of a typical
/// mesh) and keeps its 16 control points in caller memory, so evaluating
/// there costs one bicubic evaluation; the other patches refine locally at
/// each query.
#[derive(Clone, Copy, Debug)]
pub struct FeatureEvaluator<'m, 'a> {
    mesh: &'m FeatureMesh<'a>,
    /// Per level-1 face: index + 1 of its grid in `grids`, or 0.
    grid_of: &'m [u32],
    /// 48 values (16 points, x y z) per cached grid.
    grids: &'m [f64],
}

impl<'m, 'a> FeatureEvaluator<'m, 'a> {
    /// Exact bytes [`FeatureEvaluator::build`] uses for `mesh` (it counts
    /// the B-spline patches, which costs one neighbourhood gather per
    /// level-1 face).
    pub fn required_bytes(mesh: &FeatureMesh) -> usize {
        let n = mesh.level1.num_faces();
        let regular = (0..n).filter(|&f| Self::grid(mesh, f).is_some()).count();
        let mut l = Layout::default();
        l.u32s(n);
        l.f64s(48 * regular);
        l.bytes()
    }

    /// The evaluator of `mesh`, with the B-spline patches' control points in
    /// `mem` (see [`FeatureEvaluator::required_bytes`]).
    pub fn build(mesh: &'m FeatureMesh<'a>, mem: &'m mut [u64]) -> Result<Self, Error> {
        let need = Self::required_bytes(mesh);
        if crate::mem::bytes_of(mem.len()) < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        let n = mesh.level1.num_faces();
        let mut arena = Arena::new(mem);
        let grid_of = arena.u32s(n);
        let regular = (need - 8 * n.div_ceil(2)) / (8 * 48);
        let grids = arena.f64s(48 * regular);
        let mut k = 0;
        for f in 0..n {
            if let Some(g) = Self::grid(mesh, f) {
                for (i, p) in g.iter().enumerate() {
                    grids[48 * k + 3 * i] = p.x;
                    grids[48 * k + 3 * i + 1] = p.y;
                    grids[48 * k + 3 * i + 2] = p.z;
                }
                k += 1;
                grid_of[f] = k as u32;
            }
        }
        Ok(FeatureEvaluator {
            mesh,
            grid_of,
            grids,
        })
    }

    /// The B-spline control points of level-1 face `f`, if it is one.
    fn grid(mesh: &FeatureMesh, f: usize) -> Option<[glam::DVec3; 16]> {
        LocalPatch::<64, 196, 256>::gather(mesh, f, 0)
            .ok()?
            .regular_grid()
    }

    /// Number of sub-faces of base face `f` (1 for a quad, `N` for an
    /// `N`-gon).
    pub fn num_subfaces(&self, f: usize) -> usize {
        let n = self.mesh.base.face(f).len();
        if n == 4 {
            1
        } else {
            n
        }
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.mesh.num_faces()
    }

    /// Checks a query without evaluating it: face and sub-face in range,
    /// parameters in `[0, 1]`, face not a hole.
    pub fn check(&self, q: &Query) -> Result<(), Error> {
        q.check_ranges(self.mesh.num_faces(), |f| self.num_subfaces(f))?;
        if self.mesh.hole[self.mesh.child_face(q.face as usize, 0)] != 0 {
            return Err(Error::HoleFace { face: q.face });
        }
        Ok(())
    }

    /// Position, first derivatives and normal at `(u, v)` of sub-face `sub`
    /// of base face `face`.
    pub fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl(face, sub, u, v, false)
    }

    /// As [`FeatureEvaluator::eval`], plus second derivatives.
    pub fn eval_second(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl(face, sub, u, v, true)
    }

    fn eval_impl(&self, face: u32, sub: u32, u: f64, v: f64, second: bool) -> Result<Eval, Error> {
        let fm = self.mesh;
        let f = face as usize;
        self.check(&Query { face, sub, u, v })?;
        // Level-1 face and parameters there.
        let quad = fm.base.face(f).len() == 4;
        let (face1, s, t, scale) = if quad {
            let (cx, cy) = (u > 0.5, v > 0.5);
            let k = match (cx, cy) {
                (false, false) => 0,
                (true, false) => 1,
                (true, true) => 2,
                (false, true) => 3,
            };
            let s = 2.0 * u - if cx { 1.0 } else { 0.0 };
            let t = 2.0 * v - if cy { 1.0 } else { 0.0 };
            (fm.child_face(f, k), s, t, 2.0)
        } else {
            (fm.child_face(f, sub as usize), u, v, 1.0)
        };
        if let Some(k) = (self.grid_of[face1] as usize).checked_sub(1) {
            let g = &self.grids[48 * k..48 * k + 48];
            let mut pts = [glam::DVec3::ZERO; 16];
            for (i, p) in pts.iter_mut().enumerate() {
                *p = glam::DVec3::new(g[3 * i], g[3 * i + 1], g[3 * i + 2]);
            }
            return Ok(finish(
                if second {
                    bspline::eval_points::<true>(&pts, s, t)
                } else {
                    bspline::eval_points::<false>(&pts, s, t)
                },
                scale,
            ));
        }
        let small = self.descend::<64, 196, 256>(face1, (s, t, scale), face, sub, (u, v), second);
        match small {
            Err(Error::NeighbourhoodTooLarge { .. }) => {
                self.descend::<400, 1204, 1600>(face1, (s, t, scale), face, sub, (u, v), second)
            }
            r => r,
        }
    }

    /// Local refinement of level-1 face `face1` towards `(s, t)` with a
    /// patch of the given capacity (a frame of its own, so the large one
    /// costs stack only when used).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn descend<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        face1: usize,
        (mut s, mut t, mut scale): (f64, f64, f64),
        face: u32,
        sub: u32,
        (u, v): (f64, f64),
        second: bool,
    ) -> Result<Eval, Error> {
        let opts = self.mesh.options;
        let too_large = |_| Error::NeighbourhoodTooLarge { face };
        let mut patch = LocalPatch::<NF, NV, NE>::gather(self.mesh, face1, face)?;
        for _ in 0..MAX_STEPS {
            if let Some(g) = patch.regular_grid() {
                let e = if second {
                    bspline::eval_points::<true>(&g, s, t)
                } else {
                    bspline::eval_points::<false>(&g, s, t)
                };
                return Ok(finish(e, scale));
            }
            // Exactly at an irregular corner: the exact limit there.
            let at = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
            if let Some(k) = at.iter().position(|&c| c == (s, t)) {
                let c = patch.corners()[k];
                if !patch.corner_is_regular(c) {
                    return self.at_corner(patch, k, face, sub, u, v);
                }
            }
            let (cx, cy) = (s > 0.5, t > 0.5);
            let q = match (cx, cy) {
                (false, false) => 0,
                (true, false) => 1,
                (true, true) => 2,
                (false, true) => 3,
            };
            patch = patch.child(&opts, q).map_err(too_large)?;
            s = 2.0 * s - if cx { 1.0 } else { 0.0 };
            t = 2.0 * t - if cy { 1.0 } else { 0.0 };
            scale *= 2.0;
        }
        Err(Error::InvalidArgument(
            "internal: local refinement did not reach a regular patch",
        ))
    }

    /// The limit at irregular corner `k` of `patch` (the query point), with
    /// unit tangent directions from chords along the two parameter lines.
    fn at_corner<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        mut patch: LocalPatch<NF, NV, NE>,
        k: usize,
        face: u32,
        sub: u32,
        u: f64,
        v: f64,
    ) -> Result<Eval, Error> {
        let opts = self.mesh.options;
        let too_large = |_| Error::NeighbourhoodTooLarge { face };
        // Semi-sharp values decay within about ten steps towards the corner.
        for _ in 0..64 {
            if patch.corner_is_stationary(patch.corners()[k]) {
                break;
            }
            patch = patch.child(&opts, k).map_err(too_large)?;
        }
        let p = patch.corner_limit(&opts, k).map_err(too_large)?;
        // Chords towards increasing / decreasing u and v within the face.
        const H: f64 = 1.0 / (1u64 << 40) as f64;
        let du_sign = if u < 0.5 { 1.0 } else { -1.0 };
        let dv_sign = if v < 0.5 { 1.0 } else { -1.0 };
        let pu = self.eval_impl(face, sub, u + du_sign * H, v, false)?.p;
        let pv = self.eval_impl(face, sub, u, v + dv_sign * H, false)?.p;
        let du = ((pu - p) * du_sign).normalize_or_zero();
        let dv = ((pv - p) * dv_sign).normalize_or_zero();
        Ok(Eval {
            p,
            du,
            dv,
            normal: du.cross(dv).normalize_or_zero(),
            ..Eval::default()
        })
    }
}

/// Scales a B-spline evaluation of a level-k patch to the base face's
/// parameters (`scale = 2^k`) and adds the normal.
fn finish(mut e: Eval, scale: f64) -> Eval {
    e.du *= scale;
    e.dv *= scale;
    e.duu *= scale * scale;
    e.duv *= scale * scale;
    e.dvv *= scale * scale;
    e.normal = e.du.cross(e.dv).normalize_or_zero();
    e
}
