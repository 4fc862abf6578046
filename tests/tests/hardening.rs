//! Hardening (issue 27): bounds that include rounding, bounded work and
//! clean refusals on adversarial coordinates.
//!
//! * `build_rounding_constant`: the patch data of corpus shapes shifted by
//!   up to 1e12 agrees with the unshifted data plus the shift to well within
//!   `measure::BUILD_ROUNDING` (the measured constant the mass-property
//!   bounds rely on); the ratio found is printed.
//! * `build_rounding_constant_feature_meshes`: the same on 12 feature
//!   meshes (creases, corners, boundaries, holes), near sub-face corners too.
//! * `measure_translation_and_scale`: the unit cube shifted by 1e0..1e12 and
//!   scaled by 2^-190..2^190 (and by powers of ten) gives volume and area
//!   whose distance from the unshifted, unscaled values (scaled) is within
//!   the two stated bounds; sizes out of range are refused with
//!   `CoordinateRange`.
//! * `measure_needle_is_bounded`: the tetrahedron with a vertex at
//!   (65536, 65536, 65536) (formerly > 30 s) finishes within the area-cell cap.
//! * `measure_options_trade_work_for_bounds`: `mass_properties_with` at the
//!   fuzz target's loose tolerances and small budgets stays within its own
//!   bounds of the default result, with less work; bad tolerances refused.

use ccss_core::voxel::measure::{AREA_CELLS_MIN, AREA_CELLS_PER_PIECE, BUILD_ROUNDING};
use ccss_core::voxel::{mass_properties, MassProperties};
use ccss_core::Error;
use ccss_tests::harness::{standard_tables, with_evaluator, XorShift};
use ccss_tests::reference::PolyMesh;

fn cube(scale: f64, shift: [f64; 3]) -> PolyMesh {
    let mut positions = Vec::new();
    for k in 0..8 {
        let c = [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64];
        positions.push([
            (c[0] - 0.5) * scale + shift[0],
            (c[1] - 0.5) * scale + shift[1],
            (c[2] - 0.5) * scale + shift[2],
        ]);
    }
    // Outward counter-clockwise quads.
    let faces = vec![
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
    ];
    PolyMesh { positions, faces }
}

fn props(m: &PolyMesh) -> Result<MassProperties, Error> {
    with_evaluator(m, standard_tables(), |_, ev| mass_properties(ev))?
}

#[test]
fn build_rounding_constant() {
    let names = [
        "catmark_cube",
        "catmark_torus",
        "catmark_pyramid",
        "catmark_toroidal_tet",
        "catmark_helmet",
        "catmark_bishop",
        "catmark_car",
    ];
    let dir = ccss_tests::harness::workspace_root().join("tests/data/osd");
    let mut worst = 0.0f64;
    for name in names {
        let base = PolyMesh::from_obj(&dir.join(format!("{name}.obj")));
        if with_evaluator(&base, standard_tables(), |_, _| ()).is_err() {
            continue;
        }
        for t in [1e3, 1e6, 1e9, 1e12] {
            let shift = [t, -0.37 * t, 0.71 * t];
            let mut moved = base.clone();
            for p in &mut moved.positions {
                for a in 0..3 {
                    p[a] += shift[a];
                }
            }
            let mag = moved
                .positions
                .iter()
                .flat_map(|p| p.iter())
                .fold(0.0f64, |m, x| m.max(x.abs()));
            let pts: Vec<(u32, u32, f64, f64)> =
                with_evaluator(&base, standard_tables(), |_, ev| {
                    let mut r = XorShift(0x9e37_79b9_7f4a_7c15);
                    (0..400)
                        .map(|_| {
                            let f = (r.next_u64() % ev.num_faces() as u64) as u32;
                            let s = (r.next_u64() % ev.num_subfaces(f as usize) as u64) as u32;
                            (f, s, r.unit(), r.unit())
                        })
                        .collect()
                })
                .unwrap();
            let a: Vec<[f64; 3]> = with_evaluator(&base, standard_tables(), |_, ev| {
                pts.iter()
                    .map(|&(f, s, u, v)| ev.eval(f, s, u, v).unwrap().p.to_array())
                    .collect()
            })
            .unwrap();
            let b: Vec<[f64; 3]> = with_evaluator(&moved, standard_tables(), |_, ev| {
                pts.iter()
                    .map(|&(f, s, u, v)| ev.eval(f, s, u, v).unwrap().p.to_array())
                    .collect()
            })
            .unwrap();
            for (p, q) in a.iter().zip(&b) {
                for ax in 0..3 {
                    let d = (q[ax] - shift[ax] - p[ax]).abs() / (f64::EPSILON * mag);
                    worst = worst.max(d);
                }
            }
        }
    }
    println!("build rounding: worst |S(shifted) - S - t| = {worst:.2} eps M (allowance {BUILD_ROUNDING})");
    assert!(worst * 8.0 <= BUILD_ROUNDING, "worst {worst} eps M");
}

/// `BUILD_ROUNDING` on feature meshes (creases, corners, boundaries, holes,
/// semi-sharp and Chaikin creases, darts): the limit surface of the shape
/// shifted by up to 1e12 agrees with the unshifted one plus the shift
/// within a share of `BUILD_ROUNDING eps M`, at uniform points and at points
/// within 2^-4..2^-24 of a sub-face corner (where the feature evaluator
/// refines locally the deepest).
#[test]
fn build_rounding_constant_feature_meshes() {
    use ccss_tests::feature_input::{flat, with_feature_mesh};
    use ccss_tests::sharp::TaggedMesh;
    let names = [
        "catmark_cube_creases1",
        "catmark_cube_corner3",
        "catmark_torus_creases0",
        "catmark_chaikin1",
        "catmark_cubes_semisharp",
        "catmark_edgecorner",
        "catmark_edgeonly",
        "catmark_dart_edgecorner",
        "catmark_hole_test2",
        "catmark_xord_boundary",
        "catmark_pyramid_creases1",
        "catmark_fan",
    ];
    let dir = ccss_tests::harness::workspace_root().join("tests/data/osd");
    let mut worst = (0.0f64, String::new());
    let mut points = 0usize;
    for name in names {
        let base = TaggedMesh::from_obj(&dir.join(format!("{name}.obj"))).unwrap();
        let fb = flat(&base);
        // Points: uniform, and near a sub-face corner.
        let pts: Vec<(u32, u32, f64, f64)> =
            with_feature_mesh(&fb, Some(standard_tables()), |ev| {
                let mut r = XorShift(0x2545_f491_4f6c_dd1d);
                let mut out = Vec::new();
                for k in 0..300 {
                    let f = (r.next_u64() % ev.num_faces() as u64) as u32;
                    let s = (r.next_u64() % ev.num_subfaces(f as usize).max(1) as u64) as u32;
                    let (mut u, mut v) = (r.unit(), r.unit());
                    if k % 2 == 1 {
                        let e = -4 - (r.next_u64() % 21) as i32;
                        u *= 2f64.powi(e);
                        v *= 2f64.powi(e);
                        if r.next_u64() % 2 == 1 {
                            u = 1.0 - u;
                        }
                    }
                    if ev.eval(f, s, u, v).is_ok() {
                        out.push((f, s, u, v));
                    }
                }
                out
            })
            .unwrap();
        assert!(pts.len() > 100, "{name}: {} points", pts.len());
        let eval_all = |m: &TaggedMesh| -> Vec<[f64; 3]> {
            with_feature_mesh(&flat(m), Some(standard_tables()), |ev| {
                pts.iter()
                    .map(|&(f, s, u, v)| ev.eval(f, s, u, v).unwrap().p.to_array())
                    .collect()
            })
            .unwrap()
        };
        let a = eval_all(&base);
        for t in [1e3, 1e6, 1e9, 1e12] {
            let shift = [t, -0.37 * t, 0.71 * t];
            let mut moved = base.clone();
            for p in &mut moved.positions {
                for ax in 0..3 {
                    p[ax] += shift[ax];
                }
            }
            let mag = moved
                .positions
                .iter()
                .flat_map(|p| p.iter())
                .fold(0.0f64, |m, x| m.max(x.abs()));
            let b = eval_all(&moved);
            for (p, q) in a.iter().zip(&b) {
                for ax in 0..3 {
                    let d = (q[ax] - shift[ax] - p[ax]).abs() / (f64::EPSILON * mag);
                    if d > worst.0 {
                        worst = (d, name.to_string());
                    }
                }
            }
            points += a.len();
        }
    }
    println!(
        "feature build rounding: worst |S(shifted) - S - t| = {:.2} eps M ({}) over {points} points (allowance {BUILD_ROUNDING})",
        worst.0, worst.1
    );
    assert!(worst.0 * 8.0 <= BUILD_ROUNDING, "worst {worst:?} eps M");
}

/// `|x - y| <= b` up to the rounding of the comparison itself.
fn within(x: f64, y: f64, b: f64) -> bool {
    (x - y).abs() <= b * (1.0 + 1e-12) + 4.0 * f64::EPSILON * x.abs().max(y.abs())
}

#[test]
fn measure_translation_and_scale() {
    let p0 = props(&cube(1.0, [0.0; 3])).unwrap();
    assert!(p0.volume > 0.3 && p0.volume < 0.34, "{p0:?}");
    let mut worst_ratio = 0.0f64;
    for k in 0..=12 {
        let t = libm_pow10(k);
        let p = props(&cube(1.0, [t, -t, 0.5 * t])).unwrap();
        let (dv, da) = ((p.volume - p0.volume).abs(), (p.area - p0.area).abs());
        let (bv, ba) = (
            p.volume_error_bound + p0.volume_error_bound,
            p.area_error_bound + p0.area_error_bound,
        );
        println!(
            "shift 1e{k}: volume error {dv:.2e} (bound {bv:.2e}), area error {da:.2e} (bound {ba:.2e})"
        );
        assert!(within(p.volume, p0.volume, bv), "shift 1e{k}: {p:?}");
        assert!(within(p.area, p0.area, ba), "shift 1e{k}: {p:?}");
        assert!((p.centroid[0] - t).abs() <= p.centroid_error_bound + p0.centroid_error_bound);
        worst_ratio = worst_ratio.max(dv / bv).max(da / ba);
    }
    // Powers of two scale exactly: the same digits, bounds scaled.
    for e in [-190, -100, -10, 10, 100, 190] {
        let s = 2f64.powi(e);
        let p = props(&cube(s, [0.0; 3])).unwrap();
        assert_eq!(p.volume, p0.volume * s * s * s, "2^{e}");
        assert_eq!(p.area, p0.area * s * s, "2^{e}");
    }
    // Powers of ten: within the bounds.
    for k in [-60, -30, -5, 5, 30, 60] {
        let s = libm_pow10(k);
        let p = props(&cube(s, [0.0; 3])).unwrap();
        let (v0, a0) = (p0.volume * s * s * s, p0.area * s * s);
        let bv = p.volume_error_bound + p0.volume_error_bound * s * s * s;
        let ba = p.area_error_bound + p0.area_error_bound * s * s;
        assert!(within(p.volume, v0, bv), "1e{k}: {p:?}");
        assert!(within(p.area, a0, ba), "1e{k}: {p:?}");
        assert!(p.volume.is_finite() && p.inertia.iter().all(|x| x.is_finite()));
    }
    // Out of range: refused, never NaN/inf or zero.
    for k in [-300, -200, -70, 70, 150, 200, 250] {
        let r = props(&cube(libm_pow10(k), [0.0; 3]));
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "1e{k}: {r:?}");
    }
    // A tiny model far out: refused, not an infinite bound.
    let r = props(&cube(1e-6, [1e12, 0.0, 0.0]));
    assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
    let mut big = cube(1.0, [0.0; 3]);
    big.positions[7] = [1e308, 0.5, 0.5];
    let r = props(&big);
    assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
    println!("worst error / bound over the shifts: {worst_ratio:.2e}");
}

fn libm_pow10(k: i32) -> f64 {
    format!("1e{k}").parse().unwrap()
}

#[test]
fn measure_needle_is_bounded() {
    let m = needle();
    let t0 = std::time::Instant::now();
    let p = props(&m).unwrap();
    println!("needle: {:.2} s, {p:?}", t0.elapsed().as_secs_f64());
    assert!(p.volume.is_finite() && p.area.is_finite() && p.area_error_bound.is_finite());
    assert!(p.area_cells <= AREA_CELLS_MIN + AREA_CELLS_PER_PIECE * p.pieces + 5 * p.pieces + 4);
}

/// The certification walk's cells per first-walk leaf on closed corpus
/// shapes (the cap is `CERTIFY_CELLS_MIN + CERTIFY_CELLS_PER_LEAF * leaves`),
/// and the needle refused within the cap.
#[test]
fn voxel_certification_is_capped() {
    use ccss_core::voxel::rasterize::{
        CERTIFY_CELLS_MIN, CERTIFY_CELLS_PER_LEAF, CERTIFY_SUBTREE_CELLS, FIRST_CELLS_PER_ROOT,
        FIRST_CELLS_PER_VOXEL,
    };
    use ccss_core::voxel::{Adjacency, VoxelGrid, VoxelParams, VoxelWork};
    let mut worst = (0.0f64, String::new());
    // First walk: cells against the cap's size-dependent part (the cap
    // adds FIRST_CELLS_MIN on top).
    let mut worst_first = (0.0f64, String::new());
    let mut shapes = 0;
    let mut max_sub = 0u64;
    for path in ccss_tests::harness::corpus_shapes() {
        let m = PolyMesh::from_obj(&path);
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let r = with_evaluator(&m, standard_tables(), |_, ev| {
            let mut out = Vec::new();
            for adj in [Adjacency::Six, Adjacency::TwentySix] {
                for res in [24u32, 64] {
                    let params = VoxelParams::new([res; 3], adj);
                    let mut gmem = vec![
                        0u64;
                        ccss_core::mem::words_for(
                            VoxelGrid::required_bytes(params.res).unwrap()
                        )
                    ];
                    let mut grid = VoxelGrid::new(params.res, &mut gmem).unwrap();
                    let mut work = Box::new(VoxelWork::ZERO);
                    let st = grid.voxelize(ev, &params, None, &mut work).unwrap();
                    let (nr, ne) = ev.patch_counts();
                    let roots = (nr + ne) as u64 * (params.presplit as u64).pow(2);
                    let voxels = (res as u64).pow(3);
                    let first = st.cells as f64
                        / (FIRST_CELLS_PER_ROOT * roots + FIRST_CELLS_PER_VOXEL * voxels) as f64;
                    out.push((
                        st.refined as f64 / st.leaves.max(1) as f64,
                        st.max_subtree,
                        first,
                    ));
                }
            }
            out
        });
        let Ok(r) = r else { continue };
        shapes += 1;
        for (ratio, sub, first) in r {
            if ratio > worst.0 {
                worst = (ratio, name.clone());
            }
            if first > worst_first.0 {
                worst_first = (first, name.clone());
            }
            max_sub = max_sub.max(sub);
        }
    }
    println!("certification: worst {:.3} cells per leaf ({}) over {shapes} shapes; cap {CERTIFY_CELLS_PER_LEAF} per leaf + {CERTIFY_CELLS_MIN}", worst.0, worst.1);
    println!("largest certification subtree: {max_sub} cells (cap {CERTIFY_SUBTREE_CELLS})");
    assert!(shapes > 20);
    assert!(worst.0 * 4.0 <= CERTIFY_CELLS_PER_LEAF as f64);
    println!(
        "first walk: worst {:.4} of the cap's size-dependent part ({})",
        worst_first.0, worst_first.1
    );
    assert!(max_sub * 8 <= CERTIFY_SUBTREE_CELLS);
    assert!(worst_first.0 * 4.0 <= 1.0);
    // The needle along the voxel diagonal: refused, quickly.
    let m = needle();
    with_evaluator(&m, standard_tables(), |_, ev| {
        for res in [64u32, 256] {
            let params = VoxelParams::new([res; 3], Adjacency::Six);
            let mut gmem =
                vec![
                    0u64;
                    ccss_core::mem::words_for(VoxelGrid::required_bytes(params.res).unwrap())
                ];
            let mut grid = VoxelGrid::new(params.res, &mut gmem).unwrap();
            let mut work = Box::new(VoxelWork::ZERO);
            let t0 = std::time::Instant::now();
            let r = grid.voxelize(ev, &params, None, &mut work);
            println!(
                "needle res {res}: {r:?} in {:.2} s",
                t0.elapsed().as_secs_f64()
            );
            assert!(matches!(r, Err(Error::WorkLimitExceeded { .. })), "{r:?}");
        }
    })
    .unwrap();
}

/// Fuzz finding (voxel target, session 7): a cube with one control point
/// at z = 1.251e303 beside an ordinary cube. Subdividing near that point
/// overflowed to NaN in the box search of `voxel::limit_bounds`, which
/// `f64::min`/`max` dropped, so the box held only the ordinary cube; the
/// first walk then split the other cube's cells (about 10^303 voxels
/// tall) to depth 48 everywhere and never ended. Now the box refuses the
/// non-finite candidate (`CoordinateRange`), and the first walk has a
/// work cap as well. Without the fix this test does not end.
#[test]
fn overflowing_box_search_is_refused_not_a_hang() {
    use ccss_core::voxel::{limit_bounds, Adjacency, VoxelGrid, VoxelParams, VoxelWork};
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for (dx, far) in [(-1.5, true), (0.0, false)] {
        let b = positions.len();
        for &(x, y, z) in &[
            (1.25, -0.5, 1.25),
            (1.25, 0.5, 1.25),
            (0.25, -0.5, 1.25),
            (0.25, 0.5, 1.25),
            (0.25, -0.5, 0.25),
            (0.25, 0.5, 0.25),
            (1.25, -0.5, 0.25),
            (1.25, 0.5, 0.25),
        ] {
            positions.push([x + dx, y, z]);
        }
        if far {
            positions[b][2] = 1.251e303;
        }
        for f in [
            [0, 1, 3, 2],
            [2, 3, 5, 4],
            [4, 5, 7, 6],
            [6, 7, 1, 0],
            [1, 7, 5, 3],
            [6, 0, 2, 4],
        ] {
            faces.push(f.iter().map(|&i| (b + i) as u32).collect());
        }
    }
    let m = PolyMesh { positions, faces };
    with_evaluator(&m, standard_tables(), |_, ev| {
        let mut work = Box::new(VoxelWork::ZERO);
        let r = limit_bounds(ev, &mut work);
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
        let params = VoxelParams::new([7; 3], Adjacency::Eighteen);
        let mut gmem =
            vec![0u64; ccss_core::mem::words_for(VoxelGrid::required_bytes(params.res).unwrap())];
        let mut grid = VoxelGrid::new(params.res, &mut gmem).unwrap();
        let r = grid.voxelize(ev, &params, None, &mut work);
        assert!(matches!(r, Err(Error::CoordinateRange(_))), "{r:?}");
    })
    .unwrap();
}

fn needle() -> PolyMesh {
    PolyMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [65536.0, 65536.0, 65536.0],
        ],
        faces: vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]],
    }
}

/// `mass_properties_with` at loose tolerances and small area budgets (the
/// fuzz target's range, `fuzz/fuzz_targets/measure.rs`) against the default
/// accuracy on closed corpus shapes: the cheap volume and area are within
/// their own stated bounds (plus the default's) of the default's, with less
/// work (or a `CoordinateRange` refusal when the loose volume bound leaves
/// the centroid unbounded); tolerances that are not finite and positive are
/// refused.
#[test]
fn measure_options_trade_work_for_bounds() {
    use ccss_core::voxel::{mass_properties_with, MeasureOptions};
    let dir = ccss_tests::harness::workspace_root().join("tests/data/osd");
    let cheap = [
        (1e-1, 1e-1, 0, 0),
        (1e-1, 1e-2, 0, 0),
        (1e-4, 1e-4, 16, 1),
        (1e-8, 1e-6, 63, 3),
    ];
    let mut checked = 0;
    for name in [
        "catmark_cube",
        "catmark_torus",
        "catmark_pyramid",
        "catmark_toroidal_tet",
        "catmark_tet",
        "catmark_cube_creases0",
        "catmark_cube_corner2",
    ] {
        let path = dir.join(format!("{name}.obj"));
        if !path.exists() {
            continue;
        }
        let m = PolyMesh::from_obj(&path);
        let r = with_evaluator(&m, standard_tables(), |_, ev| {
            let full = mass_properties(ev).unwrap();
            let mut rows = Vec::new();
            for &(at, ct, min, per) in &cheap {
                let o = MeasureOptions {
                    area_rel_tol: at,
                    corner_rel_tol: ct,
                    area_cells_min: min,
                    area_cells_per_piece: per,
                };
                match mass_properties_with(ev, &o) {
                    Ok(p) => rows.push((o, p)),
                    // A volume bound as large as the volume leaves the
                    // centroid bound unbounded: refused, not a number.
                    Err(Error::CoordinateRange(why)) => println!("{name} {o:?}: refused ({why})"),
                    Err(e) => panic!("{name} {o:?}: {e:?}"),
                }
            }
            for bad in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
                for which in 0..2 {
                    let mut o = MeasureOptions::default();
                    if which == 0 {
                        o.area_rel_tol = bad;
                    } else {
                        o.corner_rel_tol = bad;
                    }
                    assert!(matches!(
                        mass_properties_with(ev, &o),
                        Err(Error::InvalidArgument(_))
                    ));
                }
            }
            (full, rows)
        });
        let Ok((full, rows)) = r else { continue };
        assert!(!rows.is_empty(), "{name}: every option set refused");
        for (o, p) in rows {
            let dv = (p.volume - full.volume).abs();
            let da = (p.area - full.area).abs();
            println!(
                "{name} {o:?}: volume off {dv:.2e} (bound {:.2e}), area off {da:.2e} \
                 (bound {:.2e}), cells {} vs {}, corner level {} vs {}",
                p.volume_error_bound,
                p.area_error_bound,
                p.area_cells,
                full.area_cells,
                p.max_corner_level,
                full.max_corner_level
            );
            assert!(
                dv <= p.volume_error_bound + full.volume_error_bound,
                "{name} {o:?}"
            );
            assert!(
                da <= p.area_error_bound + full.area_error_bound,
                "{name} {o:?}"
            );
            assert!(p.area_cells <= full.area_cells && p.max_corner_level <= full.max_corner_level);
            assert!(p.area_cells <= o.area_cells_min + (o.area_cells_per_piece + 5) * p.pieces + 4);
        }
        checked += 1;
    }
    assert!(checked >= 5, "{checked} shapes");
}
