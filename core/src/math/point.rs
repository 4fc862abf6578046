//! The value type of an evaluation: position, derivatives and normal.
//!
//! It lives in `math` because both the eigen kernel ([`crate::eigen`]) and
//! the mesh-level evaluator ([`crate::eval`]) return it.

use glam::DVec3;

/// Result of one evaluation.
///
/// Derivatives are with respect to the (sub-)face's own (u, v).
/// `normal` is `normalize(du x dv)` (zero where that vanishes). At the
/// extraordinary vertex itself see [`crate::ValenceTable::eval_at_ev`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Eval {
    /// Position.
    pub p: DVec3,
    /// dS/du.
    pub du: DVec3,
    /// dS/dv.
    pub dv: DVec3,
    /// d2S/du2 (zero unless second derivatives were requested).
    pub duu: DVec3,
    /// d2S/dudv.
    pub duv: DVec3,
    /// d2S/dv2.
    pub dvv: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Eval {
    /// Multiplies the first derivatives by `s` and, with `SECOND`, the
    /// second ones by `s * s` (a change of parameter scale).
    #[inline(always)]
    pub(crate) fn scale_derivatives<const SECOND: bool>(&mut self, s: f64) {
        self.du *= s;
        self.dv *= s;
        if SECOND {
            let s2 = s * s;
            self.duu *= s2;
            self.duv *= s2;
            self.dvv *= s2;
        }
    }
}
