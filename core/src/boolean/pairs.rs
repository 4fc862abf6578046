//! Intersection of two triangles by exact predicates only: the segment
//! where triangle `a` of A meets triangle `b` of B, as its two end points,
//! each named by the edge that pierces the other triangle (an edge of `a`
//! through `b`, or an edge of `b` through `a`). Naming points by
//! (edge, triangle) instead of by coordinates is what makes the output
//! crack-free: both triangles on an edge, and both solids, refer to the
//! same point.

use super::predicates::orient3d;
use glam::DVec3;

/// One end of an intersection segment: `edge_of_a` says whose edge
/// pierces; `side` is that edge's side in its own triangle (0..3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pierce {
    /// The piercing edge belongs to triangle `a` (else to `b`).
    pub edge_of_a: bool,
    /// Side index `k` (corner `k` to corner `k + 1`) of the piercing edge.
    pub side: usize,
    /// Parameter along that side from corner `k` (float).
    pub t: f64,
}

/// What the test found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contact {
    /// The triangles do not meet.
    None,
    /// They cross along a segment with these two ends.
    Segment([Pierce; 2]),
    /// A vertex on the other's plane, coplanar triangles, or an edge
    /// through an edge: not handled (see [`crate::error::Error::DegenerateContact`]).
    Degenerate(&'static str),
}

/// Does segment `p q` pass through the interior of triangle `tri`
/// (given that `p` and `q` lie strictly on opposite sides of its plane)?
/// `Err` when it passes through an edge or vertex of the triangle.
fn pierces(p: DVec3, q: DVec3, tri: &[DVec3; 3]) -> Result<bool, ()> {
    let s0 = orient3d(p, q, tri[0], tri[1]).0;
    let s1 = orient3d(p, q, tri[1], tri[2]).0;
    let s2 = orient3d(p, q, tri[2], tri[0]).0;
    if s0 == 0 || s1 == 0 || s2 == 0 {
        // Zero with the others of equal sign: through an edge or vertex.
        let nz = [s0, s1, s2];
        let pos = nz.iter().filter(|&&s| s > 0).count();
        let neg = nz.iter().filter(|&&s| s < 0).count();
        return if pos > 0 && neg > 0 {
            Ok(false)
        } else {
            Err(())
        };
    }
    Ok(s0 == s1 && s1 == s2)
}

/// Intersects triangles `a` and `b` (vertices counter-clockwise).
pub fn intersect(a: &[DVec3; 3], b: &[DVec3; 3]) -> Contact {
    let mut oa = [0i32; 3];
    let mut va = [0f64; 3];
    for i in 0..3 {
        (oa[i], va[i]) = orient3d(b[0], b[1], b[2], a[i]);
    }
    if (oa[0] > 0 && oa[1] > 0 && oa[2] > 0) || (oa[0] < 0 && oa[1] < 0 && oa[2] < 0) {
        return Contact::None;
    }
    let mut ob = [0i32; 3];
    let mut vb = [0f64; 3];
    for i in 0..3 {
        (ob[i], vb[i]) = orient3d(a[0], a[1], a[2], b[i]);
    }
    if (ob[0] > 0 && ob[1] > 0 && ob[2] > 0) || (ob[0] < 0 && ob[1] < 0 && ob[2] < 0) {
        return Contact::None;
    }
    if oa.contains(&0) || ob.contains(&0) {
        return Contact::Degenerate("a vertex lies exactly on the other triangle's plane");
    }
    let mut ends = [Pierce {
        edge_of_a: true,
        side: 0,
        t: 0.0,
    }; 4];
    let mut n = 0;
    for (own, tri, o, v, other) in [(true, a, &oa, &va, b), (false, b, &ob, &vb, a)] {
        for k in 0..3 {
            let k1 = (k + 1) % 3;
            if o[k] == o[k1] {
                continue;
            }
            match pierces(tri[k], tri[k1], other) {
                Ok(true) => {
                    let t = (v[k] / (v[k] - v[k1])).clamp(0.0, 1.0);
                    ends[n] = Pierce {
                        edge_of_a: own,
                        side: k,
                        t: if t.is_finite() { t } else { 0.5 },
                    };
                    n += 1;
                }
                Ok(false) => {}
                Err(()) => {
                    return Contact::Degenerate("an edge passes exactly through the other's edge")
                }
            }
        }
    }
    match n {
        0 => Contact::None,
        2 => Contact::Segment([ends[0], ends[1]]),
        _ => Contact::Degenerate("the crossing is not a single segment"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn crossing_disjoint_and_degenerate() {
        let a = [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)];
        // Vertical triangle through a: both of b's lower edges pierce a? No:
        // b's edges cross a's plane at (0.5, 0.5) and (0.5, 0.1)... it
        // crosses a's interior along a segment.
        let b = [v(0.5, 0.1, -1.0), v(0.5, 1.2, 1.0), v(0.5, 0.3, 1.0)];
        match intersect(&a, &b) {
            Contact::Segment(e) => {
                assert!(!e[0].edge_of_a && !e[1].edge_of_a);
            }
            c => panic!("{c:?}"),
        }
        // b through an edge of a: one end from each.
        let b2 = [v(1.0, 1.5, -1.0), v(1.0, -1.0, -1.0), v(1.0, 0.3, 1.0)];
        match intersect(&a, &b2) {
            Contact::Segment(e) => assert_ne!(e[0].edge_of_a, e[1].edge_of_a),
            c => panic!("{c:?}"),
        }
        let far = [v(5.0, 5.0, 1.0), v(6.0, 5.0, 1.0), v(5.0, 6.0, 1.0)];
        assert_eq!(intersect(&a, &far), Contact::None);
        let touching = [v(0.5, 0.5, 0.0), v(6.0, 5.0, 1.0), v(5.0, 6.0, 1.0)];
        assert!(matches!(intersect(&a, &touching), Contact::Degenerate(_)));
    }
}
