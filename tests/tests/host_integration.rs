//! ccss installed for C/C++ hosts, end to end (issue #8).
//!
//! 1. `scripts/install.sh` builds ccss-ffi (release, its own cargo target
//!    directory `<target>/install-test/cargo`, so it never waits for the lock
//!    of the `cargo test` running this file) and installs it into a fresh
//!    prefix `<target>/install-test/prefix`.
//! 2. The installed files: header identical to `include/ccss.h`, the shared
//!    library's soname (`readelf -d`) and its links, `ccss.pc`,
//!    `ccss-static.pc` and the CMake package; a second install with
//!    `--libdir lib/<multiarch> --destdir` (staging for packagers) and
//!    `--uninstall`.
//! 3. The static link line: what `rustc --print native-static-libs` reports
//!    for the real library equals an independent probe (an empty staticlib),
//!    the pkg-config files and the CMake package carry exactly it, the line
//!    documented in README.md (section "Use from C/C++") is
//!    it, and `c_examples/eval.c` links with it and runs.
//! 4. `c_examples/hosts` (CMake) against the installed package, four ways:
//!    find_package + shared and pkg-config + static build the OpenMesh and
//!    CGAL examples as well as `eval.c`; find_package + static and
//!    pkg-config + shared build `eval.c` only (a quick link check). Shared
//!    binaries must need `libccss.so.<soversion>`, static ones no libccss.
//! 5. The examples on OpenSubdiv shapes: their output files (exact limit
//!    position and normal of every vertex and face centre) against the
//!    reference subdivider's limit masks (`ccss_tests::reference`), OpenMesh
//!    and CGAL outputs against each other, and the convergence of each peer's
//!    Catmull-Clark control points to our limit points: per valence, the
//!    distance must shrink per level by the factor the subdivision matrix
//!    predicts (4 at valence 4), recomputed here independently.
//! 6. The depth, tessellation and voxel examples (find_package + shared):
//!    `openmesh_tessellate` (absolute flatness, STL) on the torus, cube and
//!    pyramid: closed 2-manifold with the input's Euler characteristic,
//!    vertices on the limit surface, sampled flatness within eps, volume
//!    within area x eps of the exact one, and the STL file read here
//!    (closed and consistently oriented by float identity of the corners);
//!    `cgal_depth_voxels` on the torus, cube, pyramid and right hand: CGAL's
//!    Catmull-Clark control faces within eps of the limit surface at each
//!    slot's ccss depth, ccss's voxel interior equal to CGAL's
//!    Side_of_triangle_mesh away from the surface, surface and clearance
//!    distances, volume bracket. Both also run once with a check tolerance
//!    below the measured distance and must fail (exit status 2).
//!
//! Needs cargo, a C compiler, readelf; for 4. and 5. also cmake, pkg-config,
//! OpenMesh and CGAL (Debian: cmake pkgconf libopenmesh-dev libcgal-dev).
//! Without those, 4. and 5. print a note and pass, unless
//! `CCSS_REQUIRE_HOSTS=1` (set by `.ci/run`, which installs them).
use ccss_tests::reference::{standard_weights, PolyMesh, Refiner};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn root() -> PathBuf {
    ccss_tests::harness::workspace_root()
}

/// `<target>/install-test`.
fn work_dir() -> PathBuf {
    ccss_tests::harness::target_subdir("install-test")
}

fn require_hosts() -> bool {
    std::env::var("CCSS_REQUIRE_HOSTS").as_deref() == Ok("1")
}

fn show(what: &str, out: &Output) -> String {
    format!(
        "{what}: {}\n--- stdout ---\n{}\n--- stderr ---\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Runs `cmd`, panics with its output unless it succeeds; returns stdout.
fn run(what: &str, cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {cmd:?}: {e}"));
    assert!(out.status.success(), "{}", show(what, &out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn have(tool: &str, arg: &str) -> bool {
    Command::new(tool)
        .arg(arg)
        .output()
        .is_ok_and(|o| o.status.success())
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

fn host_triple() -> String {
    let vv = run("rustc -vV", Command::new(rustc()).arg("-vV"));
    vv.lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_owned))
        .expect("host triple in rustc -vV")
}

const VERSION: &str = env!("CARGO_PKG_VERSION"); // the workspace version

fn soversion() -> String {
    let mut it = VERSION.split('.');
    let (major, minor) = (it.next().unwrap(), it.next().unwrap());
    if major == "0" {
        format!("0.{minor}")
    } else {
        major.to_owned()
    }
}

struct Install {
    prefix: PathBuf,
    cargo_target: PathBuf,
    /// What the install script's `cargo rustc -- --print native-static-libs`
    /// reported for libccss.a.
    native_libs: Vec<String>,
}

impl Install {
    fn lib(&self) -> PathBuf {
        self.prefix.join("lib")
    }
}

fn install_script(args: &[&str]) -> Output {
    Command::new("bash")
        .arg(root().join("scripts/install.sh"))
        .args(args)
        .env("CARGO", env!("CARGO"))
        .env_remove("DESTDIR")
        .current_dir(root())
        .output()
        .expect("run scripts/install.sh")
}

/// The install of step 1, once per test process.
fn install() -> &'static Install {
    static I: OnceLock<Install> = OnceLock::new();
    I.get_or_init(|| {
        let work = work_dir();
        let prefix = work.join("prefix");
        let cargo_target = work.join("cargo");
        if prefix.exists() {
            std::fs::remove_dir_all(&prefix).unwrap();
        }
        let out = install_script(&[
            "--quiet",
            "--prefix",
            prefix.to_str().unwrap(),
            "--target-dir",
            cargo_target.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", show("scripts/install.sh", &out));
        let notes = std::fs::read_to_string(cargo_target.join("ccss-install-notes.txt"))
            .expect("the install's cargo output");
        let native_libs = notes
            .lines()
            .filter_map(|l| l.split("native-static-libs:").nth(1))
            .next_back()
            .expect("native-static-libs note in the install's cargo output")
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        Install {
            prefix,
            cargo_target,
            native_libs,
        }
    })
}

fn pkg_config(inst: &Install, args: &[&str]) -> String {
    run(
        &format!("pkg-config {args:?}"),
        Command::new("pkg-config")
            .args(args)
            .env("PKG_CONFIG_PATH", inst.lib().join("pkgconfig"))
            .env_remove("PKG_CONFIG_LIBDIR"),
    )
    .trim()
    .to_owned()
}

fn readelf_dynamic(file: &Path) -> String {
    run("readelf -d", Command::new("readelf").arg("-d").arg(file))
}

/// The `[...]` values of the `(tag)` lines of `readelf -d`.
fn dynamic_entries(dynamic: &str, tag: &str) -> Vec<String> {
    dynamic
        .lines()
        .filter(|l| l.contains(&format!("({tag})")))
        .filter_map(|l| {
            let a = l.find('[')?;
            let b = l.rfind(']')?;
            Some(l[a + 1..b].to_owned())
        })
        .collect()
}

#[test]
fn install_puts_library_header_pkgconfig_and_cmake_package_in_the_prefix() {
    let inst = install();
    let lib = inst.lib();
    let so = soversion();
    let real = format!("libccss.so.{VERSION}");
    let soname = format!("libccss.so.{so}");

    // Header: the repository's, byte for byte.
    let header = std::fs::read(inst.prefix.join("include/ccss.h")).expect("installed ccss.h");
    assert_eq!(
        header,
        std::fs::read(root().join("include/ccss.h")).unwrap(),
        "installed ccss.h differs from include/ccss.h"
    );

    // Libraries: the real file, soname link, dev link.
    assert!(lib.join("libccss.a").is_file());
    assert!(lib.join(&real).is_file());
    for (link, target) in [(soname.as_str(), real.as_str()), ("libccss.so", &soname)] {
        let t = std::fs::read_link(lib.join(link))
            .unwrap_or_else(|e| panic!("{link} is not a symlink: {e}"));
        assert_eq!(t, Path::new(target), "{link} -> {}", t.display());
    }
    let dynamic = readelf_dynamic(&lib.join(&real));
    assert_eq!(
        dynamic_entries(&dynamic, "SONAME"),
        vec![soname.clone()],
        "{dynamic}"
    );
    // The static library holds the C ABI (readelf: nm would try to read the
    // embedded LLVM bitcode through the system's LTO plugin).
    let syms = run(
        "readelf -s libccss.a",
        Command::new("readelf")
            .arg("-sW")
            .arg(lib.join("libccss.a")),
    );
    for f in [
        "ccss_version",
        "ccss_evaluator_eval",
        "ccss_evaluator_build",
    ] {
        assert!(
            syms.lines().any(|l| l.contains(" GLOBAL ")
                && l.contains(" FUNC ")
                && l.ends_with(&format!(" {f}"))),
            "{f} not defined in libccss.a"
        );
    }

    // CMake package files.
    let cmake_dir = lib.join("cmake/ccss");
    let config = std::fs::read_to_string(cmake_dir.join("ccssConfig.cmake")).unwrap();
    assert!(!config.contains('@'), "unreplaced placeholder:\n{config}");
    assert!(config.contains(&format!("IMPORTED_SONAME \"{soname}\"")));
    assert!(config.contains(&format!("/{real}\"")));
    let cv = std::fs::read_to_string(cmake_dir.join("ccssConfigVersion.cmake")).unwrap();
    assert!(cv.contains(&format!("set(PACKAGE_VERSION \"{VERSION}\")")));

    // Manifest: every installed file, nothing else.
    let manifest =
        std::fs::read_to_string(inst.prefix.join("share/ccss/install_manifest.txt")).unwrap();
    let mut listed: Vec<&str> = manifest.lines().collect();
    listed.sort();
    let mut want = vec![
        "include/ccss.h".to_owned(),
        "lib/libccss.a".to_owned(),
        format!("lib/{real}"),
        format!("lib/{soname}"),
        "lib/libccss.so".to_owned(),
        "lib/pkgconfig/ccss.pc".to_owned(),
        "lib/pkgconfig/ccss-static.pc".to_owned(),
        "lib/cmake/ccss/ccssConfig.cmake".to_owned(),
        "lib/cmake/ccss/ccssConfigVersion.cmake".to_owned(),
    ];
    want.sort();
    assert_eq!(listed, want);

    // pkg-config.
    if !have("pkg-config", "--version") {
        assert!(!require_hosts(), "pkg-config missing");
        eprintln!("NOTE: pkg-config not found, .pc checks skipped");
        return;
    }
    let p = inst.prefix.display();
    assert_eq!(pkg_config(inst, &["--modversion", "ccss"]), VERSION);
    assert_eq!(
        pkg_config(inst, &["--cflags", "ccss"]),
        format!("-I{p}/include")
    );
    assert_eq!(
        pkg_config(inst, &["--libs", "ccss"]),
        format!("-L{p}/lib -lccss")
    );
    assert_eq!(pkg_config(inst, &["--modversion", "ccss-static"]), VERSION);
}

#[test]
fn static_link_line_is_what_rustc_prints_and_is_documented() {
    let inst = install();
    let libs = &inst.native_libs;
    assert!(!libs.is_empty());

    // An independent probe: the native libraries of an empty std staticlib.
    // Our dependencies are pure Rust, so those of libccss.a must be the same.
    let probe = work_dir().join("native-libs-probe");
    std::fs::create_dir_all(&probe).unwrap();
    std::fs::write(probe.join("empty.rs"), "").unwrap();
    let out = Command::new(rustc())
        .current_dir(&probe)
        .args(["--crate-type", "staticlib", "--crate-name", "empty"])
        .args(["--print", "native-static-libs", "-o"])
        .arg(probe.join("libempty.a"))
        .arg(probe.join("empty.rs"))
        .output()
        .expect("rustc");
    assert!(out.status.success(), "{}", show("rustc probe", &out));
    let probe_libs: Vec<String> = String::from_utf8_lossy(&out.stderr)
        .lines()
        .find_map(|l| l.split("native-static-libs:").nth(1).map(str::to_owned))
        .expect("native-static-libs note")
        .split_whitespace()
        .map(str::to_owned)
        .collect();
    assert_eq!(
        libs, &probe_libs,
        "libccss.a needs other native libraries than std"
    );
    let line = libs.join(" ");

    // The installed package files carry exactly that line.
    let lib = inst.lib();
    let pc = std::fs::read_to_string(lib.join("pkgconfig/ccss.pc")).unwrap();
    assert!(
        pc.lines().any(|l| l == format!("Libs.private: {line}")),
        "{pc}"
    );
    let pcs = std::fs::read_to_string(lib.join("pkgconfig/ccss-static.pc")).unwrap();
    assert!(
        pcs.lines()
            .any(|l| l == format!("Libs: ${{libdir}}/libccss.a {line}")),
        "{pcs}"
    );
    let config = std::fs::read_to_string(lib.join("cmake/ccss/ccssConfig.cmake")).unwrap();
    assert!(
        config.contains(&format!(
            "set(ccss_NATIVE_STATIC_LIBS \"{}\")",
            libs.join(";")
        )),
        "{config}"
    );
    if have("pkg-config", "--version") {
        let p = inst.prefix.display();
        assert_eq!(
            pkg_config(inst, &["--libs", "ccss-static"]),
            format!("{p}/lib/libccss.a {line}")
        );
        assert_eq!(
            pkg_config(inst, &["--static", "--libs", "ccss"]),
            format!("-L{p}/lib -lccss {line}")
        );
    }

    // The documentation shows it (on the platform it was written for): the
    // line with `libccss.a -l...` in a code block.
    let host = host_triple();
    let documented_for = "x86_64-unknown-linux-gnu";
    let doc = root().join("README.md");
    let docs = vec![(
        doc.clone(),
        std::fs::read_to_string(&doc).expect("README.md"),
    )];
    for (path, text) in &docs {
        let shown: Vec<&str> = text
            .lines()
            .filter_map(|l| l.split("libccss.a ").nth(1))
            .filter(|rest| rest.starts_with("-l"))
            .collect();
        assert!(
            !shown.is_empty(),
            "{}: no `libccss.a -l...` link line",
            path.display()
        );
        assert!(
            text.contains(documented_for),
            "{}: does not say which platform the link line is for",
            path.display()
        );
        if host == documented_for {
            for s in shown {
                assert_eq!(
                    s.trim_end_matches(['`', ' ']),
                    line,
                    "{}: documented static link line differs from rustc's",
                    path.display()
                );
            }
        }
    }

    // And it links: c_examples/eval.c with exactly that line, then runs.
    let bin = work_dir().join("eval-static-cc");
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    run(
        "cc eval.c libccss.a <native libs>",
        Command::new(&cc)
            .args(["-std=c99", "-O1", "-I"])
            .arg(inst.prefix.join("include"))
            .arg(root().join("c_examples/eval.c"))
            .arg(lib.join("libccss.a"))
            .args(libs)
            .arg("-o")
            .arg(&bin),
    );
    let out = run("eval (static)", &mut Command::new(&bin));
    assert!(out.starts_with(&format!("# ccss {VERSION}\n")), "{out}");
    let dynamic = readelf_dynamic(&bin);
    assert!(
        !dynamic_entries(&dynamic, "NEEDED")
            .iter()
            .any(|n| n.starts_with("libccss")),
        "static binary needs libccss:\n{dynamic}"
    );
}

#[test]
fn install_with_multiarch_libdir_staged_by_destdir_then_uninstall() {
    let inst = install(); // builds; this install reuses the build
    let stage = work_dir().join("stage");
    if stage.exists() {
        std::fs::remove_dir_all(&stage).unwrap();
    }
    let prefix = "/opt/ccss-test";
    let out = install_script(&[
        "--quiet",
        "--no-build",
        "--prefix",
        prefix,
        "--libdir",
        "lib/x86_64-linux-gnu",
        "--destdir",
        stage.to_str().unwrap(),
        "--target-dir",
        inst.cargo_target.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        show("install.sh --destdir", &out)
    );
    let root_dir = stage.join("opt/ccss-test");
    let lib = root_dir.join("lib/x86_64-linux-gnu");
    assert!(lib.join("libccss.a").is_file());
    assert!(lib.join(format!("libccss.so.{VERSION}")).is_file());
    // The files refer to the final prefix, not the staging directory.
    let pc = std::fs::read_to_string(lib.join("pkgconfig/ccss.pc")).unwrap();
    assert!(pc.contains(&format!("prefix={prefix}\n")), "{pc}");
    assert!(
        pc.contains("libdir=${prefix}/lib/x86_64-linux-gnu\n"),
        "{pc}"
    );
    assert!(!pc.contains(stage.to_str().unwrap()), "{pc}");
    // The CMake package finds the prefix relative to itself (relocatable):
    // lib/x86_64-linux-gnu/cmake/ccss is four levels below it.
    let config = std::fs::read_to_string(lib.join("cmake/ccss/ccssConfig.cmake")).unwrap();
    assert!(
        config.contains("\"${CMAKE_CURRENT_LIST_DIR}/../../../..\""),
        "{config}"
    );
    assert!(config.contains("set(_ccss_libdir \"${_ccss_prefix}/lib/x86_64-linux-gnu\")"));

    let out = install_script(&[
        "--quiet",
        "--uninstall",
        "--prefix",
        prefix,
        "--destdir",
        stage.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        show("install.sh --uninstall", &out)
    );
    let left: Vec<PathBuf> = walk(&stage);
    assert!(left.is_empty(), "left after --uninstall: {left:?}");

    // Bad arguments are refused with a message.
    let out = install_script(&["--prefix", "relative/path", "--no-build"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("absolute"));
}

/// Files (not directories) under `dir`.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() && !p.is_symlink() {
                todo.push(p);
            } else {
                files.push(p);
            }
        }
    }
    files
}

// ---------------------------------------------------------------------------
// CMake hosts.

#[derive(Clone, Copy, Debug)]
struct Config {
    find: &'static str, // "config" | "pkg-config"
    link: &'static str, // "shared" | "static"
    peers: bool,
    /// Also the depth / tessellation / voxel examples (openmesh_tessellate,
    /// cgal_depth_voxels): one CGAL compile costs about 30 s, so only one
    /// of the two peer builds has them.
    extras: bool,
}

/// Configures and builds c_examples/hosts; returns the build directory.
fn cmake_build(inst: &Install, c: Config) -> PathBuf {
    let build = work_dir().join(format!(
        "build-{}-{}{}",
        c.find,
        c.link,
        if c.peers { "" } else { "-c" }
    ));
    // A cache from another checkout (same target dir) would make CMake
    // refuse the source directory: always configure from scratch.
    let _ = std::fs::remove_dir_all(&build);
    let mut cfg = Command::new("cmake");
    cfg.arg("-S")
        .arg(root().join("c_examples/hosts"))
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", inst.prefix.display()))
        .arg(format!("-DCCSS_FIND={}", c.find))
        .arg(format!("-DCCSS_LINK={}", c.link))
        .arg(format!(
            "-DCCSS_HOSTS_PEERS={}",
            if c.peers { "ON" } else { "OFF" }
        ))
        .arg(format!(
            "-DCCSS_HOSTS_EXTRAS={}",
            if c.extras { "ON" } else { "OFF" }
        ))
        .arg(format!(
            "-DCCSS_HOSTS_REQUIRE_ALL={}",
            if require_hosts() { "ON" } else { "OFF" }
        ))
        .arg("-DCMAKE_BUILD_TYPE=Release")
        // Only the prefix, never a PKG_CONFIG_PATH of the environment.
        .env_remove("PKG_CONFIG_PATH")
        .env_remove("ccss_DIR");
    let log = run(&format!("cmake configure {c:?}"), &mut cfg);
    match c.find {
        "config" => assert!(
            log.contains(&format!(
                "ccss {VERSION} from {}",
                inst.lib().join("cmake/ccss").display()
            )),
            "{log}"
        ),
        _ => assert!(
            log.contains(&format!("ccss {VERSION} from pkg-config")),
            "{log}"
        ),
    }
    run(
        &format!("cmake --build {c:?}"),
        Command::new("cmake")
            .arg("--build")
            .arg(&build)
            .args(["--parallel", "2"]),
    );
    build
}

/// Checks that `bin` needs libccss.so.<soversion> (shared) or no libccss.
fn check_link_style(bin: &Path, link: &str) {
    let dynamic = readelf_dynamic(bin);
    let needed = dynamic_entries(&dynamic, "NEEDED");
    let ccss: Vec<&String> = needed.iter().filter(|n| n.starts_with("libccss")).collect();
    match link {
        "shared" => assert_eq!(
            ccss,
            vec![&format!("libccss.so.{}", soversion())],
            "{}: {needed:?}",
            bin.display()
        ),
        _ => assert!(ccss.is_empty(), "{}: {needed:?}", bin.display()),
    }
}

fn run_eval_c(build: &Path, c: Config) {
    let bin = build.join("eval_c");
    check_link_style(&bin, c.link);
    let out = run(
        &format!("eval_c {c:?}"),
        // The shared build finds libccss through its build RPATH.
        Command::new(&bin).env_remove("LD_LIBRARY_PATH"),
    );
    assert!(out.starts_with(&format!("# ccss {VERSION}\n")), "{out}");
    assert_eq!(
        out.lines().filter(|l| !l.starts_with('#')).count(),
        25,
        "{out}"
    );
}

/// One line of the examples' output file.
#[derive(Clone, Copy, Debug)]
struct Point {
    control: [f64; 3],
    limit: [f64; 3],
    normal: [f64; 3],
}

#[derive(Debug, Default)]
struct LimitFile {
    vertices: BTreeMap<usize, Point>,
    centres: BTreeMap<usize, Point>,
}

fn parse_limit_file(path: &Path) -> LimitFile {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut f = LimitFile::default();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let t: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(t.len(), 11, "{}: {line:?}", path.display());
        let idx: usize = t[1].parse().unwrap();
        let x: Vec<f64> = t[2..]
            .iter()
            .map(|s| {
                s.parse()
                    .unwrap_or_else(|_| panic!("bad number in {line:?}"))
            })
            .collect();
        let p = Point {
            control: [x[0], x[1], x[2]],
            limit: [x[3], x[4], x[5]],
            normal: [x[6], x[7], x[8]],
        };
        let map = match t[0] {
            "v" => &mut f.vertices,
            "f" => &mut f.centres,
            k => panic!("unknown kind {k:?} in {line:?}"),
        };
        assert!(map.insert(idx, p).is_none(), "duplicate {line:?}");
    }
    f
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Index of the point of `pts` nearest to `p`, and that distance.
fn nearest<'a>(p: [f64; 3], pts: impl Iterator<Item = (usize, &'a [f64; 3])>) -> (usize, f64) {
    pts.map(|(i, q)| (i, dist(p, *q)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("no points")
}

/// Checks a limit file against the reference subdivider's limit masks on the
/// mesh as the host read it (its control points; OpenMesh's OBJ reader, for
/// one, parses single precision).
fn check_limit_file(mesh_path: &Path, f: &LimitFile, who: &str) {
    let mut pm = PolyMesh::from_obj(mesh_path);
    let diag = pm.bbox_diagonal();
    assert_eq!(f.vertices.len(), pm.positions.len(), "{who}: vertex count");
    assert_eq!(f.centres.len(), pm.faces.len(), "{who}: face count");
    // tobj renumbers vertices; map ours to the host's by position.
    let host: Vec<(usize, [f64; 3])> = f.vertices.iter().map(|(&i, p)| (i, p.control)).collect();
    let mut map = Vec::with_capacity(pm.positions.len());
    for p in &pm.positions {
        let (i, d) = nearest(*p, host.iter().map(|(i, q)| (*i, q)));
        assert!(d <= 1e-6 * diag, "{who}: no host vertex at {p:?} ({d})");
        map.push(i);
    }
    for (k, &i) in map.iter().enumerate() {
        pm.positions[k] = f.vertices[&i].control;
    }
    let tol = 1e-12 * diag;
    let mut refiner = Refiner::new(&pm, None);
    for (k, &i) in map.iter().enumerate() {
        let want = refiner.limit_position(0, k as u32);
        let got = f.vertices[&i];
        assert!(
            dist(got.limit, want) <= tol,
            "{who}: vertex {i}: limit {:?}, reference {want:?}",
            got.limit
        );
        let len = dist(got.normal, [0.0; 3]);
        assert!(
            (len - 1.0).abs() <= 1e-12,
            "{who}: vertex {i} normal {:?}",
            got.normal
        );
    }
    let centres: Vec<(usize, [f64; 3])> = f.centres.iter().map(|(&i, p)| (i, p.control)).collect();
    for (j, face) in pm.faces.iter().enumerate() {
        let n = face.len() as f64;
        let c: [f64; 3] = std::array::from_fn(|k| {
            face.iter()
                .map(|&v| pm.positions[v as usize][k])
                .sum::<f64>()
                / n
        });
        let (i, d) = nearest(c, centres.iter().map(|(i, q)| (*i, q)));
        assert!(d <= 1e-12 * diag, "{who}: no host face with centroid {c:?}");
        // (1/2, 1/2) of a quad; (1, 1) of sub-face 0 of an n-gon.
        let want = if face.len() == 4 {
            refiner.dyadic_limit_point(j, 0, 1, 1, 1)
        } else {
            refiner.dyadic_limit_point(j, 0, 1, 1, 0)
        };
        let got = f.centres[&i];
        assert!(
            dist(got.limit, want) <= tol,
            "{who}: face {i}: centre limit {:?}, reference {want:?}",
            got.limit
        );
        let len = dist(got.normal, [0.0; 3]);
        assert!(
            (len - 1.0).abs() <= 1e-12,
            "{who}: face {i} normal {:?}",
            got.normal
        );
    }
}

/// One `conv` line of an example's report.
#[derive(Debug, Clone)]
struct Conv {
    kind: String,
    valence: usize,
    count: usize,
    expected: f64,
    /// d1..dL: largest distance after L levels / bbox diagonal.
    d: Vec<f64>,
}

fn parse_conv(out: &str) -> Vec<Conv> {
    let mut v = Vec::new();
    for line in out.lines().filter(|l| l.starts_with("conv ")) {
        let t: Vec<&str> = line.split_whitespace().collect();
        let field = |name: &str| -> &str {
            t.iter()
                .find_map(|x| x.strip_prefix(&format!("{name}=")))
                .unwrap_or_else(|| panic!("no {name}= in {line:?}"))
        };
        let mut d = Vec::new();
        for l in 1.. {
            match t.iter().find_map(|x| x.strip_prefix(&format!("d{l}="))) {
                Some(s) => d.push(s.parse::<f64>().unwrap()),
                None => break,
            }
        }
        v.push(Conv {
            kind: t[1].to_owned(),
            valence: field("valence").parse().unwrap(),
            count: field("count").parse().unwrap(),
            expected: field("expected_ratio").parse().unwrap(),
            d,
        });
    }
    v
}

/// 1/mu for valence n: mu the larger root of x^2 - (alpha - 1/4) x +
/// (1 - 2 beta)/16 (the rotationally symmetric part of the one-ring
/// subdivision matrix, besides eigenvalue 1), standard weights.
fn expected_ratio(n: usize) -> f64 {
    let (alpha, beta, _) = standard_weights(n);
    let t = alpha - 0.25;
    let d = (1.0 - 2.0 * beta) / 16.0;
    let disc = t * t - 4.0 * d;
    assert!(disc >= 0.0);
    1.0 / ((t + disc.sqrt()) / 2.0)
}

/// Runs one example on one mesh; checks its output file and its convergence
/// report; returns the report.
fn run_example(build: &Path, c: Config, example: &str, mesh: &str) -> (Vec<Conv>, LimitFile) {
    let bin = build.join(example);
    check_link_style(&bin, c.link);
    let mesh_path = root().join("tests/data/osd").join(format!("{mesh}.obj"));
    let out_dir = build.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let txt = out_dir.join(format!("{example}-{mesh}.txt"));
    let limit_mesh = out_dir.join(format!(
        "{example}-{mesh}.{}",
        if example.starts_with("openmesh") {
            "obj"
        } else {
            "off"
        }
    ));
    let _ = std::fs::remove_file(&txt);
    let _ = std::fs::remove_file(&limit_mesh);
    let out = Command::new(&bin)
        .arg(&mesh_path)
        .arg(&txt)
        .arg(&limit_mesh)
        .env_remove("LD_LIBRARY_PATH")
        .output()
        .expect("run example");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let what = format!("{example} {mesh} ({c:?})");
    // The example checks the rates itself (exit status 2 and FAIL lines with
    // the measured numbers); re-checked below from its numbers.
    assert!(out.status.success(), "{}", show(&what, &out));
    assert!(stdout.contains("PASS: 0 failure(s)"), "{what}:\n{stdout}");
    assert!(
        std::fs::metadata(&limit_mesh).is_ok_and(|m| m.len() > 0),
        "{what}: no {}",
        limit_mesh.display()
    );

    let file = parse_limit_file(&txt);
    check_limit_file(&mesh_path, &file, &what);

    let conv = parse_conv(&stdout);
    assert!(!conv.is_empty(), "{what}: no conv lines\n{stdout}");
    for g in &conv {
        let want = expected_ratio(g.valence);
        assert!(
            (g.expected - want).abs() <= 1e-4 * want,
            "{what}: {g:?}: expected ratio {want}"
        );
        assert_eq!(g.d.len(), 4, "{what}: {g:?}");
        // From the second step of the all-quad one-ring dynamics on:
        // vertices from level 2, face centres (born at level 1) from 3.
        let first = if g.kind == "centre" { 3 } else { 2 };
        for l in first..=g.d.len() {
            let (a, b) = (g.d[l - 2], g.d[l - 1]);
            if b <= 1e-12 {
                continue; // round-off
            }
            let tol = if l == g.d.len() { 0.03 } else { 0.10 };
            let r = a / b;
            assert!(
                (r / want - 1.0).abs() <= tol,
                "{what}: {} valence {} ({} points): level {} -> {}: distance {a:.3e} -> \
                 {b:.3e} of the bbox diagonal, ratio {r:.4}, expected {want:.4} +- {}%\n{stdout}",
                g.kind,
                g.valence,
                g.count,
                l - 1,
                l,
                tol * 100.0
            );
        }
        // And the distance is really going to zero.
        assert!(g.d[3] < 0.5 * g.d[0], "{what}: {g:?}");
    }
    (conv, file)
}

#[test]
fn cmake_hosts_build_against_the_install_and_cross_check_openmesh_and_cgal() {
    let have_cmake = have("cmake", "--version");
    let have_pc = have("pkg-config", "--version");
    if !(have_cmake && have_pc) {
        assert!(
            !require_hosts(),
            "CCSS_REQUIRE_HOSTS=1 but cmake ({have_cmake}) or pkg-config ({have_pc}) is missing"
        );
        eprintln!("NOTE: cmake or pkg-config not found, host examples skipped");
        return;
    }
    let inst = install();
    let configs = [
        Config {
            find: "config",
            link: "shared",
            peers: true,
            extras: true,
        },
        Config {
            find: "pkg-config",
            link: "static",
            peers: true,
            extras: false,
        },
        Config {
            find: "config",
            link: "static",
            peers: false,
            extras: false,
        },
        Config {
            find: "pkg-config",
            link: "shared",
            peers: false,
            extras: false,
        },
    ];
    let meshes = [
        "catmark_righthanded",
        "catmark_toroidal_tet",
        "catmark_pyramid",
    ];
    let mut summary = Vec::new();
    let mut per_mesh: BTreeMap<(&str, &str), LimitFile> = BTreeMap::new();
    let mut capability_summary = Vec::new();
    for c in configs {
        let build = cmake_build(inst, c);
        run_eval_c(&build, c);
        if !c.peers {
            continue;
        }
        for example in ["openmesh_limit", "cgal_limit"] {
            if !build.join(example).exists() {
                assert!(!require_hosts(), "{example} was not built ({c:?})");
                eprintln!("NOTE: {example} not built (library missing), skipped");
                continue;
            }
            for mesh in meshes {
                let (conv, file) = run_example(&build, c, example, mesh);
                if c.link == "shared" {
                    for g in conv {
                        summary.push((example, mesh, g));
                    }
                    per_mesh.insert((example, mesh), file);
                }
            }
        }
        if c.extras {
            capability_summary = run_capability_examples(&build, c);
            capability_summary.extend(run_creases_example(&build, c));
        }
    }

    // OpenMesh and CGAL hand us the same mesh (up to OpenMesh's
    // single-precision OBJ reader): the limits they got must agree.
    for mesh in meshes {
        let (Some(a), Some(b)) = (
            per_mesh.get(&("openmesh_limit", mesh)),
            per_mesh.get(&("cgal_limit", mesh)),
        ) else {
            continue;
        };
        // Limit points are convex combinations of control points, so they
        // differ by at most the largest control-point difference.
        assert_eq!(a.vertices.len(), b.vertices.len());
        let input = a
            .vertices
            .iter()
            .map(|(i, p)| dist(p.control, b.vertices[i].control))
            .fold(0.0, f64::max);
        assert!(
            input <= 1e-6,
            "{mesh}: OpenMesh and CGAL read different points ({input})"
        );
        let all = |f: &LimitFile| -> Vec<(usize, Point)> {
            let v = f.vertices.iter().map(|(&i, p)| (i, *p));
            v.chain(f.centres.iter().map(|(&i, p)| (usize::MAX - i, *p)))
                .collect()
        };
        for ((i, p), (j, q)) in all(a).into_iter().zip(all(b)) {
            assert_eq!(i, j);
            assert!(
                dist(p.limit, q.limit) <= input + 1e-12,
                "{mesh}: point {i}: OpenMesh {p:?} CGAL {q:?} (inputs differ by {input})"
            );
        }
    }

    // The measured rates (cargo test -- --nocapture shows them).
    eprintln!("convergence of the peers' Catmull-Clark control points to ccss's limit points");
    eprintln!("(max distance / bbox diagonal after L levels; ratio = d(L-1)/d(L))");
    for (example, mesh, g) in &summary {
        let ratios: Vec<String> =
            g.d.windows(2)
                .map(|w| format!("{:.3}", w[0] / w[1]))
                .collect();
        eprintln!(
            "{example:15} {mesh:22} {:6} n={:2} count={:3} expected={:.3} d4={:.2e} ratios {}",
            g.kind,
            g.valence,
            g.count,
            g.expected,
            g.d[3],
            ratios.join(" ")
        );
    }
    eprintln!("openmesh_tessellate / cgal_depth_voxels (key numbers)");
    for l in &capability_summary {
        eprintln!("{l}");
    }
}

// ---------------------------------------------------------------------------
// Depth, tessellation and voxels from the hosts: openmesh_tessellate and
// cgal_depth_voxels.

/// The `key=value` fields of the first stdout line starting with `tag `.
fn fields(out: &str, tag: &str, what: &str) -> BTreeMap<String, String> {
    let line = out
        .lines()
        .find(|l| l.starts_with(&format!("{tag} ")))
        .unwrap_or_else(|| panic!("{what}: no {tag:?} line\n{out}"));
    line.split_whitespace()
        .filter_map(|t| t.split_once('='))
        .map(|(k, v)| (k.to_owned(), v.to_owned()))
        .collect()
}

/// Field `key` of line `tag` as a number.
fn num(out: &str, tag: &str, key: &str, what: &str) -> f64 {
    let f = fields(out, tag, what);
    let v = f
        .get(key)
        .unwrap_or_else(|| panic!("{what}: no {key}= on the {tag:?} line\n{out}"));
    v.parse()
        .unwrap_or_else(|_| panic!("{what}: {tag} {key}={v} is not a number\n{out}"))
}

/// Runs `bin args`; returns (exit code, stdout, stderr).
fn run_capability(bin: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(bin)
        .args(args)
        .env_remove("LD_LIBRARY_PATH")
        .output()
        .unwrap_or_else(|e| panic!("run {}: {e}", bin.display()));
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A binary STL read independently of OpenMesh: its triangles as f32
/// corner triples. Panics unless the size is 84 + 50 n for the header's n.
fn read_stl(path: &Path) -> Vec<[[u32; 3]; 3]> {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(b.len() >= 84, "{}: {} bytes", path.display(), b.len());
    let n = u32::from_le_bytes(b[80..84].try_into().unwrap()) as usize;
    assert_eq!(
        b.len(),
        84 + 50 * n,
        "{}: size vs count {n}",
        path.display()
    );
    (0..n)
        .map(|t| {
            let r = &b[84 + 50 * t + 12..84 + 50 * t + 48];
            std::array::from_fn(|c| {
                std::array::from_fn(|k| {
                    let at = 12 * c + 4 * k;
                    u32::from_le_bytes(r[at..at + 4].try_into().unwrap())
                })
            })
        })
        .collect()
}

/// Closed and consistently oriented, by float identity of the corners:
/// every directed edge once, and its reverse once. Returns V - E + F.
fn stl_closed_euler(tris: &[[[u32; 3]; 3]], what: &str) -> i64 {
    let mut directed: BTreeMap<([u32; 3], [u32; 3]), usize> = BTreeMap::new();
    let mut verts = std::collections::BTreeSet::new();
    for t in tris {
        for c in 0..3 {
            verts.insert(t[c]);
            *directed.entry((t[c], t[(c + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "{what}: STL edge used {n} times in one direction");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "{what}: STL edge without its reverse (boundary or flipped triangle)"
        );
    }
    verts.len() as i64 - (directed.len() / 2) as i64 + tris.len() as i64
}

/// openmesh_tessellate and cgal_depth_voxels on bundled shapes, with the
/// checks of their printed numbers; returns one summary line per run.
fn run_capability_examples(build: &Path, c: Config) -> Vec<String> {
    let mut summary = Vec::new();
    let data = root().join("tests/data/osd");
    let out_dir = build.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();

    let om = build.join("openmesh_tessellate");
    if om.exists() {
        check_link_style(&om, c.link);
        // (mesh, eps, Euler characteristic)
        for (mesh, eps, chi) in [
            ("catmark_torus", 1e-3, 0),
            ("catmark_cube", 1e-3, 2),
            ("catmark_pyramid", 1e-3, 2),
        ] {
            let stl = out_dir.join(format!("{mesh}.stl"));
            let _ = std::fs::remove_file(&stl);
            let mesh_path = data.join(format!("{mesh}.obj"));
            let eps_s = eps.to_string();
            let args = [mesh_path.to_str().unwrap(), stl.to_str().unwrap(), &eps_s];
            let (code, out, err) = run_capability(&om, &args);
            let what = format!("openmesh_tessellate {mesh} {eps} ({c:?})");
            assert_eq!(code, Some(0), "{what}\n{out}\n{err}");
            assert!(out.contains("PASS: 0 failure(s)"), "{what}\n{out}");
            let n = |tag: &str, key: &str| num(&out, tag, key, &what);
            let tris = n("tess", "triangles");
            assert!(n("tess", "bound") <= eps, "{what}\n{out}");
            // Closed 2-manifold in OpenMesh with the input's characteristic.
            assert_eq!(n("topology", "manifold"), 1.0, "{what}\n{out}");
            for k in [
                "add_face_failures",
                "boundary_halfedges",
                "bad_edges",
                "nonmanifold_vertices",
                "isolated_vertices",
            ] {
                assert_eq!(n("topology", k), 0.0, "{what}: {k}\n{out}");
            }
            assert_eq!(n("topology", "euler"), chi as f64, "{what}\n{out}");
            assert_eq!(n("topology", "euler_input"), chi as f64, "{what}\n{out}");
            // Vertices on the limit surface, flatness, orientation.
            assert!(n("surface", "max_dist_rel") <= 1e-12, "{what}\n{out}");
            assert_eq!(n("surface", "bad_params"), 0.0, "{what}\n{out}");
            assert_eq!(n("flatness", "violations"), 0.0, "{what}\n{out}");
            assert_eq!(n("flatness", "outside_cell"), 0.0, "{what}\n{out}");
            assert!(n("flatness", "max_ratio") <= 1.0, "{what}\n{out}");
            assert!(n("flatness", "coverage") >= 0.5, "{what}\n{out}");
            assert_eq!(n("flatness", "samples"), 7.0 * n("flatness", "sampled"));
            assert_eq!(n("orientation", "flipped"), 0.0, "{what}\n{out}");
            // Volume: within the area times eps of the exact one.
            let dv = n("volume", "diff").abs();
            assert!(dv <= n("volume", "area") * eps, "{what}\n{out}");
            // The STL file, read here (not by OpenMesh): closed, oriented,
            // same triangle count and characteristic.
            let t = read_stl(&stl);
            assert_eq!(t.len() as f64, tris, "{what}");
            assert_eq!(stl_closed_euler(&t, &what), chi, "{what}");
            summary.push(format!(
                "openmesh_tessellate {mesh:20} eps={eps} triangles={tris} max_level={} \
                 coverage={} max_ratio={} dV/(A eps)={}",
                n("tess", "max_level"),
                n("flatness", "coverage"),
                n("flatness", "max_ratio"),
                n("volume", "diff_over_area_eps")
            ));
        }
        // The flatness check can fail: the same tessellation against a
        // tolerance below its measured distance.
        let mesh_path = data.join("catmark_cube.obj");
        let stl = out_dir.join("catmark_cube-tight.stl");
        let args = [
            mesh_path.to_str().unwrap(),
            stl.to_str().unwrap(),
            "0.001",
            "--check-tol",
            "0.0003",
        ];
        let (code, out, _) = run_capability(&om, &args);
        let what = format!("openmesh_tessellate --check-tol ({c:?})");
        assert_eq!(code, Some(2), "{what}\n{out}");
        assert!(
            num(&out, "flatness", "violations", &what) > 0.0,
            "{what}\n{out}"
        );
    } else {
        assert!(
            !require_hosts(),
            "openmesh_tessellate was not built ({c:?})"
        );
    }

    let cg = build.join("cgal_depth_voxels");
    if cg.exists() {
        check_link_style(&cg, c.link);
        // (mesh, eps, interior voxels expected)
        for (mesh, eps, solid) in [
            ("catmark_torus", "0.001", true),
            ("catmark_cube", "0.01", true),
            ("catmark_pyramid", "0.01", true),
            ("catmark_righthanded", "0.004", false),
        ] {
            let mesh_path = data.join(format!("{mesh}.obj"));
            let args = [mesh_path.to_str().unwrap(), "--eps", eps, "--res", "32"];
            let (code, out, err) = run_capability(&cg, &args);
            let what = format!("cgal_depth_voxels {mesh} --eps {eps} ({c:?})");
            assert_eq!(code, Some(0), "{what}\n{out}\n{err}");
            assert!(out.contains("PASS: 0 failure(s)"), "{what}\n{out}");
            let n = |tag: &str, key: &str| num(&out, tag, key, &what);
            // Depth: every slot checked at its depth, nothing beyond eps.
            assert_eq!(n("depth_check", "unchecked"), 0.0, "{what}\n{out}");
            assert_eq!(
                n("depth_check", "slots_checked"),
                n("depth", "slots"),
                "{what}\n{out}"
            );
            assert_eq!(n("depth_check", "violations"), 0.0, "{what}\n{out}");
            assert!(n("depth_check", "max_ratio") <= 1.0, "{what}\n{out}");
            assert!(n("depth_check", "samples") > 0.0, "{what}\n{out}");
            // Voxels against CGAL.
            assert_eq!(n("voxels", "guard_hits"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxels", "unresolved"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxel_tess", "closed"), 1.0, "{what}\n{out}");
            assert_eq!(n("voxel_check", "disagree"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxel_check", "skipped"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxel_surface", "far"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxel_clearance", "violations"), 0.0, "{what}\n{out}");
            assert_eq!(n("voxel_volume", "bracket"), 1.0, "{what}\n{out}");
            let inside = n("voxel_check", "checked_interior");
            assert_eq!(inside, n("voxels", "interior"), "{what}\n{out}");
            assert_eq!(inside > 0.0, solid, "{what}\n{out}");
            assert!(n("voxel_check", "checked_outside") > 0.0, "{what}\n{out}");
            summary.push(format!(
                "cgal_depth_voxels   {mesh:20} eps={eps} max_depth={} max_ratio={} \
                 before_max_ratio={} interior={} outside={} disagree=0",
                n("depth", "max_depth"),
                n("depth_check", "max_ratio"),
                n("depth_info", "before_max_ratio"),
                inside,
                n("voxel_check", "checked_outside")
            ));
            if mesh == "catmark_righthanded" {
                // One level before the depth the control faces are farther
                // than eps somewhere: the sampled distance is not vacuous.
                assert!(n("depth_info", "before_max_ratio") > 1.0, "{what}\n{out}");
            }
        }
        // The depth check can fail: a tolerance below the measured distance.
        let mesh_path = data.join("catmark_torus.obj");
        let args = [
            mesh_path.to_str().unwrap(),
            "--eps",
            "0.001",
            "--check-tol",
            "0.0001",
            "--res",
            "8",
        ];
        let (code, out, _) = run_capability(&cg, &args);
        let what = format!("cgal_depth_voxels --check-tol ({c:?})");
        assert_eq!(code, Some(2), "{what}\n{out}");
        assert!(
            num(&out, "depth_check", "violations", &what) > 0.0,
            "{what}\n{out}"
        );
    } else {
        assert!(!require_hosts(), "cgal_depth_voxels was not built ({c:?})");
    }
    summary
}

/// openmesh_creases on bundled shapes: boundary and dihedral-angle creases
/// through the C feature evaluator, checked by the example against the
/// closed-form crease and corner limits (it exits 2 on any violation);
/// here the counts it reports are checked against the shapes.
fn run_creases_example(build: &Path, c: Config) -> Vec<String> {
    let bin = build.join("openmesh_creases");
    if !bin.exists() {
        assert!(!require_hosts(), "openmesh_creases was not built ({c:?})");
        return Vec::new();
    }
    check_link_style(&bin, c.link);
    let data = root().join("tests/data/osd");
    let out_dir = build.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let mut summary = Vec::new();
    // (mesh, crease vertices, corners) expected at the default 40 degrees:
    // the cube's 12 edges are all creases and its 8 corners meet 3 each;
    // edgeonly's 32 border vertices are creases; the car and the bishop
    // have both (counts not fixed here, only non-zero).
    for (mesh, creases, corners) in [
        ("catmark_cube", Some(0), Some(8)),
        ("catmark_edgeonly", Some(32), Some(0)),
        ("catmark_car", None, None),
        ("catmark_bishop", None, None),
    ] {
        let txt = out_dir.join(format!("{mesh}_creases.txt"));
        let obj = data.join(format!("{mesh}.obj"));
        let (code, out, err) =
            run_capability(&bin, &[obj.to_str().unwrap(), txt.to_str().unwrap()]);
        let what = format!("openmesh_creases {mesh} ({c:?})");
        assert_eq!(code, Some(0), "{what}\n{out}\n{err}");
        assert!(out.contains("PASS: 0 failure(s)"), "{what}\n{out}");
        let n = |key: &str| num(&out, "features", key, &what);
        if let Some(k) = creases {
            assert_eq!(n("crease_vertices"), k as f64, "{what}\n{out}");
        }
        if let Some(k) = corners {
            assert_eq!(n("corners"), k as f64, "{what}\n{out}");
        }
        assert!(n("crease_vertices") + n("corners") > 0.0, "{what}\n{out}");
        // One line per vertex with a face.
        let lines = std::fs::read_to_string(&txt).unwrap().lines().count();
        assert!(lines > 0, "{what}: empty {}", txt.display());
        summary.push(format!(
            "openmesh_creases {mesh:20} {}",
            out.lines().next().unwrap_or("")
        ));
    }
    // Without creases the cube has no sharp vertex: nothing to check is a
    // failure (exit 2), not a silent pass.
    let obj = data.join("catmark_cube.obj");
    let txt = out_dir.join("cube_nocrease.txt");
    let (code, out, _) = run_capability(
        &bin,
        &[
            obj.to_str().unwrap(),
            txt.to_str().unwrap(),
            "--angle",
            "179",
        ],
    );
    assert_eq!(code, Some(2), "openmesh_creases --angle 179\n{out}");
    summary
}
