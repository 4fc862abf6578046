//! The demo solids, copied from the OpenSubdiv regression shapes in
//! `tests/data/osd/` (see its LICENSE-OpenSubdiv.txt): positions, face sizes
//! and indices as `MeshInput` wants them, and the crease tags.
//!
//! The coordinates are the files' decimals (1.414214 is not meant as sqrt 2).
#![allow(clippy::approx_constant)]

/// `catmark_pyramid.obj`: 5 vertices, 5 faces (a square base and four triangles; valences 3 and 4).
pub const PYRAMID_POSITIONS: [f64; 15] = [
    0.0, 0.0, 2.0, 0.0, -2.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0, 0.0, -2.0, 0.0, 0.0,
];
/// Face sizes of `catmark_pyramid.obj`.
pub const PYRAMID_SIZES: [u32; 5] = [3, 3, 3, 3, 4];
/// Face corners of `catmark_pyramid.obj`.
pub const PYRAMID_INDICES: [u32; 16] = [0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 4, 3, 2, 1];

/// `catmark_cube_creases1.obj`: 8 vertices, 6 faces.
pub const CREASED_CUBE_POSITIONS: [f64; 24] = [
    0.0, -1.414214, 1.0, 1.414214, 0.0, 1.0, -1.414214, 0.0, 1.0, 0.0, 1.414214, 1.0, -1.414214,
    0.0, -1.0, 0.0, 1.414214, -1.0, 0.0, -1.414214, -1.0, 1.414214, 0.0, -1.0,
];
/// Face sizes of `catmark_cube_creases1.obj`.
pub const CREASED_CUBE_SIZES: [u32; 6] = [4, 4, 4, 4, 4, 4];
/// Face corners of `catmark_cube_creases1.obj`.
pub const CREASED_CUBE_INDICES: [u32; 24] = [
    0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4,
];
/// Crease vertex pairs of `catmark_cube_creases1.obj`.
pub const CREASED_CUBE_CREASE_VERTICES: [u32; 24] = [
    0, 1, 1, 3, 3, 2, 2, 0, 4, 5, 5, 7, 7, 6, 6, 4, 0, 6, 1, 7, 2, 4, 3, 5,
];
/// Crease sharpness of `catmark_cube_creases1.obj`, one per pair.
pub const CREASED_CUBE_CREASE_SHARPNESS: [f32; 12] =
    [5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 0.1];
