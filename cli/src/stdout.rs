//! Writing results to stdout: flushed at once (a reader of a pipe sees each
//! result when it is ready), and a closed pipe stops the command quietly
//! (see [`CliError::write`]).

use crate::error::{CliError, CliResult};
use std::io::Write;

/// Writes `text` (whole lines, each ending with `\n`) to stdout and flushes
/// it.
pub fn text(text: &str) -> CliResult {
    let mut o = std::io::stdout().lock();
    o.write_all(text.as_bytes())
        .and_then(|_| o.flush())
        .map_err(|e| CliError::write(&e))
}

/// Writes one line to stdout (`line` and `\n`) and flushes it.
pub fn line(line: &str) -> CliResult {
    let mut o = std::io::stdout().lock();
    writeln!(o, "{line}")
        .and_then(|_| o.flush())
        .map_err(|e| CliError::write(&e))
}
