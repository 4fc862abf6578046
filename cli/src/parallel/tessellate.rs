//! Adaptive tessellation on all cores: every slot is marked in parallel
//! (rayon, one `Scratch` per worker), then counted and emitted into `Vec`s
//! on one core; and the uniform level that meets the same criterion, also
//! checked slot by slot in parallel.

use crate::mem::words;
use crate::progress::Progress;
use ccss_core::tessellate::{
    mark_slot, mark_slot_field, uniform_passes, Counts, Criterion, Options, Output, Scratch,
    SlotMark, Stats, Tessellation, ToleranceField,
};
use ccss_core::{Evaluator, Topology};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Template of the (delayed) progress bar of the phases below.
pub const PROGRESS: &str = "{msg:>12} [{bar:40}] {pos}/{len}";

/// A tessellation in `Vec`s.
pub struct Tess {
    pub counts: Counts,
    pub stats: Stats,
    pub positions: Vec<f64>,
    pub normals: Vec<f64>,
    pub sizes: Vec<u32>,
    pub indices: Vec<u32>,
    pub triangles: Vec<u32>,
}

/// Marks every slot on all cores (rayon; one `Scratch` per worker).
pub fn mark_parallel(
    ev: &Evaluator,
    opts: &Options,
    progress: &Progress,
) -> Result<(Vec<SlotMark>, Vec<u32>), ccss_core::Error> {
    mark_with(ev, progress, |s, buf, scratch| {
        mark_slot(ev, opts, s, Some(buf), scratch)
    })
}

/// As [`mark_parallel`], with a tolerance field ([`mark_slot_field`]).
pub fn mark_parallel_field<F: ToleranceField + Sync>(
    ev: &Evaluator,
    opts: &Options,
    field: &F,
    progress: &Progress,
) -> Result<(Vec<SlotMark>, Vec<u32>), ccss_core::Error> {
    mark_with(ev, progress, |s, buf, scratch| {
        mark_slot_field(ev, opts, s, Some(buf), field, scratch)
    })
}

/// Marks every slot with `mark_one(slot, nodes, scratch)` on all cores.
fn mark_with<M>(
    ev: &Evaluator,
    progress: &Progress,
    mark_one: M,
) -> Result<(Vec<SlotMark>, Vec<u32>), ccss_core::Error>
where
    M: Fn(usize, &mut [u32], &mut Scratch) -> Result<SlotMark, ccss_core::Error> + Sync,
{
    progress.phase("marking", ev.num_slots());
    let per: Vec<Result<(SlotMark, Vec<u32>), ccss_core::Error>> = (0..ev.num_slots())
        .into_par_iter()
        .map_init(
            || (Box::new(Scratch::ZERO), vec![0u32; 1 << 12]),
            |(scratch, buf), s| {
                let r = loop {
                    match mark_one(s, buf, scratch) {
                        Ok(m) => break Ok((m, buf[..m.nodes as usize].to_vec())),
                        Err(ccss_core::Error::BufferTooSmall { required }) => {
                            buf.resize(required.max(2 * buf.len()), 0)
                        }
                        Err(e) => break Err(e),
                    }
                };
                progress.inc();
                r
            },
        )
        .collect();
    let mut marks = Vec::with_capacity(per.len());
    let mut trees = Vec::new();
    for r in per {
        let (m, t) = r?;
        marks.push(m);
        trees.extend_from_slice(&t);
    }
    Ok((marks, trees))
}

/// Emits a built tessellation into `Vec`s.
pub fn emit_vecs(t: &mut Tessellation, triangles: bool) -> Result<Tess, ccss_core::Error> {
    let c = t.counts();
    let mut r = Tess {
        counts: c,
        stats: t.stats(),
        positions: vec![0.0; 3 * c.vertices],
        normals: vec![0.0; 3 * c.vertices],
        sizes: vec![0; c.polygons],
        indices: vec![0; c.polygon_indices],
        triangles: vec![0; if triangles { 3 * c.triangles } else { 0 }],
    };
    t.emit(Output {
        positions: &mut r.positions,
        normals: Some(&mut r.normals),
        params: None,
        polygon_sizes: &mut r.sizes,
        polygon_indices: &mut r.indices,
        triangles: if triangles {
            Some(&mut r.triangles)
        } else {
            None
        },
        cells: None,
    })?;
    Ok(r)
}

/// Marking on all cores, then counting and emission on one.
pub fn tessellate(
    topo: &Topology,
    ev: &Evaluator,
    opts: Options,
    triangles: bool,
    progress: &Progress,
) -> Result<Tess, ccss_core::Error> {
    let (marks, trees) = mark_parallel(ev, &opts, progress)?;
    let need = Tessellation::required_bytes_marked(topo, &marks)?;
    let mut mem = words(need);
    progress.phase("emitting", 1);
    let mut t = Tessellation::build_marked(topo, ev, opts, &marks, &trees, &mut mem)?;
    let r = emit_vecs(&mut t, triangles);
    progress.inc();
    r
}

/// The smallest uniform level from `from` on whose cells all pass
/// `crit` (all cores), or `None` up to level 30.
pub fn uniform_depth(
    ev: &Evaluator,
    crit: Criterion,
    from: u32,
    progress: &Progress,
) -> Result<Option<u32>, ccss_core::Error> {
    for l in from..=ccss_core::tessellate::MAX_LEVEL {
        progress.phase("uniform check", ev.num_slots());
        let fail = AtomicBool::new(false);
        let r: Result<(), ccss_core::Error> = (0..ev.num_slots())
            .into_par_iter()
            .map_init(
                || Box::new(Scratch::ZERO),
                |scratch, s| {
                    if fail.load(Ordering::Relaxed) {
                        return Ok(());
                    }
                    let ok = uniform_passes(ev, crit, s, l, scratch)?;
                    if !ok {
                        fail.store(true, Ordering::Relaxed);
                    }
                    progress.inc();
                    Ok(())
                },
            )
            .collect();
        r?;
        if !fail.load(Ordering::Relaxed) {
            return Ok(Some(l));
        }
    }
    Ok(None)
}
