//! Accuracy and work budget of [`super::measure::mass_properties_with`].

use crate::error::Error;

/// Relative agreement of the two area estimates of a cell at which the
/// adaptive area quadrature accepts it (default of
/// [`MeasureOptions::area_rel_tol`]).
pub const AREA_REL_TOL: f64 = 1e-13;
/// Left-out corner volume, relative to the model's size cubed, at which the
/// corner levels of an extraordinary patch stop (default of
/// [`MeasureOptions::corner_rel_tol`]).
pub const CORNER_REL_TOL: f64 = 1e-15;
/// Area cells per polynomial piece on average (plus [`AREA_CELLS_MIN`]):
/// the default cap of the adaptive area quadrature
/// ([`MeasureOptions::area_cells_per_piece`]). A piece that finds the
/// budget used up keeps its current estimate (counted in
/// [`super::MassProperties::area_unconverged`], its estimated error in the
/// bound).
pub const AREA_CELLS_PER_PIECE: u64 = 256;
/// Area cells always allowed (default of [`MeasureOptions::area_cells_min`]).
pub const AREA_CELLS_MIN: u64 = 1 << 16;

/// Accuracy and work of a mass-properties computation. Looser tolerances
/// and smaller budgets make it cheaper and its error bounds larger; the
/// bounds stay bounds of the result returned (module docs of
/// [`super::measure`]). `Default` is the full accuracy of
/// [`super::mass_properties`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasureOptions {
    /// A cell of the adaptive area quadrature is accepted when its two
    /// estimates agree to this fraction (default [`AREA_REL_TOL`] = 1e-13).
    /// Finite and positive.
    pub area_rel_tol: f64,
    /// Corner levels of an extraordinary patch stop when the left-out
    /// corner's volume bound is below this fraction of the model's size
    /// cubed, or at 60 levels (default [`CORNER_REL_TOL`] = 1e-15). Finite
    /// and positive.
    pub corner_rel_tol: f64,
    /// Area cells always allowed (default [`AREA_CELLS_MIN`] = 2^16).
    pub area_cells_min: u64,
    /// Area cells added to the budget per polynomial piece (default
    /// [`AREA_CELLS_PER_PIECE`] = 256). With both budgets 0 every piece
    /// takes one cell (its four children against it).
    pub area_cells_per_piece: u64,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions {
            area_rel_tol: AREA_REL_TOL,
            corner_rel_tol: CORNER_REL_TOL,
            area_cells_min: AREA_CELLS_MIN,
            area_cells_per_piece: AREA_CELLS_PER_PIECE,
        }
    }
}

impl MeasureOptions {
    /// `InvalidArgument` naming the first tolerance that is not finite and
    /// positive.
    pub fn check(&self) -> Result<(), Error> {
        if !(self.area_rel_tol.is_finite() && self.area_rel_tol > 0.0) {
            return Err(Error::InvalidArgument(
                "area_rel_tol must be finite and positive",
            ));
        }
        if !(self.corner_rel_tol.is_finite() && self.corner_rel_tol > 0.0) {
            return Err(Error::InvalidArgument(
                "corner_rel_tol must be finite and positive",
            ));
        }
        Ok(())
    }
}
