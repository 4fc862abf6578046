//! Integration tests of the `ccss` binary: output format, values, exit codes
//! and messages of `eval`, `info`, `bench eval`, `bench tables` and `depth`.

mod common;
// The CLI's block helpers (8-byte aligned memory for the core builders).
#[path = "../src/mem.rs"]
mod mem;

use common::{data, text};
use std::path::PathBuf;
use std::process::Output;

/// Runs `ccss args...` with `stdin` as standard input.
fn ccss(args: &[&str], stdin: &str) -> Output {
    common::ccss_stdin(args, stdin)
}

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// The stderr lines that are errors: there must be exactly one.
fn one_error_line(o: &Output) -> String {
    let err = text(&o.stderr);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("ccss: error: "))
        .collect();
    assert_eq!(lines.len(), 1, "stderr: {err}");
    assert!(
        err.lines().all(|l| l.starts_with("ccss: ")),
        "stderr: {err}"
    );
    lines[0].to_string()
}

/// Minimal OBJ reader for the reference computations: positions and faces
/// (0-based `v`-line indices) of a file without negative indices.
fn read_obj(name: &str) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let s = std::fs::read_to_string(data(name)).unwrap();
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for l in s.lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.first() {
            Some(&"v") => v.push([
                t[1].parse().unwrap(),
                t[2].parse().unwrap(),
                t[3].parse().unwrap(),
            ]),
            Some(&"f") => f.push(
                t[1..]
                    .iter()
                    .map(|x| x.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (v, f)
}

type V3 = [f64; 3];
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn avg(ps: &[V3]) -> V3 {
    scale(
        ps.iter().fold([0.0; 3], |s, &p| add(s, p)),
        1.0 / ps.len() as f64,
    )
}

/// Limit position of vertex `c` of an all-quad closed mesh by the classic
/// mask `(n^2 V + 4 sum E + sum D) / (n (n + 5))` (E: edge neighbours, D:
/// the opposite corners of the incident quads).
fn limit_of_vertex(v: &[V3], f: &[Vec<usize>], c: usize) -> V3 {
    let (mut e, mut d, mut n) = ([0.0; 3], [0.0; 3], 0.0);
    for q in f.iter().filter(|q| q.contains(&c)) {
        let k = q.iter().position(|&x| x == c).unwrap();
        // Each edge neighbour is seen from its two quads: weight 1/2 each.
        e = add(e, scale(add(v[q[(k + 1) % 4]], v[q[(k + 3) % 4]]), 0.5));
        d = add(d, v[q[(k + 2) % 4]]);
        n += 1.0;
    }
    scale(
        add(add(scale(v[c], n * n), scale(e, 4.0)), d),
        1.0 / (n * (n + 5.0)),
    )
}

/// Limit position of the centre of quad `fi`: after one Catmull-Clark step
/// the centre is the face point, a regular (valence 4) vertex whose edge
/// neighbours are the edge points of the face and whose diagonal
/// neighbours are the new vertex points of its corners; apply the regular
/// mask `(16 V + 4 sum E + sum D) / 36` to those level-1 points.
fn limit_of_face_centre(v: &[V3], f: &[Vec<usize>], fi: usize) -> V3 {
    let face_point = |q: &Vec<usize>| avg(&q.iter().map(|&i| v[i]).collect::<Vec<_>>());
    let faces_of_edge = |a: usize, b: usize| {
        f.iter()
            .filter(|q| q.contains(&a) && q.contains(&b))
            .map(face_point)
            .collect::<Vec<_>>()
    };
    let edge_point = |a: usize, b: usize| {
        let fp = faces_of_edge(a, b);
        avg(&[v[a], v[b], fp[0], fp[1]])
    };
    let vertex_point = |c: usize| {
        // (Q + 2R + (n-3) V) / n: Q average of face points, R of edge midpoints.
        let fs: Vec<&Vec<usize>> = f.iter().filter(|q| q.contains(&c)).collect();
        let n = fs.len() as f64;
        let q = avg(&fs.iter().map(|q| face_point(q)).collect::<Vec<_>>());
        let mids: Vec<V3> = fs
            .iter()
            .map(|q| {
                let k = q.iter().position(|&x| x == c).unwrap();
                scale(add(v[c], v[q[(k + 1) % q.len()]]), 0.5)
            })
            .collect();
        let r = avg(&mids);
        scale(add(add(q, scale(r, 2.0)), scale(v[c], n - 3.0)), 1.0 / n)
    };
    let q = &f[fi];
    let mut e = [0.0; 3];
    let mut d = [0.0; 3];
    for k in 0..4 {
        e = add(e, edge_point(q[k], q[(k + 1) % 4]));
        d = add(d, vertex_point(q[k]));
    }
    scale(
        add(add(scale(face_point(q), 16.0), scale(e, 4.0)), d),
        1.0 / 36.0,
    )
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn cube_face_centre_and_corner() {
    let cube = data("catmark_cube.obj");
    let o = ccss(&["eval", cube.to_str().unwrap()], "0 0.5 0.5\n0 0 0\n");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2);
    let (v, f) = read_obj("catmark_cube.obj");
    // Face 0 of catmark_cube.obj is the top face z = +1 (f 1 2 4 3). With all
    // z coordinates exactly +-1 the reference z is 68/81: face point 1, edge
    // points 3/4, vertex points 5/9 -> (16 + 4*4*3/4 + 4*5/9) / 36.
    let centre = limit_of_face_centre(&v, &f, 0);
    assert!((centre[2] - 68.0 / 81.0).abs() < 1e-15, "{centre:?}");
    let c = numbers(lines[0]);
    assert_eq!(c.len(), 9);
    assert!(close(&c[..3], &centre, 1e-12), "{c:?} vs {centre:?}");
    assert!((c[2] - 68.0 / 81.0).abs() < 1e-14, "{}", c[2]);
    // Corner (0,0) is v0 of the face, a valence-3 vertex.
    let corner = limit_of_vertex(&v, &f, f[0][0]);
    let p = numbers(lines[1]);
    assert!(close(&p[..3], &corner, 1e-12), "{p:?} vs {corner:?}");
    // 17 significant digits, {:.16e}.
    for tok in lines[0].split(' ') {
        let mantissa = tok.split('e').next().unwrap().trim_start_matches('-');
        assert_eq!(mantissa.len(), 18, "{tok}");
    }
}

#[test]
fn torus_matches_limit_mask_at_corners() {
    // All vertices regular: every corner of every face is a limit point.
    let torus = data("catmark_torus.obj");
    let (v, f) = read_obj("catmark_torus.obj");
    let mut input = String::new();
    for fi in 0..f.len() {
        input += &format!("{fi} 0 0\n{fi} 1 0\n{fi} 1 1\n{fi} 0 1\n");
    }
    let o = ccss(&["eval", torus.to_str().unwrap()], &input);
    assert!(o.status.success());
    let out = text(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 4 * f.len());
    for (i, l) in lines.iter().enumerate() {
        let (fi, k) = (i / 4, i % 4);
        let want = limit_of_vertex(&v, &f, f[fi][k]);
        assert!(
            close(&numbers(l)[..3], &want, 1e-12),
            "face {fi} corner {k}"
        );
    }
}

#[test]
fn second_adds_nine_numbers() {
    let cube = data("catmark_cube.obj");
    let input = "0 0.25 0.75\n3 0.1 0.9\n";
    let a = ccss(&["eval", cube.to_str().unwrap()], input);
    let b = ccss(&["eval", "--second", cube.to_str().unwrap()], input);
    assert!(a.status.success() && b.status.success());
    let (a, b) = (text(&a.stdout), text(&b.stdout));
    for (la, lb) in a.lines().zip(b.lines()) {
        let (na, nb) = (numbers(la), numbers(lb));
        assert_eq!(na.len(), 9);
        assert_eq!(nb.len(), 18);
        assert_eq!(na[..], nb[..9]);
    }
    assert_eq!(b.lines().count(), 2);
}

#[test]
fn eval_skips_comments_and_takes_sub() {
    // Pyramid: face 0 is a triangle (3 sub-faces), face 4 the quad base.
    let pyr = data("catmark_pyramid.obj");
    let o = ccss(
        &["eval", pyr.to_str().unwrap()],
        "# header\n\n  0 0.5 0.5 2\n\t4 0.5 0.5 0\n",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout).lines().count(), 2);
    let o = ccss(&["eval", pyr.to_str().unwrap()], "0 0.5 0.5 3\n");
    assert_eq!(o.status.code(), Some(2));
    let e = one_error_line(&o);
    assert!(e.contains("stdin line 1: face 0 has no sub-face 3"), "{e}");
    assert!(e.contains("0..=2"), "{e}");
}

#[test]
fn eval_errors_name_the_line() {
    let cube = data("catmark_cube.obj");
    let m = cube.to_str().unwrap();
    // Output of the lines before the bad one is written, then the error.
    let o = ccss(&["eval", m], "0 0.5 0.5\n# comment\n\n0 1.5 0.5\n0 0 0\n");
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        one_error_line(&o),
        "ccss: error: stdin line 4: u = 1.5 is outside [0, 1]"
    );
    assert_eq!(text(&o.stdout).lines().count(), 1);

    let cases = [
        ("6 0 0\n", "stdin line 1: face 6 does not exist"),
        ("0 0 0\n0 0 0 1\n", "stdin line 2: face 0 has no sub-face 1"),
        ("0 nan 0\n", "stdin line 1: u is NaN"),
        ("0 0 -0.1\n", "stdin line 1: v = -0.1 is outside [0, 1]"),
        (
            "zero 0 0\n",
            "stdin line 1: face 'zero' is not a non-negative integer",
        ),
        (
            "0 0\n",
            "stdin line 1: expected 'face u v [sub]', got 2 fields",
        ),
        (
            "0 0 0 0 0\n",
            "stdin line 1: expected 'face u v [sub]', got 5 fields",
        ),
    ];
    for (input, want) in cases {
        let o = ccss(&["eval", m], input);
        assert_eq!(o.status.code(), Some(2), "{input:?}");
        let e = one_error_line(&o);
        assert!(e.contains(want), "{input:?}: {e}");
    }
}

#[test]
fn many_lines_keep_order() {
    // More than one chunk (4096 lines) and one parallel batch.
    let cube = data("catmark_cube.obj");
    let n = 20_000;
    let mut input = String::new();
    for i in 0..n {
        input += &format!(
            "{} {} {}\n",
            i % 6,
            (i % 101) as f64 / 100.0,
            (i % 37) as f64 / 36.0
        );
    }
    let all = ccss(&["eval", cube.to_str().unwrap()], &input);
    assert!(all.status.success());
    let all = text(&all.stdout);
    assert_eq!(all.lines().count(), n);
    // Line 12345 on its own gives the same result.
    let one = ccss(
        &["eval", cube.to_str().unwrap()],
        input.lines().nth(12345).unwrap(),
    );
    assert_eq!(
        text(&one.stdout).trim_end(),
        all.lines().nth(12345).unwrap()
    );
}

#[test]
fn info_cube() {
    let o = ccss(&["info", data("catmark_cube.obj").to_str().unwrap()], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for want in [
        "vertices: 8",
        "faces: 6",
        "edges: 12",
        "face size 4: 6",
        "valence 3: 8",
        "euler characteristic: 2",
        "genus: 0",
        "regular patches: ",
        "extraordinary patches: ",
        "internal refinement levels: ",
        "topology bytes: ",
        "evaluator bytes: ",
        "tables bytes: ",
    ] {
        assert!(
            out.lines().any(|l| l.starts_with(want)),
            "missing {want:?} in\n{out}"
        );
    }
    assert!(out.lines().all(|l| l.contains(": ")), "{out}");
    assert!(o.stderr.is_empty());
}

#[test]
fn info_open_mesh_is_described_by_opensubdiv_rules() {
    let o = ccss(
        &["info", data("catmark_edgeonly.obj").to_str().unwrap()],
        "",
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.contains("faces: 20"), "{out}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("boundary edges: ") && !l.ends_with(": 0")),
        "{out}"
    );
    // Its 'interpolateboundary' tag is used, not ignored.
    assert!(out.contains("surface: OpenSubdiv's rules"), "{out}");
    assert!(out.contains("boundary interpolation: edge-only"), "{out}");
    assert!(o.stderr.is_empty(), "{}", text(&o.stderr));
    assert!(out.lines().all(|l| l.contains(": ")), "{out}");
}

#[test]
fn bench_prints_class_lines() {
    let m = data("catmark_righthanded.obj");
    let o = ccss(
        &[
            "bench",
            "eval",
            m.to_str().unwrap(),
            "--points",
            "1000",
            "--samples",
            "3",
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for cls in ["R", "X"] {
        let prefix = format!("ccss class={cls} points=1000 ns_per_eval=");
        let line = out
            .lines()
            .find(|l| l.starts_with(&prefix))
            .unwrap_or_else(|| panic!("{out}"));
        let ns: f64 = line[prefix.len()..].parse().unwrap();
        assert!(ns > 0.0 && ns.is_finite(), "{line}");
    }
    // Per-valence sub-classes of X add up to X.
    let sub: usize = out
        .lines()
        .filter(|l| l.starts_with("ccss class=X") && !l.starts_with("ccss class=X "))
        .map(|l| {
            l.split("points=")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse::<usize>()
                .unwrap()
        })
        .sum();
    assert_eq!(sub, 1000, "{out}");
    assert!(
        out.lines().any(|l| l.starts_with("ccss checksum=")),
        "{out}"
    );
}

#[test]
fn bench_points_file_round_trip() {
    let m = data("catmark_righthanded.obj");
    let m = m.to_str().unwrap();
    let dir = std::env::temp_dir().join(format!("ccss-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pts = dir.join("pts.txt");
    let p = pts.to_str().unwrap();
    let w = ccss(
        &[
            "bench",
            "eval",
            m,
            "--points",
            "300",
            "--seed",
            "9",
            "--write-points",
            p,
        ],
        "",
    );
    assert!(w.status.success(), "{}", text(&w.stderr));
    let file = std::fs::read_to_string(&pts).unwrap();
    let rows: Vec<&str> = file.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows.len(), 600);
    assert!(rows.iter().all(|r| r.ends_with(" R") || r.contains(" X X")));
    let checksum = |o: &Output| {
        text(&o.stdout)
            .lines()
            .find(|l| l.starts_with("ccss checksum="))
            .unwrap()
            .to_string()
    };
    let gen = ccss(
        &[
            "bench",
            "eval",
            m,
            "--points",
            "300",
            "--seed",
            "9",
            "--samples",
            "1",
        ],
        "",
    );
    let from = ccss(
        &["bench", "eval", m, "--points-file", p, "--samples", "1"],
        "",
    );
    assert!(
        gen.status.success() && from.status.success(),
        "{}",
        text(&from.stderr)
    );
    assert_eq!(checksum(&gen), checksum(&from));
    // A bad points line names the file line.
    std::fs::write(&pts, "# c\n0 0 0.5 0.5 R\n0 0 0.5 2 X\n").unwrap();
    let bad = ccss(&["bench", "eval", m, "--points-file", p], "");
    assert_eq!(bad.status.code(), Some(2));
    assert!(one_error_line(&bad).ends_with("line 3: v = 2 is outside [0, 1]"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn usage_and_file_errors() {
    let o = ccss(&["eval", "--no-such-flag", "x.obj"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("'--no-such-flag'"));
    let o = ccss(&["eval", "/nonexistent/mesh.obj"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("/nonexistent/mesh.obj: cannot read"));
    let o = ccss(&["--version"], "");
    assert!(o.status.success());
    assert!(text(&o.stdout).starts_with("ccss "));
    for verb in [
        &["eval", "--help"][..],
        &["info", "--help"],
        &["bench", "eval", "--help"],
        &["bench", "tables", "--help"],
        &["depth", "--help"],
    ] {
        let o = ccss(verb, "");
        assert!(o.status.success());
        assert!(text(&o.stdout).contains("Usage: ccss"), "{verb:?}");
    }
}

/// A scratch directory for files of one test.
fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ccss-cli-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The general vertex rule `V' = a V + b/n sum E + g/n sum D` (E: edge
/// neighbours, D: opposite corners) on an all-quad mesh.
fn weighted_vertex_point(v: &[V3], f: &[Vec<usize>], c: usize, (a, b, g): (f64, f64, f64)) -> V3 {
    let (mut e, mut d, mut n) = ([0.0; 3], [0.0; 3], 0.0);
    for q in f.iter().filter(|q| q.contains(&c)) {
        let k = q.iter().position(|&x| x == c).unwrap();
        e = add(e, v[q[(k + 1) % 4]]); // each edge once: the one after c
        d = add(d, v[q[(k + 2) % 4]]);
        n += 1.0;
    }
    add(add(scale(v[c], a), scale(e, b / n)), scale(d, g / n))
}

/// The limit point of corner `c` of an all-quad mesh under the general rule
/// (Cheng & Lai eq. 2.7): `(5 V + (12b+8g) Ebar + (2b+8g) Dbar) /
/// (5 + 14b + 16g)`.
fn weighted_limit_of_vertex(v: &[V3], f: &[Vec<usize>], c: usize, b: f64, g: f64) -> V3 {
    let (mut e, mut d, mut n) = ([0.0; 3], [0.0; 3], 0.0);
    for q in f.iter().filter(|q| q.contains(&c)) {
        let k = q.iter().position(|&x| x == c).unwrap();
        e = add(e, v[q[(k + 1) % 4]]);
        d = add(d, v[q[(k + 2) % 4]]);
        n += 1.0;
    }
    let num = add(
        add(scale(v[c], 5.0), scale(e, (12.0 * b + 8.0 * g) / n)),
        scale(d, (2.0 * b + 8.0 * g) / n),
    );
    scale(num, 1.0 / (5.0 + 14.0 * b + 16.0 * g))
}

/// [`limit_of_face_centre`] with the general rule `w` for every vertex of
/// the quad (edge and face points standard; the centre itself is a regular
/// vertex after one step, with the standard regular mask).
fn weighted_limit_of_face_centre(v: &[V3], f: &[Vec<usize>], fi: usize, w: (f64, f64, f64)) -> V3 {
    let face_point = |q: &Vec<usize>| avg(&q.iter().map(|&i| v[i]).collect::<Vec<_>>());
    let edge_point = |a: usize, b: usize| {
        let fp: Vec<V3> = f
            .iter()
            .filter(|q| q.contains(&a) && q.contains(&b))
            .map(face_point)
            .collect();
        avg(&[v[a], v[b], fp[0], fp[1]])
    };
    let q = &f[fi];
    let mut e = [0.0; 3];
    let mut d = [0.0; 3];
    for k in 0..4 {
        e = add(e, edge_point(q[k], q[(k + 1) % 4]));
        d = add(d, weighted_vertex_point(v, f, q[k], w));
    }
    scale(
        add(add(scale(face_point(q), 16.0), scale(e, 4.0)), d),
        1.0 / 36.0,
    )
}

#[test]
fn weights_change_eval_as_the_general_rule_says() {
    let cube = data("catmark_cube.obj");
    let m = cube.to_str().unwrap();
    let dir = scratch_dir("weights-eval");
    let wf = dir.join("w.tsv");
    std::fs::write(
        &wf,
        "# n alpha beta gamma\n\n3\t0.5 0.3 0.2   # all cube vertices\n",
    )
    .unwrap();
    let w = wf.to_str().unwrap();
    let input = "0 0 0\n0 0.5 0.5\n";
    let std_out = ccss(&["eval", m], input);
    let out = ccss(&["eval", "--weights", w, m], input);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    let (sl, wl) = (text(&std_out.stdout), text(&out.stdout));
    let wl: Vec<Vec<f64>> = wl.lines().map(numbers).collect();
    let sl: Vec<Vec<f64>> = sl.lines().map(numbers).collect();
    assert_eq!(wl.len(), 2);
    let (v, f) = read_obj("catmark_cube.obj");
    // The corner (face 0, (0,0) = its vertex 0, of valence 3).
    let want = weighted_limit_of_vertex(&v, &f, f[0][0], 0.3, 0.2);
    assert!(close(&wl[0][..3], &want, 1e-12), "{:?} vs {want:?}", wl[0]);
    let standard = limit_of_vertex(&v, &f, f[0][0]);
    assert!(close(&sl[0][..3], &standard, 1e-12));
    assert!(
        !close(&wl[0][..3], &standard, 1e-3),
        "weights had no effect"
    );
    // The face centre: one step with the rule, then the regular mask.
    let want = weighted_limit_of_face_centre(&v, &f, 0, (0.5, 0.3, 0.2));
    assert!(close(&wl[1][..3], &want, 1e-12), "{:?} vs {want:?}", wl[1]);
    assert!(!close(&wl[1][..3], &sl[1][..3], 1e-3));
    // Standard weights given explicitly change nothing.
    std::fs::write(&wf, "3 0.41666666666666663 0.5 0.083333333333333329\n").unwrap();
    let same = ccss(&["eval", "--weights", w, m], input);
    assert!(same.status.success(), "{}", text(&same.stderr));
    assert_eq!(text(&same.stdout), text(&std_out.stdout));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_weight_files_name_the_line() {
    let cube = data("catmark_cube.obj");
    let m = cube.to_str().unwrap();
    let dir = scratch_dir("weights-bad");
    let wf = dir.join("W.tsv");
    let w = wf.to_str().unwrap();
    let cases = [
        (
            "3 0.5 0.3 0.2\n# the regular rule is fixed\n4 0.5 0.3 0.2\n",
            "line 3: weights for valence 4 rejected: valence 4 must keep the standard rule (regular patches are bicubic B-splines)",
        ),
        (
            "\n5 0.9 0.3 -0.2\n",
            "line 2: weights for valence 5 rejected: a weight is negative",
        ),
        (
            "5 0.6 0.3 0.2\n",
            "line 1: weights for valence 5 rejected: alpha + beta + gamma is not 1",
        ),
        (
            "3 nan 0.5 0.5\n",
            "line 1: weights for valence 3 rejected: a weight is NaN or infinite",
        ),
        (
            "2 0.5 0.3 0.2\n",
            "line 1: weights for valence 2 rejected: valence outside 3..=16",
        ),
        ("3 0.5 0.3\n", "line 1: expected 'n alpha beta gamma', got 3 fields"),
        ("3 0.5 0.3 0.2 x\n", "line 1: expected 'n alpha beta gamma', got 5 fields"),
        ("3 0.5 zero 0.2\n", "line 1: beta 'zero' is not a number"),
        ("three 0.5 0.3 0.2\n", "line 1: valence 'three' is not a non-negative integer"),
        (
            "3 0.5 0.3 0.2\n3 0.5 0.3 0.2\n",
            "line 2: weights for valence 3 are already given on line 1",
        ),
    ];
    for (body, want) in cases {
        let want = want.replace("3..=16", &format!("3..={}", ccss_core::MAX_VALENCE));
        std::fs::write(&wf, body).unwrap();
        for args in [
            &["eval", "--weights", w, m][..],
            &["info", "--weights", w, m],
            &["bench", "eval", "--weights", w, m, "--points", "10"],
            &["bench", "tables", "--weights", w, "--reps", "1"],
            &["depth", "--eps", "0.01", "--weights", w, m],
            &["depth", "--rates", "3", "--weights", w],
        ] {
            let o = ccss(args, "0 0 0\n");
            assert_eq!(o.status.code(), Some(2), "{args:?} {body:?}");
            assert_eq!(
                one_error_line(&o),
                format!("ccss: error: {w} {want}"),
                "{args:?}"
            );
            assert!(o.stdout.is_empty(), "{args:?}: {}", text(&o.stdout));
        }
    }
    let missing = dir.join("missing.tsv");
    let o = ccss(&["eval", "--weights", missing.to_str().unwrap(), m], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("missing.tsv: cannot read"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn info_prints_the_rule_of_each_valence() {
    let dir = scratch_dir("weights-info");
    let wf = dir.join("w.tsv");
    let w = wf.to_str().unwrap();
    // Pyramid: an apex of valence 4, four base corners of valence 3, four
    // triangles (centres of valence 3) and a quad base.
    let pyr = data("catmark_pyramid.obj");
    let p = pyr.to_str().unwrap();
    std::fs::write(&wf, "3 0.98 0.01 0.01\n5 0.5 0.3 0.2\n").unwrap();
    let o = ccss(&["info", "--weights", w, p], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let lines: Vec<&str> = out.lines().filter(|l| l.starts_with("weights ")).collect();
    // x^2 - 0.73 x + 0.06125 has the root 0.633 > lambda_2(3) = 0.410;
    // valence 4: standard (9/16, 3/8, 1/16).
    assert_eq!(
        lines,
        [
            "weights 3: 0.98 0.01 0.01 tangent_plane_continuous=no",
            "weights 4: 0.5625 0.375 0.0625 tangent_plane_continuous=yes",
        ],
        "{out}"
    );
    assert!(out.lines().all(|l| l.contains(": ")), "{out}");
    // Without --weights: no such lines.
    let o = ccss(&["info", p], "");
    assert!(!text(&o.stdout).contains("weights "));
    // The cube with a rule for valence 3.
    std::fs::write(&wf, "3 0.5 0.3 0.2\n").unwrap();
    let o = ccss(
        &[
            "info",
            "--weights",
            w,
            data("catmark_cube.obj").to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout)
            .lines()
            .any(|l| l == "weights 3: 0.5 0.3 0.2 tangent_plane_continuous=yes"),
        "{}",
        text(&o.stdout)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bench_tables_prints_one_line_per_valence() {
    let max = ccss_core::MAX_VALENCE;
    let check = |out: &str, label: &str| {
        let suffix = format!(" weights={label}");
        let lines: Vec<&str> = out.lines().filter(|l| l.ends_with(&suffix)).collect();
        assert_eq!(lines.len(), max - 2 + 1, "{out}");
        let mut sum = 0.0;
        for (n, l) in (3..=max).zip(&lines) {
            let prefix = format!("ccss tables n={n} us=");
            assert!(l.starts_with(&prefix), "{l}");
            let us: f64 = l[prefix.len()..l.len() - suffix.len()].parse().unwrap();
            assert!(us > 0.0 && us.is_finite(), "{l}");
            sum += us;
        }
        let total = lines[max - 2];
        let t: f64 = total
            .strip_prefix("ccss tables total_us=")
            .and_then(|r| r.strip_suffix(&suffix))
            .unwrap_or_else(|| panic!("{total}"))
            .parse()
            .unwrap();
        assert!((t - sum).abs() <= 0.05 * (max as f64), "{t} vs {sum}");
    };
    let o = ccss(&["bench", "tables", "--reps", "3"], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert_eq!(out.lines().count(), max - 2 + 1, "{out}");
    check(&out, "standard");

    let dir = scratch_dir("weights-bench");
    let wf = dir.join("w.tsv");
    std::fs::write(&wf, "3 0.5 0.3 0.2\n7 0.5 0.3 0.2\n").unwrap();
    let o = ccss(
        &[
            "bench",
            "tables",
            "--reps",
            "1",
            "--weights",
            wf.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert_eq!(out.lines().count(), 2 * (max - 2 + 1), "{out}");
    check(&out, "standard");
    check(&out, "custom");
    // --reps must be at least 1.
    let o = ccss(&["bench", "tables", "--reps", "0"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("ccss bench tables --help"));
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------
// ccss depth

/// The depth lines (`face depth`, `face.sub depth`) of the core API for an
/// OBJ of `tests/data/osd` (standard weights).
fn core_depth_lines(name: &str, eps: f64, method: ccss_core::bounds::depth::Method) -> Vec<String> {
    use ccss_core::{BuildScratch, Evaluator, MeshInput, TableSet, Topology, Weights};
    let (v, f) = read_obj(name);
    let positions: Vec<f64> = v.iter().flatten().copied().collect();
    let sizes: Vec<u32> = f.iter().map(|q| q.len() as u32).collect();
    let indices: Vec<u32> = f.iter().flatten().map(|&i| i as u32).collect();
    let mut tables = Box::new(TableSet::ZERO);
    tables
        .build_into(&Weights::STANDARD, &mut Box::new(BuildScratch::ZERO))
        .unwrap();
    let mut tmem = mem::words(Topology::required_bytes(v.len(), &sizes));
    let mesh = MeshInput {
        positions: &positions,
        face_sizes: &sizes,
        indices: &indices,
    };
    let topo = Topology::build(mesh, &mut tmem).unwrap();
    let need = Evaluator::required_bytes(&topo, &tables).unwrap();
    let mut emem = mem::words(need);
    let ev = Evaluator::build(&topo, &tables, &mut emem).unwrap();
    let mut d = vec![0u32; ev.num_slots()];
    ccss_core::bounds::depth::depths(&ev, eps, method, &mut d).unwrap();
    let mut lines = Vec::new();
    for fi in 0..ev.num_faces() {
        let (s0, k) = (ev.slot_start(fi), ev.num_subfaces(fi));
        if k == 1 {
            lines.push(format!("{fi} {}", d[s0]));
        } else {
            lines.extend((0..k).map(|j| format!("{fi}.{j} {}", d[s0 + j])));
        }
    }
    lines
}

/// The value of `name=` in the summary line.
fn summary_field<'a>(summary: &'a str, name: &str) -> &'a str {
    let prefix = format!("{name}=");
    summary
        .split_whitespace()
        .find_map(|t| t.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("no {name}= in {summary:?}"))
}

/// Runs `ccss depth` and splits its output into the depth lines and the
/// summary.
fn depth_run(args: &[&str]) -> (Vec<String>, String) {
    let mut all = vec!["depth"];
    all.extend_from_slice(args);
    let o = ccss(&all, "");
    assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
    assert!(o.stderr.is_empty(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let (summary, lines): (Vec<&str>, Vec<&str>) = out.lines().partition(|l| l.starts_with('#'));
    assert_eq!(summary.len(), 1, "{out}");
    assert_eq!(out.lines().last(), Some(summary[0]), "summary last");
    (
        lines.into_iter().map(str::to_string).collect(),
        summary[0].to_string(),
    )
}

#[test]
fn depth_rates_match_the_report() {
    let o = ccss(&["depth", "--rates", "5"], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert_eq!(out.lines().count(), 1, "{out}");
    let t: Vec<&str> = out.trim_end().split(' ').collect();
    assert_eq!(t.len(), 3, "{out}");
    assert_eq!(t[0], "5");
    // Report Table 2: r1 = 18/25, r2 = 0.4016 (0.401625).
    assert!(t[1].starts_with("0.720000"), "{out}");
    assert!(t[2].starts_with("0.40162") && t[2].len() == 8, "{out}");
    assert_eq!(out, "5 0.720000 0.401625\n");

    // --verbose: the same three columns, then c_new c_lemma10 r_old c_old,
    // all as the core computes them.
    let mut tables = Box::new(ccss_core::TableSet::ZERO);
    tables
        .build_into(
            &ccss_core::Weights::STANDARD,
            &mut Box::new(ccss_core::BuildScratch::ZERO),
        )
        .unwrap();
    let max = ccss_core::MAX_VALENCE;
    let o = ccss(&["depth", "--rates", "all", "--verbose"], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    let all = text(&o.stdout);
    assert_eq!(all.lines().count(), max - 2, "{all}");
    for (n, l) in (3..=max).zip(all.lines()) {
        let r = tables.get(n).unwrap().rates();
        let want = format!(
            "{n} {:.6} {:.6} {:.6} {:.6} {:.6} {:.6}",
            r.r1, r.r2, r.c_new, r.c_lemma10, r.r_old, r.c_old
        );
        assert_eq!(l, want);
    }
    let o = ccss(&["depth", "--rates", "all"], "");
    let short: Vec<String> = all
        .lines()
        .map(|l| l.split(' ').take(3).collect::<Vec<_>>().join(" "))
        .collect();
    assert_eq!(text(&o.stdout).lines().collect::<Vec<_>>(), short);
    // A rule for valence 3: the old technique's constants do not apply.
    let dir = scratch_dir("depth-rates");
    let wf = dir.join("w.tsv");
    std::fs::write(&wf, "3 0.5 0.3 0.2\n").unwrap();
    let o = ccss(
        &[
            "depth",
            "--rates",
            "3",
            "--verbose",
            "--weights",
            wf.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).ends_with(" 0.000000 0.000000\n"),
        "{}",
        text(&o.stdout)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn depth_cube_and_pyramid_agree_with_the_api() {
    use ccss_core::bounds::depth::Method;
    let methods = [
        ("old", Method::Old),
        ("new", Method::New),
        ("tight", Method::Tight),
        ("best", Method::Best),
    ];
    for name in ["catmark_cube.obj", "catmark_pyramid.obj"] {
        let m = data(name);
        for (mname, method) in methods {
            let (lines, summary) =
                depth_run(&["--eps", "0.01", "--method", mname, m.to_str().unwrap()]);
            let want = core_depth_lines(name, 0.01, method);
            assert_eq!(lines, want, "{name} {mname}");
            // The summary: counts, max, mean, histogram, times.
            let d: Vec<u32> = lines
                .iter()
                .map(|l| l.split(' ').nth(1).unwrap().parse().unwrap())
                .collect();
            assert!(summary.starts_with("# eps=0.01 method="), "{summary}");
            assert_eq!(summary_field(&summary, "method"), mname);
            assert_eq!(summary_field(&summary, "slots"), d.len().to_string());
            let faces = read_obj(name).1.len();
            assert_eq!(summary_field(&summary, "faces"), faces.to_string());
            let max = *d.iter().max().unwrap();
            assert_eq!(summary_field(&summary, "max_depth"), max.to_string());
            let mean = d.iter().sum::<u32>() as f64 / d.len() as f64;
            assert_eq!(summary_field(&summary, "mean_depth"), format!("{mean:.3}"));
            let mut hist = std::collections::BTreeMap::new();
            for &x in &d {
                *hist.entry(x).or_insert(0usize) += 1;
            }
            let h: Vec<String> = hist.iter().map(|(k, c)| format!("{k}:{c}")).collect();
            assert_eq!(summary_field(&summary, "histogram"), h.join(","));
            let secs = |f: &str| -> f64 { summary_field(&summary, f).parse().unwrap() };
            let (s, b, dd) = (
                secs("seconds"),
                secs("build_seconds"),
                secs("depth_seconds"),
            );
            assert!(b > 0.0 && dd >= 0.0, "{summary}");
            assert!((s - (b + dd)).abs() <= 2e-6, "{summary}");
        }
    }
    // The pyramid: four triangles (3 sub-faces each) and the quad base.
    let (lines, _) = depth_run(&[
        "--eps",
        "0.01",
        data("catmark_pyramid.obj").to_str().unwrap(),
    ]);
    let labels: Vec<&str> = lines.iter().map(|l| l.split(' ').next().unwrap()).collect();
    let mut want: Vec<String> = (0..4)
        .flat_map(|f| (0..3).map(move |s| format!("{f}.{s}")))
        .collect();
    want.push("4".into());
    assert_eq!(labels, want);
    // Smaller eps, deeper; the cube is uniform.
    let cube = data("catmark_cube.obj");
    let (coarse, _) = depth_run(&["--eps", "0.1", cube.to_str().unwrap()]);
    let (fine, _) = depth_run(&["--eps", "1e-4", cube.to_str().unwrap()]);
    let depth = |l: &String| l.split(' ').nth(1).unwrap().parse::<u32>().unwrap();
    assert!(coarse.iter().zip(&fine).all(|(a, b)| depth(a) < depth(b)));
    assert!(fine.iter().all(|l| depth(l) == depth(&fine[0])));
}

#[test]
fn depth_errors_exit_2() {
    let cube = data("catmark_cube.obj");
    let m = cube.to_str().unwrap();
    let cases: [(&[&str], &str); 13] = [
        (&["--eps", "0", m], "eps must be positive and finite"),
        (&["--eps", "-1", m], "eps must be positive and finite"),
        (&["--eps=-0.5", m], "eps must be positive and finite"),
        (&["--eps", "nan", m], "eps must be positive and finite"),
        (&["--eps", "inf", m], "eps must be positive and finite"),
        (&["--eps", "abc", m], "'abc' is not a number"),
        (&[m], "required arguments were not provided: --eps"),
        (
            &["--eps", "0.01"],
            "required arguments were not provided: <MESH>",
        ),
        (&["--rates", "2"], "expected a valence in 3..="),
        (&["--rates", "99"], "expected a valence in 3..="),
        (&["--rates", "5", "--eps", "0.1"], "cannot be used with"),
        (
            &["--eps", "0.1", "--method", "fast", m],
            "possible values: old, new, tight, best",
        ),
        (&["--eps", "0.1", "--verbose", m], "cannot be used with"),
    ];
    for (args, want) in cases {
        let mut all = vec!["depth"];
        all.extend_from_slice(args);
        let o = ccss(&all, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = one_error_line(&o);
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(e.ends_with("(see 'ccss depth --help')"), "{e}");
        assert!(o.stdout.is_empty(), "{args:?}");
    }
    // --method old with a non-standard rule: exit 2, naming the valence.
    let dir = scratch_dir("depth-old");
    let wf = dir.join("w.tsv");
    let w = wf.to_str().unwrap();
    std::fs::write(
        &wf,
        "3 0.41666666666666663 0.5 0.083333333333333329\n7 0.5 0.3 0.2\n",
    )
    .unwrap();
    let o = ccss(
        &[
            "depth",
            "--eps",
            "0.01",
            "--method",
            "old",
            "--weights",
            w,
            m,
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        one_error_line(&o),
        format!(
            "ccss: error: --method old needs the standard Catmull-Clark weights (Theorem 6 \
             holds only for them), but {w} changes valence 7; use --method new, tight or best"
        )
    );
    assert!(o.stdout.is_empty());
    // The other methods take the rule; old takes the standard rule restated.
    let o = ccss(
        &[
            "depth",
            "--eps",
            "0.01",
            "--method",
            "new",
            "--weights",
            w,
            m,
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    std::fs::write(&wf, "3 0.41666666666666663 0.5 0.083333333333333329\n").unwrap();
    let (std_lines, _) = depth_run(&["--eps", "0.01", "--method", "old", m]);
    let (w_lines, _) = depth_run(&["--eps", "0.01", "--method", "old", "--weights", w, m]);
    assert_eq!(std_lines, w_lines);
    // A missing mesh file is an input error too.
    let o = ccss(&["depth", "--eps", "0.01", "/nonexistent/mesh.obj"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("/nonexistent/mesh.obj: cannot read"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ccss refine`: face counts of the unified scheme and Catmull-Clark on the
/// cube, the written OBJ, and a bad split count.
#[test]
fn refine_counts_and_errors() {
    let dir = scratch_dir("refine");
    let cube = data("catmark_cube.obj");
    let m = cube.to_str().unwrap();
    let out = dir.join("out.obj");
    let o_path = out.to_str().unwrap();
    let faces_of = |line: &str| -> usize {
        line.split_whitespace()
            .find_map(|t| t.strip_prefix("faces="))
            .unwrap_or_else(|| panic!("no faces= in {line:?}"))
            .parse()
            .unwrap()
    };
    let o = ccss(
        &[
            "refine",
            "--scheme",
            "catmull-clark",
            "--levels",
            "2",
            m,
            "-o",
            o_path,
        ],
        "",
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let line = text(&o.stdout);
    assert_eq!(line.lines().count(), 1, "{line}");
    assert!(
        line.starts_with("vertices=98 faces=96 levels=2 seconds="),
        "{line}"
    );
    assert_eq!(faces_of(&line), 96);
    let obj = std::fs::read_to_string(&out).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 96);
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 98);

    let o = ccss(&["refine", "--d", "3", m, "-o", o_path], "");
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(faces_of(&text(&o.stdout)), 54);

    let o = ccss(&["refine", "--d", "1", m, "-o", o_path], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("d must be at least 2"));
    assert!(o.stdout.is_empty());

    // Worst case (docs/WORST_CASE.md): the level cap, and outputs beyond
    // the u32 counts refused at once instead of allocated.
    let o = ccss(&["refine", "--levels", "17", m, "-o", o_path], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(one_error_line(&o).contains("--levels must be in 1..=16"));
    let t0 = std::time::Instant::now();
    let o = ccss(&["refine", "--levels", "16", m, "-o", o_path], "");
    assert!(!o.status.success());
    assert!(
        one_error_line(&o).contains("too large"),
        "{}",
        text(&o.stderr)
    );
    assert!(t0.elapsed().as_secs_f64() < 30.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--classes`: the points of each class lie where the class says (checked
/// against the mesh's own faces and valences, read here from the OBJ), and
/// timing the written file gives every class line and the same checksum as
/// timing the generated points.
#[test]
fn bench_region_classes() {
    let m = data("catmark_pyramid.obj");
    let obj = std::fs::read_to_string(&m).unwrap();
    let faces: Vec<Vec<usize>> = obj
        .lines()
        .filter(|l| l.starts_with("f "))
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .map(|t| t.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                .collect()
        })
        .collect();
    // Closed mesh: valence = number of faces around the vertex.
    let mut valence = std::collections::HashMap::new();
    for f in &faces {
        for &v in f {
            *valence.entry(v).or_insert(0usize) += 1;
        }
    }
    let ev = |v: usize| valence[&v] != 4;
    let m = m.to_str().unwrap();
    let dir = std::env::temp_dir().join(format!("ccss-cli-regions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pts = dir.join("pts.txt");
    let p = pts.to_str().unwrap();
    let args = [
        "bench",
        "eval",
        m,
        "--points",
        "200",
        "--classes",
        "XUMNDCK",
    ];
    let w = ccss(&[&args[..], &["--write-points", p]].concat(), "");
    assert!(w.status.success(), "{}", text(&w.stderr));
    let file = std::fs::read_to_string(&pts).unwrap();
    let mut count = std::collections::HashMap::new();
    for row in file.lines().filter(|l| !l.starts_with('#')) {
        let t: Vec<&str> = row.split_whitespace().collect();
        let (f, sub): (usize, usize) = (t[0].parse().unwrap(), t[1].parse().unwrap());
        let (u, v): (f64, f64) = (t[2].parse().unwrap(), t[3].parse().unwrap());
        let c = t[4].chars().next().unwrap();
        *count.entry(c).or_insert(0) += 1;
        let face = &faces[f];
        let n = face.len();
        assert!(sub < if n == 4 { 1 } else { n }, "{row}");
        let d = match c {
            'N' | 'C' => 1.0 / 256.0,
            'D' | 'K' => 1.0 / (1u64 << 20) as f64,
            _ => 1.0,
        };
        let near = |cu: f64, cv: f64| (u - cu).abs() <= d && (v - cv).abs() <= d;
        match c {
            'M' => assert!(
                n == 4 && face.iter().filter(|&&x| ev(x)).count() >= 2,
                "{row}"
            ),
            'N' | 'D' if n == 4 => {
                let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                assert!(
                    (0..4).any(|k| ev(face[k]) && near(corners[k].0, corners[k].1)),
                    "{row}"
                );
            }
            'N' | 'D' => assert!(ev(face[sub]) && near(0.0, 0.0), "{row}"),
            'C' | 'K' => assert!(n != 4 && near(1.0, 1.0), "{row}"),
            _ => {}
        }
    }
    for c in ['X', 'U', 'M', 'N', 'D', 'C', 'K'] {
        assert_eq!(count.get(&c), Some(&200), "class {c}: {count:?}");
    }
    let checksum = |o: &Output| {
        assert!(o.status.success(), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        for c in ["U", "M", "N", "D", "C", "K"] {
            let prefix = format!("ccss class={c} points=200 ns_per_eval=");
            assert!(out.lines().any(|l| l.starts_with(&prefix)), "{out}");
        }
        out.lines()
            .find(|l| l.starts_with("ccss checksum="))
            .unwrap()
            .to_string()
    };
    let gen = ccss(&[&args[..], &["--samples", "1"]].concat(), "");
    let from = ccss(
        &["bench", "eval", m, "--points-file", p, "--samples", "1"],
        "",
    );
    assert_eq!(checksum(&gen), checksum(&from));
    // An unknown class letter is a usage error.
    let bad = ccss(&["bench", "eval", m, "--classes", "RQ"], "");
    assert_eq!(bad.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}
