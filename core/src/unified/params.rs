//! Parameters of the unified scheme (\[MS01\]) and their
//! validation.

use crate::error::Error;

/// Largest accepted split count `d` (refined counts are checked separately;
/// this bound only keeps the index arithmetic far from overflow).
pub const MAX_D: u32 = 1 << 12;

/// Largest accepted degree `p` (`(p - 1) / 2` smoothing passes).
pub const MAX_P: u32 = 255;

/// How triangles of the input are split.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TriangleRule {
    /// The paper's rule (MS Fig. 5 and Fig. 8): a triangle becomes `d^2`
    /// triangles (barycentric grid). Meshes with triangles keep their
    /// triangles, as the paper requires for modelling.
    #[default]
    Split,
    /// Triangles use the polygon rule (like quads and n-gons): `3 d^2 / 4`
    /// quads for even `d`, as Catmull-Clark does for `d = 2`. With this rule
    /// and [`UnifiedParams::CATMULL_CLARK`] a step equals Catmull-Clark on
    /// every mesh.
    Polygon,
}

/// Parameters of one refinement level.
///
/// * `a` — push-back ("volume") parameter, eqs. (4)–(6) and (14)–(17):
///   `0` approximating (uniform B-splines), `1` interpolating.
/// * `b` — rounding factor of the renormalisation, eqs. (18)–(21):
///   `0` plain (bi)linear interpolation of the push-back vectors, `1` exact
///   interpolation of their lengths.
/// * `g` — Catmull-Clark correction, eqs. (11)–(13): `0` simple averaging,
///   `1` exactly Catmull-Clark for `d = 2`.
/// * `d` — split count: every edge is cut into `d` pieces (`d >= 2`).
/// * `p` — odd degree `p >= 1`: `(p - 1) / 2` smoothing passes (`p = 1` is
///   plain linear subdivision, `p = 3` cubic).
/// * `triangles` — how triangles are split ([`TriangleRule`]).
///
/// [`Default`] is the paper's tool default (MS §4): `a = b = 1/2`, `g = 0`,
/// `d = 2`, `p = 3`, triangles split into triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnifiedParams {
    /// Push-back parameter `a`.
    pub a: f64,
    /// Rounding factor `b`.
    pub b: f64,
    /// Catmull-Clark correction `g`.
    pub g: f64,
    /// Split count `d` (`2..=MAX_D`).
    pub d: u32,
    /// Odd degree `p` (`1..=MAX_P`).
    pub p: u32,
    /// Triangle rule.
    pub triangles: TriangleRule,
}

impl Default for UnifiedParams {
    fn default() -> Self {
        UnifiedParams {
            a: 0.5,
            b: 0.5,
            g: 0.0,
            d: 2,
            p: 3,
            triangles: TriangleRule::Split,
        }
    }
}

impl UnifiedParams {
    /// `a = b = 0`, `g = 1`, `d = 2`, `p = 3`, triangles as polygons: one
    /// standard Catmull-Clark step (MS eq. (13) with `g = 1`).
    pub const CATMULL_CLARK: UnifiedParams = UnifiedParams {
        a: 0.0,
        b: 0.0,
        g: 1.0,
        d: 2,
        p: 3,
        triangles: TriangleRule::Polygon,
    };

    /// The same parameters with split count `d`.
    pub const fn with_d(mut self, d: u32) -> Self {
        self.d = d;
        self
    }

    /// The same parameters with push-back `a`.
    pub const fn with_a(mut self, a: f64) -> Self {
        self.a = a;
        self
    }

    /// Number of smoothing passes, `(p - 1) / 2`.
    pub fn passes(&self) -> u32 {
        self.p.saturating_sub(1) / 2
    }

    /// Checks the parameters: `a`, `b`, `g` finite, `2 <= d <= MAX_D`,
    /// `p` odd in `1..=MAX_P`. Errors are [`Error::InvalidArgument`] naming
    /// the parameter.
    pub fn validate(&self) -> Result<(), Error> {
        if !self.a.is_finite() {
            return Err(Error::InvalidArgument("unified: a is NaN or infinite"));
        }
        if !self.b.is_finite() {
            return Err(Error::InvalidArgument("unified: b is NaN or infinite"));
        }
        if !self.g.is_finite() {
            return Err(Error::InvalidArgument("unified: g is NaN or infinite"));
        }
        if self.d < 2 {
            return Err(Error::InvalidArgument("unified: d must be at least 2"));
        }
        if self.d > MAX_D {
            return Err(Error::InvalidArgument("unified: d is larger than MAX_D"));
        }
        if self.p.is_multiple_of(2) {
            return Err(Error::InvalidArgument("unified: p must be odd"));
        }
        if self.p > MAX_P {
            return Err(Error::InvalidArgument("unified: p is larger than MAX_P"));
        }
        Ok(())
    }
}
