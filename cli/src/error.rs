//! The one error type of the `ccss` command and its exit codes.
//!
//! Every failure ends the process with exactly one line on stderr,
//! `ccss: error: <reason>`, and a non-zero exit code:
//!
//! * [`EXIT_INPUT`] (2): usage errors and bad input: an unknown option, a
//!   file that cannot be read or parsed, a bad query line on stdin or in a
//!   points file;
//! * [`EXIT_FAILURE`] (1): everything else, in particular a well-formed mesh
//!   that the core rejects (open, non-manifold, unsupported valence, ...) and
//!   errors writing the output.

use std::fmt;

/// Exit code for usage and input errors.
pub const EXIT_INPUT: i32 = 2;
/// Exit code for all other failures.
pub const EXIT_FAILURE: i32 = 1;

/// A failure: its exit code and the one-line reason.
#[derive(Debug)]
pub struct CliError {
    /// Process exit code.
    pub code: i32,
    /// The reason, printed after `ccss: error: `. Never contains a newline.
    pub message: String,
}

impl CliError {
    /// A usage or input error (exit code 2).
    pub fn input(message: impl Into<String>) -> Self {
        Self::new(EXIT_INPUT, message)
    }

    /// Any other failure (exit code 1).
    pub fn failure(message: impl Into<String>) -> Self {
        Self::new(EXIT_FAILURE, message)
    }

    fn new(code: i32, message: impl Into<String>) -> Self {
        // Keep the one-line promise whatever the source of the text.
        let message = message.into().replace(['\n', '\r'], " ");
        CliError { code, message }
    }

    /// An error writing the output. A closed pipe (`ccss eval ... | head`)
    /// is not a failure: it gives [`CliError::is_quiet`] (exit code 0, no
    /// message), as `head` and friends expect.
    pub fn write(e: &std::io::Error) -> Self {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            CliError {
                code: 0,
                message: String::new(),
            }
        } else {
            Self::failure(format!("cannot write output: {e}"))
        }
    }

    /// True for the quiet stop of a closed output pipe.
    pub fn is_quiet(&self) -> bool {
        self.code == 0
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ccss: error: {}", self.message)
    }
}

/// Result of a command.
pub type CliResult<T = ()> = Result<T, CliError>;
