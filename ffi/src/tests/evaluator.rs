//! Tables, topology and evaluator: build, evaluation, errors, no allocation.

use super::*;

#[test]
fn build_eval_and_errors_do_not_allocate() {
    let (p, s, i) = cube();
    let (mut tb, mut gb, mut eb) = (0usize, 0usize, 0usize);
    let mut d = Failure::invalid("x").to_detail();
    unsafe {
        assert_eq!(
            ccss_tables_required_bytes(&mut tb, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    let b = alloc_count::get();
    let probe = std::hint::black_box(vec![1u8]);
    assert!(alloc_count::get() > b, "the allocation counter counts");
    drop(probe);
    let mut tmem = block(tb);
    let mut gmem = block(gb);
    let mut bad = i;
    bad[5] = 7; // face 1 = 4 7 6 7: repeated vertex
    let mut tables = ptr::null();
    let mut topo = ptr::null();
    let mut ev = ptr::null();
    let before = alloc_count::get();
    unsafe {
        let st =
            ccss_tables_build_standard(tmem.as_mut_ptr().cast(), tb, &mut tables, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            bad.as_ptr(),
            24,
            gmem.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_REPEATED_VERTEX);
        assert_eq!((d.face, d.vertex), (1, 7));
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            gmem.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d),
            CcssStatus::OK
        );
    }
    assert_eq!(alloc_count::get(), before, "tables / topology allocated");
    let mut emem = block(eb);
    let qs = [
        CcssEvaluatorQuery {
            face: 0,
            sub: 0,
            u: 0.5,
            v: 0.5,
        },
        CcssEvaluatorQuery {
            face: 1,
            sub: 0,
            u: 0.0,
            v: 0.25,
        },
    ];
    let mut res = [CcssEvaluatorResult::default(); 2];
    let mut r = CcssEvaluatorResult::default();
    let before = alloc_count::get();
    unsafe {
        let st = ccss_evaluator_build(topo, tables, emem.as_mut_ptr().cast(), eb, &mut ev, &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_eval(ev, 0, 0, 0.5, 0.5, &mut r, ptr::null_mut()),
            CcssStatus::OK
        );
        assert!((r.p[2] + 68.0 / 81.0).abs() < 1e-12);
        assert_eq!(
            ccss_evaluator_eval_second(ev, 0, 0, 0.5, f64::NAN, &mut r, ptr::null_mut()),
            CcssStatus::ERR_PARAMETER_OUT_OF_RANGE
        );
        let st = ccss_evaluator_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 2, &mut d);
        assert_eq!(st, CcssStatus::OK);
        let st = ccss_evaluator_eval_batch(ev, qs.as_ptr(), 2, 1, res.as_mut_ptr(), 1, &mut d);
        assert_eq!((st, d.required), (CcssStatus::ERR_BUFFER_TOO_SMALL, 2));
        let mut buf = [0 as c_char; 64];
        assert!(ccss_error_detail_format(&d, buf.as_mut_ptr(), 64) > 0);
    }
    assert_eq!(alloc_count::get(), before, "evaluator / eval allocated");
    drop((tmem, gmem, emem));
}

/// The batch, which checks every query once up front and then evaluates
/// without a second check, gives bit for bit the results of one call per
/// point, with and without second derivatives: on a triangular prism
/// (valence-3 corners, triangle sub-faces), with points near the
/// extraordinary vertices and the triangle centres (levels 1..=40 of the
/// eigen kernel) and uniform ones.
#[test]
fn batch_is_single_calls_bit_for_bit() {
    let b = tri_quad_prism();
    let mut rnd = unit_rng(0x2545_F491_4F6C_DD1D);
    let subs = [3u32, 3, 1, 1, 1];
    let mut qs = Vec::new();
    for k in 0..600u32 {
        let face = k % 5;
        let sub = (k / 5) % subs[face as usize];
        // Uniform, or within 2^-(1 + k % 40) of the corner (0, 0).
        let scale = if k % 3 == 0 {
            1.0
        } else {
            0.5f64.powi((1 + k % 40) as i32)
        };
        let (u, v) = (rnd() * scale, rnd() * scale);
        qs.push(CcssEvaluatorQuery { face, sub, u, v });
    }
    let bits = |r: &CcssEvaluatorResult| {
        [r.p, r.du, r.dv, r.duu, r.duv, r.dvv, r.normal].map(|a| a.map(f64::to_bits))
    };
    for second in [0, 1] {
        let mut out = vec![CcssEvaluatorResult::default(); qs.len()];
        let mut d = Failure::invalid("x").to_detail();
        unsafe {
            let st = ccss_evaluator_eval_batch(
                b.ev,
                qs.as_ptr(),
                qs.len(),
                second,
                out.as_mut_ptr(),
                out.len(),
                &mut d,
            );
            assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        }
        for (q, o) in qs.iter().zip(&out) {
            let mut r = CcssEvaluatorResult::default();
            let f = if second == 1 {
                ccss_evaluator_eval_second
            } else {
                ccss_evaluator_eval
            };
            let st = unsafe { f(b.ev, q.face, q.sub, q.u, q.v, &mut r, ptr::null_mut()) };
            assert_eq!(st, CcssStatus::OK);
            assert_eq!(bits(&r), bits(o), "{q:?} second {second}");
        }
    }
}

/// `ccss_evaluator_build_with_options`: every option set evaluates bit for
/// bit as the default build (near and far from the extraordinary vertices
/// and N-gon centres, with second derivatives), its size query is exact
/// (8 bytes less is BUFFER_TOO_SMALL with the size), the sizes order as
/// the options keep more, and bad options are refused with nothing
/// written.
#[test]
fn options_change_memory_not_results() {
    let b = tri_quad_prism();
    let subs = [3u32, 3, 1, 1, 1];
    let mut qs = Vec::new();
    for k in 0..400u32 {
        let face = k % 5;
        let sub = (k / 5) % subs[face as usize];
        let h = 0.5f64.powi((k % 36) as i32);
        qs.push((face, sub, 0.37 * h, 0.81 * h));
    }
    let bits = |r: &CcssEvaluatorResult| {
        [r.p, r.du, r.dv, r.duu, r.duv, r.dvv, r.normal].map(|a| a.map(f64::to_bits))
    };
    let eval_all = |ev: *const CcssEvaluator| {
        qs.iter()
            .map(|&(f, sb, u, v)| {
                let mut r = CcssEvaluatorResult::default();
                let st =
                    unsafe { ccss_evaluator_eval_second(ev, f, sb, u, v, &mut r, ptr::null_mut()) };
                assert_eq!(st, CcssStatus::OK);
                bits(&r)
            })
            .collect::<Vec<_>>()
    };
    let want = eval_all(b.ev);
    let (mut full, mut compact) = (
        CcssEvaluatorOptions {
            subpatch_grids: 9,
            corner_bounds: 9,
            deep_levels: 99,
        },
        CcssEvaluatorOptions {
            subpatch_grids: 9,
            corner_bounds: 9,
            deep_levels: 99,
        },
    );
    unsafe {
        assert_eq!(
            ccss_evaluator_options_default(&mut full, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_evaluator_options_compact(&mut compact, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    assert_eq!(
        (full.subpatch_grids, full.corner_bounds, full.deep_levels),
        (1, 1, 24)
    );
    assert_eq!(
        (
            compact.subpatch_grids,
            compact.corner_bounds,
            compact.deep_levels
        ),
        (0, 0, 0)
    );
    let deep = |l: u8| CcssEvaluatorOptions {
        deep_levels: l,
        ..full
    };
    let mut sizes = Vec::new();
    for o in [compact, deep(0), deep(5), full, deep(32)] {
        let mut d = Failure::invalid("x").to_detail();
        let mut need = 0usize;
        let st = unsafe {
            ccss_evaluator_required_bytes_with_options(b.topo, b.tables, &o, &mut need, &mut d)
        };
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        sizes.push(need);
        let mut mem = block(need);
        let mut ev = ptr::null();
        let st = unsafe {
            ccss_evaluator_build_with_options(
                b.topo,
                b.tables,
                &o,
                mem.as_mut_ptr().cast(),
                need - 8,
                &mut ev,
                &mut d,
            )
        };
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(d.required, need as u64);
        assert!(ev.is_null(), "nothing written on failure");
        let st = unsafe {
            ccss_evaluator_build_with_options(
                b.topo,
                b.tables,
                &o,
                mem.as_mut_ptr().cast(),
                need,
                &mut ev,
                &mut d,
            )
        };
        assert_eq!(st, CcssStatus::OK, "{}", msg(&d));
        assert!(eval_all(ev) == want, "{o:?} evaluates as the default build");
    }
    assert_eq!(
        sizes[3], b.eval_bytes,
        "the default options are ccss_evaluator_build's"
    );
    assert!(sizes.windows(2).all(|w| w[0] < w[1]), "{sizes:?}");
    for (bad, what) in [
        (deep(33), "deep_levels"),
        (
            CcssEvaluatorOptions {
                subpatch_grids: 2,
                ..full
            },
            "subpatch_grids",
        ),
        (
            CcssEvaluatorOptions {
                corner_bounds: 7,
                ..full
            },
            "corner_bounds",
        ),
    ] {
        let mut d = Failure::invalid("x").to_detail();
        let mut need = 12345usize;
        let st = unsafe {
            ccss_evaluator_required_bytes_with_options(b.topo, b.tables, &bad, &mut need, &mut d)
        };
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        assert!(msg(&d).contains(what), "{}", msg(&d));
        assert_eq!(need, 12345);
    }
    let mut need = 0usize;
    let st = unsafe {
        ccss_evaluator_required_bytes_with_options(
            b.topo,
            b.tables,
            ptr::null(),
            &mut need,
            ptr::null_mut(),
        )
    };
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
}

/// A prism of two triangles and three quads (valence-3 corners and two
/// triangle centres; sub-faces per face 3, 3, 1, 1, 1), built with the
/// standard tables.
fn tri_quad_prism() -> Built {
    let p = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 1.2, 0.0, 1.0, 0.9,
    ];
    let s = [3u32, 3, 4, 4, 4];
    let i = [0u32, 2, 1, 3, 4, 5, 0, 1, 4, 3, 1, 2, 5, 4, 2, 0, 3, 5];
    build_mesh(&p, &s, &i, &[])
}

/// The C ABI's evaluations (`ccss_evaluator_eval`, `_eval_second`, one
/// call per point, and `ccss_evaluator_eval_batch`, which write straight
/// into the caller's results) give bit for bit the Rust API's
/// `Evaluator::eval` / `eval_second` (value-returning, an independent
/// path through the evaluator), including the normal and the zero second
/// derivatives of the first-derivative calls. Two meshes: an 8 x 8 torus
/// with two pairs of quads merged into hexagons (regular patches, patches
/// with one extraordinary vertex, quads split for two, hexagon sub-faces
/// with a regular and with a valence-3 corner) and the triangular prism
/// (every patch extraordinary); points uniform, near every corner down to
/// `2^-45` (every level of the stored grids and the kernel beyond, the
/// N-gon centres at (1, 1)) and on the edges. The `_derivs` entries
/// (`ccss_evaluator_eval_derivs`, `_eval_second_derivs`,
/// `_eval_batch_derivs`) give the same bits with a zero normal, as the
/// Rust API's `eval_derivs` / `eval_second_derivs`. Bad queries fail with the
/// Rust API's error and leave the result untouched.
#[test]
fn c_abi_is_the_rust_api_bit_for_bit() {
    let torus = holed_torus();
    let prism = tri_quad_prism();
    let bits = |r: &CcssEvaluatorResult| {
        [r.p, r.du, r.dv, r.duu, r.duv, r.dvv, r.normal].map(|a| a.map(f64::to_bits))
    };
    let mut rnd = unit_rng(0x0123_4567_89AB_CDEF);
    let mut checked = 0;
    for b in [&torus, &prism] {
        // SAFETY: a live handle built by `build_mesh`.
        let ev = unsafe { &(*b.ev).ev };
        let mut qs = Vec::new();
        for face in 0..ev.num_faces() as u32 {
            for sub in 0..ev.num_subfaces(face as usize) as u32 {
                for k in 0..48u32 {
                    let (a, c) = (rnd(), rnd());
                    let (u, v) = match k % 4 {
                        0 => (a, c),
                        1 => (0.0, c),
                        2 => (1.0, a),
                        _ => (a, 1.0),
                    };
                    qs.push(CcssEvaluatorQuery { face, sub, u, v });
                    // Near corner k % 4 at level k (u or v may be 0).
                    let h = 0.5f64.powi(k as i32 % 46);
                    let (x, y) = (a * h, if k % 5 == 0 { 0.0 } else { c * h });
                    let (u, v) =
                        [(x, y), (1.0 - x, y), (1.0 - x, 1.0 - y), (x, 1.0 - y)][k as usize % 4];
                    qs.push(CcssEvaluatorQuery { face, sub, u, v });
                }
            }
        }
        for second in [false, true] {
            let batch = |f: BatchFn| {
                let mut out = vec![CcssEvaluatorResult::default(); qs.len()];
                let st = unsafe {
                    f(
                        b.ev,
                        qs.as_ptr(),
                        qs.len(),
                        second as c_int,
                        out.as_mut_ptr(),
                        out.len(),
                        ptr::null_mut(),
                    )
                };
                assert_eq!(st, CcssStatus::OK);
                out
            };
            let out = batch(ccss_evaluator_eval_batch);
            let out_derivs = batch(ccss_evaluator_eval_batch_derivs);
            for ((q, o), od) in qs.iter().zip(&out).zip(&out_derivs) {
                let want = if second {
                    ev.eval_second(q.face, q.sub, q.u, q.v)
                } else {
                    ev.eval(q.face, q.sub, q.u, q.v)
                }
                .unwrap();
                let want = CcssEvaluatorResult::from(want);
                let mut r = CcssEvaluatorResult::default();
                let f = if second {
                    ccss_evaluator_eval_second
                } else {
                    ccss_evaluator_eval
                };
                let st = unsafe { f(b.ev, q.face, q.sub, q.u, q.v, &mut r, ptr::null_mut()) };
                assert_eq!(st, CcssStatus::OK);
                assert_eq!(bits(&r), bits(&want), "{q:?} second {second}");
                assert_eq!(bits(o), bits(&want), "batch {q:?} second {second}");
                // Without the normal: the same bits, a zero normal.
                let want = CcssEvaluatorResult {
                    normal: [0.0; 3],
                    ..want
                };
                let d = if second {
                    ev.eval_second_derivs(q.face, q.sub, q.u, q.v)
                } else {
                    ev.eval_derivs(q.face, q.sub, q.u, q.v)
                }
                .unwrap();
                assert_eq!(bits(&CcssEvaluatorResult::from(d)), bits(&want), "{q:?}");
                let f = if second {
                    ccss_evaluator_eval_second_derivs
                } else {
                    ccss_evaluator_eval_derivs
                };
                let mut r = CcssEvaluatorResult {
                    normal: [5.0; 3],
                    ..Default::default()
                };
                let st = unsafe { f(b.ev, q.face, q.sub, q.u, q.v, &mut r, ptr::null_mut()) };
                assert_eq!(st, CcssStatus::OK);
                assert_eq!(bits(&r), bits(&want), "derivs {q:?} second {second}");
                assert_eq!(bits(od), bits(&want), "batch derivs {q:?} second {second}");
                checked += 1;
            }
        }
        // Bad queries: the Rust API's error, the result untouched.
        let nf = ev.num_faces() as u32;
        for (face, sub, u, v) in [
            (nf, 0, 0.5, 0.5),
            (0, 9, 0.5, 0.5),
            (1, 0, -0.0 - 1e-300, 0.5),
            (1, 0, 0.5, 1.0 + f64::EPSILON),
            (2, 0, f64::NAN, 0.5),
        ] {
            let want = Failure::from(ev.eval(face, sub, u, v).unwrap_err()).status;
            for f in [
                ccss_evaluator_eval,
                ccss_evaluator_eval_second,
                ccss_evaluator_eval_derivs,
                ccss_evaluator_eval_second_derivs,
            ] {
                let mut r = CcssEvaluatorResult {
                    p: [7.0; 3],
                    ..Default::default()
                };
                let keep = bits(&r);
                let st = unsafe { f(b.ev, face, sub, u, v, &mut r, ptr::null_mut()) };
                assert_eq!(st, want, "({face}, {sub}, {u}, {v})");
                assert_eq!(bits(&r), keep, "written on failure");
            }
        }
    }
    // Slots: 60 quads and two hexagons (6 each), the prism's 9; 96 points
    // each, with and without second derivatives.
    assert_eq!(checked, (60 + 12 + 9) * 96 * 2);
}

/// The signature of `ccss_evaluator_eval_batch` and `_batch_derivs`.
type BatchFn = unsafe extern "C" fn(
    *const CcssEvaluator,
    *const CcssEvaluatorQuery,
    usize,
    c_int,
    *mut CcssEvaluatorResult,
    usize,
    *mut CcssErrorDetail,
) -> CcssStatus;

/// An 8 x 8 torus of quads with the quad pairs (1, 1) + (2, 1) and
/// (1, 3) + (2, 3) merged into hexagons (their shared vertices get valence
/// 3), vertices jittered.
fn holed_torus() -> Built {
    let n = 8u32;
    let mut p = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (
                i as f64 * core::f64::consts::TAU / n as f64,
                j as f64 * core::f64::consts::TAU / n as f64,
            );
            let r = 3.0 + (1.0 + 0.05 * ((i * 7 + j * 3) % 5) as f64) * b.cos();
            p.extend([r * a.cos(), r * a.sin(), b.sin()]);
        }
    }
    let v = |i: u32, j: u32| (i % n) * n + j % n;
    let (mut s, mut idx) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in 0..n {
            let merged = (i == 1 || i == 2) && (j == 1 || j == 3);
            if merged && i == 1 {
                s.push(6);
                idx.extend([
                    v(1, j),
                    v(2, j),
                    v(3, j),
                    v(3, j + 1),
                    v(2, j + 1),
                    v(1, j + 1),
                ]);
            } else if !(merged && i == 2) {
                s.push(4);
                idx.extend([v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
    }
    build_mesh(&p, &s, &idx, &[])
}
