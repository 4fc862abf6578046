//! The cell geometry of `FeatureEvaluator::cell` against exact evaluation at
//! random points of random cells of every corpus shape: a `Poly` cell's
//! B-spline equals the surface over the cell (positions to 1e-12 of the
//! diagonal), and a `Hull` cell's box and ball contain every sampled
//! surface point of the cell (zero violations beyond 1e-12 of the diagonal,
//! with the tightness reported: largest sampled distance / radius).
use ccss_core::eval::CellCursor;
use ccss_core::math::bspline::eval_points;
use ccss_core::{CellGeom, Error};
use ccss_tests::feature_input::{flat, with_feature_mesh};
use ccss_tests::harness::{corpus_shapes, standard_tables, XorShift};
use ccss_tests::sharp::{SharpRefiner, TaggedMesh};

#[test]
fn cells_contain_the_surface_on_the_corpus() {
    let mut rng = XorShift(0x5eed_ce11);
    let (mut polys, mut hulls, mut splits, mut samples) = (0usize, 0usize, 0usize, 0usize);
    let mut worst_poly = 0.0f64;
    let mut tight = 0.0f64;
    let mut shapes = 0;
    for path in corpus_shapes() {
        let m = TaggedMesh::from_obj(&path).unwrap();
        if SharpRefiner::new(&m).is_err() {
            continue; // faces repeating a vertex: refused by both
        }
        let diag = m.bbox_diagonal();
        let tol = 1e-12 * diag;
        let f = flat(&m);
        let nf = m.faces.len();
        let stride = nf.div_ceil(40).max(1);
        let r = with_feature_mesh(&f, Some(standard_tables()), |ev| {
            for face in (0..nf).step_by(stride) {
                let subs = if m.faces[face].len() == 4 {
                    1
                } else {
                    m.faces[face].len()
                };
                for sub in 0..subs {
                    for level in 0..7u32 {
                        let n = 1u32 << level;
                        // A corner cell (next to the sub-face's corners,
                        // where irregular vertices sit) and a random one.
                        let corner = rng.next_u64() as usize % 4;
                        let (ci, cj) = [(0, 0), (n - 1, 0), (n - 1, n - 1), (0, n - 1)][corner];
                        let (ri, rj) = (rng.next_u64() as u32 % n, rng.next_u64() as u32 % n);
                        for (i, j) in [(ci, cj), (ri, rj)] {
                            let cell = match ev.cell(face as u32, sub as u32, level, i, j) {
                                Ok(c) => c,
                                Err(Error::HoleFace { .. }) => continue,
                                Err(e) => panic!("{}: face {face}: {e}", path.display()),
                            };
                            let h = 1.0 / n as f64;
                            for s in 0..12 {
                                // Corners first, then random points.
                                let (a, b) = if s < 4 {
                                    [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][s]
                                } else {
                                    (rng.unit(), rng.unit())
                                };
                                let (u, v) = ((i as f64 + a) * h, (j as f64 + b) * h);
                                let p = ev.eval(face as u32, sub as u32, u, v).unwrap().p;
                                samples += 1;
                                match &cell {
                                    CellGeom::Split => {}
                                    CellGeom::Poly { grid, rect } => {
                                        let s = rect[0] + a * (rect[1] - rect[0]);
                                        let t = rect[2] + b * (rect[3] - rect[2]);
                                        let q = eval_points::<false>(grid, s, t).p;
                                        worst_poly = worst_poly.max(p.distance(q) / diag);
                                        assert!(
                                            p.distance(q) <= tol,
                                            "{}: face {face} sub {sub} cell {level}/{i}/{j}: B-spline {q} vs eval {p}",
                                            path.display()
                                        );
                                    }
                                    CellGeom::Hull(hb) => {
                                        let inside =
                                            (p.cmpge(hb.lo - tol) & p.cmple(hb.hi + tol)).all();
                                        let d = p.distance(hb.centre());
                                        assert!(
                                            inside && d <= hb.radius + tol,
                                            "{}: face {face} sub {sub} cell {level}/{i}/{j}: {p} outside its hull {hb:?}",
                                            path.display()
                                        );
                                        if hb.radius > 0.0 {
                                            tight = tight.max(d / hb.radius);
                                        }
                                    }
                                }
                            }
                            match cell {
                                CellGeom::Split => splits += 1,
                                CellGeom::Poly { .. } => polys += 1,
                                CellGeom::Hull(_) => hulls += 1,
                            }
                        }
                    }
                }
            }
        });
        if r.is_ok() {
            shapes += 1;
        }
    }
    println!(
        "{shapes} shapes: {polys} polynomial, {hulls} hull, {splits} split cells; \
         {samples} samples; worst B-spline deviation {worst_poly:.2e} of the diagonal; \
         largest sampled distance / hull radius {tight:.3}"
    );
    assert!(shapes >= 80, "only {shapes} shapes built");
    assert!(polys > 1000 && hulls > 100 && splits > 50);
}

/// `FeatureEvaluator::cell_in` (local patches carried down the quadtree
/// in a `CellCursor`) returns exactly what `cell` returns (bit for bit),
/// and so does `cell_children` for the four children of a cell:
/// on every corpus shape, depth-first walks of the hull and split cells
/// down to level 18 (children in random order; deeper than the cursor's
/// stored path), interleaved with random
/// cells of random sub-faces and levels (so the cursor's path breaks off at
/// every depth and switches faces), one cursor per shape.
#[test]
fn cursor_cells_equal_cells_on_the_corpus() {
    let mut rng = XorShift(0x00c0_ffee_5eed);
    let (mut calls, mut hulls, mut shapes, mut children) = (0usize, 0usize, 0usize, 0usize);
    for path in corpus_shapes() {
        let m = TaggedMesh::from_obj(&path).unwrap();
        if SharpRefiner::new(&m).is_err() {
            continue;
        }
        let f = flat(&m);
        let nf = m.faces.len();
        let stride = nf.div_ceil(6).max(1);
        let subs = |face: usize| {
            if m.faces[face].len() == 4 {
                1
            } else {
                m.faces[face].len()
            }
        };
        let r = with_feature_mesh(&f, Some(standard_tables()), |ev| {
            let mut cursor = Box::new(CellCursor::new());
            let mut check = |face: usize, sub: usize, l: u32, i: u32, j: u32| {
                let a = ev.cell(face as u32, sub as u32, l, i, j);
                let b = ev.cell_in(&mut cursor, face as u32, sub as u32, l, i, j);
                assert_eq!(
                    a,
                    b,
                    "{}: face {face} sub {sub} cell {l}/{i}/{j}",
                    path.display()
                );
                calls += 1;
                a
            };
            for face in (0..nf).step_by(stride) {
                for sub in 0..subs(face) {
                    let mut stack = vec![(0u32, 0u32, 0u32)];
                    while let Some((l, i, j)) = stack.pop() {
                        let g = check(face, sub, l, i, j);
                        // All four children at once, as `cell` gives each
                        // (a quarter of the cells: `cell` descends fully
                        // for each child).
                        if rng.next_u64().is_multiple_of(4) {
                            let kids = ev.cell_children(face as u32, sub as u32, l, i, j);
                            let want: Result<Vec<_>, _> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                                .iter()
                                .map(|&(di, dj)| {
                                    ev.cell(face as u32, sub as u32, l + 1, 2 * i + di, 2 * j + dj)
                                })
                                .collect();
                            assert_eq!(
                                kids.map(|k| k.to_vec()),
                                want,
                                "{}: children of face {face} sub {sub} cell {l}/{i}/{j}",
                                path.display()
                            );
                            children += 1;
                        }
                        if matches!(g, Ok(CellGeom::Hull(_))) {
                            hulls += 1;
                        }
                        if matches!(g, Ok(CellGeom::Hull(_) | CellGeom::Split)) && l < 18 {
                            let mut kids = [(0, 0), (1, 0), (1, 1), (0, 1)];
                            let r = rng.next_u64() as usize % 4;
                            kids.rotate_left(r);
                            for (di, dj) in kids {
                                stack.push((l + 1, 2 * i + di, 2 * j + dj));
                            }
                        }
                        if rng.next_u64().is_multiple_of(8) {
                            let f2 = rng.next_u64() as usize % nf;
                            let s2 = rng.next_u64() as usize % subs(f2);
                            let l2 = rng.next_u64() as u32 % 20;
                            let n = 1u64 << l2;
                            let i2 = (rng.next_u64() % n) as u32;
                            let j2 = (rng.next_u64() % n) as u32;
                            let _ = check(f2, s2, l2, i2, j2);
                        }
                    }
                }
            }
        });
        if r.is_ok() {
            shapes += 1;
        }
    }
    println!(
        "{shapes} shapes: {calls} cells compared, {hulls} hull cells on the walks, \
         {children} cells' children compared"
    );
    assert!(shapes >= 80 && hulls > 1000);
    println!("CellCursor: {} bytes", CellCursor::BYTES);
}

#[test]
fn cell_arguments_are_checked() {
    let m = TaggedMesh::from_obj(
        &ccss_tests::harness::workspace_root().join("tests/data/osd/catmark_cube_creases0.obj"),
    )
    .unwrap();
    let f = flat(&m);
    with_feature_mesh(&f, None, |ev| {
        assert_eq!(
            ev.cell(99, 0, 1, 0, 0),
            Err(Error::FaceOutOfRange { face: 99 })
        );
        assert_eq!(
            ev.cell(0, 1, 1, 0, 0),
            Err(Error::SubFaceOutOfRange { face: 0, sub: 1 })
        );
        assert!(matches!(
            ev.cell(0, 0, 2, 4, 0),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            ev.cell(0, 0, 31, 0, 0),
            Err(Error::InvalidArgument(_))
        ));
        assert_eq!(ev.cell(0, 0, 0, 0, 0), Ok(CellGeom::Split));
    })
    .unwrap();
}
