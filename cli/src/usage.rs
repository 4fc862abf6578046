//! Command-line errors as one line: clap's message reduced to its first
//! paragraph and tips, with the `--help` command that fits the verb.

use crate::error::CliError;
use clap::error::ErrorKind;

/// The `--help` command that fits the command line: `ccss bench eval --help`
/// for errors inside `ccss bench eval ...`, and so on.
fn help_hint() -> String {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let verb: Vec<&str> = match args.first().map(String::as_str) {
        Some(
            v @ ("eval" | "info" | "depth" | "tessellate" | "refine" | "voxelize" | "measure"),
        ) => {
            vec![v]
        }
        Some("bench") => match args.get(1).map(String::as_str) {
            Some("eval") => vec!["bench", "eval"],
            Some("tables") => vec!["bench", "tables"],
            Some("tessellate") => vec!["bench", "tessellate"],
            Some("voxelize") => vec!["bench", "voxelize"],
            _ => vec!["bench"],
        },
        _ => vec![],
    };
    let mut h = String::from("ccss ");
    for v in verb {
        h.push_str(v);
        h.push(' ');
    }
    h + "--help"
}

/// A clap error as one line: its first paragraph, plus its tips.
pub fn usage_error(e: &clap::Error) -> CliError {
    let text = e.to_string();
    let mut paragraphs = text.split("\n\n");
    let first = paragraphs.next().unwrap_or("invalid command line");
    let mut msg = first.split_whitespace().collect::<Vec<_>>().join(" ");
    if let Some(rest) = msg.strip_prefix("error: ") {
        msg = rest.to_string();
    }
    for l in text.lines().map(str::trim) {
        if let Some(tip) = l.strip_prefix("tip: ") {
            msg.push_str("; ");
            msg.push_str(tip);
        }
    }
    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        msg = "missing subcommand".to_string();
    }
    CliError::input(format!("{msg} (see '{}')", help_hint()))
}
