//! The part of the `ccss` command that other crates use: the OBJ front end
//! (the line reader of `io::mesh_in` with its OpenSubdiv tags, `io::tags`)
//! and the error type its messages come in. The binary (`main.rs`) uses
//! these modules from here; the fuzz targets of `fuzz/` read OBJ texts
//! through [`io::mesh_in::Mesh::parse`], the same code as `ccss`.

pub mod error;

/// The formats shared with other crates (the rest of the binary's formats
/// live in the binary's own `io` module).
pub mod io {
    pub mod mesh_in;
    pub mod tags;
}
