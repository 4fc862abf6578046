//! The library's input form of a [`TaggedMesh`] (flat arrays, tags,
//! options) and a helper that builds its `FeatureEvaluator`.
use crate::sharp::{self, TaggedMesh};
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::{mem::words_for, FeatureEvaluator, MeshInput};

/// Flat arrays and tags of a tagged mesh, in the library's input form.
pub struct Flat {
    /// x y z per vertex.
    pub p: Vec<f64>,
    /// Vertices per face.
    pub sizes: Vec<u32>,
    /// Face corners, concatenated.
    pub idx: Vec<u32>,
    /// Crease vertex pairs.
    pub cv: Vec<u32>,
    /// Crease sharpness per pair.
    pub cs: Vec<f32>,
    /// Sharp vertices.
    pub kv: Vec<u32>,
    /// Their sharpness.
    pub ks: Vec<f32>,
    /// Hole faces.
    pub holes: Vec<u32>,
    /// Scheme options.
    pub opts: FeatureOptions,
}

/// The flat arrays, tags and options of `m`.
pub fn flat(m: &TaggedMesh) -> Flat {
    let o = m.options;
    Flat {
        p: m.positions.iter().flat_map(|p| p.iter().copied()).collect(),
        sizes: m.faces.iter().map(|f| f.len() as u32).collect(),
        idx: m.faces.iter().flat_map(|f| f.iter().copied()).collect(),
        cv: m.creases.iter().flat_map(|c| [c.0, c.1]).collect(),
        cs: m.creases.iter().map(|c| c.2).collect(),
        kv: m.corners.iter().map(|c| c.0).collect(),
        ks: m.corners.iter().map(|c| c.1).collect(),
        holes: m.holes.clone(),
        opts: FeatureOptions {
            boundary: match o.boundary {
                sharp::Boundary::None => Boundary::None,
                sharp::Boundary::EdgeOnly => Boundary::EdgeOnly,
                sharp::Boundary::EdgeAndCorner => Boundary::EdgeAndCorner,
            },
            creasing: match o.creasing {
                sharp::Creasing::Uniform => Creasing::Uniform,
                sharp::Creasing::Chaikin => Creasing::Chaikin,
            },
            smooth_triangles: o.smooth_triangles,
        },
    }
}

/// Builds the feature mesh and evaluator of `f` and runs `run` on it.
pub fn with_feature_mesh<R>(
    f: &Flat,
    tables: Option<&ccss_core::TableSet>,
    run: impl FnOnce(&FeatureEvaluator) -> R,
) -> Result<R, ccss_core::Error> {
    let mesh = MeshInput {
        positions: &f.p,
        face_sizes: &f.sizes,
        indices: &f.idx,
    };
    let tags = FeatureInput {
        crease_vertices: &f.cv,
        crease_sharpness: &f.cs,
        corner_vertices: &f.kv,
        corner_sharpness: &f.ks,
        holes: &f.holes,
        options: f.opts,
    };
    let mut mem = vec![0u64; words_for(FeatureMesh::required_bytes(&mesh)?)];
    let fm = FeatureMesh::build(&mesh, &tags, &mut mem)?;
    let mut emem = vec![0u64; words_for(FeatureEvaluator::required_bytes(&fm, tables))];
    let fe = FeatureEvaluator::build(&fm, tables, &mut emem)?;
    Ok(run(&fe))
}

/// Builds the feature mesh of `f` and one evaluator per cache setting, and
/// runs `run` on them (the same surface through different cache trees).
pub fn with_feature_caches<R>(
    f: &Flat,
    tables: Option<&ccss_core::TableSet>,
    caches: [ccss_core::eval::FeatureCache; 2],
    run: impl FnOnce(&FeatureEvaluator, &FeatureEvaluator) -> R,
) -> Result<R, ccss_core::Error> {
    let mesh = MeshInput {
        positions: &f.p,
        face_sizes: &f.sizes,
        indices: &f.idx,
    };
    let tags = FeatureInput {
        crease_vertices: &f.cv,
        crease_sharpness: &f.cs,
        corner_vertices: &f.kv,
        corner_sharpness: &f.ks,
        holes: &f.holes,
        options: f.opts,
    };
    let mut mem = vec![0u64; words_for(FeatureMesh::required_bytes(&mesh)?)];
    let fm = FeatureMesh::build(&mesh, &tags, &mut mem)?;
    let bytes = |c| FeatureEvaluator::required_bytes_with(&fm, tables, c);
    let mut m0 = vec![0u64; words_for(bytes(caches[0]))];
    let mut m1 = vec![0u64; words_for(bytes(caches[1]))];
    let a = FeatureEvaluator::build_with(&fm, tables, caches[0], &mut m0)?;
    let b = FeatureEvaluator::build_with(&fm, tables, caches[1], &mut m1)?;
    Ok(run(&a, &b))
}

/// How far evaluation `got` is from `want`: the position distance over
/// `diag`, and the largest distance of a first or second derivative,
/// each relative to the larger of its own size, `want.du`'s and `diag`
/// (second derivatives next to a semi-sharp crease are large, and their
/// rounding with them), with the derivative's name.
pub fn eval_gap(
    got: &ccss_core::Eval,
    want: &ccss_core::Eval,
    diag: f64,
) -> (f64, f64, &'static str) {
    let dp = (got.p - want.p).length() / diag;
    let mut worst = (0.0, "du");
    for (name, g, w) in [
        ("du", got.du, want.du),
        ("dv", got.dv, want.dv),
        ("duu", got.duu, want.duu),
        ("duv", got.duv, want.duv),
        ("dvv", got.dvv, want.dvv),
    ] {
        let scale = w.length().max(want.du.length()).max(diag);
        let d = (g - w).length() / scale;
        if d > worst.0 {
            worst = (d, name);
        }
    }
    (dp, worst.0, worst.1)
}
