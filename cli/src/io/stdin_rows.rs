//! Rows of numbers on stdin for the query verbs (`ccss raycast`, `ccss
//! closest`): each non-blank line not starting with '#' holds exactly `n`
//! finite numbers; a bad line is `stdin line N: <reason>`.

use crate::error::{CliError, CliResult};
use std::io::BufRead;

/// One input row: its 1-based line number and its numbers.
pub struct Row {
    /// Line number in stdin (1-based).
    pub line: usize,
    /// The numbers.
    pub values: Vec<f64>,
}

/// Reads every row of `n` numbers from `input`.
pub fn read_rows(input: impl BufRead, n: usize) -> CliResult<Vec<Row>> {
    let mut rows = vec![];
    for (i, line) in input.lines().enumerate() {
        let line = line.map_err(|e| CliError::input(format!("stdin: {e}")))?;
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let mut values = Vec::with_capacity(n);
        for w in t.split_whitespace() {
            let x: f64 = w.parse().map_err(|_| {
                CliError::input(format!("stdin line {}: '{w}' is not a number", i + 1))
            })?;
            if !x.is_finite() {
                return Err(CliError::input(format!(
                    "stdin line {}: '{w}' is not finite",
                    i + 1
                )));
            }
            values.push(x);
        }
        if values.len() != n {
            return Err(CliError::input(format!(
                "stdin line {}: expected {n} numbers, found {}",
                i + 1,
                values.len()
            )));
        }
        rows.push(Row {
            line: i + 1,
            values,
        });
    }
    Ok(rows)
}

/// Diagonal of the box of a mesh's control points (the limit surface lies
/// inside it): the unit of the query verbs' default tolerances.
pub fn control_diagonal(positions: &[f64]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions.chunks_exact(3) {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let d: f64 = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum();
    d.sqrt()
}
