//! Whether a feature mesh bounds a solid: the voxelizer's flooding and the
//! divergence theorem of [`super::measure`] need a closed, consistently
//! oriented, manifold limit surface. A mesh is such a solid when every
//! base edge has exactly two faces that run along it in opposite
//! directions, every vertex has one closed fan of faces, and no face is a
//! hole (holes, including those of boundary mode `none`, leave openings).
//! Creases, corners and darts keep the surface closed (the limit surface
//! of a closed mesh is continuous across them), so they are allowed.

use crate::error::{Error, SolidDefect};
use crate::mesh::features::FeatureMesh;

/// Checks that `fm` bounds a solid (module docs); the error names the
/// first offending edge, face or vertex (boundary edges first).
pub fn check_closed_solid(fm: &FeatureMesh) -> Result<(), Error> {
    let adj = &fm.base;
    let edge = |e: usize| {
        let v = &adj.edge_vert[2 * e..2 * e + 2];
        (v[0], v[1])
    };
    for e in 0..adj.num_edges() {
        if adj.edge_faces(e).len() < 2 {
            let (v0, v1) = edge(e);
            return Err(Error::NotClosedSolid(SolidDefect::BoundaryEdge { v0, v1 }));
        }
    }
    for e in 0..adj.num_edges() {
        if adj.edge_nonmanifold(e) {
            let (v0, v1) = edge(e);
            return Err(Error::NotClosedSolid(SolidDefect::NonManifoldEdge {
                v0,
                v1,
            }));
        }
    }
    for v in 0..adj.num_vertices() {
        if !adj.vertex_faces(v).is_empty() && adj.vertex_nonmanifold(v) {
            return Err(Error::NotClosedSolid(SolidDefect::NonManifoldVertex {
                vertex: v as u32,
            }));
        }
    }
    for f in 0..fm.num_faces() {
        if fm.hole[fm.child_face(f, 0)] != 0 {
            return Err(Error::NotClosedSolid(SolidDefect::HoleFace {
                face: f as u32,
            }));
        }
    }
    Ok(())
}
