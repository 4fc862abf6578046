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

use crate::context::{build_tables, with_context, BuildError, Context};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::numfmt::push_eval_line;
use crate::io::query::{check, is_skipped, parse_eval_line, Surface};
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use ccss_core::eval::{FeatureCache, Query};
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::mesh::weights::Weights;
use ccss_core::{Error, Eval, FeatureEvaluator, TableSet};
use rayon::prelude::*;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::PathBuf;
use std::sync::OnceLock;

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
up to 1; a bad line fails with 'ccss: error: W.tsv line N: <reason>' (exit code 2). \
Open meshes, creases, corners, holes and non-manifold parts are evaluated exactly with \
OpenSubdiv's rules: the file's OpenSubdiv tags ('t crease a b s' (vertex pairs), \
't corner v s', 't hole f', 't interpolateboundary 0|1|2' (0 none, 1 edge-and-corner, 2 \
edge-only, as OpenSubdiv's shape files), 't creasemethod chaikin|normal', \
't smoothtriangles smooth|catmark'; vertex and face numbers 0-based in file order; \
hierarchical edits are ignored with a warning) are honoured, and --boundary \
none|edge|edge-corner and --creasing uniform|chaikin override the file's options \
(defaults: edge, uniform). A query on a hole fails like a bad line. General vertex \
weights are not supported on such meshes.";

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
    /// Boundary interpolation (overrides 't interpolateboundary'):
    /// none, edge (edge-only) or edge-corner.
    #[arg(long, value_name = "MODE")]
    pub boundary: Option<BoundaryArg>,
    /// Creasing method (overrides 't creasemethod'): uniform or chaikin.
    #[arg(long, value_name = "METHOD")]
    pub creasing: Option<CreasingArg>,
    #[command(flatten)]
    pub cache: CacheArgs,
}

/// How deep the feature evaluator caches (`FeatureCache`; meshes with
/// tags, boundaries or holes only).
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct CacheArgs {
    /// Cache tree depth below a level-1 face of the feature evaluator
    /// (0-16; default 10, `FeatureCache`'s). Deeper: fewer points next to
    /// irregular corners refined at each query, more memory and build
    /// time; 2 is the least memory (the cache before the tree).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=16))]
    pub cache_depth: Option<u32>,
    /// Most split pieces per level-1 face of the cache tree (default 64,
    /// `FeatureCache`'s; taken depth first, so a small budget leaves
    /// parts of semi-sharp edges to local refinement).
    #[arg(long, value_name = "N")]
    pub cache_nodes: Option<u32>,
}

impl CacheArgs {
    /// The cache options: the given values over the defaults.
    pub fn cache(&self) -> FeatureCache {
        let d = FeatureCache::default();
        FeatureCache {
            depth: self.cache_depth.unwrap_or(d.depth),
            nodes_per_face: self.cache_nodes.unwrap_or(d.nodes_per_face),
        }
    }
}

/// `--boundary` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum BoundaryArg {
    /// Faces at un-sharpened boundary vertices are holes.
    None,
    /// Boundary edges are infinitely sharp.
    Edge,
    /// Also one-face corners are infinitely sharp.
    EdgeCorner,
}

/// `--creasing` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum CreasingArg {
    /// Sharpness decreases by one per level.
    Uniform,
    /// Chaikin averaging at each end.
    Chaikin,
}

/// Runs the verb on stdin/stdout.
pub fn run(a: &EvalArgs) -> CliResult {
    let second = a.second;
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let forced = a.boundary.is_some() || a.creasing.is_some();
    let smooth = smooth_or_feature(&mesh, &a.weights, forced, |ctx| {
        let stdin = std::io::stdin().lock();
        let stdout = std::io::stdout().lock();
        stream(&ctx.evaluator, second, stdin, stdout)
    })?;
    if let Some(r) = smooth {
        return Ok(r);
    }
    with_feature_mesh_cached(&mesh, a.boundary, a.creasing, a.cache.cache(), |fe| {
        let stdin = std::io::stdin().lock();
        let stdout = std::io::stdout().lock();
        stream(fe, second, stdin, stdout)
    })
}

/// The routing of the verbs that honour tags (`eval`, `tessellate`): a
/// mesh without tags or `--boundary`/`--creasing` that builds as a closed
/// manifold runs `smooth` on its smooth context (`Some`); an open,
/// non-manifold or high-valence one, or one with tags or overrides, needs
/// the feature path (`None`; the caller runs [`with_feature_mesh`]), which
/// does not take general vertex weights (an error).
/// The eigen tables of the standard rules, built once per process
/// (`ccss boolean` tessellates both solids once per pass); `None` for
/// other rules.
fn standard_tables(w: &Weights) -> CliResult<Option<&'static TableSet>> {
    static STANDARD: OnceLock<Box<TableSet>> = OnceLock::new();
    if *w != Weights::STANDARD {
        return Ok(None);
    }
    if let Some(t) = STANDARD.get() {
        return Ok(Some(t));
    }
    let (t, _) = build_tables(w)?;
    Ok(Some(STANDARD.get_or_init(|| t)))
}

pub fn smooth_or_feature<R>(
    mesh: &Mesh,
    weights: &WeightsArg,
    forced: bool,
    smooth: impl for<'c> FnOnce(&Context<'c>) -> CliResult<R>,
) -> CliResult<Option<R>> {
    if !mesh.tags.any() && !forced {
        let w = weights.load()?;
        let own;
        let tables = match standard_tables(&w)? {
            Some(t) => t,
            None => {
                own = build_tables(&w)?.0;
                &*own
            }
        };
        match with_context(mesh, tables, smooth) {
            Ok(r) => return r.map(Some),
            // Open, non-manifold or high-valence meshes: the feature path.
            Err(BuildError::Topology(
                Error::BoundaryEdge { .. }
                | Error::NonManifoldEdge { .. }
                | Error::NonManifoldVertex { .. }
                | Error::InconsistentOrientation { .. }
                | Error::UnusedVertex { .. }
                | Error::UnsupportedValence { .. },
            )) if weights.weights.is_none() => {}
            Err(e) => return Err(e.into_cli(mesh)),
        }
    }
    if weights.weights.is_some() {
        return Err(CliError::input(format!(
            "{}: general vertex weights (--weights) are not supported on meshes with \
             boundaries, creases, corners, holes or non-manifold parts",
            mesh.name
        )));
    }
    Ok(None)
}

/// Builds the feature mesh of `mesh` with its tags (file vertex numbers
/// mapped to mesh vertices) and the option overrides, and runs `f` on its
/// evaluator.
pub fn with_feature_mesh<R>(
    mesh: &Mesh,
    boundary: Option<BoundaryArg>,
    creasing: Option<CreasingArg>,
    f: impl FnOnce(&FeatureEvaluator) -> CliResult<R>,
) -> CliResult<R> {
    with_feature_mesh_cached(mesh, boundary, creasing, FeatureCache::default(), f)
}

/// [`with_feature_mesh`] with the evaluator's cache options.
pub fn with_feature_mesh_cached<R>(
    mesh: &Mesh,
    boundary: Option<BoundaryArg>,
    creasing: Option<CreasingArg>,
    cache: FeatureCache,
    f: impl FnOnce(&FeatureEvaluator) -> CliResult<R>,
) -> CliResult<R> {
    with_feature_mesh_only(mesh, boundary, creasing, |fm| {
        let (tables, _) = build_tables(&ccss_core::Weights::STANDARD)?;
        let mut emem = words(FeatureEvaluator::required_bytes_with(
            fm,
            Some(&tables),
            cache,
        ));
        let fe = FeatureEvaluator::build_with(fm, Some(&tables), cache, &mut emem)
            .map_err(|e| mesh.error(e))?;
        f(&fe)
    })
}

/// Builds the feature mesh of `mesh` with its tags (file vertex numbers
/// mapped to mesh vertices) and the option overrides, and runs `f` on it.
pub fn with_feature_mesh_only<R>(
    mesh: &Mesh,
    boundary: Option<BoundaryArg>,
    creasing: Option<CreasingArg>,
    f: impl FnOnce(&FeatureMesh) -> CliResult<R>,
) -> CliResult<R> {
    let name = &mesh.name;
    let t = &mesh.tags;
    // v-line number -> mesh vertex.
    let mut vertex_of_line = vec![u32::MAX; mesh.obj_vertex_lines];
    match &mesh.obj_vertex {
        Some(ov) => {
            for (v, &line) in ov.iter().enumerate() {
                vertex_of_line[line as usize] = v as u32;
            }
        }
        None if t.creases.is_empty() && t.corners.is_empty() => {}
        None => {
            return Err(CliError::input(format!(
                "{name}: cannot map the tags' vertex numbers to the mesh"
            )))
        }
    }
    let vertex = |x: u32, line: usize| {
        vertex_of_line
            .get(x as usize)
            .copied()
            .filter(|&v| v != u32::MAX)
            .ok_or_else(|| {
                CliError::input(format!(
                    "{name}: line {line}: vertex {x} does not exist or no face uses it"
                ))
            })
    };
    let mut cv = Vec::with_capacity(2 * t.creases.len());
    let mut cs = Vec::with_capacity(t.creases.len());
    for &(x, y, s, line) in &t.creases {
        cv.push(vertex(x, line)?);
        cv.push(vertex(y, line)?);
        cs.push(s);
    }
    let mut kv = Vec::with_capacity(t.corners.len());
    let mut ks = Vec::with_capacity(t.corners.len());
    for &(x, s, line) in &t.corners {
        kv.push(vertex(x, line)?);
        ks.push(s);
    }
    let mut holes = Vec::with_capacity(t.holes.len());
    for &(h, line) in &t.holes {
        if h as usize >= mesh.num_faces() {
            return Err(CliError::input(format!(
                "{name}: line {line}: hole on face {h}, but the mesh has {} faces",
                mesh.num_faces()
            )));
        }
        holes.push(h);
    }
    let boundary = match boundary {
        Some(BoundaryArg::None) => Boundary::None,
        Some(BoundaryArg::Edge) => Boundary::EdgeOnly,
        Some(BoundaryArg::EdgeCorner) => Boundary::EdgeAndCorner,
        None => t.boundary.unwrap_or_default(),
    };
    let creasing = match creasing {
        Some(CreasingArg::Uniform) => Creasing::Uniform,
        Some(CreasingArg::Chaikin) => Creasing::Chaikin,
        None => t.creasing.unwrap_or_default(),
    };
    let tags = FeatureInput {
        crease_vertices: &cv,
        crease_sharpness: &cs,
        corner_vertices: &kv,
        corner_sharpness: &ks,
        holes: &holes,
        options: FeatureOptions {
            boundary,
            creasing,
            smooth_triangles: t.smooth_triangles.unwrap_or(false),
        },
    };
    let input = mesh.input();
    let need = FeatureMesh::required_bytes(&input).map_err(|e| mesh.error(e))?;
    let mut mem = words(need);
    let fm = FeatureMesh::build(&input, &tags, &mut mem).map_err(|e| match e {
        Error::NotAnEdge { v0, v1 } => {
            let line = t
                .creases
                .iter()
                .zip(cv.chunks(2))
                .find(|(_, p)| (p[0] == v0 && p[1] == v1) || (p[0] == v1 && p[1] == v0))
                .map(|(c, _)| c.3)
                .unwrap_or(0);
            CliError::input(format!(
                "{name}: line {line}: crease on vertices {} and {}, which no edge joins",
                mesh.obj_vertex(v0),
                mesh.obj_vertex(v1)
            ))
        }
        other => mesh.error(other),
    })?;
    f(&fm)
}

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

fn process<S: Surface + ?Sized>(ev: &S, second: bool, c: &Chunk) -> Done {
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
    if let Err((i, e)) = ev.eval_all(&queries, second, &mut evals) {
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
pub fn stream<S: Surface + ?Sized, R: Read, W: Write>(
    ev: &S,
    second: bool,
    input: R,
    output: W,
) -> CliResult {
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
