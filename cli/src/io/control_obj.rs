//! Writing a refined control mesh as OBJ: a comment line, `v x y z` per
//! vertex (shortest round-trip decimal) and `f a b c ...` per face
//! (1-based), no normals.

use crate::error::{CliError, CliResult};
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes the mesh `pos` (x y z per vertex), `sizes` and `idx` to `path`.
pub fn write_obj(path: &Path, pos: &[f64], sizes: &[u32], idx: &[u32]) -> CliResult {
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
        w.flush()
    })();
    r.map_err(werr)
}
