//! Statuses and error details: panics, message capacity, truncation.

use super::*;

#[test]
fn panics_become_a_status() {
    let mut d = Failure::invalid("x").to_detail();
    let st = guard(&mut d, || panic!("test panic"));
    assert_eq!(st, CcssStatus::ERR_INTERNAL);
    assert_eq!(d.status, CcssStatus::ERR_INTERNAL);
    let msg: Vec<u8> = d
        .message
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    assert!(std::str::from_utf8(&msg).unwrap().contains("panic"));
}

#[test]
fn every_message_fits() {
    // The longest core messages, with the largest numbers.
    let m = u32::MAX;
    let errs = [
        Error::IndexCountMismatch {
            expected: usize::MAX,
            got: usize::MAX,
        },
        Error::BoundaryEdge { v0: m, v1: m },
        Error::UnsupportedValence {
            vertex: m,
            valence: m,
        },
        Error::FaceTooLarge { face: m, size: m },
        Error::InconsistentOrientation { v0: m, v1: m },
        Error::InvalidWeights {
            valence: m,
            problem: ccss_core::WeightsProblem::RegularValence,
        },
        Error::NotAnEdge { v0: m, v1: m },
        Error::InvalidSharpness { v0: m, v1: m - 1 },
        Error::NeighbourhoodTooLarge { face: m },
    ];
    for e in errs {
        let mut f = Failure::from(e);
        f.query_index = Some(u64::MAX - 1);
        let d = f.to_detail();
        let len = d.message.iter().position(|&c| c == 0).unwrap();
        assert!(len + 1 < CCSS_ERROR_DETAIL_MESSAGE_CAPACITY, "{e}: {len}");
    }
}

#[test]
fn truncation_is_safe() {
    let mut f = Failure::from(Error::InvalidArgument("x"));
    f.msg = Msg::Text("ééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééééé");
    let d = f.to_detail();
    let n = unsafe { ccss_error_detail_format(&d, ptr::null_mut(), 0) };
    assert!(n < CCSS_ERROR_DETAIL_MESSAGE_CAPACITY);
    let bytes: Vec<u8> = d.message[..n].iter().map(|&c| c as u8).collect();
    assert!(std::str::from_utf8(&bytes).is_ok());
    let mut buf = [0 as c_char; 8];
    let n2 = unsafe { ccss_error_detail_format(&d, buf.as_mut_ptr(), 8) };
    assert_eq!(n2, n);
    let k = buf.iter().position(|&c| c == 0).unwrap();
    let s: Vec<u8> = buf[..k].iter().map(|&c| c as u8).collect();
    assert_eq!(std::str::from_utf8(&s).unwrap(), "invalid");
}

#[test]
fn internal_errors_and_block_checks() {
    // Core's internal consistency checks are ERR_INTERNAL, not INVALID_ARGUMENT.
    let f = Failure::from(Error::InvalidArgument("internal: inconsistent counts"));
    assert_eq!(f.status, CcssStatus::ERR_INTERNAL);
    assert_eq!(
        Failure::from(Error::InvalidArgument("mesh too large")).status,
        CcssStatus::ERR_INVALID_ARGUMENT
    );
    let mut d = Failure::invalid("x").to_detail();
    let st = guard(&mut d, || Err(Failure::internal("test inconsistency")));
    assert_eq!(
        (st, d.status),
        (CcssStatus::ERR_INTERNAL, CcssStatus::ERR_INTERNAL)
    );
    assert!(msg(&d).contains("internal error: test inconsistency"));
    let m = unsafe { core::ffi::CStr::from_ptr(ccss_status_message(99)) };
    assert!(m.to_str().unwrap().contains("internal"));
    // A caller block: NULL, length, size, alignment, in this order.
    let mut mem = [0u64; 4];
    let p = mem.as_mut_ptr() as *mut core::ffi::c_void;
    let status = |r: Result<*mut u8, Failure>| r.map(|_| ()).map_err(|f| (f.status, f.required));
    use crate::boundary::try_block;
    assert_eq!(
        status(try_block(ptr::null_mut(), 8, 8)),
        Err((CcssStatus::ERR_NULL_POINTER, 0))
    );
    assert_eq!(
        status(try_block(p, isize::MAX as usize + 1, 8)),
        Err((CcssStatus::ERR_INVALID_ARGUMENT, 0))
    );
    assert_eq!(
        status(try_block(p, 16, 32)),
        Err((CcssStatus::ERR_BUFFER_TOO_SMALL, 32))
    );
    let odd = unsafe { (p as *mut u8).add(4) } as *mut core::ffi::c_void;
    assert_eq!(
        status(try_block(odd, 16, 8)),
        Err((CcssStatus::ERR_MISALIGNED, 0))
    );
    assert_eq!(status(try_block(p, 32, 32)), Ok(()));
    // core_mem: the one conversion into core memory; a range off the
    // 8-byte grid is an internal error.
    let base = p as *mut u8;
    assert_eq!(
        unsafe { crate::boundary::core_mem(base, 8, 32) }
            .map(|s| s.len())
            .ok(),
        Some(3) // bytes 8..32: three words
    );
    assert_eq!(
        unsafe { crate::boundary::core_mem(base, 4, 32) }
            .map(|_| ())
            .map_err(|f| f.status),
        Err(CcssStatus::ERR_INTERNAL)
    );
}
