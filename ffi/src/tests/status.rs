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
