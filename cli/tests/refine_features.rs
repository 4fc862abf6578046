//! `ccss refine --scheme catmull-clark` on meshes with OpenSubdiv tags,
//! boundaries, holes and non-manifold parts, against the sharp reference
//! subdivider (`ccss_tests::sharp`, itself equal to OpenSubdiv's uniform
//! refinement index by index, `tests/tests/sharp_reference.rs`): after two
//! levels the output has the reference's vertices (matched by position to
//! 1e-12 of the diagonal, one to one), faces (same cycles, same
//! orientation), edge and vertex sharpness (read back from the output's
//! `t` tags, exactly) and holes. The unified scheme refuses such meshes.
mod common;
use ccss_tests::harness::corpus_shapes;
use ccss_tests::sharp::{Level, SharpRefiner, TaggedMesh};
use common::*;
use std::collections::HashMap;

/// Matches every vertex of `a` to the vertex of `b` at the same place
/// (grid hashing with cell `tol`), one to one, except vertices that no
/// face uses (the reference keeps them, as OpenSubdiv does; `ccss` reads
/// only the vertices faces use, so it has none): those map to `u32::MAX`.
fn match_vertices(a: &Level, b: &Level, tol: f64) -> Result<Vec<u32>, String> {
    let used = |l: &Level| l.vert_faces.iter().filter(|f| !f.is_empty()).count();
    if used(a) != used(b) {
        return Err(format!("{} used vertices vs {}", used(a), used(b)));
    }
    let cell = |p: &[f64; 3]| {
        [
            (p[0] / (4.0 * tol)).floor() as i64,
            (p[1] / (4.0 * tol)).floor() as i64,
            (p[2] / (4.0 * tol)).floor() as i64,
        ]
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, p) in b.positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i as u32);
    }
    let mut taken = vec![false; b.positions.len()];
    let mut map = Vec::with_capacity(a.positions.len());
    for (i, p) in a.positions.iter().enumerate() {
        if a.vert_faces[i].is_empty() {
            map.push(u32::MAX);
            continue;
        }
        let c = cell(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                        .into_iter()
                        .flatten()
                    {
                        let q = &b.positions[j as usize];
                        let d =
                            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                                .sqrt();
                        if d <= tol && !taken[j as usize] && !b.vert_faces[j as usize].is_empty() {
                            found = Some(j);
                            break 'search;
                        }
                    }
                }
            }
        }
        let j = found.ok_or(format!("vertex {i} at {p:?} has no partner"))?;
        taken[j as usize] = true;
        map.push(j);
    }
    Ok(map)
}

/// Whether two used vertices of `l` lie within `tol` of each other.
fn has_coincident(l: &Level, tol: f64) -> bool {
    let mut keys: Vec<(f64, usize)> = (0..l.positions.len())
        .filter(|&i| !l.vert_faces[i].is_empty())
        .map(|i| (l.positions[i][0], i))
        .collect();
    keys.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (k, &(x, i)) in keys.iter().enumerate() {
        for &(y, j) in &keys[k + 1..] {
            if y - x > tol {
                break;
            }
            let (p, q) = (l.positions[i], l.positions[j]);
            let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            if d <= tol {
                return true;
            }
        }
    }
    false
}

/// A face cycle starting at its smallest vertex (orientation kept).
fn canonical(f: &[u32]) -> Vec<u32> {
    let k = (0..f.len()).min_by_key(|&k| f[k]).unwrap();
    (0..f.len()).map(|i| f[(k + i) % f.len()]).collect()
}

fn edge_key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

#[test]
fn two_levels_equal_the_sharp_reference_on_the_corpus() {
    let dir = out_dir("refine_features");
    let mut checked = Vec::new();
    let mut ambiguous = Vec::new();
    for path in corpus_shapes() {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let m = TaggedMesh::from_obj(&path).unwrap();
        let corners: usize = m.faces.iter().map(|f| f.len()).sum();
        // Smooth closed meshes go through the unified code; tags, open or
        // non-manifold ones through the sharp rules. Large shapes and
        // faces repeating a vertex (unsupported by the reference) skipped.
        if corners > 3000 {
            continue;
        }
        let Ok(mut r) = SharpRefiner::new(&m) else {
            continue;
        };
        let out = dir.join(format!("{name}.obj"));
        let o = ccss(&[
            "refine",
            "--scheme",
            "catmull-clark",
            "--levels",
            "2",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let ours_mesh = TaggedMesh::from_obj(&out).unwrap();
        let ours = Level::base(&ours_mesh).unwrap();
        let reference = r.level(2).clone();
        let tol = 1e-12 * m.bbox_diagonal();
        // Distinct vertices at one place (faces back to back) make the
        // matching by position ambiguous: such shapes are only counted.
        if has_coincident(&reference, tol) {
            let o = TaggedMesh::from_obj(&out).unwrap();
            assert_eq!(o.faces.len(), reference.faces.len(), "{name}: face count");
            ambiguous.push(name);
            continue;
        }
        let map = match_vertices(&reference, &ours, tol).unwrap_or_else(|e| panic!("{name}: {e}"));
        // Faces.
        let mut our_faces: HashMap<Vec<u32>, usize> = HashMap::new();
        for (f, face) in ours.faces.iter().enumerate() {
            our_faces.insert(canonical(face), f);
        }
        assert_eq!(
            ours.faces.len(),
            reference.faces.len(),
            "{name}: face count"
        );
        for (f, face) in reference.faces.iter().enumerate() {
            let mapped: Vec<u32> = face.iter().map(|&v| map[v as usize]).collect();
            let g = *our_faces
                .get(&canonical(&mapped))
                .unwrap_or_else(|| panic!("{name}: reference face {f} missing"));
            assert_eq!(
                ours.hole[g], reference.hole[f],
                "{name}: hole flag of face {f}"
            );
        }
        // Sharpness, exactly.
        let our_edges: HashMap<(u32, u32), usize> = ours
            .edges
            .iter()
            .enumerate()
            .map(|(e, p)| (edge_key(p[0], p[1]), e))
            .collect();
        for (e, p) in reference.edges.iter().enumerate() {
            let g = our_edges[&edge_key(map[p[0] as usize], map[p[1] as usize])];
            assert_eq!(
                ours.edge_sharpness[g], reference.edge_sharpness[e],
                "{name}: sharpness of edge {e}"
            );
        }
        for (v, &s) in reference.vertex_sharpness.iter().enumerate() {
            if map[v] == u32::MAX {
                continue;
            }
            assert_eq!(
                ours.vertex_sharpness[map[v] as usize], s,
                "{name}: sharpness of vertex {v}"
            );
        }
        checked.push(name);
    }
    println!("{} shapes checked: {}", checked.len(), checked.join(" "));
    println!(
        "{} shapes with coincident vertices (face counts only): {}",
        ambiguous.len(),
        ambiguous.join(" ")
    );
    assert!(checked.len() >= 60, "only {} shapes", checked.len());
}

#[test]
fn the_unified_scheme_refuses_features() {
    let dir = out_dir("refine_features");
    let out = dir.join("x.obj");
    for shape in ["catmark_cube_creases0.obj", "catmark_edgeonly.obj"] {
        let o = ccss(&[
            "refine",
            data(shape).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{shape}");
        let e = text(&o.stderr);
        assert!(
            e.contains("unified scheme has no rules") && e.contains("--scheme catmull-clark"),
            "{shape}: {e}"
        );
    }
}
