//! The two dense solves of the closed-loop estimate: Gram matrices by Cholesky (refusing
//! numerically singular ones) and least squares by SVD, as in [`crate::reference`].

use nalgebra::{Cholesky, DMatrix, Dyn, SVD};

use crate::closed_loop::error::ReferenceError;

/// Cholesky factor of the symmetric positive definite `g`; `RankDeficient(which)` when it is
/// singular or numerically so (squared ratio of the smallest to the largest pivot below
/// `1e-13`).
pub fn spd_factor(
    g: DMatrix<f64>,
    which: &'static str,
) -> Result<Cholesky<f64, Dyn>, ReferenceError> {
    let chol = g.cholesky().ok_or(ReferenceError::RankDeficient(which))?;
    let diag = chol.l_dirty().diagonal();
    let (lo, hi) = diag.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo > 0.0 && (lo / hi).powi(2) > 1e-13) {
        return Err(ReferenceError::RankDeficient(which));
    }
    Ok(chol)
}

/// Least-squares solution of `m x = r` through the SVD of `m`.
pub fn least_squares(
    m: DMatrix<f64>,
    r: &DMatrix<f64>,
    which: &'static str,
) -> Result<DMatrix<f64>, ReferenceError> {
    let svd = SVD::try_new(m, true, true, f64::EPSILON, 10_000)
        .ok_or(ReferenceError::NoConvergence(which))?;
    let tol = svd.singular_values.max() * 1e-14;
    svd.solve(r, tol)
        .map_err(|_| ReferenceError::NoConvergence(which))
}

/// `x` projected on the row space of `w`: `(x wᵀ)(w wᵀ)⁻¹ w`, with `w wᵀ` factored once.
pub fn project(x: &DMatrix<f64>, w: &DMatrix<f64>, gram: &Cholesky<f64, Dyn>) -> DMatrix<f64> {
    gram.solve(&(w * x.transpose())).transpose() * w
}
