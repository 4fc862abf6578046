//! `ccss eval MESH.obj [--second] [--weights W.tsv]`: evaluates `face u v [sub]` queries from
//! stdin, one output line per query, in input order.
//!
//! Pipeline: stdin is read line by line into chunks of [`CHUNK_LINES`]
//! lines; a batch of chunks is parsed, checked, evaluated (with
//! `Evaluator::eval_batch`) and formatted in parallel with rayon, one chunk
//! per task, and the chunks are written in order. A batch ends early when
//! stdin has nothing more buffered, so a program that writes one query and
//! waits for the answer (a co-process) gets it at once.
//!
//! On the first bad line everything before it is written, then the command
//! fails with `stdin line N: <reason>` (exit code 2).

use crate::context::{build_tables, with_mesh};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::numfmt::push_eval_line;
use crate::io::query::{check, is_skipped, parse_eval_line};
use crate::io::weights_file::WeightsArg;
use ccss_core::eval::Query;
use ccss_core::{Eval, Evaluator};
use rayon::prelude::*;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::PathBuf;

/// Lines per chunk (one rayon task, one `eval_batch` call).
pub const CHUNK_LINES: usize = 4096;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Evaluate the limit surface at queries read from stdin. Each input line is 'face u v [sub]' \
(whitespace separated; u and v in [0, 1]; sub, the sub-face of an N-gon with N != 4, \
defaults to 0 and must be 0 for quads); blank lines and lines starting with '#' are skipped. \
For each query one line 'px py pz dux duy duz dvx dvy dvz' is written to stdout, in input \
order, every number with 17 significant digits ('{:.16e}', e.g. -5.5555555555555558e-1, \
which reads back to the identical double); --second appends 'duux duuy duuz duvx duvy duvz \
dvvx dvvy dvvz'. Derivatives are with respect to the (sub-)face's own (u, v): quad v0 v1 v2 \
v3 has (0,0)=v0, (1,0)=v1, (1,1)=v2; sub-face k of an N-gon has (0,0)=v_k, (1,0) on edge \
v_k v_k+1 and (1,1) at the face centre (the OpenSubdiv conventions). Work is done in chunks \
of 4096 lines on all cores (RAYON_NUM_THREADS to change), keeping the order; output is \
flushed whenever stdin has nothing more buffered, so a co-process can send one query and \
read its answer. The first bad line stops the command after \
the output of all lines before it, with 'ccss: error: stdin line N: <reason>' (exit code 2). \
--weights W.tsv evaluates the surface of a general vertex rule: W.tsv has lines \
'n alpha beta gamma' (whitespace separated; '#' comments and blank lines skipped) giving \
the rule V' = alpha V + beta/n sum(E_i) + gamma/n sum(F_i) of valence n (E_i edge \
neighbours, F_i face-diagonal vertices; edge and face points stay standard); valences not \
listed keep the standard Catmull-Clark rule (alpha = 1-7/(4n), beta = 3/(2n), gamma = \
1/(4n)), and valence 4 must stay standard. Weights must be finite, non-negative and add \
up to 1; a bad line fails with 'ccss: error: W.tsv line N: <reason>' (exit code 2).";

/// Arguments of `ccss eval`.
#[derive(clap::Args, Debug)]
pub struct EvalArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Also write the second derivatives duu duv dvv (9 more numbers).
    #[arg(long)]
    pub second: bool,
    #[command(flatten)]
    pub weights: WeightsArg,
}

/// Runs the verb on stdin/stdout.
pub fn run(a: &EvalArgs) -> CliResult {
    let second = a.second;
    let weights = a.weights.load()?;
    let mesh = Mesh::load(&a.mesh)?;
    let (tables, _) = build_tables(&weights)?;
    with_mesh(&mesh, &tables, |ctx| {
        let stdin = std::io::stdin().lock();
        let stdout = std::io::stdout().lock();
        stream(&ctx.evaluator, second, stdin, stdout)
    })
}

/// Raw text of up to [`CHUNK_LINES`] consecutive input lines.
struct Chunk {
    /// 1-based number of its first line.
    first_line: u64,
    text: Vec<u8>,
}

/// A processed chunk: its output, and the first error in it (if any).
struct Done {
    out: String,
    error: Option<(u64, String)>,
}

fn process(ev: &Evaluator, second: bool, c: &Chunk) -> Done {
    let mut queries: Vec<Query> = Vec::with_capacity(CHUNK_LINES);
    let mut lines: Vec<u64> = Vec::with_capacity(CHUNK_LINES);
    let mut error = None;
    let body = c.text.strip_suffix(b"\n").unwrap_or(&c.text);
    for (i, raw) in body.split(|&b| b == b'\n').enumerate() {
        let no = c.first_line + i as u64;
        let parsed = std::str::from_utf8(raw)
            .map_err(|_| "not valid UTF-8".to_string())
            .and_then(|line| {
                if is_skipped(line) {
                    Ok(None)
                } else {
                    let q = parse_eval_line(line)?;
                    check(ev, &q)?;
                    Ok(Some(q))
                }
            });
        match parsed {
            Ok(Some(q)) => {
                queries.push(q);
                lines.push(no);
            }
            Ok(None) => {}
            Err(reason) => {
                error = Some((no, reason));
                break;
            }
        }
    }
    let mut evals = vec![Eval::default(); queries.len()];
    if let Err((i, e)) = ev.eval_batch(&queries, second, &mut evals) {
        // Unreachable: every query was checked above. Report it faithfully.
        let no = lines.get(i).copied().unwrap_or(c.first_line);
        return Done {
            out: String::new(),
            error: Some((no, e.to_string())),
        };
    }
    let per_line = if second { 18 * 25 } else { 9 * 25 };
    let mut out = String::with_capacity(evals.len() * per_line);
    for e in &evals {
        push_eval_line(&mut out, e, second);
    }
    Done { out, error }
}

/// Reads up to `max_chunks` chunks; stops early (with at least one line)
/// when the reader has nothing buffered, i.e. the next read could block.
/// Returns false at end of input.
fn read_batch<R: Read>(
    input: &mut BufReader<R>,
    line_no: &mut u64,
    max_chunks: usize,
    batch: &mut Vec<Chunk>,
) -> CliResult<bool> {
    batch.clear();
    let mut have_lines = false;
    while batch.len() < max_chunks {
        let mut c = Chunk {
            first_line: *line_no + 1,
            text: Vec::new(),
        };
        let mut n = 0;
        let mut more = true;
        while n < CHUNK_LINES {
            if have_lines && input.buffer().is_empty() {
                more = false; // flush what we have before blocking
                break;
            }
            let got = input
                .read_until(b'\n', &mut c.text)
                .map_err(|e| CliError::input(format!("cannot read stdin: {e}")))?;
            if got == 0 {
                if n > 0 {
                    batch.push(c);
                }
                return Ok(false);
            }
            n += 1;
            *line_no += 1;
            have_lines = true;
        }
        if n > 0 {
            batch.push(c);
        }
        if !more {
            break;
        }
    }
    Ok(true)
}

/// Evaluates the queries of `input` and writes the results to `output`.
pub fn stream<R: Read, W: Write>(ev: &Evaluator, second: bool, input: R, output: W) -> CliResult {
    let mut input = BufReader::with_capacity(1 << 20, input);
    let mut output = std::io::BufWriter::with_capacity(1 << 16, output);
    let max_chunks = 4 * rayon::current_num_threads().max(1);
    let mut line_no = 0u64;
    let mut batch = Vec::with_capacity(max_chunks);
    loop {
        let more = read_batch(&mut input, &mut line_no, max_chunks, &mut batch)?;
        let done: Vec<Done> = if batch.len() == 1 {
            vec![process(ev, second, &batch[0])]
        } else {
            batch.par_iter().map(|c| process(ev, second, c)).collect()
        };
        for d in done {
            output
                .write_all(d.out.as_bytes())
                .map_err(|e| CliError::write(&e))?;
            if let Some((no, reason)) = d.error {
                output.flush().map_err(|e| CliError::write(&e))?;
                return Err(CliError::input(format!("stdin line {no}: {reason}")));
            }
        }
        output.flush().map_err(|e| CliError::write(&e))?;
        if !more {
            return Ok(());
        }
    }
}
