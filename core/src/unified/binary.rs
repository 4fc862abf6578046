//! Fast path of the first pass for `d = 2`: linear subdivision (eqs. (1)–(2))
//! and simple averaging (eqs. (23)+(24) with `k = 1`, i.e. eq. (9)) fused
//! into one sweep over the input faces, as a Catmull-Clark step computes its
//! points. The result equals linear subdivision followed by
//! [`super::smooth`]'s `k = 1` averages up to rounding (the same terms,
//! summed in another order).

use super::layout::Numbering;
use crate::mesh::topology::Topology;
use glam::DVec3;

/// Writes the smoothed positions of every refined vertex into `x` (zeroed,
/// one entry per refined vertex). Reads the refined faces already emitted
/// ([`super::faces::emit`]): `idx`, `face_start`, `child_start`; `num` gives
/// the edge numbering. Every vertex is divided by its number of faces, known
/// in closed form: an old vertex has one child face per incident face, an
/// edge point two per adjacent polygon and three per adjacent split
/// triangle, a centroid `n`.
pub(crate) fn first_pass(
    t: &Topology,
    num: &Numbering,
    idx: &[u32],
    face_start: &[u32],
    child_start: &[u32],
    x: &mut [DVec3],
) {
    let sh = num.shape;
    let add = |x: &mut [DVec3], q: &[u32], p: DVec3| {
        for &r in q {
            x[r as usize] += p;
        }
    };
    let mut pos = [DVec3::ZERO; crate::config::MAX_VALENCE];
    let mut mid = [DVec3::ZERO; crate::config::MAX_VALENCE];
    for f in 0..t.num_faces() {
        let n = t.face_size(f);
        let vs = t.face_vertices(f);
        for k in 0..n {
            pos[k] = t.position(vs[k] as usize);
        }
        for k in 0..n {
            mid[k] = (pos[k] + pos[if k + 1 == n { 0 } else { k + 1 }]) * 0.5;
        }
        let c0 = face_start[child_start[f] as usize] as usize;
        if sh.is_split_tri(n) {
            // Children in emission order: [v0 e0 e2], [e0 e1 e2], [e0 v1 e1],
            // [e2 e1 v2].
            let q = &idx[c0..c0 + 12];
            add(x, &q[0..3], (pos[0] + mid[0] + mid[2]) / 3.0);
            add(x, &q[3..6], (mid[0] + mid[1] + mid[2]) / 3.0);
            add(x, &q[6..9], (mid[0] + pos[1] + mid[1]) / 3.0);
            add(x, &q[9..12], (mid[2] + mid[1] + pos[2]) / 3.0);
            continue;
        }
        let mut centre = DVec3::ZERO;
        for p in &pos[..n] {
            centre += *p;
        }
        centre /= n as f64;
        for k in 0..n {
            let kp = if k == 0 { n - 1 } else { k - 1 };
            // Child k is [v_k, e_k, centre, e_{k-1}].
            let c = (pos[k] + mid[k] + centre + mid[kp]) * 0.25;
            add(x, &idx[c0 + 4 * k..c0 + 4 * k + 4], c);
        }
    }
    let nv = t.num_vertices();
    for (v, xv) in x[..nv].iter_mut().enumerate() {
        let n = t.valence(v);
        if n > 0 {
            *xv /= n as f64;
        } else {
            // Isolated old vertex: nothing to average.
            *xv = t.position(v);
        }
    }
    let side = |h: usize| {
        if sh.is_split_tri(t.face_size(t.face_of(h))) {
            3.0
        } else {
            2.0
        }
    };
    for h in 0..t.num_half_edges() {
        let tw = t.twin(h);
        if h < tw {
            x[num.edge_point(t, h, 1)] /= side(h) + side(tw);
        }
    }
    for f in 0..t.num_faces() {
        let n = t.face_size(f);
        if !sh.is_split_tri(n) {
            x[num.interior_start[f] as usize] /= n as f64;
        }
    }
}
