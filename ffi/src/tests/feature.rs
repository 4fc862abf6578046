//! The feature evaluator: size query and build (NULL pointers, small
//! blocks, tag errors), evaluation equal to the Rust `FeatureEvaluator`,
//! holes, batches, statuses.

use super::*;
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::{FeatureEvaluator, MeshInput};

/// An open 3x3 grid of quads in the plane z = 0 (16 vertices, 9 faces),
/// with a bump at the centre vertices so that the surface is not planar
/// when `bump` is set.
pub(super) fn grid(bump: bool) -> (Vec<f64>, Vec<u32>, Vec<u32>) {
    let mut p = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            let inner = (1..3).contains(&i) && (1..3).contains(&j);
            let z = if bump && inner { 0.5 } else { 0.0 };
            p.extend_from_slice(&[i as f64, j as f64, z]);
        }
    }
    let mut idx = Vec::new();
    for j in 0..3u32 {
        for i in 0..3u32 {
            let v = 4 * j + i;
            idx.extend_from_slice(&[v, v + 1, v + 5, v + 4]);
        }
    }
    (p, vec![4; 9], idx)
}

/// Tags of the tests: creases (pairs), their sharpness, corners, holes.
#[derive(Default)]
pub(super) struct Tags {
    cv: Vec<u32>,
    cs: Vec<f32>,
    kv: Vec<u32>,
    ks: Vec<f32>,
    holes: Vec<u32>,
}

pub(super) fn defaults() -> CcssFeatureOptions {
    let mut o = CcssFeatureOptions::default();
    assert_eq!(
        unsafe { ccss_feature_options_default(&mut o, ptr::null_mut()) },
        CcssStatus::OK
    );
    o
}

unsafe fn size(
    p: &[f64],
    s: &[u32],
    i: &[u32],
    t: &Tags,
    o: *const CcssFeatureOptions,
    out: *mut usize,
    d: *mut CcssErrorDetail,
) -> CcssStatus {
    unsafe {
        ccss_feature_evaluator_required_bytes(
            p.as_ptr(),
            p.len() / 3,
            s.as_ptr(),
            s.len(),
            i.as_ptr(),
            i.len(),
            t.cv.as_ptr(),
            t.cs.as_ptr(),
            t.cs.len(),
            t.kv.as_ptr(),
            t.ks.as_ptr(),
            t.ks.len(),
            t.holes.as_ptr(),
            t.holes.len(),
            o,
            ptr::null(),
            out,
            d,
        )
    }
}

#[allow(clippy::too_many_arguments)]
unsafe fn build(
    p: &[f64],
    s: &[u32],
    i: &[u32],
    t: &Tags,
    o: *const CcssFeatureOptions,
    mem: &mut [u64],
    mem_len: usize,
    out: *mut *const CcssFeatureEvaluator,
    d: *mut CcssErrorDetail,
) -> CcssStatus {
    unsafe {
        ccss_feature_evaluator_build(
            p.as_ptr(),
            p.len() / 3,
            s.as_ptr(),
            s.len(),
            i.as_ptr(),
            i.len(),
            t.cv.as_ptr(),
            t.cs.as_ptr(),
            t.cs.len(),
            t.kv.as_ptr(),
            t.ks.as_ptr(),
            t.ks.len(),
            t.holes.as_ptr(),
            t.holes.len(),
            o,
            ptr::null(),
            mem.as_mut_ptr().cast(),
            mem_len,
            out,
            d,
        )
    }
}

/// Size query plus build in a test-owned block.
pub(super) fn make(
    p: &[f64],
    s: &[u32],
    i: &[u32],
    t: &Tags,
    o: &CcssFeatureOptions,
) -> Result<(*const CcssFeatureEvaluator, Vec<u64>), Box<CcssErrorDetail>> {
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    unsafe {
        if size(p, s, i, t, o, &mut n, &mut d) != CcssStatus::OK {
            return Err(Box::new(d));
        }
        let mut mem = block(n);
        let mut fe = ptr::null();
        let st = build(p, s, i, t, o, &mut mem, n, &mut fe, &mut d);
        if st != CcssStatus::OK {
            return Err(Box::new(d));
        }
        assert_eq!(fe as *const u8, mem.as_ptr() as *const u8);
        Ok((fe, mem))
    }
}

pub(super) fn all_edges_sharp_cube() -> ([f64; 24], [u32; 6], [u32; 24], Tags) {
    let (p, s, i) = cube();
    let mut t = Tags::default();
    for f in i.chunks(4) {
        for k in 0..4 {
            let (a, b) = (f[k], f[(k + 1) % 4]);
            if a < b {
                t.cv.extend_from_slice(&[a, b]);
                t.cs.push(10.0);
            }
        }
    }
    assert_eq!(t.cs.len(), 12);
    (p, s, i, t)
}

#[test]
fn options_default_and_checks() {
    let o = defaults();
    assert_eq!(
        (o.boundary, o.creasing, o.smooth_triangles),
        (
            CcssFeatureBoundary::FEATURE_BOUNDARY_EDGE_ONLY as u32,
            CcssFeatureCreasing::FEATURE_CREASING_UNIFORM as u32,
            0
        )
    );
    assert_eq!(CcssFeatureBoundary::FEATURE_BOUNDARY_NONE as u32, 0);
    assert_eq!(
        CcssFeatureBoundary::FEATURE_BOUNDARY_EDGE_AND_CORNER as u32,
        2
    );
    assert_eq!(CcssFeatureCreasing::FEATURE_CREASING_CHAIKIN as u32, 1);
    assert_eq!(
        unsafe { ccss_feature_options_default(ptr::null_mut(), ptr::null_mut()) },
        CcssStatus::ERR_NULL_POINTER
    );
    let (p, s, i) = grid(false);
    let t = Tags::default();
    for bad in [
        CcssFeatureOptions { boundary: 3, ..o },
        CcssFeatureOptions { creasing: 2, ..o },
        CcssFeatureOptions {
            smooth_triangles: 2,
            ..o
        },
    ] {
        let d = make(&p, &s, &i, &t, &bad).expect_err("bad options accepted");
        assert_eq!(d.status, CcssStatus::ERR_INVALID_ARGUMENT, "{}", msg(&d));
        assert!(msg(&d).contains("options."), "{}", msg(&d));
    }
}

#[test]
fn null_pointers_and_small_blocks() {
    let (p, s, i) = grid(true);
    let t = Tags {
        cv: vec![5, 6],
        cs: vec![2.5],
        ..Tags::default()
    };
    let o = defaults();
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    unsafe {
        assert_eq!(
            size(&p, &s, &i, &t, &o, ptr::null_mut(), &mut d),
            CcssStatus::ERR_NULL_POINTER
        );
        assert_eq!(
            size(&p, &s, &i, &t, ptr::null(), &mut n, &mut d),
            CcssStatus::ERR_NULL_POINTER
        );
        assert!(msg(&d).contains("`options`"), "{}", msg(&d));
        let st = ccss_feature_evaluator_required_bytes(
            ptr::null(),
            16,
            s.as_ptr(),
            9,
            i.as_ptr(),
            36,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            ptr::null(),
            &mut n,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        assert!(msg(&d).contains("`positions`"), "{}", msg(&d));
        // A crease count with NULL arrays.
        let st = ccss_feature_evaluator_required_bytes(
            p.as_ptr(),
            16,
            s.as_ptr(),
            9,
            i.as_ptr(),
            36,
            ptr::null(),
            ptr::null(),
            1,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            ptr::null(),
            &mut n,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        assert!(msg(&d).contains("`crease_vertices`"), "{}", msg(&d));

        assert_eq!(size(&p, &s, &i, &t, &o, &mut n, &mut d), CcssStatus::OK);
        assert!(n > 0 && n % 8 == 0, "{n}");
        // Too small: by one word (the refined mesh fits, the evaluator does
        // not), and far too small (the exact size from a heap build); the
        // required size in the detail, nothing written to *out.
        let sentinel = 0x10 as *const CcssFeatureEvaluator;
        for len in [n - 8, n - 1, 8, 0] {
            let mut mem = block(n);
            let mut fe = sentinel;
            let st = build(&p, &s, &i, &t, &o, &mut mem, len, &mut fe, &mut d);
            assert_eq!(
                (st, d.required),
                (CcssStatus::ERR_BUFFER_TOO_SMALL, n as u64),
                "mem_len {len}: {}",
                msg(&d)
            );
            assert_eq!(fe, sentinel, "mem_len {len}: *out written");
        }
        // NULL block with a length; NULL out; misaligned block.
        let mut fe = sentinel;
        let st = ccss_feature_evaluator_build(
            p.as_ptr(),
            16,
            s.as_ptr(),
            9,
            i.as_ptr(),
            36,
            t.cv.as_ptr(),
            t.cs.as_ptr(),
            1,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            ptr::null(),
            ptr::null_mut(),
            n,
            &mut fe,
            &mut d,
        );
        assert_eq!((st, fe), (CcssStatus::ERR_NULL_POINTER, sentinel));
        let mut mem = block(n + 8);
        let st = build(&p, &s, &i, &t, &o, &mut mem, n, ptr::null_mut(), &mut d);
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        let odd = (mem.as_mut_ptr() as *mut u8).add(4);
        let st = ccss_feature_evaluator_build(
            p.as_ptr(),
            16,
            s.as_ptr(),
            9,
            i.as_ptr(),
            36,
            t.cv.as_ptr(),
            t.cs.as_ptr(),
            1,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            ptr::null(),
            odd.cast(),
            n,
            &mut fe,
            &mut d,
        );
        assert_eq!((st, fe), (CcssStatus::ERR_MISALIGNED, sentinel));
        // NULL handle.
        let mut r = CcssEvaluatorResult::default();
        assert_eq!(
            ccss_feature_evaluator_eval(ptr::null(), 0, 0, 0.5, 0.5, &mut r, &mut d),
            CcssStatus::ERR_NULL_POINTER
        );
    }
}

#[test]
fn evaluation_equals_the_rust_feature_evaluator() {
    let (p, s, i) = grid(true);
    let t = Tags {
        cv: vec![5, 6, 6, 10],
        cs: vec![2.5, 10.0],
        kv: vec![9],
        ks: vec![1.5],
        holes: vec![],
    };
    for (boundary, creasing) in [(1u32, 0u32), (2, 1), (0, 0)] {
        let o = CcssFeatureOptions {
            boundary,
            creasing,
            smooth_triangles: 0,
        };
        let (fe, _mem) = make(&p, &s, &i, &t, &o).unwrap_or_else(|d| panic!("{}", msg(&d)));
        // The same in Rust.
        let mesh = MeshInput {
            positions: &p,
            face_sizes: &s,
            indices: &i,
        };
        let tags = FeatureInput {
            crease_vertices: &t.cv,
            crease_sharpness: &t.cs,
            corner_vertices: &t.kv,
            corner_sharpness: &t.ks,
            holes: &t.holes,
            options: FeatureOptions {
                boundary: [Boundary::None, Boundary::EdgeOnly, Boundary::EdgeAndCorner]
                    [boundary as usize],
                creasing: [Creasing::Uniform, Creasing::Chaikin][creasing as usize],
                smooth_triangles: false,
            },
        };
        let mut fmem = block(FeatureMesh::required_bytes(&mesh).unwrap());
        let fm = FeatureMesh::build(&mesh, &tags, &mut fmem).unwrap();
        let mut emem = block(FeatureEvaluator::required_bytes(&fm, None));
        let rust = FeatureEvaluator::build(&fm, None, &mut emem).unwrap();

        let mut nf = 0usize;
        unsafe {
            assert_eq!(
                ccss_feature_evaluator_face_count(fe, &mut nf, ptr::null_mut()),
                CcssStatus::OK
            );
        }
        assert_eq!(nf, 9);
        let mut compared = 0;
        for f in 0..9u32 {
            let mut hole = 7u8;
            unsafe {
                assert_eq!(
                    ccss_feature_evaluator_face_is_hole(fe, f, &mut hole, ptr::null_mut()),
                    CcssStatus::OK
                );
            }
            for (u, v) in [(0.0, 0.0), (0.5, 0.5), (0.25, 0.75), (1.0, 0.125)] {
                let mut r = CcssEvaluatorResult::default();
                let mut r2 = CcssEvaluatorResult::default();
                let mut d = Failure::invalid("x").to_detail();
                let st = unsafe { ccss_feature_evaluator_eval(fe, f, 0, u, v, &mut r, &mut d) };
                let st2 =
                    unsafe { ccss_feature_evaluator_eval_second(fe, f, 0, u, v, &mut r2, &mut d) };
                match rust.eval(f, 0, u, v) {
                    Ok(e) => {
                        assert_eq!((st, st2, hole), (CcssStatus::OK, CcssStatus::OK, 0));
                        assert_eq!(r, CcssEvaluatorResult::from(e), "face {f} ({u}, {v})");
                        let e2 = rust.eval_second(f, 0, u, v).unwrap();
                        assert_eq!(r2, CcssEvaluatorResult::from(e2));
                        compared += 1;
                    }
                    Err(Error::HoleFace { face }) => {
                        assert_eq!(
                            (st, d.face, hole),
                            (CcssStatus::ERR_HOLE_FACE, face as i64, 1)
                        );
                    }
                    Err(e) => panic!("{e}"),
                }
            }
        }
        // In mode NONE every face but the centre one touches a boundary
        // vertex, so is a hole.
        assert_eq!(compared, if boundary == 0 { 4 } else { 36 });
    }
}

#[test]
fn holes_batches_and_tag_errors() {
    let (p, s, i) = grid(true);
    let o = defaults();
    let t = Tags {
        holes: vec![4],
        ..Tags::default()
    };
    let (fe, _mem) = make(&p, &s, &i, &t, &o).unwrap_or_else(|d| panic!("{}", msg(&d)));
    let mut d = Failure::invalid("x").to_detail();
    let mut r = CcssEvaluatorResult::default();
    unsafe {
        let st = ccss_feature_evaluator_eval(fe, 4, 0, 0.5, 0.5, &mut r, &mut d);
        assert_eq!((st, d.face), (CcssStatus::ERR_HOLE_FACE, 4));
        assert!(msg(&d).contains("face 4 is a hole"), "{}", msg(&d));
        let st = ccss_feature_evaluator_eval(fe, 9, 0, 0.5, 0.5, &mut r, &mut d);
        assert_eq!((st, d.face), (CcssStatus::ERR_FACE_OUT_OF_RANGE, 9));
        let st = ccss_feature_evaluator_eval(fe, 0, 1, 0.5, 0.5, &mut r, &mut d);
        assert_eq!((st, d.value), (CcssStatus::ERR_SUBFACE_OUT_OF_RANGE, 1));
        let st = ccss_feature_evaluator_eval(fe, 0, 0, 1.5, 0.5, &mut r, &mut d);
        assert_eq!(st, CcssStatus::ERR_PARAMETER_OUT_OF_RANGE);
        let mut k = 0u32;
        assert_eq!(
            ccss_feature_evaluator_subface_count(fe, 3, &mut k, &mut d),
            CcssStatus::OK
        );
        assert_eq!(k, 1);
        assert_eq!(
            ccss_feature_evaluator_subface_count(fe, 30, &mut k, &mut d),
            CcssStatus::ERR_FACE_OUT_OF_RANGE
        );

        // Batch: the hole is found before anything is written.
        let q = |face| CcssEvaluatorQuery {
            face,
            sub: 0,
            u: 0.25,
            v: 0.5,
        };
        let qs = [q(0), q(8), q(4)];
        let mut out = [CcssEvaluatorResult::default(); 3];
        let st =
            ccss_feature_evaluator_eval_batch(fe, qs.as_ptr(), 3, 0, out.as_mut_ptr(), 3, &mut d);
        assert_eq!(
            (st, d.query_index, d.face),
            (CcssStatus::ERR_HOLE_FACE, 2, 4)
        );
        assert!(msg(&d).starts_with("query 2: "), "{}", msg(&d));
        assert_eq!(out, [CcssEvaluatorResult::default(); 3]);
        let st =
            ccss_feature_evaluator_eval_batch(fe, qs.as_ptr(), 2, 1, out.as_mut_ptr(), 1, &mut d);
        assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 2));
        let st =
            ccss_feature_evaluator_eval_batch(fe, qs.as_ptr(), 2, 1, out.as_mut_ptr(), 3, &mut d);
        assert_eq!(st, CcssStatus::OK);
        let mut one = CcssEvaluatorResult::default();
        ccss_feature_evaluator_eval_second(fe, 8, 0, 0.25, 0.5, &mut one, &mut d);
        assert_eq!(out[1], one);
    }

    // Tag errors, with the offending vertices / face in the detail.
    let cases: [(Tags, CcssStatus, [i64; 3]); 5] = [
        (
            Tags {
                cv: vec![0, 5],
                cs: vec![1.0],
                ..Tags::default()
            },
            CcssStatus::ERR_NOT_AN_EDGE,
            [-1, 0, 5],
        ),
        (
            Tags {
                cv: vec![0, 1],
                cs: vec![f32::NAN],
                ..Tags::default()
            },
            CcssStatus::ERR_INVALID_ARGUMENT,
            [-1, 0, 1],
        ),
        (
            Tags {
                kv: vec![3],
                ks: vec![-1.0],
                ..Tags::default()
            },
            CcssStatus::ERR_INVALID_ARGUMENT,
            [-1, 3, 3],
        ),
        (
            Tags {
                kv: vec![16],
                ks: vec![1.0],
                ..Tags::default()
            },
            CcssStatus::ERR_INDEX_OUT_OF_RANGE,
            [-1, 16, -1],
        ),
        (
            Tags {
                holes: vec![9],
                ..Tags::default()
            },
            CcssStatus::ERR_FACE_OUT_OF_RANGE,
            [9, -1, -1],
        ),
    ];
    for (t, status, [face, v0, v1]) in cases {
        // The size query and the build (with a generous block) agree.
        let d = make(&p, &s, &i, &t, &o).expect_err("bad tag accepted");
        assert_eq!(
            (d.status, d.face, d.vertex, d.vertex2),
            (status, face, v0, v1),
            "{}",
            msg(&d)
        );
        let mut mem = block(1 << 20);
        let mut fe = ptr::null();
        let mut d = Failure::invalid("x").to_detail();
        let st = unsafe { build(&p, &s, &i, &t, &o, &mut mem, 1 << 20, &mut fe, &mut d) };
        assert_eq!((st, d.vertex, d.vertex2), (status, v0, v1), "{}", msg(&d));
        assert!(fe.is_null());
    }
}

#[test]
fn build_and_eval_do_not_allocate() {
    let (p, s, i, t) = all_edges_sharp_cube();
    let o = defaults();
    let mut n = 0usize;
    let mut d = Failure::invalid("x").to_detail();
    unsafe {
        assert_eq!(size(&p, &s, &i, &t, &o, &mut n, &mut d), CcssStatus::OK);
    }
    let mut mem = block(n);
    let mut fe = ptr::null();
    let mut r = CcssEvaluatorResult::default();
    let before = alloc_count::get();
    unsafe {
        assert_eq!(
            build(&p, &s, &i, &t, &o, &mut mem, n, &mut fe, &mut d),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_feature_evaluator_eval(fe, 0, 0, 0.25, 0.5, &mut r, &mut d),
            CcssStatus::OK
        );
        // One word short: the refined mesh fits, so no heap build either.
        let mut fe2 = ptr::null();
        assert_eq!(
            build(&p, &s, &i, &t, &o, &mut mem, n - 8, &mut fe2, &mut d),
            CcssStatus::ERR_BUFFER_TOO_SMALL
        );
    }
    assert_eq!(alloc_count::get(), before, "build / eval allocated");
    // The fully creased cube: face 0 (z = -1, corners v0 v3 v2 v1) is the
    // bilinear square.
    let want = [0.0, -0.5, -1.0];
    assert!(
        (0..3).all(|k| (r.p[k] - want[k]).abs() <= 1e-14),
        "{:?}",
        r.p
    );
}

#[test]
fn new_statuses_have_messages() {
    for (st, want) in [
        (CcssStatus::ERR_HOLE_FACE, 23, "hole"),
        (CcssStatus::ERR_NOT_AN_EDGE, 24, "no edge"),
        (CcssStatus::ERR_NEIGHBOURHOOD_TOO_LARGE, 25, "too large"),
        (CcssStatus::ERR_NOT_CLOSED_SOLID, 26, "solid"),
        (CcssStatus::ERR_NOT_CONVERGED, 27, "converge"),
        (CcssStatus::ERR_CONFLICTING_REQUIREMENT, 28, "conflicts"),
    ]
    .map(|(s, v, m)| ((s, v), m))
    {
        assert_eq!(st.0 as c_int, st.1);
        let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(st.1)) };
        assert!(m.to_str().unwrap().contains(want), "{m:?}");
    }
    assert_eq!(CcssStatus::ERR_INTERNAL as c_int, 99);
    let f = Failure::from(Error::NeighbourhoodTooLarge { face: 7 });
    assert_eq!(
        (f.status, f.face),
        (CcssStatus::ERR_NEIGHBOURHOOD_TOO_LARGE, 7)
    );
    let f = Failure::from(Error::ConflictingRequirement { requirement: 4 });
    assert_eq!(
        (f.status, f.value),
        (CcssStatus::ERR_CONFLICTING_REQUIREMENT, 4)
    );
    let f = Failure::from(Error::NotConverged { iterations: 9 });
    assert_eq!((f.status, f.value), (CcssStatus::ERR_NOT_CONVERGED, 9));
    let f = Failure::from(Error::VertexOutOfRange { vertex: 3 });
    assert_eq!(
        (f.status, f.face, f.vertex),
        (CcssStatus::ERR_INDEX_OUT_OF_RANGE, -1, 3)
    );
}

/// With standard eigen tables the handle evaluates smooth extraordinary
/// patches with the eigen kernel: bit-equal to the Rust evaluator built
/// with the same tables; tables of another rule are refused.
#[test]
fn eigen_tables_are_used_and_checked() {
    let (p, s, i) = cube();
    let standard = build_mesh(&p, &s, &i, &[]);
    let other = build_mesh(&p, &s, &i, &[entry(3, 0.5, 0.3, 0.2)]);
    let o = defaults();
    let mut d = Failure::invalid("x").to_detail();
    let call = |tables: *const CcssTables, d: &mut CcssErrorDetail| unsafe {
        let mut n = 0usize;
        let st = ccss_feature_evaluator_required_bytes(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            tables,
            &mut n,
            d,
        );
        if st != CcssStatus::OK {
            return Err(st);
        }
        let mut mem = block(n);
        let mut fe = ptr::null();
        let st = ccss_feature_evaluator_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            ptr::null(),
            0,
            ptr::null(),
            0,
            &o,
            tables,
            mem.as_mut_ptr().cast(),
            n,
            &mut fe,
            d,
        );
        if st != CcssStatus::OK {
            return Err(st);
        }
        Ok((fe, mem))
    };
    assert_eq!(
        call(other.tables, &mut d).err(),
        Some(CcssStatus::ERR_INVALID_ARGUMENT)
    );
    assert!(msg(&d).contains("standard"), "{}", msg(&d));
    let (fe, _mem) = call(standard.tables, &mut d).unwrap_or_else(|_| panic!("{}", msg(&d)));
    // The same in Rust, with the same tables.
    let mesh = MeshInput {
        positions: &p,
        face_sizes: &s,
        indices: &i,
    };
    let tags = FeatureInput {
        options: FeatureOptions::default(),
        ..Default::default()
    };
    let set = unsafe { &(*standard.tables).inner.set };
    let mut fmem = block(FeatureMesh::required_bytes(&mesh).unwrap());
    let fm = FeatureMesh::build(&mesh, &tags, &mut fmem).unwrap();
    let mut emem = block(FeatureEvaluator::required_bytes(&fm, Some(set)));
    let rust = FeatureEvaluator::build(&fm, Some(set), &mut emem).unwrap();
    for f in 0..6u32 {
        for (u, v) in [(0.0, 0.0), (0.01, 0.02), (0.3, 0.7), (0.5, 0.5), (1.0, 1.0)] {
            let mut r = CcssEvaluatorResult::default();
            let st = unsafe { ccss_feature_evaluator_eval(fe, f, 0, u, v, &mut r, &mut d) };
            assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
            let e = rust.eval(f, 0, u, v).unwrap();
            assert_eq!(r.p, [e.p.x, e.p.y, e.p.z], "face {f} ({u}, {v})");
            assert_eq!(r.du, [e.du.x, e.du.y, e.du.z], "face {f} ({u}, {v})");
        }
    }
}

/// Voxelization, flooding, mass properties and depths of a feature
/// evaluator through the C ABI: the fully creased cube is the cube itself,
/// so its voxel classes, volume and inertia are known; an open mesh is
/// NOT_CLOSED_SOLID naming a boundary edge.
#[test]
fn voxels_measure_and_depth_of_feature_meshes() {
    let (p, s, i, t) = all_edges_sharp_cube();
    let Ok((fe, _mem)) = make(&p, &s, &i, &t, &defaults()) else {
        panic!("build failed")
    };
    let mut d = Failure::invalid("x").to_detail();
    let res = [12u32; 3];
    let mut n = 0usize;
    unsafe {
        assert_eq!(
            ccss_voxel_grid_required_bytes(res.as_ptr(), 0, 12, &mut n, &mut d),
            CcssStatus::OK
        );
        let mut gm = block(n);
        let mut g = ptr::null_mut();
        assert_eq!(
            ccss_voxel_grid_build(
                res.as_ptr(),
                0,
                12,
                gm.as_mut_ptr().cast(),
                n,
                &mut g,
                &mut d
            ),
            CcssStatus::OK
        );
        let mut tr = CcssVoxelGridTransform::default();
        assert_eq!(
            ccss_voxel_grid_fit_transform_feature(fe, g, &mut tr, &mut d),
            CcssStatus::OK
        );
        // The cube [-1, 1]^3 onto voxel centres 0..=11.
        assert!((tr.scale - 5.5).abs() < 1e-12, "{tr:?}");
        let mut vs = CcssVoxelGridVoxelizeStats::default();
        assert_eq!(
            ccss_voxel_grid_voxelize_feature(fe, g, 6, 8, ptr::null(), &mut vs, &mut d),
            CcssStatus::OK
        );
        assert_eq!(vs.guard_hits, 0);
        let mut stack = [0u32; 64];
        let mut fs = CcssVoxelGridFloodStats::default();
        assert_eq!(
            ccss_voxel_grid_flood_feature(fe, g, stack.as_mut_ptr(), 64, &mut fs, &mut d),
            CcssStatus::OK
        );
        let (mut sf, mut it) = (0u64, 0u64);
        assert_eq!(
            ccss_voxel_grid_counts(g, &mut sf, &mut it, &mut d),
            CcssStatus::OK
        );
        // Voxels whose centre is on a face are surface, the rest interior.
        assert_eq!((sf, it), (12 * 12 * 12 - 10 * 10 * 10, 10 * 10 * 10));
        let mut m = CcssMassProperties::default();
        assert_eq!(
            ccss_mass_properties_compute_feature(fe, &mut m, &mut d),
            CcssStatus::OK
        );
        assert!(
            (m.volume - 8.0).abs() <= 1e-12 + m.volume_error_bound,
            "{m:?}"
        );
        assert!((m.inertia[0] - 64.0 / 12.0).abs() <= 1e-11, "{m:?}");
        let mut steps = 99u32;
        assert_eq!(
            ccss_feature_evaluator_depth(fe, 0, 0, 1e-3, &mut steps, &mut d),
            CcssStatus::OK
        );
        assert!(steps <= 1, "{steps}");
        assert_eq!(
            ccss_feature_evaluator_depth(fe, 0, 0, 0.0, &mut steps, &mut d),
            CcssStatus::ERR_INVALID_ARGUMENT
        );
        // An open grid of quads: not a solid, naming a boundary edge.
        let (p, s, i) = grid(true);
        let Ok((open, _m2)) = make(&p, &s, &i, &Tags::default(), &defaults()) else {
            panic!("build failed")
        };
        assert_eq!(
            ccss_voxel_grid_voxelize_feature(open, g, 6, 8, ptr::null(), ptr::null_mut(), &mut d),
            CcssStatus::ERR_NOT_CLOSED_SOLID
        );
        let (a, b) = (d.vertex as u32, d.vertex2 as u32);
        let uses = i
            .chunks(4)
            .filter(|f| {
                (0..4).any(|k| {
                    let (x, y) = (f[k], f[(k + 1) % 4]);
                    (x, y) == (a, b) || (x, y) == (b, a)
                })
            })
            .count();
        assert_eq!(uses, 1, "edge {a}-{b}");
        assert_eq!(
            ccss_mass_properties_compute_feature(open, &mut m, &mut d),
            CcssStatus::ERR_NOT_CLOSED_SOLID
        );
        assert_eq!(
            ccss_feature_evaluator_depth(open, 4, 0, 1e-3, &mut steps, &mut d),
            CcssStatus::OK
        );
        let msg = core::ffi::CStr::from_ptr(ccss_status_message(26));
        assert!(msg.to_str().unwrap().contains("solid"));
        drop(gm);
    }
}

#[test]
fn queries_on_feature_meshes() {
    let (p, s, i, t) = all_edges_sharp_cube();
    let Ok((fe, _mem)) = make(&p, &s, &i, &t, &defaults()) else {
        panic!("build failed")
    };
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    unsafe {
        assert_eq!(ccss_query_required_bytes(&mut n, &mut d), CcssStatus::OK);
        let mut qm = block(n);
        let mut q = ptr::null_mut();
        assert_eq!(
            ccss_query_build(qm.as_mut_ptr().cast(), n, &mut q, &mut d),
            CcssStatus::OK
        );
        // The fully creased cube is the cube [-1, 1]^3.
        let ray = CcssQueryRay {
            origin: [0.1, 0.2, -5.0],
            dir: [0.0, 0.0, 1.0],
        };
        let mut hits = [CcssQueryHit::default(); 4];
        let mut nh = 0usize;
        let st =
            ccss_query_feature_ray_all(fe, q, &ray, 1e-9, hits.as_mut_ptr(), 4, &mut nh, &mut d);
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        assert_eq!(nh, 2);
        assert!((hits[0].t - 4.0).abs() <= 1e-9 && (hits[1].t - 6.0).abs() <= 1e-9);
        let mut found = 0 as c_int;
        let st = ccss_query_feature_ray_first(
            fe,
            q,
            &ray,
            1,
            1e-9,
            hits.as_mut_ptr(),
            &mut found,
            &mut d,
        );
        assert_eq!((st, found), (CcssStatus::OK, 1));
        assert!((hits[0].t - 4.0).abs() <= 1e-9);
        let mut ins = 7 as c_int;
        let st = ccss_query_feature_inside(fe, q, [0.1, 0.2, 0.3].as_ptr(), 1e-9, &mut ins, &mut d);
        assert_eq!((st, ins), (CcssStatus::OK, 1));
        let mut c = CcssQueryClosestInfo::default();
        let st =
            ccss_query_feature_closest(fe, q, [0.2, 0.1, 3.0].as_ptr(), 1, 1e-9, &mut c, &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert!((c.dist - 2.0).abs() <= 1e-9, "{c:?}");
        // The section z = 0.25: the square of side 2, one outer contour.
        let nz = [0.0, 0.0, 1.0];
        let mut bytes = 0usize;
        let st = ccss_query_feature_slice_required_bytes(
            fe,
            q,
            nz.as_ptr(),
            0.25,
            1e-6,
            &mut bytes,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        let mut scratch = block(bytes);
        let mut ls = CcssQuerySliceLayerStats::default();
        let st = ccss_query_feature_slice_layer(
            fe,
            q,
            nz.as_ptr(),
            0.25,
            1e-6,
            scratch.as_mut_ptr().cast(),
            bytes,
            &mut ls,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        assert_eq!(ls.contours, 1);
        let mut pts = vec![0.0; 2 * ls.points as usize];
        let mut cs = [CcssQueryContour::default(); 1];
        let st = ccss_query_slice_write(
            scratch.as_mut_ptr().cast(),
            bytes,
            &ls,
            pts.as_mut_ptr(),
            ls.points as usize,
            cs.as_mut_ptr(),
            1,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        let area: f64 = (0..ls.points as usize)
            .map(|k| {
                let l = (k + 1) % ls.points as usize;
                pts[2 * k] * pts[2 * l + 1] - pts[2 * l] * pts[2 * k + 1]
            })
            .sum::<f64>()
            * 0.5;
        assert!(
            cs[0].outer == 1 && (area - 4.0).abs() <= 1e-5,
            "area {area}"
        );
        // An open mesh: rays fine, inside and slices refused.
        let (gp, gs, gi) = grid(true);
        let Ok((open, _om)) = make(&gp, &gs, &gi, &Tags::default(), &defaults()) else {
            panic!("build failed")
        };
        let down = CcssQueryRay {
            origin: [1.5, 1.5, 5.0],
            dir: [0.0, 0.0, -1.0],
        };
        let st = ccss_query_feature_ray_first(
            open,
            q,
            &down,
            1,
            1e-9,
            hits.as_mut_ptr(),
            &mut found,
            &mut d,
        );
        assert_eq!((st, found), (CcssStatus::OK, 1));
        let st =
            ccss_query_feature_inside(open, q, [1.5, 1.5, 0.0].as_ptr(), 1e-9, &mut ins, &mut d);
        assert_eq!(st, CcssStatus::ERR_NOT_CLOSED_SOLID);
        let st = ccss_query_feature_slice_required_bytes(
            open,
            q,
            nz.as_ptr(),
            0.1,
            1e-3,
            &mut bytes,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NOT_CLOSED_SOLID);
        drop(qm);
    }
}

/// `ccss_feature_evaluator_verify`: an untouched block verifies, also after
/// many evaluations (they write nothing into it); every 5th byte after the
/// header flipped (one at a time) is CORRUPTED.
#[test]
fn feature_block_integrity_check() {
    let (p, s, i) = grid(true);
    let t = Tags {
        cv: vec![5, 6, 6, 10],
        cs: vec![2.5, 10.0],
        kv: vec![9],
        ks: vec![1.5],
        holes: vec![],
    };
    let (fe, mut mem) = make(&p, &s, &i, &t, &defaults()).unwrap_or_else(|d| panic!("{}", msg(&d)));
    let mut d = Failure::invalid("x").to_detail();
    let mut r = CcssEvaluatorResult::default();
    let mut n = 0usize;
    unsafe {
        assert_eq!(ccss_feature_evaluator_verify(fe, &mut d), CcssStatus::OK);
        assert_eq!(
            ccss_feature_evaluator_face_count(fe, &mut n, &mut d),
            CcssStatus::OK
        );
        for f in 0..n as u32 {
            for k in 0..64 {
                let (u, v) = ((k % 8) as f64 / 7.0, (k / 8) as f64 / 7.0);
                let st = ccss_feature_evaluator_eval_second(fe, f, 0, u, v, &mut r, &mut d);
                assert!(st == CcssStatus::OK || st == CcssStatus::ERR_SUBFACE_OUT_OF_RANGE);
            }
        }
        assert_eq!(
            ccss_feature_evaluator_verify(fe, &mut d),
            CcssStatus::OK,
            "{}",
            msg(&d)
        );
        let head = crate::boundary::round8(core::mem::size_of::<CcssFeatureEvaluator>());
        let bytes = mem.len() * 8;
        let base = mem.as_mut_ptr() as *mut u8;
        let mut tried = 0;
        for at in (head..bytes).step_by(5) {
            let x = base.add(at);
            let saved = x.read();
            x.write(saved ^ 0x80);
            let st = ccss_feature_evaluator_verify(fe, &mut d);
            assert_eq!(st, CcssStatus::ERR_CORRUPTED, "byte {at}");
            x.write(saved);
            tried += 1;
        }
        assert!(tried > 100);
        assert_eq!(ccss_feature_evaluator_verify(fe, &mut d), CcssStatus::OK);
        // A garbage handle: INVALID_HANDLE naming the type.
        let junk = vec![7u64; 1024];
        let st =
            ccss_feature_evaluator_verify(junk.as_ptr() as *const CcssFeatureEvaluator, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_HANDLE);
        assert!(msg(&d).contains("ccss_feature_evaluator"), "{}", msg(&d));
    }
}
