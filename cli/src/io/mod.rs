//! File and stream formats: what `ccss` reads (OBJ meshes, query lines,
//! points files, weights files) and writes (number formatting, OBJ/STL/PLY
//! meshes, binvox, voxel runs, PNG previews).

pub mod binvox;
pub mod control_obj;
pub mod mesh_out;
pub mod numfmt;
pub mod png;
pub mod points;
pub mod preview;
pub mod query;
pub mod slab_bits;
pub mod stdin_rows;
pub mod voxel_runs;
pub mod weights_file;

// The OBJ reader and its tags live in the library (`lib.rs`), shared with
// the fuzz targets.
pub use ccss_cli::io::mesh_in;
