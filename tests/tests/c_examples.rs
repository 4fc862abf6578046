//! The C examples against the real static library.
//!
//! 1. Builds `libccss.a` with `cargo build -p ccss-ffi` into its own target
//!    directory (`<target>/c-tests`, so that it never waits for the lock of
//!    the `cargo test` that runs this file).
//! 2. Compiles every `c_examples/*.c` twice with the C compiler the `cc` crate
//!    detects (honours `CC`, `CFLAGS`, ...): strict C99
//!    (`-std=c99 -Wall -Wextra -Wpedantic -Werror`), and the same plus
//!    AddressSanitizer + UndefinedBehaviorSanitizer. Both link `-Iinclude`,
//!    `libccss.a` and the native libraries `rustc --print native-static-libs`
//!    reports.
//! 3. Runs each binary (`ASAN_OPTIONS=detect_leaks=1`, so LeakSanitizer is on;
//!    `UBSAN_OPTIONS=halt_on_error=1`) and requires exit status 0 and no
//!    sanitizer report.
//! 4. Checks what `eval.c` prints, every line against an independent
//!    expectation: positions against the reference subdivider's exact dyadic
//!    limit points (`ccss_tests::reference`), the corner against the
//!    valence-3 limit mask, the centre against its closed form, normals
//!    against the cube's symmetries; and that `errors.c` passes all its checks.
//! 5. Checks what `weights.c` prints (general vertex rule alpha = 0.5,
//!    beta = 0.3, gamma = 0.2 on every valence but 4): the three rejected
//!    rules, the tangent-plane continuity per valence and the valence-3 table
//!    facts against their closed forms, the cube corner against the weighted
//!    limit formula (eq. 2.7) and the face centre against the reference
//!    subdivider with the same rule (`dyadic_limit_point_weighted`).
//! 6. Checks what `depth.c` prints against the Rust core API on the same
//!    meshes (the cube and a pentagonal prism): every per-slot depth, for
//!    every method, equals `bounds::depth::depths` (slot labels from
//!    `slot_start` / `num_subfaces`), and the rates of valences 3, 5, 6, 7, 8
//!    equal `ValenceTable::rates()` to 1e-12; plus its two error lines.
//! 7. Runs `tessellate.c` (both variants) on a bundled model with an output
//!    path and checks the binary STL it writes: as many triangles as it
//!    printed (and as the Rust API makes for the same mesh and tolerance),
//!    every edge (vertices keyed by their f32 coordinates) used by exactly
//!    two triangles in opposite directions, no degenerate triangle.
//! 8. `refine.c`, `voxelize.c`: every printed figure against the Rust API.
//! 9. `creases.c` (the feature evaluator): the fully creased cube's largest
//!    deviation from its bilinear faces (at most 1e-14), the open grid's
//!    centre and boundary point bit-equal to the Rust `FeatureEvaluator`
//!    with z = 0, the hole and not-an-edge statuses with their details
//!    (status values read from `include/ccss.h`).
//! 10. `raycast.c`, `slice.c` (the certified queries): every hit, closest
//!     point and contour against the Rust API, plus the torus' facts (hit
//!     counts, inside/outside, one outer contour and one hole per layer).
//! 12. `boolean.c` (Booleans): union, intersection and difference of the
//!     built-in prism and its rotated copy within the bound, the short-buffer
//!     status, STL triangle counts and volumes consistent.
use ccss_core::bounds::depth::Method;
use ccss_core::mem::words_for;
use ccss_tests::harness::{standard_tables, with_evaluator};
use ccss_tests::reference::{
    dyadic_limit_point, dyadic_limit_point_weighted, standard_weights, PolyMesh,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

const TOL: f64 = 1e-12;

fn root() -> PathBuf {
    ccss_tests::harness::workspace_root()
}

/// Where the library and the C binaries are built.
fn work_dir() -> PathBuf {
    ccss_tests::harness::target_subdir("c-tests")
}

fn show(what: &str, out: &Output) -> String {
    format!(
        "{what}: {}\n--- stdout ---\n{}\n--- stderr ---\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// `rustc` next to the `cargo` that runs us (else `$RUSTC`, else PATH).
fn rustc() -> PathBuf {
    if let Some(r) = std::env::var_os("RUSTC") {
        return r.into();
    }
    let cargo = Path::new(env!("CARGO"));
    let sibling = cargo.with_file_name(format!("rustc{}", std::env::consts::EXE_SUFFIX));
    if sibling.exists() {
        sibling
    } else {
        "rustc".into()
    }
}

struct Setup {
    lib: PathBuf,
    native_libs: Vec<String>,
    compiler: cc::Tool,
    bin_dir: PathBuf,
}

fn setup() -> &'static Setup {
    static S: OnceLock<Setup> = OnceLock::new();
    S.get_or_init(|| {
        let dir = work_dir();
        let bin_dir = dir.join("bin");
        std::fs::create_dir_all(&bin_dir).unwrap();

        // 1. The static library (dev profile).
        let out = Command::new(env!("CARGO"))
            .current_dir(root())
            .env("CARGO_TARGET_DIR", &dir)
            .args(["build", "--quiet", "-p", "ccss-ffi", "--lib"])
            .output()
            .expect("run cargo");
        assert!(
            out.status.success(),
            "{}",
            show("cargo build -p ccss-ffi", &out)
        );
        let lib = dir.join("debug").join("libccss.a");
        assert!(lib.exists(), "{} missing", lib.display());

        // 2. Host triple and the native libraries a Rust staticlib needs. Our
        // dependencies (ccss-core, glam, libm, heapless) are pure Rust, so
        // those of an empty staticlib (i.e. of std) are the complete list.
        let vv = Command::new(rustc())
            .arg("-vV")
            .output()
            .expect("rustc -vV");
        let host = String::from_utf8_lossy(&vv.stdout)
            .lines()
            .find_map(|l| l.strip_prefix("host: ").map(str::to_owned))
            .expect("host triple in rustc -vV");
        let probe = dir.join("native-libs");
        std::fs::create_dir_all(&probe).unwrap();
        std::fs::write(probe.join("empty.rs"), "").unwrap();
        let out = Command::new(rustc())
            .current_dir(&probe)
            .args([
                "--crate-type",
                "staticlib",
                "--crate-name",
                "empty",
                "--print",
            ])
            .arg("native-static-libs")
            .arg("-o")
            .arg(probe.join("libempty.a"))
            .arg(probe.join("empty.rs"))
            .output()
            .expect("rustc --print native-static-libs");
        assert!(
            out.status.success(),
            "{}",
            show("rustc --print native-static-libs", &out)
        );
        let native_libs: Vec<String> = String::from_utf8_lossy(&out.stderr)
            .lines()
            .find_map(|l| l.split("native-static-libs:").nth(1).map(str::to_owned))
            .expect("native-static-libs note")
            .split_whitespace()
            .map(str::to_owned)
            .collect();

        // 3. The C compiler, as the cc crate finds it outside a build script.
        let compiler = cc::Build::new()
            .target(&host)
            .host(&host)
            .opt_level(0)
            .debug(false)
            .cargo_metadata(false)
            .cargo_warnings(false)
            .try_get_compiler()
            .expect("cc: no C compiler");
        // Never `-w` (cc's `warnings(false)`): it would silence -Werror.
        assert!(
            !compiler.args().iter().any(|a| a == "-w"),
            "{:?}",
            compiler.args()
        );
        eprintln!(
            "c_examples: C compiler {} {:?}; native libs {native_libs:?}",
            compiler.path().display(),
            compiler.args()
        );
        Setup {
            lib,
            native_libs,
            compiler,
            bin_dir,
        }
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Variant {
    Strict,
    Sanitized,
}

struct Run {
    out: Output,
}

/// Compiles one example in one variant and runs it.
fn build_and_run(src: &Path, variant: Variant) -> Run {
    let s = setup();
    let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
    let exe = s.bin_dir.join(format!("{stem}-{variant:?}").to_lowercase());
    let mut cmd = s.compiler.to_command();
    cmd.args(["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror"]);
    if variant == Variant::Sanitized {
        cmd.args([
            "-fsanitize=address,undefined",
            "-fno-omit-frame-pointer",
            "-g",
        ]);
    }
    cmd.arg("-I").arg(root().join("include"));
    cmd.arg(src)
        .arg(&s.lib)
        .args(&s.native_libs)
        .arg("-o")
        .arg(&exe);
    let out = cmd.output().expect("run the C compiler");
    assert!(
        out.status.success(),
        "{}",
        show(&format!("compile {stem} ({variant:?}): {cmd:?}"), &out)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        show(
            &format!("compiler diagnostics for {stem} ({variant:?})"),
            &out
        )
    );

    let out = Command::new(&exe)
        .env(
            "ASAN_OPTIONS",
            "detect_leaks=1:abort_on_error=0:exitcode=86",
        )
        .env("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
        .output()
        .expect("run the example");
    let stderr = String::from_utf8_lossy(&out.stderr);
    for marker in ["Sanitizer", "runtime error:", "ERROR:", "panicked"] {
        assert!(
            !stderr.contains(marker),
            "{}",
            show(&format!("{stem} ({variant:?}): {marker}"), &out)
        );
    }
    assert!(
        out.status.success(),
        "{}",
        show(&format!("{stem} ({variant:?}) failed"), &out)
    );
    Run { out }
}

/// Every example in both variants, built and run once per test process.
fn runs() -> &'static BTreeMap<(String, Variant), Run> {
    static R: OnceLock<BTreeMap<(String, Variant), Run>> = OnceLock::new();
    R.get_or_init(|| {
        setup();
        let mut srcs: Vec<PathBuf> = std::fs::read_dir(root().join("c_examples"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "c"))
            .collect();
        srcs.sort();
        assert!(!srcs.is_empty(), "no c_examples/*.c");
        std::thread::scope(|sc| {
            let jobs: Vec<_> = srcs
                .iter()
                .flat_map(|p| [Variant::Strict, Variant::Sanitized].map(|v| (p.clone(), v)))
                .map(|(p, v)| {
                    let key = (p.file_stem().unwrap().to_string_lossy().into_owned(), v);
                    (key, sc.spawn(move || build_and_run(&p, v)))
                })
                .collect();
            jobs.into_iter()
                .map(|(k, h)| match h.join() {
                    Ok(r) => (k, r),
                    Err(e) => std::panic::resume_unwind(e),
                })
                .collect()
        })
    })
}

fn stdout_of(name: &str, v: Variant) -> String {
    let r = runs()
        .get(&(name.to_owned(), v))
        .unwrap_or_else(|| panic!("no c_examples/{name}.c"));
    String::from_utf8(r.out.stdout.clone()).unwrap()
}

#[test]
fn every_example_compiles_strictly_and_runs_clean_under_sanitizers() {
    let r = runs();
    for ((name, v), run) in r {
        assert!(run.out.status.success(), "{name} {v:?}");
        // Same output with and without sanitizers.
        if *v == Variant::Sanitized {
            let plain = &r[&(name.clone(), Variant::Strict)].out.stdout;
            assert_eq!(
                &run.out.stdout, plain,
                "{name}: output differs under sanitizers"
            );
        }
    }
}

#[test]
fn errors_example_passes_every_check() {
    for v in [Variant::Strict, Variant::Sanitized] {
        let out = stdout_of("errors", v);
        let pass = out.lines().filter(|l| l.starts_with("PASS ")).count();
        let fail: Vec<&str> = out.lines().filter(|l| l.starts_with("FAIL")).collect();
        assert!(fail.is_empty(), "{v:?}: {fail:?}\n{out}");
        assert!(pass >= 50, "{v:?}: only {pass} PASS lines\n{out}");
        assert!(out.contains("ALL PASS: 0 failure(s)"), "{out}");
    }
}

/// The cube of the examples: v0..v3 at z = -1, v4..v7 at z = +1.
fn cube() -> PolyMesh {
    let s = [-1.0, 1.0];
    let mut positions = Vec::new();
    for z in [-1.0, 1.0] {
        for (x, y) in [(s[0], s[0]), (s[1], s[0]), (s[1], s[1]), (s[0], s[1])] {
            positions.push([x, y, z]);
        }
    }
    let faces = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    PolyMesh {
        positions,
        faces: faces.iter().map(|f| f.to_vec()).collect(),
    }
}

type Row = [f64; 8]; // u v px py pz nx ny nz

fn parse_grid(out: &str) -> BTreeMap<(u32, u32), Row> {
    let mut grid = BTreeMap::new();
    for line in out.lines().filter(|l| !l.starts_with('#')) {
        let vals: Vec<f64> = line
            .split_whitespace()
            .map(|t| {
                t.parse()
                    .unwrap_or_else(|_| panic!("bad number {t:?} in {line:?}"))
            })
            .collect();
        let row: Row = vals
            .try_into()
            .unwrap_or_else(|_| panic!("not 8 numbers: {line:?}"));
        let (i, j) = (row[0] * 4.0, row[1] * 4.0);
        assert!(
            i.fract() == 0.0 && j.fract() == 0.0,
            "not a quarter grid point: {line:?}"
        );
        assert!(
            grid.insert((i as u32, j as u32), row).is_none(),
            "duplicate {line:?}"
        );
    }
    grid
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= TOL)
}

#[test]
fn eval_example_prints_the_exact_limit_surface() {
    let cube = cube();
    let out_strict = stdout_of("eval", Variant::Strict);
    // The compact evaluator (ccss_evaluator_options_compact) gave the same
    // grid bit for bit in less memory.
    let compact = out_strict
        .lines()
        .find_map(|l| l.strip_prefix("# compact: "))
        .unwrap_or_else(|| panic!("no compact line: {out_strict}"));
    let w: Vec<&str> = compact.split_whitespace().collect();
    assert_eq!(&w[..2], ["25", "of"], "{compact}");
    let (small, full): (usize, usize) = (w[7].parse().unwrap(), w[9].parse().unwrap());
    assert!(small < full, "{compact}");
    // ccss_evaluator_eval_derivs: the same position and derivatives bit
    // for bit at every grid point, a zero normal.
    assert!(
        out_strict.contains("# derivs: 25 of 25 points bit for bit"),
        "{out_strict}"
    );
    let g = parse_grid(&out_strict);
    assert_eq!(g.len(), 25, "{out_strict}");
    let p = |i: u32, j: u32| -> [f64; 3] {
        let r = g[&(i, j)];
        [r[2], r[3], r[4]]
    };
    let n = |i: u32, j: u32| -> [f64; 3] {
        let r = g[&(i, j)];
        [r[5], r[6], r[7]]
    };

    // Every position: the reference subdivider's exact limit point at the
    // dyadic parameter (i/4, j/4) (two subdivision steps + limit mask).
    for &(i, j) in g.keys() {
        let want = dyadic_limit_point(&cube, 0, 0, i, j, 2);
        assert!(
            close(p(i, j), want),
            "({i},{j})/4: printed {:?}, oracle {want:?}",
            p(i, j)
        );
    }

    // The corners: the valence-3 limit mask (n^2 V + 4 sum E + sum F)/(n(n+5))
    // applied to the cube (E = the 3 edge neighbours, F = the 3 face-diagonal
    // vertices), which is V/2; and their normals point away from the centre.
    let v = &cube.positions;
    let mask = |c: usize, e: [usize; 3], f: [usize; 3]| -> [f64; 3] {
        let nn = 3.0;
        std::array::from_fn(|k| {
            (nn * nn * v[c][k]
                + 4.0 * e.iter().map(|&x| v[x][k]).sum::<f64>()
                + f.iter().map(|&x| v[x][k]).sum::<f64>())
                / (nn * (nn + 5.0))
        })
    };
    let corner0 = mask(0, [1, 3, 4], [2, 5, 7]);
    assert_eq!(corner0, [-0.5, -0.5, -0.5]);
    // Face 0 = (v0 v3 v2 v1): (0,0)=v0, (1,0)=v3, (1,1)=v2, (0,1)=v1.
    for ((i, j), c) in [((0, 0), 0usize), ((4, 0), 3), ((4, 4), 2), ((0, 4), 1)] {
        let want = v[c].map(|x| x / 2.0);
        assert!(
            close(p(i, j), want),
            "corner v{c}: {:?} vs {want:?}",
            p(i, j)
        );
        let s = 1.0 / 3f64.sqrt();
        assert!(
            close(n(i, j), v[c].map(|x| x * s)),
            "corner normal v{c}: {:?}",
            n(i, j)
        );
    }
    assert!(close(p(0, 0), corner0));

    // The centre: the face point after one step is a regular vertex (valence
    // 4) whose limit z is (16(-1) + 4(4(-3/4)) + 4(-5/9))/36 = -68/81 (the
    // vertex points of the corners are at z = -5/9); normal (0, 0, -1).
    assert!(
        close(p(2, 2), [0.0, 0.0, -68.0 / 81.0]),
        "centre {:?}",
        p(2, 2)
    );
    assert!(
        close(n(2, 2), [0.0, 0.0, -1.0]),
        "centre normal {:?}",
        n(2, 2)
    );

    // Symmetries of the cube that map face 0 to itself, on every line:
    // x -> -x is v -> 1-v, y -> -y is u -> 1-u, x <-> y is u <-> v.
    for &(i, j) in g.keys() {
        let (a, b) = (p(i, j), n(i, j));
        let (q, m) = (p(i, 4 - j), n(i, 4 - j));
        assert!(close(a, [-q[0], q[1], q[2]]), "x mirror at ({i},{j})");
        assert!(close(b, [-m[0], m[1], m[2]]), "nx mirror at ({i},{j})");
        let (q, m) = (p(4 - i, j), n(4 - i, j));
        assert!(close(a, [q[0], -q[1], q[2]]), "y mirror at ({i},{j})");
        assert!(close(b, [m[0], -m[1], m[2]]), "ny mirror at ({i},{j})");
        let (q, m) = (p(j, i), n(j, i));
        assert!(close(a, [q[1], q[0], q[2]]), "diagonal mirror at ({i},{j})");
        assert!(
            close(b, [m[1], m[0], m[2]]),
            "diagonal normal mirror at ({i},{j})"
        );
        // Unit, outward (the face is the bottom, z = -1).
        let len = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
        assert!(
            (len - 1.0).abs() <= TOL && b[2] < 0.0,
            "normal at ({i},{j}): {b:?}"
        );
        // On the boundary of face 0 the surface point and normal lie in the
        // plane of the symmetry that swaps face 0 with its neighbour:
        // u=0 (edge v0-v1): y=z; u=1 (v3-v2): y=-z; v=0 (v0-v3): x=z; v=1: x=-z.
        let on = |k: usize, sign: f64| {
            (a[k] - sign * a[2]).abs() <= TOL && (b[k] - sign * b[2]).abs() <= TOL
        };
        if i == 0 {
            assert!(on(1, 1.0), "edge u=0 at ({i},{j})");
        }
        if i == 4 {
            assert!(on(1, -1.0), "edge u=1 at ({i},{j})");
        }
        if j == 0 {
            assert!(on(0, 1.0), "edge v=0 at ({i},{j})");
        }
        if j == 4 {
            assert!(on(0, -1.0), "edge v=1 at ({i},{j})");
        }
    }

    // The error demonstration.
    let errs: Vec<&str> = out_strict
        .lines()
        .filter(|l| l.starts_with("# error:"))
        .collect();
    assert_eq!(errs.len(), 2, "{out_strict}");
    assert!(
        errs[0].contains("-> 17 face index out of range"),
        "{}",
        errs[0]
    );
    assert!(
        errs[1].contains("query 1 face 99") && errs[1].contains("face 99 does not exist"),
        "{}",
        errs[1]
    );
}

/// The `key ...` line of `out` starting with `key ` (exactly one).
fn line_of<'a>(out: &'a str, key: &str) -> &'a str {
    let prefix = format!("{key} ");
    let ls: Vec<&str> = out.lines().filter(|l| l.starts_with(&prefix)).collect();
    assert_eq!(ls.len(), 1, "{key:?} lines in\n{out}");
    &ls[0][prefix.len()..]
}

/// The value of `name=` in a line of `name=value` tokens.
fn field(line: &str, name: &str) -> f64 {
    let prefix = format!("{name}=");
    let tok = line
        .split_whitespace()
        .find_map(|t| t.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("no {name}= in {line:?}"));
    tok.parse()
        .unwrap_or_else(|_| panic!("bad {name}={tok} in {line:?}"))
}

fn three(line: &str) -> [f64; 3] {
    let v: Vec<f64> = line
        .split_whitespace()
        .map(|t| {
            t.parse()
                .unwrap_or_else(|_| panic!("bad number in {line:?}"))
        })
        .collect();
    v.try_into()
        .unwrap_or_else(|_| panic!("not 3 numbers: {line:?}"))
}

#[test]
fn weights_example_matches_the_weighted_limit() {
    let (a, b, g): (f64, f64, f64) = (0.5, 0.3, 0.2);
    let out = stdout_of("weights", Variant::Strict);

    // 1. The three rejected rules: status 22, entry 1, with the reason.
    for (what, valence, reason) in [
        ("valence4", 4, "valence 4 must keep the standard rule"),
        ("negative", 5, "a weight is negative"),
        ("sum", 5, "alpha + beta + gamma is not 1"),
    ] {
        let l = line_of(&out, &format!("rejected {what}"));
        assert!(
            l.starts_with(&format!("status=22 entry=1 valence={valence} ")),
            "{l}"
        );
        assert!(
            l.contains(&format!(
                "message=entry 1: weights for valence {valence} rejected: {reason}"
            )),
            "{l}"
        );
    }

    // 2. One weights line per valence 3, 5, 6, ..., MAX_VALENCE, with the
    // tangent-plane continuity from the closed form: the frequency-0
    // eigenvalues are the roots of x^2 - (a - 1/4) x + (1 - 2b)/16 and must
    // be dominated by lambda_2 = (c + 5 + sqrt((c+1)(c+9)))/16, c = cos(2pi/n).
    let weights: Vec<&str> = out.lines().filter(|l| l.starts_with("weights ")).collect();
    let want_n: Vec<usize> = (3..=ccss_core::MAX_VALENCE).filter(|&n| n != 4).collect();
    assert_eq!(weights.len(), want_n.len(), "{out}");
    let lambda2 = |n: usize| {
        let c = (2.0 * std::f64::consts::PI / n as f64).cos();
        (c + 5.0 + ((c + 1.0) * (c + 9.0)).sqrt()) / 16.0
    };
    let (t, d) = (a - 0.25, (1.0 - 2.0 * b) / 16.0);
    let disc = t * t - 4.0 * d;
    let lambda0 = if disc >= 0.0 {
        ((t.abs() + disc.sqrt()) / 2.0).abs()
    } else {
        d.sqrt() // modulus of the complex pair
    };
    assert!(disc < 0.0, "this rule has a complex frequency-0 pair");
    for (l, &n) in weights.iter().zip(&want_n) {
        assert_eq!(field(l, "n"), n as f64, "{l}");
        assert_eq!(
            (field(l, "alpha"), field(l, "beta"), field(l, "gamma")),
            (a, b, g),
            "{l}"
        );
        let tpc = (lambda0 < lambda2(n)) as i32 as f64;
        assert_eq!(field(l, "tangent_plane_continuous"), tpc, "{l}");
    }

    // 3. The valence-3 table: rule, 2n+8 points, complex pair, subdominant
    // lambda_2(3) (the pair's modulus sqrt(1/40) is smaller), and the limit
    // weights of eq. 2.7: 5/den, (12b+8g)/(3 den), (2b+8g)/(3 den).
    let info = line_of(&out, "info");
    let den = 5.0 + 14.0 * b + 16.0 * g;
    assert_eq!(field(info, "n"), 3.0);
    assert_eq!(field(info, "points"), 14.0);
    assert_eq!(
        (
            field(info, "alpha"),
            field(info, "beta"),
            field(info, "gamma")
        ),
        (a, b, g)
    );
    assert_eq!(field(info, "complex_pair"), 1.0, "{info}");
    assert_eq!(field(info, "tangent_plane_continuous"), 1.0, "{info}");
    let near = |x: f64, y: f64| (x - y).abs() <= 1e-13;
    assert!(near(field(info, "subdominant"), lambda2(3)), "{info}");
    assert!(near(field(info, "limit_v"), 5.0 / den), "{info}");
    assert!(
        near(field(info, "limit_e"), (12.0 * b + 8.0 * g) / (3.0 * den)),
        "{info}"
    );
    assert!(
        near(field(info, "limit_f"), (2.0 * b + 8.0 * g) / (3.0 * den)),
        "{info}"
    );

    // 4. The cube corner (face 0, u = v = 0: vertex 0) by the weighted limit
    // formula over its edge neighbours 1 3 4 and diagonal vertices 2 5 7.
    let cube = cube();
    let v = &cube.positions;
    let want_corner: [f64; 3] = std::array::from_fn(|k| {
        let ebar = (v[1][k] + v[3][k] + v[4][k]) / 3.0;
        let fbar = (v[2][k] + v[5][k] + v[7][k]) / 3.0;
        (5.0 * v[0][k] + (12.0 * b + 8.0 * g) * ebar + (2.0 * b + 8.0 * g) * fbar) / den
    });
    // = -(5 + (10b)/3) / den per coordinate: differs from the standard -1/2.
    assert!((want_corner[0] + 0.5).abs() > 1e-2);
    let corner = three(line_of(&out, "corner"));
    assert!(close(corner, want_corner), "{corner:?} vs {want_corner:?}");
    let formula = three(line_of(&out, "corner_formula"));
    assert!(
        close(formula, want_corner),
        "{formula:?} vs {want_corner:?}"
    );

    // 5. The face centre: the reference subdivider with the same rule
    // (valence 3 weighted, every other valence standard), one step, then the
    // (regular) limit mask at the face point.
    let rule = move |n: usize| {
        if n == 3 {
            (a, b, g)
        } else {
            standard_weights(n)
        }
    };
    let want_centre = dyadic_limit_point_weighted(&cube, 0, 0, 1, 1, 1, &rule);
    let centre = three(line_of(&out, "centre"));
    assert!(close(centre, want_centre), "{centre:?} vs {want_centre:?}");
    // The rule matters: the standard centre is at z = -68/81.
    assert!((centre[2] + 68.0 / 81.0).abs() > 1e-3, "{centre:?}");
}

/// The pentagonal prism of `depth.c` (same literals): b0..b4 at z = -0.8,
/// t0..t4 at z = +0.8; faces: bottom, top, five sides.
fn prism() -> PolyMesh {
    let ring = [
        (1.0, 0.0),
        (0.3, 0.95),
        (-0.8, 0.6),
        (-0.8, -0.6),
        (0.3, -0.95),
    ];
    let mut positions = Vec::new();
    for z in [-0.8, 0.8] {
        positions.extend(ring.iter().map(|&(x, y)| [x, y, z]));
    }
    let mut faces = vec![vec![4, 3, 2, 1, 0], vec![5, 6, 7, 8, 9]];
    for k in 0..5u32 {
        let k1 = (k + 1) % 5;
        faces.push(vec![k, k1, 5 + k1, 5 + k]);
    }
    PolyMesh { positions, faces }
}

/// The `face depth` / `face.sub depth` lines the Rust API gives for `m`.
fn rust_depth_lines(m: &PolyMesh, eps: f64, method: Method) -> Vec<String> {
    with_evaluator(m, standard_tables(), |_, ev| {
        let mut d = vec![u32::MAX; ev.num_slots()];
        ccss_core::bounds::depth::depths(ev, eps, method, &mut d).expect("depths");
        let mut lines = Vec::new();
        for f in 0..ev.num_faces() {
            let (s0, k) = (ev.slot_start(f), ev.num_subfaces(f));
            if k == 1 {
                lines.push(format!("{f} {}", d[s0]));
            } else {
                lines.extend((0..k).map(|j| format!("{f}.{j} {}", d[s0 + j])));
            }
        }
        assert_eq!(lines.len(), d.len());
        lines
    })
    .expect("evaluator")
}

#[test]
fn depth_example_matches_the_rust_api() {
    let out = stdout_of("depth", Variant::Strict);
    // Split into sections by their '# rates' / '# depths ...' headers.
    let mut sections: Vec<(String, Vec<&str>)> = Vec::new();
    for l in out.lines() {
        if let Some(h) = l.strip_prefix("# ") {
            if h.starts_with("rates") || h.starts_with("depths ") {
                sections.push((h.to_string(), Vec::new()));
            }
        } else {
            let (_, body) = sections
                .last_mut()
                .unwrap_or_else(|| panic!("line before any section: {l:?}\n{out}"));
            body.push(l);
        }
    }

    // 1. Rates: valences 3, 5, 6, 7, 8, to 1e-12 against the tables.
    let rates: Vec<&Vec<&str>> = sections
        .iter()
        .filter(|(h, _)| h == "rates n r1 r2")
        .map(|(_, b)| b)
        .collect();
    assert_eq!(rates.len(), 1, "{out}");
    let mut ns = Vec::new();
    for l in rates[0] {
        let t: Vec<f64> = l
            .split_whitespace()
            .map(|x| x.parse().unwrap_or_else(|_| panic!("bad number in {l:?}")))
            .collect();
        assert_eq!(t.len(), 3, "{l}");
        let n = t[0] as usize;
        let want = standard_tables().get(n).unwrap().rates();
        assert!(
            (t[1] - want.r1).abs() <= TOL,
            "n={n}: r1 {} vs {}",
            t[1],
            want.r1
        );
        assert!(
            (t[2] - want.r2).abs() <= TOL,
            "n={n}: r2 {} vs {}",
            t[2],
            want.r2
        );
        ns.push(n);
    }
    assert_eq!(ns, [3, 5, 6, 7, 8]);

    // 2. Depths: both meshes x four methods, every line equal to Rust's.
    let meshes = [("cube", cube()), ("prism", prism())];
    let methods = [
        ("old", Method::Old),
        ("new", Method::New),
        ("best", Method::Best),
        ("tight", Method::Tight),
    ];
    let depth_sections = sections
        .iter()
        .filter(|(h, _)| h.starts_with("depths "))
        .count();
    assert_eq!(depth_sections, meshes.len() * methods.len(), "{out}");
    for (name, m) in &meshes {
        for (mname, method) in methods {
            let want = rust_depth_lines(m, 0.01, method);
            let head = format!(
                "depths mesh={name} method={mname} eps=0.01 slots={}",
                want.len()
            );
            let got: Vec<&Vec<&str>> = sections
                .iter()
                .filter(|(h, _)| *h == head)
                .map(|(_, b)| b)
                .collect();
            assert_eq!(got.len(), 1, "no section {head:?} in\n{out}");
            assert_eq!(*got[0], want, "{head}");
        }
    }
    // The prism has pentagon sub-faces (face.sub lines) and quads.
    let prism_best = rust_depth_lines(&meshes[1].1, 0.01, Method::Best);
    assert!(prism_best.iter().any(|l| l.starts_with("0.4 ")));
    assert!(prism_best.iter().any(|l| l.starts_with("6 ")));

    // 3. The two errors.
    let errs: Vec<&str> = out.lines().filter(|l| l.starts_with("# error:")).collect();
    assert_eq!(errs.len(), 2, "{out}");
    assert!(
        errs[0].contains("(eps = 0) -> 4 invalid argument")
            && errs[0].contains("eps must be positive and finite"),
        "{}",
        errs[0]
    );
    assert!(
        errs[1].contains("(out_len = 14) -> 2 ") && errs[1].contains("required 15:"),
        "{}",
        errs[1]
    );
}

/// 7. `tessellate.c` writes a watertight STL of the pyramid.
#[test]
fn tessellate_example_writes_a_watertight_stl() {
    use ccss_core::tessellate::{Options, Scratch, Tessellation};
    use std::collections::HashMap;
    let _ = runs();
    let s = setup();
    let model = root().join("tests/data/osd/catmark_pyramid.obj");
    let tol = 0.01;
    let want = with_evaluator(
        &PolyMesh::from_obj(&model),
        standard_tables(),
        |topo, ev| {
            let opts = Options::absolute(tol);
            let n = Tessellation::required_bytes(topo, ev, &opts, &mut Box::new(Scratch::ZERO))
                .unwrap();
            let mut mem = vec![0u64; words_for(n)];
            Tessellation::build(topo, ev, opts, &mut mem)
                .unwrap()
                .counts()
        },
    )
    .unwrap();
    for v in [Variant::Strict, Variant::Sanitized] {
        let exe = s.bin_dir.join(format!("tessellate-{v:?}").to_lowercase());
        let stl = s
            .bin_dir
            .join(format!("tessellate-{v:?}.stl").to_lowercase());
        let out = Command::new(&exe)
            .arg(&stl)
            .arg(&model)
            .arg(tol.to_string())
            .env(
                "ASAN_OPTIONS",
                "detect_leaks=1:abort_on_error=0:exitcode=86",
            )
            .env("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
            .output()
            .expect("run tessellate");
        assert!(out.status.success(), "{}", show("tessellate", &out));
        let text = String::from_utf8(out.stdout).unwrap();
        let line = text
            .lines()
            .find(|l| l.starts_with("vertices="))
            .expect(&text);
        let kv: HashMap<&str, &str> = line.split(' ').filter_map(|t| t.split_once('=')).collect();
        let num = |k: &str| kv[k].parse::<f64>().unwrap();
        assert_eq!(num("vertices") as usize, want.vertices, "{line}");
        assert_eq!(num("polygons") as usize, want.polygons, "{line}");
        assert_eq!(num("triangles") as usize, want.triangles, "{line}");
        assert!(
            num("bound") <= tol && num("uniform_depth") >= num("max_level"),
            "{line}"
        );
        assert!(text.contains(&format!(
            "stl={} triangles={}",
            stl.display(),
            want.triangles
        )));
        let b = std::fs::read(&stl).unwrap();
        let nt = u32::from_le_bytes(b[80..84].try_into().unwrap()) as usize;
        assert!(nt > 0 && nt == want.triangles, "{nt}");
        assert_eq!(b.len(), 84 + 50 * nt);
        let mut ids: HashMap<[u32; 3], usize> = HashMap::new();
        let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
        for t in 0..nt {
            let r = &b[84 + 50 * t..84 + 50 * t + 50];
            let f = |k: usize| u32::from_le_bytes(r[4 * k..4 * k + 4].try_into().unwrap());
            let vid: Vec<usize> = (0..3)
                .map(|c| {
                    let key = [f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c)];
                    let n = ids.len();
                    *ids.entry(key).or_insert(n)
                })
                .collect();
            assert!(
                vid[0] != vid[1] && vid[1] != vid[2] && vid[0] != vid[2],
                "triangle {t}"
            );
            for k in 0..3 {
                *edges.entry((vid[k], vid[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, bb), &n) in &edges {
            assert_eq!(n, 1, "{v:?}: directed edge {a}->{bb} used {n} times");
            assert_eq!(
                edges.get(&(bb, a)),
                Some(&1),
                "{v:?}: edge {a}-{bb} is open"
            );
        }
        assert_eq!(ids.len(), want.vertices, "{v:?}: distinct STL vertices");
    }
}

/// Item 8: `refine.c` (Maillot-Stam unified scheme): every printed line
/// (bytes, counts, first vertex) equals the Rust API on the same cube and
/// levels.
#[test]
fn refine_example_matches_the_rust_api() {
    use ccss_core::unified::{refine_unified_levels, unified_levels_bytes, UnifiedParams};
    use ccss_core::{MeshInput, Topology};
    let p = [
        -1., -1., -1., 1., -1., -1., 1., 1., -1., -1., 1., -1., -1., -1., 1., 1., -1., 1., 1., 1.,
        1., -1., 1., 1.,
    ];
    let sizes = [4u32; 6];
    let idx = [
        0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
    ];
    let mesh = MeshInput {
        positions: &p,
        face_sizes: &sizes,
        indices: &idx,
    };
    let cc = UnifiedParams::CATMULL_CLARK;
    let def = UnifiedParams::default();
    let cases: [(&str, Vec<UnifiedParams>); 4] = [
        ("catmull-clark", vec![cc]),
        ("default", vec![def]),
        ("default-d3", vec![def.with_d(3)]),
        ("catmull-clark-2", vec![cc, cc]),
    ];
    let mut tmem = vec![0u64; Topology::required_bytes(8, &sizes) / 8 + 1];
    let topo = Topology::build(mesh, &mut tmem).unwrap();
    for v in [Variant::Strict, Variant::Sanitized] {
        let out = stdout_of("refine", v);
        for (name, levels) in &cases {
            let line = out
                .lines()
                .find(|l| l.starts_with(&format!("refine name={name} ")))
                .unwrap_or_else(|| panic!("no line for {name}\n{out}"));
            let bytes = unified_levels_bytes(&topo, levels).unwrap();
            let mut mem = vec![0u64; bytes / 8 + 1];
            let lv = refine_unified_levels(&topo, levels, &mut mem).unwrap();
            let fine = lv.finest().unwrap();
            let want = format!(
                "refine name={name} levels={} bytes={bytes} vertices={} faces={} indices={} first=",
                levels.len(),
                fine.positions.len() / 3,
                fine.face_sizes.len(),
                fine.indices.len()
            );
            assert!(line.starts_with(&want), "{line}\nwant {want}");
            let first: Vec<f64> = line[want.len()..]
                .split(',')
                .map(|x| x.parse().unwrap())
                .collect();
            assert_eq!(first, fine.positions[..3], "{name}: {line}");
        }
        assert!(out.contains("# error: d = 1 rejected"), "{out}");
    }
}

/// `voxelize.c` (the bundled torus at 48^3, N = 6) against the Rust API:
/// counts, runs, transform, the slab equal to the whole grid, and the exact
/// volume and area.
#[test]
fn voxelize_example_matches_the_rust_api() {
    use ccss_core::voxel::{mass_properties, Adjacency, VoxelGrid, VoxelParams, VoxelWork};
    let out = stdout_of("voxelize", Variant::Strict);
    let m = PolyMesh::from_obj(&root().join("tests/data/osd/catmark_torus.obj"));
    with_evaluator(&m, standard_tables(), |_, ev| {
        let params = VoxelParams::new([48, 48, 48], Adjacency::Six);
        let mut mem = vec![0u64; words_for(VoxelGrid::required_bytes(params.res).unwrap())];
        let mut g = VoxelGrid::new(params.res, &mut mem).unwrap();
        let mut work = Box::new(VoxelWork::ZERO);
        g.voxelize(ev, &params, None, &mut work).unwrap();
        g.flood(ev, &mut [0u32; 256], &mut work).unwrap();
        let c = g.counts();
        let want = format!(
            "res=48 adjacency=6 surface={} interior={} runs={} flood_inside=1 guard_hits=0",
            c.surface,
            c.interior,
            g.run_count()
        );
        assert!(out.lines().any(|l| l == want), "want '{want}' in\n{out}");
        let t = g.transform();
        let line = line_of(&out, "transform");
        assert_eq!(field(line, "scale"), t.scale, "{line}");
        assert!(out.contains("slab_differences=0"), "{out}");
        let p = mass_properties(ev).unwrap();
        let line = line_of(&out, "exact");
        assert_eq!(field(line, "volume"), p.volume, "{line}");
        assert_eq!(field(line, "area"), p.area, "{line}");
    })
    .unwrap();
}

/// The value of the enum constant `name` in `include/ccss.h`.
fn header_constant(name: &str) -> i64 {
    let h = std::fs::read_to_string(root().join("include/ccss.h")).unwrap();
    let prefix = format!("{name} = ");
    h.lines()
        .find_map(|l| l.trim().strip_prefix(&prefix))
        .and_then(|v| v.trim_end_matches(',').parse().ok())
        .unwrap_or_else(|| panic!("no {name} in include/ccss.h"))
}

/// The three numbers after `name=` in a line.
fn three_after(line: &str, name: &str) -> [f64; 3] {
    let i = line
        .find(&format!(" {name}="))
        .unwrap_or_else(|| panic!("no {name}= in {line:?}"));
    let v: Vec<f64> = line[i + name.len() + 2..]
        .split_whitespace()
        .take(3)
        .map(|t| {
            t.parse()
                .unwrap_or_else(|_| panic!("bad {t:?} in {line:?}"))
        })
        .collect();
    v.try_into().unwrap()
}

/// Item 9: `creases.c` (boundaries, creases, holes via the feature
/// evaluator).
#[test]
fn creases_example_matches_the_rust_api() {
    use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
    use ccss_core::{FeatureEvaluator, MeshInput};
    // The open 3x3 grid of creases.c, default options (EDGE_ONLY).
    let mut p = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            p.extend_from_slice(&[i as f64, j as f64, 0.0]);
        }
    }
    let mut idx = Vec::new();
    for j in 0..3u32 {
        for i in 0..3u32 {
            let v = 4 * j + i;
            idx.extend_from_slice(&[v, v + 1, v + 5, v + 4]);
        }
    }
    let sizes = [4u32; 9];
    let mesh = MeshInput {
        positions: &p,
        face_sizes: &sizes,
        indices: &idx,
    };
    let mut fmem = vec![0u64; words_for(FeatureMesh::required_bytes(&mesh).unwrap())];
    let fm = FeatureMesh::build(&mesh, &FeatureInput::default(), &mut fmem).unwrap();
    let mut emem = vec![0u64; words_for(FeatureEvaluator::required_bytes(&fm, None))];
    let fe = FeatureEvaluator::build(&fm, None, &mut emem).unwrap();
    // The grid with face 4 a hole, tessellated as creases.c does.
    let holed = {
        use ccss_core::tessellate::{Options, Scratch, Tessellation};
        let tags = FeatureInput {
            holes: &[4],
            ..FeatureInput::default()
        };
        let mut hmem = vec![0u64; words_for(FeatureMesh::required_bytes(&mesh).unwrap())];
        let hm = FeatureMesh::build(&mesh, &tags, &mut hmem).unwrap();
        let mut hemem = vec![0u64; words_for(FeatureEvaluator::required_bytes(&hm, None))];
        let he = FeatureEvaluator::build(&hm, None, &mut hemem).unwrap();
        let opts = Options::absolute(0.01);
        let need =
            Tessellation::required_bytes_feature(&he, &opts, &mut Box::new(Scratch::ZERO)).unwrap();
        let mut tmem = vec![0u64; words_for(need)];
        let counts = Tessellation::build_feature(&he, opts, &mut tmem)
            .unwrap()
            .counts();
        counts
    };
    for v in [Variant::Strict, Variant::Sanitized] {
        let out = stdout_of("creases", v);
        assert!(out.contains("# ALL PASS: 0 failure(s)"), "{v:?}\n{out}");
        // 1. The fully creased cube: flat bilinear faces.
        let line = line_of(&out, "cube");
        assert_eq!(field(line, "points"), 486.0, "{line}");
        let dev = field(line, "max_deviation");
        assert!((0.0..=1e-14).contains(&dev), "{line}");
        // 2. The grid: the Rust evaluator's numbers, z = 0.
        for (key, face, u, w) in [
            ("grid centre", 4u32, 0.5, 0.5),
            ("grid boundary", 1, 0.5, 0.0),
        ] {
            let line = line_of(&out, key);
            assert_eq!(field(line, "face"), face as f64, "{line}");
            assert_eq!((field(line, "u"), field(line, "v")), (u, w), "{line}");
            let want = fe.eval(face, 0, u, w).unwrap();
            let (pp, nn) = (three_after(line, "p"), three_after(line, "n"));
            assert_eq!(pp, [want.p.x, want.p.y, want.p.z], "{line}");
            assert_eq!(nn, [want.normal.x, want.normal.y, want.normal.z], "{line}");
            assert!(pp.iter().chain(&nn).all(|x| x.is_finite()), "{line}");
            assert_eq!(pp[2], 0.0, "{line}");
        }
        assert_eq!(
            three_after(line_of(&out, "grid centre"), "p"),
            [1.5, 1.5, 0.0]
        );
        // 3. The hole.
        let line = line_of(&out, "hole");
        assert_eq!(
            field(line, "status") as i64,
            header_constant("CCSS_ERR_HOLE_FACE"),
            "{line}"
        );
        assert_eq!(field(line, "face"), 4.0, "{line}");
        // 4. The crease on two vertices without an edge.
        let line = line_of(&out, "not_an_edge");
        assert_eq!(
            field(line, "status") as i64,
            header_constant("CCSS_ERR_NOT_AN_EDGE"),
            "{line}"
        );
        assert!(line.ends_with("vertices=0 5"), "{line}");
        // 5. Tessellations: the creased cube closed, the holed grid open,
        // with the Rust API's counts.
        let line = line_of(&out, "tess cube");
        assert_eq!(field(line, "boundary_edges"), 0.0, "{line}");
        assert!(field(line, "bound") <= 0.01, "{line}");
        let line = line_of(&out, "tess holed_grid");
        assert_eq!(field(line, "polygons"), holed.polygons as f64, "{line}");
        assert_eq!(field(line, "vertices"), holed.vertices as f64, "{line}");
        assert!(field(line, "boundary_edges") > 0.0, "{line}");
        assert!(
            out.contains("# crease tag on vertices 0 and 5, which no edge joins"),
            "{out}"
        );
    }
}

/// `raycast.c` (the bundled torus, through its slot index) against the
/// Rust API with the same index (the same hits, closest points and inside
/// answers, bit for bit) and the torus' facts:
/// four crossings along the ray through the ring, two through the tube,
/// a miss, the point in the tube inside, in the hole outside; the zero
/// direction rejected naming ray 1.
#[test]
fn raycast_example_matches_the_rust_api() {
    use ccss_core::query::{
        closest, inside, ray_all, ray_first, ClosestOptions, Hit, IndexNode, Indexed, QueryWork,
        Ray, RayOptions, SlotIndex,
    };
    use ccss_core::DVec3;
    let out = stdout_of("raycast", Variant::Strict);
    let m = PolyMesh::from_obj(&root().join("tests/data/osd/catmark_torus.obj"));
    let rays = [
        ([-3.0, 0.01, 0.02], [1.0, 0.0, 0.0]),
        ([0.9, 2.0, 0.1], [0.0, -1.0, 0.0]),
        ([0.0, 0.0, 0.0], [0.3, 0.05, 1.0]),
        ([5.0, 5.0, 5.0], [1.0, 0.0, 0.0]),
    ];
    let points = [[0.9, 0.0, 0.05], [0.0, 0.0, 0.0], [3.0, 1.0, -2.0]];
    with_evaluator(&m, standard_tables(), |_, plain| {
        // The example queries through the torus' slot index.
        let mut nodes = vec![IndexNode::default(); SlotIndex::required_len(plain)];
        let ix = SlotIndex::build(plain, &mut nodes).unwrap();
        let indexed = Indexed::new(plain, &ix).unwrap();
        let ev = &indexed;
        let mut w = Box::new(QueryWork::ZERO);
        let opts = RayOptions {
            tol: 1e-9,
            t_min: 0.0,
            ..Default::default()
        };
        for (i, (o, d)) in rays.iter().enumerate() {
            let ray = Ray {
                origin: DVec3::from_array(*o),
                dir: DVec3::from_array(*d),
            };
            let first = ray_first(ev, &ray, &opts, &mut w).unwrap();
            let line = line_of(&out, &format!("first {i}"));
            match first {
                None => assert!(line.contains("found=0"), "{line}"),
                Some(h) => {
                    assert_eq!(field(line, "t"), h.t, "{line}");
                    assert_eq!(field(line, "u"), h.u, "{line}");
                    assert_eq!(field(line, "face") as u32, h.face, "{line}");
                }
            }
            let mut hits = [Hit::ZERO; 8];
            let n = ray_all(ev, &ray, &opts, &mut w, &mut hits).unwrap();
            let line = line_of(&out, &format!("all {i}"));
            assert_eq!(field(line, "n") as usize, n, "{line}");
            assert_eq!(n, [4, 2, 2, 0][i], "{line}");
            let ts: Vec<f64> = line
                .split("t=")
                .nth(1)
                .unwrap()
                .split(',')
                .filter(|s| !s.is_empty())
                .map(|s| s.trim().parse().unwrap())
                .collect();
            let want: Vec<f64> = hits[..n].iter().map(|h| h.t).collect();
            assert_eq!(ts, want, "{line}");
        }
        for (i, p) in points.iter().enumerate() {
            let p = DVec3::from_array(*p);
            let ins = inside(ev, p, 1e-9, &mut w).unwrap();
            assert_eq!(ins, i == 0);
            let line = line_of(&out, &format!("inside {i}"));
            assert_eq!(field(line, "value") as i32, ins as i32, "{line}");
            let c = closest(
                ev,
                p,
                &ClosestOptions {
                    tol: 1e-9,
                    ..Default::default()
                },
                &mut w,
            )
            .unwrap();
            let line = line_of(&out, &format!("closest {i}"));
            assert_eq!(field(line, "dist"), c.dist, "{line}");
            assert_eq!(field(line, "u"), c.u, "{line}");
        }
    })
    .unwrap();
    let line = line_of(&out, "error zero_direction");
    assert_eq!(
        field(line, "status") as i64,
        header_constant("CCSS_ERR_INVALID_ARGUMENT"),
        "{line}"
    );
    assert_eq!(field(line, "index") as i64, 1, "{line}");
}

/// `slice.c` (the bundled torus, planes y = -0.3 .. 0.3 across its axis)
/// against the Rust API (counts and areas, bit for bit), with the torus'
/// facts: each layer one outer contour and one hole, mirror layers with
/// equal areas (within the slices' bound), and eps = 0 rejected. The same
/// planes as one band (`ccss_query_slice_band`) against `query::slice_band`
/// (counts and summed areas bit for bit) and equal to the layers printed
/// one by one; a band of 65 layers rejected.
#[test]
fn slice_example_matches_the_rust_api() {
    use ccss_core::query::{
        band_layer, slice_band, slice_layer, slice_segment_count, slice_write, Contour, Plane,
        PlaneStack, QueryWork, SliceOptions, SliceSegment, SliceStats,
    };
    use ccss_core::DVec3;
    let out = stdout_of("slice", Variant::Strict);
    let m = PolyMesh::from_obj(&root().join("tests/data/osd/catmark_torus.obj"));
    let contour_lines: Vec<&str> = out.lines().filter(|l| l.starts_with("contour ")).collect();
    assert_eq!(contour_lines.len(), 10, "{out}");
    with_evaluator(&m, standard_tables(), |_, ev| {
        let mut w = Box::new(QueryWork::ZERO);
        let o = SliceOptions {
            eps: 1e-3,
            ..Default::default()
        };
        let mut areas = vec![];
        for k in 0..5 {
            let y = -0.3 + 0.15 * k as f64;
            let plane = Plane {
                normal: DVec3::Y,
                offset: y,
            };
            let n = slice_segment_count(ev, &plane, &o, &mut w).unwrap();
            let mut segs = vec![SliceSegment::default(); n];
            let st = slice_layer(ev, &plane, &o, &mut w, &mut segs).unwrap();
            let mut pts = vec![[0.0; 2]; st.points];
            let mut cs = vec![Contour::default(); st.contours];
            slice_write(&mut segs, &mut pts, &mut cs).unwrap();
            let line = line_of(&out, &format!("layer {k}"));
            assert_eq!(field(line, "points") as usize, st.points, "{line}");
            assert_eq!(field(line, "contours") as usize, 2, "{line}");
            for (ci, c) in cs.iter().enumerate() {
                let l = contour_lines[2 * k + ci];
                assert!(l.contains(if c.outer { "outer" } else { "hole" }), "{l}");
                let (s, len) = (c.start as usize, c.len as usize);
                let a: f64 = (0..len)
                    .map(|j| {
                        let (p, q) = (pts[s + j], pts[s + (j + 1) % len]);
                        p[0] * q[1] - p[1] * q[0]
                    })
                    .sum();
                assert_eq!(field(l, "area"), 0.5 * a, "{l}");
            }
            assert_eq!(cs.iter().filter(|c| c.outer).count(), 1);
            areas.push(
                field(contour_lines[2 * k], "area") + field(contour_lines[2 * k + 1], "area"),
            );
        }
        // The band: layer k of y = -0.3 + 0.15 k, as the example asks.
        let stack = PlaneStack {
            normal: DVec3::Y,
            offset: -0.3,
            step: 0.15,
        };
        let mut stats = [SliceStats::default(); 5];
        let n = match slice_band(ev, &stack, 0, &o, &mut w, &mut [], &mut stats) {
            Err(ccss_core::Error::BufferTooSmall { required }) => required,
            r => panic!("size query: {r:?}"),
        };
        let mut segs = vec![SliceSegment::default(); n];
        assert_eq!(
            slice_band(ev, &stack, 0, &o, &mut w, &mut segs, &mut stats).unwrap(),
            n
        );
        for (k, st) in stats.iter().enumerate() {
            let mut pts = vec![[0.0; 2]; st.points];
            let mut cs = vec![Contour::default(); st.contours];
            slice_write(band_layer(&mut segs, &stats, k), &mut pts, &mut cs).unwrap();
            let mut total = 0.0;
            for c in &cs {
                let (s, len) = (c.start as usize, c.len as usize);
                let a: f64 = (0..len)
                    .map(|j| {
                        let (p, q) = (pts[s + j], pts[s + (j + 1) % len]);
                        p[0] * q[1] - p[1] * q[0]
                    })
                    .sum();
                total += 0.5 * a;
            }
            let line = line_of(&out, &format!("band {k}"));
            assert_eq!(field(line, "points") as usize, st.points, "{line}");
            assert_eq!(field(line, "contours") as usize, st.contours, "{line}");
            assert_eq!(field(line, "area"), total, "{line}");
            // Equal to the layer sliced alone (printed above).
            let alone = line_of(&out, &format!("layer {k}"));
            assert_eq!(field(alone, "points"), field(line, "points"), "{alone}");
            assert_eq!(
                0.0 + field(contour_lines[2 * k], "area") + field(contour_lines[2 * k + 1], "area"),
                field(line, "area"),
                "{line}"
            );
        }
        // Mirror symmetry of the torus in y: areas agree within the bound
        // (perimeter ~ 12 times eps, twice).
        assert!(
            (areas[0] - areas[4]).abs() <= 2.0 * 12.0 * 1e-3,
            "{areas:?}"
        );
        assert!(
            (areas[1] - areas[3]).abs() <= 2.0 * 12.0 * 1e-3,
            "{areas:?}"
        );
    })
    .unwrap();
    let line = line_of(&out, "error eps");
    assert_eq!(
        field(line, "status") as i64,
        header_constant("CCSS_ERR_INVALID_ARGUMENT"),
        "{line}"
    );
    let line = line_of(&out, "error band count");
    assert_eq!(
        field(line, "status") as i64,
        header_constant("CCSS_ERR_INVALID_ARGUMENT"),
        "{line}"
    );
}

/// `interpolate.c` (the cube, assembled normal matrix) against the Rust API
/// on the same path: counts, iterations and the first control point bit
/// for bit, the interpolation checked by the
/// example's own limit mask, the normal requirement solved and the
/// conflicting one rejected.
#[test]
fn interpolate_example_matches_the_rust_api() {
    use ccss_core::interpolate::{InterpolationOptions, Interpolator};
    use ccss_core::{MeshInput, Topology};
    let p = [
        -1., -1., -1., 1., -1., -1., 1., 1., -1., -1., 1., -1., -1., -1., 1., 1., -1., 1., 1., 1.,
        1., -1., 1., 1.,
    ];
    let sizes = [4u32; 6];
    let idx = [
        0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
    ];
    let mesh = MeshInput {
        positions: &p,
        face_sizes: &sizes,
        indices: &idx,
    };
    let mut tmem = vec![0u64; Topology::required_bytes(8, &sizes) / 8 + 1];
    let topo = Topology::build(mesh, &mut tmem).unwrap();
    let tables = ccss_tests::harness::standard_tables();
    let mut mem = vec![0u64; Interpolator::required_bytes(&topo, &[]) / 8 + 1];
    let mut it = Interpolator::build(
        &topo,
        tables,
        InterpolationOptions::default(),
        &[],
        &mut mem,
    )
    .unwrap();
    let mut matrix = vec![0u64; it.assembled_bytes().div_ceil(8)];
    it.assemble(&mut matrix).unwrap();
    let mut q = vec![0.0; 3 * it.num_vertices()];
    let s = it.solve(&mut q, &mut |_, _| {}).unwrap();
    for v in [Variant::Strict, Variant::Sanitized] {
        let out = stdout_of("interpolate", v);
        let line = line_of(&out, "interpolate");
        let want = format!(
            "vertices={} faces={} iterations={} worst=",
            it.num_vertices(),
            it.subdivided().num_faces(),
            s.iterations
        );
        assert!(line.starts_with(&want), "{line}\nwant {want}");
        assert!(field(line, "worst") <= 1e-12, "{line}");
        let first = line.split("first=").nth(1).unwrap();
        let first: Vec<f64> = first.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(first, q[..3], "{line}");
        assert!(out.contains("normal iterations="), "{out}");
        assert!(
            out.contains("# error: conflicting requirement 0 rejected"),
            "{out}"
        );
    }
}

/// Item 12: `boolean.c` (Booleans through the C ABI, under ASan/UBSan):
/// the union, intersection and difference of the built-in prism and its
/// rotated copy reach the bound, report an exact short-buffer size, and
/// write an STL whose triangle count matches the printed line; volumes
/// (of the f32 STL) satisfy vol(A∪B) + vol(A∩B) = vol(A) + vol(B) with
/// vol(A) = vol(B) and vol(A−B) = vol(A) − vol(A∩B) to 1e-4 relative.
#[test]
fn boolean_example_writes_consistent_stls() {
    use std::collections::HashMap;
    let _ = runs();
    let s = setup();
    let eps = 0.01;
    for v in [Variant::Strict, Variant::Sanitized] {
        let exe = s.bin_dir.join(format!("boolean-{v:?}").to_lowercase());
        let mut vol = HashMap::new();
        for op in ["union", "intersection", "difference"] {
            let stl = s
                .bin_dir
                .join(format!("boolean-{op}-{v:?}.stl").to_lowercase());
            let out = Command::new(&exe)
                .arg(&stl)
                .env(
                    "ASAN_OPTIONS",
                    "detect_leaks=1:abort_on_error=0:exitcode=86",
                )
                .env("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
                .output()
                .expect("run boolean");
            // Built-in operands: the op is the fifth argument, so run again
            // with defaults spelled out when the op is not the union.
            let out = if op == "union" {
                out
            } else {
                Command::new(&exe)
                    .arg(&stl)
                    .arg("-")
                    .arg("-")
                    .arg(eps.to_string())
                    .arg(op)
                    .env(
                        "ASAN_OPTIONS",
                        "detect_leaks=1:abort_on_error=0:exitcode=86",
                    )
                    .env("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
                    .output()
                    .expect("run boolean")
            };
            assert!(out.status.success(), "{}", show("boolean", &out));
            let text = String::from_utf8(out.stdout).unwrap();
            let line = text
                .lines()
                .find(|l| l.starts_with("triangles="))
                .expect(&text);
            let kv: HashMap<&str, &str> =
                line.split(' ').filter_map(|t| t.split_once('=')).collect();
            let num = |k: &str| kv[k].parse::<f64>().unwrap();
            assert!(num("bound") <= eps && num("curve_loops") >= 1.0, "{line}");
            assert!(text.contains("one triangle index short: status"), "{text}");
            let b = std::fs::read(&stl).unwrap();
            let nt = u32::from_le_bytes(b[80..84].try_into().unwrap()) as usize;
            assert_eq!(nt, num("triangles") as usize, "{line}");
            assert_eq!(b.len(), 84 + 50 * nt);
            let mut vsum = 0.0f64;
            for t in 0..nt {
                let r = &b[84 + 50 * t..84 + 50 * t + 50];
                let f =
                    |k: usize| f32::from_le_bytes(r[4 * k..4 * k + 4].try_into().unwrap()) as f64;
                let p = |c: usize| [f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c)];
                let (a, bb, c) = (p(0), p(1), p(2));
                vsum += (a[0] * (bb[1] * c[2] - bb[2] * c[1])
                    - a[1] * (bb[0] * c[2] - bb[2] * c[0])
                    + a[2] * (bb[0] * c[1] - bb[1] * c[0]))
                    / 6.0;
            }
            assert!(vsum > 0.0, "{op}: volume {vsum}");
            vol.insert(op, vsum);
        }
        let (u, i, d) = (vol["union"], vol["intersection"], vol["difference"]);
        // vol(A) = vol(B) = u - d... : A = d + i, B = u - d.
        let (va, vb) = (d + i, u - d);
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs();
        assert!(i < va && i < vb && u > va, "{vol:?}");
        // A and B are congruent: their tessellations' volumes agree to the
        // tessellation bound x area (small), far below 1e-2 relative.
        assert!(rel(va, vb) < 1e-2, "{vol:?}");
    }
}
