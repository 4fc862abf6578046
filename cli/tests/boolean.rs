//! `ccss boolean` end to end: the summary line, a closed oriented OBJ with
//! shared vertices, the curve file (closed `l` polylines whose points are
//! output vertices), disjoint solids (note, empty intersection), and the
//! one-line errors (eps, format, open mesh, unknown op), and `--uv`
//! (every output vertex re-evaluated within the bound, smooth and creased).

mod common;
use common::*;
use std::collections::HashMap;

const KEYS: [&str; 10] = [
    "triangles",
    "vertices",
    "curve_loops",
    "curve_points",
    "tolerance",
    "amplification",
    "bound",
    "passes",
    "local",
    "seconds",
];

/// The cube moved by `t` (and rotated about z by `a`), as an OBJ file.
fn moved_cube(dir: &std::path::Path, name: &str, t: [f64; 3], a: f64) -> String {
    let src = std::fs::read_to_string(data("catmark_cube.obj")).unwrap();
    let (s, c) = a.sin_cos();
    let mut out = String::new();
    for l in src.lines() {
        if let Some(rest) = l.strip_prefix("v ") {
            let p: Vec<f64> = rest
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            let (x, y) = (c * p[0] - s * p[1], s * p[0] + c * p[1]);
            out += &format!("v {} {} {}\n", x + t[0], y + t[1], p[2] + t[2]);
        } else if l.starts_with("f ") {
            out += l;
            out += "\n";
        }
    }
    let p = dir.join(name);
    std::fs::write(&p, out).unwrap();
    p.to_str().unwrap().to_string()
}

/// Vertices, faces and polylines of an OBJ file (0-based).
type Obj = (Vec<[f64; 3]>, Vec<Vec<usize>>, Vec<Vec<usize>>);

fn read_obj(path: &std::path::Path) -> Obj {
    let (mut v, mut f, mut l) = (Vec::new(), Vec::new(), Vec::new());
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let p: Vec<f64> = it.map(|x| x.parse().unwrap()).collect();
                v.push([p[0], p[1], p[2]]);
            }
            Some("f") => f.push(
                it.map(|x| x.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            Some("l") => l.push(it.map(|x| x.parse::<usize>().unwrap() - 1).collect()),
            _ => {}
        }
    }
    (v, f, l)
}

#[test]
fn union_writes_closed_mesh_and_curve() {
    let dir = out_dir("boolean");
    let a = data("catmark_cube.obj");
    let b = moved_cube(&dir, "b.obj", [0.53, 0.31, 0.22], 0.37);
    let out = dir.join("u.obj");
    let curve = dir.join("c.obj");
    let o = ccss(&[
        "boolean",
        "--op",
        "union",
        "--eps",
        "0.02",
        a.to_str().unwrap(),
        &b,
        "-o",
        out.to_str().unwrap(),
        "--curve",
        curve.to_str().unwrap(),
    ]);
    let kv = summary(&o, &KEYS);
    assert!(num(&kv, "bound") <= 0.02 && num(&kv, "curve_loops") >= 1.0);
    let (v, f, _) = read_obj(&out);
    assert_eq!(v.len(), num(&kv, "vertices") as usize);
    assert_eq!(f.len(), num(&kv, "triangles") as usize);
    let mut e = HashMap::new();
    for t in &f {
        assert_eq!(t.len(), 3);
        for k in 0..3 {
            *e.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    assert!(e
        .iter()
        .all(|(&(x, y), &n)| n == 1 && e.get(&(y, x)) == Some(&1)));
    // Curve loops: closed, every point an output vertex.
    let (cv, _, cl) = read_obj(&curve);
    assert_eq!(cl.len(), num(&kv, "curve_loops") as usize);
    let pts: std::collections::HashSet<[u64; 3]> = v.iter().map(|p| p.map(f64::to_bits)).collect();
    for l in &cl {
        assert_eq!(l.first(), l.last());
        assert!(l.len() >= 4);
    }
    assert!(cv.iter().all(|p| pts.contains(&p.map(f64::to_bits))));
}

#[test]
fn disjoint_solids_and_errors() {
    let dir = out_dir("boolean_errors");
    let a = data("catmark_cube.obj");
    let a = a.to_str().unwrap();
    let far = moved_cube(&dir, "far.obj", [5.0, 0.1, 0.2], 0.0);
    let out = dir.join("i.stl");
    let o = ccss(&[
        "boolean",
        "--op",
        "intersection",
        "--eps",
        "0.05",
        a,
        &far,
        "-o",
        out.to_str().unwrap(),
    ]);
    let kv = summary(&o, &KEYS);
    assert_eq!(num(&kv, "triangles"), 0.0);
    assert!(text(&o.stderr).contains("note: the surfaces do not cross"));
    let u = dir.join("u.ply");
    let o = ccss(&[
        "boolean",
        "--op",
        "union",
        "--eps",
        "0.05",
        a,
        &far,
        "-o",
        u.to_str().unwrap(),
    ]);
    assert!(num(&summary(&o, &KEYS), "triangles") > 0.0);
    let one_line_error = |args: &[&str], want: &str| {
        let o = ccss(args);
        assert!(!o.status.success(), "{args:?}");
        let e = text(&o.stderr);
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.starts_with("ccss: error: ") && e.contains(want), "{e}");
    };
    let o = out.to_str().unwrap();
    one_line_error(
        &["boolean", "--op", "union", "--eps", "0", a, &far, "-o", o],
        "positive",
    );
    one_line_error(
        &["boolean", "--op", "union", "--eps", "nan", a, &far, "-o", o],
        "positive",
    );
    one_line_error(
        &["boolean", "--op", "xor", "--eps", "0.1", a, &far, "-o", o],
        "xor",
    );
    one_line_error(
        &[
            "boolean", "--op", "union", "--eps", "0.1", a, &far, "-o", "x.txt",
        ],
        "format",
    );
    let open = data("catmark_edgeonly.obj");
    one_line_error(
        &[
            "boolean",
            "--op",
            "union",
            "--eps",
            "0.1",
            a,
            open.to_str().unwrap(),
            "-o",
            o,
        ],
        "not a closed solid",
    );
    let help = ccss(&["boolean", "--help"]);
    assert!(help.status.success() && text(&help.stdout).contains("--curve"));
}

/// `--uv`: one line per output triangle; every output vertex re-evaluated
/// on the exact surface of its solid (independent evaluator built from the
/// input OBJ) at its reported `(face, sub, u, v)` lies within the printed
/// bound of the OBJ vertex (zero violations; worst ratio printed).
#[test]
fn uv_file_reevaluates_within_bound() {
    use ccss_tests::harness::{standard_tables, with_evaluator};
    use ccss_tests::reference::PolyMesh;
    let dir = out_dir("boolean_uv");
    let a = data("catmark_cube.obj");
    let b = moved_cube(&dir, "b.obj", [0.41, -0.27, 0.33], 0.61);
    let out = dir.join("d.obj");
    let uv = dir.join("d.tsv");
    let o = ccss(&[
        "boolean",
        "--op",
        "difference",
        "--eps",
        "0.02",
        a.to_str().unwrap(),
        &b,
        "-o",
        out.to_str().unwrap(),
        "--uv",
        uv.to_str().unwrap(),
    ]);
    let kv = summary(&o, &KEYS);
    let bound = num(&kv, "bound");
    let (v, f, _) = read_obj(&out);
    let lines: Vec<Vec<String>> = std::fs::read_to_string(&uv)
        .unwrap()
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect())
        .collect();
    assert_eq!(lines.len(), f.len());
    let tables = standard_tables();
    let (ma, mb) = (
        PolyMesh::from_obj(&a),
        PolyMesh::from_obj(std::path::Path::new(&b)),
    );
    let mut worst = 0.0f64;
    let mut seen = [0usize; 2];
    with_evaluator(&ma, tables, |_, ea| {
        with_evaluator(&mb, tables, |_, eb| {
            for (t, l) in f.iter().zip(&lines) {
                assert_eq!(l.len(), 9, "{l:?}");
                let n: Vec<f64> = l.iter().map(|x| x.parse().unwrap()).collect();
                let ev = if n[0] == 0.0 { ea } else { eb };
                seen[n[0] as usize] += 1;
                for c in 0..3 {
                    let (u, w) = (n[3 + 2 * c], n[4 + 2 * c]);
                    let p = ev.eval(n[1] as u32, n[2] as u32, u, w).unwrap().p;
                    let d = (p - ccss_core::DVec3::from_array(v[t[c]])).length();
                    assert!(d <= bound, "{l:?} vertex {c}: {d:e} > bound {bound:e}");
                    worst = worst.max(d / bound);
                }
            }
        })
        .unwrap()
    })
    .unwrap();
    assert!(seen[0] > 0 && seen[1] > 0);
    eprintln!(
        "--uv: {} vertices re-evaluated, worst distance / bound {worst:.3e}",
        3 * f.len()
    );
}

/// `--uv` on the feature path (semi-sharply creased cube, union): every
/// output vertex of A re-evaluated by `ccss eval` (exact, with the file's
/// crease tags) at its reported `(face, u, v, sub)` lies within the printed
/// bound of the OBJ vertex.
#[test]
fn uv_file_on_creased_solid() {
    let dir = out_dir("boolean_uv_creased");
    let a = data("catmark_cube_creases1.obj");
    let b = moved_cube(&dir, "b.obj", [0.93, 0.11, -0.17], 0.37);
    let out = dir.join("u.obj");
    let uv = dir.join("u.tsv");
    let o = ccss(&[
        "boolean",
        "--op",
        "union",
        "--eps",
        "0.02",
        a.to_str().unwrap(),
        &b,
        "-o",
        out.to_str().unwrap(),
        "--uv",
        uv.to_str().unwrap(),
    ]);
    let kv = summary(&o, &KEYS);
    let bound = num(&kv, "bound");
    let (v, f, _) = read_obj(&out);
    let text = std::fs::read_to_string(&uv).unwrap();
    assert_eq!(text.lines().count(), f.len());
    let mut queries = String::new();
    let mut want = Vec::new();
    for (t, l) in f.iter().zip(text.lines()) {
        let n: Vec<&str> = l.split('\t').collect();
        assert_eq!(n.len(), 9, "{l}");
        if n[0] != "0" {
            continue;
        }
        for c in 0..3 {
            queries += &format!("{} {} {} {}\n", n[1], n[3 + 2 * c], n[4 + 2 * c], n[2]);
            want.push(v[t[c]]);
        }
    }
    assert!(!want.is_empty());
    let e = ccss_stdin(&["eval", a.to_str().unwrap()], &queries);
    assert!(e.status.success(), "{}", String::from_utf8_lossy(&e.stderr));
    let lines = String::from_utf8(e.stdout).unwrap();
    let mut worst = 0.0f64;
    let mut n = 0;
    for (l, w) in lines.lines().zip(&want) {
        let p: Vec<f64> = l
            .split_whitespace()
            .take(3)
            .map(|x| x.parse().unwrap())
            .collect();
        let d = ((p[0] - w[0]).powi(2) + (p[1] - w[1]).powi(2) + (p[2] - w[2]).powi(2)).sqrt();
        assert!(d <= bound, "{d:e} > bound {bound:e}");
        worst = worst.max(d / bound);
        n += 1;
    }
    assert_eq!(n, want.len());
    eprintln!("--uv creased: {n} vertices of A re-evaluated, worst distance / bound {worst:.3e}");
}

/// `path` with every face's vertex order reversed (the same surface,
/// inside out).
fn reversed_faces(src: &str, dst: &std::path::Path) -> String {
    let mut out = String::new();
    for l in std::fs::read_to_string(src).unwrap().lines() {
        match l.strip_prefix("f ") {
            Some(rest) => {
                let mut vs: Vec<&str> = rest.split_whitespace().collect();
                vs.reverse();
                out += &format!("f {}\n", vs.join(" "));
            }
            None => {
                out += l;
                out += "\n";
            }
        }
    }
    std::fs::write(dst, out).unwrap();
    dst.to_str().unwrap().to_string()
}

/// Signed volume of a triangle OBJ.
fn obj_volume(path: &std::path::Path) -> f64 {
    let (v, f, _) = read_obj(path);
    let d = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    };
    f.iter().map(|t| d(v[t[0]], v[t[1]], v[t[2]])).sum::<f64>() / 6.0
}

/// An inside-out input (faces clockwise seen from outside, like
/// OpenSubdiv's catmark_lefthanded) is taken as the solid it bounds, with
/// a note: the output is the one of the outward mesh, bit for bit (the
/// same tessellation, its triangles reversed before the combination).
/// Without the orientation step the union with an inside-out B would be
/// the boundary of A's union with B's complement (negative volume).
#[test]
fn inside_out_input_is_taken_as_its_solid() {
    let dir = out_dir("boolean_inside_out");
    let a = data("catmark_cube.obj");
    let b = moved_cube(&dir, "b.obj", [0.53, 0.31, 0.22], 0.37);
    let b_rev = reversed_faces(&b, &dir.join("b_rev.obj"));
    let a_rev = reversed_faces(a.to_str().unwrap(), &dir.join("a_rev.obj"));
    for op in ["union", "intersection", "difference"] {
        let run = |x: &str, y: &str, name: &str| {
            let out = dir.join(name);
            let o = ccss(&[
                "boolean",
                "--op",
                op,
                "--eps",
                "0.02",
                x,
                y,
                "-o",
                out.to_str().unwrap(),
            ]);
            let kv = summary(&o, &KEYS);
            (out, kv, text(&o.stderr))
        };
        let (plain, kv, err) = run(a.to_str().unwrap(), &b, &format!("{op}.obj"));
        assert!(!err.contains("inside out"), "{op}: {err}");
        let vol = obj_volume(&plain);
        assert!(vol > 0.0, "{op}: volume {vol}");
        let plain_obj = read_obj(&plain);
        for (x, y, which) in [
            (a.to_str().unwrap(), b_rev.as_str(), "b_rev"),
            (a_rev.as_str(), b.as_str(), "a_rev"),
        ] {
            let (out, kv2, err) = run(x, y, &format!("{op}-{which}.obj"));
            assert!(err.contains("inside out"), "{op} {which}: {err}");
            assert_eq!(kv["triangles"], kv2["triangles"], "{op} {which}");
            assert_eq!(kv["bound"], kv2["bound"], "{op} {which}");
            // The same points (reversed faces reparametrize the patches:
            // the same dyadic cells, the vertices met in another order;
            // curve points computed from reversed triangles may differ in
            // the last bits).
            let got = read_obj(&out);
            let near = |x: &[[f64; 3]], y: &[[f64; 3]]| {
                x.iter().all(|p| {
                    y.iter()
                        .any(|q| (0..3).all(|k| (p[k] - q[k]).abs() <= 1e-12))
                })
            };
            assert_eq!(plain_obj.0.len(), got.0.len(), "{op} {which}: vertices");
            assert!(
                near(&plain_obj.0, &got.0) && near(&got.0, &plain_obj.0),
                "{op} {which}"
            );
            let v2 = obj_volume(&out);
            assert!(
                (v2 - vol).abs() <= 1e-12 * vol.abs(),
                "{op} {which}: {v2} vs {vol}"
            );
        }
    }
}
