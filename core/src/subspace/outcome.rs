//! The outcome of the PI-MOESP step, dense or structured: the singular values and `Γ_f` that
//! the order and the model are taken from.

use crate::linalg::Small;
use crate::scalar::Real;

/// The outcome of the PI-MOESP step.
#[derive(Clone, Debug)]
pub(crate) struct Projection<T, const H: usize> {
    /// Hankel columns.
    pub j: u64,
    /// Singular values of `O_f / √j`, descending (first `f` valid).
    pub sv: [T; H],
    /// Whitened singular values (order selection), descending.
    pub sv_white: [T; H],
    /// `Γ_f` for every order: its first `n` columns are the estimate of order `n`.
    pub gamma: Small<T, H>,
}

impl<T: Real, const H: usize> Projection<T, H> {
    /// Nothing yet (no columns, zero singular values and `Γ_f`), to be filled in place.
    pub(crate) fn empty() -> Self {
        Self {
            j: 0,
            sv: [T::zero(); H],
            sv_white: [T::zero(); H],
            gamma: Small::zeros(),
        }
    }
}
