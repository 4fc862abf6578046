//! Bad input gets a precise error (which face / vertex / edge), never a
//! panic; size queries are exact (the build succeeds with exactly the
//! reported size and fails one word short, reporting the same size).
use ccss_core::{Error, Evaluator, MeshInput, Topology, MAX_VALENCE};
use ccss_tests::harness::{aligned, flatten, standard_tables, validate, with_evaluator};
use ccss_tests::reference::{drum, pole_mesh, PolyMesh};
use std::path::Path;

fn corpus(name: &str) -> PolyMesh {
    PolyMesh::from_obj(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/osd")
            .join(name),
    )
}

fn cube() -> PolyMesh {
    corpus("catmark_cube.obj")
}

fn build_raw(p: &[f64], s: &[u32], i: &[u32]) -> Result<(), Error> {
    let mut mem = aligned(Topology::required_bytes(p.len() / 3, s).max(8));
    Topology::build(
        MeshInput {
            positions: p,
            face_sizes: s,
            indices: i,
        },
        &mut mem,
    )
    .map(|_| ())
}

#[test]
fn each_error_names_its_place() {
    let c = cube();
    let (p, s, i) = flatten(&c);
    assert_eq!(build_raw(&[], &[], &[]), Err(Error::EmptyMesh));
    assert_eq!(
        build_raw(&p, &s, &i[..i.len() - 1]),
        Err(Error::IndexCountMismatch {
            expected: 24,
            got: 23
        })
    );
    let mut bad = i.clone();
    bad[5] = 99;
    assert_eq!(
        build_raw(&p, &s, &bad),
        Err(Error::IndexOutOfRange {
            face: 1,
            vertex: 99
        })
    );
    let mut bad = i.clone();
    bad[6] = bad[5];
    assert_eq!(
        build_raw(&p, &s, &bad),
        Err(Error::RepeatedVertex {
            face: 1,
            vertex: bad[5]
        })
    );
    let mut sz = s.clone();
    sz[0] = 2;
    sz[1] = 6;
    assert_eq!(
        build_raw(&p, &sz, &i),
        Err(Error::FaceTooSmall { face: 0, size: 2 })
    );
    let big: Vec<u32> = (0..(MAX_VALENCE as u32 + 1)).collect();
    let pts = vec![0.0; 3 * big.len()];
    assert_eq!(
        build_raw(&pts, &[big.len() as u32], &big),
        Err(Error::FaceTooLarge {
            face: 0,
            size: MAX_VALENCE as u32 + 1
        })
    );
    let mut pn = p.clone();
    pn[3 * 5 + 1] = f64::NAN;
    assert_eq!(
        build_raw(&pn, &s, &i),
        Err(Error::NonFiniteCoordinate { vertex: 5 })
    );
    pn[3 * 5 + 1] = f64::INFINITY;
    assert_eq!(
        build_raw(&pn, &s, &i),
        Err(Error::NonFiniteCoordinate { vertex: 5 })
    );
    // Flip one face: its edges now run the same way as the neighbours'.
    let mut flipped = c.clone();
    flipped.faces[2].reverse();
    match validate(&flipped) {
        Err(Error::InconsistentOrientation { v0, v1 }) => {
            let f = &flipped.faces[2];
            assert!(f.contains(&v0) && f.contains(&v1));
        }
        other => panic!("expected orientation error, got {other:?}"),
    }
    // Open mesh: drop a face.
    let mut open = c.clone();
    open.faces.pop();
    assert!(matches!(validate(&open), Err(Error::BoundaryEdge { .. })));
    let msg = validate(&open).unwrap_err().to_string();
    assert!(
        msg.contains("boundaries") && msg.contains("not supported yet"),
        "{msg}"
    );
    // Corpus: open, non-manifold and valence-2 shapes.
    assert!(matches!(
        validate(&corpus("catmark_edgeonly.obj")),
        Err(Error::BoundaryEdge { .. })
    ));
    assert!(matches!(
        validate(&corpus("catmark_tent.obj")),
        Err(Error::BoundaryEdge { .. })
    ));
    let r = validate(&corpus("catmark_nonman_edges.obj"));
    assert!(
        // (the loader merges coincident vertices of its separate groups, which
        // makes one face degenerate; any of these names the first problem)
        matches!(
            r,
            Err(Error::NonManifoldEdge { .. }
                | Error::BoundaryEdge { .. }
                | Error::RepeatedVertex { .. })
        ),
        "{r:?}"
    );
    assert!(matches!(
        validate(&corpus("catmark_gregory_test8.obj")),
        Err(Error::UnsupportedValence { valence: 2, .. })
    ));
    assert!(matches!(
        validate(&corpus("catmark_smoothtris0.obj")),
        Err(Error::UnsupportedValence { valence: 20, .. })
    ));
}

#[test]
fn non_manifold_edge_and_vertex() {
    // Three quads on one edge: a cube plus a fin sharing edge 0-1.
    let mut m = cube();
    let f0 = m.faces[0].clone();
    let (a, b) = (f0[0], f0[1]);
    let base = m.positions.len() as u32;
    m.positions.push([5.0, 5.0, 5.0]);
    m.positions.push([6.0, 5.0, 5.0]);
    m.faces.push(vec![a, b, base + 1, base]);
    match validate(&m) {
        Err(Error::NonManifoldEdge { v0, v1 }) => {
            assert_eq!((v0.min(v1), v0.max(v1)), (a.min(b), a.max(b)))
        }
        other => panic!("expected non-manifold edge, got {other:?}"),
    }
    // Two cubes sharing one vertex: every edge is fine, the vertex is not.
    let c = cube();
    let mut two = c.clone();
    let off = c.positions.len() as u32;
    for q in &c.positions {
        two.positions.push([q[0] + 2.0, q[1] + 2.0, q[2] + 2.0]);
    }
    // Glue: the second cube's vertex that lands on... pick vertex 0 of cube 2 := vertex 6 of cube 1.
    let shared = 0u32;
    let target = 6u32;
    for f in &c.faces {
        two.faces.push(
            f.iter()
                .map(|&v| if v == shared { target } else { v + off })
                .collect(),
        );
    }
    match validate(&two) {
        Err(Error::NonManifoldVertex { vertex }) => assert_eq!(vertex, target),
        other => panic!("expected non-manifold vertex, got {other:?}"),
    }
}

#[test]
fn size_queries_are_exact() {
    for m in [cube(), drum(5), pole_mesh(7), corpus("catmark_pyramid.obj")] {
        let (p, s, i) = flatten(&m);
        let need = Topology::required_bytes(p.len() / 3, &s);
        let mut mem = aligned(need);
        let mesh = MeshInput {
            positions: &p,
            face_sizes: &s,
            indices: &i,
        };
        assert_eq!(
            Topology::build(mesh, &mut mem[..need / 8 - 1]).err(),
            Some(Error::BufferTooSmall { required: need })
        );
        let topo = Topology::build(mesh, &mut mem[..need / 8]).unwrap();
        let tables = standard_tables();
        let en = Evaluator::required_bytes(&topo, tables).unwrap();
        let mut emem = aligned(en);
        assert_eq!(
            Evaluator::build(&topo, tables, &mut emem[..en / 8 - 1]).err(),
            Some(Error::BufferTooSmall { required: en })
        );
        let ev = Evaluator::build(&topo, tables, &mut emem[..en / 8]).unwrap();
        assert!(ev.eval(0, 0, 0.3, 0.7).is_ok());
        // Misaligned memory cannot be passed from Rust (a `u64` block);
        // the C ABI's alignment check is tested in ffi/.
    }
}

#[test]
fn bad_queries() {
    let m = drum(5);
    with_evaluator(&m, standard_tables(), |_, ev| {
        assert_eq!(
            ev.eval(99, 0, 0.5, 0.5),
            Err(Error::FaceOutOfRange { face: 99 })
        );
        assert_eq!(
            ev.eval(0, 5, 0.5, 0.5),
            Err(Error::SubFaceOutOfRange { face: 0, sub: 5 })
        );
        assert!(ev.eval(0, 4, 0.5, 0.5).is_ok());
        assert_eq!(
            ev.eval(2, 1, 0.5, 0.5),
            Err(Error::SubFaceOutOfRange { face: 2, sub: 1 })
        );
        assert_eq!(
            ev.eval(0, 0, f64::NAN, 0.5),
            Err(Error::ParameterOutOfRange)
        );
        assert_eq!(
            ev.eval(0, 0, 0.5, 1.0 + 1e-15),
            Err(Error::ParameterOutOfRange)
        );
        assert_eq!(ev.eval(0, 0, -0.0, 0.0).map(|_| ()), Ok(()));
        let qs = [
            ccss_core::eval::Query {
                face: 0,
                sub: 0,
                u: 0.1,
                v: 0.2,
            },
            ccss_core::eval::Query {
                face: 7,
                sub: 0,
                u: 0.1,
                v: 0.2,
            },
        ];
        let mut out = [ccss_core::Eval::default(); 2];
        assert_eq!(
            ev.eval_batch(&qs, false, &mut out),
            Err((1, Error::FaceOutOfRange { face: 7 }))
        );
        assert_eq!(
            out[0],
            ccss_core::Eval::default(),
            "nothing written on failure"
        );
        let mut short = [ccss_core::Eval::default(); 1];
        assert_eq!(ev.eval_batch(&qs[..1], false, &mut short), Ok(()));
        assert_eq!(
            ev.eval_batch(&qs, false, &mut short),
            Err((0, Error::BufferTooSmall { required: 2 }))
        );
    })
    .unwrap();
}
