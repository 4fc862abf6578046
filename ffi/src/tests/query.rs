//! The queries' C ABI: build, the checks of every argument, exact size
//! errors with nothing written, and no allocation.

use super::*;

fn query() -> (Vec<u64>, *mut CcssQuery) {
    let mut n = 0usize;
    let mut q = ptr::null_mut();
    unsafe {
        assert_eq!(
            ccss_query_required_bytes(&mut n, ptr::null_mut()),
            CcssStatus::OK
        );
        let mut mem = block(n);
        // Too small, then right.
        let st = ccss_query_build(mem.as_mut_ptr().cast(), n - 8, &mut q, ptr::null_mut());
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert!(q.is_null());
        let st = ccss_query_build(mem.as_mut_ptr().cast(), n, &mut q, ptr::null_mut());
        assert_eq!(st, CcssStatus::OK);
        (mem, q)
    }
}

#[test]
fn queries_check_arguments_and_do_not_allocate() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let (_mem, q) = query();
    let mut d = Failure::invalid("x").to_detail();
    let before = alloc_count::get();
    unsafe {
        // Rays: a batch with a bad second ray is rejected before any cast.
        let rays = [
            CcssQueryRay {
                origin: [0.1, 0.2, -5.0],
                dir: [0.0, 0.0, 1.0],
            },
            CcssQueryRay {
                origin: [0.0; 3],
                dir: [0.0; 3],
            },
        ];
        let mut hits = [CcssQueryHit::default(); 2];
        let mut found = [7 as c_int; 2];
        let st = ccss_query_ray_first(
            b.ev,
            q,
            rays.as_ptr(),
            2,
            1e-9,
            hits.as_mut_ptr(),
            found.as_mut_ptr(),
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        assert_eq!(d.query_index, 1);
        assert_eq!(found, [7, 7], "nothing written");
        let st = ccss_query_ray_first(
            b.ev,
            q,
            rays.as_ptr(),
            1,
            0.0,
            hits.as_mut_ptr(),
            found.as_mut_ptr(),
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        let st = ccss_query_ray_first(
            b.ev,
            q,
            rays.as_ptr(),
            1,
            1e-9,
            ptr::null_mut(),
            found.as_mut_ptr(),
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        let st = ccss_query_ray_first(
            b.ev,
            q,
            rays.as_ptr(),
            1,
            1e-9,
            hits.as_mut_ptr(),
            found.as_mut_ptr(),
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(found[0], 1);
        assert!(hits[0].transversal == 1 && hits[0].point[2] < 0.0);
        // All hits: size query, one short, exact.
        let mut n = 0usize;
        let st = ccss_query_ray_all(b.ev, q, &rays[0], 1e-9, ptr::null_mut(), 0, &mut n, &mut d);
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(d.required, 2);
        hits[1].t = -1.0;
        let st = ccss_query_ray_all(
            b.ev,
            q,
            &rays[0],
            1e-9,
            hits.as_mut_ptr(),
            1,
            &mut n,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(hits[1].t, -1.0);
        let st = ccss_query_ray_all(
            b.ev,
            q,
            &rays[0],
            1e-9,
            hits.as_mut_ptr(),
            2,
            &mut n,
            &mut d,
        );
        assert_eq!((st, n), (CcssStatus::OK, 2));
        assert!(hits[0].t < hits[1].t);
        // Inside, closest.
        let mut inside = 5 as c_int;
        let st = ccss_query_inside(b.ev, q, [0.0f64; 3].as_ptr(), 1e-9, &mut inside, &mut d);
        assert_eq!((st, inside), (CcssStatus::OK, 1));
        let st = ccss_query_inside(
            b.ev,
            ptr::null_mut(),
            [0.0f64; 3].as_ptr(),
            1e-9,
            &mut inside,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
        let pts = [0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0];
        let mut near = [CcssQueryClosestInfo::default(); 2];
        let st = ccss_query_closest(b.ev, q, pts.as_ptr(), 2, 1e-9, near.as_mut_ptr(), &mut d);
        assert_eq!((st, d.query_index), (CcssStatus::ERR_INVALID_ARGUMENT, 1));
        let st = ccss_query_closest(b.ev, q, pts.as_ptr(), 1, 1e-9, near.as_mut_ptr(), &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert!(near[0].dist > 0.5 && near[0].dist < 1.0 && near[0].gap <= 1e-9);
        // Slices: scratch size, misaligned scratch, write with exact sizes.
        let normal = [0.0, 0.0, 1.0];
        let mut bytes = 0usize;
        let st = ccss_query_slice_required_bytes(
            b.ev,
            q,
            normal.as_ptr(),
            0.1,
            0.05,
            &mut bytes,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        let mut scratch = block(bytes + 8);
        let mut ls = CcssQuerySliceLayerStats::default();
        let st = ccss_query_slice_layer(
            b.ev,
            q,
            normal.as_ptr(),
            0.1,
            0.05,
            scratch.as_mut_ptr().cast::<u8>().add(4).cast(),
            bytes,
            &mut ls,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_MISALIGNED);
        let st = ccss_query_slice_layer(
            b.ev,
            q,
            normal.as_ptr(),
            0.1,
            0.05,
            scratch.as_mut_ptr().cast(),
            bytes - 1,
            &mut ls,
            &mut d,
        );
        assert_eq!(
            (st, d.required as usize),
            (CcssStatus::ERR_BUFFER_TOO_SMALL, bytes)
        );
        let st = ccss_query_slice_layer(
            b.ev,
            q,
            normal.as_ptr(),
            0.1,
            0.05,
            scratch.as_mut_ptr().cast(),
            bytes,
            &mut ls,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(ls.contours, 1);
        let np = ls.points as usize;
        let mut xy = vec![9.0f64; 2 * np];
        let mut cs = [CcssQueryContour::default(); 1];
        let st = ccss_query_slice_write(
            scratch.as_mut_ptr().cast(),
            bytes,
            &ls,
            xy.as_mut_ptr(),
            np - 1,
            cs.as_mut_ptr(),
            1,
            &mut d,
        );
        assert_eq!(
            (st, d.required as usize),
            (CcssStatus::ERR_BUFFER_TOO_SMALL, np)
        );
        assert!(xy.iter().all(|&x| x == 9.0));
        let st = ccss_query_slice_write(
            scratch.as_mut_ptr().cast(),
            bytes,
            &ls,
            xy.as_mut_ptr(),
            np,
            cs.as_mut_ptr(),
            1,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!((cs[0].start, cs[0].len as usize, cs[0].outer), (0, np, 1));
        let st = ccss_query_slice_required_bytes(
            b.ev,
            q,
            [0.0f64; 3].as_ptr(),
            0.1,
            0.05,
            &mut bytes,
            &mut d,
        );
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
    }
    // The test's own vec! above allocates once; the FFI calls nothing.
    assert_eq!(alloc_count::get() - before, 2);
}
