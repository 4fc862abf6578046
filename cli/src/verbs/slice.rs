//! `ccss slice --z0 Z --dz D [--layers K] --eps E MESH.obj -o OUT`: planar
//! sections of the solid (ccss-core's `query::slice_band`: bands of up to
//! 64 layers per walk of the cells), as text or SVG.

use crate::context::build_tables;
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::progress::Progress;
use crate::surface::{with_surface, FeatureArgs, SurfaceJob};
use ccss_core::query::{
    band_layer, slice_band, slice_layer, slice_segment_count, slice_write, Contour, PlaneStack,
    QuerySurface, QueryWork, SliceOptions, SliceSegment, SliceStats, MAX_BAND,
};
use ccss_core::Weights;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Planar slices of the closed solid bounded by the limit surface, at z = z0 + k dz for k = 0 .. \
K-1 (--layers K; default: every layer up to the top of the control points' box), as closed \
polylines within Hausdorff distance --eps (model units) of the exact section curves: every \
point of the exact section is within eps of a polyline and every polyline point within eps \
of the exact section (certified by the guaranteed cell bounds; polyline vertices are exact \
limit points). Contours are oriented: outer boundaries counter-clockwise seen from +z, holes \
clockwise. Output -o OUT: OUT.svg writes one SVG with a group per layer (<g id=\"layer-k\" \
data-z=\"z\">, one even-odd path per layer, y up); any other name writes text: per layer a \
line 'layer k z', then per contour 'contour outer|hole n' followed by n lines 'x y' (numbers as 'ccss eval' writes them). The solid must be closed (an open mesh fails with the \
offending edge or hole face). OpenSubdiv tags ('t crease', 't corner', 't hole', \
't interpolateboundary', 't creasemethod') and --boundary / --creasing are honoured. Layers \
are sliced in bands of up to 64 per walk of the surface's cells (the same contours as one \
layer at a time, the descent shared); bands run on all cores; a progress bar shows on a \
terminal.";

/// Arguments of `ccss slice`.
#[derive(clap::Args, Debug)]
pub struct SliceArgs {
    /// Closed polygon mesh (OBJ; OpenSubdiv tags honoured).
    pub mesh: PathBuf,
    /// Height of the first layer.
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub z0: f64,
    /// Distance between layers (> 0).
    #[arg(long, value_name = "D")]
    pub dz: f64,
    /// Number of layers (default: up to the top of the control box).
    #[arg(long, value_name = "K")]
    pub layers: Option<usize>,
    /// Hausdorff bound of the polylines (model units, > 0).
    #[arg(long, value_name = "E")]
    pub eps: f64,
    /// Work budget: cells one layer's walk may visit before it stops with
    /// `work limit exceeded` (docs/WORST_CASE.md).
    #[arg(long, value_name = "N", default_value_t = ccss_core::query::MAX_CELLS)]
    pub max_cells: u64,
    /// Output file: .svg for SVG, anything else for text.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// One sliced layer.
struct Layer {
    z: f64,
    points: Vec<[f64; 2]>,
    contours: Vec<Contour>,
}

/// Slices one plane with fresh buffers of the exact sizes (names the
/// failing layer of a band that failed).
fn slice_one<S: QuerySurface + ?Sized>(
    ev: &S,
    stack: &PlaneStack,
    k: usize,
    o: &SliceOptions,
    w: &mut QueryWork,
) -> Result<Layer, ccss_core::Error> {
    let plane = stack.layer(k);
    let o = *o;
    let n = slice_segment_count(ev, &plane, &o, w)?;
    let mut segs = vec![SliceSegment::default(); n];
    let st = slice_layer(ev, &plane, &o, w, &mut segs)?;
    let mut points = vec![[0.0; 2]; st.points];
    let mut contours = vec![Contour::default(); st.contours];
    slice_write(&mut segs, &mut points, &mut contours)?;
    Ok(Layer {
        z: plane.offset,
        points,
        contours,
    })
}

/// Slices layers `first .. first + count` in one band walk (scratch sized
/// by the band's own size error).
fn slice_bands<S: QuerySurface + ?Sized>(
    ev: &S,
    stack: &PlaneStack,
    first: usize,
    count: usize,
    o: &SliceOptions,
    w: &mut QueryWork,
) -> Result<Vec<Layer>, ccss_core::Error> {
    let o = *o;
    let mut stats = vec![SliceStats::default(); count];
    let n = match slice_band(ev, stack, first, &o, w, &mut [], &mut stats) {
        Err(ccss_core::Error::BufferTooSmall { required }) => required,
        r => r?,
    };
    let mut segs = vec![SliceSegment::default(); n];
    slice_band(ev, stack, first, &o, w, &mut segs, &mut stats)?;
    (0..count)
        .map(|i| {
            let st = stats[i];
            let mut points = vec![[0.0; 2]; st.points];
            let mut contours = vec![Contour::default(); st.contours];
            slice_write(band_layer(&mut segs, &stats, i), &mut points, &mut contours)?;
            Ok(Layer {
                z: stack.layer(first + i).offset,
                points,
                contours,
            })
        })
        .collect()
}

fn text(layers: &[Layer]) -> String {
    let mut s = String::new();
    for (k, l) in layers.iter().enumerate() {
        let _ = writeln!(s, "layer {k} {:.16e}", l.z);
        for c in &l.contours {
            let _ = writeln!(
                s,
                "contour {} {}",
                if c.outer { "outer" } else { "hole" },
                c.len
            );
            for p in &l.points[c.start as usize..(c.start + c.len) as usize] {
                let _ = writeln!(s, "{:.16e} {:.16e}", p[0], p[1]);
            }
        }
    }
    s
}

fn svg(layers: &[Layer]) -> String {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in layers.iter().flat_map(|l| l.points.iter()) {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    if !lo[0].is_finite() {
        lo = [0.0; 2];
        hi = [1.0; 2];
    }
    let (w, h) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
    let m = 0.02 * w.max(h);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\">",
        lo[0] - m,
        -hi[1] - m,
        w + 2.0 * m,
        h + 2.0 * m
    );
    let stroke = 0.002 * w.max(h);
    for (k, l) in layers.iter().enumerate() {
        let _ = write!(
            s,
            "<g id=\"layer-{k}\" data-z=\"{}\" transform=\"scale(1,-1)\"><path fill-rule=\"evenodd\" fill=\"none\" stroke=\"black\" stroke-width=\"{stroke}\" d=\"",
            l.z
        );
        for c in &l.contours {
            let pts = &l.points[c.start as usize..(c.start + c.len) as usize];
            for (i, p) in pts.iter().enumerate() {
                let _ = write!(s, "{}{} {} ", if i == 0 { "M" } else { "L" }, p[0], p[1]);
            }
            s.push_str("Z ");
        }
        s.push_str("\"/></g>\n");
    }
    s.push_str("</svg>\n");
    s
}

/// Runs the verb.
pub fn run(a: &SliceArgs) -> CliResult {
    if !(a.dz > 0.0 && a.dz.is_finite()) {
        return Err(CliError::input("--dz must be positive and finite"));
    }
    if !(a.eps > 0.0 && a.eps.is_finite()) {
        return Err(CliError::input("--eps must be positive and finite"));
    }
    if !a.z0.is_finite() {
        return Err(CliError::input("--z0 must be finite"));
    }
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let ztop = mesh
        .positions
        .chunks_exact(3)
        .map(|p| p[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let k = match a.layers {
        Some(0) => return Err(CliError::input("--layers must be at least 1")),
        Some(k) => k,
        None if ztop < a.z0 => 1,
        None => ((ztop - a.z0) / a.dz).floor() as usize + 1,
    };
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let opts = SliceOptions {
        eps: a.eps,
        max_cells: a.max_cells,
    };
    let job = Job {
        a,
        k,
        opts,
        name: &mesh.name,
    };
    let layers = with_surface(&mesh, &tables, a.features, job)?;
    let is_svg = a
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    let body = if is_svg { svg(&layers) } else { text(&layers) };
    std::fs::write(&a.output, body)
        .map_err(|e| CliError::failure(format!("{}: {e}", a.output.display())))
}

/// The verb's work on either surface.
struct Job<'j> {
    a: &'j SliceArgs,
    k: usize,
    opts: SliceOptions,
    name: &'j str,
}

impl SurfaceJob<Vec<Layer>> for Job<'_> {
    fn run<S: QuerySurface + Sync + ?Sized>(self, ev: &S, _feature: bool) -> CliResult<Vec<Layer>> {
        crate::surface::with_index(ev, |ev| {
            let (k, opts) = (self.k, self.opts);
            let stack = PlaneStack::z(self.a.z0, self.a.dz);
            let bar = Progress::delayed("{msg} [{bar:40}] {pos}/{len} layers");
            bar.phase("slice", k);
            let bands: Vec<CliResult<Vec<Layer>>> = (0..k.div_ceil(MAX_BAND))
                .into_par_iter()
                .map_init(
                    || Box::new(QueryWork::ZERO),
                    |w, b| {
                        let first = b * MAX_BAND;
                        let count = MAX_BAND.min(k - first);
                        let ls = slice_bands(ev, &stack, first, count, &opts, w).or_else(|_| {
                            // Name the failing layer: one walk per layer.
                            (first..first + count)
                                .map(|i| {
                                    slice_one(ev, &stack, i, &opts, w).map_err(|e| {
                                        let z = stack.layer(i).offset;
                                        CliError::failure(format!(
                                            "{}: layer {i} (z = {z}): {e}",
                                            self.name
                                        ))
                                    })
                                })
                                .collect::<CliResult<Vec<Layer>>>()
                        })?;
                        for _ in 0..count {
                            bar.inc();
                        }
                        Ok(ls)
                    },
                )
                .collect();
            bar.finish();
            let layers: Vec<CliResult<Layer>> = bands
                .into_iter()
                .flat_map(|b| match b {
                    Ok(v) => v.into_iter().map(Ok).collect::<Vec<_>>(),
                    Err(e) => vec![Err(e)],
                })
                .collect();
            layers.into_iter().collect::<CliResult<Vec<Layer>>>()
        })
    }
}
