//! Tessellation with a tolerance field (`mark_slot_field` +
//! `build_marked`), on righthanded (extraordinary vertices of valence 3 to
//! 6, so corner-cell chains and light splits occur) and the torus:
//! * the output is a closed, consistently oriented 2-manifold (the crack
//!   elimination is that of any quadtree);
//! * every polygon's cell bound (`marking_bound`, recomputed top down) is
//!   at most `min(eps, field(box of the polygon's vertices))`: the
//!   per-triangle bound the Boolean uses is an upper bound of the real one;
//! * the field refines only where it is small: the polygon count lies
//!   strictly between the tessellations at `eps` and at the field's
//!   smallest value everywhere;
//! * a field that is `eps` everywhere gives exactly the trees of
//!   `mark_slot` (no field);
//! * criteria other than absolute flatness are refused.
mod tessellate_util;

use ccss_core::tessellate::{
    mark_slot, mark_slot_field, marking_bound, Criterion, Options, Output, PolygonCell, Scratch,
    SlotMark, Tessellation, ToleranceField,
};
use ccss_core::{DVec3, Error, Evaluator, Topology};
use ccss_tests::harness::{aligned, standard_tables, with_evaluator};
use tessellate_util::*;

/// `fine` inside a ball (centre, radius) met by the box, `coarse` elsewhere
/// (monotone: a larger box meets the ball whenever a smaller one does).
struct Ball {
    centre: DVec3,
    radius: f64,
    fine: f64,
    coarse: f64,
}

impl ToleranceField for Ball {
    fn tolerance(&self, lo: DVec3, hi: DVec3) -> f64 {
        let nearest = self.centre.clamp(lo, hi);
        if (nearest - self.centre).length() <= self.radius {
            self.fine
        } else {
            self.coarse
        }
    }
}

struct Out {
    pos: Vec<f64>,
    sizes: Vec<u32>,
    idx: Vec<u32>,
    cells: Vec<PolygonCell>,
    trees: Vec<u32>,
}

fn run_marked(
    topo: &Topology,
    ev: &Evaluator,
    opts: Options,
    field: Option<&dyn ToleranceField>,
) -> Out {
    let mut scratch = Box::new(Scratch::ZERO);
    let mut marks: Vec<SlotMark> = Vec::new();
    let mut trees = Vec::new();
    for s in 0..ev.num_slots() {
        let mut buf = vec![0u32; 16];
        let m = loop {
            let r = match field {
                Some(f) => mark_slot_field(ev, &opts, s, Some(&mut buf), f, &mut scratch),
                None => mark_slot(ev, &opts, s, Some(&mut buf), &mut scratch),
            };
            match r {
                Ok(m) => break m,
                Err(Error::BufferTooSmall { required }) => buf.resize(required, 0),
                Err(e) => panic!("slot {s}: {e}"),
            }
        };
        marks.push(m);
        trees.extend_from_slice(&buf[..m.nodes as usize]);
    }
    let need = Tessellation::required_bytes_marked(topo, &marks).unwrap();
    let mut mem = aligned(need);
    let mut t = Tessellation::build_marked(topo, ev, opts, &marks, &trees, &mut mem).unwrap();
    let c = t.counts();
    let mut o = Out {
        pos: vec![0.0; 3 * c.vertices],
        sizes: vec![0; c.polygons],
        idx: vec![0; c.polygon_indices],
        cells: vec![PolygonCell::default(); c.polygons],
        trees,
    };
    t.emit(Output {
        positions: &mut o.pos,
        normals: None,
        params: None,
        polygon_sizes: &mut o.sizes,
        polygon_indices: &mut o.idx,
        triangles: None,
        cells: Some(&mut o.cells),
    })
    .unwrap();
    o
}

fn polys(o: &Out) -> Vec<&[u32]> {
    let mut v = Vec::new();
    let mut at = 0usize;
    for &s in &o.sizes {
        v.push(&o.idx[at..at + s as usize]);
        at += s as usize;
    }
    v
}

fn check(name: &str) {
    let m = corpus(name);
    let (lo, hi) =
        m.positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                let p = DVec3::from_array(*p);
                (lo.min(p), hi.max(p))
            });
    let diag = (hi - lo).length();
    let eps = 2e-3 * diag;
    // The ball around the first control point (on or near the surface).
    let field = Ball {
        centre: DVec3::from_array(m.positions[0]),
        radius: 0.15 * diag,
        fine: eps / 8.0,
        coarse: eps,
    };
    with_evaluator(&m, standard_tables(), |topo, ev| {
        let opts = Options::absolute(eps);
        let plain = run_marked(topo, ev, opts, None);
        let local = run_marked(topo, ev, opts, Some(&field));
        let fine = run_marked(topo, ev, Options::absolute(eps / 8.0), None);
        let n = local.pos.len() / 3;
        check_closed_manifold(name, n, &polys(&local));
        // Bounds against the field at each polygon's box.
        let mut finer = 0usize;
        for (k, f) in polys(&local).iter().enumerate() {
            let c = local.cells[k];
            let b = marking_bound(ev, c.face, c.sub, c.level, c.i, c.j).unwrap();
            let p = |v: u32| DVec3::from_slice(&local.pos[3 * v as usize..3 * v as usize + 3]);
            let (blo, bhi) = f.iter().fold(
                (DVec3::INFINITY, DVec3::NEG_INFINITY),
                |(lo, hi), &v| (lo.min(p(v)), hi.max(p(v))),
            );
            let allowed = field.tolerance(blo, bhi).min(eps);
            assert!(
                b <= allowed,
                "{name}: polygon {k} (cell {c:?}) bound {b:e} above the field's {allowed:e}"
            );
            if b <= eps / 8.0 {
                finer += 1;
            }
        }
        let (np, nl, nf) = (plain.sizes.len(), local.sizes.len(), fine.sizes.len());
        eprintln!("{name}: polygons at eps {np}, with the field {nl}, at eps/8 {nf}; {finer} cells within eps/8");
        assert!(np < nl && nl < nf, "{name}: {np} < {nl} < {nf} expected");
        // A field equal to eps everywhere: the plain trees.
        let flat = Ball {
            coarse: eps,
            fine: eps,
            ..field
        };
        let same = run_marked(topo, ev, opts, Some(&flat));
        assert_eq!(same.trees, plain.trees, "{name}: a constant field changed the trees");
        // Only absolute flatness takes a field.
        let rel = Options {
            criterion: Criterion::Relative(0.01),
            ..opts
        };
        let mut buf = vec![0u32; 1 << 12];
        let e = mark_slot_field(ev, &rel, 0, Some(&mut buf), &field, &mut Box::new(Scratch::ZERO));
        assert!(matches!(e, Err(Error::InvalidArgument(_))), "{e:?}");
    })
    .unwrap();
}

#[test]
fn field_tessellation_righthanded() {
    check("catmark_righthanded.obj");
}

#[test]
fn field_tessellation_torus() {
    check("catmark_torus.obj");
}
