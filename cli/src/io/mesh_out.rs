//! Writing a tessellation: OBJ (text), STL (binary) or PLY (binary little
//! endian), chosen by the file extension.
//!
//! * OBJ: `v x y z` and `vn nx ny nz` per vertex (shortest round-trip
//!   decimal), then `f a//a b//b ...` per polygon or triangle (1-based).
//! * STL: binary; an 80-byte header, the triangle count, then per triangle
//!   its unit facet normal (from the triangle's vertices) and three vertices
//!   as `f32`, and a zero attribute word. STL holds triangles only.
//! * PLY: `binary_little_endian 1.0`; vertex properties `double x y z nx ny
//!   nz`; faces as `list uchar uint vertex_indices` (or `list uint uint`
//!   when a polygon has more than 255 vertices).

use crate::error::{CliError, CliResult};
use std::io::{BufWriter, Write};
use std::path::Path;

/// Output file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Binary STL.
    Stl,
    /// Binary PLY.
    Ply,
}

impl Format {
    /// The format of a path, from its extension (case-insensitive).
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "stl" => Some(Format::Stl),
            "ply" => Some(Format::Ply),
            _ => None,
        }
    }
}

/// A mesh to write: vertices with normals, faces as sizes + indices.
pub struct MeshOut<'a> {
    /// x y z per vertex.
    pub positions: &'a [f64],
    /// Unit normal per vertex (x y z).
    pub normals: &'a [f64],
    /// Vertex count of each face.
    pub face_sizes: &'a [u32],
    /// Indices of all faces, concatenated.
    pub indices: &'a [u32],
}

fn werr(path: &Path, e: std::io::Error) -> CliError {
    CliError::failure(format!("cannot write {}: {e}", path.display()))
}

/// Writes `m` to `path` in format `f` (STL needs triangles).
pub fn write(path: &Path, f: Format, m: &MeshOut) -> CliResult {
    let file = std::fs::File::create(path).map_err(|e| werr(path, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let r = match f {
        Format::Obj => write_obj(&mut w, m),
        Format::Stl => write_stl(&mut w, m),
        Format::Ply => write_ply(&mut w, m),
    };
    r.and_then(|_| w.flush()).map_err(|e| werr(path, e))
}

fn faces<'a>(m: &'a MeshOut) -> impl Iterator<Item = &'a [u32]> + 'a {
    let mut o = 0usize;
    m.face_sizes.iter().map(move |&s| {
        let f = &m.indices[o..o + s as usize];
        o += s as usize;
        f
    })
}

fn write_obj(w: &mut impl Write, m: &MeshOut) -> std::io::Result<()> {
    writeln!(w, "# ccss tessellate: exact limit-surface points")?;
    for p in m.positions.chunks_exact(3) {
        writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
    }
    for n in m.normals.chunks_exact(3) {
        writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
    }
    let mut line = String::with_capacity(64);
    for f in faces(m) {
        line.clear();
        line.push('f');
        for &v in f {
            use std::fmt::Write as _;
            let _ = write!(line, " {0}//{0}", v + 1);
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

fn write_stl(w: &mut impl Write, m: &MeshOut) -> std::io::Result<()> {
    let mut header = [0u8; 80];
    let text = b"ccss tessellate: binary STL of exact limit-surface points";
    header[..text.len()].copy_from_slice(text);
    w.write_all(&header)?;
    let n = m.face_sizes.len() as u32;
    w.write_all(&n.to_le_bytes())?;
    let p = |v: u32| {
        let i = 3 * v as usize;
        [m.positions[i], m.positions[i + 1], m.positions[i + 2]]
    };
    let mut rec = [0u8; 50];
    for f in faces(m) {
        let (a, b, c) = (p(f[0]), p(f[1]), p(f[2]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let mut nn = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let l = (nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]).sqrt();
        if l > 0.0 {
            nn = nn.map(|x| x / l);
        }
        let vals = [nn, a, b, c];
        for (k, x) in vals.iter().flatten().enumerate() {
            rec[4 * k..4 * k + 4].copy_from_slice(&(*x as f32).to_le_bytes());
        }
        rec[48] = 0;
        rec[49] = 0;
        w.write_all(&rec)?;
    }
    Ok(())
}

fn write_ply(w: &mut impl Write, m: &MeshOut) -> std::io::Result<()> {
    let nv = m.positions.len() / 3;
    let wide = m.face_sizes.iter().any(|&s| s > 255);
    let count_type = if wide { "uint" } else { "uchar" };
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment ccss tessellate: exact limit-surface points\n\
         element vertex {nv}\nproperty double x\nproperty double y\nproperty double z\n\
         property double nx\nproperty double ny\nproperty double nz\n\
         element face {}\nproperty list {count_type} uint vertex_indices\nend_header\n",
        m.face_sizes.len()
    )?;
    let mut buf = Vec::with_capacity(48);
    for v in 0..nv {
        buf.clear();
        for x in m.positions[3 * v..3 * v + 3]
            .iter()
            .chain(&m.normals[3 * v..3 * v + 3])
        {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    for f in faces(m) {
        buf.clear();
        if wide {
            buf.extend_from_slice(&(f.len() as u32).to_le_bytes());
        } else {
            buf.push(f.len() as u8);
        }
        for &i in f {
            buf.extend_from_slice(&i.to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> (Vec<f64>, Vec<f64>, Vec<u32>, Vec<u32>) {
        let p = vec![0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.];
        let n = vec![0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1.];
        (p, n, vec![3; 4], vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2])
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::of(Path::new("a.OBJ")), Some(Format::Obj));
        assert_eq!(Format::of(Path::new("a.stl")), Some(Format::Stl));
        assert_eq!(Format::of(Path::new("x/y.ply")), Some(Format::Ply));
        assert_eq!(Format::of(Path::new("a.off")), None);
        assert_eq!(Format::of(Path::new("a")), None);
    }

    #[test]
    fn stl_and_ply_sizes() {
        let (p, n, s, i) = tetra();
        let m = MeshOut {
            positions: &p,
            normals: &n,
            face_sizes: &s,
            indices: &i,
        };
        let mut stl = Vec::new();
        write_stl(&mut stl, &m).unwrap();
        assert_eq!(stl.len(), 84 + 50 * 4);
        assert_eq!(u32::from_le_bytes(stl[80..84].try_into().unwrap()), 4);
        // First facet normal: (0,0,-1) for triangle 0 2 1.
        let nz = f32::from_le_bytes(stl[92..96].try_into().unwrap());
        assert_eq!(nz, -1.0);
        let mut ply = Vec::new();
        write_ply(&mut ply, &m).unwrap();
        let h = b"end_header\n";
        let at = ply.windows(h.len()).position(|w| w == h).unwrap() + h.len();
        assert_eq!(ply.len() - at, 4 * 48 + 4 * 13);
        let mut obj = Vec::new();
        write_obj(&mut obj, &m).unwrap();
        let text = String::from_utf8(obj).unwrap();
        assert!(text.contains("\nf 1//1 3//3 2//2\n"), "{text}");
        assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 4);
    }
}
