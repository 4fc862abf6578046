//! `ccss bench query MESH [--rays N] [--points N] [--tol R] [--eps R]
//! [--layers K] [--stack L] [--band B]`: single-threaded throughput of the
//! certified queries. OpenSubdiv tags of the OBJ (creases, corners, holes,
//! boundary options) and `--boundary` / `--creasing` select the feature
//! evaluator, as in the other verbs; the tessellation compared against is
//! then the feature tessellation.
//!
//! Output (stdout), one line per query kind:
//!
//! ```text
//! ccss raycast tol=9.7e-10 rays=2000 hits=1830 first_rays_per_s=.. all_rays_per_s=..
//! ccss closest tol=9.7e-10 points=500 points_per_s=..
//! ccss slice eps=9.7e-4 layers=20 points=.. ms_per_layer=.. tessellate_ms=.. slice_over_tessellate=.. cut_ms_per_layer=.. tessellate_plus_cut_ms_per_layer=..
//! ccss slice_stack eps=9.7e-4 layers=1000 band=64 points=.. stack_ms=.. tessellate_ms=.. stack_over_tessellate=.. eval_floor_ms=.. floor_over_tessellate=..
//! ```
//!
//! The stack line (with `--stack L`, L > 0): the L planes
//! `z = lo + (k + 1/2) (hi - lo) / L` of the control box, sliced in bands
//! of `--band` layers (`query::slice_band`, contours written), timed
//! against the same tessellation in the same run. `eval_floor_ms` is a
//! lower bound for any slicer whose contour points are limit points, as
//! ours are: one exact evaluation (position and first derivatives, the
//! least a root on the surface needs) per point of the stack, at as many
//! random points `(face, sub, u, v)` (the smooth evaluator's batch, or
//! the feature evaluator point by point); `floor_over_tessellate` is its
//! ratio to the tessellation.
//!
//! Rays start on the sphere of radius one diagonal around the centre of the
//! control points' box and aim at random points of the box's inner half;
//! closest-point queries are random points of the box grown by a quarter;
//! tolerances are relative to the box diagonal. Slices are `--layers`
//! planes z = const spread over the box height; `tessellate_ms` is the
//! adaptive tessellation to the same absolute `eps` (size query, build and
//! emission), for the comparison the issue asks for (one layer against one
//! tessellation); `cut_ms_per_layer` is the naive slicer's plane cut of
//! that tessellation's triangles (segments only, no chaining), and
//! `tessellate_plus_cut_ms_per_layer` its cost per layer with the
//! tessellation shared by the layers. SplitMix64 with a fixed seed: the same queries every run.

use super::rng::SplitMix64;
use crate::context::{build_tables, with_mesh};
use crate::error::{CliError, CliResult};
use crate::io::mesh_in::Mesh;
use crate::io::stdin_rows::control_diagonal;
use crate::mem::words;
use crate::progress::Progress;
use crate::stdout;
use crate::surface::FeatureArgs;
use crate::verbs::eval::with_feature_mesh;
use ccss_core::eval::{Eval, Query};
use ccss_core::query::{
    band_layer, closest, ray_all, ray_first, slice_band, slice_layer, slice_write, ClosestOptions,
    Contour, Plane, PlaneStack, QuerySurface, QueryWork, Ray, RayOptions, SliceOptions,
    SliceSegment, SliceStats, MAX_BAND,
};
use ccss_core::tessellate::{Options, Output, Scratch, Tessellation};
use ccss_core::{DVec3, Weights};
use std::path::PathBuf;
use std::time::Instant;

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Time the certified queries on one thread: first hit and all hits of random rays (rays/s), \
closest points of random points (points/s), and planar slices (ms per layer) beside the \
adaptive tessellation to the same absolute eps. Tolerances are relative to the diagonal of \
the control points' box (--tol for rays and closest points, default 1e-9; --eps for slices, \
default 1e-3). Fixed seed: the same queries every run.";

/// Arguments of `ccss bench query`.
#[derive(clap::Args, Debug)]
pub struct BenchQueryArgs {
    /// Closed polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Number of rays.
    #[arg(long, default_value_t = 2000)]
    pub rays: usize,
    /// Number of closest-point queries.
    #[arg(long, default_value_t = 500)]
    pub points: usize,
    /// Ray and closest-point tolerance, relative to the box diagonal.
    #[arg(long, default_value_t = 1e-9)]
    pub tol: f64,
    /// Slice tolerance (Hausdorff), relative to the box diagonal.
    #[arg(long, default_value_t = 1e-3)]
    pub eps: f64,
    /// Number of slice layers.
    #[arg(long, default_value_t = 20)]
    pub layers: usize,
    /// Layers of the whole-stack slice (0: none), sliced in bands.
    #[arg(long, default_value_t = 0)]
    pub stack: usize,
    /// Layers per band of the stack slice (1 to 64): the scratch holds
    /// a band's segments; a stack takes ceil(stack / band) walks.
    #[arg(long, default_value_t = 64)]
    pub band: usize,
    /// Walk every slot instead of the slot index (the walks without
    /// `ccss_core::query::SlotIndex`, for comparison).
    #[arg(long)]
    pub no_index: bool,
    #[command(flatten)]
    pub features: FeatureArgs,
}

/// Runs of the tessellation and of the evaluation floor; the fastest is
/// reported.
const TIMED_RUNS: usize = 5;

/// A tessellation to an absolute bound for the comparison: vertex
/// positions, triangles, vertex count.
type Tess = (Vec<f64>, Vec<u32>, usize);

fn box_of(p: &[f64]) -> (DVec3, DVec3) {
    p.chunks_exact(3).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), q| {
            let q = DVec3::new(q[0], q[1], q[2]);
            (lo.min(q), hi.max(q))
        },
    )
}

/// Times the queries on `ev` through its slot index (built and timed
/// here), or without one under `--no-index`.
fn bench<S: QuerySurface + Sync + ?Sized>(
    a: &BenchQueryArgs,
    mesh: &Mesh,
    ev: &S,
    tessellate: impl Fn(f64) -> Result<Tess, ccss_core::Error>,
    eval_floor: impl Fn(usize) -> Result<f64, ccss_core::Error>,
) -> CliResult {
    if a.no_index {
        return bench_on(a, mesh, ev, tessellate, eval_floor);
    }
    let t0 = Instant::now();
    crate::surface::with_index(ev, |iev| {
        stdout::line(&format!(
            "ccss index nodes={} build_ms={:.3}",
            ccss_core::query::SlotIndex::required_len(ev),
            t0.elapsed().as_secs_f64() * 1e3
        ))?;
        bench_on(a, mesh, iev, tessellate, eval_floor)
    })
}

fn bench_on<S: QuerySurface + ?Sized>(
    a: &BenchQueryArgs,
    mesh: &Mesh,
    ev: &S,
    tessellate: impl Fn(f64) -> Result<Tess, ccss_core::Error>,
    eval_floor: impl Fn(usize) -> Result<f64, ccss_core::Error>,
) -> CliResult {
    let fail = |e: ccss_core::Error| CliError::failure(format!("{}: {e}", mesh.name));
    let diag = control_diagonal(&mesh.positions);
    let (lo, hi) = box_of(&mesh.positions);
    let c = 0.5 * (lo + hi);
    let mut rng = SplitMix64::new(0x5eed_0fc0_ffee);
    let unit = |rng: &mut SplitMix64| {
        DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 2.0 - DVec3::ONE
    };
    let mut w = Box::new(QueryWork::ZERO);
    let bar = Progress::delayed("{msg} [{bar:40}] {pos}/{len}");

    // Rays.
    let rays: Vec<Ray> = (0..a.rays)
        .map(|_| {
            let o = c + unit(&mut rng).normalize_or(DVec3::X) * diag;
            let t = c + unit(&mut rng) * 0.25 * (hi - lo);
            Ray {
                origin: o,
                dir: t - o,
            }
        })
        .collect();
    let ropts = RayOptions {
        tol: a.tol * diag,
        t_min: 0.0,
        ..Default::default()
    };
    bar.phase("first hits", rays.len());
    let t0 = Instant::now();
    let mut found = 0usize;
    for r in &rays {
        found += ray_first(ev, r, &ropts, &mut w).map_err(fail)?.is_some() as usize;
        bar.inc();
    }
    let first_s = t0.elapsed().as_secs_f64();
    bar.phase("all hits", rays.len());
    let t0 = Instant::now();
    let mut hits = 0usize;
    for r in &rays {
        hits += match ray_all(ev, r, &ropts, &mut w, &mut []) {
            Ok(n) => n,
            Err(ccss_core::Error::BufferTooSmall { required }) => required,
            Err(e) => return Err(fail(e)),
        };
        bar.inc();
    }
    let all_s = t0.elapsed().as_secs_f64();
    stdout::line(&format!(
        "ccss raycast tol={:.2e} rays={} hit_rays={found} hits={hits} first_rays_per_s={:.0} all_rays_per_s={:.0}",
        ropts.tol,
        rays.len(),
        rays.len() as f64 / first_s,
        rays.len() as f64 / all_s
    ))?;

    // Closest points.
    let pts: Vec<DVec3> = (0..a.points)
        .map(|_| c + unit(&mut rng) * 0.625 * (hi - lo))
        .collect();
    let copts = ClosestOptions {
        tol: a.tol * diag,
        ..Default::default()
    };
    bar.phase("closest", pts.len());
    let t0 = Instant::now();
    let mut sum = 0.0;
    for p in &pts {
        sum += closest(ev, *p, &copts, &mut w).map_err(fail)?.dist;
        bar.inc();
    }
    let cs = t0.elapsed().as_secs_f64();
    stdout::line(&format!(
        "ccss closest tol={:.2e} points={} points_per_s={:.0} mean_dist={:.6e}",
        copts.tol,
        pts.len(),
        pts.len() as f64 / cs,
        sum / pts.len().max(1) as f64
    ))?;

    // Slices against one tessellation to the same eps.
    let eps = a.eps * diag;
    let so = SliceOptions {
        eps,
        ..Default::default()
    };
    let k = a.layers.max(1);
    bar.phase("slices", k);
    let t0 = Instant::now();
    let mut npts = 0usize;
    // One walk per layer: the scratch is kept and grown on a size error
    // (the streaming use; the size query is a second walk).
    let mut segs = vec![];
    for i in 0..k {
        let z = lo.z + (hi.z - lo.z) * (i as f64 + 0.5) / k as f64;
        let plane = Plane::z(z);
        let st = match slice_layer(ev, &plane, &so, &mut w, &mut segs) {
            Err(ccss_core::Error::BufferTooSmall { required }) => {
                segs.resize(2 * required, SliceSegment::default());
                slice_layer(ev, &plane, &so, &mut w, &mut segs).map_err(fail)?
            }
            r => r.map_err(fail)?,
        };
        let segs = &mut segs[..st.segments];
        let mut p = vec![[0.0; 2]; st.points];
        let mut cn = vec![Contour::default(); st.contours];
        slice_write(segs, &mut p, &mut cn).map_err(fail)?;
        npts += st.points;
        bar.inc();
    }
    let slice_ms = t0.elapsed().as_secs_f64() * 1e3 / k as f64;
    bar.finish();
    // The fastest of TIMED_RUNS tessellations (one is a millisecond or
    // two: a single run is mostly page faults and cold caches).
    let mut tess_ms = f64::INFINITY;
    let mut timed = || -> Result<Tess, CliError> {
        let t0 = Instant::now();
        let t = tessellate(eps).map_err(fail)?;
        tess_ms = tess_ms.min(t0.elapsed().as_secs_f64() * 1e3);
        Ok(t)
    };
    let (pos, tris, nverts) = timed()?;
    for _ in 1..TIMED_RUNS {
        timed()?;
    }
    // The naive baseline: the same planes cut through the triangles.
    let t0 = Instant::now();
    let mut cut = 0usize;
    for i in 0..k {
        let z = lo.z + (hi.z - lo.z) * (i as f64 + 0.5) / k as f64;
        cut += plane_cut(&pos, &tris, z).len();
    }
    let cut_ms = t0.elapsed().as_secs_f64() * 1e3 / k as f64;
    stdout::line(&format!(
        "ccss slice eps={eps:.2e} layers={k} points={npts} ms_per_layer={slice_ms:.3} tessellate_ms={tess_ms:.2} tessellate_vertices={} slice_over_tessellate={:.3} cut_segments={cut} cut_ms_per_layer={cut_ms:.3} tessellate_plus_cut_ms_per_layer={:.3}",
        nverts,
        slice_ms / tess_ms,
        tess_ms / k as f64 + cut_ms
    ))?;
    if a.stack > 0 {
        let l = a.stack;
        let dz = (hi.z - lo.z) / l as f64;
        let stack = PlaneStack::z(lo.z + 0.5 * dz, dz);
        let bar = Progress::delayed("{msg} [{bar:40}] {pos}/{len} layers");
        bar.phase("stack", l);
        let t0 = Instant::now();
        let mut segs = vec![];
        let mut stats = vec![SliceStats::default(); a.band];
        let mut npts = 0usize;
        let mut first = 0;
        while first < l {
            let st = &mut stats[..a.band.min(l - first)];
            let n = match slice_band(ev, &stack, first, &so, &mut w, &mut segs, st) {
                Err(ccss_core::Error::BufferTooSmall { required }) => {
                    segs.resize(2 * required, SliceSegment::default());
                    slice_band(ev, &stack, first, &so, &mut w, &mut segs, st).map_err(fail)?
                }
                r => r.map_err(fail)?,
            };
            for i in 0..st.len() {
                let mut p = vec![[0.0; 2]; st[i].points];
                let mut cn = vec![Contour::default(); st[i].contours];
                slice_write(band_layer(&mut segs[..n], st, i), &mut p, &mut cn).map_err(fail)?;
                npts += st[i].points;
            }
            first += st.len();
            for _ in 0..st.len() {
                bar.inc();
            }
        }
        let stack_ms = t0.elapsed().as_secs_f64() * 1e3;
        bar.finish();
        let mut floor_ms = f64::INFINITY;
        for _ in 0..TIMED_RUNS {
            floor_ms = floor_ms.min(eval_floor(npts).map_err(fail)?);
        }
        stdout::line(&format!(
            "ccss slice_stack eps={eps:.2e} layers={l} band={} points={npts} stack_ms={stack_ms:.2} tessellate_ms={tess_ms:.2} stack_over_tessellate={:.2} eval_floor_ms={floor_ms:.2} floor_over_tessellate={:.2}",
            a.band,
            stack_ms / tess_ms,
            floor_ms / tess_ms
        ))?;
    }
    Ok(())
}

/// The segments where the plane `z` cuts the triangles (the naive
/// slicer's work per layer, without chaining): `[x0, y0, x1, y1]` each.
fn plane_cut(pos: &[f64], tris: &[u32], z: f64) -> Vec<[f64; 4]> {
    let mut out = vec![];
    let p = |i: u32| {
        let i = 3 * i as usize;
        [pos[i], pos[i + 1], pos[i + 2]]
    };
    for t in tris.chunks_exact(3) {
        let v = [p(t[0]), p(t[1]), p(t[2])];
        let mut ends = [[0.0; 2]; 2];
        let mut n = 0;
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            if (a[2] < z) != (b[2] < z) && n < 2 {
                let w = (z - a[2]) / (b[2] - a[2]);
                ends[n] = [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])];
                n += 1;
            }
        }
        if n == 2 {
            out.push([ends[0][0], ends[0][1], ends[1][0], ends[1][1]]);
        }
    }
    out
}

/// Runs the verb.
pub fn run(a: &BenchQueryArgs) -> CliResult {
    if !(a.tol > 0.0 && a.eps > 0.0) {
        return Err(CliError::input("--tol and --eps must be positive"));
    }
    if !(1..=MAX_BAND).contains(&a.band) {
        return Err(CliError::input("--band must be 1 to 64"));
    }
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let f = a.features;
    if mesh.tags.any() || f.boundary.is_some() || f.creasing.is_some() {
        return with_feature_mesh(&mesh, f.boundary, f.creasing, |fe| {
            bench(
                a,
                &mesh,
                fe,
                |eps| {
                    let opts = Options::absolute(eps);
                    let mut scratch = Box::new(Scratch::ZERO);
                    let need = Tessellation::required_bytes_feature(fe, &opts, &mut scratch)?;
                    let mut mem = words(need);
                    emit(Tessellation::build_feature(fe, opts, &mut mem)?)
                },
                |n| {
                    let faces: Vec<usize> = (0..fe.num_faces())
                        .filter(|&f| fe.num_subfaces(f) > 0)
                        .collect();
                    let qs = floor_queries(n, &faces, |f| fe.num_subfaces(f));
                    let t0 = Instant::now();
                    let mut sum = 0.0;
                    for q in &qs {
                        sum += fe.eval(q.face, q.sub, q.u, q.v)?.p.x;
                    }
                    std::hint::black_box(sum);
                    Ok(t0.elapsed().as_secs_f64() * 1e3)
                },
            )
        });
    }
    with_mesh(&mesh, &tables, |ctx| {
        bench(
            a,
            &mesh,
            &ctx.evaluator,
            |eps| {
                let opts = Options::absolute(eps);
                let mut scratch = Box::new(Scratch::ZERO);
                let need = Tessellation::required_bytes(
                    &ctx.topology,
                    &ctx.evaluator,
                    &opts,
                    &mut scratch,
                )?;
                let mut mem = words(need);
                emit(Tessellation::build(
                    &ctx.topology,
                    &ctx.evaluator,
                    opts,
                    &mut mem,
                )?)
            },
            |n| {
                let ev = &ctx.evaluator;
                let faces: Vec<usize> = (0..ev.num_faces()).collect();
                let qs = floor_queries(n, &faces, |f| ev.num_subfaces(f));
                let mut out = vec![Eval::default(); qs.len()];
                let t0 = Instant::now();
                ev.eval_batch(&qs, false, &mut out).map_err(|(_, e)| e)?;
                std::hint::black_box(&out);
                Ok(t0.elapsed().as_secs_f64() * 1e3)
            },
        )
    })
}

/// `n` random queries on `faces` (sub-face and `(u, v)` uniform; a
/// fixed seed), for the evaluation floor of the stack line.
fn floor_queries(n: usize, faces: &[usize], subs: impl Fn(usize) -> usize) -> Vec<Query> {
    let mut rng = SplitMix64::new(0xf1_00_f1_00);
    (0..if faces.is_empty() { 0 } else { n })
        .map(|_| {
            let f = faces[rng.below(faces.len())];
            Query {
                face: f as u32,
                sub: rng.below(subs(f).max(1)) as u32,
                u: rng.next_f64(),
                v: rng.next_f64(),
            }
        })
        .collect()
}

/// Emits a built tessellation with triangles (timed with the build).
fn emit(mut t: Tessellation) -> Result<Tess, ccss_core::Error> {
    let cnt = t.counts();
    let mut pos = vec![0.0; 3 * cnt.vertices];
    let mut sizes = vec![0u32; cnt.polygons];
    let mut idx = vec![0u32; cnt.polygon_indices];
    let mut tris = vec![0u32; 3 * cnt.triangles];
    t.emit(Output {
        positions: &mut pos,
        normals: None,
        params: None,
        polygon_sizes: &mut sizes,
        polygon_indices: &mut idx,
        triangles: Some(&mut tris),
        cells: None,
    })?;
    Ok((pos, tris, cnt.vertices))
}
