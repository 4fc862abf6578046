//! OpenSubdiv's `t` tag lines of an OBJ file: creases, corners, holes and
//! the scheme options (`interpolateboundary`, `creasemethod`,
//! `smoothtriangles`). Hierarchical edits (`vertexedit`, `edgeedit`,
//! `faceedit`) and face-varying options are ignored with a warning, as
//! OpenSubdiv's Far does.
//!
//! Form: `t name nint/nfloat/nstring ints... floats... strings...`. Vertex
//! numbers are 0-based `v`-line numbers, face numbers 0-based `f`-line
//! numbers (OpenSubdiv's shape files). The values mean what OpenSubdiv's
//! regression harness (`regression/common/far_utils.h`) makes of them:
//!
//! * `crease`: vertex pairs `a b c d ...` (disjoint pairs, not a chain), one
//!   sharpness for all of them or one per pair (an odd vertex count, or
//!   another number of values, is an error: OpenSubdiv would silently drop
//!   or misread them);
//! * `interpolateboundary`: `0` none, `1` edge-and-corner, `2` edge-only
//!   (RenderMan's numbering, not the order of `Sdc::Options`);
//! * `creasemethod`: `normal` (uniform) or `chaikin`;
//! * `smoothtriangles`: `catmark` or `smooth`.

use ccss_core::mesh::sharpness::{Boundary, Creasing};

/// The tags of one file (vertex numbers are `v`-line numbers).
#[derive(Debug, Clone, Default)]
pub struct Tags {
    /// `(a, b, sharpness, line)` per sharpened edge.
    pub creases: Vec<(u32, u32, f32, usize)>,
    /// `(vertex, sharpness, line)` per sharp vertex.
    pub corners: Vec<(u32, f32, usize)>,
    /// `(face, line)` per hole.
    pub holes: Vec<(u32, usize)>,
    /// `interpolateboundary`, if given.
    pub boundary: Option<Boundary>,
    /// `creasemethod`, if given.
    pub creasing: Option<Creasing>,
    /// `smoothtriangles`, if given.
    pub smooth_triangles: Option<bool>,
    /// Tag lines that were ignored, `(name, line)`.
    pub ignored: Vec<(String, usize)>,
}

impl Tags {
    /// True when any tag changes the surface (or the scheme options).
    pub fn any(&self) -> bool {
        !self.creases.is_empty()
            || !self.corners.is_empty()
            || !self.holes.is_empty()
            || self.boundary.is_some()
            || self.creasing.is_some()
            || self.smooth_triangles.is_some()
    }

    /// Parses one `t` line (the tokens after `t`); `line` is 1-based.
    pub fn parse_line<'a>(
        &mut self,
        mut tok: impl Iterator<Item = &'a str>,
        line: usize,
    ) -> Result<(), String> {
        let name = tok.next().ok_or("tag without a name")?;
        let counts = tok.next().ok_or(format!(
            "tag '{name}' without its counts 'nint/nfloat/nstring'"
        ))?;
        let c: Vec<usize> = counts
            .split('/')
            .map(|x| x.parse::<usize>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("tag '{name}': bad counts '{counts}'"))?;
        if c.len() != 3 {
            return Err(format!(
                "tag '{name}': counts must be 'nint/nfloat/nstring'"
            ));
        }
        let rest: Vec<&str> = tok.collect();
        // Counts come from the file: their sum may overflow (found by the
        // `obj` and `tessellate` fuzz targets).
        let total = c[0].checked_add(c[1]).and_then(|x| x.checked_add(c[2]));
        if !matches!(total, Some(t) if t <= rest.len()) {
            return Err(format!("tag '{name}': fewer values than its counts say"));
        }
        let int = |s: &str| {
            s.parse::<u32>()
                .map_err(|_| format!("tag '{name}': '{s}' is not a non-negative integer"))
        };
        let float = |s: &str| {
            s.parse::<f32>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or(format!("tag '{name}': '{s}' is not a finite number"))
        };
        let sharpness = |x: f32| {
            if x >= 0.0 {
                Ok(x)
            } else {
                Err(format!("tag '{name}': sharpness {x} is negative"))
            }
        };
        let ints: Vec<u32> = rest[..c[0]]
            .iter()
            .map(|s| int(s))
            .collect::<Result<_, _>>()?;
        let floats: Vec<f32> = rest[c[0]..c[0] + c[1]]
            .iter()
            .map(|s| float(s))
            .collect::<Result<_, _>>()?;
        let strings = &rest[c[0] + c[1]..c[0] + c[1] + c[2]];
        match name {
            "crease" => {
                let pairs = ints.len() / 2;
                if ints.len() < 2 || !ints.len().is_multiple_of(2) {
                    return Err(format!(
                        "tag 'crease' needs vertex pairs (an even count of at least 2), got {} \
                         vertices",
                        ints.len()
                    ));
                }
                if floats.len() != 1 && floats.len() != pairs {
                    return Err(format!(
                        "tag 'crease' needs 1 sharpness or one per pair ({pairs}), got {}",
                        floats.len()
                    ));
                }
                for (k, w) in ints.chunks_exact(2).enumerate() {
                    let x = sharpness(floats[if floats.len() == 1 { 0 } else { k }])?;
                    self.creases.push((w[0], w[1], x, line));
                }
            }
            "corner" => {
                if ints.is_empty() || floats.len() != 1 {
                    return Err("tag 'corner' needs vertices and 1 sharpness".into());
                }
                let x = sharpness(floats[0])?;
                for &v in &ints {
                    self.corners.push((v, x, line));
                }
            }
            "hole" => self.holes.extend(ints.iter().map(|&f| (f, line))),
            "interpolateboundary" => {
                self.boundary = Some(match ints.first() {
                    Some(0) => Boundary::None,
                    Some(1) => Boundary::EdgeAndCorner,
                    Some(2) => Boundary::EdgeOnly,
                    _ => {
                        return Err("tag 'interpolateboundary' must be 0 (none), 1 \
                                    (edge-and-corner) or 2 (edge-only)"
                            .into())
                    }
                })
            }
            "creasemethod" => {
                self.creasing = Some(match strings.first() {
                    Some(&"chaikin") => Creasing::Chaikin,
                    Some(&"normal") | Some(&"uniform") => Creasing::Uniform,
                    other => {
                        return Err(format!(
                            "tag 'creasemethod': '{}' is not 'chaikin' or 'normal'",
                            other.unwrap_or(&"")
                        ))
                    }
                })
            }
            "smoothtriangles" => {
                self.smooth_triangles = Some(match strings.first() {
                    Some(&"smooth") => true,
                    Some(&"catmark") => false,
                    other => {
                        return Err(format!(
                            "tag 'smoothtriangles': '{}' is not 'smooth' or 'catmark'",
                            other.unwrap_or(&"")
                        ))
                    }
                })
            }
            other => self.ignored.push((other.to_string(), line)),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (cargo-fuzz `obj` and `tessellate`, 2026-11-27): counts
    /// whose sum overflows `usize` panicked ("attempt to add with
    /// overflow"; wrapped and sliced out of range without debug
    /// assertions).
    #[test]
    fn overflowing_counts_are_an_error() {
        for counts in [
            "18446744073709551615/1/0",
            "1/18446744073709551615/0",
            "0/1/18446744073709551615",
            "9223372036854775808/9223372036854775808/0",
        ] {
            let line = format!("ry {counts} r non-parallel");
            let mut t = Tags::default();
            let e = t.parse_line(line.split_whitespace(), 3).unwrap_err();
            assert!(e.contains("fewer values than its counts say"), "{e}");
        }
    }

    #[test]
    fn parses_opensubdiv_tags() {
        let mut t = Tags::default();
        t.parse_line("crease 4/1/0 0 1 1 2 2.5".split_whitespace(), 7)
            .unwrap();
        t.parse_line("corner 1/1/0 4 10".split_whitespace(), 8)
            .unwrap();
        t.parse_line("hole 2/0/0 3 5".split_whitespace(), 9)
            .unwrap();
        t.parse_line("interpolateboundary 1/0/0 2".split_whitespace(), 10)
            .unwrap();
        t.parse_line("creasemethod 0/0/1 chaikin".split_whitespace(), 11)
            .unwrap();
        t.parse_line("vertexedit 1/1/2 0 1.0 set P".split_whitespace(), 12)
            .unwrap();
        assert_eq!(t.creases, vec![(0, 1, 2.5, 7), (1, 2, 2.5, 7)]);
        assert_eq!(t.corners, vec![(4, 10.0, 8)]);
        assert_eq!(t.holes, vec![(3, 9), (5, 9)]);
        // RenderMan's numbering, as OpenSubdiv's harness: 2 is edge-only.
        assert_eq!(t.boundary, Some(Boundary::EdgeOnly));
        assert_eq!(t.creasing, Some(Creasing::Chaikin));
        assert_eq!(t.ignored, vec![("vertexedit".to_string(), 12)]);
        let e = t
            .parse_line("crease 2/1/0 0 1 -3".split_whitespace(), 13)
            .unwrap_err();
        assert!(e.contains("negative"), "{e}");
        // Pairs, not chains; per-pair values.
        let mut t = Tags::default();
        t.parse_line("crease 4/2/0 0 1 5 6 1 2".split_whitespace(), 3)
            .unwrap();
        assert_eq!(t.creases, vec![(0, 1, 1.0, 3), (5, 6, 2.0, 3)]);
        for bad in ["crease 3/1/0 0 1 2 1", "crease 4/3/0 0 1 2 3 1 1 1"] {
            let e = t.parse_line(bad.split_whitespace(), 4).unwrap_err();
            assert!(e.contains("pair"), "{bad}: {e}");
        }
        t.parse_line("interpolateboundary 1/0/0 1".split_whitespace(), 5)
            .unwrap();
        assert_eq!(t.boundary, Some(Boundary::EdgeAndCorner));
    }
}
