//! `ccss eval` on meshes with OpenSubdiv tags, boundaries and holes (the
//! feature path): tags honoured, options overridden, errors with line
//! numbers. The numerical oracle of the feature evaluator is
//! `tests/tests/feature_eval.rs`; here one exact case checks the plumbing
//! end to end: a cube whose twelve edges are infinitely sharp is the cube
//! itself, each face the bilinear interpolation of its corners.
mod common;
use common::*;

fn eval(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut a = vec!["eval"];
    a.extend_from_slice(args);
    let o = ccss_stdin(&a, stdin);
    (
        o.status.code().unwrap_or(-1),
        text(&o.stdout),
        text(&o.stderr),
    )
}

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n\
v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

fn write(name: &str, text: &str) -> String {
    let p = out_dir("features").join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn fully_creased_cube_is_the_cube() {
    let mut obj = CUBE.to_string();
    for (a, b) in [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        obj += &format!("t crease 2/1/0 {a} {b} 10\n");
    }
    let path = write("sharp_cube.obj", &obj);
    let corners = [
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    let mut q = String::new();
    let mut want = Vec::new();
    for i in 0..=4 {
        for j in 0..=4 {
            let (u, v) = (i as f64 / 4.0, j as f64 / 4.0);
            q += &format!("1 {u} {v}\n");
            let w = [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v];
            let p: Vec<f64> = (0..3)
                .map(|c| (0..4).map(|k| w[k] * corners[k][c]).sum())
                .collect();
            want.push(p);
        }
    }
    let (code, out, err) = eval(&[&path], &q);
    assert_eq!(code, 0, "{err}");
    for (line, w) in out.lines().zip(&want) {
        let p = numbers(line);
        for c in 0..3 {
            assert!((p[c] - w[c]).abs() < 1e-14, "{line} vs {w:?}");
        }
    }
    // The same file smooth (tags ignored by another verb, with a warning)
    // is not the cube.
    let (code, out, _) = eval(&[&write("smooth_cube.obj", CUBE)], "1 0.5 0.5\n");
    assert_eq!(code, 0);
    assert!((numbers(&out)[2] - 1.0).abs() > 0.1);
}

#[test]
fn open_meshes_holes_and_boundary_modes() {
    // A 2x1 strip of quads: open, every vertex on the boundary.
    let strip = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n";
    let path = write("strip.obj", strip);
    let (code, out, err) = eval(&[&path], "0 0.5 0.5\n1 1 1\n");
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 2);
    // Planar input, planar surface.
    for line in out.lines() {
        assert_eq!(numbers(line)[2], 0.0, "{line}");
    }
    // Boundary mode none: every face touches an un-sharpened boundary
    // vertex, so every face is a hole.
    let (code, _, err) = eval(&["--boundary", "none", &path], "0 0.5 0.5\n");
    assert_eq!(code, 2);
    assert!(err.contains("face 0 is a hole"), "{err}");
    // A tagged hole.
    let holed = format!("{strip}t hole 1/0/0 1\n");
    let (code, _, err) = eval(
        &[&write("strip_hole.obj", &holed)],
        "0 0.5 0.5\n1 0.5 0.5\n",
    );
    assert_eq!(code, 2);
    assert!(
        err.contains("stdin line 2") && err.contains("face 1 is a hole"),
        "{err}"
    );
}

#[test]
fn bad_tags_name_their_line() {
    let bad = format!("{CUBE}t crease 2/1/0 0 6 3\n");
    let (code, _, err) = eval(&[&write("bad_crease.obj", &bad)], "0 0.5 0.5\n");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("line 15") && err.contains("no edge joins"),
        "{err}"
    );
    let neg = format!("{CUBE}t corner 1/1/0 0 -1\n");
    let (code, _, err) = eval(&[&write("neg_corner.obj", &neg)], "0 0.5 0.5\n");
    assert_eq!(code, 2);
    assert!(err.contains("line 15") && err.contains("negative"), "{err}");
    let weights = write("w.tsv", "3 0.5 0.3 0.2\n");
    let tagged = format!("{CUBE}t crease 2/1/0 0 1 2\n");
    let (code, _, err) = eval(
        &["--weights", &weights, &write("tagged.obj", &tagged)],
        "0 0.5 0.5\n",
    );
    assert_eq!(code, 2);
    assert!(err.contains("--weights"), "{err}");
}

#[test]
fn bench_features_writes_and_times_points() {
    // Edge-only mode: its one-face corners are crease vertices of an
    // irregular sector, so some points need local refinement.
    let mesh = data("catmark_edgeonly.obj");
    let m = mesh.to_str().unwrap();
    let f = out_dir("features").join("edgeonly.pts");
    let o = ccss(&[
        "bench",
        "features",
        m,
        "--points",
        "50",
        "--write-points",
        f.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(
        out.contains("local_share=") && out.contains("(R=50, X=50)"),
        "{out}"
    );
    let o = ccss(&[
        "bench",
        "features",
        m,
        "--points-file",
        f.to_str().unwrap(),
        "--samples",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for key in [
        "ccss class=R points=50 ",
        "ccss class=X points=50 ",
        "ccss checksum=",
    ] {
        assert!(out.contains(key), "{key} missing in {out}");
    }
}

/// `key: value` lines of `ccss info`.
fn info(path: &str) -> (i32, std::collections::HashMap<String, String>, String) {
    let o = ccss(&["info", path]);
    let out = text(&o.stdout);
    let kv = out
        .lines()
        .filter_map(|l| l.split_once(": "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    (o.status.code().unwrap_or(-1), kv, text(&o.stderr))
}

#[test]
fn info_describes_meshes_with_features() {
    // Tag counts recounted from the file's own 't' lines; an open mesh
    // without tags (boundary edges) takes the same path.
    for (shape, open) in [
        ("catmark_cube_creases1.obj", false),
        ("catmark_car.obj", true),
        ("catmark_hole_test1.obj", false),
        ("catmark_edgeonly.obj", true),
    ] {
        let path = data(shape);
        let file = std::fs::read_to_string(&path).unwrap();
        let creases: usize = file
            .lines()
            .filter(|l| l.starts_with("t crease"))
            .map(|l| {
                let c: Vec<usize> = l
                    .split_whitespace()
                    .nth(2)
                    .unwrap()
                    .split('/')
                    .map(|x| x.parse().unwrap())
                    .collect();
                c[0] - 1 // consecutive pairs
            })
            .sum();
        let holes: usize = file
            .lines()
            .filter(|l| l.starts_with("t hole"))
            .map(|l| {
                l.split_whitespace()
                    .nth(2)
                    .unwrap()
                    .split('/')
                    .next()
                    .unwrap()
                    .parse::<usize>()
                    .unwrap()
            })
            .sum();
        let (code, kv, err) = info(path.to_str().unwrap());
        assert_eq!(code, 0, "{shape}: {err}");
        assert!(!err.contains("ignored"), "{shape}: {err}");
        assert!(kv["surface"].starts_with("OpenSubdiv's rules"), "{shape}");
        let count =
            |k: &str| -> usize { kv[k].split_whitespace().next().unwrap().parse().unwrap() };
        assert_eq!(count("crease edges"), creases, "{shape}");
        assert_eq!(count("hole faces"), holes, "{shape}");
        assert_eq!(kv["boundary edges"] != "0", open, "{shape}");
        // Every level-1 face is cached whole or split (or locally refined).
        assert!(count("level-1 faces") >= count("sub-faces"), "{shape}");
        // Every cached piece is a whole level-1 face or a quadrant of a
        // tree node, and the trees keep the default budget of 64 nodes per
        // split level-1 face.
        let (faces, split) = (count("level-1 faces"), count("split level-1 faces"));
        let nodes = count("cache tree nodes");
        assert!(nodes <= 64 * split, "{shape}: {nodes} nodes");
        assert!(
            count("cached B-spline pieces")
                + count("cached eigen patches")
                + count("cached crease strips")
                <= faces - split + 4 * nodes,
            "{shape}"
        );
        assert!(count("feature evaluator bytes") > 0, "{shape}");
    }
}

#[test]
fn cache_depth_option_changes_memory_not_values() {
    // catmark_dart_edgeonly: dart and irregular boundary corners, whose
    // trees grow with the depth. Depth 0 caches no tree (every point of a
    // split level-1 face refines locally): the oracle of the tree's values.
    let mesh = data("catmark_dart_edgeonly.obj");
    let m = mesh.to_str().unwrap();
    let info_at = |d: Option<&str>| {
        let mut a = vec!["info", m];
        if let Some(d) = d {
            a.extend_from_slice(&["--cache-depth", d]);
        }
        let o = ccss(&a);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        let get = |k: &str| -> String {
            out.lines()
                .find_map(|l| l.strip_prefix(k))
                .unwrap_or_else(|| panic!("{k} missing in {out}"))
                .to_string()
        };
        let bytes: usize = get("feature evaluator bytes: ").parse().unwrap();
        (bytes, get("cache tree nodes: "))
    };
    let (b0, n0) = info_at(Some("0"));
    let (b2, _) = info_at(Some("2"));
    let (b6, n6) = info_at(Some("6"));
    let (bd, nd) = info_at(None);
    assert!(n0.starts_with("0 ") && n0.ends_with("(depth 0)"), "{n0}");
    assert!(n6.ends_with("(depth 6)"), "{n6}");
    assert!(nd.ends_with("(depth 10)"), "default depth: {nd}");
    assert!(b0 < b2 && b2 < b6 && b6 < bd, "{b0} {b2} {b6} {bd}");
    // Points next to the special vertices (the X class of bench features).
    let f = out_dir("features").join("dart_cache.pts");
    let o = ccss(&[
        "bench",
        "features",
        m,
        "--points",
        "40",
        "--write-points",
        f.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let mut q = String::new();
    for l in std::fs::read_to_string(&f).unwrap().lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        if t.len() >= 5 && t[4] == "X" {
            q += &format!("{} {} {} {}\n", t[0], t[2], t[3], t[1]);
        }
    }
    assert!(q.lines().count() >= 20, "{q}");
    let (code, local, err) = eval(&[m, "--cache-depth", "0"], &q);
    assert_eq!(code, 0, "{err}");
    for d in ["3", "10", "16"] {
        let (code, tree, err) = eval(&[m, "--cache-depth", d], &q);
        assert_eq!(code, 0, "{err}");
        let mut worst = 0.0f64;
        for (a, b) in local.lines().zip(tree.lines()) {
            for (x, y) in numbers(a).iter().zip(numbers(b)) {
                worst = worst.max((x - y).abs() / (1.0 + x.abs()));
            }
        }
        assert_eq!(local.lines().count(), tree.lines().count());
        assert!(worst < 1e-12, "depth {d}: {worst:e}");
    }
    let o = ccss(&["info", m, "--cache-depth", "17"]);
    assert_ne!(o.status.code(), Some(0));
}
