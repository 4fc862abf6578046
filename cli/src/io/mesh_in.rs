//! Loading a polygon mesh from an OBJ file.
//!
//! The file is parsed by `tobj` (`single_index: false`, `triangulate:
//! false`, points and lines ignored, coordinates as `f64`), and all its
//! models (`o`/`g` groups, material splits) are merged into one mesh.
//!
//! Numbering: `tobj` renumbers the vertices of each model in order of first
//! use, which would make error messages such as "edge 4-9 is a boundary edge"
//! name vertices the user cannot find. So the file text is also scanned here
//! (cheaply: only the first number of each `f` token) and the vertices are
//! renumbered back to file order: mesh vertex `i` is the `i`-th *used* `v`
//! line, and error messages translate vertex numbers to 0-based `v`-line
//! numbers (OBJ index minus one). Faces keep their file order, so face `f`
//! is the `f`-th `f` line (0-based). Vertices shared between models are
//! merged through their common OBJ index.
//!
//! The scan also parses OpenSubdiv's `t` tag lines (creases, corners,
//! holes, boundary and crease options; [`crate::io::tags`]): `ccss eval`
//! evaluates the surface they define; the other verbs do not support them
//! yet and say so once on stderr.

use crate::error::{CliError, CliResult};
use crate::io::tags::Tags;
use ccss_core::{Error, MeshInput, SolidDefect};
use std::collections::HashMap;
use std::path::Path;

/// A polygon mesh ready for `ccss_core::Topology::build`.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// The path as the user gave it (used as the prefix of messages).
    pub name: String,
    /// x y z per vertex.
    pub positions: Vec<f64>,
    /// Number of vertices of each face, in file order.
    pub face_sizes: Vec<u32>,
    /// Vertex indices of all faces, concatenated.
    pub indices: Vec<u32>,
    /// 0-based OBJ `v`-line number of each mesh vertex, when the scan could
    /// match `tobj`'s result (always, for files `tobj` reads correctly).
    pub obj_vertex: Option<Vec<u32>>,
    /// Number of `v` lines in the file (used or not).
    pub obj_vertex_lines: usize,
    /// Number of OpenSubdiv `t` tag lines.
    pub tag_lines: usize,
    /// The parsed tags (vertex numbers are 0-based `v`-line numbers).
    pub tags: Tags,
}

/// What the text scan found.
#[derive(Default)]
struct Scan {
    v_lines: usize,
    t_lines: usize,
    tags: Tags,
    sizes: Vec<u32>,
    refs: Vec<u32>,
    /// First problem found, with its 1-based line number.
    problem: Option<(usize, String)>,
}

/// Scans the OBJ text for `v`, `f` and `t` lines (see the module docs).
fn scan(text: &str) -> Scan {
    let mut s = Scan::default();
    for (i, line) in text.lines().enumerate() {
        let mut tok = line.split_whitespace();
        match tok.next() {
            Some("v") => s.v_lines += 1,
            Some("t") => {
                s.t_lines += 1;
                if let Err(what) = s.tags.parse_line(tok, i + 1) {
                    s.problem.get_or_insert((i + 1, what));
                }
            }
            Some("f") => {
                let start = s.refs.len();
                for t in tok {
                    let first = t.split('/').next().unwrap_or("");
                    let r = first.parse::<i64>().ok().and_then(|k| {
                        let n = s.v_lines as i64;
                        let z = if k > 0 { k - 1 } else { n + k };
                        (k != 0 && (0..n).contains(&z)).then_some(z as u32)
                    });
                    match r {
                        Some(z) => s.refs.push(z),
                        None => {
                            s.problem.get_or_insert((
                                i + 1,
                                format!("bad face vertex '{t}' (no such vertex)"),
                            ));
                            break;
                        }
                    }
                }
                let n = s.refs.len() - start;
                if n < 3 && s.problem.is_none() {
                    s.problem =
                        Some((i + 1, format!("face with {n} vertices (at least 3 needed)")));
                }
                s.sizes.push(n as u32);
            }
            _ => {}
        }
    }
    s
}

/// The merged `tobj` result in `tobj`'s own numbering (models concatenated).
struct Loaded {
    positions: Vec<f64>,
    sizes: Vec<u32>,
    indices: Vec<u32>,
}

fn load_tobj(text: &str, name: &str) -> CliResult<Loaded> {
    // The update covers fields of optional tobj features (`merging`,
    // `reordering`) that another crate of the build may enable.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // Materials are irrelevant: never open .mtl files.
    let (models, _) =
        tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Ok(Default::default()))
            .map_err(|e| CliError::input(format!("{name}: cannot parse OBJ: {e}")))?;
    let mut out = Loaded {
        positions: Vec::new(),
        sizes: Vec::new(),
        indices: Vec::new(),
    };
    for m in &models {
        let mesh = &m.mesh;
        let base = (out.positions.len() / 3) as u32;
        // f64 thanks to tobj's `use_f64` feature (see Cargo.toml).
        out.positions.extend_from_slice(&mesh.positions);
        if mesh.face_arities.is_empty() {
            // tobj's convention: no arities means all faces are triangles.
            out.sizes
                .extend(std::iter::repeat_n(3, mesh.indices.len() / 3));
        } else {
            out.sizes.extend_from_slice(&mesh.face_arities);
        }
        out.indices.extend(mesh.indices.iter().map(|&i| i + base));
    }
    Ok(out)
}

/// Renumbers `t` (tobj numbering) to file order with the scan, if they match.
fn renumber(t: &Loaded, s: &Scan) -> Option<(Vec<f64>, Vec<u32>, Vec<u32>)> {
    if t.sizes != s.sizes || t.indices.len() != s.refs.len() {
        return None;
    }
    // tobj vertex -> OBJ vertex; must be a function.
    let mut t2o = vec![u32::MAX; t.positions.len() / 3];
    for (&ti, &o) in t.indices.iter().zip(&s.refs) {
        let slot = t2o.get_mut(ti as usize)?;
        if *slot == u32::MAX {
            *slot = o;
        } else if *slot != o {
            return None;
        }
    }
    // Used OBJ vertices in file order.
    let mut rank = vec![u32::MAX; s.v_lines];
    for &o in &s.refs {
        rank[o as usize] = 0;
    }
    let mut obj_vertex = Vec::new();
    for (o, r) in rank.iter_mut().enumerate() {
        if *r == 0 {
            *r = obj_vertex.len() as u32;
            obj_vertex.push(o as u32);
        }
    }
    let mut positions = vec![0.0; 3 * obj_vertex.len()];
    for (ti, &o) in t2o.iter().enumerate() {
        if o != u32::MAX {
            let r = rank[o as usize] as usize;
            positions[3 * r..3 * r + 3].copy_from_slice(&t.positions[3 * ti..3 * ti + 3]);
        }
    }
    let indices = s.refs.iter().map(|&o| rank[o as usize]).collect();
    Some((positions, indices, obj_vertex))
}

/// Fallback merge when the scan does not match `tobj`: a vertex whose
/// position is bit-identical to one of an earlier vertex is merged into it.
fn merge_by_position(t: &Loaded) -> (Vec<f64>, Vec<u32>) {
    let mut seen: HashMap<[u64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut map = Vec::with_capacity(t.positions.len() / 3);
    for p in t.positions.chunks_exact(3) {
        let key = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        let next = (positions.len() / 3) as u32;
        let id = *seen.entry(key).or_insert_with(|| {
            positions.extend_from_slice(p);
            next
        });
        map.push(id);
    }
    let indices = t.indices.iter().map(|&i| map[i as usize]).collect();
    (positions, indices)
}

impl Mesh {
    /// Reads and parses `path` for a verb that does not support tags: a
    /// file with tags gets a warning on stderr. Unreadable or unparsable
    /// files are input errors (exit code 2); topology is not checked here.
    pub fn load(path: &Path) -> CliResult<Mesh> {
        let m = Mesh::load_with_tags(path)?;
        if m.tags.any() {
            eprintln!(
                "ccss: warning: {}: OpenSubdiv tags (creases, corners, holes, boundary options) \
                 ignored: this command evaluates the smooth Catmull-Clark surface; \
                 'ccss eval', 'tessellate', 'info' and 'refine' honour them",
                m.name
            );
        }
        Ok(m)
    }

    /// Reads and parses `path` with its tags (see [`crate::io::tags`]); tags
    /// that ccss ignores (hierarchical edits, face-varying options) get one
    /// warning each.
    pub fn load_with_tags(path: &Path) -> CliResult<Mesh> {
        let name = path.display().to_string();
        let text = std::fs::read(path)
            .map_err(|e| CliError::input(format!("{name}: cannot read: {e}")))?;
        let text = String::from_utf8(text)
            .map_err(|_| CliError::input(format!("{name}: not a text (UTF-8) OBJ file")))?;
        let s = scan(&text);
        if let Some((line, what)) = &s.problem {
            return Err(CliError::input(format!("{name}: line {line}: {what}")));
        }
        let t = load_tobj(&text, &name)?;
        if t.sizes.is_empty() {
            return Err(CliError::input(format!("{name}: no faces")));
        }
        for (tag, line) in &s.tags.ignored {
            eprintln!(
                "ccss: warning: {name}: line {line}: tag '{tag}' ignored (hierarchical edits \
                 and face-varying options are not supported, as in OpenSubdiv's Far)"
            );
        }
        let (positions, indices, obj_vertex) = match renumber(&t, &s) {
            Some((p, i, o)) => (p, i, Some(o)),
            None => {
                eprintln!(
                    "ccss: warning: {name}: could not match tobj's vertices to the file's 'v' lines; \
                     vertex numbers in messages follow tobj's loading order"
                );
                let (p, i) = merge_by_position(&t);
                (p, i, None)
            }
        };
        Ok(Mesh {
            name,
            positions,
            face_sizes: t.sizes,
            indices,
            obj_vertex,
            obj_vertex_lines: s.v_lines,
            tag_lines: s.t_lines,
            tags: s.tags,
        })
    }

    /// Number of (used) vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len() / 3
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_sizes.len()
    }

    /// The mesh as core input.
    pub fn input(&self) -> MeshInput<'_> {
        MeshInput {
            positions: &self.positions,
            face_sizes: &self.face_sizes,
            indices: &self.indices,
        }
    }

    /// 0-based OBJ `v`-line number of mesh vertex `v`.
    pub fn obj_vertex(&self, v: u32) -> u32 {
        match &self.obj_vertex {
            Some(map) => map.get(v as usize).copied().unwrap_or(v),
            None => v,
        }
    }

    /// A core error about this mesh as a CLI error: `<file>: <core text>`,
    /// with vertex numbers translated to 0-based `v`-line numbers. Exit code
    /// 1 (the file was read; the mesh is not supported).
    pub fn error(&self, e: Error) -> CliError {
        CliError::failure(format!("{}: {}", self.name, self.translate(e)))
    }

    /// `e` with its vertex numbers in file numbering.
    fn translate(&self, e: Error) -> Error {
        let m = |v: u32| self.obj_vertex(v);
        match e {
            Error::RepeatedVertex { face, vertex } => Error::RepeatedVertex {
                face,
                vertex: m(vertex),
            },
            Error::NonFiniteCoordinate { vertex } => {
                Error::NonFiniteCoordinate { vertex: m(vertex) }
            }
            Error::NonManifoldEdge { v0, v1 } => Error::NonManifoldEdge {
                v0: m(v0),
                v1: m(v1),
            },
            Error::InconsistentOrientation { v0, v1 } => Error::InconsistentOrientation {
                v0: m(v0),
                v1: m(v1),
            },
            Error::NonManifoldVertex { vertex } => Error::NonManifoldVertex { vertex: m(vertex) },
            Error::UnusedVertex { vertex } => Error::UnusedVertex { vertex: m(vertex) },
            Error::BoundaryEdge { v0, v1 } => Error::BoundaryEdge {
                v0: m(v0),
                v1: m(v1),
            },
            Error::UnsupportedValence { vertex, valence } => Error::UnsupportedValence {
                vertex: m(vertex),
                valence,
            },
            Error::NotClosedSolid(d) => Error::NotClosedSolid(match d {
                SolidDefect::BoundaryEdge { v0, v1 } => SolidDefect::BoundaryEdge {
                    v0: m(v0),
                    v1: m(v1),
                },
                SolidDefect::NonManifoldEdge { v0, v1 } => SolidDefect::NonManifoldEdge {
                    v0: m(v0),
                    v1: m(v1),
                },
                SolidDefect::NonManifoldVertex { vertex } => {
                    SolidDefect::NonManifoldVertex { vertex: m(vertex) }
                }
                SolidDefect::HoleFace { face } => SolidDefect::HoleFace { face },
            }),
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_str(text: &str) -> Mesh {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!("ccss-mesh-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("m{}.obj", N.fetch_add(1, Ordering::Relaxed)));
        std::fs::write(&p, text).unwrap();
        let m = Mesh::load(&p).unwrap();
        let _ = std::fs::remove_file(&p);
        m
    }

    #[test]
    fn file_order_and_groups() {
        // Two groups sharing vertices; first face uses v3 before v2.
        let m = load_str(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\nv 2 0 0\n\
             g a\nf 1 2 4/1 \ng b\nf 2 6 3\nf 2 3 -3\n",
        );
        assert_eq!(m.face_sizes, vec![3, 3, 3]);
        // v line 5 (9 9 9) is unused: vertices 0..4 are v lines 1,2,3,4,6.
        assert_eq!(m.obj_vertex.as_deref(), Some(&[0, 1, 2, 3, 5][..]));
        assert_eq!(m.indices, vec![0, 1, 3, 1, 4, 2, 1, 2, 3]);
        assert_eq!(&m.positions[12..15], &[2.0, 0.0, 0.0]);
        assert_eq!(m.obj_vertex_lines, 6);
    }

    #[test]
    fn translate_boundary_edge() {
        let m = load_str("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\n");
        let e = m.error(Error::BoundaryEdge { v0: 0, v1: 2 });
        assert!(
            e.message.contains("edge 1-3 is a boundary edge"),
            "{}",
            e.message
        );
    }
}
