//! Writing results to stdout: flushed at once (a reader of a pipe sees each
//! result when it is ready), and a closed pipe stops the command quietly
//! (see [`CliError::write`]).

use crate::error::{CliError, CliResult};
use std::io::Write;

/// Writes one line to stdout and flushes it.
pub fn line(line: &str) -> CliResult {
    let mut o = std::io::stdout().lock();
    writeln!(o, "{line}")
        .and_then(|_| o.flush())
        .map_err(|e| CliError::write(&e))
}
