//! Integration tests of `ccss interpolate`: the summary line, Q.obj and
//! G.obj read back, Q's Type I limit points (the standard limit mask,
//! computed here from Q's faces) equal to P's vertices, and the one-line
//! errors for bad input.

mod common;

use common::{ccss, data, num, out_dir, summary, text};
use std::path::Path;

fn read_obj(path: &Path) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let s = std::fs::read_to_string(path).unwrap();
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for l in s.lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.first() {
            Some(&"v") => v.push([t[1], t[2], t[3]].map(|x| x.parse::<f64>().unwrap())),
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

/// Standard limit mask of vertex `i` of an all-quad closed mesh.
fn limit(v: &[[f64; 3]], f: &[Vec<usize>], i: usize) -> [f64; 3] {
    let (mut n, mut e, mut d) = (0.0, [0.0; 3], [0.0; 3]);
    for face in f {
        if let Some(k) = face.iter().position(|&x| x == i) {
            n += 1.0;
            for c in 0..3 {
                e[c] += v[face[(k + 1) % 4]][c];
                d[c] += v[face[(k + 2) % 4]][c];
            }
        }
    }
    let mut out = [0.0; 3];
    for c in 0..3 {
        out[c] = (n * n * v[i][c] + 4.0 * e[c] + d[c]) / (n * (n + 5.0));
    }
    out
}

#[test]
fn interpolates_the_vertices_and_writes_g() {
    let dir = out_dir("interpolate-cli");
    let (q, g) = (dir.join("q.obj"), dir.join("g.obj"));
    let p = data("catmark_torus.obj");
    let o = ccss(&[
        "interpolate",
        p.to_str().unwrap(),
        "-o",
        q.to_str().unwrap(),
        "--subdivided",
        g.to_str().unwrap(),
    ]);
    let kv = summary(
        &o,
        &[
            "vertices",
            "faces",
            "iterations",
            "residual",
            "similarity",
            "naive",
            "seconds",
            "fold_rounds",
            "folds",
        ],
    );
    assert!(num(&kv, "residual") <= 1e-6);
    assert!(num(&kv, "similarity") < num(&kv, "naive"));
    assert_eq!(num(&kv, "folds"), 0.0);
    let (pv, _) = read_obj(&p);
    let (qv, qf) = read_obj(&q);
    let (gv, gf) = read_obj(&g);
    assert_eq!(qf, gf);
    assert_eq!(qv.len(), num(&kv, "vertices") as usize);
    assert_eq!(qf.len(), num(&kv, "faces") as usize);
    let (mut worst, mut g_off) = (0.0f64, 0.0f64);
    for (i, pi) in pv.iter().enumerate() {
        let (lq, lg) = (limit(&qv, &qf, i), limit(&gv, &gf, i));
        for c in 0..3 {
            worst = worst.max((lq[c] - pi[c]).abs());
            g_off = g_off.max((lg[c] - pi[c]).abs());
        }
    }
    assert!(worst <= 1e-12 && g_off > 1e-3, "{worst} {g_off}");
}

#[test]
fn bad_input_is_one_clear_line() {
    let dir = out_dir("interpolate-cli");
    let q = dir.join("bad.obj");
    let q = q.to_str().unwrap();
    let torus = data("catmark_torus.obj");
    let torus = torus.to_str().unwrap();
    let err = |args: &[&str], want: &str| {
        let o = ccss(args);
        assert!(!o.status.success());
        let e = text(&o.stderr);
        let last = e.lines().last().unwrap_or("");
        assert!(
            last.starts_with("ccss: error:") && last.contains(want),
            "{e}"
        );
    };
    let car = data("catmark_car.obj");
    err(
        &["interpolate", car.to_str().unwrap(), "-o", q],
        "boundary edge",
    );
    err(
        &["interpolate", torus, "-o", q, "--tolerance", "2"],
        "--tolerance",
    );
    err(
        &["interpolate", torus, "-o", q, "--max-iterations", "2"],
        "did not converge within 2 iterations",
    );
    let nan = dir.join("nan.obj");
    std::fs::write(
        &nan,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n",
    )
    .unwrap();
    err(&["interpolate", nan.to_str().unwrap(), "-o", q], "NaN");
    let normals = dir.join("n.tsv");
    std::fs::write(
        &normals,
        "# two normals at one point\n40 0.5 0.5 0 0 1\n40 0.5 0.5 1 0 0\n",
    )
    .unwrap();
    err(
        &[
            "interpolate",
            torus,
            "-o",
            q,
            "--normals",
            normals.to_str().unwrap(),
        ],
        "n.tsv:2: this normal conflicts",
    );
    std::fs::write(&normals, "40 0.5 x 0 0 1\n").unwrap();
    err(
        &[
            "interpolate",
            torus,
            "-o",
            q,
            "--normals",
            normals.to_str().unwrap(),
        ],
        "n.tsv:1: bad number",
    );
}

/// The assembled matrix (default), its symmetric Gauss-Seidel sweep and
/// the matrix-free products (`--matrix-free`, the former path) print the
/// same similarity residual and interpolate P's vertices.
#[test]
fn solver_paths_agree() {
    let dir = out_dir("interpolate-paths");
    let p = data("catmark_toroidal_tet.obj");
    let (pv, _) = read_obj(&p);
    let mut sims = Vec::new();
    for (i, extra) in [
        &[][..],
        &["--preconditioner", "symmetric-gauss-seidel"][..],
        &["--matrix-free"][..],
    ]
    .iter()
    .enumerate()
    {
        let q = dir.join(format!("q{i}.obj"));
        let mut args = vec![
            "interpolate",
            p.to_str().unwrap(),
            "-o",
            q.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let kv = summary(
            &ccss(&args),
            &[
                "vertices",
                "faces",
                "iterations",
                "residual",
                "similarity",
                "naive",
                "seconds",
                "fold_rounds",
                "folds",
            ],
        );
        assert!(num(&kv, "residual") <= 1e-6, "{extra:?}");
        sims.push(kv["similarity"].clone());
        let (qv, qf) = read_obj(&q);
        for (i, pi) in pv.iter().enumerate() {
            let l = limit(&qv, &qf, i);
            for c in 0..3 {
                assert!((l[c] - pi[c]).abs() <= 1e-12, "{extra:?}");
            }
        }
    }
    assert!(sims.iter().all(|s| *s == sims[0]), "{sims:?}");
}
