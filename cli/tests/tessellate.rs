//! Integration tests of `ccss tessellate` and `ccss bench tessellate`: the
//! summary line, the three output formats (OBJ polygons and triangles,
//! binary STL, binary PLY) read back and checked for closedness, and the
//! usage errors.

mod common;

use common::{ccss, data, num, out_dir, text};
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Output;

/// The key=value pairs of the summary line (checked to be the only line).
fn summary(o: &Output) -> HashMap<String, String> {
    common::summary(
        o,
        &[
            "polygons",
            "triangles",
            "vertices",
            "max_depth",
            "uniform_depth",
            "au_ratio",
            "bound",
            "seconds",
        ],
    )
}

/// Every directed edge once and its reverse once.
fn closed(faces: &[Vec<usize>]) -> bool {
    let mut e: HashMap<(usize, usize), usize> = HashMap::new();
    for f in faces {
        for k in 0..f.len() {
            *e.entry((f[k], f[(k + 1) % f.len()])).or_default() += 1;
        }
    }
    e.iter()
        .all(|(&(a, b), &n)| n == 1 && e.get(&(b, a)) == Some(&1))
}

fn read_obj(path: &PathBuf) -> (usize, usize, Vec<Vec<usize>>) {
    let s = std::fs::read_to_string(path).unwrap();
    let (mut v, mut vn, mut f) = (0, 0, Vec::new());
    for l in s.lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.first() {
            Some(&"v") => v += 1,
            Some(&"vn") => vn += 1,
            Some(&"f") => f.push(
                t[1..]
                    .iter()
                    .map(|x| x.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (v, vn, f)
}

#[test]
fn obj_polygons_and_triangles_are_closed() {
    let out = out_dir("tessellate-cli").join("pyramid.obj");
    let o = ccss(&[
        "tessellate",
        "--abs-flatness",
        "0.005",
        data("catmark_pyramid.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let kv = summary(&o);
    let (v, vn, f) = read_obj(&out);
    assert_eq!(v as f64, num(&kv, "vertices"));
    assert_eq!(vn, v);
    assert_eq!(f.len() as f64, num(&kv, "polygons"));
    assert!(
        f.iter().any(|p| p.len() > 4),
        "expected polygons with extra side points"
    );
    assert!(closed(&f));
    assert!(num(&kv, "bound") <= 0.005);
    assert!(num(&kv, "uniform_depth") >= num(&kv, "max_depth"));
    let au = num(&kv, "au_ratio");
    assert!(au > 0.0 && au <= 1.0);
    let expect_au = num(&kv, "polygons") / (13.0 * 4f64.powf(num(&kv, "uniform_depth")));
    assert!((au - expect_au).abs() <= 1e-6 * expect_au + 1e-6);
    let tri = out_dir("tessellate-cli").join("pyramid-tri.obj");
    let o = ccss(&[
        "tessellate",
        "--abs-flatness",
        "0.005",
        "--triangulate",
        data("catmark_pyramid.obj").to_str().unwrap(),
        "-o",
        tri.to_str().unwrap(),
    ]);
    let kv2 = summary(&o);
    let (v2, _, t) = read_obj(&tri);
    assert_eq!(v2, v);
    assert!(t.iter().all(|x| x.len() == 3));
    assert_eq!(t.len() as f64, num(&kv2, "triangles"));
    assert!(closed(&t));
}

#[test]
fn stl_is_binary_triangles_and_closed() {
    let out = out_dir("tessellate-cli").join("torus.stl");
    let o = ccss(&[
        "tessellate",
        "--rel-flatness",
        "0.1",
        data("catmark_torus.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let kv = summary(&o);
    let b = std::fs::read(&out).unwrap();
    let n = u32::from_le_bytes(b[80..84].try_into().unwrap()) as usize;
    assert_eq!(n as f64, num(&kv, "triangles"));
    assert_eq!(b.len(), 84 + 50 * n);
    let mut ids: HashMap<[u32; 3], usize> = HashMap::new();
    let mut faces = Vec::new();
    for t in 0..n {
        let r = &b[84 + 50 * t..84 + 50 * t + 50];
        let f = |k: usize| u32::from_le_bytes(r[4 * k..4 * k + 4].try_into().unwrap());
        faces.push(
            (0..3)
                .map(|c| {
                    let k = ids.len();
                    *ids.entry([f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c)])
                        .or_insert(k)
                })
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(ids.len() as f64, num(&kv, "vertices"));
    assert!(closed(&faces));
}

#[test]
fn ply_is_binary_with_normals() {
    let out = out_dir("tessellate-cli").join("cube.ply");
    let o = ccss(&[
        "tessellate",
        "--abs-flatness",
        "0.02",
        data("catmark_cube.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let kv = summary(&o);
    let b = std::fs::read(&out).unwrap();
    let h = b"end_header\n";
    let at = b.windows(h.len()).position(|w| w == h).unwrap() + h.len();
    let header = String::from_utf8(b[..at].to_vec()).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    let nv = num(&kv, "vertices") as usize;
    let np = num(&kv, "polygons") as usize;
    assert!(header.contains(&format!("element vertex {nv}\n")));
    assert!(header.contains(&format!("element face {np}\n")));
    assert!(header.contains("property double nx\n"));
    // Vertices (6 doubles each), then faces (count byte + indices).
    let mut p = at + 48 * nv;
    let mut faces = Vec::new();
    for _ in 0..np {
        let k = b[p] as usize;
        p += 1;
        faces.push(
            (0..k)
                .map(|i| {
                    u32::from_le_bytes(b[p + 4 * i..p + 4 * i + 4].try_into().unwrap()) as usize
                })
                .collect::<Vec<_>>(),
        );
        p += 4 * k;
    }
    assert_eq!(p, b.len());
    assert!(closed(&faces));
    // Unit normals.
    for v in 0..nv {
        let d = |k: usize| {
            f64::from_le_bytes(
                b[at + 48 * v + 8 * k..at + 48 * v + 8 * k + 8]
                    .try_into()
                    .unwrap(),
            )
        };
        let l = (d(3) * d(3) + d(4) * d(4) + d(5) * d(5)).sqrt();
        assert!((l - 1.0).abs() < 1e-12, "{l}");
    }
}

#[test]
fn usage_errors() {
    let mesh = data("catmark_cube.obj");
    let m = mesh.to_str().unwrap();
    let o = out_dir("tessellate-cli").join("x.obj");
    let os = o.to_str().unwrap();
    for (args, want) in [
        (vec!["tessellate", m, "-o", os], "--abs-flatness"),
        (
            vec![
                "tessellate",
                "--abs-flatness",
                "0.1",
                "--rel-flatness",
                "0.1",
                m,
                "-o",
                os,
            ],
            "cannot be used with",
        ),
        (
            vec!["tessellate", "--abs-flatness", "-1", m, "-o", os],
            "positive and finite",
        ),
        (
            vec!["tessellate", "--abs-flatness", "0.1", m, "-o", "x.off"],
            "unknown output format",
        ),
        (
            vec![
                "tessellate",
                "--abs-flatness",
                "1e-12",
                "--max-level",
                "4",
                m,
                "-o",
                os,
            ],
            "max_level",
        ),
    ] {
        let r = ccss(&args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", text(&r.stderr));
        let err = text(&r.stderr);
        assert!(
            err.starts_with("ccss: error: ") && err.contains(want),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn bench_prints_adaptive_and_uniform_lines() {
    // The cube at AF 0.01, one timed run, with the flags `extra`: stdout.
    let bench = |extra: &[&str]| {
        let cube = data("catmark_cube.obj");
        let mut args = vec![
            "bench",
            "tessellate",
            cube.to_str().unwrap(),
            "--abs-flatness",
            "0.01",
            "--reps",
            "1",
        ];
        args.extend_from_slice(extra);
        let o = ccss(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        text(&o.stdout)
    };
    let s = bench(&[]);
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines.len(), 3, "{s}");
    assert!(
        lines[0].starts_with("ccss adaptive criterion=abs:0.01 slots=6 ")
            && lines[0].contains("mvertices_per_s="),
        "{s}"
    );
    assert!(
        lines[1].starts_with("ccss uniform depth=") && lines[1].contains("mvertices_per_s="),
        "{s}"
    );
    assert!(lines[2].starts_with("ccss au_ratio="), "{s}");
    assert!(lines[0].ends_with(" outputs=full"), "{s}");
    // Positions and polygons only: the same tessellation, another output.
    let m = bench(&["--adaptive-only", "--mesh-only"]);
    let key = |line: &str, k: &str| {
        line.split(' ')
            .find_map(|kv| kv.strip_prefix(k).map(str::to_owned))
            .unwrap_or_default()
    };
    let mesh = m.lines().next().unwrap_or_default();
    assert!(mesh.ends_with(" outputs=mesh"), "{m}");
    for k in ["polygons=", "vertices=", "bound="] {
        assert_eq!(key(mesh, k), key(lines[0], k), "{k} {m} {s}");
    }
    assert_ne!(
        key(mesh, "checksum="),
        key(lines[0], "checksum="),
        "{m} {s}"
    );
}

/// The summary line of the feature path.
fn feature_summary(o: &Output) -> HashMap<String, String> {
    common::summary(
        o,
        &[
            "polygons",
            "triangles",
            "vertices",
            "max_depth",
            "uniform_depth",
            "au_ratio",
            "bound",
            "seconds",
            "boundary_edges",
        ],
    )
}

/// Tagged, open and holed meshes take the feature path: no "tags ignored"
/// warning, the bound met, a closed creased cube gives a closed output, an
/// open mesh an output whose one-polygon edges are as many as reported and
/// lie on the input's boundary (a flat strip with sharp corners, whose
/// limit boundary is its border), `--boundary none` and a tagged hole make
/// faces holes.
#[test]
fn tags_open_meshes_and_holes_take_the_feature_path() {
    let dir = out_dir("tessellate-cli");
    // The creased cube: closed.
    let out = dir.join("creases.obj");
    let o = ccss(&[
        "tessellate",
        "--abs-flatness",
        "0.01",
        data("catmark_cube_creases0.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!text(&o.stderr).contains("ignored"), "{}", text(&o.stderr));
    let kv = feature_summary(&o);
    assert!(num(&kv, "bound") <= 0.01);
    assert_eq!(num(&kv, "boundary_edges"), 0.0);
    assert_eq!(kv["uniform_depth"], "-");
    let (v, vn, f) = read_obj(&out);
    assert_eq!(
        (v as f64, vn as f64),
        (num(&kv, "vertices"), num(&kv, "vertices"))
    );
    assert_eq!(f.len() as f64, num(&kv, "polygons"));
    assert!(closed(&f));
    // An open strip of two quads, then with a tagged hole, then with
    // boundary mode none (every face a hole: nothing to tessellate).
    let strip = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n";
    let path = dir.join("strip.obj");
    std::fs::write(&path, strip).unwrap();
    let holed = dir.join("strip_hole.obj");
    std::fs::write(&holed, format!("{strip}t hole 1/0/0 1\n")).unwrap();
    let mut polys = vec![];
    for (input, tri) in [(&path, false), (&path, true), (&holed, false)] {
        let out = dir.join("strip_out.obj");
        // Corners sharp: the limit boundary of the flat strip is its border.
        let mut args = vec![
            "tessellate",
            "--boundary",
            "edge-corner",
            "--rel-flatness",
            "0.01",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        if tri {
            args.push("--triangulate");
        }
        let o = ccss(&args);
        let kv = feature_summary(&o);
        let (v, _, f) = read_obj(&out);
        assert_eq!(v as f64, num(&kv, "vertices"));
        // One-polygon edges: on the border of the flat input.
        let s = std::fs::read_to_string(&out).unwrap();
        let p: Vec<[f64; 3]> = s
            .lines()
            .filter(|l| l.starts_with("v "))
            .map(|l| {
                let x: Vec<f64> = l[2..]
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                [x[0], x[1], x[2]]
            })
            .collect();
        let mut e: HashMap<(usize, usize), usize> = HashMap::new();
        for face in &f {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                *e.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let xmax = if input == &holed { 1.0 } else { 2.0 };
        let at = |a: f64, b: f64| (a - b).abs() < 1e-12;
        let border =
            |q: [f64; 3]| at(q[0], 0.0) || at(q[0], xmax) || at(q[1], 0.0) || at(q[1], 1.0);
        let boundary: Vec<_> = e.iter().filter(|(_, &n)| n == 1).collect();
        assert_eq!(boundary.len() as f64, num(&kv, "boundary_edges"));
        assert!(!boundary.is_empty());
        for (&(a, b), _) in boundary {
            assert!(border(p[a]) && border(p[b]), "{:?} {:?}", p[a], p[b]);
            // On one side of the border.
            assert!(
                at(p[a][0], p[b][0]) || at(p[a][1], p[b][1]),
                "{:?} {:?}",
                p[a],
                p[b]
            );
        }
        assert!(p.iter().all(|q| q[2] == 0.0 && q[0] <= xmax + 1e-12));
        polys.push(f.len());
    }
    // The holed strip has half the polygons.
    assert_eq!(2 * polys[2], polys[0]);
    // Boundary mode none: both faces are holes, nothing to write but a
    // valid (empty) tessellation.
    let out = dir.join("strip_none.obj");
    let o = ccss(&[
        "tessellate",
        "--abs-flatness",
        "0.01",
        "--boundary",
        "none",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let kv = feature_summary(&o);
    assert_eq!(num(&kv, "polygons"), 0.0);
}
