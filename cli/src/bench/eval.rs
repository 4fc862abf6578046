//! `ccss bench eval MESH.obj`: single-threaded timing of evaluation per
//! class of points (see [`super::classes`]), comparable with the OpenSubdiv
//! harness `bench/osd/osd_eval` on the same points file.
//!
//! Output (stdout), one line each:
//!
//! ```text
//! ccss setup_ms=0.123 tables_ms=4.567
//! ccss class=R points=1000000 ns_per_eval=61.2
//! ccss class=X points=1000000 ns_per_eval=83.4
//! ccss class=X3 points=331234 ns_per_eval=80.1     (X sub-classes, when X has several)
//! ccss checksum=1.2345678901234567e6
//! ```
//!
//! `setup_ms` is topology + evaluator build (the per-mesh work, like OSD's
//! `setup_ms`); `tables_ms` the mesh-independent eigen tables. Each class is
//! timed after a warm-up pass as the median of `--samples` samples, a sample
//! being as many whole passes as last at least 20 ms. The checksum is the sum
//! of all output components of one pass over all points.

use super::classes::{classify_all, FaceClass};
use super::regions;
use super::rng::SplitMix64;
use super::timing::{measure, Api};
use crate::context::{build_tables, with_mesh, Context};
use crate::error::CliResult;
use crate::io::mesh_in::Mesh;
use crate::io::points::{self, Point};
use crate::io::query::POINT_CLASSES;
use crate::io::weights_file::WeightsArg;
use crate::progress::Progress;
use crate::stdout;
use ccss_core::eval::Query;
use ccss_core::Topology;
use std::path::PathBuf;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Time single-threaded evaluation per class of points and print one line per class, \
'ccss class=R points=N ns_per_eval=XX.X' (median over --samples samples, after a warm-up \
pass), then 'ccss checksum=...'. Class R: random points on quads whose 1-ring is fully \
regular (4 corners and all their neighbours of valence 4, all faces around them quads); \
class X: random points on quads with an extraordinary vertex, with sub-class lines X3, X5, \
..., Xmulti (two or more extraordinary vertices) when there are several. Points are drawn \
with SplitMix64 from --seed, --points per class, uniform over the faces of the class and \
uniform in (u, v). --classes adds classes of points (letters, in report order): U uniform \
over all sub-faces (N-gon sub-faces included), M quads with several extraordinary \
vertices, N and D within 1/256 and 2^-20 of an extraordinary vertex, C and K within 1/256 \
and 2^-20 of an N-gon centre (the default RX draws R and X only); --write-points F writes them in the OpenSubdiv harness format \
('face sub u v class', bench/osd/README.md; X lines carry the sub-class as a sixth token, \
which osd_eval ignores) and exits, and --points-file F times the points \
of such a file instead, so that ccss and bench/osd/osd_eval time identical points. A \
progress bar is shown on stderr for long runs when stderr is a terminal. --weights W.tsv \
times the surface of that vertex rule (format: see 'ccss eval --help').";

/// Arguments of `ccss bench eval`.
#[derive(clap::Args, Debug)]
pub struct BenchEvalArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Random points per class (underscores allowed: 1_000_000).
    #[arg(long, default_value = "1000000", value_parser = parse_count)]
    pub points: usize,
    /// Seed of the point generator (SplitMix64).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Time the points of this file (`face sub u v class` lines, the
    /// OpenSubdiv harness format) instead of random ones.
    #[arg(long, value_name = "F", conflicts_with_all = ["points", "seed", "write_points"])]
    pub points_file: Option<PathBuf>,
    /// Write the generated points to F in the harness format and exit
    /// without timing (X lines get a sixth token, the sub-class, which
    /// osd_eval ignores).
    #[arg(long, value_name = "F")]
    pub write_points: Option<PathBuf>,
    /// Also evaluate second derivatives.
    #[arg(long)]
    pub second: bool,
    /// Timed samples per class (the median is reported).
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub samples: u32,
    /// Point classes to draw, in report order: R and X (face classes) and
    /// U, M, N, D, C, K (`bench/regions.rs`: uniform over all sub-faces,
    /// quads with several extraordinary vertices, within 1/256 and 2^-20
    /// of an extraordinary vertex, of an N-gon centre).
    #[arg(long, default_value = "RX", value_parser = parse_classes, conflicts_with = "points_file")]
    pub classes: String,
    /// Evaluator entry point to time.
    #[arg(long, value_enum, default_value_t = Api::Derivs)]
    pub api: Api,
    #[command(flatten)]
    pub weights: WeightsArg,
}

/// Parses a count such as `1000`, `1_000_000`.
fn parse_count(s: &str) -> Result<usize, String> {
    let digits: String = s.chars().filter(|&c| c != '_').collect();
    match digits.parse::<usize>() {
        Ok(n) if n > 0 && !s.starts_with('_') => Ok(n),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err(format!("'{s}' is not a positive integer")),
    }
}

/// Parses `--classes`: distinct letters of [`POINT_CLASSES`].
fn parse_classes(s: &str) -> Result<String, String> {
    for (i, c) in s.char_indices() {
        if !POINT_CLASSES.contains(c) {
            return Err(format!("'{c}' is not a class letter ({POINT_CLASSES})"));
        }
        if s[..i].contains(c) {
            return Err(format!("class '{c}' given twice"));
        }
    }
    if s.is_empty() {
        return Err("no class given".into());
    }
    Ok(s.to_string())
}

/// Random points: `n` per class of `letters`; R and X uniform over the
/// faces of the class, the others as [`regions`] draws them; uniform (u, v).
fn generate(
    t: &Topology,
    classes: &[FaceClass],
    letters: &str,
    n: usize,
    seed: u64,
    name: &str,
) -> Vec<Point> {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::new();
    for letter in letters.chars() {
        if letter != 'R' && letter != 'X' {
            let qs = regions::draw(t, letter, n, &mut rng);
            if qs.is_empty() {
                let what = regions::CLASSES
                    .iter()
                    .find(|c| c.0 == letter)
                    .map_or("", |c| c.1);
                eprintln!("ccss: note: {name}: no points can lie {what}; class {letter} skipped");
            }
            pts.extend(qs.into_iter().map(|q| (q, letter)));
            continue;
        }
        let what = if letter == 'R' {
            "a fully regular 1-ring"
        } else {
            "an extraordinary vertex"
        };
        let pool: Vec<u32> = classes
            .iter()
            .enumerate()
            .filter(|(_, c)| match c {
                FaceClass::R => letter == 'R',
                FaceClass::X(_) => letter == 'X',
                FaceClass::None => false,
            })
            .map(|(f, _)| f as u32)
            .collect();
        if pool.is_empty() {
            eprintln!("ccss: note: {name}: no quad face with {what}; class {letter} skipped");
            continue;
        }
        for _ in 0..n {
            let face = pool[rng.below(pool.len())];
            let u = rng.next_f64();
            let v = rng.next_f64();
            pts.push((Query { face, sub: 0, u, v }, letter));
        }
    }
    pts
}

/// The timed groups: R, X, the X sub-classes when there are several, then
/// the other classes in the order of their first point.
fn groups(pts: &[Point], classes: &[FaceClass]) -> Vec<(String, Vec<Query>)> {
    let pick = |l: char| {
        pts.iter()
            .filter(|p| p.1 == l)
            .map(|p| p.0)
            .collect::<Vec<_>>()
    };
    let x = pick('X');
    let mut subs: Vec<(String, Vec<Query>)> = Vec::new();
    for q in &x {
        let label = match classes.get(q.face as usize) {
            Some(FaceClass::X(l)) => l.clone(),
            _ => "Xother".to_string(),
        };
        match subs.iter_mut().find(|s| s.0 == label) {
            Some(s) => s.1.push(*q),
            None => subs.push((label, vec![*q])),
        }
    }
    subs.sort_by_key(|(l, _)| (l[1..].parse::<u32>().unwrap_or(u32::MAX), l.clone()));
    let mut g = vec![("R".to_string(), pick('R')), ("X".to_string(), x)];
    if subs.len() > 1 {
        g.extend(subs);
    }
    let mut others: Vec<char> = Vec::new();
    for p in pts {
        if p.1 != 'R' && p.1 != 'X' && !others.contains(&p.1) {
            others.push(p.1);
        }
    }
    g.extend(others.into_iter().map(|l| (l.to_string(), pick(l))));
    g
}

fn bench(a: &BenchEvalArgs, mesh: &Mesh, ctx: &Context, tables_ms: f64) -> CliResult {
    let ev = &ctx.evaluator;
    let classes = classify_all(&ctx.topology);
    let pts = match &a.points_file {
        Some(f) => points::read(f, ev)?,
        None => generate(
            &ctx.topology,
            &classes,
            &a.classes,
            a.points,
            a.seed,
            &mesh.name,
        ),
    };
    if let Some(w) = &a.write_points {
        points::write(w, &pts, |q| match classes.get(q.face as usize) {
            Some(FaceClass::X(l)) => Some(l.as_str()),
            _ => None,
        })?;
        let count = |l: char| pts.iter().filter(|p| p.1 == l).count();
        let per: Vec<String> = a
            .classes
            .chars()
            .map(|l| format!("{l}={}", count(l)))
            .collect();
        return stdout::line(&format!(
            "ccss wrote {} points to {} ({})",
            pts.len(),
            w.display(),
            per.join(", ")
        ));
    }
    let setup_ms = (ctx.timings.topology + ctx.timings.evaluator).as_secs_f64() * 1e3;
    stdout::line(&format!(
        "ccss setup_ms={setup_ms:.3} tables_ms={tables_ms:.3}"
    ))?;
    let groups = groups(&pts, &classes);
    let samples = a.samples as usize;
    let evals: usize = groups.iter().map(|g| g.1.len()).sum::<usize>() * (samples + 1);
    let total = groups.iter().filter(|g| !g.1.is_empty()).count() * samples;
    let progress = Progress::new(
        "timing class {msg:7} [{bar:40}] {pos}/{len} samples",
        total as u64,
        evals >= 5_000_000,
    );
    let mut checksum = 0.0;
    for (label, qs) in &groups {
        if qs.is_empty() {
            stdout::line(&format!("ccss class={label} points=0 ns_per_eval=nan"))?;
            continue;
        }
        let counted = label.len() == 1;
        progress.message(label.clone());
        let m = measure(ev, qs, a.second, a.api, samples, || progress.inc());
        if counted {
            checksum += m.checksum;
        }
        let line = format!(
            "ccss class={label} points={} ns_per_eval={:.1}",
            qs.len(),
            m.ns_per_eval
        );
        progress.suspend(|| stdout::line(&line))?;
    }
    progress.finish();
    stdout::line(&format!("ccss checksum={checksum:.16e}"))
}

/// Runs the verb.
pub fn run(a: &BenchEvalArgs) -> CliResult {
    let weights = a.weights.load()?;
    let mesh = Mesh::load(&a.mesh)?;
    let (tables, t_tables) = build_tables(&weights)?;
    let tables_ms = t_tables.as_secs_f64() * 1e3;
    with_mesh(&mesh, &tables, |ctx| bench(a, &mesh, ctx, tables_ms))
}

#[cfg(test)]
mod tests {
    use super::parse_count;

    #[test]
    fn counts() {
        assert_eq!(parse_count("1_000_000"), Ok(1_000_000));
        assert_eq!(parse_count("17"), Ok(17));
        assert!(parse_count("0").is_err());
        assert!(parse_count("1e6").is_err());
        assert!(parse_count("_1").is_err());
    }

    #[test]
    fn classes() {
        use super::parse_classes;
        assert_eq!(parse_classes("RXND").as_deref(), Ok("RXND"));
        assert!(parse_classes("RR").is_err());
        assert!(parse_classes("RQ").is_err());
        assert!(parse_classes("").is_err());
    }
}
