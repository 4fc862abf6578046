//! Eigen tables as plain words, for tables baked into flash.
//!
//! [`ValenceTable::for_each_word`] lists, as `u64` words (floats by their
//! bits), everything of a table that evaluation, bounds and depths read:
//! the leading `k x k` blocks and first `k` entries (`k = 2n + 8`) of each
//! field, never the unused rest of the fixed `MAX_K` layout. A baked file
//! is the words `[count, table 1, table 2, ...]` of valences `3, 4, ...`
//! ([`bake_words`]; the example `bake_tables` writes
//! `core/src/eigen/baked_tables.bin`), and [`decode_set`] turns a table's words
//! back into a table in a `const` context, so that, with the crate feature
//! `baked-tables`, `ccss_core::eigen::BAKED_TABLES` is a `static` computed by
//! the compiler: in flash, no RAM and no table-building code at run time.
//! The runtime builder stays ([`crate::TableSet::build_into`]) for other
//! rules and valences. `tests/tests/baked_tables.rs` checks that the file
//! is what the builder makes now, word for word.

use super::rates::Rates;
use super::set::TableSet;
use super::table::ValenceTable;
use crate::config::MAX_K;

/// Largest valence in `baked_tables.bin`.
pub const BAKED_MAX_VALENCE: usize = 8;

impl ValenceTable {
    /// Calls `f` with every word of the table's meaningful part, in the
    /// order [`decode_set`] reads them (see the module docs).
    pub fn for_each_word(&self, mut f: impl FnMut(u64)) {
        let k = self.k;
        let mut reals = |x: f64| f(x.to_bits());
        let index = |i: usize| f64::from_bits(i as u64);
        reals(index(self.n));
        reals(index(k));
        reals(self.weights.0);
        reals(self.weights.1);
        reals(self.weights.2);
        for c in 0..k {
            reals(self.mu[c]);
        }
        let (q0, m) = self.quad.unwrap_or((usize::MAX, [[0.0; 2]; 2]));
        reals(index(self.quad.is_some() as usize));
        reals(index(q0));
        for row in m {
            for x in row {
                reals(x);
            }
        }
        for i in 0..k {
            for j in 0..k {
                reals(self.left[i][j]);
            }
        }
        for i in 0..k {
            for j in 0..k {
                reals(self.right[i][j]);
            }
        }
        for b in 0..3 {
            for c in 0..k {
                for x in self.x[b][c] {
                    reals(x);
                }
            }
        }
        reals(index(self.sub.0));
        reals(index(self.sub.1));
        for c in 0..k {
            reals(self.tan_u[c]);
            reals(self.tan_v[c]);
        }
        let r = &self.rates;
        reals(index(r.n));
        for x in [r.r1, r.r2, r.c_new, r.c_lemma10, r.r_old, r.c_old] {
            reals(x);
        }
        for c in 0..k {
            reals(self.sup_phi[c]);
        }
        reals(self.quad_growth);
        for c in 0..k {
            reals(self.flat_phi[c]);
            reals(self.flat_lin[c][0]);
            reals(self.flat_lin[c][1]);
            reals(self.flat_pair[c]);
        }
        for d in 0..3 {
            for c in 0..k {
                reals(self.ring_sd[d][c]);
                reals(self.ring_pair[d][c]);
            }
        }
        for c in 0..k {
            for x in self.ring_pts[c] {
                reals(x);
            }
        }
        // The kernel's eigenvalue powers (`powi`, not available in a
        // `const fn`, so baked rather than recomputed at decode).
        for row in &self.mu_pow {
            for &x in &row[..k] {
                reals(x);
            }
        }
    }
}

/// Calls `f` with the words of a baked file of the valences `3..=max_n`
/// of `set` (those it holds): their count, then each table's words.
pub fn bake_words(set: &TableSet, max_n: usize, mut f: impl FnMut(u64)) {
    let tables = (3..=max_n).filter_map(|n| set.get(n));
    f(tables.clone().count() as u64);
    for t in tables {
        t.for_each_word(&mut f);
    }
}

/// Reads words of a little-endian byte file in a `const` context.
struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
}

impl Reader<'_> {
    const fn word(&mut self) -> u64 {
        let b = self.bytes;
        let i = self.at;
        self.at += 8;
        u64::from_le_bytes([
            b[i],
            b[i + 1],
            b[i + 2],
            b[i + 3],
            b[i + 4],
            b[i + 5],
            b[i + 6],
            b[i + 7],
        ])
    }
    const fn real(&mut self) -> f64 {
        f64::from_bits(self.word())
    }
    const fn index(&mut self) -> usize {
        self.word() as usize
    }
}

/// Decodes one table from `r` (the order of
/// [`ValenceTable::for_each_word`]); entries beyond `k` stay zero, as in a
/// freshly built table.
const fn decode(r: &mut Reader) -> ValenceTable {
    let mut t = ValenceTable::ZERO;
    t.n = r.index();
    let k = r.index();
    t.k = k;
    assert!(k <= MAX_K, "baked table larger than MAX_K");
    t.weights = (r.real(), r.real(), r.real());
    let mut c = 0;
    while c < k {
        t.mu[c] = r.real();
        c += 1;
    }
    let has_quad = r.word() != 0;
    let q0 = r.index();
    let m = [[r.real(), r.real()], [r.real(), r.real()]];
    t.quad = if has_quad { Some((q0, m)) } else { None };
    let mut i = 0;
    while i < k {
        let mut j = 0;
        while j < k {
            t.left[i][j] = r.real();
            j += 1;
        }
        i += 1;
    }
    i = 0;
    while i < k {
        let mut j = 0;
        while j < k {
            t.right[i][j] = r.real();
            j += 1;
        }
        i += 1;
    }
    let mut b = 0;
    while b < 3 {
        c = 0;
        while c < k {
            let mut e = 0;
            while e < 16 {
                t.x[b][c][e] = r.real();
                e += 1;
            }
            c += 1;
        }
        b += 1;
    }
    t.sub = (r.index(), r.index());
    c = 0;
    while c < k {
        t.tan_u[c] = r.real();
        t.tan_v[c] = r.real();
        c += 1;
    }
    t.rates = Rates {
        n: r.index(),
        r1: r.real(),
        r2: r.real(),
        c_new: r.real(),
        c_lemma10: r.real(),
        r_old: r.real(),
        c_old: r.real(),
    };
    c = 0;
    while c < k {
        t.sup_phi[c] = r.real();
        c += 1;
    }
    t.quad_growth = r.real();
    c = 0;
    while c < k {
        t.flat_phi[c] = r.real();
        t.flat_lin[c] = [r.real(), r.real()];
        t.flat_pair[c] = r.real();
        c += 1;
    }
    let mut d = 0;
    while d < 3 {
        c = 0;
        while c < k {
            t.ring_sd[d][c] = r.real();
            t.ring_pair[d][c] = r.real();
            c += 1;
        }
        d += 1;
    }
    c = 0;
    while c < k {
        let mut e = 0;
        while e < 16 {
            t.ring_pts[c][e] = r.real();
            e += 1;
        }
        c += 1;
    }
    let mut e = 0;
    while e < super::table::POW_LEVELS {
        c = 0;
        while c < k {
            t.mu_pow[e][c] = r.real();
            c += 1;
        }
        e += 1;
    }
    t
}

/// The standard-rule tables of a baked file (`bytes`: little-endian words
/// of [`bake_words`]) of valences up to `MAX_VALENCE`, in a `const`
/// context; valences the file lacks stay unbuilt ([`TableSet::get`] gives
/// `None` for them).
pub const fn decode_set(bytes: &[u8]) -> TableSet {
    let mut set = TableSet::ZERO;
    let mut r = Reader { bytes, at: 0 };
    let count = r.index();
    let mut i = 0;
    while i < count {
        let t = decode(&mut r);
        if let Some(slot) = TableSet::slot(t.n) {
            set.tables[slot] = t;
        }
        i += 1;
    }
    set
}

/// Decodes a baked file at run time (for the tests: the `const` decoder
/// run on bytes made now).
pub fn decode_set_into(bytes: &[u8], out: &mut TableSet) {
    let mut r = Reader { bytes, at: 0 };
    let count = r.index();
    *out = TableSet::ZERO;
    for _ in 0..count {
        let t = decode(&mut r);
        if let Some(slot) = TableSet::slot(t.n) {
            out.tables[slot] = t;
        }
    }
}

/// The bytes of `baked_tables.bin` (standard rule, valences
/// `3..=BAKED_MAX_VALENCE`). Under Miri the C ABI decodes its standard
/// tables from them ([`decode_set_into`]) instead of building them (an
/// eigen decomposition takes minutes interpreted).
#[cfg(any(miri, feature = "baked-tables"))]
pub const BAKED_BYTES: &[u8] = include_bytes!("baked_tables.bin");

/// The standard-rule tables of the valences of
/// [`crate::config::TABLE_VALENCES`] up to 8 from `baked_tables.bin`,
/// computed at compile time into a `static` (flash on a microcontroller):
/// `8 * (2 MAX_K^2 + 110 MAX_K)` bytes per listed valence (30 KiB each for
/// `CCSS_MAX_VALENCE=8`; `CCSS_TABLE_VALENCES=3,4` keeps two), no RAM.
/// Listed valences above 8 are not built (`get` gives `None`).
#[cfg(feature = "baked-tables")]
pub static BAKED_TABLES: TableSet = decode_set(BAKED_BYTES);
