//! Benchmark and shrinkage study of the unified scheme (Maillot & Stam 2001).
//!
//! ```sh
//! cargo run --release -p ccss-core --example unified_bench
//! ```
//!
//! 1. **Speed**: refined vertices per second, one thread, of the plain
//!    Catmull-Clark step (`refine::refine`) and of `unified::refine_unified`
//!    on the same input topology (built once, outside the timing; output
//!    memory allocated once, outside the timing). Median of 9 rounds, each
//!    round timing every variant once (interleaved, so that load changes of
//!    a shared machine hit all variants alike).
//! 2. **Shrinking and popping** on corpus models: for a in {0, 0.5, 0.7, 1}
//!    (d = 2, b = 0, g = 0, p = 3) and levels 1-3,
//!    * volume ratio `V_l / V_0` (divergence theorem on the fan-triangulated
//!      mesh, `V = Σ p0 · (p1 x p2) / 6`);
//!    * silhouette change: the three axis-aligned orthographic silhouettes
//!      are rasterised into 1024² masks (common frame: the base mesh's
//!      bounding box plus 25 %), and the changed area `|S_l xor S_0| /
//!      |S_0|` is averaged over the three views (the paper's image-difference
//!      measure, Figs. 1, 3, 6); "popping" is the same between consecutive
//!      levels `l - 1` and `l`.
//!
//! 3. One step for each `d = 2..7` (the paper's Fig. 11 setting, `a = 1/2`,
//!    `b = 0`, against `a = 0`): volume and silhouette change vs the base.
//!
//! Corpus: `tests/data/osd/*.obj` (OpenSubdiv regression shapes, closed
//! ones only).
use ccss_core::unified::{
    refine_unified, refine_unified_levels, unified_bytes, unified_levels_bytes, TriangleRule,
    UnifiedParams,
};
use ccss_core::{mesh::refine, MeshInput, Topology, Weights};
use std::path::Path;
use std::time::Instant;

/// An owned polygon mesh.
#[derive(Clone)]
struct Mesh {
    pos: Vec<f64>,
    sizes: Vec<u32>,
    idx: Vec<u32>,
}

impl Mesh {
    fn input(&self) -> MeshInput<'_> {
        MeshInput {
            positions: &self.pos,
            face_sizes: &self.sizes,
            indices: &self.idx,
        }
    }
    fn from(m: MeshInput) -> Mesh {
        Mesh {
            pos: m.positions.to_vec(),
            sizes: m.face_sizes.to_vec(),
            idx: m.indices.to_vec(),
        }
    }
    fn p(&self, v: u32) -> [f64; 3] {
        let v = v as usize;
        [self.pos[3 * v], self.pos[3 * v + 1], self.pos[3 * v + 2]]
    }
    /// Fan triangles of every face.
    fn triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        let mut c = 0;
        for &n in &self.sizes {
            let f = &self.idx[c..c + n as usize];
            for k in 1..f.len() - 1 {
                out.push([f[0], f[k], f[k + 1]]);
            }
            c += n as usize;
        }
        out
    }
    fn volume(&self) -> f64 {
        let mut v = 0.0;
        for [a, b, c] in self.triangles() {
            let (a, b, c) = (self.p(a), self.p(b), self.p(c));
            let cross = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            v += a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2];
        }
        v / 6.0
    }
    fn bbox(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::MAX; 3];
        let mut hi = [f64::MIN; 3];
        for p in self.pos.chunks(3) {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }
}

/// Minimal OBJ reader: `v` and `f` lines (1-based or negative indices,
/// `v/vt/vn` forms).
fn load_obj(path: &Path) -> Mesh {
    let text = std::fs::read_to_string(path).expect("read obj");
    let mut m = Mesh {
        pos: Vec::new(),
        sizes: Vec::new(),
        idx: Vec::new(),
    };
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                for _ in 0..3 {
                    m.pos.push(it.next().unwrap().parse().unwrap());
                }
            }
            Some("f") => {
                let nv = (m.pos.len() / 3) as i64;
                let mut n = 0;
                for tok in it {
                    let i: i64 = tok.split('/').next().unwrap().parse().unwrap();
                    let i = if i < 0 { nv + i } else { i - 1 };
                    m.idx.push(i as u32);
                    n += 1;
                }
                m.sizes.push(n);
            }
            _ => {}
        }
    }
    m
}

fn aligned(bytes: usize) -> Vec<u64> {
    vec![0u64; bytes.div_ceil(8).max(1)]
}

fn with_topo<R>(m: &Mesh, f: impl FnOnce(&Topology) -> R) -> Option<R> {
    let mut mem = aligned(Topology::required_bytes(m.pos.len() / 3, &m.sizes));
    let t = Topology::build(m.input(), &mut mem).ok()?;
    Some(f(&t))
}

fn unified(m: &Mesh, p: &UnifiedParams) -> Mesh {
    with_topo(m, |t| {
        let mut mem = aligned(unified_bytes(t, p).unwrap());
        Mesh::from(refine_unified(t, p, &mut mem).unwrap().mesh)
    })
    .unwrap()
}

/// Levels 1..=n of the unified scheme in one call.
fn unified_levels(m: &Mesh, p: &[UnifiedParams]) -> Vec<Mesh> {
    with_topo(m, |t| {
        let mut mem = aligned(unified_levels_bytes(t, p).unwrap());
        let l = refine_unified_levels(t, p, &mut mem).unwrap();
        l.meshes().iter().map(|x| Mesh::from(*x)).collect()
    })
    .unwrap()
}

fn cc(m: &Mesh) -> Mesh {
    with_topo(m, |t| {
        let mut mem = aligned(refine::refine_bytes(t));
        Mesh::from(
            refine::refine(t, &Weights::STANDARD, &mut mem)
                .unwrap()
                .mesh,
        )
    })
    .unwrap()
}

/// Seconds per call of `f`, repeated until at least 10 ms pass (to beat
/// timer resolution).
fn batch(f: &mut dyn FnMut()) -> f64 {
    let mut reps = 0u32;
    let t0 = Instant::now();
    loop {
        f();
        reps += 1;
        if t0.elapsed().as_secs_f64() > 0.01 {
            break;
        }
    }
    t0.elapsed().as_secs_f64() / reps as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

/// Rounds of interleaved timings (every variant once per round, so that
/// load changes of the shared machine hit all of them alike).
const ROUNDS: usize = 9;

fn speed(name: &str, m: &Mesh) {
    with_topo(m, |t| {
        let runs: [(&str, UnifiedParams); 7] = [
            (
                "unified d=2, CC params (a=0,b=0,g=1)",
                UnifiedParams::CATMULL_CLARK,
            ),
            (
                "unified d=2, a=b=1/2, g=0 (defaults)",
                UnifiedParams::default(),
            ),
            (
                "unified d=2, a=b=1/2, g=1, polygon triangles",
                UnifiedParams {
                    g: 1.0,
                    triangles: TriangleRule::Polygon,
                    ..Default::default()
                },
            ),
            ("unified d=3, defaults", UnifiedParams::default().with_d(3)),
            ("unified d=4, defaults", UnifiedParams::default().with_d(4)),
            ("unified d=5, defaults", UnifiedParams::default().with_d(5)),
            ("unified d=6, defaults", UnifiedParams::default().with_d(6)),
        ];
        let mut cc_mem = aligned(refine::refine_bytes(t));
        let cc_verts = t.num_vertices() + t.num_edges() + t.num_faces();
        let mut mems: Vec<Vec<u64>> = runs
            .iter()
            .map(|(_, p)| aligned(unified_bytes(t, p).unwrap()))
            .collect();
        let verts: Vec<usize> = runs
            .iter()
            .map(|(_, p)| ccss_core::unified::unified_counts(t, p).unwrap().vertices)
            .collect();
        let mut cc_t = Vec::new();
        let mut un_t = vec![Vec::new(); runs.len()];
        for _ in 0..ROUNDS {
            cc_t.push(batch(&mut || {
                let r = refine::refine(t, &Weights::STANDARD, &mut cc_mem).unwrap();
                std::hint::black_box(r.mesh.positions[0]);
            }));
            for (k, (_, p)) in runs.iter().enumerate() {
                let mem = &mut mems[k];
                un_t[k].push(batch(&mut || {
                    let r = refine_unified(t, p, mem).unwrap();
                    std::hint::black_box(r.mesh.positions[0]);
                }));
            }
        }
        let cc_t = median(cc_t);
        let cc_rate = cc_verts as f64 / cc_t;
        println!(
            "| {name} | {} | Catmull-Clark (`refine::refine`) | {cc_verts} | {:.3} | {:.1} | 1.00 |",
            t.num_faces(),
            cc_t * 1e3,
            cc_rate / 1e6
        );
        for (k, (label, _)) in runs.iter().enumerate() {
            let tt = median(un_t[k].clone());
            let rate = verts[k] as f64 / tt;
            println!(
                "| {name} | {} | {label} | {} | {:.3} | {:.1} | {:.2} |",
                t.num_faces(),
                verts[k],
                tt * 1e3,
                rate / 1e6,
                cc_rate / rate
            );
        }
    });
}

/// Orthographic silhouette along `axis` as a `RES x RES` mask in the frame
/// `(lo, hi)`.
const RES: usize = 1024;

fn silhouette(m: &Mesh, axis: usize, lo: [f64; 3], hi: [f64; 3]) -> Vec<bool> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut mask = vec![false; RES * RES];
    let to_px = |p: [f64; 3]| -> (f64, f64) {
        (
            (p[u] - lo[u]) / (hi[u] - lo[u]) * RES as f64,
            (p[v] - lo[v]) / (hi[v] - lo[v]) * RES as f64,
        )
    };
    for [a, b, c] in m.triangles() {
        let (a, b, c) = (to_px(m.p(a)), to_px(m.p(b)), to_px(m.p(c)));
        let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if area == 0.0 {
            continue;
        }
        let x0 = a.0.min(b.0).min(c.0).floor().max(0.0) as usize;
        let x1 = (a.0.max(b.0).max(c.0).ceil() as usize).min(RES);
        let y0 = a.1.min(b.1).min(c.1).floor().max(0.0) as usize;
        let y1 = (a.1.max(b.1).max(c.1).ceil() as usize).min(RES);
        let s = area.signum();
        let edge = |p: (f64, f64), q: (f64, f64), x: f64, y: f64| {
            s * ((q.0 - p.0) * (y - p.1) - (q.1 - p.1) * (x - p.0)) >= 0.0
        };
        for y in y0..y1 {
            for x in x0..x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                if edge(a, b, px, py) && edge(b, c, px, py) && edge(c, a, px, py) {
                    mask[y * RES + x] = true;
                }
            }
        }
    }
    mask
}

/// Mean over the three views of `|A xor B| / |B0|`.
fn change(a: &[Vec<bool>; 3], b: &[Vec<bool>; 3], base: &[Vec<bool>; 3]) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let x = a[k].iter().zip(&b[k]).filter(|(p, q)| p != q).count();
        let n = base[k].iter().filter(|&&p| p).count();
        s += x as f64 / n as f64;
    }
    s / 3.0
}

fn study(name: &str, m: &Mesh, b: f64) {
    let (mut lo, mut hi) = m.bbox();
    for a in 0..3 {
        let pad = 0.25 * (hi[a] - lo[a]).max(1e-9);
        lo[a] -= pad;
        hi[a] += pad;
    }
    let views = |x: &Mesh| [0, 1, 2].map(|k| silhouette(x, k, lo, hi));
    let v0 = m.volume();
    let s0 = views(m);
    let mut rows: Vec<(String, Vec<Mesh>)> = Vec::new();
    let c1 = cc(m);
    let c2 = cc(&c1);
    let c3 = cc(&c2);
    rows.push(("Catmull-Clark".into(), vec![c1, c2, c3]));
    for a in [0.0, 0.5, 0.7, 1.0] {
        let p = UnifiedParams {
            a,
            b,
            g: 0.0,
            d: 2,
            p: 3,
            triangles: TriangleRule::Split,
        };
        rows.push((format!("a = {a}"), unified_levels(m, &[p; 3])));
    }
    for (label, levels) in rows {
        let mut prev = s0.clone();
        let mut cells = Vec::new();
        for cur in &levels {
            let s = views(cur);
            cells.push(format!(
                "{:.1} / {:.1} / {:.1}",
                100.0 * cur.volume() / v0,
                100.0 * change(&s, &s0, &s0),
                100.0 * change(&s, &prev, &s0)
            ));
            prev = s;
        }
        println!("| {name} | {label} | {} |", cells.join(" | "));
    }
}

/// One step with each `d` (the paper's Fig. 11 setting: a = 1/2, b = 0,
/// g = 0, p = 3, against a = 0): volume % and silhouette change % vs base.
fn d_sweep(name: &str, m: &Mesh) {
    let (mut lo, mut hi) = m.bbox();
    for a in 0..3 {
        let pad = 0.25 * (hi[a] - lo[a]).max(1e-9);
        lo[a] -= pad;
        hi[a] += pad;
    }
    let views = |x: &Mesh| [0, 1, 2].map(|k| silhouette(x, k, lo, hi));
    let v0 = m.volume();
    let s0 = views(m);
    for a in [0.0, 0.5] {
        let mut cells = Vec::new();
        for d in 2..=7 {
            let p = UnifiedParams {
                a,
                b: 0.0,
                g: 0.0,
                d,
                p: 3,
                triangles: TriangleRule::Split,
            };
            let x = unified(m, &p);
            cells.push(format!(
                "{:.1} / {:.1}",
                100.0 * x.volume() / v0,
                100.0 * change(&views(&x), &s0, &s0)
            ));
        }
        println!("| {name} | a = {a} | {} |", cells.join(" | "));
    }
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/osd");
    let names = [
        "catmark_cube",
        "catmark_pyramid",
        "catmark_toroidal_tet",
        "catmark_torus",
        "catmark_righthanded",
    ];
    let models: Vec<(&str, Mesh)> = names
        .iter()
        .map(|n| (*n, load_obj(&dir.join(format!("{n}.obj")))))
        .collect();

    println!("## Speed: one refinement step, refined vertices per second (single thread)\n");
    println!("| input | faces | step | refined vertices | ms | M vertices/s | CC rate / this |");
    println!("|---|---:|---|---:|---:|---:|---:|");
    let right = &models[4].1;
    let r1 = cc(right);
    let r2 = cc(&r1);
    speed("righthanded", right);
    speed("righthanded, CC level 1", &r1);
    speed("righthanded, CC level 2", &r2);
    speed("pyramid, CC level 4", &cc(&cc(&cc(&cc(&models[1].1)))));
    speed(
        "torus (all regular), CC level 3",
        &cc(&cc(&cc(&models[3].1))),
    );

    for b in [0.0, 0.5] {
        println!(
            "\n## Shrinking (d = 2, b = {b}, g = 0, p = 3): volume % of base / silhouette change % vs base / popping % vs previous level\n"
        );
        println!("| model | scheme | level 1 | level 2 | level 3 |");
        println!("|---|---|---|---|---|");
        for (name, m) in &models {
            study(name, m, b);
        }
    }
    println!("\n## One step with d = 2..7 (b = 0, g = 0, p = 3): volume % of base / silhouette change % vs base\n");
    println!("| model | a | d = 2 | d = 3 | d = 4 | d = 5 | d = 6 | d = 7 |");
    println!("|---|---|---|---|---|---|---|---|");
    for (name, m) in &models {
        d_sweep(name, m);
    }
}
