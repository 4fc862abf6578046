//! Integration tests of `ccss raycast`, `ccss closest` and `ccss slice`:
//! the text contracts, checked through other verbs (`ccss eval` gives the
//! same limit points at the printed parameters), geometry (hits on their
//! rays, closest points no farther than densely sampled ones, slice
//! vertices on the surface and on their plane, orientation of outer
//! contours and holes), the SVG layers, `--help` and the errors.

mod common;

use common::{ccss, ccss_stdin, data, text};

fn nums(l: &str) -> Vec<f64> {
    l.split_whitespace().map(|w| w.parse().unwrap()).collect()
}

/// `ccss args...` with a large stdin written from a thread (the child's
/// output would otherwise fill its pipe while we still write).
fn ccss_big(args: &[&str], input: String) -> std::process::Output {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_ccss"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let w = std::thread::spawn(move || {
        let _ = stdin.write_all(input.as_bytes());
    });
    let o = child.wait_with_output().unwrap();
    w.join().unwrap();
    o
}

/// `ccss eval` at `(face, u, v, sub)`: the position.
fn eval_points(mesh: &str, q: &[(u32, u32, f64, f64)]) -> Vec<[f64; 3]> {
    let input: String = q
        .iter()
        .map(|(f, s, u, v)| format!("{f} {u:e} {v:e} {s}\n"))
        .collect();
    let o = ccss_big(&["eval", mesh], input);
    assert!(o.status.success(), "{}", text(&o.stderr));
    text(&o.stdout)
        .lines()
        .map(|l| {
            let v = nums(l);
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn raycast_hits_lie_on_rays_and_on_the_surface() {
    let m = data("catmark_torus.obj");
    let mesh = m.to_str().unwrap();
    let rays = "-3 0.01 0.02 1 0 0\n# comment\n0.9 2 0.1 0 -1 0\n5 5 5 1 0 0\n0 0 0 0.3 0.05 1\n";
    let o = ccss_stdin(&["raycast", "--all", "--tol", "1e-9", mesh], rays);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 4);
    let counts: Vec<usize> = lines
        .iter()
        .map(|l| l.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(counts, [4, 2, 0, 2]);
    let ray_list: Vec<Vec<f64>> = rays
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(nums)
        .collect();
    let mut q = vec![];
    let mut pts = vec![];
    for (l, r) in lines.iter().zip(&ray_list) {
        let v = nums(l);
        assert_eq!(v.len(), 1 + 11 * v[0] as usize);
        for h in v[1..].chunks_exact(11) {
            let (t, p) = (h[0], [h[5], h[6], h[7]]);
            let on = [r[0] + t * r[3], r[1] + t * r[4], r[2] + t * r[5]];
            assert!(dist(on, p) <= 1e-9, "{l}");
            let n = (h[8] * h[8] + h[9] * h[9] + h[10] * h[10]).sqrt();
            assert!((n - 1.0).abs() < 1e-12);
            q.push((h[1] as u32, h[2] as u32, h[3], h[4]));
            pts.push(p);
        }
    }
    for (a, b) in eval_points(mesh, &q).iter().zip(&pts) {
        assert!(dist(*a, *b) <= 1e-14, "{a:?} {b:?}");
    }
    // First hits: the first of --all, or 'miss'.
    let o = ccss_stdin(&["raycast", mesh], rays);
    let first = text(&o.stdout);
    let fl: Vec<&str> = first.lines().collect();
    assert_eq!(fl[2], "miss");
    // The same crossing as the first of --all (within the tolerance: the
    // two walks may certify it from neighbouring cells).
    let (a, b) = (nums(fl[0]), nums(lines[0]));
    assert!((a[0] - b[1]).abs() * 1.0 <= 1e-9, "{a:?} {b:?}");
    assert!(dist([a[5], a[6], a[7]], [b[6], b[7], b[8]]) <= 2e-9);
    // --timing: the same stdout, plus one timing line on stderr.
    let o = ccss_stdin(&["raycast", "--timing", mesh], rays);
    assert!(o.status.success());
    assert_eq!(text(&o.stdout), first);
    let err = text(&o.stderr);
    let line = err
        .lines()
        .find(|l| l.starts_with("ccss raycast: rays="))
        .unwrap_or_else(|| panic!("no timing line in {err:?}"));
    assert!(line.contains(&format!("rays={} ", fl.len())), "{line}");
}

#[test]
fn closest_is_no_farther_than_dense_samples() {
    let m = data("catmark_torus.obj");
    let mesh = m.to_str().unwrap();
    let points = [[0.9, 0.0, 0.05], [0.0, 0.3, 0.0], [2.0, -1.0, 0.5]];
    let input: String = points
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    let o = ccss_stdin(&["closest", "--tol", "1e-9", mesh], &input);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    // Dense samples through `ccss eval`: 32 faces x 33 x 33.
    let mut q = vec![];
    for f in 0..32u32 {
        for a in 0..=32 {
            for b in 0..=32 {
                q.push((f, 0, a as f64 / 32.0, b as f64 / 32.0));
            }
        }
    }
    let samples = eval_points(mesh, &q);
    for (l, p) in out.lines().zip(&points) {
        let v = nums(l);
        assert_eq!(v.len(), 8);
        let c = [v[5], v[6], v[7]];
        assert!((dist(c, *p) - v[0]).abs() <= 1e-14);
        let e = eval_points(mesh, &[(v[1] as u32, v[2] as u32, v[3], v[4])]);
        assert!(dist(e[0], c) <= 1e-14);
        let best = samples
            .iter()
            .map(|s| dist(*s, *p))
            .fold(f64::INFINITY, f64::min);
        assert!(v[0] <= best + 1e-9, "{l}: sampled {best}");
    }
}

#[test]
fn slice_text_and_svg() {
    let m = data("catmark_torus.obj");
    let mesh = m.to_str().unwrap();
    let dir = common::out_dir("query-cli");
    let txt = dir.join("torus.txt");
    let o = ccss(&[
        "slice",
        "--z0",
        "-0.6",
        "--dz",
        "0.3",
        "--eps",
        "0.005",
        mesh,
        "-o",
        txt.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let body = std::fs::read_to_string(&txt).unwrap();
    // Layers z = -0.6 .. 1.2 (the control box top is 1.25).
    let mut layers = vec![];
    let mut lines = body.lines().peekable();
    let mut probe = String::new();
    while let Some(l) = lines.next() {
        let w: Vec<&str> = l.split_whitespace().collect();
        assert_eq!(w[0], "layer", "{l}");
        let z: f64 = w[2].parse().unwrap();
        let mut contours = vec![];
        while lines.peek().is_some_and(|l| l.starts_with("contour")) {
            let c: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
            let n: usize = c[2].parse().unwrap();
            let pts: Vec<[f64; 2]> = (0..n)
                .map(|_| {
                    let v = nums(lines.next().unwrap());
                    [v[0], v[1]]
                })
                .collect();
            let area: f64 = (0..n)
                .map(|i| {
                    let (p, q) = (pts[i], pts[(i + 1) % n]);
                    p[0] * q[1] - p[1] * q[0]
                })
                .sum::<f64>()
                * 0.5;
            assert_eq!(c[1] == "outer", area > 0.0, "{c:?} area {area}");
            for p in pts.iter().step_by(97) {
                probe.push_str(&format!("{} {} {}\n", p[0], p[1], z));
            }
            contours.push(c[1] == "outer");
        }
        layers.push((z, contours));
    }
    assert_eq!(layers.len(), 7);
    // At z = 0 the ring is cut across: two outer contours, no hole.
    let mid = layers.iter().find(|(z, _)| z.abs() < 1e-12).unwrap();
    assert_eq!(mid.1, vec![true, true]);
    // Vertices are exact limit points: at distance ~0 from the surface.
    // (1e-10: the rounding term of the torus' coordinates, 4096 eps M,
    // refuses 1e-12.)
    let o = ccss_big(&["closest", "--tol", "1e-10", mesh], probe);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for l in text(&o.stdout).lines() {
        assert!(nums(l)[0] <= 1e-9, "{l}");
    }
    let svg = dir.join("torus.svg");
    let o = ccss(&[
        "slice",
        "--z0",
        "-0.6",
        "--dz",
        "0.3",
        "--layers",
        "3",
        "--eps",
        "0.01",
        mesh,
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
    assert_eq!(s.matches("<g id=\"layer-").count(), 3);
}

#[test]
fn query_verbs_help_and_errors() {
    let m = data("catmark_torus.obj");
    let mesh = m.to_str().unwrap();
    for v in ["raycast", "closest", "slice"] {
        let o = ccss(&[v, "--help"]);
        assert!(
            o.status.success() && text(&o.stdout).contains("Certified")
                || text(&o.stdout).contains("certified"),
            "{v}"
        );
    }
    let bad = [
        (
            vec!["raycast", mesh],
            "1 2 3 0 0 0\n",
            "stdin line 1: the ray direction is zero",
        ),
        (vec!["raycast", mesh], "1 2 3 nan 0 1\n", "stdin line 1:"),
        (
            vec!["closest", mesh],
            "1 2\n",
            "stdin line 1: expected 3 numbers",
        ),
        (
            vec!["closest", "--tol", "0", mesh],
            "1 2 3\n",
            "--tol must be positive",
        ),
        (
            vec![
                "slice",
                "--z0",
                "0",
                "--dz",
                "0.1",
                "--eps",
                "0",
                mesh,
                "-o",
                "/dev/null",
            ],
            "",
            "--eps must be positive",
        ),
    ];
    for (args, input, want) in bad {
        let o = ccss_stdin(&args, input);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(
            e.starts_with("ccss: error: ") && e.contains(want),
            "{args:?}: {e}"
        );
        assert_eq!(e.lines().count(), 1);
    }
    // An open mesh: a clear failure naming the boundary edge.
    let open = data("catmark_fan.obj");
    let o = ccss(&[
        "slice",
        "--z0",
        "0",
        "--dz",
        "0.1",
        "--eps",
        "0.01",
        open.to_str().unwrap(),
        "-o",
        "/dev/null",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("boundary edge"),
        "{}",
        text(&o.stderr)
    );

    // Work budgets (docs/WORST_CASE.md) and a tolerance the coordinates
    // cannot certify: one-line failures.
    for (args, input, want) in [
        (
            vec!["closest", "--max-cells", "3", mesh],
            "0.1 0.2 3\n",
            "work limit exceeded: more than 3 cells",
        ),
        // All hits: with the slot index the first hit of this ray is
        // certified on the first cell it visits.
        (
            vec!["raycast", "--all", "--max-cells", "2", mesh],
            "0.1 0.2 3 0 0 -1\n",
            "work limit exceeded: more than 2 cells",
        ),
        (
            vec![
                "slice",
                "--z0",
                "0.1",
                "--dz",
                "0.1",
                "--eps",
                "1e-3",
                "--max-cells",
                "4",
                mesh,
                "-o",
                "/dev/null",
            ],
            "",
            "work limit exceeded: more than 4 cells",
        ),
        (
            vec!["closest", "--tol", "1e-15", mesh],
            "0.1 0.2 3\n",
            "coordinates out of the certifiable range",
        ),
    ] {
        let o = ccss_stdin(&args, input);
        let e = text(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(
            e.starts_with("ccss: error: ") && e.contains(want),
            "{args:?}: {e}"
        );
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

/// Tagged and open meshes go through the feature evaluator: hits on their
/// rays and equal to `ccss eval` (which honours the same tags) at their
/// parameters; closest points on an open mesh likewise; slices of a creased
/// solid closed, of an open mesh refused.
#[test]
fn query_verbs_on_feature_meshes() {
    for (name, rays) in [
        (
            "catmark_cube_creases1.obj",
            "0.1 0.2 -5 0 0 1\n-4 0.3 0.1 1 0.05 0\n0.01 -3 0.9 0 1 0\n",
        ),
        (
            "catmark_edgecorner.obj",
            "-0.8 -3 0.7 0 1 0\n-0.6 2 0.8 0.01 -1 0.02\n",
        ),
    ] {
        let m = data(name);
        let mesh = m.to_str().unwrap();
        let o = ccss_stdin(&["raycast", "--all", "--tol", "1e-9", mesh], rays);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let out = text(&o.stdout);
        let (mut q, mut pts) = (vec![], vec![]);
        for (l, r) in out.lines().zip(rays.lines().map(nums)) {
            let v = nums(l);
            assert!(v[0] >= 1.0, "{name}: {l}");
            for h in v[1..].chunks_exact(11) {
                let (t, p) = (h[0], [h[5], h[6], h[7]]);
                let on = [r[0] + t * r[3], r[1] + t * r[4], r[2] + t * r[5]];
                assert!(dist(on, p) <= 1e-9, "{name}: {l}");
                q.push((h[1] as u32, h[2] as u32, h[3], h[4]));
                pts.push(p);
            }
        }
        let o = ccss_stdin(
            &["closest", "--tol", "1e-9", mesh],
            "0.2 0.1 3\n-2 0.5 0.3\n",
        );
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        for l in text(&o.stdout).lines() {
            let v = nums(l);
            q.push((v[1] as u32, v[2] as u32, v[3], v[4]));
            pts.push([v[5], v[6], v[7]]);
        }
        for (a, b) in eval_points(mesh, &q).iter().zip(&pts) {
            assert!(dist(*a, *b) <= 1e-12, "{name}: {a:?} {b:?}");
        }
    }
    let dir = std::env::temp_dir().join(format!("ccss_qf_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("cube.txt");
    let m = data("catmark_cube_creases1.obj");
    let o = ccss(&[
        "slice",
        "--z0",
        "-0.3",
        "--dz",
        "0.3",
        "--layers",
        "3",
        "--eps",
        "1e-4",
        m.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = std::fs::read_to_string(&out).unwrap();
    assert_eq!(s.lines().filter(|l| l.starts_with("layer")).count(), 3);
    assert_eq!(s.lines().filter(|l| *l == "contour outer 0").count(), 0);
    assert_eq!(
        s.lines().filter(|l| l.starts_with("contour outer")).count(),
        3,
        "{s}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let open = data("catmark_edgecorner.obj");
    let o = ccss(&[
        "slice",
        "--z0",
        "0",
        "--dz",
        "0.1",
        "--eps",
        "0.01",
        open.to_str().unwrap(),
        "-o",
        "/dev/null",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("not a closed solid"),
        "{}",
        text(&o.stderr)
    );
}

/// `ccss bench query` reads OpenSubdiv tags as the other verbs do: on the
/// creased cube the closest-point distances and the tessellation compared
/// against differ from those of the same OBJ without its tag lines (the
/// smooth surface), and the stack line reports its layers.
#[test]
fn bench_query_honours_tags() {
    let tagged = data("catmark_cube_creases1.obj");
    let src = std::fs::read_to_string(&tagged).unwrap();
    assert!(src.lines().any(|l| l.starts_with("t ")));
    let plain = common::out_dir("bench_query_tags").join("plain.obj");
    let stripped: String = src
        .lines()
        .filter(|l| !l.starts_with("t "))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&plain, stripped).unwrap();
    let run = |m: &std::path::Path| {
        let o = ccss(&[
            "bench",
            "query",
            m.to_str().unwrap(),
            "--rays",
            "4",
            "--points",
            "6",
            "--layers",
            "2",
            "--stack",
            "3",
            "--band",
            "2",
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        let field = |line: &str, key: &str| -> String {
            let l = out
                .lines()
                .find(|l| l.starts_with(line))
                .unwrap_or_else(|| panic!("{out}"));
            l.split(' ')
                .find_map(|t| t.strip_prefix(&format!("{key}=")).map(str::to_string))
                .unwrap_or_else(|| panic!("{key} in {l}"))
        };
        assert_eq!(field("ccss slice_stack", "layers"), "3");
        (
            field("ccss closest", "mean_dist"),
            field("ccss slice ", "tessellate_vertices"),
        )
    };
    let (dt, vt) = run(&tagged);
    let (dp, vp) = run(&plain);
    assert_ne!(dt, dp, "closest distances equal with and without creases");
    assert_ne!(vt, vp, "tessellations equal with and without creases");
}
