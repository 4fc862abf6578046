//! The one error type of `ccss-core`.
//!
//! Every fallible operation returns [`Error`]. Variants name the offending
//! element (face, vertex, edge given by its two vertices) so that a caller can
//! point a user at the exact place in the input.

use core::fmt;

/// What went wrong, and where.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The mesh has no vertices or no faces.
    EmptyMesh,
    /// The face-size array and the index array disagree in length.
    IndexCountMismatch {
        /// Sum of the face sizes.
        expected: usize,
        /// Length of the index array.
        got: usize,
    },
    /// A face refers to a vertex index that does not exist.
    IndexOutOfRange {
        /// Face index.
        face: u32,
        /// The bad vertex index.
        vertex: u32,
    },
    /// A face has fewer than 3 vertices.
    FaceTooSmall {
        /// Face index.
        face: u32,
        /// Its number of vertices.
        size: u32,
    },
    /// A face has more vertices than [`crate::config::MAX_VALENCE`] allows (after one
    /// refinement step its centre becomes a vertex of that valence).
    FaceTooLarge {
        /// Face index.
        face: u32,
        /// Its number of vertices.
        size: u32,
    },
    /// A face uses the same vertex twice.
    RepeatedVertex {
        /// Face index.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// A vertex coordinate is NaN or infinite.
    NonFiniteCoordinate {
        /// Vertex index.
        vertex: u32,
    },
    /// An edge is used by more than two faces.
    NonManifoldEdge {
        /// First end of the edge.
        v0: u32,
        /// Second end of the edge.
        v1: u32,
    },
    /// Two faces traverse a shared edge in the same direction.
    InconsistentOrientation {
        /// First end of the edge.
        v0: u32,
        /// Second end of the edge.
        v1: u32,
    },
    /// The faces around a vertex do not form a single fan (e.g. two cones
    /// touching at their tips).
    NonManifoldVertex {
        /// Vertex index.
        vertex: u32,
    },
    /// A vertex is not used by any face.
    UnusedVertex {
        /// Vertex index.
        vertex: u32,
    },
    /// An edge has only one face. Boundaries are not supported yet.
    BoundaryEdge {
        /// First end of the edge.
        v0: u32,
        /// Second end of the edge.
        v1: u32,
    },
    /// A vertex valence is outside `3..=MAX_VALENCE`.
    UnsupportedValence {
        /// Vertex index.
        vertex: u32,
        /// Its valence.
        valence: u32,
    },
    /// A caller buffer is too small; `required` is the size needed in the
    /// unit of that buffer (bytes for memory arenas, elements for outputs).
    BufferTooSmall {
        /// Required size.
        required: usize,
    },
    /// A memory block is not aligned to 8 bytes. Core itself never returns
    /// it (its builders take `&mut [u64]`, see [`crate::mem`]); the C ABI
    /// does, for a `void*` block.
    Misaligned,
    /// A face index is out of range.
    FaceOutOfRange {
        /// The bad face index.
        face: u32,
    },
    /// A sub-face index is out of range for that face.
    SubFaceOutOfRange {
        /// Face index.
        face: u32,
        /// The bad sub-face index.
        sub: u32,
    },
    /// A parameter is NaN or outside `[0, 1]`.
    ParameterOutOfRange,
    /// No eigen table was built for this valence.
    MissingTable {
        /// The valence.
        valence: u32,
    },
    /// The eigen decomposition of the subdivision matrix failed its own
    /// reconstruction check (should not happen for valid weights).
    TableBuildFailed {
        /// The valence.
        valence: u32,
    },
    /// An argument is invalid (message names it).
    InvalidArgument(&'static str),
    /// A crease tag names two vertices that no edge joins.
    NotAnEdge {
        /// First vertex.
        v0: u32,
        /// Second vertex.
        v1: u32,
    },
    /// A crease (`v0 != v1`) or corner (`v0 == v1`) sharpness is NaN or
    /// negative.
    InvalidSharpness {
        /// First vertex.
        v0: u32,
        /// Second vertex (equal to `v0` for a corner).
        v1: u32,
    },
    /// A tag names a vertex that does not exist.
    VertexOutOfRange {
        /// The bad vertex index.
        vertex: u32,
    },
    /// The face is a hole: it has no surface.
    HoleFace {
        /// The face.
        face: u32,
    },
    /// A face's neighbourhood exceeds the fixed capacity of local
    /// refinement (valences above `MAX_VALENCE`, or an edge with very many
    /// faces).
    NeighbourhoodTooLarge {
        /// The face.
        face: u32,
    },
    /// The mesh does not bound a solid (voxelization, flooding and
    /// integral properties need a closed, oriented, manifold surface).
    NotClosedSolid(SolidDefect),

    /// An iterative solve did not reach its tolerance within its
    /// iteration limit (interpolation: raise the limit or the tolerance).
    NotConverged {
        /// Iterations done.
        iterations: u32,
    },
    /// An interpolation requirement contradicts the interpolation
    /// conditions or the requirements before it.
    ConflictingRequirement {
        /// Index of the requirement.
        requirement: u32,
    },
    /// Vertex-rule weights rejected for this valence.
    InvalidWeights {
        /// The valence.
        valence: u32,
        /// What is wrong with them.
        problem: WeightsProblem,
    },
    /// An adaptive computation needed more work than its documented cap
    /// (a pathological input, e.g. a needle-thin or near-degenerate surface):
    /// it stopped instead of running for minutes.
    WorkLimitExceeded {
        /// The cap that was reached.
        limit: u64,
        /// What was counted (e.g. "cells of the voxel certification walk").
        what: &'static str,
    },
    /// The coordinates' magnitude or dynamic range is beyond what the
    /// computation can certify in `f64` (a bound or a result would overflow,
    /// underflow or be dominated by rounding).
    CoordinateRange(&'static str),
    /// Boolean: the two surfaces meet at an angle too close to tangential
    /// for the requested tolerance (the result's boundary is ill-conditioned
    /// there): triangle `triangle_a` of solid A (on base face `face_a`)
    /// against triangle `triangle_b` of solid B (base face `face_b`; the
    /// faces are `u32::MAX` when unknown).
    NearTangential {
        /// Base face of solid A (or `u32::MAX`).
        face_a: u32,
        /// Base face of solid B (or `u32::MAX`).
        face_b: u32,
        /// Triangle of A's tessellation.
        triangle_a: u32,
        /// Triangle of B's tessellation.
        triangle_b: u32,
    },
    /// Boolean: the tessellations of the two solids touch in a degenerate
    /// configuration (a vertex exactly on the other's triangle, coplanar
    /// triangles, or a closed intersection loop inside one triangle):
    /// `what` says which; a smaller tolerance or a tiny shift resolves it.
    DegenerateContact {
        /// Triangle of A's tessellation.
        triangle_a: u32,
        /// Triangle of B's tessellation.
        triangle_b: u32,
        /// The configuration.
        what: &'static str,
    },
}

/// Why a set of vertex-rule weights was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WeightsProblem {
    /// A weight is NaN or infinite.
    NonFinite,
    /// `alpha + beta + gamma` differs from 1 by more than
    /// [`crate::mesh::weights::SUM_TOLERANCE`].
    SumNotOne,
    /// A weight is negative.
    Negative,
    /// Valence 4 must keep the standard rule: regular patches are bicubic
    /// B-splines.
    RegularValence,
    /// The valence is outside `3..=MAX_VALENCE`.
    ValenceOutOfRange,
}

impl fmt::Display for WeightsProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            WeightsProblem::NonFinite => "a weight is NaN or infinite",
            WeightsProblem::SumNotOne => "alpha + beta + gamma is not 1",
            WeightsProblem::Negative => "a weight is negative",
            WeightsProblem::RegularValence => {
                "valence 4 must keep the standard rule (regular patches are bicubic B-splines)"
            }
            WeightsProblem::ValenceOutOfRange => {
                return write!(f, "valence outside 3..={}", crate::config::MAX_VALENCE);
            }
        })
    }
}

/// Why a mesh is not a closed solid ([`Error::NotClosedSolid`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidDefect {
    /// An edge with one face: the mesh has a boundary.
    BoundaryEdge {
        /// First end of the edge.
        v0: u32,
        /// Second end of the edge.
        v1: u32,
    },
    /// A face tagged as a hole (or a hole face of boundary mode `none`).
    HoleFace {
        /// The face.
        face: u32,
    },
    /// An edge with more than two faces, or two faces running along it in
    /// the same direction.
    NonManifoldEdge {
        /// First end of the edge.
        v0: u32,
        /// Second end of the edge.
        v1: u32,
    },
    /// A vertex whose faces do not form one closed fan.
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use Error::*;
        match *self {
            EmptyMesh => write!(f, "mesh has no vertices or no faces"),
            IndexCountMismatch { expected, got } => write!(
                f,
                "face sizes add up to {expected} indices but {got} were given"
            ),
            IndexOutOfRange { face, vertex } => {
                write!(f, "face {face} uses vertex {vertex}, which does not exist")
            }
            FaceTooSmall { face, size } => write!(f, "face {face} has only {size} vertices"),
            FaceTooLarge { face, size } => write!(
                f,
                "face {face} has {size} vertices, more than the supported maximum {}",
                crate::config::MAX_VALENCE
            ),
            RepeatedVertex { face, vertex } => {
                write!(f, "face {face} uses vertex {vertex} more than once")
            }
            NonFiniteCoordinate { vertex } => {
                write!(f, "vertex {vertex} has a NaN or infinite coordinate")
            }
            NonManifoldEdge { v0, v1 } => {
                write!(f, "edge {v0}-{v1} is shared by more than two faces")
            }
            InconsistentOrientation { v0, v1 } => {
                write!(f, "faces on edge {v0}-{v1} are inconsistently oriented")
            }
            NonManifoldVertex { vertex } => write!(f, "vertex {vertex} is non-manifold"),
            UnusedVertex { vertex } => write!(f, "vertex {vertex} is not used by any face"),
            BoundaryEdge { v0, v1 } => write!(
                f,
                "edge {v0}-{v1} is a boundary edge; open meshes (boundaries) are not supported yet"
            ),
            UnsupportedValence { vertex, valence } => write!(
                f,
                "vertex {vertex} has valence {valence}; supported valences are 3..={}",
                crate::config::MAX_VALENCE
            ),
            BufferTooSmall { required } => {
                write!(f, "buffer too small: {required} required")
            }
            Misaligned => write!(f, "memory buffer is not 8-byte aligned"),
            FaceOutOfRange { face } => write!(f, "face {face} does not exist"),
            SubFaceOutOfRange { face, sub } => {
                write!(f, "face {face} has no sub-face {sub}")
            }
            ParameterOutOfRange => write!(f, "parameter (u, v) is NaN or outside [0, 1]"),
            NotConverged { iterations } => write!(
                f,
                "the solve did not converge within {iterations} iterations"
            ),
            ConflictingRequirement { requirement } => write!(
                f,
                "requirement {requirement} conflicts with the interpolation conditions or an earlier requirement"
            ),
            MissingTable { valence } => write!(f, "no eigen table for valence {valence}"),
            TableBuildFailed { valence } => {
                write!(
                    f,
                    "eigen decomposition for valence {valence} failed its check"
                )
            }
            InvalidArgument(what) => write!(f, "invalid argument: {what}"),
            NotAnEdge { v0, v1 } => {
                write!(
                    f,
                    "crease tag on vertices {v0} and {v1}, which no edge joins"
                )
            }
            InvalidSharpness { v0, v1 } if v0 == v1 => {
                write!(f, "corner sharpness of vertex {v0} is NaN or negative")
            }
            InvalidSharpness { v0, v1 } => {
                write!(f, "crease sharpness of edge {v0}-{v1} is NaN or negative")
            }
            VertexOutOfRange { vertex } => write!(f, "vertex {vertex} does not exist"),
            HoleFace { face } => write!(f, "face {face} is a hole (it has no surface)"),
            NotClosedSolid(d) => {
                write!(f, "not a closed solid: ")?;
                match d {
                    SolidDefect::BoundaryEdge { v0, v1 } => {
                        write!(f, "edge {v0}-{v1} is a boundary edge (the mesh is open)")
                    }
                    SolidDefect::HoleFace { face } => write!(f, "face {face} is a hole"),
                    SolidDefect::NonManifoldEdge { v0, v1 } => write!(
                        f,
                        "edge {v0}-{v1} has more than two faces or inconsistently oriented faces"
                    ),
                    SolidDefect::NonManifoldVertex { vertex } => {
                        write!(f, "vertex {vertex} is non-manifold")
                    }
                }
            }
            NeighbourhoodTooLarge { face } => write!(
                f,
                "the neighbourhood of face {face} is too large for local refinement \
                 (valence above {} or an edge with very many faces)",
                crate::config::MAX_VALENCE
            ),
            InvalidWeights { valence, problem } => {
                write!(f, "weights for valence {valence} rejected: {problem}")
            }
            WorkLimitExceeded { limit, what } => {
                write!(f, "work limit exceeded: more than {limit} {what}")
            }
            CoordinateRange(what) => write!(f, "coordinates out of the certifiable range: {what}"),
            NearTangential {
                face_a,
                face_b,
                triangle_a,
                triangle_b,
            } => write!(
                f,
                "the surfaces meet nearly tangentially (face {face_a} of A, face {face_b} of B; \
                 triangles {triangle_a} and {triangle_b}): the result is ill-conditioned there"
            ),
            DegenerateContact {
                triangle_a,
                triangle_b,
                what,
            } => write!(
                f,
                "degenerate contact between triangle {triangle_a} of A and triangle {triangle_b} of B: {what}"
            ),
        }
    }
}
