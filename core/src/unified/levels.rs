//! Several levels of the unified scheme in one call, each with its own
//! parameters (MS §4: "a few parameters per level" replace progressive-mesh
//! updates), into one caller buffer with an exact size query.
//!
//! Memory: every level's refined mesh is kept (they are the levels of
//! detail), followed by one topology region (the largest intermediate level)
//! and one working region (the largest level), both reused level to level.

use super::layout::MeshStats;
use super::params::UnifiedParams;
use super::surface::{bytes_of, out_requests, step, work_requests};
use crate::error::Error;
use crate::mem::words_for;
use crate::mesh::topology::{MeshInput, Topology};

/// Largest number of levels per call (each level multiplies the face count
/// by at least 4, so more would overflow the supported mesh size anyway).
pub const MAX_LEVELS: usize = 16;

/// The refined meshes of [`refine_unified_levels`], coarsest first.
#[derive(Clone, Debug, Default)]
pub struct UnifiedLevels<'a> {
    meshes: heapless::Vec<MeshInput<'a>, MAX_LEVELS>,
}

impl<'a> UnifiedLevels<'a> {
    /// All levels, level 1 (one step from the input) first.
    pub fn meshes(&self) -> &[MeshInput<'a>] {
        &self.meshes
    }
    /// Number of levels.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }
    /// Whether no level was requested.
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }
    /// The last (finest) level.
    pub fn finest(&self) -> Option<MeshInput<'a>> {
        self.meshes.last().copied()
    }
}

/// Byte sizes of the parts of a multi-level run.
struct Plan {
    stats: heapless::Vec<MeshStats, { MAX_LEVELS + 1 }>,
    outs: heapless::Vec<usize, MAX_LEVELS>,
    out_total: usize,
    topo: usize,
    work: usize,
}

fn too_large() -> Error {
    Error::InvalidArgument("unified: refined mesh too large for memory")
}

impl Plan {
    fn new(t: &Topology, levels: &[UnifiedParams]) -> Result<Plan, Error> {
        if levels.len() > MAX_LEVELS {
            return Err(Error::InvalidArgument(
                "unified: more than MAX_LEVELS levels",
            ));
        }
        let mut stats = heapless::Vec::new();
        let mut s = MeshStats::of(t);
        stats.push(s).map_err(|_| too_large())?;
        let mut plan = Plan {
            stats: heapless::Vec::new(),
            outs: heapless::Vec::new(),
            out_total: 0,
            topo: 0,
            work: 0,
        };
        for (l, p) in levels.iter().enumerate() {
            p.validate()?;
            let fine = s.refined(p)?;
            let out = bytes_of(|r| out_requests(r, &s, &fine))?;
            let work = bytes_of(|r| work_requests(r, &s, &fine, p))?;
            if l > 0 {
                let c = s.counts();
                // Topology's carving: a handful of u32 arrays; bound it in u64
                // before asking for the exact (usize) layout.
                let bound =
                    4 * (c.faces as u64 + 3 * c.corners as u64 + 2 * c.vertices as u64) + 64;
                if bound > isize::MAX as u64 {
                    return Err(too_large());
                }
                let topo = Topology::layout(c.vertices, c.faces, c.corners).bytes();
                plan.topo = plan.topo.max(topo);
            }
            plan.outs.push(out).map_err(|_| too_large())?;
            plan.out_total = plan.out_total.checked_add(out).ok_or_else(too_large)?;
            plan.work = plan.work.max(work);
            s = fine;
            stats.push(s).map_err(|_| too_large())?;
        }
        plan.stats = stats;
        Ok(plan)
    }

    fn total(&self) -> Result<usize, Error> {
        self.out_total
            .checked_add(self.topo)
            .and_then(|x| x.checked_add(self.work))
            .filter(|&x| x <= isize::MAX as usize)
            .ok_or_else(too_large)
    }
}

/// Bytes [`refine_unified_levels`] needs: all refined levels plus one
/// topology and one working region.
///
/// Errors: more than [`MAX_LEVELS`] levels, invalid parameters (of any
/// level) or a refined mesh too large ([`Error::InvalidArgument`]).
pub fn unified_levels_bytes(t: &Topology, levels: &[UnifiedParams]) -> Result<usize, Error> {
    Plan::new(t, levels)?.total()
}

/// Refines `t` once per entry of `levels` (level `l` with `levels[l]`) into
/// `mem` (at least [`unified_levels_bytes`] bytes, in words) and returns
/// every level. Each intermediate level's topology is rebuilt (and so
/// validated) with [`Topology::build`].
///
/// Errors: those of [`unified_levels_bytes`], [`Error::BufferTooSmall`]
/// (bytes), and any [`Topology::build`] error of an
/// intermediate level (e.g. a valence above [`crate::config::MAX_VALENCE`] when
/// split triangles meet a small build-time maximum).
pub fn refine_unified_levels<'a>(
    t: &Topology,
    levels: &[UnifiedParams],
    mem: &'a mut [u64],
) -> Result<UnifiedLevels<'a>, Error> {
    let plan = Plan::new(t, levels)?;
    let required = plan.total()?;
    if crate::mem::bytes_of(mem.len()) < required {
        return Err(Error::BufferTooSmall { required });
    }
    if levels.is_empty() {
        return Ok(UnifiedLevels::default());
    }
    // Every piece is a whole number of words (the arena rounds to 8 bytes).
    let (mut outs, tail) = mem.split_at_mut(words_for(plan.out_total));
    let (topo_mem, tail) = tail.split_at_mut(words_for(plan.topo));
    let work_mem = &mut tail[..words_for(plan.work)];
    let mut result = UnifiedLevels::default();
    for (l, p) in levels.iter().enumerate() {
        let (out, rest) = core::mem::take(&mut outs).split_at_mut(words_for(plan.outs[l]));
        outs = rest;
        let (base, fine) = (&plan.stats[l], &plan.stats[l + 1]);
        let refined = if l == 0 {
            step(t, p, base, fine, out, &mut *work_mem)?
        } else {
            let prev = result.meshes[l - 1];
            let topo = Topology::build(prev, &mut *topo_mem)?;
            step(&topo, p, base, fine, out, &mut *work_mem)?
        };
        result.meshes.push(refined.mesh).map_err(|_| too_large())?;
    }
    Ok(result)
}
