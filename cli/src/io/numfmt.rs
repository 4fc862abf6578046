//! Number formatting of evaluation results.
//!
//! Every number is written with Rust's `{:.16e}`: 17 significant digits in
//! scientific notation (`-5.5555555555555558e-1`, `0.0000000000000000e0`),
//! which reads back to the identical `f64` (17 digits always round-trip) and
//! is accepted by `strtod`, Python's `float` and C++ streams. Non-finite
//! values (which the core does not produce) would print as `NaN`/`inf`.

use ccss_core::Eval;
use std::fmt::Write;

/// Appends `x` as `{:.16e}`.
#[inline]
pub fn push_f64(out: &mut String, x: f64) {
    let _ = write!(out, "{x:.16e}");
}

/// Appends one output line of `ccss eval`: `px py pz dux duy duz dvx dvy dvz`
/// and, with `second`, `duux duuy duuz duvx duvy duvz dvvx dvvy dvvz`,
/// separated by single spaces, ending with `\n`.
pub fn push_eval_line(out: &mut String, e: &Eval, second: bool) {
    let mut vecs = [e.p, e.du, e.dv, e.duu, e.duv, e.dvv].into_iter();
    let n = if second { 6 } else { 3 };
    for (i, v) in vecs.by_ref().take(n).enumerate() {
        for (j, x) in v.to_array().into_iter().enumerate() {
            if i + j > 0 {
                out.push(' ');
            }
            push_f64(out, x);
        }
    }
    out.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use ccss_core::DVec3;

    #[test]
    fn round_trip_and_shape() {
        let mut s = String::new();
        for x in [
            0.1,
            -5.0 / 9.0,
            1e-300,
            123456789.123,
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
        ] {
            s.clear();
            push_f64(&mut s, x);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
            let mantissa = s.split('e').next().unwrap().trim_start_matches('-');
            assert_eq!(mantissa.len(), 18, "{s}"); // d.dddddddddddddddd
        }
        let e = Eval {
            p: DVec3::new(1.0, 2.0, 3.0),
            ..Default::default()
        };
        s.clear();
        push_eval_line(&mut s, &e, false);
        assert_eq!(s.split(' ').count(), 9);
        assert!(s.starts_with("1.0000000000000000e0 2.0000000000000000e0 3.0000000000000000e0 "));
        s.clear();
        push_eval_line(&mut s, &e, true);
        assert_eq!(s.trim_end().split(' ').count(), 18);
        assert!(s.ends_with('\n'));
    }
}
