//! `ccss info MESH.obj [--weights W.tsv]`: counts, histograms, patch counts
//! and memory of a mesh, as plain `key: value` lines; with `--weights`, also
//! the vertex rule of each valence of the mesh and whether it is
//! tangent-plane continuous.
//!
//! The combinatorial part (counts, histograms, Euler characteristic) comes
//! from the raw face lists and is printed even when the core rejects the
//! mesh; the command then ends with the core's reason (exit code 1).
//!
//! Meshes with OpenSubdiv tags, boundaries or non-manifold parts are
//! described as the feature evaluator sees them (OpenSubdiv's rules): the
//! scheme options, the tags, and what the evaluator caches.

use super::eval::{with_feature_mesh_only, CacheArgs};
use crate::context::{build_tables, with_context, BuildError};
use crate::error::CliResult;
use crate::io::mesh_in::Mesh;
use crate::io::weights_file::WeightsArg;
use crate::mem::words;
use crate::mesh_stats::Stats;
use crate::stdout;
use ccss_core::mesh::features::FeatureMesh;
use ccss_core::mesh::sharpness::{Boundary, Creasing};
use ccss_core::{Error, FeatureEvaluator};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// `--help` text of the verb.
pub const ABOUT: &str = "\
Print facts about a mesh as 'key: value' lines: vertex, face and edge counts, the face-size \
and valence histograms ('face size 4: 6', 'valence 3: 8'), connected components, Euler \
characteristic and genus; then what the evaluator makes of it: sub-faces, regular and \
extraordinary patches, internal refinement levels, and the bytes used by the topology, \
the evaluator and the eigen tables, with build times. If the mesh is not supported \
(open, non-manifold, valence out of range, ...) the counts are printed and the command \
fails with the reason, naming the vertex, edge or face (exit code 1). With --weights W.tsv \
(the format of 'ccss eval --help') the tables are built for that vertex rule, and for each \
valence that occurs (vertex valences, and the sizes of non-quad faces, whose centres become \
vertices of that valence) a line 'weights n: alpha beta gamma tangent_plane_continuous=yes|no' \
tells the rule and whether it gives a tangent-plane continuous surface there (the \
frequency-0 eigenvalues below the subdominant one). Meshes with OpenSubdiv tags ('t crease', 't corner', 't hole', options), boundaries or non-manifold parts are described as OpenSubdiv's rules see them: boundary interpolation, crease method, the tags (infinitely sharp and semi-sharp), then what the feature evaluator caches (B-spline pieces, eigen patches, split faces) and its bytes and build times.";

/// Arguments of `ccss info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Polygon mesh (OBJ).
    pub mesh: PathBuf,
    #[command(flatten)]
    pub weights: WeightsArg,
    #[command(flatten)]
    pub cache: CacheArgs,
}

/// Runs the verb.
pub fn run(a: &InfoArgs) -> CliResult {
    let weights = a.weights.load()?;
    let mesh = Mesh::load_with_tags(&a.mesh)?;
    let st = Stats::of(&mesh);
    let mut o = String::new();
    let _ = writeln!(o, "file: {}", mesh.name);
    let _ = writeln!(o, "vertices: {}", st.vertices);
    let unused = mesh.obj_vertex_lines.saturating_sub(st.vertices);
    if unused > 0 && mesh.obj_vertex.is_some() {
        let _ = writeln!(o, "unused vertex lines: {unused}");
    }
    let _ = writeln!(o, "faces: {}", st.faces);
    let _ = writeln!(o, "edges: {}", st.edges);
    for (n, c) in &st.face_sizes {
        let _ = writeln!(o, "face size {n}: {c}");
    }
    for (n, c) in &st.valences {
        let _ = writeln!(o, "valence {n}: {c}");
    }
    if a.weights.weights.is_some() {
        // The rules that matter: vertex valences, and the sizes of non-quad
        // faces (their centres become vertices of that valence).
        let present: BTreeSet<u32> = st
            .valences
            .keys()
            .chain(st.face_sizes.keys().filter(|&&s| s != 4))
            .copied()
            .filter(|&n| (3..=ccss_core::MAX_VALENCE as u32).contains(&n))
            .collect();
        for n in present {
            let n = n as usize;
            let (al, be, ga) = weights.get(n);
            let tpc = if weights.tangent_plane_continuous(n) {
                "yes"
            } else {
                "no"
            };
            let _ = writeln!(
                o,
                "weights {n}: {al} {be} {ga} tangent_plane_continuous={tpc}"
            );
        }
    }
    let _ = writeln!(o, "boundary edges: {}", st.boundary_edges);
    if st.nonmanifold_edges > 0 {
        let _ = writeln!(o, "non-manifold edges: {}", st.nonmanifold_edges);
    }
    let _ = writeln!(o, "components: {}", st.components);
    let _ = writeln!(o, "euler characteristic: {}", st.euler());
    if mesh.tag_lines > 0 {
        let _ = writeln!(o, "tag lines: {}", mesh.tag_lines);
    }
    if !mesh.tags.ignored.is_empty() {
        let _ = writeln!(o, "ignored tag lines: {}", mesh.tags.ignored.len());
    }
    if mesh.tags.any() && a.weights.weights.is_none() {
        return features(&mesh, a.cache, o);
    }

    let (tables, t_tables) = build_tables(&weights)?;
    let built = with_context(&mesh, &tables, |ctx| {
        let ev = &ctx.evaluator;
        let (regular, extraordinary) = ev.patch_counts();
        let subfaces: usize = (0..ev.num_faces()).map(|f| ev.num_subfaces(f)).sum();
        let mut o = String::new();
        let _ = writeln!(o, "genus: {}", st.genus());
        let _ = writeln!(o, "sub-faces: {subfaces}");
        let _ = writeln!(o, "regular patches: {regular}");
        let _ = writeln!(o, "extraordinary patches: {extraordinary}");
        let _ = writeln!(o, "internal refinement levels: {}", ev.internal_levels());
        let _ = writeln!(o, "topology bytes: {}", ctx.memory.topology);
        let _ = writeln!(o, "evaluator bytes: {}", ctx.memory.evaluator);
        let _ = writeln!(o, "tables bytes: {}", ctx.memory.tables);
        let _ = writeln!(o, "max valence: {}", ccss_core::MAX_VALENCE);
        let _ = writeln!(o, "tables build ms: {:.3}", ms(t_tables));
        let _ = writeln!(o, "topology build ms: {:.3}", ms(ctx.timings.topology));
        let _ = writeln!(o, "evaluator build ms: {:.3}", ms(ctx.timings.evaluator));
        o
    });
    match built {
        Ok(rest) => {
            o.push_str(&rest);
            stdout::text(&o)
        }
        // Open, non-manifold or high-valence meshes: OpenSubdiv's rules.
        Err(BuildError::Topology(
            Error::BoundaryEdge { .. }
            | Error::NonManifoldEdge { .. }
            | Error::NonManifoldVertex { .. }
            | Error::InconsistentOrientation { .. }
            | Error::UnusedVertex { .. }
            | Error::UnsupportedValence { .. },
        )) if a.weights.weights.is_none() => features(&mesh, a.cache, o),
        Err(e) => {
            stdout::text(&o)?;
            Err(e.into_cli(&mesh))
        }
    }
}

/// `infinitely sharp: a, semi-sharp: b` of sharpness values.
fn sharp_classes(values: impl Iterator<Item = f32>) -> (usize, usize, usize) {
    let (mut inf, mut semi, mut n) = (0, 0, 0);
    for s in values {
        n += 1;
        if s >= 10.0 {
            inf += 1;
        } else if s > 0.0 {
            semi += 1;
        }
    }
    (n, inf, semi)
}

/// The part of the report for a mesh with features (after the counts in
/// `o`).
fn features(mesh: &Mesh, cache: CacheArgs, mut o: String) -> CliResult {
    let cache = cache.cache();
    let t = &mesh.tags;
    let start = Instant::now();
    let built = with_feature_mesh_only(mesh, None, None, |fm| {
        let t_mesh = start.elapsed();
        let opts = fm.options;
        let _ = writeln!(
            o,
            "surface: OpenSubdiv's rules (boundaries, creases, corners, holes)"
        );
        let boundary = match opts.boundary {
            Boundary::None => "none",
            Boundary::EdgeOnly => "edge-only",
            Boundary::EdgeAndCorner => "edge-and-corner",
        };
        let creasing = match opts.creasing {
            Creasing::Uniform => "uniform",
            Creasing::Chaikin => "chaikin",
        };
        let _ = writeln!(o, "boundary interpolation: {boundary}");
        let _ = writeln!(o, "crease method: {creasing}");
        let smooth = if opts.smooth_triangles { "yes" } else { "no" };
        let _ = writeln!(o, "smooth triangles: {smooth}");
        let (n, inf, semi) = sharp_classes(t.creases.iter().map(|c| c.2));
        let _ = writeln!(
            o,
            "crease edges: {n} (infinitely sharp: {inf}, semi-sharp: {semi})"
        );
        let (n, inf, semi) = sharp_classes(t.corners.iter().map(|c| c.1));
        let _ = writeln!(
            o,
            "corner vertices: {n} (infinitely sharp: {inf}, semi-sharp: {semi})"
        );
        let _ = writeln!(o, "hole faces: {}", t.holes.len());
        let (tables, _) = build_tables(&ccss_core::Weights::STANDARD)?;
        let ebytes = FeatureEvaluator::required_bytes_with(fm, Some(&tables), cache);
        let mut emem = words(ebytes);
        let t0 = Instant::now();
        let fe = FeatureEvaluator::build_with(fm, Some(&tables), cache, &mut emem)
            .map_err(|e| mesh.error(e))?;
        let t_eval = t0.elapsed();
        let subfaces: usize = (0..fe.num_faces()).map(|f| fe.num_subfaces(f)).sum();
        let c = fe.cache_counts();
        let mbytes = FeatureMesh::required_bytes(&mesh.input()).map_err(|e| mesh.error(e))?;
        let _ = writeln!(o, "sub-faces: {subfaces}");
        let _ = writeln!(o, "level-1 faces: {}", c.level1_faces);
        let _ = writeln!(o, "cached B-spline pieces: {}", c.grids);
        let _ = writeln!(o, "cached eigen patches: {}", c.eigen_patches);
        let _ = writeln!(o, "cached crease strips: {}", c.crease_strips);
        let _ = writeln!(o, "split level-1 faces: {}", c.split_faces);
        let _ = writeln!(
            o,
            "cache tree nodes: {} (depth {})",
            c.nodes,
            fe.cache_depth()
        );
        let _ = writeln!(o, "feature mesh bytes: {mbytes}");
        let _ = writeln!(o, "feature evaluator bytes: {ebytes}");
        let _ = writeln!(o, "feature mesh build ms: {:.3}", ms(t_mesh));
        let _ = writeln!(o, "feature evaluator build ms: {:.3}", ms(t_eval));
        Ok(())
    });
    match built {
        Ok(()) => stdout::text(&o),
        Err(e) => {
            stdout::text(&o)?;
            Err(e)
        }
    }
}
