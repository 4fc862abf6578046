//! # ccss-ffi: the C ABI of ccss
//!
//! Built as `libccss.a` / `libccss.so` (and an rlib); the C header is
//! `include/ccss.h`, generated from these files by cbindgen 0.29.4
//! (`ffi/gen_header.sh`; committed, and diffed in CI).
//!
//! ## Files (modelled on rustls-ffi: one file per C object family)
//!
//! | file | C objects |
//! |---|---|
//! | `lib.rs` | the library: `ccss_version`, `ccss_max_valence` |
//! | `status.rs` | `ccss_status`, `ccss_error_detail` (the core error mapping) |
//! | `boundary.rs` | no exports: the panic guard and the pointer helpers |
//! | `tables.rs` | `ccss_tables`, `ccss_weight_entry`, `ccss_tables_valence_info` |
//! | `topology.rs` | `ccss_topology` |
//! | `evaluator_options.rs` | `ccss_evaluator_options` (what an evaluator keeps: memory against speed) |
//! | `evaluator.rs` | `ccss_evaluator`, `ccss_evaluator_query`, `ccss_evaluator_result` |
//! | `feature.rs` | `ccss_feature_evaluator`, `ccss_feature_options`, `ccss_feature_boundary`, `ccss_feature_creasing` |
//! | `depth.rs` | `ccss_depth_*` (subdivision depth) |
//! | `tessellation.rs` | `ccss_tessellation` and its `ccss_tessellation_*` types |
//! | `unified.rs` | `ccss_unified_*` (the unified scheme of Maillot & Stam) |
//! | `voxel.rs` | `ccss_voxel_grid` and its types, `ccss_mass_properties` |
//! | `interpolation.rs` | `ccss_interpolation_*` (one-shot, matrix-free), `ccss_interpolation_options`, `_requirement`, `_stats` |
//! | `interpolator.rs` | `ccss_interpolator` (the same problem as a handle: build, assemble the normal matrix, solve) |
//! | `query.rs` | `ccss_query` (work area of the certified queries): rays, inside/outside, closest points, slices |
//! | `query_band.rs` | `ccss_query_slice_band*` (up to `CCSS_QUERY_MAX_BAND` layers of a plane family per walk) |
//!
//! ## Naming rule (one rule, every export)
//!
//! * **Functions** are `ccss_<object>_<verb>`. `<object>` is the C type the
//!   function works on, without its `ccss_` prefix: a handle (`tables`,
//!   `topology`, `evaluator`, `feature_evaluator`, `tessellation`,
//!   `voxel_grid`, `query`), a family without a handle (`depth`, `unified`), or a
//!   plain value type that has functions of its own (`status`,
//!   `error_detail`, `weight_entry`, `feature_options`, `unified_params`,
//!   `mass_properties`). The library itself is the object
//!   `ccss`: `ccss_version`, `ccss_max_valence`.
//! * **Verbs**: `_required_bytes` (the size query of a memory block; the
//!   only size-query name), `_build` (make a handle in a caller block; no
//!   `_init` / `_new`), `_eval*`, `_emit`, `_compute`, `_check`, `_verify` (integrity check of a handle block),
//!   `_format` (`ccss_tessellation_feature_required_bytes` / `_build`:
//!   the tessellation's size query and build for a `feature_evaluator`;
//!   `ccss_query_feature_<verb>`: the queries on a `feature_evaluator`;
//!   `ccss_evaluator_required_bytes_with_options` / `_build_with_options`:
//!   the size query and build with a `ccss_evaluator_options`),
//!   `_assemble` / `_solve` (`ccss_interpolator_matrix_required_bytes` /
//!   `_assemble`: the size query and build of an interpolator's normal
//!   matrix, a second block);
//!   a query that reads a property is named by what it writes
//!   (`_face_count`, `_counts`, `_rates`, `_valence`), with no `get_`
//!   prefix.
//! * **Types** are `ccss_<object>` (the handle, or the value type) or
//!   `ccss_<object>_<noun>` (a struct or enum of that object). C has one
//!   namespace for functions and typedefs, so the struct a query
//!   `ccss_<object>_<what>` fills is `ccss_<object>_<what>_info`
//!   (`ccss_depth_rates` -> `ccss_depth_rates_info`), and the statistics of
//!   an operation are `ccss_<object>_<verb>_stats`.
//! * **Constants** are `CCSS_<OBJECT>_<NAME>`; enum values are
//!   `CCSS_<ENUM>_<VALUE>` (`CCSS_DEPTH_BEST`, `CCSS_TESSELLATION_RELATIVE`),
//!   statuses `CCSS_OK` and `CCSS_ERR_<WHAT>`.
//! * **Parameters**: inputs first (handles, then arrays with their counts,
//!   then scalars), then the caller memory block `mem, mem_len`, then the
//!   out-parameters `out` (or `out_<what>` when there are several; an output
//!   array's capacity is `out_len` / `out_<what>_len`), and last
//!   `ccss_error_detail *detail`.
//!
//! ## Conventions
//!
//! * Every function that can fail returns a [`CcssStatus`] (`ccss_status`
//!   in C) and takes `ccss_error_detail *detail` as its last parameter (may
//!   be NULL), filled on failure with the status, the offending face /
//!   vertex / edge / query / entry, the required size and a message.
//!   Results go to out-parameters, which are written **only on success**.
//! * Every pointer is checked for NULL (a NULL array with a zero count is
//!   fine), for the alignment of its type and for a length of at most
//!   `isize::MAX` bytes (`boundary.rs`); every export catches panics and
//!   returns `CCSS_ERR_INTERNAL` instead of unwinding into C.
//! * A caller buffer that is too small is always `CCSS_ERR_BUFFER_TOO_SMALL`
//!   with the required size (bytes of a memory block, elements of an
//!   array) in `detail.required`; a bug in ccss (a caught panic, an
//!   internal inconsistency) is always `CCSS_ERR_INTERNAL`.
//! * **No allocation**: the C caller provides all memory. Each handle has a
//!   size query (`*_required_bytes`); the caller allocates a block of that
//!   many bytes, 8-byte aligned (`malloc` is fine), and the build function
//!   writes the handle at the start of the block and uses the rest as its
//!   arena. The returned handle pointer *is* the block address: there is
//!   nothing to destroy, the caller frees the block when done.
//!
//! ## Lifetime contract (C side)
//!
//! * A block must stay allocated, unmoved and unmodified while its handle is
//!   used, and while any handle built from it is used.
//! * `ccss_topology` copies the positions, face sizes and indices into its
//!   block: the caller's arrays may be freed right after
//!   `ccss_topology_build`.
//! * `ccss_evaluator` refers to its `ccss_tables` (keep the tables block alive
//!   as long as the evaluator) but **not** to the `ccss_topology`: core's
//!   `Evaluator` stores only its tables reference and slices of its own
//!   memory, so the topology block may be freed right after
//!   `ccss_evaluator_build`.
//! * `ccss_feature_evaluator` refers to nothing outside its block: the
//!   refined mesh it evaluates is computed into the block, so the input
//!   arrays (mesh and tags) may be freed right after
//!   `ccss_feature_evaluator_build`.
//! * `ccss_interpolator` refers to its `ccss_tables` and, once assembled,
//!   to its matrix block (keep both alive), not to the `ccss_topology`.
//! * `ccss_query_index` refers to its evaluator (keep it alive); a query
//!   area refers to the index attached to it (`ccss_query_set_index`; keep
//!   it alive and unmoved while attached, or detach it with NULL).
//! * Handles are immutable after build (except `ccss_tessellation`,
//!   `ccss_voxel_grid` and `ccss_interpolator`, which their functions write): const handles may be
//!   used from any number of threads at once.
//!
//! In Rust the handles hold core structures whose lifetimes are erased to
//! `'static`; the contract above is what makes that sound.
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

use core::ffi::c_char;

// In the order of the header (cbindgen follows the declarations; the
// comments keep rustfmt from sorting them).
mod status;
// The boundary helpers (no exports).
mod boundary;
// Object families, each built on the ones before it.
mod tables;
// -
mod topology;
// -
mod evaluator_options;
// -
mod evaluator;
// -
mod feature;
// -
mod depth;
// -
mod tessellation;
// -
mod unified;
// -
mod voxel;
// -
mod interpolation;
// -
mod interpolator;
// -
mod query;
// -
mod query_band;
// -
mod query_index;
// -
mod boolean;

#[cfg(test)]
mod tests;

use boundary::{guard, put};
pub use depth::*;
pub use evaluator::*;
pub use evaluator_options::*;
pub use feature::*;
pub use interpolation::*;
pub use interpolator::*;
pub use query::*;
pub use query_band::*;
pub use query_index::*;
pub use status::*;
pub use tables::*;
pub use tessellation::*;
pub use topology::*;
pub use unified::*;
pub use voxel::*;

// ---------------------------------------------------------------------------
// Library information.

/// The ccss version, e.g. "0.2.0": a static NUL-terminated string (never
/// free it).
#[no_mangle]
pub extern "C" fn ccss_version() -> *const c_char {
    const V: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    V.as_ptr() as *const c_char
}

/// Writes the largest supported vertex valence (and face size) to `*out`;
/// ccss-core's compile-time `MAX_VALENCE` (default 16).
///
/// Errors: NULL_POINTER, MISALIGNED.
///
/// # Safety
/// `out` is NULL or points to a writable `size_t`; `detail` is NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn ccss_max_valence(
    out: *mut usize,
    detail: *mut CcssErrorDetail,
) -> CcssStatus {
    // SAFETY: forwarded caller promise.
    guard(detail, || unsafe {
        put(out, "out", ccss_core::MAX_VALENCE)
    })
}
