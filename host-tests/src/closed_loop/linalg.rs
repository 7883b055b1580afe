//! The two dense solves of the closed-loop estimate: Gram matrices by Cholesky (refusing
//! numerically singular ones) and least squares by SVD, as in [`crate::reference`].

use nalgebra::{Cholesky, DMatrix, Dyn};

use crate::closed_loop::error::ReferenceError;
use crate::reference;

/// Cholesky factor of the symmetric positive definite `g` ([`reference::spd_factor`]);
/// `RankDeficient(which)` when it is singular or numerically so.
pub(crate) fn spd_factor(
    g: DMatrix<f64>,
    which: &'static str,
) -> Result<Cholesky<f64, Dyn>, ReferenceError> {
    reference::spd_factor(g, which).map_err(|_| ReferenceError::RankDeficient(which))
}

/// Least-squares solution of `m x = r` ([`reference::least_squares`]).
pub(crate) fn least_squares(
    m: DMatrix<f64>,
    r: &DMatrix<f64>,
    which: &'static str,
) -> Result<DMatrix<f64>, ReferenceError> {
    reference::least_squares(m, r, which).map_err(|_| ReferenceError::NoConvergence(which))
}

/// `x` projected on the row space of `w`: `(x wᵀ)(w wᵀ)⁻¹ w`, with `w wᵀ` factored once.
pub fn project(x: &DMatrix<f64>, w: &DMatrix<f64>, gram: &Cholesky<f64, Dyn>) -> DMatrix<f64> {
    gram.solve(&(w * x.transpose())).transpose() * w
}
