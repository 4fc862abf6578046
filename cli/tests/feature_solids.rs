//! `ccss voxelize` and `ccss measure` on meshes with OpenSubdiv tags: the
//! feature path (creases and corners honoured, no "tags ignored" warning),
//! the fully creased cube measured and voxelized as the cube itself, the
//! `--boundary` / `--creasing` switches, and the one-line "not a closed
//! solid" error naming the boundary edge of an open mesh.

mod common;

use common::{ccss, data, num, out_dir, summary, text};

const MEASURE_KEYS: [&str; 8] = [
    "volume",
    "area",
    "centroid",
    "inertia",
    "mass",
    "error_bound",
    "area_error_bound",
    "seconds",
];

/// The cube [-1, 1]^3 with every edge and corner infinitely sharp, written
/// to `name` (one file per test: tests run in parallel).
fn creased_cube(name: &str) -> String {
    let mut obj = String::new();
    for z in [-1, 1] {
        for y in [-1, 1] {
            for x in [-1, 1] {
                obj += &format!("v {x} {y} {z}\n");
            }
        }
    }
    obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\n";
    for (a, b) in [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        obj += &format!("t crease 2/1/0 {a} {b} 10\n");
    }
    let p = out_dir("feature-solids").join(name);
    std::fs::write(&p, obj).unwrap();
    p.display().to_string()
}

#[test]
fn measure_honours_creases() {
    let cube = creased_cube("cube_m.obj");
    let o = ccss(&["measure", &cube]);
    assert!(text(&o.stderr).is_empty(), "{}", text(&o.stderr));
    let kv = summary(&o, &MEASURE_KEYS);
    let v = num(&kv, "volume");
    assert!((v - 8.0).abs() <= 1e-12 + num(&kv, "error_bound"), "{v}");
    assert!((num(&kv, "area") - 24.0).abs() <= 1e-11 + num(&kv, "area_error_bound"));
    let inertia: Vec<f64> = kv["inertia"]
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    for k in 0..3 {
        assert!((inertia[k] - 64.0 / 12.0).abs() < 1e-11, "{inertia:?}");
    }
    // A corpus shape with creases differs from its smooth surface.
    let creased = summary(
        &ccss(&[
            "measure",
            data("catmark_cube_creases0.obj").to_str().unwrap(),
        ]),
        &MEASURE_KEYS,
    );
    let o = ccss(&["measure", data("catmark_cube.obj").to_str().unwrap()]);
    let smooth = summary(&o, &MEASURE_KEYS);
    assert!((num(&creased, "volume") - num(&smooth, "volume")).abs() > 0.1);
    // --creasing on an untagged closed mesh selects the feature path: the
    // same surface as the smooth path.
    let o = ccss(&[
        "measure",
        "--creasing",
        "chaikin",
        data("catmark_cube.obj").to_str().unwrap(),
    ]);
    let feat = summary(&o, &MEASURE_KEYS);
    assert!((num(&feat, "volume") - num(&smooth, "volume")).abs() < 1e-12);
}

#[test]
fn voxelize_honours_creases() {
    let cube = creased_cube("cube_v.obj");
    let out = out_dir("feature-solids").join("cube.binvox");
    let o = ccss(&[
        "voxelize",
        "--res",
        "20",
        "--adjacency",
        "6",
        &cube,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(text(&o.stderr).is_empty(), "{}", text(&o.stderr));
    let kv = summary(
        &o,
        &[
            "res",
            "adjacency",
            "surface",
            "interior",
            "volume",
            "area",
            "seconds",
            "threads",
        ],
    );
    // The cube fills the grid: voxel centres 0..19 span it exactly, so
    // the surface is the outer layer and the rest is interior.
    let (s, i) = (num(&kv, "surface"), num(&kv, "interior"));
    assert_eq!(s + i, 8000.0, "{kv:?}");
    assert!(i >= 16.0f64.powi(3), "{kv:?}");
}

#[test]
fn open_meshes_are_not_solids() {
    for verb in [
        vec!["measure"],
        vec!["voxelize", "--res", "16", "-o", "/dev/null"],
    ] {
        for name in ["catmark_edgeonly.obj", "catmark_car.obj"] {
            let mesh = data(name);
            let mut args = verb.clone();
            args.push(mesh.to_str().unwrap());
            let o = ccss(&args);
            assert!(!o.status.success());
            let err = text(&o.stderr);
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(
                err.starts_with("ccss: error: ")
                    && err.contains("not a closed solid: edge ")
                    && err.contains("is a boundary edge"),
                "{err}"
            );
            assert!(!err.contains("ignored"), "{err}");
        }
    }
    // A closed mesh with a hole face.
    let mut obj = std::fs::read_to_string(data("catmark_cube_creases0.obj")).unwrap();
    obj += "t hole 1/0/0 3\n";
    let p = out_dir("feature-solids").join("holed.obj");
    std::fs::write(&p, obj).unwrap();
    let o = ccss(&["measure", p.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("not a closed solid: face 3 is a hole"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn depth_uses_the_feature_path() {
    // The fully creased cube: every control face is already on the (flat)
    // limit surface; the bound needs at most the one step that splits a
    // quad into its four B-spline pieces.
    let cube = creased_cube("cube_d.obj");
    let o = ccss(&["depth", "--eps", "0.001", &cube]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).is_empty(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 7, "{out}");
    for l in &lines[..6] {
        let d: u32 = l.split(' ').nth(1).unwrap().parse().unwrap();
        assert!(d <= 1, "{out}");
    }
    assert!(lines[6].contains("method=features"), "{out}");
    // Creases make the surface differ from the smooth one; an open mesh
    // has depths too (no closed solid needed).
    for name in ["catmark_cube_creases0.obj", "catmark_edgeonly.obj"] {
        let o = ccss(&["depth", "--eps", "0.01", data(name).to_str().unwrap()]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        assert!(out.lines().last().unwrap().contains("method=features"));
    }
}
