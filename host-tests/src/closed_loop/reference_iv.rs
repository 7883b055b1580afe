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

use nalgebra::{DMatrix, DVector, RowDVector};

use crate::closed_loop::error::ReferenceError;
use crate::closed_loop::instruments::{PREDICTOR_LAGS, instruments, predicted_input};
use crate::closed_loop::linalg::{least_squares, project, spd_factor};
use crate::numerics::poly::eigenvalues;
use crate::reference::{RefConfig, RefError, RefModel, block_hankel, regressors};

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
    let space = column_space(&yf_w, &zf_w, cfg.order)?;
    let x_db = bold_bd(&space, &yf_w, &zf_w, cfg)?;
    let mut model = split(x_db, &space, mu0, cfg)?;
    model.j = j;
    Ok(model)
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

fn column_space(
    yf_w: &DMatrix<f64>,
    zf_w: &DMatrix<f64>,
    n: usize,
) -> Result<ColumnSpace, ReferenceError> {
    let (f, j) = (yf_w.nrows(), yf_w.ncols());
    let chol = spd_factor(zf_w * zf_w.transpose(), "the projected Z_f Z_f^T")?;
    let o_f = yf_w - chol.solve(&(zf_w * yf_w.transpose())).transpose() * zf_w;
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

/// Bold `[D; B]` (`(n + 1) × m`) from `U₂ᵀ Ξ_f(B, D) = U₂ᵀ Ȳ_f^W Z_f^Wᵀ (Z_f^W Z_f^Wᵀ)⁻¹`.
fn bold_bd(
    s: &ColumnSpace,
    yf_w: &DMatrix<f64>,
    zf_w: &DMatrix<f64>,
    cfg: &RefConfig,
) -> Result<DMatrix<f64>, ReferenceError> {
    let (f, n, m) = (cfg.f, s.a.nrows(), cfg.m());
    let q = f - n;
    let chol = spd_factor(zf_w * zf_w.transpose(), "the projected Z_f Z_f^T")?;
    let rhs_all = &s.u2t * chol.solve(&(zf_w * yf_w.transpose())).transpose();
    let mut ca = Vec::with_capacity(f);
    let mut cur = s.c.clone();
    for _ in 0..f {
        ca.push(cur.clone());
        cur = &cur * &s.a;
    }
    let mut coef = DMatrix::zeros(f * q, n + 1);
    let mut rhs = DMatrix::zeros(f * q, m);
    for jj in 0..f {
        coef.view_mut((jj * q, 0), (q, 1))
            .copy_from(&s.u2t.column(jj));
        let mut acc = DMatrix::zeros(q, n);
        for i in (jj + 1)..f {
            acc += s.u2t.column(i) * &ca[i - jj - 1];
        }
        coef.view_mut((jj * q, 1), (q, n)).copy_from(&acc);
        rhs.view_mut((jj * q, 0), (q, m))
            .copy_from(&rhs_all.view((0, jj * m), (q, m)));
    }
    least_squares(coef, &rhs, "the Xi_f system")
}

/// The rank-1 split of bold `[D; B]` (eq. 14), `γ` for `G(1) = 1`, the borders from `μ0`.
fn split(
    x_db: DMatrix<f64>,
    s: &ColumnSpace,
    mu0: f64,
    cfg: &RefConfig,
) -> Result<RefModel, ReferenceError> {
    let n = s.a.nrows();
    let d_over = x_db.rows(0, 1).into_owned();
    let b_over = x_db.rows(1, n).into_owned();
    let svd = nalgebra::SVD::try_new(x_db, true, true, f64::EPSILON, 10_000)
        .ok_or(ReferenceError::NoConvergence("[bold D; bold B]"))?;
    let uu = svd
        .u
        .ok_or(ReferenceError::NoConvergence("[bold D; bold B]"))?;
    let vt = svd
        .v_t
        .ok_or(ReferenceError::NoConvergence("[bold D; bold B]"))?;
    let s1 = svd.singular_values[0];
    let u_b: DVector<f64> = uu.column(0).rows(1, n).into_owned();
    let i_a = DMatrix::identity(n, n) - &s.a;
    let x_static = i_a.lu().solve(&u_b).ok_or(RefError::PoleAtOne)?;
    let denom = s1 * ((&s.c * x_static)[(0, 0)] + uu[(0, 0)]);
    if !(denom.is_finite() && denom.abs() > f64::MIN_POSITIVE.sqrt()) {
        return Err(RefError::ZeroStaticGain.into());
    }
    let gamma = 1.0 / denom;
    let mu: Vec<f64> = vt.row(0).iter().map(|v| v / gamma).collect();
    let (mu_asc, mu_desc) = (mu[..cfg.n_asc()].to_vec(), mu[cfg.n_asc()..].to_vec());
    Ok(RefModel {
        singular_values: s.singular_values.clone(),
        poles: eigenvalues(s.a.clone()).ok_or(RefError::EigenFailed)?,
        a: s.a.clone(),
        b: &u_b * (gamma * s1),
        c: s.c.clone(),
        d: gamma * s1 * uu[(0, 0)],
        mu0,
        border_asc: borders(&cfg.knots_asc, &mu_asc, mu0),
        border_desc: borders(&cfg.knots_desc, &mu_desc, mu0),
        mu_asc,
        mu_desc,
        b_over,
        d_over,
        knots_asc: cfg.knots_asc.clone(),
        knots_desc: cfg.knots_desc.clone(),
        j: 0,
    })
}

/// The border's values at the knots: `μ0`, then the running sum of slope × segment width.
fn borders(knots: &[f64], slopes: &[f64], mu0: f64) -> Vec<f64> {
    let mut acc = mu0;
    let mut out = vec![mu0];
    for (w, s) in knots.windows(2).zip(slopes) {
        acc += s * (w[1] - w[0]);
        out.push(acc);
    }
    out
}
