//! The slot index through the C ABI: exact size errors with nothing
//! written; with an index attached, every hit of a ray, inside/outside and
//! the slice sizes bit for bit those without it, the first hit and the
//! closest distance within the tolerance, on the smooth and the feature
//! evaluator; an index used with another evaluator is refused; detaching
//! works; no allocation.

use super::feature::{all_edges_sharp_cube, defaults, make};
use super::query_band::query;
use super::*;
use core::ffi::c_void;

type Bytes<E> = unsafe extern "C" fn(*const E, *mut usize, *mut CcssErrorDetail) -> CcssStatus;
type Build<E> = unsafe extern "C" fn(
    *const E,
    *mut c_void,
    usize,
    *mut *mut CcssQueryIndex,
    *mut CcssErrorDetail,
) -> CcssStatus;

/// Size query, a block one word short (BUFFER_TOO_SMALL, `*out` not
/// written), then the index.
unsafe fn index_of<E>(
    ev: *const E,
    bytes: Bytes<E>,
    build: Build<E>,
) -> (Vec<u64>, *mut CcssQueryIndex) {
    let mut d = Failure::invalid("x").to_detail();
    let mut n = 0usize;
    unsafe {
        assert_eq!(bytes(ev, &mut n, &mut d), CcssStatus::OK);
        let mut mem = block(n);
        let mut ix = ptr::null_mut();
        let st = build(ev, mem.as_mut_ptr().cast(), n - 8, &mut ix, &mut d);
        assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
        assert_eq!(d.required, n as u64);
        assert!(ix.is_null());
        assert_eq!(
            build(ev, mem.as_mut_ptr().cast(), n, &mut ix, &mut d),
            CcssStatus::OK
        );
        assert_eq!(ix as *const u8, mem.as_ptr() as *const u8);
        (mem, ix)
    }
}

/// Rays from all around the origin aimed near it.
fn rays() -> Vec<CcssQueryRay> {
    let mut r = unit_rng(0x1d3_5eed);
    (0..64)
        .map(|_| {
            let o = [r() - 0.5, r() - 0.5, r() - 0.5];
            let l = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt().max(1e-3);
            let origin = o.map(|x| 4.0 * x / l);
            let t = [r() - 0.5, r() - 0.5, r() - 0.5];
            CcssQueryRay {
                origin,
                dir: [t[0] - origin[0], t[1] - origin[1], t[2] - origin[2]],
            }
        })
        .collect()
}

/// The query exports of one evaluator kind.
struct Fns<E> {
    ray_all: unsafe extern "C" fn(
        *const E,
        *mut CcssQuery,
        *const CcssQueryRay,
        f64,
        *mut CcssQueryHit,
        usize,
        *mut usize,
        *mut CcssErrorDetail,
    ) -> CcssStatus,
    ray_first: unsafe extern "C" fn(
        *const E,
        *mut CcssQuery,
        *const CcssQueryRay,
        usize,
        f64,
        *mut CcssQueryHit,
        *mut c_int,
        *mut CcssErrorDetail,
    ) -> CcssStatus,
    closest: unsafe extern "C" fn(
        *const E,
        *mut CcssQuery,
        *const f64,
        usize,
        f64,
        *mut CcssQueryClosestInfo,
        *mut CcssErrorDetail,
    ) -> CcssStatus,
    inside: unsafe extern "C" fn(
        *const E,
        *mut CcssQuery,
        *const f64,
        f64,
        *mut c_int,
        *mut CcssErrorDetail,
    ) -> CcssStatus,
    slice_bytes: unsafe extern "C" fn(
        *const E,
        *mut CcssQuery,
        *const f64,
        f64,
        f64,
        *mut usize,
        *mut CcssErrorDetail,
    ) -> CcssStatus,
}

const SMOOTH: Fns<CcssEvaluator> = Fns {
    ray_all: ccss_query_ray_all,
    ray_first: ccss_query_ray_first,
    closest: ccss_query_closest,
    inside: ccss_query_inside,
    slice_bytes: ccss_query_slice_required_bytes,
};

const FEATURE: Fns<CcssFeatureEvaluator> = Fns {
    ray_all: ccss_query_feature_ray_all,
    ray_first: ccss_query_feature_ray_first,
    closest: ccss_query_feature_closest,
    inside: ccss_query_feature_inside,
    slice_bytes: ccss_query_feature_slice_required_bytes,
};

/// Every query on `qi` (index attached) and on `qp` (none) gives the same
/// answers; returns the hits compared.
unsafe fn same_answers<E>(
    f: &Fns<E>,
    ev: *const E,
    qi: *mut CcssQuery,
    qp: *mut CcssQuery,
    rays: &[CcssQueryRay],
) -> usize {
    let mut d = Failure::invalid("x").to_detail();
    let tol = 1e-9;
    let mut total = 0;
    unsafe {
        for (k, r) in rays.iter().enumerate() {
            let mut a = [CcssQueryHit::default(); 16];
            let mut b = [CcssQueryHit::default(); 16];
            let (mut na, mut nb) = (0usize, 0usize);
            assert_eq!(
                (f.ray_all)(ev, qp, r, tol, a.as_mut_ptr(), 16, &mut na, &mut d),
                CcssStatus::OK
            );
            assert_eq!(
                (f.ray_all)(ev, qi, r, tol, b.as_mut_ptr(), 16, &mut nb, &mut d),
                CcssStatus::OK
            );
            assert_eq!(a[..na], b[..nb], "ray {k}");
            total += na;
            let (mut ha, mut hb) = (CcssQueryHit::default(), CcssQueryHit::default());
            let (mut fa, mut fb) = (7 as c_int, 7 as c_int);
            assert_eq!(
                (f.ray_first)(ev, qp, r, 1, tol, &mut ha, &mut fa, &mut d),
                CcssStatus::OK
            );
            assert_eq!(
                (f.ray_first)(ev, qi, r, 1, tol, &mut hb, &mut fb, &mut d),
                CcssStatus::OK
            );
            assert_eq!(fa, fb, "ray {k}");
            assert_eq!(fa, (na > 0) as c_int);
            if fa == 1 {
                let l = (r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2]).sqrt();
                assert!(
                    (ha.t - hb.t).abs() * l <= tol,
                    "ray {k}: {} / {}",
                    ha.t,
                    hb.t
                );
            }
            // The ray's origin as a closest-point and inside query.
            let (mut ca, mut cb) = (
                CcssQueryClosestInfo::default(),
                CcssQueryClosestInfo::default(),
            );
            assert_eq!(
                (f.closest)(ev, qp, r.origin.as_ptr(), 1, tol, &mut ca, &mut d),
                CcssStatus::OK
            );
            assert_eq!(
                (f.closest)(ev, qi, r.origin.as_ptr(), 1, tol, &mut cb, &mut d),
                CcssStatus::OK
            );
            assert!(
                (ca.dist - cb.dist).abs() <= tol,
                "point {k}: {} / {}",
                ca.dist,
                cb.dist
            );
            let p = r.origin.map(|x| 0.2 * x);
            let (mut ia, mut ib) = (7 as c_int, 7 as c_int);
            assert_eq!(
                (f.inside)(ev, qp, p.as_ptr(), tol, &mut ia, &mut d),
                CcssStatus::OK
            );
            assert_eq!(
                (f.inside)(ev, qi, p.as_ptr(), tol, &mut ib, &mut d),
                CcssStatus::OK
            );
            assert_eq!(ia, ib, "inside {k}");
        }
        for z in [-0.95, -0.5, 0.0, 0.3, 0.7, 0.99] {
            let (mut sa, mut sb) = (0usize, 1usize);
            let n = [0.1, 0.2, 1.0];
            assert_eq!(
                (f.slice_bytes)(ev, qp, n.as_ptr(), z, 1e-4, &mut sa, &mut d),
                CcssStatus::OK
            );
            assert_eq!(
                (f.slice_bytes)(ev, qi, n.as_ptr(), z, 1e-4, &mut sb, &mut d),
                CcssStatus::OK
            );
            assert_eq!(sa, sb, "slice at {z}");
        }
    }
    total
}

#[test]
fn index_through_the_c_abi() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let other = build_mesh(&p, &s, &i, &[]);
    let (fp, fs, fi, ft) = all_edges_sharp_cube();
    let Ok((fe, _fm)) = make(&fp, &fs, &fi, &ft, &defaults()) else {
        panic!("build failed")
    };
    let (_qim, qi) = query();
    let (_qpm, qp) = query();
    let mut d = Failure::invalid("x").to_detail();
    let rs = rays();
    unsafe {
        let (_im, ix) = index_of(
            b.ev,
            ccss_query_index_required_bytes,
            ccss_query_index_build,
        );
        let (_fim, fix) = index_of(
            fe,
            ccss_query_feature_index_required_bytes,
            ccss_query_feature_index_build,
        );
        assert_eq!(ccss_query_set_index(qi, ix, &mut d), CcssStatus::OK);
        let before = alloc_count::get();
        let smooth = same_answers(&SMOOTH, b.ev, qi, qp, &rs);
        assert_eq!(alloc_count::get(), before, "no allocation");
        assert_eq!(ccss_query_set_index(qi, fix, &mut d), CcssStatus::OK);
        let feature = same_answers(&FEATURE, fe, qi, qp, &rs);
        assert!(smooth >= 60 && feature >= 60, "{smooth} {feature}");

        // The feature index with the smooth evaluator, the smooth index
        // with another evaluator: refused, nothing written.
        let r = rs[0];
        let mut h = [CcssQueryHit::default(); 4];
        let mut n = 9usize;
        let st = ccss_query_ray_all(b.ev, qi, &r, 1e-9, h.as_mut_ptr(), 4, &mut n, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        assert!(msg(&d).contains("another evaluator"), "{}", msg(&d));
        assert_eq!(n, 9);
        assert_eq!(ccss_query_set_index(qi, ix, &mut d), CcssStatus::OK);
        let st = ccss_query_ray_all(other.ev, qi, &r, 1e-9, h.as_mut_ptr(), 4, &mut n, &mut d);
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
        // Detached: the other evaluator answers.
        assert_eq!(
            ccss_query_set_index(qi, ptr::null(), &mut d),
            CcssStatus::OK
        );
        let st = ccss_query_ray_all(other.ev, qi, &r, 1e-9, h.as_mut_ptr(), 4, &mut n, &mut d);
        assert_eq!(st, CcssStatus::OK);
        // Not an index: refused, the area unchanged (still detached).
        let junk = block(256);
        let st = ccss_query_set_index(qi, junk.as_ptr().cast(), &mut d);
        assert_ne!(st, CcssStatus::OK);
        let st = ccss_query_ray_all(other.ev, qi, &r, 1e-9, h.as_mut_ptr(), 4, &mut n, &mut d);
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_query_set_index(ptr::null_mut(), ix, &mut d),
            CcssStatus::ERR_NULL_POINTER
        );
    }
}

/// The index block's raw-pointer life cycle (small enough for Miri): size
/// query, build, attach, a slice size and a refused ray through it (the
/// walks themselves are safe code, compared in `index_through_the_c_abi`),
/// detach, a foreign block refused.
#[test]
fn index_block_life_cycle() {
    let (p, s, i) = cube();
    let b = build_mesh(&p, &s, &i, &[]);
    let (_qm, q) = query();
    let mut d = Failure::invalid("x").to_detail();
    unsafe {
        let (_im, ix) = index_of(
            b.ev,
            ccss_query_index_required_bytes,
            ccss_query_index_build,
        );
        assert_eq!(ccss_query_set_index(q, ix, &mut d), CcssStatus::OK);
        // A plane beyond the cube: every slot box is skipped.
        let (n, mut bytes) = ([0.0, 0.0, 1.0], 7usize);
        let st =
            ccss_query_slice_required_bytes(b.ev, q, n.as_ptr(), 100.0, 1e-3, &mut bytes, &mut d);
        assert_eq!((st, bytes), (CcssStatus::OK, 0));
        // A bad ray passes the index and fails its own check.
        let r = CcssQueryRay {
            origin: [0.2, 0.1, 3.0],
            dir: [0.0; 3],
        };
        let (mut h, mut found) = (CcssQueryHit::default(), 7 as c_int);
        let st = ccss_query_ray_first(b.ev, q, &r, 1, 1e-9, &mut h, &mut found, &mut d);
        assert_eq!((st, found), (CcssStatus::ERR_INVALID_ARGUMENT, 7));
        assert_eq!(ccss_query_set_index(q, ptr::null(), &mut d), CcssStatus::OK);
        let junk = block(64);
        assert_ne!(
            ccss_query_set_index(q, junk.as_ptr().cast(), &mut d),
            CcssStatus::OK
        );
    }
}
