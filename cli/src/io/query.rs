//! Parsing and checking of query lines.
//!
//! * `ccss eval` reads `face u v [sub]` (sub defaults to 0);
//! * points files (the OpenSubdiv harness format, `bench/osd/README.md`)
//!   hold `face sub u v class` with class `R` or `X`, optionally followed by
//!   one more token (ccss writes the X sub-class there, e.g. `X5`; it is
//!   informational, ignored when read, and `osd_eval` ignores it too).
//!
//! Fields are separated by any whitespace; blank lines and lines whose first
//! non-blank character is `#` are skipped. Reasons are returned as text
//! without the line prefix; callers add `stdin line N: ` or similar.

use ccss_core::eval::Query;
use ccss_core::{Error, Eval, Evaluator, FeatureEvaluator};

/// True for lines that carry no query.
pub fn is_skipped(line: &str) -> bool {
    let t = line.trim_start();
    t.is_empty() || t.starts_with('#')
}

fn index(name: &str, tok: &str) -> Result<u32, String> {
    tok.parse::<u32>()
        .map_err(|_| format!("{name} '{tok}' is not a non-negative integer"))
}

fn param(name: &str, tok: &str) -> Result<f64, String> {
    let x: f64 = tok
        .parse()
        .map_err(|_| format!("{name} '{tok}' is not a number"))?;
    if x.is_nan() {
        return Err(format!("{name} is NaN"));
    }
    if !(0.0..=1.0).contains(&x) {
        return Err(format!("{name} = {tok} is outside [0, 1]"));
    }
    Ok(x)
}

/// Parses an `eval` line `face u v [sub]` (not a skipped line).
pub fn parse_eval_line(line: &str) -> Result<Query, String> {
    let mut tok = [""; 4];
    let mut n = 0;
    for t in line.split_whitespace() {
        if n == 4 {
            return Err(format!(
                "expected 'face u v [sub]', got {} fields",
                line.split_whitespace().count()
            ));
        }
        tok[n] = t;
        n += 1;
    }
    if n < 3 {
        return Err(format!(
            "expected 'face u v [sub]', got {n} field{}",
            if n == 1 { "" } else { "s" }
        ));
    }
    let face = index("face", tok[0])?;
    let u = param("u", tok[1])?;
    let v = param("v", tok[2])?;
    let sub = if n == 4 { index("sub", tok[3])? } else { 0 };
    Ok(Query { face, sub, u, v })
}

/// The class letters of points files: `R`, `X` (face classes,
/// `crate::bench::classes`) and those of `crate::bench::regions`.
pub const POINT_CLASSES: &str = "RXUMNDCK";

/// Parses a points-file line `face sub u v class [subclass]` (not a
/// skipped line).
pub fn parse_points_line(line: &str) -> Result<(Query, char), String> {
    let t: Vec<&str> = line.split_whitespace().collect();
    if !(5..=6).contains(&t.len()) {
        return Err(format!(
            "expected 'face sub u v class', got {} fields",
            t.len()
        ));
    }
    let face = index("face", t[0])?;
    let sub = index("sub", t[1])?;
    let u = param("u", t[2])?;
    let v = param("v", t[3])?;
    let class = match t[4] {
        c if c.len() == 1 && POINT_CLASSES.contains(c) => c.chars().next().unwrap_or('R'),
        other => {
            return Err(format!(
                "class '{other}' is not one of the letters {POINT_CLASSES}"
            ))
        }
    };
    Ok((Query { face, sub, u, v }, class))
}

/// Checks a parsed query against the mesh (face and sub-face ranges), with
/// the core's wording plus the valid range.
/// A surface `ccss eval` can query: the eigen-table evaluator of closed
/// smooth meshes, or the feature evaluator of meshes with boundaries,
/// creases, corners and holes.
pub trait Surface: Sync {
    /// Number of base faces.
    fn num_faces(&self) -> usize;
    /// Number of sub-faces of face `f`.
    fn num_subfaces(&self, f: usize) -> usize;
    /// The core's check of one query.
    fn check_query(&self, q: &Query) -> Result<(), Error>;
    /// Evaluates checked queries into `out` (first failure: its index).
    fn eval_all(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)>;
}

impl Surface for Evaluator<'_> {
    fn num_faces(&self) -> usize {
        Evaluator::num_faces(self)
    }
    fn num_subfaces(&self, f: usize) -> usize {
        Evaluator::num_subfaces(self, f)
    }
    fn check_query(&self, q: &Query) -> Result<(), Error> {
        self.check(q)
    }
    fn eval_all(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)> {
        self.eval_batch(qs, second, out)
    }
}

impl Surface for FeatureEvaluator<'_, '_> {
    fn num_faces(&self) -> usize {
        FeatureEvaluator::num_faces(self)
    }
    fn num_subfaces(&self, f: usize) -> usize {
        FeatureEvaluator::num_subfaces(self, f)
    }
    fn check_query(&self, q: &Query) -> Result<(), Error> {
        self.check(q)
    }
    fn eval_all(&self, qs: &[Query], second: bool, out: &mut [Eval]) -> Result<(), (usize, Error)> {
        for (i, (q, o)) in qs.iter().zip(out.iter_mut()).enumerate() {
            *o = if second {
                self.eval_second(q.face, q.sub, q.u, q.v)
            } else {
                self.eval(q.face, q.sub, q.u, q.v)
            }
            .map_err(|e| (i, e))?;
        }
        Ok(())
    }
}

/// Checks a query against `ev`, with the face and sub-face ranges in the
/// message.
pub fn check<S: Surface + ?Sized>(ev: &S, q: &Query) -> Result<(), String> {
    ev.check_query(q).map_err(|e| match e {
        Error::FaceOutOfRange { .. } => {
            format!(
                "{e} (the mesh has {} faces: 0..={})",
                ev.num_faces(),
                ev.num_faces() - 1
            )
        }
        Error::SubFaceOutOfRange { face, .. } => {
            let n = ev.num_subfaces(face as usize);
            if n == 1 {
                format!("{e} (it is a quad: sub must be 0)")
            } else {
                format!("{e} (it has {n} sub-faces: 0..={})", n - 1)
            }
        }
        other => other.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eval_lines() {
        let q = parse_eval_line(" 3 0.25\t1 2 ").unwrap();
        assert_eq!(
            q,
            Query {
                face: 3,
                sub: 2,
                u: 0.25,
                v: 1.0
            }
        );
        assert_eq!(parse_eval_line("3 0 0").unwrap().sub, 0);
        assert!(parse_eval_line("3 0").unwrap_err().contains("got 2 fields"));
        assert!(parse_eval_line("3 0 0 0 0")
            .unwrap_err()
            .contains("got 5 fields"));
        assert!(parse_eval_line("-1 0 0").unwrap_err().contains("face '-1'"));
        assert!(parse_eval_line("1 1.5 0")
            .unwrap_err()
            .contains("u = 1.5 is outside"));
        assert!(parse_eval_line("1 0 nan").unwrap_err().contains("v is NaN"));
        assert!(parse_eval_line("1 0 x")
            .unwrap_err()
            .contains("v 'x' is not a number"));
        assert!(is_skipped("   # c"));
        assert!(is_skipped(" \t"));
    }

    #[test]
    fn points_lines() {
        let (q, c) = parse_points_line("7 0 0.5 0.25 X").unwrap();
        assert_eq!((q.face, q.sub, q.u, q.v, c), (7, 0, 0.5, 0.25, 'X'));
        assert!(parse_points_line("7 0 0.5 0.25 Q").is_err());
        assert!(parse_points_line("7 0 0.5 0.25 NN").is_err());
        assert_eq!(parse_points_line("7 0 0.5 0.25 D").unwrap().1, 'D');
        assert!(parse_points_line("7 0 0.5 0.25").is_err());
        assert_eq!(parse_points_line("7 0 0.5 0.25 X X5").unwrap().1, 'X');
        assert!(parse_points_line("7 0 0.5 0.25 X X5 y").is_err());
    }
}
