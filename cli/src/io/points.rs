//! Points files in the OpenSubdiv harness format (`bench/osd/README.md`):
//! one `face sub u v class` per line, class `R` or `X`, `#` lines skipped.
//!
//! Written with `{:.16e}` for u and v, so both tools read identical `f64`s.
//! X points get a sixth token, their sub-class (`X3`, `X5`, `Xmulti`, ...),
//! so that scripts can split a file by sub-class; `osd_eval` reads the
//! first five tokens of a line and ignores the rest.

use crate::error::{CliError, CliResult};
use crate::io::query::{check, is_skipped, parse_points_line, Surface};
use ccss_core::eval::Query;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

/// A benchmark point and its class letter.
pub type Point = (Query, char);

/// Reads and checks a points file (errors name the line; exit code 2).
pub fn read<S: Surface + ?Sized>(path: &Path, ev: &S) -> CliResult<Vec<Point>> {
    let name = path.display();
    let file = std::fs::File::open(path)
        .map_err(|e| CliError::input(format!("{name}: cannot read: {e}")))?;
    let mut pts = Vec::new();
    for (i, line) in BufReader::new(file).lines().enumerate() {
        let line =
            line.map_err(|e| CliError::input(format!("{name}: line {}: cannot read: {e}", i + 1)))?;
        if is_skipped(&line) {
            continue;
        }
        let p = parse_points_line(&line)
            .and_then(|p| check(ev, &p.0).map(|_| p))
            .map_err(|r| CliError::input(format!("{name}: line {}: {r}", i + 1)))?;
        pts.push(p);
    }
    Ok(pts)
}

/// Writes `pts` to `path`; `subclass` gives the optional sixth token.
pub fn write<'a>(
    path: &Path,
    pts: &[Point],
    subclass: impl Fn(&Query) -> Option<&'a str>,
) -> CliResult {
    let fail =
        |e: std::io::Error| CliError::failure(format!("{}: cannot write: {e}", path.display()));
    let mut w = BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    writeln!(
        w,
        "# face sub u v class [subclass] (ccss bench eval --write-points)"
    )
    .map_err(fail)?;
    for (q, c) in pts {
        write!(w, "{} {} {:.16e} {:.16e} {}", q.face, q.sub, q.u, q.v, c).map_err(fail)?;
        match subclass(q) {
            Some(s) if *c == 'X' => writeln!(w, " {s}"),
            _ => writeln!(w),
        }
        .map_err(fail)?;
    }
    w.flush().map_err(fail)
}
