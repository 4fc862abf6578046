//! Subdivision depths of feature meshes (`bounds::feature_depth`) against
//! the actual distance between the refined control mesh and the limit
//! surface: the control mesh of the reference subdivider
//! (`tests/src/sharp.rs`, OpenSubdiv's rules) at the claimed level and one
//! level deeper, bilinear over each control face, against exact limit
//! points (`FeatureEvaluator::eval`) at the same parameters. Zero
//! violations; the tightness (largest distance / eps, and how many levels
//! a measured depth would save) is printed.
use ccss_core::bounds::feature_depth::feature_depth;
use ccss_core::DVec3;
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{standard_tables, workspace_root};
use ccss_tests::sharp::{SharpRefiner, TaggedMesh};

/// Largest distance, over every control face of `(face, sub)` at cell
/// level `k` (refinement level `k + extra`) and 9 points per face, between
/// the bilinear control face and the limit surface.
fn measured(
    r: &mut SharpRefiner,
    ev: &ccss_core::FeatureEvaluator,
    face: usize,
    sub: usize,
    k: u32,
    extra: u32,
) -> f64 {
    let n = 1u32 << k;
    let level = (k + extra) as usize;
    // Vertex of each dyadic point, then positions at the level.
    let mut ids = vec![0u32; ((n + 1) * (n + 1)) as usize];
    for j in 0..=n {
        for i in 0..=n {
            let (l, v) = r.dyadic_vertex(face, sub, i, j, k);
            assert!(l <= level);
            ids[(j * (n + 1) + i) as usize] = v;
        }
    }
    let pos = r.level(level).positions.clone();
    let p = |i: u32, j: u32| DVec3::from_array(pos[ids[(j * (n + 1) + i) as usize] as usize]);
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            for (s, t) in [0.25, 0.5, 0.75]
                .iter()
                .flat_map(|&s| [0.25, 0.5, 0.75].map(|t| (s, t)))
            {
                let l = a * ((1.0 - s) * (1.0 - t))
                    + b * (s * (1.0 - t))
                    + c * (s * t)
                    + d * ((1.0 - s) * t);
                let (u, v) = ((i as f64 + s) / n as f64, (j as f64 + t) / n as f64);
                let q = ev.eval(face as u32, sub as u32, u, v).unwrap().p;
                worst = worst.max(l.distance(q));
            }
        }
    }
    worst
}

#[test]
fn feature_depths_hold_on_the_refined_control_mesh() {
    let tables = standard_tables();
    let mut checked = 0;
    for (name, rel_eps) in [
        ("catmark_cube_creases0.obj", 0.02),
        ("catmark_cube_corner2.obj", 0.02),
        ("catmark_cubes_semisharp.obj", 0.03),
        ("catmark_pyramid_creases0.obj", 0.02),
        ("catmark_torus_creases0.obj", 0.03),
        ("catmark_edgecorner.obj", 0.02),
        ("catmark_dart_edgeonly.obj", 0.03),
    ] {
        let m = TaggedMesh::from_obj(&workspace_root().join("tests/data/osd").join(name)).unwrap();
        let eps = rel_eps * m.bbox_diagonal();
        let f = flat(&m);
        let mut r = SharpRefiner::new(&m).unwrap();
        with_feature_mesh(&f, Some(tables), |ev| {
            let (mut worst, mut saved, mut deepest) = (0.0f64, 0u32, 0u32);
            let (mut polys, mut hulls) = (0u32, 0u32);
            for face in 0..ev.num_faces() {
                let extra = u32::from(m.faces[face].len() != 4);
                for sub in 0..ev.num_subfaces(face) {
                    let d = feature_depth(ev, face as u32, sub as u32, eps).unwrap();
                    polys += d.poly_cells;
                    hulls += d.final_hulls + d.split_hulls;
                    let steps = d.steps.expect("depth bounded");
                    deepest = deepest.max(steps);
                    let k = steps - extra;
                    // One level deeper too where that is cheap.
                    let levels: &[u32] = if k < 5 { &[k, k + 1] } else { &[k] };
                    for &kk in levels {
                        let dist = measured(&mut r, ev, face, sub, kk, extra);
                        assert!(
                            dist <= eps,
                            "{name}: face {face} sub {sub}: depth {steps}, level {kk}: \
                             distance {dist:e} > eps {eps:e}"
                        );
                        if kk == k {
                            worst = worst.max(dist / eps);
                        }
                    }
                    // How many levels a measured depth would save.
                    let mut kk = k;
                    while kk > 0 && measured(&mut r, ev, face, sub, kk - 1, extra) <= eps {
                        kk -= 1;
                    }
                    saved = saved.max(k - kk);
                    checked += 1;
                }
            }
            println!(
                "{name}: eps {rel_eps} of the diagonal: deepest {deepest} steps; \
                 {polys} Lemma-1 cells, {hulls} hull cells; largest distance at the depth \
                 {worst:.3} eps; a measured depth is at most {saved} levels shallower"
            );
        })
        .unwrap();
    }
    assert!(checked > 50);
}
