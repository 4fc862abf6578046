//! The patch table of one mesh (`ccss_evaluator`): build, exact evaluation
//! (`ccss_evaluator_eval*` with `ccss_evaluator_query` /
//! `ccss_evaluator_result`) and the (face, sub-face) slots.

use crate::boundary::{
    block_bytes, check_len, check_ptr, core_mem, guard, overlaps, put, round8, try_block, try_slice,
};
use crate::boundary::{checksum_words, try_handle, try_ref};
use crate::evaluator_options::{core_options, CcssEvaluatorOptions};
use crate::status::{CcssErrorDetail, CcssStatus, Failure, Msg};
use crate::tables::CcssTables;
use crate::topology::CcssTopology;
use ccss_core::eval::{EvaluatorOptions, Query};
use ccss_core::{DVec3, Error, Eval, Evaluator};
use core::ffi::{c_int, c_void};
use core::mem::{align_of, needs_drop, offset_of, size_of};

/// Patch table of one mesh for exact evaluation (opaque; lives at the start
/// of its memory block). Refers to its `ccss_tables`, not to the topology.
pub struct CcssEvaluator {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// Checksum of the core arena `EVAL_HEAD..arena_end` (the patch table),
    /// taken at build ([`ccss_evaluator_verify`]).
    checksum: u64,
    /// End of the core arena (bytes from the handle).
    arena_end: usize,
    /// The tables the evaluator was built from (verified with it).
    tables: *const CcssTables,
    pub(crate) ev: Evaluator<'static>,
}

impl crate::boundary::Handle for CcssEvaluator {
    const MAGIC: u64 = crate::boundary::magic(b"ccssEVL2");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssEvaluator, magic);
    const NAME: &'static str = "ccss_evaluator";
}

const EVAL_HEAD: usize = round8(size_of::<CcssEvaluator>());

/// Writes to `*out` the number of bytes `ccss_evaluator_build` needs for this
/// topology and tables.
///
/// Errors: NULL_POINTER, MISALIGNED, MISSING_TABLE (a valence of the mesh has
/// no table; not with standard tables), INVALID_ARGUMENT; details in
/// `*detail` (may be NULL).
///
/// # Safety
/// `topo`, `tables` are NULL or live handles; `out`, `detail` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_required_bytes(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    let o = EvaluatorOptions::default().into();
    // SAFETY: forwarded caller promises (`o` is a live local).
    unsafe { ccss_evaluator_required_bytes_with_options(topo, tables, &o, out, detail) }
}

/// As `ccss_evaluator_required_bytes`, for an evaluator built with
/// `ccss_evaluator_build_with_options` and these `options` (exact).
///
/// Errors: NULL_POINTER, MISALIGNED, MISSING_TABLE, INVALID_ARGUMENT (also
/// a bad `options` field, named in `detail`); details in `*detail` (may be
/// NULL).
///
/// # Safety
/// `topo`, `tables` are NULL or live handles; `options` is NULL or
/// readable; `out`, `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_required_bytes_with_options(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    options: *const CcssEvaluatorOptions,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let (t, tb) = unsafe { (try_handle(topo, "topo")?, try_handle(tables, "tables")?) };
        // SAFETY: forwarded caller promise.
        let opts = core_options(unsafe { try_ref(options, "options")? })?;
        check_ptr(out as *const usize, "out")?;
        let total = evaluator_bytes(t, tb, opts)?;
        // SAFETY: checked above.
        unsafe { put(out, "out", total) }
    })
}

/// Builds the evaluator (patch table) of `topo` into `mem` (`mem_len` bytes,
/// 8-byte aligned, at least `ccss_evaluator_required_bytes`) and writes the
/// handle (which equals `mem`) to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// bytes), MISSING_TABLE, INVALID_ARGUMENT; details in `*detail` (may be
/// NULL). On failure `*out` is not written and `mem`'s contents are
/// unspecified.
///
/// Ownership: the caller owns `mem`. The evaluator refers to the tables, which
/// must stay alive (allocated, unmoved, unmodified) as long as it is used; it
/// does NOT refer to the topology, whose block may be freed right after this
/// call. Nothing to destroy: free `mem` when done.
///
/// # Safety
/// `topo`, `tables` are NULL or live handles; `mem` is NULL or points to
/// `mem_len` writable bytes not otherwise in use (not the topology's or tables'
/// blocks); `out`, `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_build(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    let o = EvaluatorOptions::default().into();
    // SAFETY: forwarded caller promises (`o` is a live local).
    unsafe { ccss_evaluator_build_with_options(topo, tables, &o, mem, mem_len, out, detail) }
}

/// As `ccss_evaluator_build`, keeping per extraordinary patch what
/// `options` says (`ccss_evaluator_options_default`: what
/// `ccss_evaluator_build` keeps; `ccss_evaluator_options_compact`: the
/// least memory). Every evaluation, depth and tessellation is the same bit
/// for bit whatever the options; only memory and speed differ. `mem_len`:
/// at least `ccss_evaluator_required_bytes_with_options` for the same
/// options.
///
/// Errors: as `ccss_evaluator_build`, and INVALID_ARGUMENT for a bad
/// `options` field (named in `detail`). On failure `*out` is not written.
///
/// # Safety
/// As `ccss_evaluator_build`; `options` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_build_with_options(
    topo: *const CcssTopology,
    tables: *const CcssTables,
    options: *const CcssEvaluatorOptions,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises; the tables outlive the evaluator
        // by the C-side contract, hence 'static.
        let (t, tb): (&CcssTopology, &'static CcssTables) =
            unsafe { (try_handle(topo, "topo")?, try_handle(tables, "tables")?) };
        // SAFETY: forwarded caller promise.
        let opts = core_options(unsafe { try_ref(options, "options")? })?;
        check_ptr(out as *const *const CcssEvaluator, "out")?;
        let total = evaluator_bytes(t, tb, opts)?;
        let base = try_block(mem, mem_len, total)?;
        // SAFETY: `base` is 8-aligned with `mem_len >= total` writable bytes: the
        // handle at 0, the core arena after it; 'static by the C contract.
        unsafe {
            let arena = core_mem(base, EVAL_HEAD, mem_len)?;
            let ev = Evaluator::build_with(&t.topo, &tb.set, opts, arena)?;
            let checksum = checksum_words(base, EVAL_HEAD, total);
            let h = base as *mut CcssEvaluator;
            h.write(CcssEvaluator {
                magic: <CcssEvaluator as crate::boundary::Handle>::MAGIC,
                checksum,
                arena_end: total,
                tables: tb,
                ev,
            });
            *out = h;
        }
        Ok(())
    })
}

/// Checks the integrity of the evaluator's block and of its tables: the
/// patch table in the block (every word after the handle header) against
/// the checksum taken by `ccss_evaluator_build`, then the tables as
/// `ccss_tables_verify` does. Any changed word (a flipped bit or byte, a
/// stray write into the block) is found; several changed words go unnoticed
/// with probability about 2^-64. Cost: one pass over the block and the
/// tables (about 0.1 ms per 100,000 words); not done by the other calls,
/// which check only the handle's magic word.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_HANDLE (the header itself was
/// overwritten), CORRUPTED (the block or its tables changed after build).
///
/// # Safety
/// `ev` is NULL or a live handle (its tables alive); `detail` is NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_verify(
    ev: *const CcssEvaluator,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: the handle is live, so `ev .. ev + arena_end` is its block.
        let now = unsafe { checksum_words(ev as *const u8, EVAL_HEAD, e.arena_end) };
        if now != e.checksum {
            return Err(Failure::new(
                CcssStatus::ERR_CORRUPTED,
                Msg::Corrupted("ccss_evaluator"),
            ));
        }
        // SAFETY: the tables outlive the evaluator (build contract).
        crate::tables::verify_tables(unsafe { &*e.tables })
    })
}

/// Writes the number of base faces to `*out`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_face_count(
    ev: *const CcssEvaluator,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(ev, "ev")?.ev.num_faces()) }
    })
}

/// Writes the number of sub-faces of base face `face` to `*out`: 1 for a
/// quad, N for an N-gon (sub-face k is the quad at corner k after one
/// Catmull-Clark step, with its own (u, v)).
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_subface_count(
    ev: *const CcssEvaluator,
    face: u32,
    out: *mut u32,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        check_ptr(out as *const u32, "out")?;
        if face as usize >= e.ev.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", e.ev.num_subfaces(face as usize) as u32) }
    })
}

/// Writes the number of regular (bicubic) and extraordinary patches of the
/// patch table to `*out_regular` and `*out_extraordinary`.
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `out_regular`, `out_extraordinary` are NULL or
/// writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_patch_counts(
    ev: *const CcssEvaluator,
    out_regular: *mut usize,
    out_extraordinary: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        check_ptr(out_regular as *const usize, "out_regular")?;
        check_ptr(out_extraordinary as *const usize, "out_extraordinary")?;
        let (r, x) = e.ev.patch_counts();
        // SAFETY: checked above.
        unsafe {
            out_regular.write(r);
            out_extraordinary.write(x);
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------
// Evaluation.

/// One evaluation result. Derivatives are with respect to the (sub-)face's
/// own (u, v); `normal` is `normalize(du x dv)` (zero where that vanishes; at
/// an extraordinary vertex the limit normal). Second derivatives are zero
/// unless requested.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssEvaluatorResult {
    /// Position.
    pub p: [f64; 3],
    /// dS/du.
    pub du: [f64; 3],
    /// dS/dv.
    pub dv: [f64; 3],
    /// d2S/du2.
    pub duu: [f64; 3],
    /// d2S/dudv.
    pub duv: [f64; 3],
    /// d2S/dv2.
    pub dvv: [f64; 3],
    /// Unit normal.
    pub normal: [f64; 3],
}

impl From<Eval> for CcssEvaluatorResult {
    fn from(e: Eval) -> Self {
        let a = |d: DVec3| [d.x, d.y, d.z];
        CcssEvaluatorResult {
            p: a(e.p),
            du: a(e.du),
            dv: a(e.dv),
            duu: a(e.duu),
            duv: a(e.duv),
            dvv: a(e.dvv),
            normal: a(e.normal),
        }
    }
}

/// One query of a batch: base face, sub-face (0 for quads), parameters in
/// `[0, 1]`. Same layout as ccss-core's `evaluator::Query`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssEvaluatorQuery {
    /// Base face index.
    pub face: u32,
    /// Sub-face index (0 for quads, 0..N-1 for N-gons).
    pub sub: u32,
    /// Parameter u in [0, 1].
    pub u: f64,
    /// Parameter v in [0, 1].
    pub v: f64,
}

// Layout and drop assumptions, checked at compile time.
const _: () = {
    assert!(size_of::<CcssEvaluatorQuery>() == size_of::<Query>());
    assert!(align_of::<CcssEvaluatorQuery>() == align_of::<Query>());
    assert!(offset_of!(CcssEvaluatorQuery, face) == offset_of!(Query, face));
    assert!(offset_of!(CcssEvaluatorQuery, sub) == offset_of!(Query, sub));
    assert!(offset_of!(CcssEvaluatorQuery, u) == offset_of!(Query, u));
    assert!(offset_of!(CcssEvaluatorQuery, v) == offset_of!(Query, v));
    assert!(align_of::<CcssEvaluator>() <= 8);
    // `CcssEvaluatorResult` is `Eval` field for field (seven `[f64; 3]`
    // at the same offsets; `DVec3` is `#[repr(C)] { x, y, z }` of f64):
    // the evaluations write straight into the caller's result
    // ([`result_as_eval`]).
    assert!(size_of::<CcssEvaluatorResult>() == size_of::<Eval>());
    assert!(align_of::<CcssEvaluatorResult>() == align_of::<Eval>());
    assert!(size_of::<DVec3>() == 24 && align_of::<DVec3>() == 8);
    assert!(offset_of!(DVec3, x) == 0 && offset_of!(DVec3, y) == 8 && offset_of!(DVec3, z) == 16);
    assert!(offset_of!(CcssEvaluatorResult, p) == offset_of!(Eval, p));
    assert!(offset_of!(CcssEvaluatorResult, du) == offset_of!(Eval, du));
    assert!(offset_of!(CcssEvaluatorResult, dv) == offset_of!(Eval, dv));
    assert!(offset_of!(CcssEvaluatorResult, duu) == offset_of!(Eval, duu));
    assert!(offset_of!(CcssEvaluatorResult, duv) == offset_of!(Eval, duv));
    assert!(offset_of!(CcssEvaluatorResult, dvv) == offset_of!(Eval, dvv));
    assert!(offset_of!(CcssEvaluatorResult, normal) == offset_of!(Eval, normal));
    assert!(!needs_drop::<Eval>());
    // Blocks are simply freed by C: nothing may need dropping.
    assert!(!needs_drop::<CcssEvaluator>());
};

/// What the point and batch exports of both evaluator families need: the
/// query check and the two evaluations (`ccss_evaluator`,
/// `ccss_feature_evaluator`).
pub(crate) trait PointEval {
    /// Validates a query without evaluating it.
    fn check(&self, q: &Query) -> Result<(), Error>;
    /// Position, first derivatives and normal (second: also second
    /// derivatives).
    fn point(&self, face: u32, sub: u32, u: f64, v: f64, second: bool) -> Result<Eval, Error>;
    /// [`PointEval::point`] of a query that passed [`PointEval::check`]:
    /// what the batch calls, so that an evaluator whose evaluation
    /// re-checks nothing else skips the second check.
    fn point_checked(&self, q: &Query, second: bool) -> Result<Eval, Error> {
        self.point(q.face, q.sub, q.u, q.v, second)
    }
    /// [`PointEval::point`] into `out`, written only on success (an
    /// evaluator may write its result in place, without a move); without
    /// `what.normal` the normal is zero.
    #[inline(always)]
    fn point_into(
        &self,
        (face, sub, u, v): (u32, u32, f64, f64),
        what: Outputs,
        out: &mut Eval,
    ) -> Result<(), Error> {
        *out = what.trim(self.point(face, sub, u, v, what.second)?);
        Ok(())
    }
    /// [`PointEval::point_checked`] into `out`, written only on success
    /// (without `what.normal` the normal is zero).
    #[inline(always)]
    fn point_checked_into(&self, q: &Query, what: Outputs, out: &mut Eval) -> Result<(), Error> {
        *out = what.trim(self.point_checked(q, what.second)?);
        Ok(())
    }
}

/// What a point or batch export writes besides the position and first
/// derivatives.
#[derive(Clone, Copy)]
pub(crate) struct Outputs {
    /// Second derivatives (else zero).
    pub second: bool,
    /// The unit normal (else zero).
    pub normal: bool,
}

impl Outputs {
    /// `ccss_evaluator_eval` (`second` false) / `_eval_second`: with the
    /// normal.
    pub fn with_normal(second: bool) -> Outputs {
        Outputs {
            second,
            normal: true,
        }
    }

    /// `ccss_evaluator_eval_derivs` (`second` false) /
    /// `_eval_second_derivs`: without the normal.
    pub fn derivs(second: bool) -> Outputs {
        Outputs {
            second,
            normal: false,
        }
    }

    /// `e` with its normal cleared unless it is wanted.
    #[inline(always)]
    fn trim(self, mut e: Eval) -> Eval {
        if !self.normal {
            e.normal = DVec3::ZERO;
        }
        e
    }
}

impl PointEval for Evaluator<'_> {
    fn check(&self, q: &Query) -> Result<(), Error> {
        Evaluator::check(self, q)
    }
    fn point(&self, face: u32, sub: u32, u: f64, v: f64, second: bool) -> Result<Eval, Error> {
        if second {
            self.eval_second(face, sub, u, v)
        } else {
            self.eval(face, sub, u, v)
        }
    }
    #[inline(always)]
    fn point_checked(&self, q: &Query, second: bool) -> Result<Eval, Error> {
        // Every failure of `eval` is a failed range check.
        Ok(self.eval_checked(q, second))
    }
    #[inline(always)]
    fn point_into(
        &self,
        (face, sub, u, v): (u32, u32, f64, f64),
        what: Outputs,
        out: &mut Eval,
    ) -> Result<(), Error> {
        match (what.second, what.normal) {
            (true, true) => self.eval_to::<true, true>(face, sub, u, v, out),
            (false, true) => self.eval_to::<false, true>(face, sub, u, v, out),
            (true, false) => self.eval_to::<true, false>(face, sub, u, v, out),
            (false, false) => self.eval_to::<false, false>(face, sub, u, v, out),
        }
    }
    #[inline(always)]
    fn point_checked_into(&self, q: &Query, what: Outputs, out: &mut Eval) -> Result<(), Error> {
        match (what.second, what.normal) {
            (true, true) => self.eval_checked_to::<true, true>(q, out),
            (false, true) => self.eval_checked_to::<false, true>(q, out),
            (true, false) => self.eval_checked_to::<true, false>(q, out),
            (false, false) => self.eval_checked_to::<false, false>(q, out),
        }
        Ok(())
    }
}

/// The caller's result as the core's [`Eval`] (the same layout, asserted
/// at compile time above).
///
/// # Safety
/// `out` is non-NULL, aligned and writable, not otherwise in use for `'a`.
#[inline(always)]
unsafe fn result_as_eval<'a>(out: *mut CcssEvaluatorResult) -> &'a mut Eval {
    // SAFETY: caller promise; `Eval` has the layout of
    // `CcssEvaluatorResult` (f64 fields only: every bit pattern is valid).
    unsafe { &mut *out.cast::<Eval>() }
}

/// One evaluation into `*out` (checked non-NULL and aligned first; written
/// only on success).
///
/// # Safety
/// `out` is NULL or writable.
pub(crate) unsafe fn eval_point<E: PointEval>(
    ev: &E,
    (face, sub, u, v): (u32, u32, f64, f64),
    what: Outputs,
    out: *mut CcssEvaluatorResult,
) -> Result<(), Failure> {
    check_ptr(out as *const CcssEvaluatorResult, "out")?;
    // SAFETY: checked non-NULL and aligned above; writable by the caller's
    // promise. `point_into` writes only on success.
    ev.point_into((face, sub, u, v), what, unsafe { result_as_eval(out) })
        .map_err(Failure::from)
}

/// A batch into `out`: `queries` (`count`) and `out` (`out_len`) checked,
/// every query checked before anything is written (the first bad one's
/// index in `detail.query_index`), then evaluated in order.
///
/// # Safety
/// `queries` is NULL or points to `count` readable queries; `out` is NULL
/// or points to `out_len` writable results.
pub(crate) unsafe fn eval_batch_into<E: PointEval>(
    ev: &E,
    queries: *const CcssEvaluatorQuery,
    count: usize,
    what: Outputs,
    out: *mut CcssEvaluatorResult,
    out_len: usize,
) -> Result<(), Failure> {
    // SAFETY: forwarded caller promise.
    let qs = unsafe { try_slice(queries, count, "queries") }?;
    if out.is_null() && out_len != 0 {
        return Err(Failure::null("out"));
    }
    if out_len < count {
        return Err(Failure::too_small(count));
    }
    if count == 0 {
        return Ok(());
    }
    check_ptr(out as *const CcssEvaluatorResult, "out")?;
    check_len::<CcssEvaluatorResult>(count, "array length too large")?;
    let res_bytes = count * size_of::<CcssEvaluatorResult>();
    if overlaps(
        qs.as_ptr() as *const u8,
        count * size_of::<CcssEvaluatorQuery>(),
        out as *const u8,
        res_bytes,
    ) {
        return Err(Failure::invalid("out overlaps queries"));
    }
    let at = |i: usize| {
        move |err: Error| {
            let mut f = Failure::from(err);
            f.query_index = Some(i as u64);
            f
        }
    };
    let query = |q: &CcssEvaluatorQuery| Query {
        face: q.face,
        sub: q.sub,
        u: q.u,
        v: q.v,
    };
    for (i, q) in qs.iter().enumerate() {
        ev.check(&query(q)).map_err(at(i))?;
    }
    // Checked above: evaluated without a second check.
    for (i, q) in qs.iter().enumerate() {
        // SAFETY: `out` is non-NULL, aligned, with `out_len >= count`
        // writable elements not overlapping `queries`.
        let o = unsafe { result_as_eval(out.add(i)) };
        ev.point_checked_into(&query(q), what, o).map_err(at(i))?;
    }
    Ok(())
}

/// # Safety
/// `ev` is NULL or a live handle; `out`, `detail` are NULL or writable.
#[allow(clippy::too_many_arguments)]
unsafe fn eval_one(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    what: Outputs,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promise.
        unsafe { eval_point(&e.ev, (face, sub, u, v), what, out) }
    })
}

/// The batch exports (`ccss_evaluator_eval_batch`, `_eval_batch_derivs`).
///
/// # Safety
/// `ev` is NULL or a live handle; `queries` is NULL or points to `count`
/// readable queries; `out` is NULL or points to `out_len` writable results;
/// `detail` is NULL or writable.
unsafe fn eval_many(
    ev: *const CcssEvaluator,
    queries: *const CcssEvaluatorQuery,
    count: usize,
    what: Outputs,
    out: *mut CcssEvaluatorResult,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { eval_batch_into(&e.ev, queries, count, what, out, out_len) }
    })
}

/// Evaluates position, first derivatives and normal at (u, v) of sub-face
/// `sub` (0 for quads) of base face `face` into `*out` (second derivatives
/// are set to zero). Quad parameterisation: (0,0) at the face's vertex 0,
/// (1,0) at vertex 1, (1,1) at vertex 2, (0,1) at vertex 3.
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE,
/// SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE (u or v NaN or outside
/// [0, 1]). `*out` is written only on success.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe {
        eval_one(
            ev,
            face,
            sub,
            u,
            v,
            Outputs::with_normal(false),
            out,
            detail,
        )
    }
}

/// As `ccss_evaluator_eval`, plus second derivatives (`duu`, `duv`, `dvv`).
///
/// Errors: as `ccss_evaluator_eval`.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval_second(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(ev, face, sub, u, v, Outputs::with_normal(true), out, detail) }
}

/// As `ccss_evaluator_eval` without the unit normal: position and first
/// derivatives (what OpenSubdiv's patch evaluation computes); `normal`
/// and the second derivatives are set to zero. The same position and
/// derivatives bit for bit, and cheaper per call: the normal's square root
/// and division end every `ccss_evaluator_eval` with a chain of about 50
/// cycles that a host which does not need the normal should not wait for
/// (BENCHMARKS.md).
///
/// Errors: as `ccss_evaluator_eval`.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval_derivs(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(ev, face, sub, u, v, Outputs::derivs(false), out, detail) }
}

/// As `ccss_evaluator_eval_second` without the unit normal (`normal` set
/// to zero): position, first and second derivatives, bit for bit those of
/// `ccss_evaluator_eval_second`.
///
/// Errors: as `ccss_evaluator_eval`.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval_second_derivs(
    ev: *const CcssEvaluator,
    face: u32,
    sub: u32,
    u: f64,
    v: f64,
    out: *mut CcssEvaluatorResult,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promises.
    unsafe { eval_one(ev, face, sub, u, v, Outputs::derivs(true), out, detail) }
}

/// Evaluates `count` queries into `out[0..count]` (`out_len` elements
/// available), with second derivatives when `second` is non-zero.
///
/// All queries are validated before anything is written: on the first bad
/// query the function fails with its status and `detail.query_index` (plus
/// `face` / `value` = sub-face) and `out` is untouched.
///
/// Errors: NULL_POINTER (`ev`; `queries` or `out` with a non-zero count),
/// MISALIGNED, BUFFER_TOO_SMALL (`out_len < count`; `detail.required` =
/// `count` elements), INVALID_ARGUMENT (`out` overlaps `queries`),
/// FACE_OUT_OF_RANGE, SUBFACE_OUT_OF_RANGE, PARAMETER_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `queries` is NULL or points to `count`
/// readable queries; `out` is NULL or points to `out_len` writable results;
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval_batch(
    ev: *const CcssEvaluator,
    queries: *const CcssEvaluatorQuery,
    count: usize,
    second: c_int,
    out: *mut CcssEvaluatorResult,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    let what = Outputs::with_normal(second != 0);
    // SAFETY: forwarded caller promises.
    unsafe { eval_many(ev, queries, count, what, out, out_len, detail) }
}

/// As `ccss_evaluator_eval_batch` without the unit normals (`normal` set
/// to zero in every result; see `ccss_evaluator_eval_derivs`): the same
/// positions and derivatives bit for bit.
///
/// Errors: as `ccss_evaluator_eval_batch`.
///
/// # Safety
/// `ev` is NULL or a live handle; `queries` is NULL or points to `count`
/// readable queries; `out` is NULL or points to `out_len` writable results;
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_eval_batch_derivs(
    ev: *const CcssEvaluator,
    queries: *const CcssEvaluatorQuery,
    count: usize,
    second: c_int,
    out: *mut CcssEvaluatorResult,
    out_len: usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    let what = Outputs::derivs(second != 0);
    // SAFETY: forwarded caller promises.
    unsafe { eval_many(ev, queries, count, what, out, out_len, detail) }
}

/// Bytes of an evaluator block for `t` and `tb` (size query and build).
fn evaluator_bytes(
    t: &CcssTopology,
    tb: &CcssTables,
    opts: EvaluatorOptions,
) -> Result<usize, Failure> {
    block_bytes(
        Evaluator::required_bytes_with(&t.topo, &tb.set, opts)?,
        EVAL_HEAD,
        "mesh too large",
    )
}

/// Writes to `*out` the number of (face, sub-face) slots of the evaluator:
/// one per quad, N per N-gon. This is the number of depths `ccss_depth_compute`
/// writes (the size query of its output array).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_slot_count(
    ev: *const CcssEvaluator,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        unsafe { put(out, "out", try_handle(ev, "ev")?.ev.num_slots()) }
    })
}

/// Writes to `*out` the first slot of base face `face`: the depths of face
/// `face` are at `slot_start .. slot_start + n` of the `ccss_depth_compute` array,
/// `n` its sub-face count (`ccss_evaluator_subface_count`; slots are faces in
/// order, the sub-faces of an N-gon consecutively).
///
/// Errors: NULL_POINTER, MISALIGNED, FACE_OUT_OF_RANGE.
///
/// # Safety
/// `ev` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_evaluator_slot_start(
    ev: *const CcssEvaluator,
    face: u32,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_handle(ev, "ev") }?;
        check_ptr(out as *const usize, "out")?;
        if face as usize >= e.ev.num_faces() {
            return Err(Error::FaceOutOfRange { face }.into());
        }
        // SAFETY: checked above.
        unsafe { put(out, "out", e.ev.slot_start(face as usize)) }
    })
}
