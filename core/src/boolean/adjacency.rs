//! Edge twins of a closed triangle mesh in caller memory: side `3 t + k`
//! (from corner `k` to corner `k + 1` of triangle `t`) and the opposite
//! side of the neighbouring triangle. An edge is named by the smaller of
//! its two side indices (its *canonical side*).

use super::SolidMesh;
use crate::error::{Error, SolidDefect};

/// Fills `twin` (`3 T`) using `keys` (`3 T` words) and `order` (`3 T`) as
/// scratch; a mesh that is not closed, manifold and consistently oriented
/// is [`Error::NotClosedSolid`] naming the edge.
pub fn build_twins(
    m: &SolidMesh,
    twin: &mut [u32],
    keys: &mut [u64],
    order: &mut [u32],
) -> Result<(), Error> {
    let n = m.triangles.len();
    for s in 0..n {
        let (v0, v1) = side_ends(m, s);
        let (lo, hi) = (v0.min(v1) as u64, v0.max(v1) as u64);
        keys[s] = (lo << 32) | hi;
        order[s] = s as u32;
    }
    order[..n].sort_unstable_by_key(|&s| keys[s as usize]);
    let mut i = 0;
    while i < n {
        let s = order[i] as usize;
        let mut j = i + 1;
        while j < n && keys[order[j] as usize] == keys[s] {
            j += 1;
        }
        let (v0, v1) = side_ends(m, s);
        if j - i == 1 {
            return Err(Error::NotClosedSolid(SolidDefect::BoundaryEdge { v0, v1 }));
        }
        let o = order[i + 1] as usize;
        if j - i > 2 || side_ends(m, o) != (v1, v0) {
            return Err(Error::NotClosedSolid(SolidDefect::NonManifoldEdge {
                v0,
                v1,
            }));
        }
        twin[s] = o as u32;
        twin[o] = s as u32;
        i = j;
    }
    Ok(())
}

/// The end vertices of side `s`.
#[inline]
pub fn side_ends(m: &SolidMesh, s: usize) -> (u32, u32) {
    let t = s / 3;
    let k = s % 3;
    (m.triangles[3 * t + k], m.triangles[3 * t + (k + 1) % 3])
}
