//! Loading a polygon mesh from an OBJ file.
//!
//! A small line reader of our own (no `tobj`), so that every problem is
//! reported with its 1-based line number: a UTF-8 byte-order mark is
//! skipped; lines end at `\n`, `\r\n` or a lone `\r`; `#` starts a comment;
//! `v x y z [w | r g b]` is a vertex (extra numbers such as vertex colours are
//! ignored); `f` tokens `v`, `v/vt`, `v//vn`, `v/vt/vn` with 1-based or
//! negative (relative) indices; `l` (polylines) and `p` (points) lines of
//! any length are ignored and never become faces; `o`, `g`, `s`, `usemtl`,
//! `mtllib`, `vt`, `vn` and unknown statements are ignored (groups are merged
//! into one mesh).
//!
//! Numbering: mesh vertex `i` is the `i`-th *used* `v` line (unused `v`
//! lines are dropped), and error messages translate vertex numbers to
//! 0-based `v`-line numbers (OBJ index minus one). Faces keep their file
//! order, so face `f` is the `f`-th `f` line (0-based).
//!
//! A coordinate must be a finite `f64` literal: `nan`, `inf` and literals that
//! overflow (`1e309`) are refused with their line; finite values of any
//! magnitude (`1e308`) are read as they are (a later stage may refuse them
//! with its own reason).
//!
//! The reader also parses OpenSubdiv's `t` tag lines (creases, corners,
//! holes, boundary and crease options; [`crate::io::tags`]): `ccss eval`
//! evaluates the surface they define; the other verbs do not support them
//! yet and say so once on stderr.

use crate::error::{CliError, CliResult};
use crate::io::tags::Tags;
use ccss_core::{Error, MeshInput, SolidDefect};
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
    /// 0-based OBJ `v`-line number of each mesh vertex (always `Some` since
    /// the reader is our own; kept optional for meshes built in memory).
    pub obj_vertex: Option<Vec<u32>>,
    /// Number of `v` lines in the file (used or not).
    pub obj_vertex_lines: usize,
    /// Number of OpenSubdiv `t` tag lines.
    pub tag_lines: usize,
    /// The parsed tags (vertex numbers are 0-based `v`-line numbers).
    pub tags: Tags,
}

/// What the reader found.
#[derive(Default)]
struct Scan {
    /// x y z of every `v` line.
    positions: Vec<f64>,
    t_lines: usize,
    tags: Tags,
    sizes: Vec<u32>,
    /// 0-based `v`-line number of every face corner.
    refs: Vec<u32>,
    /// First problem found, with its 1-based line number.
    problem: Option<(usize, String)>,
}

/// The lines of `text` with their 1-based numbers; a line ends at `\n`,
/// `\r\n` or a lone `\r`.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = text;
    let mut n = 0usize;
    core::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        n += 1;
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let line = &rest[..end];
        let skip = match rest.as_bytes().get(end) {
            Some(b'\r') if rest.as_bytes().get(end + 1) == Some(&b'\n') => 2,
            Some(_) => 1,
            None => 0,
        };
        rest = &rest[end + skip..];
        Some((n, line))
    })
}

/// One coordinate of a `v` line.
fn coordinate(tok: Option<&str>, axis: &str) -> Result<f64, String> {
    let t = tok.ok_or(format!("vertex without its {axis} coordinate"))?;
    let x: f64 = t
        .parse()
        .map_err(|_| format!("vertex {axis} coordinate '{t}' is not a number"))?;
    if x.is_finite() {
        Ok(x)
    } else if t.to_ascii_lowercase().contains("n") {
        Err(format!("vertex {axis} coordinate '{t}' is NaN or infinite"))
    } else {
        Err(format!(
            "vertex {axis} coordinate '{t}' overflows a double (beyond 1.8e308)"
        ))
    }
}

/// Reads the OBJ text (see the module docs).
fn scan(text: &str) -> Scan {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut s = Scan::default();
    for (ln, line) in lines(text) {
        if s.problem.is_some() {
            break;
        }
        let line = line.split('#').next().unwrap_or("");
        let mut tok = line.split_whitespace();
        let r: Result<(), String> = match tok.next() {
            Some("v") => (|| {
                for axis in ["x", "y", "z"] {
                    let x = coordinate(tok.next(), axis)?;
                    s.positions.push(x);
                }
                Ok(())
            })(),
            Some("t") => {
                s.t_lines += 1;
                s.tags.parse_line(tok, ln)
            }
            Some("f") => {
                let start = s.refs.len();
                let nv = (s.positions.len() / 3) as i64;
                let mut r = Ok(());
                for t in tok {
                    let first = t.split('/').next().unwrap_or("");
                    let Ok(k) = first.parse::<i64>() else {
                        r = Err(format!("bad face vertex '{t}' (not an index)"));
                        break;
                    };
                    let z = if k > 0 { k - 1 } else { nv + k };
                    if k == 0 || !(0..nv).contains(&z) {
                        r = Err(format!(
                            "bad face vertex '{t}' (no such vertex: {nv} 'v' lines so far)"
                        ));
                        break;
                    }
                    s.refs.push(z as u32);
                }
                let n = s.refs.len() - start;
                if r.is_ok() && n < 3 {
                    r = Err(format!("face with {n} vertices (at least 3 needed)"));
                }
                s.sizes.push(n as u32);
                r
            }
            _ => Ok(()),
        };
        if let Err(what) = r {
            s.problem = Some((ln, what));
        }
    }
    s
}

/// Keeps the used vertices in file order: (positions, indices, v-line of
/// each mesh vertex).
fn compact(s: &Scan) -> (Vec<f64>, Vec<u32>, Vec<u32>) {
    let mut rank = vec![u32::MAX; s.positions.len() / 3];
    for &o in &s.refs {
        rank[o as usize] = 0;
    }
    let mut obj_vertex = Vec::new();
    let mut positions = Vec::new();
    for (o, r) in rank.iter_mut().enumerate() {
        if *r == 0 {
            *r = obj_vertex.len() as u32;
            obj_vertex.push(o as u32);
            positions.extend_from_slice(&s.positions[3 * o..3 * o + 3]);
        }
    }
    let indices = s.refs.iter().map(|&o| rank[o as usize]).collect();
    (positions, indices, obj_vertex)
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
        let m = Mesh::parse(&name, &text)?;
        for (tag, line) in &m.tags.ignored {
            eprintln!(
                "ccss: warning: {name}: line {line}: tag '{tag}' ignored (hierarchical edits \
                 and face-varying options are not supported, as in OpenSubdiv's Far)"
            );
        }
        Ok(m)
    }

    /// Parses the bytes of an OBJ file named `name` (the prefix of
    /// messages), tags included, without printing anything: what
    /// [`Mesh::load_with_tags`] does after reading the file (ignored tags
    /// are left in `tags.ignored`). Not UTF-8, a parse error (with its line)
    /// or no faces are input errors; topology is not checked here.
    pub fn parse(name: &str, bytes: &[u8]) -> CliResult<Mesh> {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| CliError::input(format!("{name}: not a text (UTF-8) OBJ file")))?;
        let s = scan(text);
        if let Some((line, what)) = &s.problem {
            return Err(CliError::input(format!("{name}: line {line}: {what}")));
        }
        if s.sizes.is_empty() {
            return Err(CliError::input(format!("{name}: no faces")));
        }
        let (positions, indices, obj_vertex) = compact(&s);
        Ok(Mesh {
            name: name.to_string(),
            positions,
            face_sizes: s.sizes,
            indices,
            obj_vertex: Some(obj_vertex),
            obj_vertex_lines: s.positions.len() / 3,
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

    fn load_any(text: &str) -> CliResult<Mesh> {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!("ccss-mesh-err-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("e{}.obj", N.fetch_add(1, Ordering::Relaxed)));
        std::fs::write(&p, text).unwrap();
        let m = Mesh::load(&p);
        let _ = std::fs::remove_file(&p);
        m
    }

    const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn bom_cr_lines_points_colours() {
        // BOM: the first vertex is kept.
        let m = load_str(&format!("\u{feff}{QUAD}f 1 2 3 4\n"));
        assert_eq!(m.num_vertices(), 4);
        assert_eq!(&m.positions[..3], &[0.0, 0.0, 0.0]);
        // CR-only and CRLF line ends, comments, colours, l and p lines of
        // any length.
        let m = load_str(
            "v 0 0 0 1 0 0\rv 1 0 0 0 1 0\r\nv 1 1 0 # c\rv 0 1 0\r\
             l 1 2 3 4 1\rp 1 2 3\rf 1 2 3 4\r",
        );
        assert_eq!(m.face_sizes, vec![4]);
        assert_eq!(m.positions[3..6], [1.0, 0.0, 0.0]);
        // Finite 1e308 is read as it is.
        let m = load_str(&format!("{QUAD}v 1e308 -1e308 2.2e-308\nf 1 2 5\n"));
        assert_eq!(&m.positions[6..9], &[1e308, -1e308, 2.2e-308]);
    }

    #[test]
    fn every_parse_error_has_its_line() {
        for (text, line, what) in [
            ("v 0 0 0\nv 1 x 0\n", 2, "'x' is not a number"),
            ("v 0 0\n", 1, "without its z coordinate"),
            ("\u{feff}v 0 0 0\nv nan 0 0\n", 2, "NaN or infinite"),
            ("v 0 0 0\r\rv inf 0 0\n", 3, "NaN or infinite"),
            ("v 0 0 0\nv 1e309 0 0\n", 2, "overflows"),
            (&format!("{QUAD}f 1 2 9\n"), 5, "no such vertex"),
            (&format!("{QUAD}f 1 2 a\n"), 5, "not an index"),
            (&format!("{QUAD}f 1 2\n"), 5, "at least 3"),
            (&format!("{QUAD}f 1 0 2\n"), 5, "no such vertex"),
            (&format!("{QUAD}l 1 2 3\n"), 0, "no faces"),
        ] {
            let e = load_any(text).expect_err(text).message;
            let want = if line > 0 {
                format!(": line {line}: ")
            } else {
                String::new()
            };
            assert!(e.contains(&want) && e.contains(what), "{text:?}: {e}");
        }
    }

    /// Stable-toolchain fuzz driver of the reader: byte- and token-level
    /// mutations of OBJ texts (corpus shapes and hand-made ones); the
    /// reader must never panic, and a text it accepts has faces whose
    /// indices are in range. `CCSS_FUZZ_ITERS` inputs (default 2000).
    #[test]
    fn fuzz_obj_reader() {
        let iters: usize = std::env::var("CCSS_FUZZ_ITERS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(2000);
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/osd");
        let mut seeds: Vec<String> = [
            "catmark_cube.obj",
            "catmark_torus.obj",
            "catmark_pyramid.obj",
        ]
        .iter()
        .filter_map(|f| std::fs::read_to_string(dir.join(f)).ok())
        .collect();
        seeds.push(format!("\u{feff}{QUAD}l 1 2 3 4\rp 1 2\r\nf 1 2 3 4\n"));
        const TOKENS: [&str; 16] = [
            "v",
            "f",
            "l",
            "p",
            "t",
            "#",
            "\r",
            "\n",
            "\u{feff}",
            "1e309",
            "nan",
            "-1",
            "0",
            "1/2/3",
            "//",
            "4294967296",
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        let t0 = std::time::Instant::now();
        let mut accepted = 0usize;
        for _ in 0..iters {
            let mut b: Vec<u8> = seeds[(next() % seeds.len() as u64) as usize]
                .clone()
                .into_bytes();
            for _ in 0..1 + next() % 4 {
                let at = (next() % (b.len() as u64 + 1)) as usize;
                match next() % 3 {
                    0 if at < b.len() => b[at] = (next() % 128) as u8,
                    1 => {
                        let t = TOKENS[(next() % TOKENS.len() as u64) as usize];
                        b.splice(at..at, format!(" {t} ").into_bytes());
                    }
                    _ => {
                        let end = (at + (next() % 16) as usize).min(b.len());
                        b.drain(at..end);
                    }
                }
            }
            let Ok(text) = String::from_utf8(b) else {
                continue;
            };
            let s = scan(&text);
            if s.problem.is_none() && !s.sizes.is_empty() {
                accepted += 1;
                let (p, idx, _) = compact(&s);
                assert!(idx.iter().all(|&i| (i as usize) < p.len() / 3));
                assert!(p.iter().all(|x| x.is_finite()));
            }
        }
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "fuzz: {iters} OBJ texts, {accepted} accepted, {:.0} executions/s",
            iters as f64 / dt
        );
    }

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
