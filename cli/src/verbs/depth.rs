//! `ccss depth --eps E MESH.obj [--method old|new|tight|best] [--weights W.tsv]`:
//! subdivision depth for a tolerance per (sub-)face, and
//! `ccss depth --rates N|all [--verbose] [--weights W.tsv]`: the per-valence
//! constants behind it (Cheng & Lai report, ch. 3).
//!
//! Depth output (stdout), one line per slot in slot order (faces in file
//! order, the sub-faces of an N-gon consecutively), then one summary line:
//!
//! ```text
//! 0 6
//! 4.0 7            (sub-face 0 of the pentagon face 4)
//! ...
//! # eps=0.01 method=best faces=7 slots=15 max_depth=7 mean_depth=5.667 histogram=5:5,7:10 seconds=0.000412 build_seconds=0.000301 depth_seconds=0.000111
//! ```
//!
//! A depth the method cannot bound (possible only with general weights whose
//! `r2 >= 1`) prints as `inf`. `build_seconds` is topology + evaluator build
//! (the per-mesh work; the eigen tables are not counted), `depth_seconds`
//! the `Evaluator::depths` call, `seconds` their sum.
//!
//! Rates output: `n r1 r2` per valence (`{:.6}`), with `--verbose` also
//! `c_new c_lemma10 r_old c_old`.

use crate::context::{build_tables, with_context, BuildError};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::stdout;
use crate::surface::FeatureArgs;
use crate::verbs::eval::with_feature_mesh;
use ccss_core::bounds::depth::Method;
use ccss_core::bounds::feature_depth::feature_depth;
use ccss_core::{Error, TableSet, Weights, MAX_VALENCE};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::Instant;

/// The bound used for extraordinary patches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    /// Theorem 6 (Lemmas 2-5); standard weights only.
    Old,
    /// Theorem 11 (the matrix technique, rates r1 and r2).
    New,
    /// Bezier-net distances of the exactly subdivided control faces
    /// (regular patches and ring regions) and the split eigen-expansion
    /// bound of the corner face, or Theorem 11 with measured norms where
    /// smaller (never deeper than new).
    Tight,
    /// The smallest valid depth of all methods.
    Best,
}

impl MethodArg {
    fn core(self) -> Method {
        match self {
            MethodArg::Old => Method::Old,
            MethodArg::New => Method::New,
            MethodArg::Tight => Method::Tight,
            MethodArg::Best => Method::Best,
        }
    }

    fn name(self) -> &'static str {
        match self {
            MethodArg::Old => "old",
            MethodArg::New => "new",
            MethodArg::Tight => "tight",
            MethodArg::Best => "best",
        }
    }
}

/// Which valences `--rates` prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RatesArg {
    /// One valence.
    One(usize),
    /// Every valence 3..=MAX_VALENCE.
    All,
}

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Subdivision depth for a tolerance (Cheng & Lai report, ch. 3): for each (sub-)face, the number \
of uniform Catmull-Clark steps of the base mesh after which its control faces (as bilinear \
patches) lie within --eps of the limit surface. Prints one line 'face depth' per quad and \
'face.sub depth' per sub-face of an N-gon (N != 4), in face order, then a summary line \
'# eps=E method=M faces=F slots=S max_depth=D mean_depth=X histogram=d:count,... seconds=T \
build_seconds=B depth_seconds=C' (mean over the printed lines; T = B + C, B the topology and \
evaluator build, C the depth computation; the eigen tables are not counted). Regular patches \
use Lemma 1 (depth = ceil(log4(M / (3 eps))), M the second-order norm of the 4x4 control \
points), with tight and best also the Bezier-net distance of each subdivided control face \
(up to 3 steps, Lemma 1 beyond); extraordinary ones the --method: old (Theorem 6, rate and constant of Lemmas 2-5; \
standard weights only), new (Theorem 11, the matrix technique with rates r1 = \
||A Lambda A^+||, r2 = ||A Lambda^2 A^+|| and the supremum constant c_new), tight (the Bezier-net \
distances of the ring-region faces, the corner face by the eigen expansion with its cell split \
into ring regions, or Theorem 11's constant with the measured norms where smaller; never \
deeper than new) or best (the smallest of all; default). A depth that cannot be bounded (only with \
general weights where r2 >= 1) prints as 'inf'. --weights W.tsv (the format of 'ccss eval \
--help') computes the depths of that vertex rule's surface; --method old then requires every \
valence to keep the standard rule. --rates N prints 'n r1 r2' for valence N (3..=max \
valence), --rates all for every valence, and --verbose adds 'c_new c_lemma10 r_old c_old' \
(c_lemma10: the report's Lemma 10 constant; r_old, c_old: 0 where the old technique does not \
apply). Bad or missing --eps is a usage error (exit code 2). Meshes with OpenSubdiv tags ('t \
crease', 't corner', 't hole', 't interpolateboundary', 't creasemethod'), open or \
non-manifold meshes, and --boundary / --creasing use OpenSubdiv's rules (method=features in \
the summary): Lemma 1 on each B-spline piece (phantom points across sharp edges included), and \
next to crease ends, corners, darts, extraordinary and semi-sharp vertices the diameter of the \
convex hull of the local control points (it shrinks by half per step, so depths there are \
about twice the regular ones); hole faces print 0.";

/// Arguments of `ccss depth`.
#[derive(clap::Args, Debug)]
pub struct DepthArgs {
    /// Closed polygon mesh (OBJ).
    #[arg(required_unless_present = "rates", conflicts_with = "rates")]
    pub mesh: Option<PathBuf>,
    /// Tolerance: the largest distance allowed between the refined control
    /// mesh and the limit surface (positive and finite).
    #[arg(long, value_name = "E", value_parser = parse_eps, allow_negative_numbers = true,
          required_unless_present = "rates", conflicts_with = "rates")]
    pub eps: Option<f64>,
    /// Bound used for extraordinary patches.
    #[arg(long, value_enum, default_value_t = MethodArg::Best, conflicts_with = "rates")]
    pub method: MethodArg,
    /// Print the depth constants of valence N (3..=max valence), or of all
    /// valences, instead of depths: 'n r1 r2'.
    #[arg(long, value_name = "N|all", value_parser = parse_rates)]
    pub rates: Option<RatesArg>,
    /// With --rates: also print 'c_new c_lemma10 r_old c_old'.
    #[arg(long, conflicts_with_all = ["mesh", "eps"])]
    pub verbose: bool,
    #[command(flatten)]
    pub weights: WeightsArg,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// Parses `--eps`: a positive finite number.
fn parse_eps(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(e) if e.is_finite() && e > 0.0 => Ok(e),
        Ok(_) => Err("eps must be positive and finite".into()),
        Err(_) => Err(format!("'{s}' is not a number")),
    }
}

/// Parses `--rates`: a valence in 3..=MAX_VALENCE or `all`.
fn parse_rates(s: &str) -> Result<RatesArg, String> {
    if s == "all" {
        return Ok(RatesArg::All);
    }
    match s.parse::<usize>() {
        Ok(n) if (3..=MAX_VALENCE).contains(&n) => Ok(RatesArg::One(n)),
        _ => Err(format!(
            "expected a valence in 3..={MAX_VALENCE} or 'all', got '{s}'"
        )),
    }
}

/// Runs the verb.
pub fn run(a: &DepthArgs) -> CliResult {
    let weights = a.weights.load()?;
    if let Some(r) = a.rates {
        return rates(&weights, r, a.verbose);
    }
    // Both are present unless --rates (clap's required_unless_present).
    let (Some(path), Some(eps)) = (&a.mesh, a.eps) else {
        return Err(CliError::input(
            "give --eps E and a mesh, or --rates N (see 'ccss depth --help')",
        ));
    };
    if a.method == MethodArg::Old {
        if let Some(n) = (3..=MAX_VALENCE).find(|&n| !weights.is_standard(n)) {
            let file = a
                .weights
                .weights
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default();
            return Err(CliError::input(format!(
                "--method old needs the standard Catmull-Clark weights (Theorem 6 holds only \
                 for them), but {file} changes valence {n}; use --method new, tight or best"
            )));
        }
    }
    let mesh = Mesh::load_with_tags(path)?;
    let (tables, _) = build_tables(&weights)?;
    let forced = a.features.boundary.is_some() || a.features.creasing.is_some();
    if mesh.tags.any() || forced {
        return feature_depths(a, &mesh, eps);
    }
    let smooth = with_context(&mesh, &tables, |ctx| {
        let ev = &ctx.evaluator;
        let mut d = vec![0u32; ev.num_slots()];
        let t0 = Instant::now();
        ccss_core::bounds::depth::depths(ev, eps, a.method.core(), &mut d).map_err(
            |e| match e {
                ccss_core::Error::InvalidArgument(_) => {
                    CliError::input(format!("{}: {e}", mesh.name))
                }
                _ => CliError::failure(format!("{}: cannot compute depths: {e}", mesh.name)),
            },
        )?;
        let depth_s = t0.elapsed().as_secs_f64();
        let build_s = (ctx.timings.topology + ctx.timings.evaluator).as_secs_f64();
        let subs: Vec<usize> = (0..ev.num_faces()).map(|f| ev.num_subfaces(f)).collect();
        write_depths(&subs, &d, eps, a.method.name(), build_s, depth_s)
    });
    match smooth {
        Ok(r) => r,
        // Open or non-manifold meshes: the feature path (OpenSubdiv's
        // boundary rules).
        Err(BuildError::Topology(
            Error::BoundaryEdge { .. }
            | Error::NonManifoldEdge { .. }
            | Error::NonManifoldVertex { .. }
            | Error::InconsistentOrientation { .. }
            | Error::UnusedVertex { .. }
            | Error::UnsupportedValence { .. },
        )) => feature_depths(a, &mesh, eps),
        Err(e) => Err(e.into_cli(&mesh)),
    }
}

/// Depths of a mesh with features (`ccss_core::bounds::feature_depth`):
/// Lemma 1 on the B-spline pieces (phantoms included), the hull diameter
/// next to special vertices; hole faces print 0.
fn feature_depths(a: &DepthArgs, mesh: &Mesh, eps: f64) -> CliResult {
    if a.weights.weights.is_some() {
        return Err(CliError::input(format!(
            "{}: general vertex weights (--weights) are not supported on meshes with \
             boundaries, creases, corners, holes or non-manifold parts",
            mesh.name
        )));
    }
    let t0 = Instant::now();
    with_feature_mesh(mesh, a.features.boundary, a.features.creasing, |fe| {
        let build_s = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let mut d = Vec::new();
        let mut subs = Vec::with_capacity(fe.num_faces());
        for f in 0..fe.num_faces() {
            let k = fe.num_subfaces(f);
            subs.push(k);
            for s in 0..k {
                match feature_depth(fe, f as u32, s as u32, eps) {
                    Ok(r) => d.push(r.steps.unwrap_or(u32::MAX)),
                    Err(Error::HoleFace { .. }) => d.push(0),
                    Err(e) => return Err(mesh.error(e)),
                }
            }
        }
        let depth_s = t1.elapsed().as_secs_f64();
        write_depths(&subs, &d, eps, "features", build_s, depth_s)
    })
}

/// A depth as printed: the number, or `inf` where no bound exists.
fn push_depth(out: &mut String, d: u32) {
    if d == u32::MAX {
        out.push_str("inf");
    } else {
        let _ = write!(out, "{d}");
    }
}

/// Writes the slot lines and the summary.
/// `subs`: sub-faces per face (`d` holds their depths consecutively).
fn write_depths(
    subs: &[usize],
    d: &[u32],
    eps: f64,
    method: &str,
    build_s: f64,
    depth_s: f64,
) -> CliResult {
    let mut out = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
    let mut line = String::with_capacity(32);
    let mut s0 = 0usize;
    for (f, &k) in subs.iter().enumerate() {
        let first = s0;
        s0 += k;
        for (j, &x) in d[first..first + k].iter().enumerate() {
            line.clear();
            if k == 1 {
                let _ = write!(line, "{f} ");
            } else {
                let _ = write!(line, "{f}.{j} ");
            }
            push_depth(&mut line, x);
            line.push('\n');
            out.write_all(line.as_bytes())
                .map_err(|e| CliError::write(&e))?;
        }
    }
    let mut hist: BTreeMap<u32, usize> = BTreeMap::new();
    for &x in d {
        *hist.entry(x).or_default() += 1;
    }
    let unbounded = hist.contains_key(&u32::MAX);
    let mut s = String::new();
    let _ = write!(
        s,
        "# eps={eps} method={method} faces={} slots={} max_depth=",
        subs.len(),
        d.len()
    );
    push_depth(&mut s, d.iter().copied().max().unwrap_or(0));
    if unbounded {
        s.push_str(" mean_depth=inf");
    } else {
        let sum: u64 = d.iter().map(|&x| x as u64).sum();
        let _ = write!(s, " mean_depth={:.3}", sum as f64 / d.len().max(1) as f64);
    }
    s.push_str(" histogram=");
    for (i, (&k, &c)) in hist.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        push_depth(&mut s, k);
        let _ = write!(s, ":{c}");
    }
    let _ = writeln!(
        s,
        " seconds={:.6} build_seconds={build_s:.6} depth_seconds={depth_s:.6}",
        build_s + depth_s
    );
    out.write_all(s.as_bytes())
        .and_then(|_| out.flush())
        .map_err(|e| CliError::write(&e))
}

/// Prints the rates of the chosen valences.
fn rates(weights: &Weights, which: RatesArg, verbose: bool) -> CliResult {
    let (tables, _) = build_tables(weights)?;
    let valences = match which {
        RatesArg::One(n) => n..=n,
        RatesArg::All => 3..=MAX_VALENCE,
    };
    let mut o = String::new();
    for n in valences {
        rate_line(&mut o, &tables, n, verbose)?;
    }
    stdout::text(&o)
}

fn rate_line(o: &mut String, tables: &TableSet, n: usize, verbose: bool) -> CliResult {
    let r = tables
        .get(n)
        .ok_or_else(|| CliError::failure(format!("no eigen table for valence {n}")))?
        .rates();
    let _ = write!(o, "{n} {:.6} {:.6}", r.r1, r.r2);
    if verbose {
        let _ = write!(
            o,
            " {:.6} {:.6} {:.6} {:.6}",
            r.c_new, r.c_lemma10, r.r_old, r.c_old
        );
    }
    o.push('\n');
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eps_and_rates_parsers() {
        assert_eq!(parse_eps("0.01"), Ok(0.01));
        assert_eq!(parse_eps("1e-3"), Ok(1e-3));
        for bad in ["0", "-0", "-1", "nan", "inf", "-inf"] {
            assert_eq!(
                parse_eps(bad),
                Err("eps must be positive and finite".into()),
                "{bad}"
            );
        }
        assert!(parse_eps("abc")
            .unwrap_err()
            .contains("'abc' is not a number"));
        assert_eq!(parse_rates("5"), Ok(RatesArg::One(5)));
        assert_eq!(parse_rates("all"), Ok(RatesArg::All));
        assert_eq!(
            parse_rates(&MAX_VALENCE.to_string()),
            Ok(RatesArg::One(MAX_VALENCE))
        );
        for bad in ["2", "0", "-3", "x", "ALL", ""] {
            assert!(parse_rates(bad).is_err(), "{bad}");
        }
        assert!(parse_rates(&(MAX_VALENCE + 1).to_string()).is_err());
    }
}
