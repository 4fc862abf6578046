//! Voxel runs: the runs reproduce the grid, the size error reports the
//! required count, and slab mode (memory for a z-slab only) produces exactly
//! the runs of the whole grid.

use ccss_core::voxel::{
    Adjacency, VoxelClass, VoxelGrid, VoxelParams, VoxelRun, VoxelWork, SLAB_MARGIN,
};
use ccss_core::{Error, Evaluator};
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use ccss_tests::reference::PolyMesh;
use ccss_tests::shapes::cavity;
use std::path::Path;

fn full_runs(
    ev: &Evaluator,
    params: &VoxelParams,
) -> (Vec<VoxelRun>, ccss_core::voxel::VoxelTransform) {
    let mut mem = aligned(VoxelGrid::required_bytes(params.res).unwrap());
    let mut grid = VoxelGrid::new(params.res, &mut mem).unwrap();
    let mut work = Box::new(VoxelWork::ZERO);
    grid.voxelize(ev, params, None, &mut work).unwrap();
    grid.flood(ev, &mut [0u32; 256], &mut work).unwrap();
    let n = grid.run_count();
    // Too small: the error names the count and nothing is written.
    let mut small = vec![VoxelRun::default(); n - 1];
    assert_eq!(
        grid.write_runs(&mut small),
        Err(Error::BufferTooSmall { required: n })
    );
    assert!(small.iter().all(|r| *r == VoxelRun::default()));
    let mut runs = vec![VoxelRun::default(); n];
    assert_eq!(grid.write_runs(&mut runs), Ok(n));
    // The runs reproduce the grid.
    let [m1, m2, m3] = params.res;
    let mut cls = vec![0u32; (m1 * m2 * m3) as usize];
    for r in &runs {
        assert!(r.x0 < r.x1 && r.x1 <= m1 && (r.class == 1 || r.class == 2));
        for x in r.x0..r.x1 {
            cls[(x + m1 * (r.y + m2 * r.z)) as usize] = r.class;
        }
    }
    for k in 0..m3 {
        for j in 0..m2 {
            for i in 0..m1 {
                let want = match grid.class(i, j, k) {
                    VoxelClass::Outside => 0,
                    VoxelClass::Surface => 1,
                    VoxelClass::Interior => 2,
                };
                assert_eq!(cls[(i + m1 * (j + m2 * k)) as usize], want);
            }
        }
    }
    (runs, grid.transform())
}

#[test]
fn slab_runs_equal_full_grid_runs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/osd");
    let meshes = [
        (
            "catmark_torus",
            PolyMesh::from_obj(&dir.join("catmark_torus.obj")),
        ),
        (
            "catmark_toroidal_tet",
            PolyMesh::from_obj(&dir.join("catmark_toroidal_tet.obj")),
        ),
        ("cavity", cavity()),
    ];
    for (name, m) in meshes {
        with_evaluator(&m, standard_tables(), |_, ev| {
            for adj in [Adjacency::Six, Adjacency::TwentySix] {
                let params = VoxelParams::new([37, 30, 33], adj);
                let (full, t) = full_runs(ev, &params);
                let m3 = params.res[2];
                for cuts in [
                    vec![0, 1, 2, 9, 16, 17, 33],
                    vec![0, 11, 22, 33],
                    vec![0, 33],
                ] {
                    let mut slab_runs = vec![];
                    let mut work = Box::new(VoxelWork::ZERO);
                    for w in cuts.windows(2) {
                        let (z0, z1) = (w[0], w[1]);
                        let need = VoxelGrid::slab_required_bytes(params.res, z0, z1).unwrap();
                        if z1 - z0 + 2 * SLAB_MARGIN < m3 {
                            assert!(need < VoxelGrid::required_bytes(params.res).unwrap());
                        }
                        let mut mem = aligned(need);
                        let mut g = VoxelGrid::new_slab(params.res, z0, z1, &mut mem).unwrap();
                        g.voxelize(ev, &params, Some(t), &mut work).unwrap();
                        g.flood(ev, &mut [0u32; 3], &mut work).unwrap();
                        let mut r = vec![VoxelRun::default(); g.run_count()];
                        g.write_runs(&mut r).unwrap();
                        assert!(r.iter().all(|r| r.z >= z0 && r.z < z1));
                        slab_runs.extend(r);
                    }
                    assert_eq!(
                        slab_runs.len(),
                        full.len(),
                        "{name} N={} cuts={cuts:?}",
                        adj.n()
                    );
                    assert!(slab_runs == full, "{name} N={} cuts={cuts:?}", adj.n());
                }
                println!("{name} N={} runs={} slab runs equal", adj.n(), full.len());
            }
        })
        .unwrap();
    }
}
