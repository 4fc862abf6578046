//! General vertex-rule weights from a file (`--weights W.tsv`).
//!
//! One rule per line, `n alpha beta gamma` (whitespace separated): a vertex
//! `V` of valence `n` moves to `alpha V + beta/n sum(E_i) + gamma/n sum(F_i)`
//! (`E_i` edge neighbours, `F_i` face-diagonal vertices); edge and face
//! points keep the standard rules. Blank lines and `#` comments (whole lines,
//! or the rest of a line) are skipped. Valences not listed keep the standard
//! Catmull-Clark rule; a valence may be listed once. The core validates each
//! rule (finite, non-negative, sum 1, valence 4 standard, valence in range).
//!
//! Every problem is an input error (exit code 2) naming the file and line:
//! `W.tsv line 3: weights for valence 4 rejected: ...`.

use crate::error::{CliError, CliResult};
use ccss_core::Weights;
use std::path::{Path, PathBuf};

/// The `--weights W.tsv` option, shared by the verbs that build tables.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct WeightsArg {
    /// Vertex-rule weights: a file of 'n alpha beta gamma' lines (valences
    /// not listed keep the standard Catmull-Clark rule; '#' comments).
    #[arg(long, value_name = "W.tsv")]
    pub weights: Option<PathBuf>,
}

impl WeightsArg {
    /// The rule: standard, or read from the file.
    pub fn load(&self) -> CliResult<Weights> {
        match &self.weights {
            Some(p) => load(p),
            None => Ok(Weights::STANDARD),
        }
    }
}

/// Reads a weights file.
pub fn load(path: &Path) -> CliResult<Weights> {
    let name = path.display().to_string();
    let text =
        std::fs::read(path).map_err(|e| CliError::input(format!("{name}: cannot read: {e}")))?;
    parse(&text).map_err(|(line, reason)| CliError::input(format!("{name} line {line}: {reason}")))
}

/// Parses the text of a weights file; errors are `(1-based line, reason)`.
pub fn parse(text: &[u8]) -> Result<Weights, (usize, String)> {
    let mut w = Weights::STANDARD;
    // (valence, line) of the rules read so far.
    let mut given: Vec<(u32, usize)> = Vec::new();
    for (i, raw) in text.split(|&b| b == b'\n').enumerate() {
        let no = i + 1;
        let line = std::str::from_utf8(raw).map_err(|_| (no, "not valid UTF-8".to_string()))?;
        let line = line.split('#').next().unwrap_or("");
        let t: Vec<&str> = line.split_whitespace().collect();
        if t.is_empty() {
            continue;
        }
        if t.len() != 4 {
            return Err((
                no,
                format!(
                    "expected 'n alpha beta gamma', got {} field{}",
                    t.len(),
                    if t.len() == 1 { "" } else { "s" }
                ),
            ));
        }
        let n: u32 = t[0].parse().map_err(|_| {
            (
                no,
                format!("valence '{}' is not a non-negative integer", t[0]),
            )
        })?;
        let num = |what: &str, tok: &str| -> Result<f64, (usize, String)> {
            tok.parse::<f64>()
                .map_err(|_| (no, format!("{what} '{tok}' is not a number")))
        };
        let (a, b, g) = (num("alpha", t[1])?, num("beta", t[2])?, num("gamma", t[3])?);
        if let Some(&(_, first)) = given.iter().find(|(v, _)| *v == n) {
            return Err((
                no,
                format!("weights for valence {n} are already given on line {first}"),
            ));
        }
        w.set(n as usize, a, b, g)
            .map_err(|e| (no, e.to_string()))?;
        given.push((n, no));
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ccss_core::mesh::weights::standard;

    #[test]
    fn parses_rules_and_comments() {
        let w =
            parse(b"# n alpha beta gamma\n\n 3\t0.5 0.3 0.2  # mine\r\n5 0.4 0.4 0.2\n").unwrap();
        assert_eq!(w.get(3), (0.5, 0.3, 0.2));
        assert_eq!(w.get(5), (0.4, 0.4, 0.2));
        assert_eq!(w.get(6), standard(6));
        assert!(w.is_standard(4));
        // Valence 4 may be given with its standard weights.
        let w = parse(b"4 0.5625 0.375 0.0625\n").unwrap();
        assert!(w.is_standard(4));
        assert_eq!(parse(b"").unwrap(), Weights::STANDARD);
    }

    #[test]
    fn errors_name_the_line() {
        let err = |t: &str| parse(t.as_bytes()).unwrap_err();
        assert_eq!(err("3 0.5 0.3\n").0, 1);
        assert!(err("3 0.5 0.3\n").1.contains("got 3 fields"));
        let (l, m) = err("# c\n3 0.5 0.3 0.2\n4 0.5 0.3 0.2\n");
        assert_eq!(l, 3);
        assert!(m.starts_with("weights for valence 4 rejected: "), "{m}");
        assert!(err("3 x 0.3 0.2").1.contains("alpha 'x' is not a number"));
        assert!(err("-3 0.5 0.3 0.2").1.contains("valence '-3'"));
        assert!(err("3 0.5 -0.3 0.8").1.contains("negative"));
        assert!(err("3 0.5 0.3 0.3").1.contains("is not 1"));
        assert!(err("3 nan 0.3 0.2").1.contains("NaN"));
        assert!(err("99 0.5 0.3 0.2").1.contains("valence outside"));
        let (l, m) = err("3 0.5 0.3 0.2\n\n3 0.5 0.3 0.2\n");
        assert_eq!(l, 3);
        assert!(m.contains("already given on line 1"), "{m}");
    }
}
