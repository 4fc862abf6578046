//! `ccss_boolean_*`: exact block size through BUFFER_TOO_SMALL, counts,
//! emission (short buffer first), closed output, statuses 34 and 35,
//! NULL and bad-argument checks, no allocation.

use super::*;
use crate::boolean::*;

/// A box of half size `h` at `c`, rotated about z by `a`, 12 triangles.
fn boxed(c: [f64; 3], h: f64, a: f64) -> ([f64; 24], [u32; 36]) {
    let mut p = [0.0; 24];
    let (s, co) = a.sin_cos();
    for i in 0..8 {
        let x = if i & 1 != 0 { h } else { -h };
        let y = if i & 2 != 0 { h } else { -h };
        let z = if i & 4 != 0 { h } else { -h };
        p[3 * i] = c[0] + co * x - s * y;
        p[3 * i + 1] = c[1] + s * x + co * y;
        p[3 * i + 2] = c[2] + z;
    }
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut t = [0u32; 36];
    for (f, q) in quads.iter().enumerate() {
        t[6 * f..6 * f + 6].copy_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
    }
    (p, t)
}

fn mesh(p: &[f64; 24], t: &[u32]) -> CcssBooleanMesh {
    CcssBooleanMesh {
        positions: p.as_ptr(),
        num_vertices: 8,
        triangles: t.as_ptr(),
        num_triangles: t.len() / 3,
    }
}

#[test]
#[cfg_attr(
    miri,
    ignore = "too slow under Miri: exact-predicate Boolean of two boxes, minutes interpreted"
)]
fn build_counts_emit_and_errors() {
    let (pa, ta) = boxed([0.0; 3], 1.0, 0.0);
    let (pb, tb) = boxed([0.61, 0.43, 0.37], 0.9, 0.53);
    let (a, b) = (mesh(&pa, &ta), mesh(&pb, &tb));
    let opts = CcssBooleanOptions::default();
    let mut d = Failure::invalid("x").to_detail();
    let mut base = 0usize;
    let st = unsafe { ccss_boolean_required_bytes(&a, &b, &mut base, &mut d) };
    assert_eq!(st, CcssStatus::OK);
    let mut mem = vec![0u64; base / 8 + 1];
    let mut h: *mut CcssBoolean = ptr::null_mut();
    let op = CcssBooleanOp::BOOLEAN_DIFFERENCE as u32;
    let st = unsafe {
        ccss_boolean_build(
            &a,
            &b,
            op,
            &opts,
            mem.as_mut_ptr().cast(),
            base,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
    assert!(h.is_null());
    let need = d.required as usize;
    assert!(need > base);
    let mut mem = vec![0u64; need / 8];
    let before = alloc_count::get();
    let st = unsafe {
        ccss_boolean_build(
            &a,
            &b,
            op,
            &opts,
            mem.as_mut_ptr().cast(),
            need,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::OK, "{}", d.status as i32);
    assert_eq!(alloc_count::get(), before, "the build allocated");
    let mut c = CcssBooleanCountsInfo::default();
    assert_eq!(
        unsafe { ccss_boolean_counts(h, &mut c, &mut d) },
        CcssStatus::OK
    );
    assert!(c.triangles > 12 && c.curve_loops >= 1 && c.amplification >= 1.0);
    let mut pos = vec![0.0; 3 * c.vertices];
    let mut tri = vec![0u32; 3 * c.triangles];
    let mut cs = vec![0u32; c.curve_loops];
    let mut ci = vec![0u32; c.curve_points];
    let mut o = CcssBooleanOutput {
        positions: pos.as_mut_ptr(),
        positions_len: pos.len(),
        triangles: tri.as_mut_ptr(),
        triangles_len: tri.len() - 1,
        sources: ptr::null_mut(),
        sources_len: 0,
        curve_sizes: cs.as_mut_ptr(),
        curve_sizes_len: cs.len(),
        curve_indices: ci.as_mut_ptr(),
        curve_indices_len: ci.len(),
    };
    assert_eq!(
        unsafe { ccss_boolean_emit(h, &o, &mut d) },
        CcssStatus::ERR_BUFFER_TOO_SMALL
    );
    assert_eq!(d.required as usize, 3 * c.triangles);
    assert!(pos.iter().all(|&x| x == 0.0));
    o.triangles_len += 1;
    let before = alloc_count::get();
    assert_eq!(unsafe { ccss_boolean_emit(h, &o, &mut d) }, CcssStatus::OK);
    assert_eq!(alloc_count::get(), before, "the emission allocated");
    // Closed: every directed edge once, with its reverse.
    let mut e = std::collections::HashMap::new();
    for t in tri.chunks_exact(3) {
        for k in 0..3 {
            *e.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    assert!(e
        .iter()
        .all(|(&(x, y), &n)| n == 1 && e.get(&(y, x)) == Some(&1)));
    // Parameter-space provenance: each input triangle's (u, v) are its
    // vertices' x and y, so every output vertex's (u, v) must be its x, y
    // (barycentric mapping of a linear function).
    let patches = |p: &[f64; 24], t: &[u32]| -> Vec<CcssBooleanPatchTriangle> {
        t.chunks_exact(3)
            .enumerate()
            .map(|(k, c)| {
                let mut uv = [0.0; 6];
                for j in 0..3 {
                    uv[2 * j] = p[3 * c[j] as usize];
                    uv[2 * j + 1] = p[3 * c[j] as usize + 1];
                }
                CcssBooleanPatchTriangle {
                    face: k as u32,
                    sub: 0,
                    uv,
                }
            })
            .collect()
    };
    let (ua, ub) = (patches(&pa, &ta), patches(&pb, &tb));
    let mut uv = vec![CcssBooleanUv::default(); c.triangles];
    let emit_uv = |uv: &mut [CcssBooleanUv], n: usize, a_len: usize, d: &mut CcssErrorDetail| unsafe {
        ccss_boolean_emit_uv(
            h,
            ua.as_ptr(),
            a_len,
            ub.as_ptr(),
            ub.len(),
            uv.as_mut_ptr(),
            n,
            d,
        )
    };
    let st = emit_uv(&mut uv, c.triangles - 1, ua.len(), &mut d);
    assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
    assert_eq!(d.required as usize, c.triangles);
    assert!(uv.iter().all(|u| *u == CcssBooleanUv::default()));
    let st = emit_uv(&mut uv, c.triangles, ua.len() - 1, &mut d);
    assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
    let before = alloc_count::get();
    assert_eq!(
        emit_uv(&mut uv, c.triangles, ua.len(), &mut d),
        CcssStatus::OK
    );
    assert_eq!(alloc_count::get(), before, "emit_uv allocated");
    let mut worst = 0.0f64;
    for (k, u) in uv.iter().enumerate() {
        for j in 0..3 {
            let v = tri[3 * k + j] as usize;
            worst = worst
                .max((u.uv[2 * j] - pos[3 * v]).abs())
                .max((u.uv[2 * j + 1] - pos[3 * v + 1]).abs());
        }
        assert!(u.solid <= 1 && (u.face as usize) < 12 && u.reserved == 0);
    }
    assert!(worst <= 1e-12, "barycentric (u, v) off by {worst:e}");
    let st = unsafe {
        ccss_boolean_emit_uv(
            h,
            ua.as_ptr(),
            ua.len(),
            ub.as_ptr(),
            ub.len(),
            ptr::null_mut(),
            0,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
    // Errors.
    let st = unsafe { ccss_boolean_counts(h, ptr::null_mut(), &mut d) };
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
    let st = unsafe {
        ccss_boolean_build(
            &a,
            &b,
            7,
            &opts,
            mem.as_mut_ptr().cast(),
            need,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
    let open = mesh(&pa, &ta[..33]);
    let st = unsafe {
        ccss_boolean_build(
            &open,
            &b,
            op,
            &opts,
            mem.as_mut_ptr().cast(),
            need,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_NOT_CLOSED_SOLID);
    let strict = CcssBooleanOptions {
        max_amplification: 1.0 + 1e-12,
    };
    let st = unsafe {
        ccss_boolean_build(
            &a,
            &b,
            op,
            &strict,
            mem.as_mut_ptr().cast(),
            need,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_NEAR_TANGENTIAL);
    assert!((0..12).contains(&d.face) && (0..12).contains(&d.value));
    // Coplanar faces: degenerate contact.
    let (pc, tc) = boxed([2.0, 0.3, 0.2], 1.0, 0.0);
    let cm = mesh(&pc, &tc);
    let mut big = vec![0u64; 1 << 16];
    let st = unsafe {
        ccss_boolean_build(
            &a,
            &cm,
            op,
            &opts,
            big.as_mut_ptr().cast(),
            8 << 16,
            &mut h,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_DEGENERATE_CONTACT);
    for (s, v, want) in [
        (CcssStatus::ERR_NEAR_TANGENTIAL, 34, "tangentially"),
        (CcssStatus::ERR_DEGENERATE_CONTACT, 35, "degenerately"),
    ] {
        assert_eq!(s as c_int, v);
        let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(v)) };
        assert!(m.to_str().unwrap().contains(want), "{m:?}");
    }
}
