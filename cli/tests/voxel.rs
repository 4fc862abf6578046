//! Integration tests of `ccss voxelize`, `ccss measure` and
//! `ccss bench voxelize`: the summary lines, the binvox file decoded by a
//! reader written here from the format's description (header, RLE pairs,
//! x-slowest / z / y-fastest order, the voxel <-> model mapping through
//! `translate` and `scale`), limit-surface points from `ccss eval` landing
//! in set voxels, the runs file against the binvox data, the PNG preview,
//! voxel volumes bracketing the exact volume of `ccss measure`, and usage
//! errors.

mod common;

use common::{ccss, data, num, summary, text};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn out_dir() -> PathBuf {
    common::out_dir("voxel-cli")
}

/// A binvox file: `dim` per axis, model box `[t, t + s]^3`, voxels in
/// binvox order (index `x * dim^2 + z * dim + y`).
struct Binvox {
    dim: usize,
    translate: [f64; 3],
    scale: f64,
    bits: Vec<bool>,
}

impl Binvox {
    fn read(path: &PathBuf) -> Binvox {
        let b = std::fs::read(path).unwrap();
        let mut pos = 0;
        let mut line = || {
            let end = pos + b[pos..].iter().position(|&c| c == b'\n').unwrap();
            let l = text(&b[pos..end]);
            pos = end + 1;
            l
        };
        assert_eq!(line(), "#binvox 1");
        let (mut dim, mut translate, mut scale) = (0, [0.0; 3], 0.0);
        loop {
            let l = line();
            let w: Vec<&str> = l.split(' ').collect();
            match w[0] {
                "dim" => {
                    let d: Vec<usize> = w[1..].iter().map(|x| x.parse().unwrap()).collect();
                    assert!(d[0] == d[1] && d[1] == d[2], "{l}");
                    dim = d[0];
                }
                "translate" => {
                    for (t, x) in translate.iter_mut().zip(&w[1..]) {
                        *t = x.parse().unwrap();
                    }
                }
                "scale" => scale = w[1].parse().unwrap(),
                "data" => break,
                _ => panic!("unexpected header line {l}"),
            }
        }
        let mut bits = Vec::with_capacity(dim * dim * dim);
        for pair in b[pos..].chunks(2) {
            assert_eq!(pair.len(), 2, "odd RLE data");
            assert!(pair[0] <= 1 && pair[1] >= 1, "bad RLE pair {pair:?}");
            bits.extend(std::iter::repeat_n(pair[0] == 1, pair[1] as usize));
        }
        assert_eq!(bits.len(), dim * dim * dim);
        Binvox {
            dim,
            translate,
            scale,
            bits,
        }
    }

    fn get(&self, v: [usize; 3]) -> bool {
        let n = self.dim;
        self.bits[v[0] * n * n + v[2] * n + v[1]]
    }

    fn count(&self) -> u64 {
        self.bits.iter().filter(|&&b| b).count() as u64
    }

    /// Voxel coordinates (continuous) of a model point: voxel i covers
    /// `[i, i + 1)`.
    fn coords(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| (p[a] - self.translate[a]) / self.scale * self.dim as f64)
    }

    fn voxel_of(&self, p: [f64; 3]) -> Option<[usize; 3]> {
        let c = self.coords(p);
        if c.iter().all(|&x| x >= 0.0 && x < self.dim as f64) {
            Some(c.map(|x| x.floor() as usize))
        } else {
            None
        }
    }

    fn cell_volume(&self) -> f64 {
        (self.scale / self.dim as f64).powi(3)
    }
}

/// Limit points and unit normals at `(face, u, v)` queries, by `ccss eval`.
fn limit_points(mesh: &PathBuf, queries: &[(usize, f64, f64)]) -> Vec<([f64; 3], [f64; 3])> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ccss"))
        .arg("eval")
        .arg(mesh)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = String::new();
    for (f, u, v) in queries {
        input.push_str(&format!("{f} {u} {v}\n"));
    }
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    text(&out.stdout)
        .lines()
        .map(|l| {
            let x: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            let (du, dv) = ([x[3], x[4], x[5]], [x[6], x[7], x[8]]);
            let n = [
                du[1] * dv[2] - du[2] * dv[1],
                du[2] * dv[0] - du[0] * dv[2],
                du[0] * dv[1] - du[1] * dv[0],
            ];
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            ([x[0], x[1], x[2]], n.map(|c| c / l))
        })
        .collect()
}

const VOXELIZE_KEYS: [&str; 8] = [
    "res",
    "adjacency",
    "surface",
    "interior",
    "volume",
    "area",
    "seconds",
    "threads",
];

/// `ccss <base> <out> <extra>`'s summary (`base` ends with `-o`).
fn voxelize(base: &[&str], out: &Path, extra: &[&str]) -> HashMap<String, String> {
    let mut args = base.to_vec();
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    summary(&ccss(&args), &VOXELIZE_KEYS)
}

fn face_count(mesh: &PathBuf) -> usize {
    std::fs::read_to_string(mesh)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("f "))
        .count()
}

/// Width, height and RGB bytes of an 8-bit RGB PNG file.
fn decode_png(file: &[u8]) -> (u32, u32, Vec<u8>) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// The preview layout of `ccss voxelize --help`: up to 16 z-slices in 4
/// columns, each at most 256 pixels wide (every `step`-th voxel), 4-pixel
/// gaps. Returns (tiles, step, tile width).
fn preview_layout(res: u32) -> (u32, u32, u32) {
    let tiles = 16.min(res);
    let step = res.div_ceil(256).max(1);
    (tiles, step, res.div_ceil(step))
}

fn preview_size(res: u32) -> (u32, u32) {
    let (tiles, _, tw) = preview_layout(res);
    (4 * (tw + 4) + 4, tiles.div_ceil(4) * (tw + 4) + 4)
}

/// The montage of a `--fill` run from its binvox files: slice t is the
/// layer z = (2t + 1) res / 32, y up; surface dark red, interior grey,
/// outside white, gaps dark grey.
fn expected_preview(surface: &Binvox, filled: &Binvox) -> Vec<u8> {
    let res = surface.dim as u32;
    let (tiles, step, tw) = preview_layout(res);
    let (w, h) = preview_size(res);
    let mut img = vec![60u8; (w * h * 3) as usize];
    for t in 0..tiles {
        let z = (t * 2 + 1) * res / (tiles * 2);
        let (ox, oy) = (4 + (t % 4) * (tw + 4), 4 + (t / 4) * (tw + 4));
        for py in 0..tw {
            for px in 0..tw {
                let v = [px * step, res - 1 - (py * step).min(res - 1), z].map(|c| c as usize);
                let c = if surface.get(v) {
                    [150, 20, 20]
                } else if filled.get(v) {
                    [170, 170, 170]
                } else {
                    [255, 255, 255]
                };
                let i = (((oy + py) * w + ox + px) * 3) as usize;
                img[i..i + 3].copy_from_slice(&c);
            }
        }
    }
    img
}

#[test]
fn binvox_runs_and_preview_agree_with_the_summary_and_the_surface() {
    for (name, res, adj) in [
        ("catmark_cube.obj", 40u32, 6u32),
        ("catmark_torus.obj", 48, 26),
    ] {
        let mesh = data(name);
        let dir = out_dir();
        let stem = name.trim_end_matches(".obj");
        let (bv, bv_fill, runs, png) = (
            dir.join(format!("{stem}.binvox")),
            dir.join(format!("{stem}_fill.binvox")),
            dir.join(format!("{stem}.runs")),
            dir.join(format!("{stem}.png")),
        );
        let r = res.to_string();
        let a = adj.to_string();
        let m = mesh.to_str().unwrap();
        let base = ["voxelize", "--res", &r, "--adjacency", &a, m, "-o"];
        let s = voxelize(&base, &bv, &[]);
        let f = voxelize(
            &base,
            &bv_fill,
            &[
                "--fill",
                "--runs",
                runs.to_str().unwrap(),
                "--preview",
                png.to_str().unwrap(),
            ],
        );
        assert_eq!(num(&s, "res"), res as f64);
        assert_eq!(num(&s, "adjacency"), adj as f64);
        assert_eq!(s["surface"], f["surface"]);
        let (surface, interior) = (num(&f, "surface") as u64, num(&f, "interior") as u64);
        assert!(surface > 0 && interior > 0, "{f:?}");

        // The files hold exactly the reported voxels.
        let b = Binvox::read(&bv);
        let bf = Binvox::read(&bv_fill);
        assert_eq!(b.dim, res as usize);
        assert_eq!(b.count(), surface, "{name}");
        assert_eq!(bf.count(), surface + interior, "{name}");
        assert!(b.bits.iter().zip(&bf.bits).all(|(s, f)| !s || *f));
        assert_eq!((b.translate, b.scale), (bf.translate, bf.scale));
        // The summary's volume is (surface + interior) voxel volumes.
        let vol = (surface + interior) as f64 * b.cell_volume();
        assert!((num(&f, "volume") - vol).abs() <= 1e-9 * vol, "{f:?}");

        // Runs: 'z y x0 x1 class' lines, the same voxels and classes.
        let mut from_runs = vec![0u8; bf.bits.len()];
        let mut count = [0u64; 3];
        for l in std::fs::read_to_string(&runs).unwrap().lines() {
            if l.starts_with('#') {
                continue;
            }
            let w: Vec<usize> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            let (z, y, x0, x1, class) = (w[0], w[1], w[2], w[3], w[4]);
            assert!(
                x0 < x1 && x1 <= res as usize && (1..=2).contains(&class),
                "{l}"
            );
            for x in x0..x1 {
                let i = x * b.dim * b.dim + z * b.dim + y;
                assert_eq!(from_runs[i], 0, "overlapping runs: {l}");
                from_runs[i] = class as u8;
                count[class] += 1;
            }
        }
        assert_eq!((count[1], count[2]), (surface, interior), "{name}");
        for (i, &c) in from_runs.iter().enumerate() {
            assert_eq!(c != 0, bf.bits[i], "{name} voxel {i}");
            assert_eq!(c == 1, b.bits[i], "{name} voxel {i}");
        }

        // The preview is a PNG: the montage of z-slices, pixel for pixel.
        let p = std::fs::read(&png).unwrap();
        assert_eq!(&p[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(&p[12..16], b"IHDR");
        let (w, h, rgb) = decode_png(&p);
        assert_eq!((w, h), preview_size(res), "{name}");
        assert_eq!(rgb, expected_preview(&b, &bf), "{name}");

        // Limit points: with 6-adjacency their voxel is set (a surface voxel,
        // skipping points within 1e-4 voxel of a voxel face), with 26 a
        // surface voxel is next to it; the voxel 2.5 voxels inside along the
        // normal is set, 2.5 outside is clear (where those lie in the grid).
        let faces = face_count(&mesh);
        let mut q = vec![];
        for fi in 0..faces {
            for i in 0..7 {
                for j in 0..7 {
                    q.push((fi, (i as f64 + 0.31) / 7.0, (j as f64 + 0.57) / 7.0));
                }
            }
        }
        let h = b.scale / b.dim as f64;
        let (mut on, mut checked) = (0, 0);
        for (p, n) in limit_points(&mesh, &q) {
            let v = b.voxel_of(p).expect("limit point outside the grid");
            if adj == 6 {
                assert!(bf.get(v), "{name}: voxel of {p:?} is clear");
            } else {
                // Thin surfaces: a surface voxel among the 27 around it.
                let near = (0..27).any(|k| {
                    let d = [k % 3, k / 3 % 3, k / 9];
                    let w = [0, 1, 2].map(|a| (v[a] + d[a]).wrapping_sub(1));
                    w.iter().all(|&x| x < b.dim) && b.get(w)
                });
                assert!(near, "{name}: no surface voxel next to {p:?}");
            }
            let c = b.coords(p);
            let margin = c.iter().map(|x| (x - x.round()).abs()).fold(1.0, f64::min);
            if adj == 6 && margin > 1e-4 {
                assert!(b.get(v), "{name}: voxel of {p:?} is not a surface voxel");
                on += 1;
            }
            let at = |d: f64| [0, 1, 2].map(|a| p[a] + d * h * n[a]);
            if let Some(vi) = bf.voxel_of(at(-2.5)) {
                assert!(bf.get(vi), "{name}: inside of {p:?} is clear");
                checked += 1;
            }
            if let Some(vo) = bf.voxel_of(at(2.5)) {
                assert!(!bf.get(vo), "{name}: outside of {p:?} is set");
            }
        }
        assert!(checked > q.len() / 2, "{name}: {checked} of {}", q.len());
        assert!(adj != 6 || on > q.len() / 2, "{name}: {on}");
    }
}

#[test]
fn measure_brackets_the_voxel_volume_and_scales_mass() {
    let mesh = data("catmark_cube.obj");
    let m = summary(
        &ccss(&["measure", mesh.to_str().unwrap(), "--density", "2.5"]),
        &[
            "volume",
            "area",
            "centroid",
            "inertia",
            "mass",
            "error_bound",
            "area_error_bound",
            "seconds",
        ],
    );
    let v = num(&m, "volume");
    assert!((num(&m, "mass") - 2.5 * v).abs() <= 1e-12 * v);
    assert!(num(&m, "error_bound") < 1e-9 * v);
    let c: Vec<f64> = m["centroid"]
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(c.len() == 3 && c.iter().all(|x| x.abs() < 1e-12), "{c:?}");
    let inertia: Vec<f64> = m["inertia"]
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(inertia.len(), 6);
    // Cube symmetry: equal principal moments, no products.
    assert!((inertia[0] - inertia[1]).abs() < 1e-9 && (inertia[1] - inertia[2]).abs() < 1e-6);
    assert!(inertia[3..].iter().all(|x| x.abs() < 1e-12));
    // 6-adjacency voxels: interior voxels lie inside the solid, and the solid
    // inside interior + surface voxels.
    for res in ["24", "48"] {
        let out = out_dir().join(format!("measure_{res}.binvox"));
        let m = mesh.to_str().unwrap();
        let base = ["voxelize", "--res", res, "--adjacency", "6", m, "-o"];
        let s = voxelize(&base, &out, &["--fill"]);
        let cell = Binvox::read(&out).cell_volume();
        let (sf, it) = (num(&s, "surface"), num(&s, "interior"));
        assert!(it * cell < v && v < (sf + it) * cell, "{s:?} exact {v}");
    }
}

#[test]
fn bench_voxelize_ccss_only_prints_two_lines() {
    let o = ccss(&[
        "bench",
        "voxelize",
        data("catmark_torus.obj").to_str().unwrap(),
        "--res",
        "32",
        "--reps",
        "1",
        "--ccss-only",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines.len(), 2, "{s}");
    assert!(lines[0].starts_with("ccss res=32 adjacency=26 "), "{s}");
    assert!(lines[1].starts_with("walk cells="), "{s}");
    assert!(lines[1].ends_with(" guard_hits=0"), "{s}");
}

#[test]
fn voxel_usage_errors_exit_non_zero_with_one_line() {
    let cube = data("catmark_cube.obj");
    let out = out_dir().join("err.binvox");
    let (c, o) = (cube.to_str().unwrap(), out.to_str().unwrap());
    for args in [
        vec!["voxelize", "--res", "1", c, "-o", o],
        vec!["voxelize", "--res", "16", "--adjacency", "7", c, "-o", o],
        vec!["voxelize", "--res", "16", "--presplit", "3", c, "-o", o],
        vec!["voxelize", "--res", "16", "/nonexistent.obj", "-o", o],
        vec!["measure", c, "--density", "-1"],
        vec!["measure", "/nonexistent.obj"],
    ] {
        let r = ccss(&args);
        assert!(!r.status.success(), "{args:?} succeeded");
        let e = text(&r.stderr);
        assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
        assert!(e.starts_with("ccss: error: "), "{args:?}: {e}");
    }
}
