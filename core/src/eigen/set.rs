//! The tables of every valence of `TABLE_VALENCES` (by default
//! `3..=MAX_VALENCE`; `CCSS_TABLE_VALENCES` at build time), built together.

use super::table::{BuildScratch, ValenceTable};
use crate::config::{TABLE_SLOT, TABLE_VALENCES};
use crate::error::Error;
use crate::mesh::weights::Weights;

/// Tables for every valence of [`crate::config::TABLE_VALENCES`] (by
/// default `3..=MAX_VALENCE`: about 60 KiB each for `MAX_VALENCE = 16`, 14
/// tables: about 834 KiB; a firmware lists only the valences of its meshes
/// with `CCSS_TABLE_VALENCES`).
pub struct TableSet {
    pub(super) tables: [ValenceTable; TABLE_VALENCES.len()],
    weights: Weights,
}

impl TableSet {
    /// An empty set; fill it with [`TableSet::build_into`].
    pub const ZERO: TableSet = TableSet {
        tables: [const { ValenceTable::ZERO }; TABLE_VALENCES.len()],
        weights: Weights::STANDARD,
    };

    /// Builds all valences of [`crate::config::TABLE_VALENCES`] for
    /// vertex rule `w`.
    pub fn build_into(&mut self, w: &Weights, scratch: &mut BuildScratch) -> Result<(), Error> {
        self.weights = *w;
        for (t, &n) in self.tables.iter_mut().zip(TABLE_VALENCES.iter()) {
            t.build_into(n, w, scratch)?;
        }
        Ok(())
    }

    /// The index in `tables` of valence `n`'s table, if the set has one.
    #[inline]
    pub(super) const fn slot(n: usize) -> Option<usize> {
        if n < TABLE_SLOT.len() && TABLE_SLOT[n] != usize::MAX {
            Some(TABLE_SLOT[n])
        } else {
            None
        }
    }

    /// The table of valence `n`, if built.
    #[inline]
    pub fn get(&self, n: usize) -> Option<&ValenceTable> {
        if let Some(i) = Self::slot(n) {
            let t = &self.tables[i];
            if t.n == n {
                return Some(t);
            }
        }
        None
    }

    /// The vertex rule the tables were built for.
    pub fn weights(&self) -> &Weights {
        &self.weights
    }
}
