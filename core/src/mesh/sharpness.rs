//! Sharpness arithmetic and the refinement masks of Catmull-Clark with
//! boundaries, creases and corners, as OpenSubdiv's `Sdc` defines them
//! \[OSD\] (semi-sharp creases \[DKT98\]).
//!
//! Sharpness values are `f32` and are combined in `f32` exactly as
//! OpenSubdiv does, so that the same fractional weights come out; masks are
//! `f64`. A value `>= INFINITE` (10) is infinitely sharp; boundary and
//! non-manifold edges are made infinitely sharp by the mesh builder.
//!
//! Vertex rules: a sharp vertex, or one with more than two sharp incident
//! edges, is a *corner*; two sharp edges make a *crease*, one a *dart*, none
//! *smooth*. When the rule changes from one level to the next (semi-sharp
//! values decaying to zero), the vertex point is the blend of the parent
//! rule's and the child rule's masks with OpenSubdiv's fractional weight;
//! an edge point of an edge with sharpness `s < 1` whose halves become
//! smooth is `s * midpoint + (1 - s) * smooth point`.
//!
//! Layer 3 (with the rest of `mesh/`): imports nothing from the crate.

/// Sharpness at or above which an edge or vertex is infinitely sharp.
pub const INFINITE: f32 = 10.0;

/// Boundary interpolation (OpenSubdiv's `VtxBoundaryInterpolation`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub enum Boundary {
    /// Boundary edges are sharp, but every face at a boundary vertex with an
    /// un-sharpened boundary edge is a hole (no surface).
    None = 0,
    /// Boundary edges are infinitely sharp (the default).
    #[default]
    EdgeOnly = 1,
    /// As `EdgeOnly`, and a vertex with one face and two edges is an
    /// infinitely sharp corner.
    EdgeAndCorner = 2,
}

/// How semi-sharp values decay (OpenSubdiv's `CreasingMethod`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub enum Creasing {
    /// Minus one per level.
    #[default]
    Uniform = 0,
    /// At each end vertex, 3/4 of the value plus 1/4 of the average of the
    /// other semi-sharp edges there, then minus one.
    Chaikin = 1,
}

/// Scheme options of a mesh with features.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FeatureOptions {
    /// Boundary interpolation; default [`Boundary::EdgeOnly`].
    pub boundary: Boundary,
    /// Creasing method; default [`Creasing::Uniform`].
    pub creasing: Creasing,
    /// OpenSubdiv's `TRI_SUB_SMOOTH`: edge points next to triangles use the
    /// weight 0.47 for the triangle's centroid. Default off (`TRI_SUB_CATMARK`).
    pub smooth_triangles: bool,
}

/// A vertex rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// No sharp incident edge, vertex not sharp.
    Smooth,
    /// One sharp incident edge.
    Dart,
    /// Two sharp incident edges.
    Crease,
    /// A sharp vertex, or more than two sharp incident edges.
    Corner,
}

/// True for any positive sharpness.
#[inline]
pub fn is_sharp(s: f32) -> bool {
    s > 0.0
}

/// True for an infinitely sharp value.
#[inline]
pub fn is_infinite(s: f32) -> bool {
    s >= INFINITE
}

/// True for a sharpness strictly between 0 and [`INFINITE`].
#[inline]
pub fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < INFINITE
}

/// One level of uniform decay: infinite stays infinite, `s <= 1` becomes 0.
#[inline]
pub fn decrement(s: f32) -> f32 {
    if is_infinite(s) {
        INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// The rule of a vertex from its sharpness and the number of its sharp
/// incident edges.
#[inline]
pub fn rule_of(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
    if is_sharp(vertex_sharpness) {
        return Rule::Corner;
    }
    match sharp_edges {
        0 => Rule::Smooth,
        1 => Rule::Dart,
        2 => Rule::Crease,
        _ => Rule::Corner,
    }
}

/// Semi-sharp statistics of the edges around one vertex, enough to decay
/// any of them at that end: the number of incident edges, the number of
/// semi-sharp ones and the `f32` sum of their values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EndStats {
    /// All incident edges.
    pub edges: u32,
    /// Semi-sharp incident edges.
    pub semi: u32,
    /// Sum of the semi-sharp values (in incident-edge order, `f32`).
    pub sum: f32,
}

impl EndStats {
    /// Statistics of the given incident edge values, in order.
    pub fn of(values: impl Iterator<Item = f32>) -> EndStats {
        let mut st = EndStats::default();
        for s in values {
            st.edges += 1;
            if is_semi_sharp(s) {
                st.semi += 1;
                st.sum += s;
            }
        }
        st
    }
}

/// The child sharpness, at an end vertex with statistics `end`, of an edge
/// of sharpness `s` (OpenSubdiv's `SubdivideEdgeSharpnessAtVertex`).
#[inline]
pub fn decay_at(creasing: Creasing, s: f32, end: EndStats) -> f32 {
    if creasing == Creasing::Uniform || end.edges < 2 {
        return decrement(s);
    }
    if !is_sharp(s) {
        return 0.0;
    }
    if is_infinite(s) {
        return INFINITE;
    }
    if end.semi <= 1 {
        return decrement(s);
    }
    let others = (end.sum - s) / (end.semi - 1) as f32;
    let c = (0.75f32 * s + 0.25f32 * others) - 1.0f32;
    if is_sharp(c) {
        c
    } else {
        0.0
    }
}

/// OpenSubdiv's fractional weight of the parent rule when a vertex's rule
/// changes (`ComputeFractionalWeightAtVertex`). `edges` yields
/// `(parent, child)` sharpness per incident edge.
pub fn fractional_weight(
    creasing: Creasing,
    parent_vertex: f32,
    child_vertex: f32,
    edges: impl Iterator<Item = (f32, f32)>,
) -> f32 {
    let mut count = 0u32;
    let mut sum = 0.0f32;
    if is_sharp(parent_vertex) && !is_sharp(child_vertex) {
        count = 1;
        sum = parent_vertex;
    }
    for (p, c) in edges {
        let transition = match creasing {
            Creasing::Uniform => is_sharp(p) && p <= 1.0,
            Creasing::Chaikin => is_sharp(p) && !is_sharp(c),
        };
        if transition {
            sum += p;
            count += 1;
        }
    }
    if count == 0 {
        return 0.0;
    }
    let w = sum / count as f32;
    if w > 1.0 {
        1.0
    } else {
        w
    }
}

/// A vertex-point mask: the vertex's weight, one weight shared by the far
/// ends of all incident edges, one shared by the centroids of all incident
/// faces, plus up to four extra edge weights (the crease ends of the parent
/// and of the child rule).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexMask {
    /// Weight of the vertex itself.
    pub vertex: f64,
    /// Weight of every incident edge's far end.
    pub each_edge: f64,
    /// Weight of every incident face's centroid.
    pub each_face: f64,
    /// Additional `(incident edge index, weight)` terms; unused slots have
    /// weight 0.
    pub extra: [(u32, f64); 4],
}

impl VertexMask {
    fn corner() -> Self {
        VertexMask {
            vertex: 1.0,
            ..Default::default()
        }
    }

    fn smooth(faces: usize) -> Self {
        let n = faces as f64;
        VertexMask {
            vertex: (n - 2.0) / n,
            each_edge: 1.0 / (n * n),
            each_face: 1.0 / (n * n),
            extra: [(0, 0.0); 4],
        }
    }

    /// Crease mask on the first two incident edges that `sharp` marks.
    fn crease(sharp: &mut dyn Iterator<Item = bool>) -> Self {
        let mut m = VertexMask {
            vertex: 0.75,
            ..Default::default()
        };
        let mut k = 0;
        for (i, s) in sharp.enumerate() {
            if s && k < 2 {
                m.extra[k] = (i as u32, 0.125);
                k += 1;
            }
        }
        m
    }

    fn scaled(&self, w: f64) -> Self {
        let mut m = *self;
        m.vertex *= w;
        m.each_edge *= w;
        m.each_face *= w;
        for e in &mut m.extra {
            e.1 *= w;
        }
        m
    }

    /// Weight of incident edge `i`'s far end.
    #[inline]
    pub fn edge_weight(&self, i: usize) -> f64 {
        let mut w = self.each_edge;
        for &(k, x) in &self.extra {
            if k as usize == i {
                w += x;
            }
        }
        w
    }
}

/// Sharpness around one vertex, as a mask needs it: per incident edge its
/// sharpness and its child sharpness at this vertex.
pub trait Around {
    /// Number of incident edges.
    fn edges(&self) -> usize;
    /// Number of incident faces.
    fn faces(&self) -> usize;
    /// Sharpness of incident edge `i`.
    fn sharpness(&self, i: usize) -> f32;
    /// Child sharpness, at this vertex's end, of incident edge `i`.
    fn child_sharpness(&self, i: usize) -> f32;
}

/// The vertex-point mask of a vertex of sharpness `vs` (OpenSubdiv's
/// `ComputeVertexVertexMask`, parent and child rules from the sharpness).
pub fn vertex_mask(creasing: Creasing, vs: f32, a: &dyn Around) -> VertexMask {
    let ne = a.edges();
    let nf = a.faces();
    if nf == 0 {
        return VertexMask::corner();
    }
    let psharp = (0..ne).filter(|&i| is_sharp(a.sharpness(i))).count();
    let prule = rule_of(vs, psharp);
    let mask_for = |rule: Rule, child: bool| -> VertexMask {
        match rule {
            Rule::Smooth | Rule::Dart => VertexMask::smooth(nf),
            Rule::Crease => VertexMask::crease(&mut (0..ne).map(|i| {
                is_sharp(if child {
                    a.child_sharpness(i)
                } else {
                    a.sharpness(i)
                })
            })),
            Rule::Corner => VertexMask::corner(),
        }
    };
    let pmask = mask_for(prule, false);
    if matches!(prule, Rule::Smooth | Rule::Dart) {
        return pmask;
    }
    let cvs = decrement(vs);
    let csharp = (0..ne).filter(|&i| is_sharp(a.child_sharpness(i))).count();
    let crule = rule_of(cvs, csharp);
    if crule == prule {
        return pmask;
    }
    let cmask = mask_for(crule, true);
    let w = fractional_weight(
        creasing,
        vs,
        cvs,
        (0..ne).map(|i| (a.sharpness(i), a.child_sharpness(i))),
    ) as f64;
    let p = pmask.scaled(w);
    let c = cmask.scaled(1.0 - w);
    let mut m = VertexMask {
        vertex: p.vertex + c.vertex,
        each_edge: p.each_edge + c.each_edge,
        each_face: p.each_face + c.each_face,
        extra: [(0, 0.0); 4],
    };
    m.extra[0] = p.extra[0];
    m.extra[1] = p.extra[1];
    m.extra[2] = c.extra[0];
    m.extra[3] = c.extra[1];
    m
}

/// An edge-point mask: weights of the two ends and of each face centroid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeMask {
    /// Weight of each end vertex.
    pub end: f64,
    /// Weight of face `k`'s centroid is `face[min(k, 1)]` when the edge has
    /// two faces (`face[0]` for every face otherwise).
    pub face: [f64; 2],
}

/// The edge-point mask of an edge of sharpness `s` with `faces` faces whose
/// halves decay to `halves`; `triangles` tells which of the (first two)
/// faces are triangles, for [`FeatureOptions::smooth_triangles`].
pub fn edge_mask(
    opts: &FeatureOptions,
    s: f32,
    halves: [f32; 2],
    faces: usize,
    triangles: [bool; 2],
) -> EdgeMask {
    let smooth = || {
        if opts.smooth_triangles && faces == 2 && (triangles[0] || triangles[1]) {
            let w = |t: bool| if t { 0.47 } else { 0.25 };
            let (f0, f1) = (w(triangles[0]), w(triangles[1]));
            let fw = 0.5 * (f0 + f1);
            EdgeMask {
                end: 0.5 * (1.0 - 2.0 * fw),
                face: [fw, fw],
            }
        } else {
            let fw = if faces == 2 {
                0.25
            } else {
                0.5 / faces.max(1) as f64
            };
            EdgeMask {
                end: 0.25,
                face: [fw, fw],
            }
        }
    };
    if !is_sharp(s) {
        return smooth();
    }
    if is_sharp(halves[0]) && is_sharp(halves[1]) {
        return EdgeMask {
            end: 0.5,
            face: [0.0, 0.0],
        };
    }
    let mut m = smooth();
    let pw = s as f64;
    let cw = 1.0 - pw;
    m.end = pw * 0.5 + cw * m.end;
    m.face = [m.face[0] * cw, m.face[1] * cw];
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decay_and_weights_follow_opensubdiv() {
        assert_eq!(decrement(2.5), 1.5);
        assert_eq!(decrement(0.7), 0.0);
        assert_eq!(decrement(12.0), INFINITE);
        // Chaikin: 3/4 of 2 plus 1/4 of the other (1), minus 1.
        let end = EndStats::of([2.0f32, 1.0, 0.0].into_iter());
        assert_eq!(decay_at(Creasing::Chaikin, 2.0, end), 0.75);
        assert_eq!(decay_at(Creasing::Uniform, 2.0, end), 1.0);
        // Uniform transition weight counts edges of sharpness <= 1.
        let w = fractional_weight(
            Creasing::Uniform,
            0.0,
            0.0,
            [(0.5f32, 0.0f32), (0.5, 0.0)].into_iter(),
        );
        assert_eq!(w, 0.5);
        assert_eq!(rule_of(0.0, 2), Rule::Crease);
        assert_eq!(rule_of(0.1, 0), Rule::Corner);
    }
}
