//! Benchmark classes of quad faces (the definitions of
//! `bench/osd/gen_points.py`):
//!
//! * `R`: a quad whose 1-ring is regular: its 4 vertices and every vertex of
//!   every face incident to them have valence 4, and all those faces are
//!   quads;
//! * `X`: a quad with at least one vertex of valence != 4 (an extraordinary
//!   vertex, EV). Sub-classes: `X<n>` for exactly one EV of valence n,
//!   `Xmulti` for two or more EVs (ccss splits those faces into four
//!   patches).
//!
//! Other faces (N-gons, quads with regular corners but an irregular 1-ring)
//! are in no class.

use ccss_core::Topology;

/// The class of a face.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FaceClass {
    /// Fully regular 1-ring.
    R,
    /// Extraordinary; the sub-class label (`X3`, `X5`, `Xmulti`, ...).
    X(String),
    /// Neither.
    None,
}

/// Faces incident to vertex `v`.
fn faces_around(t: &Topology, v: usize, mut visit: impl FnMut(usize)) {
    let h0 = t.vertex_half_edge(v);
    if h0 == usize::MAX {
        return;
    }
    let mut h = h0;
    for _ in 0..t.valence(v) {
        visit(t.face_of(h));
        h = t.rotate_ccw(h);
        if h == h0 {
            break;
        }
    }
}

/// The class of face `f`.
pub fn classify(t: &Topology, f: usize) -> FaceClass {
    let vs = t.face_vertices(f);
    if vs.len() != 4 {
        return FaceClass::None;
    }
    let evs: Vec<usize> = vs
        .iter()
        .map(|&v| t.valence(v as usize))
        .filter(|&n| n != 4)
        .collect();
    match evs.len() {
        0 => {}
        1 => return FaceClass::X(format!("X{}", evs[0])),
        _ => return FaceClass::X("Xmulti".to_string()),
    }
    let mut regular = true;
    for &c in vs {
        faces_around(t, c as usize, |g| {
            let gv = t.face_vertices(g);
            regular &= gv.len() == 4 && gv.iter().all(|&w| t.valence(w as usize) == 4);
        });
    }
    if regular {
        FaceClass::R
    } else {
        FaceClass::None
    }
}

/// Classes of all faces.
pub fn classify_all(t: &Topology) -> Vec<FaceClass> {
    (0..t.num_faces()).map(|f| classify(t, f)).collect()
}
