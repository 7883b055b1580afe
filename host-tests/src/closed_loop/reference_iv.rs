//! A closed-loop consistent estimate from a logged reference: PI-MOESP on the data projected
//! on instruments built from the reference.
//!
//! Why not the open-loop estimate: in closed loop the controller feeds the noise of earlier
//! samples into the input, so the regressors `Z_p`, `Z_f` are correlated with the future
//! noise `V_f` in `Ȳ_f = Γ_f X + H_f Z_f + V_f`, and PI-MOESP's instruments `Z_p` no longer
//! remove it: the poles are biased.
//!
//! What is done instead (instruments built from the reference, in the spirit of Verhaegen,
//! "Application of a subspace model identification technique to identify LTI systems
//! operating in closed-loop", Automatica 29(4), 1993): the reference `r`, chosen by the
//! experimenter, is independent of the noise, so every row of an instrument matrix `W` built
//! from `r` alone is asymptotically orthogonal to `V_f`. Projecting on the row space of `W`
//! (`X^W = X Wᵀ(WWᵀ)⁻¹W`) keeps the relation, which is linear in `z` even though `z(u)` is
//! not linear in `u`: `Ȳ_f^W = Γ_f X^W + H_f Z_f^W + V_f^W` with `V_f^W → 0`. PI-MOESP on the
//! projected data is then consistent: `O_f = Ȳ_f^W Π⊥_{Z_f^W} → Γ_f X^W Π⊥_{Z_f^W}` (the
//! projection of eq. 11 on `[Z_p^W; Z_f^W]` is the identity there, `Ȳ_f^W` being in the row
//! space of `W`), and `U₂ᵀ Ȳ_f^W Z_f^Wᵀ (Z_f^W Z_f^Wᵀ)⁻¹ → U₂ᵀ H_f` gives bold `B`, `D` as in
//! the open-loop MOESP. The rank-1 split, `γ` (`G(1) = 1`) and the borders from `μ0` follow
//! the open-loop path ([`crate::reference`]), so a full model comes out.
//!
//! `W` must be rich enough for `[X; Z_f]` to keep full rank after the projection. A block
//! Hankel matrix of `r` itself is not: its rows are linear filters of `r`, on which the
//! ramps of one lag project nearly collinearly (and a scalar `r` gives one row per lag
//! against `m` per lag of `z`). `W` is therefore the block Hankel matrix of the regressors
//! `z(ũ)` of the input predicted from the reference alone ([`crate::closed_loop::instruments`]),
//! the same shape as `[Z_p; Z_f]` (a just-identified instrumental variable). The prediction
//! needs not be good for consistency, only correlated with the input (its quality sets the
//! variance).
//!
//! Assumption: the samples at `u_min` and `u_max` (the Table I excursions) are scheduled, not
//! decided by the controller from the measured output; they are kept in `ũ` as they are.

use nalgebra::{DMatrix, RowDVector};

use crate::closed_loop::error::ReferenceError;
use crate::closed_loop::instruments::{PREDICTOR_LAGS, instruments, predicted_input};
use crate::closed_loop::linalg::{least_squares, project, spd_factor};
use crate::reference::{
    RefConfig, RefError, RefModel, block_hankel, bold_bd, regressors, split_model,
};

/// The estimate of `u`, `y` (excitation only, no hold; the system at rest at `u_min` before
/// it), `μ0` and the reference `r` logged with them, with the knots, horizons and order of
/// `cfg`. See the module's documentation for the method.
pub fn identify_with_reference(
    u: &[f64],
    y: &[f64],
    r: &[f64],
    mu0: f64,
    cfg: &RefConfig,
) -> Result<RefModel, ReferenceError> {
    let j = check(u, y, r, mu0, cfg)?;
    let (f, p) = (cfg.f, cfg.p);
    let w = instruments(&predicted_input(u, r, cfg, PREDICTOR_LAGS)?, cfg, j);
    let gram_w = spd_factor(&w * w.transpose(), "the reference's instruments W W^T")?;
    let ybar = DMatrix::from_row_slice(1, y.len(), y).add_scalar(-mu0);
    let zf = block_hankel(&regressors(u, cfg), p, f, j);
    let zf_w = project(&zf, &w, &gram_w);
    let yf_w = project(&block_hankel(&ybar, p, f, j), &w, &gram_w);
    let chol = spd_factor(&zf_w * zf_w.transpose(), "the projected Z_f Z_f^T")?;
    // Ȳ_f^W Z_f^Wᵀ (Z_f^W Z_f^Wᵀ)⁻¹, for Π⊥_{Z_f^W} and for MOESP's B, D step.
    let coef = chol.solve(&(&zf_w * yf_w.transpose())).transpose();
    let space = column_space(&yf_w, &zf_w, &coef, cfg.order)?;
    let x_db = bold_bd(
        &space.u2t,
        &space.c,
        &space.a,
        &(&space.u2t * &coef),
        cfg.m(),
    )?;
    let ColumnSpace {
        c,
        a,
        singular_values,
        ..
    } = space;
    Ok(split_model(x_db, a, c, singular_values, mu0, cfg, j)?)
}

/// Checks the data and returns the Hankel columns `j = N − f − p + 1`.
fn check(
    u: &[f64],
    y: &[f64],
    r: &[f64],
    mu0: f64,
    cfg: &RefConfig,
) -> Result<usize, ReferenceError> {
    cfg.validate()?;
    if u.len() != y.len() || u.len() != r.len() {
        return Err(ReferenceError::LengthMismatch {
            u: u.len(),
            y: y.len(),
            r: r.len(),
        });
    }
    if let Some(at) = r.iter().position(|v| !v.is_finite()) {
        return Err(ReferenceError::NonFiniteReference { at });
    }
    if !mu0.is_finite() || u.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(RefError::NonFinite.into());
    }
    let k = cfg.f + cfg.p;
    // W W^T is k m × k m: twice as many columns as rows at least.
    let needed = 2 * k * cfg.m() + k - 1;
    if u.len() < needed {
        return Err(ReferenceError::TooShort {
            needed,
            got: u.len(),
        });
    }
    if r.iter().all(|&v| v == r[0]) {
        return Err(ReferenceError::ConstantReference);
    }
    Ok(u.len() - k + 1)
}

/// `C`, `A` (from `Γ_f`), `U₂ᵀ` and the singular values (divided by `√j`) of
/// `O_f = Ȳ_f^W Π⊥_{Z_f^W}`.
struct ColumnSpace {
    c: RowDVector<f64>,
    a: DMatrix<f64>,
    u2t: DMatrix<f64>,
    singular_values: Vec<f64>,
}

/// `coef` is `Ȳ_f^W Z_f^Wᵀ (Z_f^W Z_f^Wᵀ)⁻¹`.
fn column_space(
    yf_w: &DMatrix<f64>,
    zf_w: &DMatrix<f64>,
    coef: &DMatrix<f64>,
    n: usize,
) -> Result<ColumnSpace, ReferenceError> {
    let (f, j) = (yf_w.nrows(), yf_w.ncols());
    let o_f = yf_w - coef * zf_w;
    let svd = nalgebra::SVD::try_new(o_f, true, false, f64::EPSILON, 10_000)
        .ok_or(ReferenceError::NoConvergence("O_f"))?;
    let u_full = svd.u.ok_or(ReferenceError::NoConvergence("O_f"))?;
    let s = svd.singular_values;
    let sqrt_s = DMatrix::from_diagonal(&s.rows(0, n).map(f64::sqrt));
    let gamma = u_full.columns(0, n).into_owned() * sqrt_s;
    let u2t = u_full.columns(n, f - n).transpose();
    let a = least_squares(
        gamma.rows(0, f - 1).into_owned(),
        &gamma.rows(1, f - 1).into_owned(),
        "Gamma_f",
    )?;
    let sqrt_j = (j as f64).sqrt();
    Ok(ColumnSpace {
        c: gamma.row(0).into_owned(),
        a,
        u2t,
        singular_values: s.iter().map(|v| v / sqrt_j).collect(),
    })
}
