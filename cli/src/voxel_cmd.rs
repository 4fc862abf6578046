//! `ccss voxelize --res N [--adjacency 6|18|26] [--fill] [--runs RUNS.txt]
//! [--preview SLICES.png] MESH.obj -o OUT.binvox`: voxelization of the limit
//! surface (ccss-core's `voxel` module: the paper's recursive
//! parameter-space subdivision with a certification pass, then flooding).
//!
//! The per-patch work runs on all cores (`RAYON_NUM_THREADS` to change): the
//! grid is cut into z-slabs, and each slab is voxelized and classified in its
//! own slab grid, which gives exactly the voxels of the whole grid (see
//! `ccss_core::voxel::rasterize`). The slabs are then written as binvox
//! (x slowest, then z, then y fastest; run-length coded), optionally as runs
//! and as a PNG montage of z-slices.

use crate::context::{build_tables, with_mesh};
use crate::error::{CliError, CliResult};
use crate::mesh::Mesh;
use ccss_core::voxel::{
    fit_transform, Adjacency, RasterStats, VoxelGrid, VoxelParams, VoxelTransform, VoxelWork,
};
use ccss_core::{Evaluator, Weights};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `ccss voxelize`.
#[derive(clap::Args, Debug)]
pub struct VoxelizeArgs {
    /// Polygon mesh (OBJ).
    pub mesh: PathBuf,
    /// Output binvox file.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Resolution N (an N x N x N grid, 2..=4096).
    #[arg(long)]
    pub res: u32,
    /// Adjacency of the stop test: 6 (thick, no holes), 18 or 26 (thin).
    #[arg(long, default_value_t = 26)]
    pub adjacency: u32,
    /// Also write the interior voxels (surface only without it).
    #[arg(long)]
    pub fill: bool,
    /// Write the voxel runs as text: lines 'z y x0 x1 class' (x1 exclusive;
    /// class 1 surface, 2 interior).
    #[arg(long)]
    pub runs: Option<PathBuf>,
    /// Write a PNG montage of up to 16 z-slices.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Pre-split count k (a power of two, 1..=64).
    #[arg(long, default_value_t = 8)]
    pub presplit: u32,
}

/// Voxelizes (and, with `flood`, classifies) the z-slabs `cuts` in
/// parallel; `each` is called on every finished slab grid (in slab order
/// per thread) and its results are collected.
pub fn run_slabs<R: Send>(
    ev: &Evaluator,
    params: &VoxelParams,
    t: VoxelTransform,
    cuts: &[u32],
    flood: bool,
    bar: Option<&ProgressBar>,
    each: impl Fn(&VoxelGrid, RasterStats) -> R + Sync,
) -> Result<Vec<R>, ccss_core::Error> {
    cuts.par_windows(2)
        .map(|w| {
            let (z0, z1) = (w[0], w[1]);
            let need = VoxelGrid::slab_required_bytes(params.res, z0, z1)?;
            let mut mem = vec![0u64; need.div_ceil(8)];
            let mut grid = VoxelGrid::new_slab(params.res, z0, z1, &mut mem)?;
            let mut work = Box::new(VoxelWork::ZERO);
            let st = grid.voxelize(ev, params, Some(t), &mut work)?;
            if flood {
                let rows = params.res[1] as usize * (z1 - z0) as usize;
                let mut stack = vec![0u32; rows.clamp(1, 1 << 20)];
                grid.flood(ev, &mut stack, &mut work)?;
            }
            if let Some(b) = bar {
                b.inc(1);
            }
            Ok(each(&grid, st))
        })
        .collect()
}

/// Slab boundaries for `threads` workers: about four slabs per thread, at
/// least 8 layers each.
pub fn cuts(m3: u32, threads: usize) -> Vec<u32> {
    let n = ((threads * 4) as u32).clamp(1, (m3 / 8).max(1));
    (0..=n)
        .map(|i| (m3 as u64 * i as u64 / n as u64) as u32)
        .collect()
}

/// The bits of one slab needed by the writers.
pub struct SlabBits {
    pub z0: u32,
    pub z1: u32,
    pub wpr: usize,
    /// Rows (y fastest) of the slab: surface and interior words.
    pub surface: Vec<u64>,
    pub interior: Vec<u64>,
}

fn slab_bits(g: &VoxelGrid) -> SlabBits {
    let (z0, z1) = g.slab();
    let m2 = g.resolution()[1];
    let wpr = g.words_per_row();
    let mut surface = Vec::with_capacity((z1 - z0) as usize * m2 as usize * wpr);
    let mut interior = Vec::with_capacity(surface.capacity());
    for z in z0..z1 {
        for y in 0..m2 {
            let r = g.row_of(y, z).unwrap_or(usize::MAX);
            for w in 0..wpr {
                surface.push(g.surface_word(r, w));
                interior.push(g.interior_word(r, w));
            }
        }
    }
    SlabBits {
        z0,
        z1,
        wpr,
        surface,
        interior,
    }
}

/// Bit `x` of row `(y, z)` of the selected planes.
#[inline]
fn bit(s: &SlabBits, m2: u32, x: u32, y: u32, z: u32, fill: bool) -> bool {
    let r = ((z - s.z0) * m2 + y) as usize * s.wpr + (x / 64) as usize;
    let m = 1u64 << (x % 64);
    s.surface[r] & m != 0 || (fill && s.interior[r] & m != 0)
}

/// Writes the binvox file (x slowest, then z, then y; RLE pairs).
fn write_binvox(
    path: &Path,
    slabs: &[SlabBits],
    res: u32,
    t: &VoxelTransform,
    fill: bool,
) -> CliResult {
    let n = res as usize;
    // Transpose into binvox order: bit index x*n*n + z*n + y.
    let mut bits = vec![0u64; (n * n * n).div_ceil(64)];
    for s in slabs {
        for z in s.z0..s.z1 {
            for y in 0..res {
                let r = ((z - s.z0) * res + y) as usize * s.wpr;
                for w in 0..s.wpr {
                    let mut word = s.surface[r + w] | if fill { s.interior[r + w] } else { 0 };
                    while word != 0 {
                        let x = w * 64 + word.trailing_zeros() as usize;
                        word &= word - 1;
                        let i = x * n * n + z as usize * n + y as usize;
                        bits[i / 64] |= 1u64 << (i % 64);
                    }
                }
            }
        }
    }
    let scale = n as f64 / t.scale;
    let tr = t.offset.map(|o| (-0.5 - o) / t.scale);
    let mut out = Vec::new();
    let _ = write!(
        out,
        "#binvox 1\ndim {n} {n} {n}\ntranslate {} {} {}\nscale {}\ndata\n",
        tr[0], tr[1], tr[2], scale
    );
    // RLE pairs (value, count <= 255); run ends found a word at a time.
    let total = n * n * n;
    let mut i = 0usize;
    while i < total {
        let v = bits[i / 64] >> (i % 64) & 1;
        let mut j = i;
        while j < total {
            let (w, b) = (j / 64, j % 64);
            // Ones where the bit differs from v (padding past `total` is 0).
            let differ = if v == 1 { !bits[w] } else { bits[w] } >> b;
            if differ != 0 {
                j += differ.trailing_zeros() as usize;
                break;
            }
            j = (w + 1) * 64;
        }
        let mut len = j.min(total) - i;
        i += len;
        while len > 0 {
            let c = len.min(255);
            out.push(v as u8);
            out.push(c as u8);
            len -= c;
        }
    }
    std::fs::write(path, out)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}

fn write_runs(path: &Path, slabs: &[SlabBits], res: u32, fill: bool) -> CliResult {
    let mut out = String::new();
    out.push_str(&format!(
        "# ccss voxel runs: res {res} {res} {res}; lines 'z y x0 x1 class' (x1 exclusive; class 1 surface, 2 interior)\n"
    ));
    for s in slabs {
        for z in s.z0..s.z1 {
            for y in 0..res {
                let mut x = 0;
                while x < res {
                    let sb = bit(s, res, x, y, z, false);
                    let ib = fill && !sb && bit(s, res, x, y, z, true);
                    if !sb && !ib {
                        x += 1;
                        continue;
                    }
                    let class = if sb { 1 } else { 2 };
                    let x0 = x;
                    while x < res {
                        let s2 = bit(s, res, x, y, z, false);
                        let i2 = fill && !s2 && bit(s, res, x, y, z, true);
                        if (class == 1 && !s2) || (class == 2 && !i2) {
                            break;
                        }
                        x += 1;
                    }
                    out.push_str(&format!("{z} {y} {x0} {x} {class}\n"));
                }
            }
        }
    }
    std::fs::write(path, out)
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}

/// CRC-32 (IEEE) of PNG chunks.
fn crc32(data: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in data {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG (8-bit RGB) with zlib stored (uncompressed) deflate blocks.
pub fn png_rgb(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
    let mut raw = Vec::with_capacity((w as usize * 3 + 1) * h as usize);
    for y in 0..h as usize {
        raw.push(0);
        raw.extend_from_slice(&rgb[y * w as usize * 3..(y + 1) * w as usize * 3]);
    }
    let mut z = vec![0x78, 0x01];
    for (i, chunk) in raw.chunks(65535).enumerate() {
        let last = (i + 1) * 65535 >= raw.len();
        z.push(last as u8);
        let n = chunk.len() as u16;
        z.extend_from_slice(&n.to_le_bytes());
        z.extend_from_slice(&(!n).to_le_bytes());
        z.extend_from_slice(chunk);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &x in &raw {
        a = (a + x as u32) % 65521;
        b = (b + a) % 65521;
    }
    z.extend_from_slice(&((b << 16) | a).to_be_bytes());
    let mut png = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut chunk = |kind: &[u8; 4], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut c = kind.to_vec();
        c.extend_from_slice(data);
        png.extend_from_slice(&c);
        png.extend_from_slice(&crc32(&c).to_be_bytes());
    };
    let mut ihdr = vec![];
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &z);
    chunk(b"IEND", &[]);
    png
}

/// A 4 x 4 montage of z-slices (surface dark red, interior grey, outside
/// white), each slice at most 256 pixels wide.
fn write_preview(path: &Path, slabs: &[SlabBits], res: u32, fill: bool) -> CliResult {
    let tiles = 16u32.min(res);
    let cols = 4u32;
    let rows = tiles.div_ceil(cols);
    let step = res.div_ceil(256).max(1);
    let tw = res.div_ceil(step);
    let gap = 4u32;
    let (w, h) = (cols * (tw + gap) + gap, rows * (tw + gap) + gap);
    let mut img = vec![60u8; (w * h * 3) as usize];
    for t in 0..tiles {
        let z = ((t as u64 * 2 + 1) * res as u64 / (tiles as u64 * 2)) as u32;
        let Some(s) = slabs.iter().find(|s| z >= s.z0 && z < s.z1) else {
            continue;
        };
        let (ox, oy) = (gap + (t % cols) * (tw + gap), gap + (t / cols) * (tw + gap));
        for py in 0..tw {
            for px in 0..tw {
                let (x, y) = (px * step, res - 1 - (py * step).min(res - 1));
                let c = if bit(s, res, x, y, z, false) {
                    [150, 20, 20]
                } else if bit(s, res, x, y, z, true) {
                    if fill {
                        [170, 170, 170]
                    } else {
                        [235, 235, 235]
                    }
                } else {
                    [255, 255, 255]
                };
                let i = (((oy + py) * w + ox + px) * 3) as usize;
                img[i..i + 3].copy_from_slice(&c);
            }
        }
    }
    std::fs::write(path, png_rgb(w, h, &img))
        .map_err(|e| CliError::failure(format!("cannot write {}: {e}", path.display())))
}

/// Runs the verb.
pub fn run(a: &VoxelizeArgs) -> CliResult {
    let adjacency = Adjacency::from_n(a.adjacency).ok_or_else(|| {
        CliError::input(format!(
            "--adjacency must be 6, 18 or 26, got {}",
            a.adjacency
        ))
    })?;
    if !(2..=4096).contains(&a.res) {
        return Err(CliError::input(format!(
            "--res must be in 2..=4096, got {}",
            a.res
        )));
    }
    if !(1..=64).contains(&a.presplit) || !a.presplit.is_power_of_two() {
        return Err(CliError::input(
            "--presplit must be a power of two in 1..=64",
        ));
    }
    let mesh = Mesh::load(&a.mesh)?;
    let (tables, _) = build_tables(&Weights::STANDARD)?;
    let res = [a.res; 3];
    let params = VoxelParams {
        res,
        adjacency,
        presplit: a.presplit,
    };
    with_mesh(&mesh, &tables, |ctx| {
        let ev = &ctx.evaluator;
        let t0 = Instant::now();
        let mut work = Box::new(VoxelWork::ZERO);
        let t = fit_transform(ev, res, &mut work)
            .map_err(|e| CliError::failure(format!("{}: {e}", mesh.name)))?;
        let threads = rayon::current_num_threads();
        let cuts = cuts(a.res, threads);
        let bar = (std::io::stderr().is_terminal() && a.res >= 256).then(|| {
            let pb = ProgressBar::with_draw_target(
                Some((cuts.len() - 1) as u64),
                ProgressDrawTarget::stderr(),
            );
            if let Ok(style) =
                ProgressStyle::with_template("voxelizing [{bar:40}] {pos}/{len} slabs")
            {
                pb.set_style(style.progress_chars("=> "));
            }
            pb
        });
        let out = run_slabs(ev, &params, t, &cuts, true, bar.as_ref(), |g, st| {
            (slab_bits(g), st, g.counts())
        })
        .map_err(|e| CliError::failure(format!("{}: {e}", mesh.name)))?;
        if let Some(b) = &bar {
            b.finish_and_clear();
        }
        let seconds = t0.elapsed().as_secs_f64();
        let (mut surface, mut interior, mut area) = (0u64, 0u64, 0.0);
        let mut slabs = Vec::with_capacity(out.len());
        for (bits, st, c) in out {
            surface += c.surface;
            interior += c.interior;
            area += st.quad_area;
            slabs.push(bits);
        }
        let volume = (surface + interior) as f64 / t.scale.powi(3);
        write_binvox(&a.output, &slabs, a.res, &t, a.fill)?;
        if let Some(p) = &a.runs {
            write_runs(p, &slabs, a.res, a.fill)?;
        }
        if let Some(p) = &a.preview {
            write_preview(p, &slabs, a.res, a.fill)?;
        }
        let line = format!(
            "res={} adjacency={} surface={surface} interior={interior} volume={volume:.9e} area={area:.9e} seconds={seconds:.4} threads={threads}\n",
            a.res, a.adjacency
        );
        let mut o = std::io::stdout().lock();
        o.write_all(line.as_bytes())
            .and_then(|_| o.flush())
            .map_err(|e| CliError::write(&e))
    })
}
