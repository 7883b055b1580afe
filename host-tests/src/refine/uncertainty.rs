//! Standard deviations of the poles, the Bode magnitude and the border values, from the
//! refinement's asymptotic covariance `P = σ̂² (JᵀJ)⁻¹` mapped through first derivatives
//! (the delta method): `std(g(θ̂)) = √(∇g P ∇gᵀ)`.
//!
//! * Poles: a simple root `z` of `zⁿ + f₁zⁿ⁻¹ + … + f_n` moves by `∂z/∂f_i = −z^{n−i}/F'(z)`;
//!   the real and imaginary parts give a 2 × 2 covariance per pole.
//! * Bode magnitude: with `b₀ = F(1) − Σb_i`, `∂G/∂b_i = (e^{−jωi} − 1)/F(e^{jω})` and
//!   `∂G/∂f_i = (1 − e^{−jωi} G)/F`, and `∂(20 log₁₀|G|) = (20/ln 10) Re(Ḡ ∂G)/|G|²`.
//! * Borders: the border values at the knots are parameters; between knots the border is the
//!   linear interpolation, a linear map of them.

use nalgebra::{Complex, DMatrix};

use super::pem::{ParamLayout, PemFit};
use super::poly::{eval_w, root_sensitivity, roots};
use crate::identify::interpolate;

/// A pole with its standard deviation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoleStd {
    /// The pole `(re, im)`.
    pub pole: (f64, f64),
    /// Standard deviations of the real and imaginary parts.
    pub std: (f64, f64),
    /// Covariance of `(re, im)`.
    pub cov: [[f64; 2]; 2],
}

/// Poles of `den` (monic, `[1, f₁ …]`) with the covariance of `f₁ … f_n` mapped onto them.
pub fn pole_std(den: &[f64], cov_f: &DMatrix<f64>) -> Vec<PoleStd> {
    let Some(r) = roots(den) else {
        return Vec::new();
    };
    let n = den.len() - 1;
    r.into_iter()
        .map(|(re, im)| {
            let s = root_sensitivity(den, Complex::new(re, im));
            let jr: Vec<f64> = s.iter().map(|c| c.re).collect();
            let ji: Vec<f64> = s
                .iter()
                .map(|c| if im == 0.0 { 0.0 } else { c.im })
                .collect();
            let quad = |a: &[f64], b: &[f64]| {
                let mut acc = 0.0;
                for i in 0..n {
                    for j in 0..n {
                        acc += a[i] * cov_f[(i, j)] * b[j];
                    }
                }
                acc
            };
            let (rr, ii, ri) = (quad(&jr, &jr), quad(&ji, &ji), quad(&jr, &ji));
            PoleStd {
                pole: (re, im),
                std: (rr.max(0.0).sqrt(), ii.max(0.0).sqrt()),
                cov: [[rr, ri], [ri, ii]],
            }
        })
        .collect()
}

/// The sub-block of `P` for the index ranges `rows` (as a dense matrix).
fn block(p: &DMatrix<f64>, idx: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(idx.len(), idx.len(), |i, j| p[(idx[i], idx[j])])
}

/// The poles of a refined model with their standard deviations.
pub(crate) fn fit_poles(fit: &PemFit) -> Vec<PoleStd> {
    let l = fit.layout;
    let p = l.polynomials(&fit.theta);
    let idx: Vec<usize> = l.f().collect();
    pole_std(&p.f, &block(&fit.covariance, &idx))
}

/// The pole in the upper half plane (largest imaginary part) with its standard deviation.
pub fn upper_pole(fit: &PemFit) -> Option<PoleStd> {
    fit_poles(fit)
        .into_iter()
        .max_by(|a, b| a.pole.1.total_cmp(&b.pole.1))
}

/// Gradient of `|G(e^{jω})|` in dB with respect to the plant parameters `(f, b)`, and the
/// value.
pub(crate) fn bode_db_gradient(l: &ParamLayout, theta: &[f64], w: f64) -> (f64, Vec<f64>) {
    let p = l.polynomials(theta);
    let fz = eval_w(&p.f, w);
    let g = eval_w(&p.b, w) / fz;
    let mag2 = g.norm_sqr();
    let k = 20.0 / std::f64::consts::LN_10;
    let mut grad = Vec::with_capacity(l.n + l.nb());
    let ph = |i: usize| Complex::new((-w * i as f64).cos(), (-w * i as f64).sin());
    let pe = ph(l.eliminated());
    for i in 1..=l.n {
        let dg = (pe - ph(i) * g) / fz;
        grad.push(k * (g.conj() * dg).re / mag2);
    }
    for i in 1..=l.nb() {
        let dg = (ph(i) - pe) / fz;
        grad.push(k * (g.conj() * dg).re / mag2);
    }
    (10.0 * mag2.log10(), grad)
}

/// `|G(e^{jω})|` in dB and its standard deviation at every `ω`.
pub fn bode_db_std(fit: &PemFit, w: &[f64]) -> Vec<(f64, f64)> {
    let l = fit.layout;
    let idx: Vec<usize> = l.f().chain(l.b()).collect();
    let pb = block(&fit.covariance, &idx);
    w.iter()
        .map(|&x| {
            let (db, g) = bode_db_gradient(&l, &fit.theta, x);
            let gv = nalgebra::DVector::from_column_slice(&g);
            let var = (gv.transpose() * &pb * &gv)[(0, 0)];
            (db, var.max(0.0).sqrt())
        })
        .collect()
}

/// Standard deviations of the border values at the knots: `(ascending, descending)`, each
/// starting with μ0's.
pub fn border_std(fit: &PemFit) -> (Vec<f64>, Vec<f64>) {
    let l = fit.layout;
    let b0 = l.beta().start;
    let sd = |i: usize| fit.covariance[(b0 + i, b0 + i)].max(0.0).sqrt();
    let na = fit.model.border_asc.len().saturating_sub(1);
    let nd = fit.model.border_desc.len().saturating_sub(1);
    let asc = (0..=na).map(&sd).collect();
    let off = if l.shared { 0 } else { na };
    let desc = std::iter::once(sd(0))
        .chain((1..=nd).map(|i| sd(off + i)))
        .collect();
    (asc, desc)
}

/// The covariance of the border values at the knots, ascending then descending (each path
/// starting with μ0's value, as [`border_std`] orders them): the block of the refinement's
/// parameter covariance of the hat coefficients they are, correlations included.
pub fn border_covariance(fit: &PemFit) -> DMatrix<f64> {
    let l = fit.layout;
    let b0 = l.beta().start;
    let na = fit.model.border_asc.len().saturating_sub(1);
    let nd = fit.model.border_desc.len().saturating_sub(1);
    let off = if l.shared { 0 } else { na };
    let index: Vec<usize> = (0..=na)
        .chain(std::iter::once(0))
        .chain((1..=nd).map(|i| off + i))
        .collect();
    DMatrix::from_fn(index.len(), index.len(), |i, j| {
        fit.covariance[(b0 + index[i], b0 + index[j])]
    })
}

/// Standard deviation of the interpolated border of one path on a grid of inputs.
/// `indices[i]` is the position in `β` of the value at knot `i`.
fn path_std_on_grid(fit: &PemFit, knots: &[f64], indices: &[usize], grid: &[f64]) -> Vec<f64> {
    let b0 = fit.layout.beta().start;
    grid.iter()
        .map(|&u| {
            // Interpolation weights: interpolate unit vectors.
            let w: Vec<f64> = (0..knots.len())
                .map(|i| {
                    let mut e = vec![0.0; knots.len()];
                    e[i] = 1.0;
                    interpolate(knots, &e, u)
                })
                .collect();
            let mut var = 0.0;
            for (i, wi) in w.iter().enumerate() {
                if *wi == 0.0 {
                    continue;
                }
                for (j, wj) in w.iter().enumerate() {
                    var += wi * wj * fit.covariance[(b0 + indices[i], b0 + indices[j])];
                }
            }
            var.max(0.0).sqrt()
        })
        .collect()
}

/// Standard deviations of `P_a(u)` and `P_d(u)` on a grid.
pub(crate) fn border_std_on_grid(fit: &PemFit, grid: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let na = fit.model.knots_asc.len().saturating_sub(1);
    let nd = fit.model.knots_desc.len().saturating_sub(1);
    let ia: Vec<usize> = (0..=na).collect();
    let off = if fit.layout.shared { 0 } else { na };
    let id: Vec<usize> = std::iter::once(0)
        .chain((1..=nd).map(|i| off + i))
        .collect();
    (
        path_std_on_grid(fit, &fit.model.knots_asc, &ia, grid),
        path_std_on_grid(fit, &fit.model.knots_desc, &id, grid),
    )
}
