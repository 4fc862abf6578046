//! The firmware demo of ccss: what a CNC or prototyping controller would do
//! with `ccss-core`, through its public API only, in caller memory.
//!
//! [`run`] takes the eigen tables and fixed memory pools ([`Pools`]) and, on
//! two solids of [`meshes`],
//!
//! 1. builds the topology and the eigen evaluator of a smooth solid
//!    (`catmark_pyramid`: a quad and four triangles, valences 3
//!    and 4) and evaluates a
//!    grid of points on every face (position, first and second
//!    derivatives, normal);
//! 2. builds a [`FeatureMesh`] and a [`FeatureEvaluator`] of a creased
//!    cube (`catmark_cube_creases1`: 11 infinitely sharp creases and one
//!    semi-sharp) and evaluates the same grid;
//! 3. computes the subdivision depth of every slot for a tolerance;
//! 4. tessellates the smooth solid to an absolute flatness and streams the
//!    triangles out one by one (here: into a checksum);
//! 5. voxelizes and floods it slab by slab, each slab in one small grid,
//!    and streams the voxel runs of each slab out through a fixed buffer.
//!
//! [`Parts`] leaves out steps 2 and 5 ([`Parts::SMOOTH`]: what a
//! firmware that only evaluates and tessellates needs).
//!
//! Every result goes to a [`Report`] as a [`Sum`] (floats; compared to a
//! relative tolerance) or an integer (compared exactly), so that the
//! Cortex-M4F firmware (`embedded/firmware`) and the x86-64 reference
//! (`tests/tests/firmware.rs`, `scripts/firmware.sh`) can compare their
//! lines ([`line`] formats them).
#![no_std]
#![deny(missing_docs)]

pub mod meshes;
mod sum;

pub use sum::{Hash, Sum};

use ccss_core::bounds::depth::{depths, Method};
use ccss_core::eval::FeatureCache;
use ccss_core::mem::words_for;
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::tessellate::{Keep, Options, Scratch, Tessellation};
use ccss_core::voxel::{fit_transform, Adjacency, VoxelGrid, VoxelParams, VoxelRun, VoxelWork};
use ccss_core::{
    Error, Eval, Evaluator, EvaluatorOptions, FeatureEvaluator, MeshInput, TableSet, Topology,
};

/// Absolute flatness of the tessellation (model units; the pyramid spans 4, and a smaller
/// value needs more RAM than the demo's pools).
pub const TESS_EPS: f64 = 0.05;
/// Tolerance of the subdivision depths.
pub const DEPTH_EPS: f64 = 1e-3;
/// What the smooth solid's evaluator keeps per extraordinary patch: only
/// the eigen projection and control points (the level-1/2 sub-patch
/// grids and corner bounds are recomputed per query, bit for bit the
/// default build's results, in a third of its memory).
pub const EVALUATOR: EvaluatorOptions = EvaluatorOptions::COMPACT;
/// What the tessellation keeps between marking and emission: no saved
/// corner-cell expansions (redone at emission; the same output).
pub const TESS_KEEP: Keep = Keep::LEAST;
/// Voxel resolution per axis.
pub const VOXEL_RES: u32 = 16;
/// z-layers per voxel slab.
pub const SLAB_LAYERS: u32 = 8;
/// Evaluation grid per (sub-)face: `GRID x GRID` points.
pub const GRID: u32 = 5;
/// Cache tree of the creased cube's [`FeatureEvaluator`]: children and
/// grandchildren only (57 KiB; the default depth 12 takes 701 KiB on this
/// cube, more than the firmware's pool).
pub const FEATURE_CACHE: FeatureCache = FeatureCache {
    depth: 2,
    nodes_per_face: 64,
};

/// Which steps [`run`] takes besides the smooth solid's build, grid
/// evaluation, depths and tessellation (always taken).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parts {
    /// Step 2: the creased cube through the feature evaluator.
    pub creased: bool,
    /// Step 5: voxels slab by slab (needs [`Pools::voxel_work`]).
    pub voxels: bool,
}

impl Parts {
    /// Every step.
    pub const ALL: Parts = Parts {
        creased: true,
        voxels: true,
    };
    /// Only the smooth solid: build, evaluation (f64 and f32), depths,
    /// tessellation.
    pub const SMOOTH: Parts = Parts {
        creased: false,
        voxels: false,
    };
}

/// Caller memory of [`run`]. Each phase carves what it needs from the
/// front of `words`, `reals` and `ints` and gives it back at its end, so
/// the pools need the largest phase, not the sum.
pub struct Pools<'a> {
    /// Builder memory (topology, evaluators, tessellation, voxel slab; the
    /// smooth evaluator's build memory, apart, is reused by the later
    /// phases).
    pub words: &'a mut [u64],
    /// Tessellation positions.
    pub reals: &'a mut [f64],
    /// Depths, the streamed polygon and its triangles, flood stack.
    pub ints: &'a mut [u32],
    /// The voxel runs of one slab (may be empty without [`Parts::voxels`]).
    pub runs: &'a mut [VoxelRun],
    /// The voxelizer's work area (needed only with [`Parts::voxels`]).
    pub voxel_work: Option<&'a mut VoxelWork>,
    /// With a scratch (58 KiB), [`run`] also reports the exact bytes the
    /// tessellation needs (`info` lines; the firmware passes `None`).
    pub tess_scratch: Option<&'a mut Scratch>,
}

/// Where [`run`] sends its results.
pub trait Report {
    /// A float checksum.
    fn sum(&mut self, key: &str, s: Sum);
    /// An integer result.
    fn int(&mut self, key: &str, x: u64);
    /// A figure that is not compared (buffer sizes).
    fn info(&mut self, key: &str, x: u64) {
        let _ = (key, x);
    }
    /// Called when phase `name` ends (the firmware measures its stack
    /// there).
    fn phase(&mut self, name: &str) {
        let _ = name;
    }
}

/// One report line: `key f64 <sum bits> <abs bits> <count>` or
/// `key int <value>` (bits as 16 hex digits, exact on both machines),
/// written by `w` piece by piece (the firmware has no allocator).
pub fn line(w: &mut dyn core::fmt::Write, key: &str, value: Value) -> core::fmt::Result {
    match value {
        Value::Sum(s) => writeln!(
            w,
            "{key} f64 {:016x} {:016x} {}",
            s.sum.to_bits(),
            s.abs.to_bits(),
            s.count
        ),
        Value::Int(x) => writeln!(w, "{key} int {x}"),
    }
}

/// A reported value (for [`line`]).
#[derive(Clone, Copy, Debug)]
pub enum Value {
    /// A float checksum.
    Sum(Sum),
    /// An integer.
    Int(u64),
}

fn add_eval(s: &mut Sum, e: &Eval) {
    for v in [e.p, e.du, e.dv, e.duu, e.duv, e.dvv, e.normal] {
        s.add3(v.to_array());
    }
}

/// `GRID x GRID` parameters of a cell, corners included.
fn grid_param(i: u32) -> f64 {
    i as f64 / (GRID - 1) as f64
}

/// Runs the demo (see the crate docs; the steps of `parts`) with `tables`
/// (standard rule; baked into flash on the firmware, built at run time on
/// the host).
pub fn run(
    tables: &TableSet,
    pools: &mut Pools,
    parts: Parts,
    out: &mut dyn Report,
) -> Result<(), Error> {
    let smooth = MeshInput {
        positions: &meshes::PYRAMID_POSITIONS,
        face_sizes: &meshes::PYRAMID_SIZES,
        indices: &meshes::PYRAMID_INDICES,
    };
    let nv = smooth.positions.len() / 3;
    let topo_words = words_for(Topology::required_bytes(nv, smooth.face_sizes));
    out.info("bytes.topology", 8 * topo_words as u64);
    let (topo_mem, rest) = split(pools.words, topo_words)?;
    let topo = Topology::build(smooth, topo_mem)?;
    // What the evaluator keeps, and apart (free again after the build,
    // taken over by the later phases) what only its build uses.
    let build_words = words_for(Evaluator::build_scratch_bytes(&topo));
    let ev_words =
        words_for(Evaluator::required_bytes_with(&topo, tables, EVALUATOR)?) - build_words;
    out.info("bytes.evaluator", 8 * ev_words as u64);
    out.info("bytes.evaluator_build", 8 * build_words as u64);
    let (ev_mem, rest) = split(rest, ev_words)?;
    let ev = build_evaluator(&topo, tables, ev_mem, &mut *rest)?;
    out.int("smooth.slots", ev.num_slots() as u64);
    let (regular, extraordinary) = ev.patch_counts();
    out.info("evaluator.regular_patches", regular as u64);
    out.info("evaluator.ev_patches", extraordinary as u64);
    out.info("evaluator.internal_levels", ev.internal_levels() as u64);
    out.phase("build");

    grids(&ev, diagonal(smooth.positions), out)?;

    // 2. The creased cube through the feature evaluator.
    if parts.creased {
        creased(tables, &mut *rest, out)?;
        out.phase("feature");
    }

    // 3. Subdivision depths.
    let ns = ev.num_slots();
    let (depth, _) = split(pools.ints, ns)?;
    depths(&ev, DEPTH_EPS, Method::Best, depth)?;
    let mut h = Hash::default();
    for &d in depth.iter() {
        h.add(d);
    }
    out.int("smooth.depths", h.0);
    out.int(
        "smooth.depth_max",
        depth.iter().copied().max().unwrap_or(0) as u64,
    );
    out.phase("depth");

    // 4. Tessellation, triangles streamed out.
    if let Some(scratch) = pools.tess_scratch.as_deref_mut() {
        let opts = Options::absolute(TESS_EPS);
        let need = Tessellation::required_bytes_with(&topo, &ev, &opts, TESS_KEEP, scratch)?;
        out.info("bytes.tessellation", need as u64);
    }
    tessellate(&topo, &ev, &mut *rest, pools.reals, pools.ints, out)?;
    out.phase("tess_emit");

    // 5. Voxels slab by slab.
    if parts.voxels {
        let work = pools
            .voxel_work
            .as_deref_mut()
            .ok_or(Error::InvalidArgument(
                "Parts::voxels needs Pools::voxel_work",
            ))?;
        voxels(&ev, rest, pools.ints, pools.runs, work, out)?;
        out.phase("voxel");
    }
    Ok(())
}

/// `Evaluator::build_split` in a frame of its own: its locals are off the
/// stack in the later steps (the firmware's stack per step). `scratch`:
/// the build's own memory (the front of it).
#[inline(never)]
fn build_evaluator<'a>(
    topo: &Topology,
    tables: &'a TableSet,
    mem: &'a mut [u64],
    scratch: &mut [u64],
) -> Result<Evaluator<'a>, Error> {
    Evaluator::build_split(topo, tables, EVALUATOR, mem, scratch)
}

/// Steps 1 and 1b: the grid of every slot through `eval_second`, `eval`
/// and `eval_f32`, and the largest position error of `eval_f32` relative
/// to `diag` (own frame, as [`build_evaluator`]).
#[inline(never)]
fn grids(ev: &Evaluator, diag: f64, out: &mut dyn Report) -> Result<(), Error> {
    // 1. Grid evaluation, eigen evaluator.
    let mut s = Sum::default();
    for f in 0..ev.num_faces() {
        for sub in 0..ev.num_subfaces(f) {
            for i in 0..GRID {
                for j in 0..GRID {
                    let e = ev.eval_second(f as u32, sub as u32, grid_param(i), grid_param(j))?;
                    add_eval(&mut s, &e);
                }
            }
        }
    }
    out.sum("smooth.eval", s);
    out.phase("eval");

    // 1b. The same grid, first derivatives and normal only: f64, then f32.
    let mut s64 = Sum::default();
    each_grid_point(ev, |f, sub, u, v| {
        let e = ev.eval(f, sub, u, v)?;
        for x in [e.p, e.du, e.dv, e.normal] {
            s64.add3(x.to_array());
        }
        Ok(())
    })?;
    out.sum("smooth.eval_first", s64);
    out.phase("eval_f64");
    let mut s32 = Sum::default();
    each_grid_point(ev, |f, sub, u, v| {
        let e = ev.eval_f32(f, sub, u as f32, v as f32)?;
        for x in [e.p, e.du, e.dv, e.normal] {
            s32.add3(x.map(f64::from));
        }
        Ok(())
    })?;
    out.sum("smooth.eval_f32", s32);
    out.phase("eval_f32");
    // Largest position error of f32 against f64, relative to the diagonal
    // of the control points' box (outside the timed phases).
    let mut worst = 0.0f64;
    each_grid_point(ev, |f, sub, u, v| {
        let a = ev.eval_f32(f, sub, u as f32, v as f32)?;
        let b = ev.eval(f, sub, u, v)?;
        let d = [
            a.p[0] as f64 - b.p.x,
            a.p[1] as f64 - b.p.y,
            a.p[2] as f64 - b.p.z,
        ];
        worst = worst.max(libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / diag);
        Ok(())
    })?;
    out.sum(
        "f32.max_err",
        Sum {
            sum: worst,
            abs: worst,
            count: 1,
        },
    );
    Ok(())
}

/// Calls `f(face, sub, u, v)` at the `GRID x GRID` points of every slot.
fn each_grid_point(
    ev: &Evaluator,
    mut f: impl FnMut(u32, u32, f64, f64) -> Result<(), Error>,
) -> Result<(), Error> {
    for face in 0..ev.num_faces() {
        for sub in 0..ev.num_subfaces(face) {
            for i in 0..GRID {
                for j in 0..GRID {
                    f(face as u32, sub as u32, grid_param(i), grid_param(j))?;
                }
            }
        }
    }
    Ok(())
}

/// Diagonal of the bounding box of `x y z` positions.
fn diagonal(p: &[f64]) -> f64 {
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for q in p.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let d: f64 = (0..3).map(|k| (hi[k] - lo[k]) * (hi[k] - lo[k])).sum();
    libm::sqrt(d)
}

/// The front `n` elements of `mem` and the rest, or `BufferTooSmall` with
/// the number of elements needed.
fn split<T>(mem: &mut [T], n: usize) -> Result<(&mut [T], &mut [T]), Error> {
    if mem.len() < n {
        return Err(Error::BufferTooSmall { required: n });
    }
    Ok(mem.split_at_mut(n))
}

fn creased(tables: &TableSet, words: &mut [u64], out: &mut dyn Report) -> Result<(), Error> {
    let cube = MeshInput {
        positions: &meshes::CREASED_CUBE_POSITIONS,
        face_sizes: &meshes::CREASED_CUBE_SIZES,
        indices: &meshes::CREASED_CUBE_INDICES,
    };
    let tags = FeatureInput {
        crease_vertices: &meshes::CREASED_CUBE_CREASE_VERTICES,
        crease_sharpness: &meshes::CREASED_CUBE_CREASE_SHARPNESS,
        ..Default::default()
    };
    let fm_words = words_for(FeatureMesh::required_bytes(&cube)?);
    out.info("bytes.feature_mesh", 8 * fm_words as u64);
    let (fm_mem, rest) = split(words, fm_words)?;
    let fm = FeatureMesh::build(&cube, &tags, fm_mem)?;
    let fe_words = words_for(FeatureEvaluator::required_bytes_with(
        &fm,
        Some(tables),
        FEATURE_CACHE,
    ));
    out.info("bytes.feature_evaluator", 8 * fe_words as u64);
    let (fe_mem, _) = split(rest, fe_words)?;
    let fe = FeatureEvaluator::build_with(&fm, Some(tables), FEATURE_CACHE, fe_mem)?;
    let mut s = Sum::default();
    for f in 0..fe.num_faces() {
        for sub in 0..fe.num_subfaces(f) {
            for i in 0..GRID {
                for j in 0..GRID {
                    let e = fe.eval_second(f as u32, sub as u32, grid_param(i), grid_param(j))?;
                    add_eval(&mut s, &e);
                }
            }
        }
    }
    out.sum("creased.eval", s);
    Ok(())
}

fn tessellate(
    topo: &Topology,
    ev: &Evaluator,
    words: &mut [u64],
    reals: &mut [f64],
    ints: &mut [u32],
    out: &mut dyn Report,
) -> Result<(), Error> {
    let mut t = Tessellation::build_with(topo, ev, Options::absolute(TESS_EPS), TESS_KEEP, words)?;
    out.phase("tess_mark");
    let c = t.counts();
    let buf_len = t.stream_len()?;
    out.info("bytes.tess_output", (24 * c.vertices + 4 * buf_len) as u64);
    out.info("tess.stream_len", buf_len as u64);
    let (pos, _) = split(reals, 3 * c.vertices)?;
    let (buf, _) = split(ints, buf_len)?;
    // Stream the triangles as a controller would send them: three corner
    // positions each, polygon by polygon as they are made.
    let mut s = Sum::default();
    let (mut polygons, mut triangles) = (0u64, 0u64);
    t.emit_stream(pos, buf, &mut |p, _, tris| {
        polygons += 1;
        for tri in tris.chunks_exact(3) {
            triangles += 1;
            for &v in tri {
                let v = v as usize;
                s.add3([p[3 * v], p[3 * v + 1], p[3 * v + 2]]);
            }
        }
    })?;
    out.int("tess.vertices", c.vertices as u64);
    out.int("tess.triangles", c.triangles as u64);
    out.int(
        "tess.streamed",
        (polygons == c.polygons as u64 && triangles == c.triangles as u64) as u64,
    );
    out.int("tess.bound_ok", (t.stats().bound <= TESS_EPS) as u64);
    out.info("tess.max_level", t.stats().max_level as u64);
    out.sum("tess.triangles", s);
    Ok(())
}

fn voxels(
    ev: &Evaluator,
    words: &mut [u64],
    ints: &mut [u32],
    runs: &mut [VoxelRun],
    work: &mut VoxelWork,
    out: &mut dyn Report,
) -> Result<(), Error> {
    let res = [VOXEL_RES; 3];
    let params = VoxelParams::new(res, Adjacency::Six);
    let t = fit_transform(ev, res, work)?;
    let mut h = Hash::default();
    let (mut nruns, mut surface, mut interior) = (0u64, 0u64, 0u64);
    let mut z0 = 0;
    while z0 < VOXEL_RES {
        let z1 = (z0 + SLAB_LAYERS).min(VOXEL_RES);
        let need = words_for(VoxelGrid::slab_required_bytes(res, z0, z1)?);
        if z0 == 0 {
            out.info("bytes.voxel_slab", 8 * need as u64);
        }
        let (mem, _) = split(&mut *words, need)?;
        let mut grid = VoxelGrid::new_slab(res, z0, z1, mem)?;
        grid.voxelize(ev, &params, Some(t), work)?;
        grid.flood(ev, ints, work)?;
        let n = grid.write_runs(runs)?;
        for r in &runs[..n] {
            for x in [r.x0, r.x1, r.y, r.z, r.class] {
                h.add(x);
            }
        }
        let c = grid.counts();
        nruns += n as u64;
        surface += c.surface;
        interior += c.interior;
        z0 = z1;
    }
    out.int("voxel.runs", nruns);
    out.int("voxel.surface", surface);
    out.int("voxel.interior", interior);
    out.int("voxel.hash", h.0);
    Ok(())
}
