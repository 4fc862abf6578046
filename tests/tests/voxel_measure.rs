//! Integral properties: the exact (quadrature) volume, area, centroid and
//! inertia against closed triangle meshes of exact limit points at two
//! refinement levels (the exact value must be closer to the finer one than
//! the two are to each other), and the voxel volume converging to the exact
//! one as the resolution grows (the table is printed).

use ccss_core::voxel::{mass_properties, Adjacency, VoxelGrid, VoxelParams, VoxelWork};
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use ccss_tests::reference::PolyMesh;
use ccss_tests::shapes::{cavity, pretzel, RefSurface};
use std::path::Path;

/// Volume, area, centroid and inertia [Ixx, Iyy, Izz] (about the centroid)
/// of a closed triangle mesh.
fn poly_props(tris: &[[[f64; 3]; 3]]) -> (f64, f64, [f64; 3], [f64; 3]) {
    let (mut v, mut a) = (0.0, 0.0);
    let mut m = [0.0; 3];
    let mut s = [0.0; 3];
    for t in tris {
        let [p, q, r] = *t;
        let cross = [
            q[1] * r[2] - q[2] * r[1],
            q[2] * r[0] - q[0] * r[2],
            q[0] * r[1] - q[1] * r[0],
        ];
        let vt = (p[0] * cross[0] + p[1] * cross[1] + p[2] * cross[2]) / 6.0;
        v += vt;
        let e1 = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let e2 = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
        let c = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        a += 0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        for k in 0..3 {
            m[k] += vt * (p[k] + q[k] + r[k]) / 4.0;
            let (x, y, z) = (p[k], q[k], r[k]);
            s[k] += vt / 10.0 * (x * x + y * y + z * z + x * y + x * z + y * z);
        }
    }
    let c = [m[0] / v, m[1] / v, m[2] / v];
    let sc = [
        s[0] - v * c[0] * c[0],
        s[1] - v * c[1] * c[1],
        s[2] - v * c[2] * c[2],
    ];
    (v, a, c, [sc[1] + sc[2], sc[0] + sc[2], sc[0] + sc[1]])
}

fn meshes() -> Vec<(String, PolyMesh)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    let mut v: Vec<(String, PolyMesh)> = [
        "catmark_torus",
        "catmark_cube",
        "catmark_pyramid",
        "catmark_toroidal_tet",
    ]
    .iter()
    .map(|n| {
        (
            n.to_string(),
            PolyMesh::from_obj(&dir.join(format!("{n}.obj"))),
        )
    })
    .collect();
    v.push(("pretzel3".into(), pretzel(3)));
    v.push(("cavity".into(), cavity()));
    v
}

#[test]
fn exact_properties_agree_with_fine_tessellations() {
    for (name, m) in meshes() {
        let t3 = poly_props(&RefSurface::new(&m, 2).tris);
        let t4 = poly_props(&RefSurface::new(&m, 3).tris);
        with_evaluator(&m, standard_tables(), |_, ev| {
            let p = mass_properties(ev).unwrap();
            println!(
                "{name}: volume={:.12} (tess3 {:.12}, tess2 {:.12}) area={:.12} (tess3 {:.12}, tess2 {:.12}) \
                 error_bound={:.1e} area_error_bound={:.1e} max_corner_level={}",
                p.volume, t4.0, t3.0, p.area, t4.1, t3.1, p.volume_error_bound, p.area_error_bound,
                p.max_corner_level
            );
            assert!(p.rigorous);
            assert!(p.volume_error_bound < 1e-10 && p.area_error_bound < 1e-9);
            // Inscribed meshes converge to the exact values from one side at
            // O(h^2): the exact value is beyond the finer mesh, within the
            // step between the two meshes.
            let within = |e: f64, f: f64, c: f64| (e - f).abs() <= (f - c).abs() && (e - f) * (f - c) >= 0.0;
            assert!(within(p.volume, t4.0, t3.0), "{name} volume");
            assert!(within(p.area, t4.1, t3.1), "{name} area");
            let size = (t4.0.abs()).cbrt();
            for k in 0..3 {
                let step = (t4.2[k] - t3.2[k]).abs().max(1e-12 * size);
                assert!((p.centroid[k] - t4.2[k]).abs() <= 2.0 * step, "{name} centroid {k}");
                let istep = (t4.3[k] - t3.3[k]).abs().max(1e-12);
                assert!((p.inertia[k] - t4.3[k]).abs() <= 2.0 * istep, "{name} inertia {k}");
            }
        })
        .unwrap();
    }
}

#[test]
fn voxel_volume_converges_to_the_exact_volume() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    for name in ["catmark_torus", "catmark_cube"] {
        let m = PolyMesh::from_obj(&dir.join(format!("{name}.obj")));
        with_evaluator(&m, standard_tables(), |_, ev| {
            let exact = mass_properties(ev).unwrap();
            let mut prev = f64::INFINITY;
            println!("{name}: exact volume {:.6} area {:.6}", exact.volume, exact.area);
            println!("res  N   surface  interior  voxel_volume  rel_err  midpoint_rel_err  quad_area_rel_err");
            for res in [16u32, 32, 64] {
                let params = VoxelParams::new([res; 3], Adjacency::Six);
                let mut mem = aligned(VoxelGrid::required_bytes(params.res).unwrap());
                let mut g = VoxelGrid::new(params.res, &mut mem).unwrap();
                let mut work = Box::new(VoxelWork::ZERO);
                let st = g.voxelize(ev, &params, None, &mut work).unwrap();
                g.flood(ev, &mut vec![0u32; 4096], &mut work).unwrap();
                let c = g.counts();
                let cell = g.transform().voxel_size().powi(3);
                let vol = (c.surface + c.interior) as f64 * cell;
                let mid = (c.surface as f64 * 0.5 + c.interior as f64) * cell;
                let err = (vol - exact.volume).abs() / exact.volume;
                println!(
                    "{res:4} 6 {:9} {:9} {vol:12.6} {err:8.4} {:8.5} {:10.2e}",
                    c.surface,
                    c.interior,
                    (mid - exact.volume).abs() / exact.volume,
                    (st.quad_area - exact.area).abs() / exact.area
                );
                assert!(err < prev, "{name}: voxel volume error must shrink");
                assert!(vol >= exact.volume, "{name}: surface + interior covers the solid");
                prev = err;
            }
            assert!(prev < 0.2);
        })
        .unwrap();
    }
}
