//! The point classes of `ccss bench eval` beyond R and X (issue #28): where
//! on the surface the points lie, whatever the face's class.
//!
//! * `U`: uniform over all sub-faces (a slot drawn uniformly: each quad, each
//!   sub-face of an N-gon), uniform (u, v);
//! * `M`: uniform on quads with two or more extraordinary vertices (EVs);
//! * `N` / `D`: within 1/256 / 2^-20 (in u and v) of an extraordinary corner
//!   of a sub-face: an EV of a quad, or vertex k (valence != 4) of sub-face k
//!   of an N-gon (its corner (0, 0));
//! * `C` / `K`: within 1/256 / 2^-20 of an N-gon centre (corner (1, 1) of
//!   every sub-face of an N-gon, an extraordinary point of valence N).
//!
//! Corners are drawn uniformly over all such (sub-face, corner) pairs, then
//! (u, v) uniformly in the square of the given side at that corner.

use super::rng::SplitMix64;
use ccss_core::eval::Query;
use ccss_core::Topology;

/// The class letters this file draws, in report order, with where their
/// points lie (for notes).
pub const CLASSES: [(char, &str); 6] = [
    ('U', "on any sub-face"),
    ('M', "on a quad with several extraordinary vertices"),
    ('N', "within 1/256 of an extraordinary vertex"),
    ('D', "within 2^-20 of an extraordinary vertex"),
    ('C', "within 1/256 of an N-gon centre"),
    ('K', "within 2^-20 of an N-gon centre"),
];

/// A sub-face corner: the query's face and sub-face, and the corner
/// (0..4, counter-clockwise from (0, 0)).
#[derive(Clone, Copy, Debug)]
struct Corner {
    face: u32,
    sub: u32,
    corner: u8,
}

/// Maps (s, t) in the square at `corner` to (u, v): corner 0 = (0, 0),
/// 1 = (1, 0), 2 = (1, 1), 3 = (0, 1).
fn at_corner(corner: u8, s: f64, t: f64) -> (f64, f64) {
    match corner & 3 {
        0 => (s, t),
        1 => (1.0 - s, t),
        2 => (1.0 - s, 1.0 - t),
        _ => (s, 1.0 - t),
    }
}

/// The pool of class `letter`: sub-face corners (`N`, `D`, `C`, `K`) or
/// sub-faces (`U`, `M`, corner unused).
fn pool(t: &Topology, letter: char) -> Vec<Corner> {
    let mut out = Vec::new();
    for f in 0..t.num_faces() {
        let vs = t.face_vertices(f);
        let ev = |v: u32| t.valence(v as usize) != 4;
        let face = f as u32;
        let quad = vs.len() == 4;
        match letter {
            'U' => {
                let subs = if quad { 1 } else { vs.len() as u32 };
                out.extend((0..subs).map(|sub| Corner {
                    face,
                    sub,
                    corner: 0,
                }));
            }
            'M' if quad && vs.iter().filter(|&&v| ev(v)).count() >= 2 => {
                out.push(Corner {
                    face,
                    sub: 0,
                    corner: 0,
                });
            }
            'N' | 'D' => {
                for (k, &v) in vs.iter().enumerate() {
                    if !ev(v) {
                        continue;
                    }
                    let (sub, corner) = if quad { (0, k as u8) } else { (k as u32, 0) };
                    out.push(Corner { face, sub, corner });
                }
            }
            'C' | 'K' if !quad => {
                out.extend((0..vs.len() as u32).map(|sub| Corner {
                    face,
                    sub,
                    corner: 2,
                }));
            }
            _ => {}
        }
    }
    out
}

/// Side of the corner squares of class `letter` (1 for the uniform ones).
fn side(letter: char) -> f64 {
    match letter {
        'N' | 'C' => 1.0 / 256.0,
        'D' | 'K' => 2f64.powi(-20),
        _ => 1.0,
    }
}

/// `n` random points of class `letter` (empty when the mesh has no place
/// of that kind).
pub fn draw(t: &Topology, letter: char, n: usize, rng: &mut SplitMix64) -> Vec<Query> {
    let pool = pool(t, letter);
    if pool.is_empty() {
        return Vec::new();
    }
    let d = side(letter);
    (0..n)
        .map(|_| {
            let c = pool[rng.below(pool.len())];
            let (s, tt) = (d * rng.next_f64(), d * rng.next_f64());
            let (u, v) = at_corner(c.corner, s, tt);
            Query {
                face: c.face,
                sub: c.sub,
                u,
                v,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_and_sides() {
        assert_eq!(at_corner(0, 0.25, 0.125), (0.25, 0.125));
        assert_eq!(at_corner(1, 0.25, 0.125), (0.75, 0.125));
        assert_eq!(at_corner(2, 0.25, 0.125), (0.75, 0.875));
        assert_eq!(at_corner(3, 0.25, 0.125), (0.25, 0.875));
        assert_eq!(side('D'), 1.0 / (1u64 << 20) as f64);
        assert_eq!(side('N'), 1.0 / 256.0);
    }
}
