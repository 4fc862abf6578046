//! Eigen tables (`ccss_tables`) of a vertex rule: standard Catmull-Clark or
//! general weights per valence (`ccss_weight_entry`), and the facts of one
//! valence (`ccss_tables_valence`).

use crate::boundary::{check_ptr, guard, put, round8, try_block, try_ref, try_slice};
use crate::boundary::{try_handle, Checksum};
use crate::status::{CcssErrorDetail, CcssStatus, Failure, Msg};
use ccss_core::config::MAX_VALENCE;
use ccss_core::eigen::bake::bake_words;
use ccss_core::{BuildScratch, Error, TableSet, Weights};
use core::ffi::{c_int, c_void};
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// Eigen tables of one vertex rule (standard Catmull-Clark, or general
/// weights per valence, see `ccss_tables_build`) for every valence
/// `3..=ccss_max_valence` (opaque; lives at the start of its memory block).
/// Evaluators built from them refine and evaluate with that rule.
pub struct CcssTables {
    /// The one field (at offset 0, checked below): C layout inside, so the
    /// magic word is the block's first 8 bytes.
    pub(crate) inner: TablesInner,
}

/// The handle's contents in C layout (magic first).
#[repr(C)]
#[doc(hidden)]
pub struct TablesInner {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// Checksum of the tables' words (`bake_words`), taken at build
    /// ([`ccss_tables_verify`]).
    checksum: u64,
    pub(crate) set: TableSet,
}

impl core::ops::Deref for CcssTables {
    type Target = TablesInner;
    fn deref(&self) -> &TablesInner {
        &self.inner
    }
}

static ZERO_TABLES: TableSet = TableSet::ZERO;
static ZERO_SCRATCH: BuildScratch = BuildScratch::ZERO;

impl crate::boundary::Handle for CcssTables {
    const MAGIC: u64 = crate::boundary::magic(b"ccssTAB2");
    const MAGIC_OFFSET: usize =
        core::mem::offset_of!(CcssTables, inner) + core::mem::offset_of!(TablesInner, magic);
    const NAME: &'static str = "ccss_tables";
}

const _: () = assert!(<CcssTables as crate::boundary::Handle>::MAGIC_OFFSET == 0);

const TABLES_HEAD: usize = round8(size_of::<CcssTables>());
const TABLES_BYTES: usize = TABLES_HEAD + round8(size_of::<BuildScratch>());

// Layout and drop assumptions, checked at compile time: both parts of the
// block need at most its 8-byte alignment, and blocks are simply freed by C.
const _: () = {
    assert!(align_of::<CcssTables>() <= 8 && align_of::<BuildScratch>() <= 8);
    assert!(!needs_drop::<CcssTables>() && !needs_drop::<BuildScratch>());
};

/// Writes to `*out` the number of bytes `ccss_tables_build_standard` and
/// `ccss_tables_build` need (the tables plus the build scratch; about 900 KiB
/// for the default maximum valence 16).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or points to a writable `size_t`.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_required_bytes(
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(detail, || unsafe { put(out, "out", TABLES_BYTES) })
}

/// Builds the standard-rule eigen tables of all valences into `mem` (`mem_len`
/// bytes, 8-byte aligned, at least `ccss_tables_required_bytes`) and writes
/// the handle (which equals `mem`) to `*out`. Takes a few milliseconds.
///
/// Errors: NULL_POINTER (`out`, or `mem` with `mem_len > 0`), BUFFER_TOO_SMALL,
/// MISALIGNED, TABLE_BUILD_FAILED. On failure `*out` is not written and the
/// contents of `mem` are unspecified.
///
/// Ownership: the caller owns `mem`; the handle is valid while `mem` stays
/// allocated, unmoved and unmodified. Evaluators built from it refer to it.
/// Nothing to destroy: free `mem` when no evaluator uses the tables any more.
///
/// # Safety
/// `mem` is NULL or points to `mem_len` writable bytes not otherwise in use;
/// `out` is NULL or points to a writable `const ccss_tables *`.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_build_standard(
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssTables,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const *const CcssTables, "out")?;
        // SAFETY: forwarded caller promise.
        unsafe { build_tables(mem, mem_len, out, &Weights::STANDARD) }
    })
}

/// Builds the tables of rule `w` into the block `mem` (`mem_len` bytes) and
/// writes the handle to `*out` (already checked non-NULL and aligned).
///
/// # Safety
/// `mem` is NULL or points to `mem_len` writable bytes not otherwise in use;
/// `out` is writable.
unsafe fn build_tables(
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssTables,
    w: &Weights,
) -> Result<(), Failure> {
    let base = try_block(mem, mem_len, TABLES_BYTES)?;
    let t = base as *mut CcssTables;
    // SAFETY: `base` is 8-aligned with TABLES_BYTES writable bytes: the
    // tables at offset 0, the scratch at TABLES_HEAD (both align <= 8,
    // see the assertions below). Both are initialised by copying from
    // zeroed statics (a memcpy: no large temporaries on the stack).
    unsafe {
        let scratch = base.add(TABLES_HEAD) as *mut BuildScratch;
        ptr::addr_of_mut!((*t).inner.magic).write(0);
        ptr::copy_nonoverlapping(&ZERO_TABLES, ptr::addr_of_mut!((*t).inner.set), 1);
        ptr::copy_nonoverlapping(&ZERO_SCRATCH, scratch, 1);
        build_set(&mut (*t).inner.set, w, &mut *scratch)?;
        ptr::addr_of_mut!((*t).inner.checksum).write(set_checksum(&(*t).inner.set));
        ptr::addr_of_mut!((*t).inner.magic).write(<CcssTables as crate::boundary::Handle>::MAGIC);
        *out = t;
    }
    Ok(())
}

/// Builds the tables of rule `w` into `set` ([`TableSet::build_into`]).
fn build_set(set: &mut TableSet, w: &Weights, scratch: &mut BuildScratch) -> Result<(), Failure> {
    // Under Miri the standard tables come from the baked file (valences
    // 3..=8): building them is minutes interpreted, and the ABI's pointer
    // and handle paths are what Miri is run for.
    #[cfg(miri)]
    if *w == Weights::STANDARD {
        ccss_core::eigen::bake::decode_set_into(ccss_core::eigen::bake::BAKED_BYTES, set);
        return Ok(());
    }
    set.build_into(w, scratch)?;
    Ok(())
}

/// The [`Checksum`] of every word of the tables (each valence's table as
/// `ccss_core::eigen::bake::bake_words` lists it, then the vertex rule).
fn set_checksum(set: &TableSet) -> u64 {
    let mut h = Checksum::new();
    bake_words(set, MAX_VALENCE, |w| h.word(w));
    let w = set.weights();
    for n in 1..=MAX_VALENCE {
        let (a, b, c) = w.get(n);
        for x in [a, b, c] {
            h.word(x.to_bits());
        }
    }
    h.value()
}

/// `Ok` if the tables' words still match the checksum taken at build;
/// CORRUPTED otherwise (also when the header's magic word was overwritten,
/// `t` being a handle an evaluator was built from).
pub(crate) fn verify_tables(t: &CcssTables) -> Result<(), Failure> {
    if t.inner.magic != <CcssTables as crate::boundary::Handle>::MAGIC
        || set_checksum(&t.inner.set) != t.inner.checksum
    {
        return Err(Failure::new(
            CcssStatus::ERR_CORRUPTED,
            Msg::Corrupted("ccss_tables"),
        ));
    }
    Ok(())
}

/// Checks the integrity of a tables block: every word of the tables against
/// the checksum taken by `ccss_tables_build*`. Any single changed word is
/// found; several changed words go unnoticed with probability about 2^-64.
/// Cost: one pass over the tables (about 830 KiB for the default maximum
/// valence 16; well under a millisecond); the other calls check only the
/// handle's magic word.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_HANDLE, CORRUPTED.
///
/// # Safety
/// `tables` is NULL or a live handle; `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_verify(
    tables: *const CcssTables,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let tb = unsafe { try_handle(tables, "tables") }?;
        verify_tables(tb)
    })
}

/// Largest accepted `|alpha + beta + gamma - 1|` of a weight entry (ccss-core's
/// `weights::SUM_TOLERANCE`).
pub const CCSS_WEIGHT_ENTRY_SUM_TOLERANCE: f64 = 1e-12;

/// The vertex rule of one valence: a vertex `V` of valence `n` moves to
/// `alpha V + beta/n sum(E_i) + gamma/n sum(F_i)` (`E_i` its edge neighbours,
/// `F_i` its face-diagonal vertices; for a non-quad face the virtual vertex
/// `4 C - V - E_i - E_(i+1)`, `C` the face centroid). Edge and face points
/// keep the standard rules. Standard Catmull-Clark is `alpha = 1 - 7/(4n)`,
/// `beta = 3/(2n)`, `gamma = 1/(4n)`.
///
/// Valid entries: `3 <= valence <= ccss_max_valence`, finite non-negative
/// weights adding up to 1 (within `CCSS_WEIGHT_ENTRY_SUM_TOLERANCE`), and for
/// valence 4 exactly the standard weights (9/16, 3/8, 1/16): regular patches
/// are bicubic B-splines.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssWeightEntry {
    /// The valence `n` this rule applies to.
    pub valence: u32,
    /// Weight of the vertex itself.
    pub alpha: f64,
    /// Total weight of the `n` edge neighbours.
    pub beta: f64,
    /// Total weight of the `n` face-diagonal vertices.
    pub gamma: f64,
}

/// The rule of `e` set into `w` (core's validation).
fn set_entry(w: &mut Weights, e: &CcssWeightEntry) -> Result<(), Error> {
    // u32 -> usize is lossless on every platform ccss supports (>= 32 bits).
    w.set(e.valence as usize, e.alpha, e.beta, e.gamma)
}

/// Validates `count` weight entries (all before any is used) into a rule:
/// valences not listed keep the standard rule.
fn weights_of(entries: &[CcssWeightEntry]) -> Result<Weights, Failure> {
    let mut w = Weights::STANDARD;
    for (i, e) in entries.iter().enumerate() {
        if let Some(first) = entries[..i].iter().position(|p| p.valence == e.valence) {
            let mut f = Failure::new(
                CcssStatus::ERR_INVALID_ARGUMENT,
                Msg::DuplicateValence {
                    valence: e.valence,
                    first: first as u64,
                },
            );
            f.value = e.valence as i64;
            f.query_index = Some(i as u64);
            f.index_name = "entry";
            return Err(f);
        }
        set_entry(&mut w, e).map_err(|err| {
            let mut f = Failure::from(err);
            f.query_index = Some(i as u64);
            f.index_name = "entry";
            f
        })?;
    }
    Ok(w)
}

/// Builds the eigen tables of a general vertex rule into `mem` (`mem_len` bytes,
/// 8-byte aligned, at least `ccss_tables_required_bytes`, the same size as
/// for `ccss_tables_build_standard`) and writes the handle (which equals
/// `mem`) to `*out`. Takes a few milliseconds.
///
/// `entries[0..count]` give the rule of some valences (see
/// `ccss_weight_entry`); every valence not listed keeps the standard rule, so
/// `count == 0` (`entries` may then be NULL) builds the standard tables. Each
/// valence may be listed once. Evaluators built from these tables use the
/// rule both for the eigen evaluation near extraordinary vertices and for
/// their internal refinement steps.
///
/// All entries are validated before the memory block is looked at: on the
/// first bad entry the function fails with INVALID_WEIGHTS (or INVALID_ARGUMENT for a
/// valence listed twice), `detail.query_index` = the entry's index,
/// `detail.value` = its valence, and neither `mem` nor `*out` is written.
///
/// Errors: NULL_POINTER (`out`, `entries` with `count > 0`, `mem` with
/// `mem_len > 0`), MISALIGNED, INVALID_WEIGHTS, INVALID_ARGUMENT,
/// BUFFER_TOO_SMALL (`detail.required` = bytes; checked after the entries),
/// TABLE_BUILD_FAILED. On a failure after validation `*out` is not written
/// and the contents of `mem` are unspecified.
///
/// Ownership: as `ccss_tables_build_standard`; the entries are not referred
/// to after the call.
///
/// # Safety
/// `entries` is NULL or points to `count` readable entries; `mem` is NULL or
/// points to `mem_len` writable bytes not otherwise in use (not overlapping
/// `entries`); `out` and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_build(
    entries: *const CcssWeightEntry,
    count: usize,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *const CcssTables,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        check_ptr(out as *const *const CcssTables, "out")?;
        // SAFETY: forwarded caller promise.
        let es = unsafe { try_slice(entries, count, "entries") }?;
        // Validated into a small rule on the stack (no heap) before `mem` is
        // touched.
        let w = weights_of(es)?;
        // SAFETY: forwarded caller promises.
        unsafe { build_tables(mem, mem_len, out, &w) }
    })
}

/// Validates one weight entry without building anything and writes to
/// `*out` 1 if the rule gives a tangent-plane continuous
/// surface at extraordinary vertices of that valence, else 0: the
/// frequency-0 eigenvalues are dominated by the subdominant eigenvalue of the
/// rest of the spectrum, `|lambda_0| < lambda_2` (Ball and Storry; 1 for the
/// standard rule). Tangent-plane discontinuity is a property, not an error:
/// such weights are accepted by `ccss_tables_build`.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_WEIGHTS (`detail.value` = the
/// valence; `query_index` is `UINT64_MAX`). `*out` is
/// written only on success.
///
/// # Safety
/// `entry` is NULL or points to a readable entry; `out`
/// and `detail` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_weight_entry_check(
    entry: *const CcssWeightEntry,
    out: *mut c_int,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let e = unsafe { try_ref(entry, "entry") }?;
        check_ptr(out as *const c_int, "out")?;
        let mut w = Weights::STANDARD;
        set_entry(&mut w, e)?;
        let tpc = w.tangent_plane_continuous(e.valence as usize);
        // SAFETY: checked above.
        unsafe { put(out, "out", c_int::from(tpc)) }
    })
}

/// Facts about the eigen table of one valence `n` (`ccss_tables_valence`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CcssTablesValenceInfo {
    /// The valence `n`.
    pub valence: u32,
    /// Control points of an extraordinary patch, `2n + 8`.
    pub num_points: u32,
    /// The vertex rule the table was built for (see `ccss_weight_entry`).
    pub alpha: f64,
    /// See `alpha`.
    pub beta: f64,
    /// See `alpha`.
    pub gamma: f64,
    /// The subdominant eigenvalue of the local subdivision matrix (largest
    /// modulus below 1; for a complex pair, its modulus).
    pub subdominant: f64,
    /// 1 if the rule is tangent-plane continuous at this valence
    /// (`|lambda_0| < lambda_2`, see `ccss_weight_entry_check`), else 0.
    pub tangent_plane_continuous: c_int,
    /// 1 if the frequency-0 eigenvalues are a complex pair (possible with
    /// general weights), else 0.
    pub complex_pair: c_int,
    /// Limit-point weight of the extraordinary vertex itself (the left
    /// eigenvector of eigenvalue 1, report eq. 2.7): the limit position of a
    /// vertex whose faces are all quads is
    /// `limit_v V + limit_e sum(E_i) + limit_f sum(F_i)`.
    pub limit_v: f64,
    /// Limit-point weight of each of the `n` edge neighbours.
    pub limit_e: f64,
    /// Limit-point weight of each of the `n` face-diagonal vertices.
    pub limit_f: f64,
}

/// Writes to `*out` facts about the eigen table of valence `valence`: its
/// vertex rule, subdominant eigenvalue, tangent-plane continuity, complex
/// pair, and limit-point weights.
///
/// Errors: NULL_POINTER, MISALIGNED, UNSUPPORTED_VALENCE (`valence` outside
/// `3..=ccss_max_valence`).
///
/// # Safety
/// `tables` is NULL or a live handle; `out` is NULL or writable.
/// `detail` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_tables_valence(
    tables: *const CcssTables,
    valence: u32,
    out: *mut CcssTablesValenceInfo,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promise.
        let tb = unsafe { try_handle(tables, "tables") }?;
        check_ptr(out as *const CcssTablesValenceInfo, "out")?;
        let t = tb
            .set
            .get(valence as usize)
            .ok_or(Error::UnsupportedValence {
                vertex: u32::MAX,
                valence,
            })?;
        let (alpha, beta, gamma) = t.weights();
        let lw = t.limit_weights();
        let at = |i: usize| lw.get(i).copied().unwrap_or(f64::NAN);
        let info = CcssTablesValenceInfo {
            valence,
            num_points: t.num_points() as u32,
            alpha,
            beta,
            gamma,
            subdominant: t.subdominant(),
            tangent_plane_continuous: c_int::from(t.tangent_plane_continuous()),
            complex_pair: c_int::from(t.has_complex_pair()),
            limit_v: at(0),
            limit_e: at(1),
            limit_f: at(2),
        };
        // SAFETY: checked above.
        unsafe { put(out, "out", info) }
    })
}
