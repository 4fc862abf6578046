//! The slot index of one evaluator for the queries (`ccss_query_index`):
//! built once into a caller block, attached to a query area with
//! `ccss_query_set_index`; the ray, inside, closest and slice exports on
//! that area then visit only the slots their ray, point or planes can
//! reach, with the same answers (`ccss_core::query::SlotIndex`).

use crate::boundary::{block_bytes, check_ptr, guard, put, round8, try_block, try_handle};
use crate::evaluator::CcssEvaluator;
use crate::feature::CcssFeatureEvaluator;
use crate::query::CcssQuery;
use crate::status::{CcssErrorDetail, CcssStatus, Failure};
use ccss_core::query::{IndexNode, QuerySurface, SlotIndex};
use core::ffi::c_void;
use core::mem::{align_of, needs_drop, size_of};
use core::ptr;

/// The slot index of one evaluator (opaque; lives at the start of its
/// block, the boxes after it). Refers to the evaluator it was built from.
pub struct CcssQueryIndex {
    /// Type tag and layout version (checked by every export).
    magic: u64,
    /// The evaluator handle (smooth or feature) the index belongs to.
    surface: *const c_void,
    index: SlotIndex<'static>,
}

impl crate::boundary::Handle for CcssQueryIndex {
    const MAGIC: u64 = crate::boundary::magic(b"ccssIDX1");
    const MAGIC_OFFSET: usize = core::mem::offset_of!(CcssQueryIndex, magic);
    const NAME: &'static str = "ccss_query_index";
}

const INDEX_HEAD: usize = round8(size_of::<CcssQueryIndex>());

const _: () = {
    assert!(align_of::<CcssQueryIndex>() <= 8);
    assert!(align_of::<IndexNode>() <= 8);
    assert!(!needs_drop::<CcssQueryIndex>());
};

/// Bytes of the block for `surf`.
fn index_bytes<S: QuerySurface + ?Sized>(surf: &S) -> Result<usize, Failure> {
    block_for(SlotIndex::required_len(surf))
}

/// Bytes of the block for `nodes` nodes.
fn block_for(nodes: usize) -> Result<usize, Failure> {
    let nodes = nodes
        .checked_mul(size_of::<IndexNode>())
        .ok_or(Failure::invalid("slot index size overflows"))?;
    block_bytes(nodes, INDEX_HEAD, "slot index size overflows")
}

/// Builds the index of `surf` (the handle at `surface`) in `mem`.
///
/// # Safety
/// `mem` NULL or `mem_len` writable bytes not otherwise in use; `out` NULL
/// or writable.
unsafe fn build_on<S: QuerySurface + ?Sized>(
    surf: &S,
    surface: *const c_void,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssQueryIndex,
) -> Result<(), Failure> {
    check_ptr(out as *const *mut CcssQueryIndex, "out")?;
    let n = SlotIndex::required_len(surf);
    let need = block_for(n)?;
    let base = try_block(mem, mem_len, need)?;
    // SAFETY: `base` is 8-aligned with `need` writable bytes: the header,
    // then `n` nodes (8-aligned: INDEX_HEAD is a multiple of 8), each
    // written before the slice is made.
    let nodes: &'static mut [IndexNode] = unsafe {
        let p = base.add(INDEX_HEAD) as *mut IndexNode;
        for i in 0..n {
            p.add(i).write(IndexNode::default());
        }
        core::slice::from_raw_parts_mut(p, n)
    };
    let index = SlotIndex::build(surf, nodes)?;
    // SAFETY: the header's bytes at `base` are writable and not aliased by
    // `nodes` (they follow it).
    unsafe {
        let h = base as *mut CcssQueryIndex;
        ptr::addr_of_mut!((*h).surface).write(surface);
        ptr::addr_of_mut!((*h).index).write(index);
        ptr::addr_of_mut!((*h).magic).write(<CcssQueryIndex as crate::boundary::Handle>::MAGIC);
        *out = h;
    }
    Ok(())
}

/// Writes to `*out` the bytes `ccss_query_index_build` needs for `ev`: a
/// header and 56 bytes per node (the slots plus twice the power of two
/// above their number).
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (size overflow).
///
/// # Safety
/// `ev` a live evaluator; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_index_required_bytes(
    ev: *const CcssEvaluator,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let n = index_bytes(&unsafe { try_handle(ev, "ev") }?.ev)?;
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", n) }
    })
}

/// Builds the slot index of `ev` in `mem` (`mem_len` bytes, 8-byte
/// aligned, at least `ccss_query_index_required_bytes`) and writes the
/// handle (which equals `mem`) to `*out`: one root cell per slot and a
/// sort. Attach it to query areas with `ccss_query_set_index`. Nothing to
/// destroy: free `mem` when done (after detaching it).
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL (`detail.required` =
/// bytes), INVALID_ARGUMENT. On failure `*out` is not written.
///
/// # Safety
/// `ev` a live evaluator that outlives the index; `mem` NULL or `mem_len`
/// writable bytes not otherwise in use, not moved while the index is used;
/// `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_index_build(
    ev: *const CcssEvaluator,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssQueryIndex,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { build_on(&e.ev, ev as *const c_void, mem, mem_len, out) }
    })
}

/// As `ccss_query_index_required_bytes`, for a feature evaluator.
///
/// Errors: NULL_POINTER, MISALIGNED, INVALID_ARGUMENT (size overflow).
///
/// # Safety
/// `ev` a live feature evaluator; `out`, `detail` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_index_required_bytes(
    ev: *const CcssFeatureEvaluator,
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let n = index_bytes(unsafe { try_handle(ev, "ev") }?.evaluator())?;
        // SAFETY: forwarded caller promise.
        unsafe { put(out, "out", n) }
    })
}

/// As `ccss_query_index_build`, for a feature evaluator (the index then
/// serves the `ccss_query_feature_*` exports).
///
/// Errors: NULL_POINTER, MISALIGNED, BUFFER_TOO_SMALL, INVALID_ARGUMENT.
/// On failure `*out` is not written.
///
/// # Safety
/// As `ccss_query_index_build`, with a live feature evaluator.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_feature_index_build(
    ev: *const CcssFeatureEvaluator,
    mem: *mut c_void,
    mem_len: usize,
    out: *mut *mut CcssQueryIndex,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        // SAFETY: forwarded caller promises.
        let e = unsafe { try_handle(ev, "ev") }?;
        // SAFETY: forwarded caller promises.
        unsafe { build_on(e.evaluator(), ev as *const c_void, mem, mem_len, out) }
    })
}

/// Attaches `index` to the query area `q` (NULL detaches): the query
/// exports called with `q` and the evaluator the index was built from use
/// it; called with another evaluator they fail with INVALID_ARGUMENT
/// (detach or attach that evaluator's index).
///
/// Errors: NULL_POINTER (`q`), MISALIGNED, INVALID_ARGUMENT (`index` is
/// not a built index). On failure `q` is unchanged.
///
/// # Safety
/// `q` a live query area not used elsewhere during the call; `index` NULL
/// or a live index that stays live and unmoved while attached; `detail`
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_query_set_index(
    q: *mut CcssQuery,
    index: *const CcssQueryIndex,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    guard(detail, || {
        if !index.is_null() {
            // SAFETY: forwarded caller promise.
            unsafe { try_handle(index, "index") }?;
        }
        // SAFETY: forwarded caller promise.
        let w = unsafe { crate::boundary::try_handle_mut(q, "q") }?;
        w.index = index;
        Ok(())
    })
}

/// The index attached to `q`, checked to belong to the evaluator handle
/// at `surface`; `None` when none is attached.
///
/// # Safety
/// `q` NULL or a live query area whose attached index (if any) is live.
pub(crate) unsafe fn attached<'a>(
    q: *mut CcssQuery,
    surface: *const c_void,
) -> Result<Option<&'a SlotIndex<'static>>, Failure> {
    // SAFETY: forwarded caller promise.
    let w = unsafe { try_handle(q as *const CcssQuery, "q") }?;
    if w.index.is_null() {
        return Ok(None);
    }
    // SAFETY: the attached index is live (caller promise).
    let ix = unsafe { try_handle(w.index, "q's index") }?;
    if ix.surface != surface {
        return Err(Failure::invalid(
            "q's index was built for another evaluator (ccss_query_set_index)",
        ));
    }
    Ok(Some(&ix.index))
}

/// Calls `$f(surface, q, args..)`, with the surface in the slot index
/// attached to `q` ([`attached`]) when there is one.
macro_rules! on_surface {
    ($f:ident, $surf:expr, $ev:expr, $q:expr $(, $arg:expr)* $(,)?) => {{
        let surf = $surf;
        // SAFETY: forwarded caller promises (`q` live, its index live).
        match unsafe { crate::query_index::attached($q, $ev as *const core::ffi::c_void) }? {
            Some(ix) => {
                let isurf = ccss_core::query::Indexed::new(surf, ix)?;
                // SAFETY: forwarded caller promises.
                unsafe { $f(&isurf, $q $(, $arg)*) }
            }
            // SAFETY: forwarded caller promises.
            None => unsafe { $f(surf, $q $(, $arg)*) },
        }
    }};
}
pub(crate) use on_surface;
