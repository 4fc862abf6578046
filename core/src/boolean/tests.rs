//! Unit tests on polyhedra: closed oriented output, inclusion-exclusion of
//! volumes (exact identities for polyhedral Booleans), disjoint operands,
//! errors.

use super::*;
use glam::DMat3;

const MEM: usize = 1 << 14;

fn cube(centre: DVec3, half: f64, rot: DMat3) -> ([f64; 24], [u32; 36]) {
    let mut p = [0.0; 24];
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 != 0 { 1.0 } else { -1.0 },
            if i & 2 != 0 { 1.0 } else { -1.0 },
            if i & 4 != 0 { 1.0 } else { -1.0 },
        );
        let x = centre + rot * (c * half);
        p[3 * i..3 * i + 3].copy_from_slice(&x.to_array());
    }
    // Quads counter-clockwise seen from outside.
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

fn volume(p: &[f64], t: &[u32]) -> f64 {
    let v = |i: u32| DVec3::from_slice(&p[3 * i as usize..3 * i as usize + 3]);
    t.chunks(3)
        .map(|c| v(c[0]).dot(v(c[1]).cross(v(c[2]))) / 6.0)
        .sum()
}

/// Every edge used twice, in opposite directions.
fn assert_closed(t: &[u32]) {
    let n = t.len() / 3;
    for i in 0..n {
        for k in 0..3 {
            let (a, b) = (t[3 * i + k], t[3 * i + (k + 1) % 3]);
            assert_ne!(a, b, "degenerate triangle {i}");
            let same = (0..n)
                .filter(|&j| (0..3).any(|m| t[3 * j + m] == a && t[3 * j + (m + 1) % 3] == b))
                .count();
            let opp = (0..n)
                .filter(|&j| (0..3).any(|m| t[3 * j + m] == b && t[3 * j + (m + 1) % 3] == a))
                .count();
            assert_eq!((same, opp), (1, 1), "edge {a}-{b}");
        }
    }
}

struct Res {
    vol: f64,
    counts: Counts,
}

fn run(a: SolidMesh, b: SolidMesh, op: Op) -> Res {
    let mut mem = [0u64; MEM];
    let mut bo = Boolean::build(a, b, op, Options::default(), &mut mem).unwrap();
    let c = bo.counts();
    let mut pos = [0.0; 3 * 512];
    let mut tri = [0u32; 3 * 1024];
    let mut cs = [0u32; 16];
    let mut ci = [0u32; 512];
    bo.emit(Output {
        positions: &mut pos,
        triangles: &mut tri,
        sources: None,
        curve_sizes: &mut cs,
        curve_indices: &mut ci,
    })
    .unwrap();
    let t = &tri[..3 * c.triangles];
    assert_closed(t);
    Res {
        vol: volume(&pos[..3 * c.vertices], t),
        counts: c,
    }
}

#[test]
#[cfg_attr(
    miri,
    ignore = "too slow under Miri: exact-predicate Boolean of two boxes, minutes interpreted"
)]
fn cubes_inclusion_exclusion() {
    let rot = DMat3::from_euler(glam::EulerRot::XYZ, 0.31, -0.47, 0.23);
    let (pa, ta) = cube(DVec3::ZERO, 1.0, DMat3::IDENTITY);
    let (pb, tb) = cube(DVec3::new(0.71, 0.53, 0.37), 0.9, rot);
    let a = SolidMesh {
        positions: &pa,
        triangles: &ta,
    };
    let b = SolidMesh {
        positions: &pb,
        triangles: &tb,
    };
    let (va, vb) = (volume(&pa, &ta), volume(&pb, &tb));
    assert!((va - 8.0).abs() < 1e-12);
    let u = run(a, b, Op::Union);
    let i = run(a, b, Op::Intersection);
    let d = run(a, b, Op::Difference);
    assert!(u.counts.curve_loops >= 1 && u.counts.curve_points >= 3);
    assert!(i.vol > 0.1 && i.vol < vb, "{}", i.vol);
    assert!(
        (u.vol + i.vol - va - vb).abs() < 1e-12,
        "{} {}",
        u.vol + i.vol,
        va + vb
    );
    assert!((d.vol - (va - i.vol)).abs() < 1e-12);
    // B - A by swapping.
    let d2 = run(b, a, Op::Difference);
    assert!((d2.vol - (vb - i.vol)).abs() < 1e-12);
}

#[test]
#[cfg_attr(
    miri,
    ignore = "too slow under Miri: exact-predicate Boolean of two boxes, minutes interpreted"
)]
fn disjoint_and_nested() {
    let (pa, ta) = cube(DVec3::ZERO, 1.0, DMat3::IDENTITY);
    let (pb, tb) = cube(DVec3::new(5.0, 0.1, 0.2), 0.5, DMat3::IDENTITY);
    let (pc, tc) = cube(DVec3::new(0.1, 0.2, 0.05), 0.3, DMat3::from_rotation_z(0.4));
    let a = SolidMesh {
        positions: &pa,
        triangles: &ta,
    };
    let b = SolidMesh {
        positions: &pb,
        triangles: &tb,
    };
    let c = SolidMesh {
        positions: &pc,
        triangles: &tc,
    };
    assert_eq!(run(a, b, Op::Union).counts.triangles, 24);
    assert_eq!(run(a, b, Op::Intersection).counts.triangles, 0);
    assert!((run(a, b, Op::Difference).vol - 8.0).abs() < 1e-12);
    let vc = volume(&pc, &tc);
    assert!((run(a, c, Op::Union).vol - 8.0).abs() < 1e-12);
    assert!((run(a, c, Op::Intersection).vol - vc).abs() < 1e-12);
    assert!((run(a, c, Op::Difference).vol - (8.0 - vc)).abs() < 1e-12);
}

#[test]
fn errors_and_sizes() {
    let (pa, ta) = cube(DVec3::ZERO, 1.0, DMat3::IDENTITY);
    let (pb, tb) = cube(DVec3::new(0.5, 0.4, 0.3), 1.0, DMat3::from_rotation_y(0.3));
    let a = SolidMesh {
        positions: &pa,
        triangles: &ta,
    };
    let b = SolidMesh {
        positions: &pb,
        triangles: &tb,
    };
    // Open mesh.
    let open = SolidMesh {
        positions: &pa,
        triangles: &ta[..33],
    };
    let mut mem = [0u64; MEM];
    assert!(matches!(
        Boolean::build(open, b, Op::Union, Options::default(), &mut mem),
        Err(Error::NotClosedSolid(_))
    ));
    // Exact block size: base is too small, the reported size suffices.
    let base = Boolean::required_bytes_base(&a, &b);
    let mut small = [0u64; 64];
    let need = match Boolean::build(a, b, Op::Union, Options::default(), &mut small[..1]) {
        Err(Error::BufferTooSmall { required }) => required,
        r => panic!("{:?}", r.err()),
    };
    assert_eq!(need, base);
    let mut block = [0u64; MEM];
    let full = match Boolean::build(a, b, Op::Union, Options::default(), &mut block[..base / 8]) {
        Err(Error::BufferTooSmall { required }) => required,
        r => panic!("{:?}", r.err()),
    };
    assert!(full > base);
    assert!(Boolean::build(a, b, Op::Union, Options::default(), &mut block[..full / 8]).is_ok());
    // A vertex exactly on the other's plane.
    let (pc, tc) = cube(DVec3::new(2.0, 0.3, 0.2), 1.0, DMat3::IDENTITY);
    let c = SolidMesh {
        positions: &pc,
        triangles: &tc,
    };
    assert!(matches!(
        Boolean::build(a, c, Op::Union, Options::default(), &mut mem),
        Err(Error::DegenerateContact { .. })
    ));
    // A crossing steeper than the accepted amplification: named triangles.
    let strict = Options {
        max_amplification: 1.0 + 1e-9,
    };
    assert!(matches!(
        Boolean::build(a, b, Op::Difference, strict, &mut mem),
        Err(Error::NearTangential { triangle_a, triangle_b, .. }) if triangle_a < 12 && triangle_b < 12
    ));
    let bad = Options {
        max_amplification: f64::NAN,
    };
    assert!(Boolean::build(a, b, Op::Union, bad, &mut mem).is_err());
    assert!(tessellation_tolerance(0.0, 1.0).is_err());
    assert!(tessellation_tolerance(f64::NAN, 1.0).is_err());
    assert_eq!(tessellation_tolerance(1.0, 4.0), Ok(0.25));
}

/// Distance from `p` to a triangle (closest point by clamped barycentric
/// search over the plane and the three edges).
fn point_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    let q = p - n * ((p - a).dot(n) / n.dot(n));
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(q - u).dot(n) >= 0.0);
    if inside {
        return (p - q).length();
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| {
            let t = ((p - u).dot(v - u) / (v - u).dot(v - u)).clamp(0.0, 1.0);
            (p - (u + (v - u) * t)).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Largest distance from sample points of mesh `x` (vertices, edge
/// midpoints, centroids) farther than `r` from every point of `avoid` to
/// mesh `y`.
fn one_sided(px: &[f64], tx: &[u32], py: &[f64], ty: &[u32], avoid: &[DVec3], r: f64) -> f64 {
    let v = |p: &[f64], i: u32| DVec3::from_slice(&p[3 * i as usize..3 * i as usize + 3]);
    let mut worst: f64 = 0.0;
    for t in tx.chunks(3) {
        let (a, b, c) = (v(px, t[0]), v(px, t[1]), v(px, t[2]));
        for s in [
            a,
            b,
            c,
            (a + b) / 2.0,
            (b + c) / 2.0,
            (c + a) / 2.0,
            (a + b + c) / 3.0,
        ] {
            if avoid.iter().any(|q| (*q - s).length() < r) {
                continue;
            }
            let d = ty
                .chunks(3)
                .map(|u| point_triangle(s, v(py, u[0]), v(py, u[1]), v(py, u[2])))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

/// The wedge lemma on polyhedra: moving every face of both boxes outward
/// by `t` moves the Boolean's boundary by at most `amplification x t`
/// (two-sided, sampled), and by more than `t` where the crossing is steep;
/// moving A's faces by `t` and B's by `t / 3`, by at most the largest
/// [`crossing_bound`](super::crossing_bound) of the crossings (less than
/// `amplification x t`).
/// Points within `50 t` of the curve's corners are left out: there an edge
/// of one box (a crease, two planes) pierces a face of the other, three
/// planes meet, and the displacement can exceed the two-plane bound (the
/// lemma is for smooth surfaces, whose tessellation edges are nearly flat);
/// so are the boxes' own corners (three planes of one box: `sqrt(3) t`).
#[test]
#[cfg_attr(
    miri,
    ignore = "too slow under Miri: exact-predicate Boolean of two boxes, minutes interpreted"
)]
fn wedge_lemma_on_moved_boxes() {
    let t = 1e-3;
    let rot = DMat3::from_euler(glam::EulerRot::XYZ, 0.2, -0.3, 0.9);
    let c = DVec3::new(1.1, 0.6, 0.3);
    let (pa, ta) = cube(DVec3::ZERO, 1.0, DMat3::IDENTITY);
    let (pb, tb) = cube(c, 0.8, rot);
    for (op, t_b) in [
        (Op::Union, t),
        (Op::Intersection, t),
        (Op::Difference, t),
        (Op::Union, t / 3.0),
        (Op::Intersection, t / 3.0),
        (Op::Difference, t / 3.0),
    ] {
        // A box of half-width h moved out by d: half-width h + d.
        let (qa, _) = cube(DVec3::ZERO, 1.0 + t, DMat3::IDENTITY);
        let (qb, _) = cube(c, 0.8 + t_b, rot);
        let mut wedge = 0.0f64;
        let mut out = [([0.0; 3 * 512], [0u32; 3 * 1024], 0usize, 0.0f64); 2];
        let mut corners = [DVec3::ZERO; 256];
        let mut nc = 0;
        for (k, (p1, p2)) in [(&pa, &pb), (&qa, &qb)].into_iter().enumerate() {
            let a = SolidMesh {
                positions: p1,
                triangles: &ta,
            };
            let b = SolidMesh {
                positions: p2,
                triangles: &tb,
            };
            let mut mem = [0u64; MEM];
            let mut bo = Boolean::build(a, b, op, Options::default(), &mut mem).unwrap();
            let n = bo.counts();
            let (pos, tri, nt, amp) = &mut out[k];
            let mut cs = [0u32; 16];
            let mut ci = [0u32; 512];
            bo.emit(Output {
                positions: pos,
                triangles: tri,
                sources: None,
                curve_sizes: &mut cs,
                curve_indices: &mut ci,
            })
            .unwrap();
            *nt = n.triangles;
            *amp = bo.stats().amplification;
            bo.crossings(&mut |x| {
                wedge = wedge.max(super::crossing_bound(x.amplification, t, t_b));
            });
            for &i in &ci[..n.curve_points] {
                corners[nc] = DVec3::from_slice(&pos[3 * i as usize..3 * i as usize + 3]);
                nc += 1;
            }
        }
        // The boxes' own corners (three planes of one solid) move by
        // `sqrt(3)` times their faces: not a crossing, left out too.
        for q in pa.chunks_exact(3).chain(pb.chunks_exact(3)) {
            corners[nc] = DVec3::from_slice(q);
            nc += 1;
        }
        let amp = out[0].3.max(out[1].3);
        let (x, y) = (&out[0], &out[1]);
        let (av, r) = (&corners[..nc], 50.0 * t);
        let d = one_sided(&x.0, &x.1[..3 * x.2], &y.0, &y.1[..3 * y.2], av, r).max(one_sided(
            &y.0,
            &y.1[..3 * y.2],
            &x.0,
            &x.1[..3 * x.2],
            av,
            r,
        ));
        extern crate std;
        std::eprintln!(
            "{op:?}, moves {t:e} / {t_b:e}: moved {d:.4e}, bound {wedge:.4e} (amplification {amp:.4}: {:.4e})",
            amp * t
        );
        assert!(d <= amp * t * (1.0 + 1e-6), "{op:?}: {d:e} > {amp} x {t:e}");
        assert!(
            d <= wedge * (1.0 + 1e-6),
            "{op:?}: {d:e} > crossing bound {wedge:e}"
        );
        assert!(d >= t * (1.0 - 1e-9), "{op:?}: {d:e} < {t:e}");
        if t_b < t {
            assert!(
                wedge < amp * t,
                "{op:?}: unequal moves give a smaller bound"
            );
        }
        // A face moved by t gives exactly t away from the curve; at the
        // crossing edges the distance grows with the amplification.
        if amp > 1.5 {
            assert!(d > 1.2 * t, "{op:?}: {d:e} with amplification {amp}");
        }
    }
}
