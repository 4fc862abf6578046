//! Curve rules of the unified scheme ([MS01 §3.1]): the 5x5
//! matrix (7), the four-point scheme for a = 1, d-ary B-splines for a = 0,
//! open polylines, and errors.
// Index loops mirror the matrix and grid formulas they check.
#![allow(clippy::needless_range_loop)]
use ccss_core::unified::{curve_buffer_len, curve_len, refine_curve, UnifiedParams};
use ccss_core::{DVec3, Error, TriangleRule};

fn params(a: f64, d: u32, p: u32) -> UnifiedParams {
    UnifiedParams {
        a,
        b: 0.0,
        g: 0.0,
        d,
        p,
        triangles: TriangleRule::Split,
    }
}

fn step(points: &[DVec3], closed: bool, p: &UnifiedParams) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; curve_buffer_len(points.len(), closed, p).unwrap()];
    let n = refine_curve(points, closed, p, &mut out).unwrap();
    assert_eq!(n, curve_len(points.len(), closed, p.d).unwrap());
    out.truncate(n);
    out
}

/// Column `j` of the subdivision matrix of a closed curve with `m` points:
/// the step applied to the `j`-th unit impulse (x coordinate).
fn matrix(m: usize, p: &UnifiedParams) -> Vec<Vec<f64>> {
    let cols: Vec<Vec<f64>> = (0..m)
        .map(|j| {
            let pts: Vec<DVec3> = (0..m)
                .map(|i| DVec3::new(if i == j { 1.0 } else { 0.0 }, 0.0, 0.0))
                .collect();
            step(&pts, true, p).iter().map(|q| q.x).collect()
        })
        .collect();
    (0..cols[0].len())
        .map(|r| cols.iter().map(|c| c[r]).collect())
        .collect()
}

#[test]
fn p3_d2_is_matrix_7() {
    let m = 12;
    for a in [0.0, 0.25, 0.5, 0.7, 1.0, -0.3] {
        let s = matrix(m, &params(a, 2, 3));
        let m7 = [
            [2.0 - 2.0 * a, 4.0 * (3.0 + a), 2.0 - 2.0 * a, 0.0, 0.0],
            [-a, 8.0 + a, 8.0 + a, -a, 0.0],
            [0.0, 2.0 - 2.0 * a, 4.0 * (3.0 + a), 2.0 - 2.0 * a, 0.0],
            [0.0, -a, 8.0 + a, 8.0 + a, -a],
            [0.0, 0.0, 2.0 - 2.0 * a, 4.0 * (3.0 + a), 2.0 - 2.0 * a],
        ];
        let i = 6;
        for (r, row) in m7.iter().enumerate() {
            for (c, &want) in row.iter().enumerate() {
                let got = 16.0 * s[2 * i - 2 + r][i - 2 + c];
                assert!(
                    (got - want).abs() < 1e-13,
                    "a={a} M[{r}][{c}] = {got}, want {want}"
                );
            }
            // Nothing outside the 5 columns.
            let outside: f64 = (0..m)
                .filter(|&c| !(i - 2..=i + 2).contains(&c))
                .map(|c| s[2 * i - 2 + r][c].abs())
                .sum();
            assert!(outside < 1e-15);
        }
    }
}

#[test]
fn a1_is_the_four_point_scheme() {
    let m = 10;
    let s = matrix(m, &params(1.0, 2, 3));
    for i in 0..m {
        for j in 0..m {
            let even = if i == j { 1.0 } else { 0.0 };
            assert!((s[2 * i][j] - even).abs() < 1e-15, "even row {i}");
            let off = (j + m - i) % m;
            let odd = match off {
                0 | 1 => 9.0 / 16.0,
                2 => -1.0 / 16.0,
                _ if off == m - 1 => -1.0 / 16.0,
                _ => 0.0,
            };
            assert!((s[2 * i + 1][j] - odd).abs() < 1e-15, "odd row {i} col {j}");
        }
    }
}

/// `(box_d)^{*(p+1)} / d^p`: the d-ary refinement mask of the degree-p
/// uniform B-spline.
fn bspline_mask(d: usize, p: usize) -> Vec<f64> {
    let mut mask = vec![1.0];
    for _ in 0..p + 1 {
        let mut next = vec![0.0; mask.len() + d - 1];
        for (i, &x) in mask.iter().enumerate() {
            for t in 0..d {
                next[i + t] += x;
            }
        }
        mask = next;
    }
    mask.iter().map(|x| x / (d as f64).powi(p as i32)).collect()
}

#[test]
fn a0_is_the_d_ary_bspline() {
    let m = 12;
    for p in [1, 3, 5, 7] {
        for d in 2..=5usize {
            let s = matrix(m, &params(0.0, d as u32, p));
            let mask = bspline_mask(d, p as usize);
            let half = (mask.len() - 1) as isize / 2;
            let j = 6;
            for (t, &w) in mask.iter().enumerate() {
                let row =
                    (d as isize * j as isize + t as isize - half).rem_euclid((m * d) as isize);
                assert!(
                    (s[row as usize][j] - w).abs() < 1e-14,
                    "p={p} d={d} t={t}: {} vs {w}",
                    s[row as usize][j]
                );
            }
            let col_sum: f64 = (0..m * d).map(|r| s[r][j]).sum();
            assert!((col_sum - d as f64).abs() < 1e-12);
        }
    }
    // d = 3: 27 * mask = [1, 4, 10, 16, 19, 16, 10, 4, 1].
    let m3: Vec<f64> = bspline_mask(3, 3).iter().map(|x| x * 27.0).collect();
    assert_eq!(m3, [1.0, 4.0, 10.0, 16.0, 19.0, 16.0, 10.0, 4.0, 1.0]);
}

#[test]
fn open_polylines_keep_their_ends_and_lines() {
    let pts: Vec<DVec3> = (0..6)
        .map(|i| DVec3::new(i as f64, (i * i) as f64 * 0.3, (i as f64).sin()))
        .collect();
    for d in 2..=5 {
        for a in [0.0, 0.5, 1.0] {
            for p in [3, 5] {
                let pr = UnifiedParams {
                    b: 0.5,
                    ..params(a, d, p)
                };
                let out = step(&pts, false, &pr);
                assert_eq!(out.len(), 5 * d as usize + 1);
                assert!((out[0] - pts[0]).length() < 1e-15);
                assert!((out[out.len() - 1] - pts[5]).length() < 1e-14);
                if a == 1.0 {
                    for (i, q) in pts.iter().enumerate() {
                        assert!(
                            (out[d as usize * i] - *q).length() < 1e-13,
                            "d={d} p={p} i={i}"
                        );
                    }
                }
            }
            // Points evenly spaced on a line stay evenly spaced on it.
            let line: Vec<DVec3> = (0..4)
                .map(|i| DVec3::new(1.0, 2.0, 3.0) * i as f64)
                .collect();
            let out = step(&line, false, &params(a, d, 3));
            for (k, q) in out.iter().enumerate() {
                let want = DVec3::new(1.0, 2.0, 3.0) * (k as f64 / d as f64);
                assert!((*q - want).length() < 1e-13);
            }
        }
    }
    // Away from the ends the open rule equals the closed one.
    let d = 3;
    let pr = params(0.5, d, 3);
    let open = step(&pts, false, &pr);
    let closed = step(&pts, true, &pr);
    let du = d as usize;
    for k in 2 * du..3 * du + 1 {
        assert!((open[k] - closed[k]).length() < 1e-14, "k={k}");
    }
    // A single point.
    assert_eq!(step(&pts[..1], false, &pr), vec![pts[0]]);
}

#[test]
fn curve_errors() {
    let pts = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let mut out = vec![DVec3::ZERO; 64];
    let ok = params(0.5, 2, 3);
    assert!(matches!(
        refine_curve(&pts, true, &UnifiedParams { d: 1, ..ok }, &mut out),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        refine_curve(&pts, true, &UnifiedParams { p: 2, ..ok }, &mut out),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        refine_curve(&pts, true, &UnifiedParams { a: f64::NAN, ..ok }, &mut out),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        refine_curve(&[], true, &ok, &mut out),
        Err(Error::InvalidArgument(_))
    ));
    assert_eq!(
        refine_curve(&pts, true, &ok, &mut out[..11]),
        Err(Error::BufferTooSmall { required: 12 })
    );
    assert_eq!(
        refine_curve(
            &[DVec3::ZERO, DVec3::new(f64::INFINITY, 0.0, 0.0)],
            false,
            &ok,
            &mut out
        ),
        Err(Error::NonFiniteCoordinate { vertex: 1 })
    );
    assert!(matches!(
        curve_len(usize::MAX, true, 3),
        Err(Error::InvalidArgument(_))
    ));
    // Closed curves with one or two points are valid.
    assert_eq!(step(&pts[..1], true, &ok), vec![DVec3::ZERO; 2]);
    assert_eq!(step(&pts[..2], true, &ok).len(), 4);
}
