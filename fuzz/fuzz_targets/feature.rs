//! Meshes with features (boundaries, creases, corners, holes):
//! `FeatureMesh` from the OBJ's OpenSubdiv tags (vertex numbers mapped as
//! `ccss eval` maps them; unmapped ones stay invalid), with header byte 2
//! overriding the boundary / crease options, byte 3 distorting the
//! sharpness values (scaled, NaN, negative, infinite, huge), byte 4 the
//! cache depth (0..=4); then `FeatureEvaluator`, evaluations, depths and a
//! small tessellation (byte 5). No panic; tame meshes give finite points;
//! the tessellation emits in range.
#![no_main]
use ccss_core::bounds::feature_depth::feature_depth;
use ccss_core::eval::{FeatureCache, Query};
use ccss_core::mesh::features::{FeatureInput, FeatureMesh};
use ccss_core::mesh::sharpness::{Boundary, Creasing, FeatureOptions};
use ccss_core::tessellate::{Criterion, Options, Output, Scratch, Tessellation};
use ccss_core::{Error, FeatureEvaluator};
use ccss_fuzz::{assert_finite, tables, words, Caps, Input};
use libfuzzer_sys::fuzz_target;
use std::cell::RefCell;

thread_local! {
    static SCRATCH: RefCell<Box<Scratch>> = RefCell::new(Box::new(Scratch::ZERO));
}

const CAPS: Caps = Caps {
    faces: 16,
    corners: 64,
};

fn sharp(s: f32, how: u8) -> f32 {
    match how % 8 {
        0..=2 => s,
        3 => s * (how >> 3) as f32 / 8.0,
        4 => f32::NAN,
        5 => -s,
        6 => 1e30,
        _ => (how >> 3) as f32 / 4.0,
    }
}

fuzz_target!(|data: &[u8]| {
    let Some(x) = Input::parse(data, CAPS) else {
        return;
    };
    let h = x.header;
    let m = &x.mesh;
    let mut of_line = vec![u32::MAX; m.obj_vertex_lines];
    for v in 0..m.num_vertices() as u32 {
        of_line[m.obj_vertex(v) as usize] = v;
    }
    let map = |l: u32| of_line.get(l as usize).copied().unwrap_or(u32::MAX);
    let t = &m.tags;
    let cv: Vec<u32> = t
        .creases
        .iter()
        .flat_map(|c| [map(c.0), map(c.1)])
        .collect();
    let cs: Vec<f32> = t.creases.iter().map(|c| sharp(c.2, h[3])).collect();
    let kv: Vec<u32> = t.corners.iter().map(|c| map(c.0)).collect();
    let ks: Vec<f32> = t.corners.iter().map(|c| sharp(c.1, h[3] >> 1)).collect();
    let holes: Vec<u32> = t.holes.iter().map(|h| h.0).collect();
    let options = FeatureOptions {
        boundary: match h[2] & 3 {
            1 => Boundary::None,
            2 => Boundary::EdgeOnly,
            3 => Boundary::EdgeAndCorner,
            _ => t.boundary.unwrap_or_default(),
        },
        creasing: match (h[2] >> 2) & 3 {
            1 => Creasing::Uniform,
            2 => Creasing::Chaikin,
            _ => t.creasing.unwrap_or_default(),
        },
        smooth_triangles: t.smooth_triangles.unwrap_or(false) ^ (h[2] & 16 != 0),
    };
    let tags = FeatureInput {
        crease_vertices: &cv,
        crease_sharpness: &cs,
        corner_vertices: &kv,
        corner_sharpness: &ks,
        holes: &holes,
        options,
    };
    let input = x.input();
    let Ok(need) = FeatureMesh::required_bytes(&input) else {
        return;
    };
    let mut mmem = words(need);
    let Ok(fm) = FeatureMesh::build(&input, &tags, &mut mmem) else {
        return;
    };
    let cache = FeatureCache {
        depth: h[4] as u32 % 3,
        ..FeatureCache::default()
    };
    let tb = if h[4] & 0x80 != 0 {
        None
    } else {
        Some(tables())
    };
    let ebytes = FeatureEvaluator::required_bytes_with(&fm, tb, cache);
    let mut emem = words(ebytes);
    let fe = match FeatureEvaluator::build_with(&fm, tb, cache, &mut emem) {
        Ok(fe) => fe,
        Err(Error::CoordinateRange(_) | Error::InvalidArgument(_)) => return,
        Err(e) => panic!("feature evaluator: {e:?}"),
    };
    let mut r = x.rng();
    let nf = fe.num_faces() as u64;
    for _ in 0..4 {
        let face = r.below(nf + 1) as u32;
        let sub = r.below(5) as u32;
        let (u, v) = (r.param(), r.param());
        if let Ok(e) = fe.eval_second(face, sub, u, v) {
            if x.tame() {
                assert_finite("p", &e.p.to_array());
            }
            let _ = fe.piece_depth(&Query { face, sub, u, v });
        }
        let eps = x.max_abs.max(1e-300) * 2f64.powi(-1 - (r.below(6) as i32));
        let _ = feature_depth(&fe, face, sub, eps);
    }
    let opts = Options {
        criterion: if h[5] & 1 == 0 {
            Criterion::Uniform((h[5] as u32 >> 1) % 2)
        } else {
            Criterion::Relative(2f64.powi(-1 - (h[5] as i32 >> 1) % 4))
        },
        max_level: 2,
    };
    let Ok(tbytes) =
        SCRATCH.with(|s| Tessellation::required_bytes_feature(&fe, &opts, &mut s.borrow_mut()))
    else {
        return;
    };
    let mut tmem = words(tbytes);
    let mut ts = Tessellation::build_feature(&fe, opts, &mut tmem).expect("size query accepted it");
    let c = ts.counts();
    let mut pos = vec![0.0; 3 * c.vertices];
    let mut sizes = vec![0; c.polygons];
    let mut idx = vec![0; c.polygon_indices];
    ts.emit(Output {
        positions: &mut pos,
        normals: None,
        params: None,
        polygon_sizes: &mut sizes,
        polygon_indices: &mut idx,
        triangles: None,
        cells: None,
    })
    .expect("exact buffers");
    assert!(idx.iter().all(|&i| (i as usize) < c.vertices));
    if x.tame() {
        assert_finite("positions", &pos);
    }
});
