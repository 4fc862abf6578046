//! The tables of every valence `3..=MAX_VALENCE`, built together.

use super::table::{BuildScratch, ValenceTable};
use crate::config::MAX_VALENCE;
use crate::error::Error;
use crate::mesh::weights::Weights;

/// Tables for every valence `3..=MAX_VALENCE` (about 60 KiB each for
/// `MAX_VALENCE = 16`, 14 tables: about 834 KiB).
pub struct TableSet {
    pub(super) tables: [ValenceTable; MAX_VALENCE - 2],
    weights: Weights,
}

impl TableSet {
    /// An empty set; fill it with [`TableSet::build_into`].
    pub const ZERO: TableSet = TableSet {
        tables: [const { ValenceTable::ZERO }; MAX_VALENCE - 2],
        weights: Weights::STANDARD,
    };

    /// Builds all valences for vertex rule `w`.
    pub fn build_into(&mut self, w: &Weights, scratch: &mut BuildScratch) -> Result<(), Error> {
        self.weights = *w;
        for n in 3..=MAX_VALENCE {
            self.tables[n - 3].build_into(n, w, scratch)?;
        }
        Ok(())
    }

    /// The table of valence `n`, if built.
    #[inline]
    pub fn get(&self, n: usize) -> Option<&ValenceTable> {
        if (3..=MAX_VALENCE).contains(&n) {
            let t = &self.tables[n - 3];
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
