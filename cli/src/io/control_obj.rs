//! Writing a refined control mesh as OBJ: a comment line, `v x y z` per
//! vertex (shortest round-trip decimal) and `f a b c ...` per face
//! (1-based), no normals; optionally OpenSubdiv's `t` tags (sharpness,
//! holes, scheme options) of a mesh with features.

use crate::error::{CliError, CliResult};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use std::io::{BufWriter, Write};
use std::path::Path;

/// The features of a refined level, written as OpenSubdiv `t` lines
/// (0-based vertex and face numbers, as OpenSubdiv's shape files).
#[derive(Debug, Default)]
pub struct LevelTags {
    /// Two vertices per sharpened edge.
    pub crease_vertices: Vec<u32>,
    /// Sharpness per sharpened edge.
    pub crease_sharpness: Vec<f32>,
    /// Sharp vertices.
    pub corner_vertices: Vec<u32>,
    /// Their sharpness.
    pub corner_sharpness: Vec<f32>,
    /// Hole faces.
    pub holes: Vec<u32>,
    /// Boundary and crease options.
    pub options: FeatureOptions,
}

impl LevelTags {
    fn write(&self, w: &mut impl Write) -> std::io::Result<()> {
        let o = &self.options;
        // OpenSubdiv's shape-file numbering (RenderMan's).
        let boundary = match o.boundary {
            Boundary::None => 0,
            Boundary::EdgeAndCorner => 1,
            Boundary::EdgeOnly => 2,
        };
        writeln!(w, "t interpolateboundary 1/0/0 {boundary}")?;
        let method = match o.creasing {
            Creasing::Uniform => "normal",
            Creasing::Chaikin => "chaikin",
        };
        writeln!(w, "t creasemethod 0/0/1 {method}")?;
        for (p, s) in self
            .crease_vertices
            .chunks_exact(2)
            .zip(&self.crease_sharpness)
        {
            writeln!(w, "t crease 2/1/0 {} {} {s}", p[0], p[1])?;
        }
        for (v, s) in self.corner_vertices.iter().zip(&self.corner_sharpness) {
            writeln!(w, "t corner 1/1/0 {v} {s}")?;
        }
        for f in &self.holes {
            writeln!(w, "t hole 1/0/0 {f}")?;
        }
        Ok(())
    }
}

/// Writes the mesh `pos` (x y z per vertex), `sizes` and `idx` to `path`.
pub fn write_obj(path: &Path, pos: &[f64], sizes: &[u32], idx: &[u32]) -> CliResult {
    write_mesh(path, pos, sizes, idx, None)
}

/// As [`write_obj`], followed by the `t` lines of `tags`.
pub fn write_obj_tagged(
    path: &Path,
    pos: &[f64],
    sizes: &[u32],
    idx: &[u32],
    tags: &LevelTags,
) -> CliResult {
    write_mesh(path, pos, sizes, idx, Some(tags))
}

fn write_mesh(
    path: &Path,
    pos: &[f64],
    sizes: &[u32],
    idx: &[u32],
    tags: Option<&LevelTags>,
) -> CliResult {
    let werr =
        |e: std::io::Error| CliError::failure(format!("cannot write {}: {e}", path.display()));
    let file = std::fs::File::create(path).map_err(werr)?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let r = (|| -> std::io::Result<()> {
        writeln!(w, "# ccss refine: refined control mesh")?;
        for p in pos.chunks_exact(3) {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
        }
        let mut o = 0usize;
        let mut line = String::with_capacity(64);
        for &s in sizes {
            use std::fmt::Write as _;
            line.clear();
            line.push('f');
            for &v in &idx[o..o + s as usize] {
                let _ = write!(line, " {}", v + 1);
            }
            line.push('\n');
            o += s as usize;
            w.write_all(line.as_bytes())?;
        }
        if let Some(t) = tags {
            t.write(&mut w)?;
        }
        w.flush()
    })();
    r.map_err(werr)
}
