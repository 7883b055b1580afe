//! Where the ±2σ bands and ellipses come from: a refined fit's parameter covariance (first-order
//! propagation, the delta method) or the standard deviations stored in a model file.

use nalgebra::{Complex, DMatrix, DVector};

use crate::identify::{HostModel, interpolate};
use crate::model_file::ModelFile;
use crate::numerics::poly::eval_w;
use crate::refine::pem::PemFit;
use crate::refine::uncertainty::{border_covariance, border_std_on_grid, fit_poles};

/// Covariance of `(re, im)` of a pole.
pub(crate) type Cov2 = [[f64; 2]; 2];

/// The source of a model's uncertainty.
#[derive(Debug, Clone, Copy)]
pub enum UncertaintySource<'a> {
    /// A refined fit with its asymptotic parameter covariance `P = σ̂² (JᵀJ)⁻¹`: bands for the
    /// borders, the Bode magnitude and phase, and 2σ ellipses of the poles, all by first-order
    /// propagation of `P` (correlations included).
    Refined(&'a PemFit),
    /// A model file with standard deviations (`std`): borders and poles only, since the file
    /// keeps no covariance. Between knots the border band interpolates the knots' standard
    /// deviations (an upper bound of the interpolated border's); pole ellipses have their axes
    /// along the real and imaginary directions (the correlation is not stored).
    Stored(&'a ModelFile),
}

impl<'a> UncertaintySource<'a> {
    /// The stored standard deviations of a model file, if it has them.
    pub fn from_file(file: &'a ModelFile) -> Option<Self> {
        file.std.as_ref().map(|_| Self::Stored(file))
    }

    /// One sentence for captions and the documentation.
    pub fn describe(&self) -> &'static str {
        match self {
            Self::Refined(_) => {
                "±2σ from the refinement's parameter covariance, first-order propagation"
            }
            Self::Stored(_) => "±2σ from the standard deviations stored in the model file",
        }
    }

    /// Standard deviations of `P_a(u)` and `P_d(u)` on `grid`.
    pub fn border_std(&self, model: &HostModel, grid: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        match self {
            Self::Refined(fit) => Some(border_std_on_grid(fit, grid)),
            Self::Stored(file) => {
                let std = file.std.as_ref()?;
                let on = |knots: &[f64], s: &[f64]| -> Vec<f64> {
                    grid.iter().map(|&u| interpolate(knots, s, u)).collect()
                };
                Some((
                    on(&model.knots_asc, &std.border_asc),
                    on(&model.knots_desc, &std.border_desc),
                ))
            }
        }
    }

    /// The covariance of `model`'s border values, `border_asc` then `border_desc`: the
    /// refinement's block, correlations included, or the one a model file's standard
    /// deviations give ([`HostModel::border_covariance_of_std`]).
    pub fn border_covariance(&self, model: &HostModel) -> Option<DMatrix<f64>> {
        match self {
            Self::Refined(fit) => Some(border_covariance(fit)),
            Self::Stored(file) => model.border_covariance_of_std(file.std.as_ref()?),
        }
    }

    /// The 2 × 2 covariance of `(re, im)` of each pole in `poles` (each paired with the
    /// nearest pole of the source).
    pub(crate) fn pole_covariances(&self, poles: &[(f64, f64)]) -> Option<Vec<Cov2>> {
        let known: Vec<((f64, f64), Cov2)> = match self {
            Self::Refined(fit) => fit_poles(fit).iter().map(|p| (p.pole, p.cov)).collect(),
            Self::Stored(file) => {
                let std = file.std.as_ref()?;
                file.poles
                    .iter()
                    .zip(&std.poles)
                    .map(|(p, s)| ((p[0], p[1]), [[s[0] * s[0], 0.0], [0.0, s[1] * s[1]]]))
                    .collect()
            }
        };
        poles
            .iter()
            .map(|&(re, im)| {
                let d = |p: (f64, f64)| (p.0 - re).hypot(p.1 - im);
                known
                    .iter()
                    .min_by(|a, b| d(a.0).total_cmp(&d(b.0)))
                    .map(|k| k.1)
            })
            .collect()
    }

    /// Standard deviations of the Bode magnitude (dB) and phase (deg) at each `w`
    /// (rad/sample); only a refined fit has the covariance they need.
    pub(crate) fn bode_std(&self, w: &[f64]) -> Option<Vec<(f64, f64)>> {
        match self {
            Self::Refined(fit) => Some(bode_std(fit, w)),
            Self::Stored(_) => None,
        }
    }
}

/// `G(e^{jω}) = B(e^{−jω}) / F(e^{−jω})` of the parameter vector `theta`.
fn response(fit: &PemFit, theta: &[f64], w: f64) -> Complex<f64> {
    let p = fit.layout.polynomials(theta);
    eval_w(&p.b, w) / eval_w(&p.f, w)
}

/// First-order propagation: the derivative of `G` with respect to each plant parameter by
/// central differences, then `∂ dB = (20/ln 10) Re(Ḡ ∂G)/|G|²`, `∂ phase = Im(∂G / G)`, and
/// `var = ∇ᵀ P ∇` with the plant block of the covariance.
fn bode_std(fit: &PemFit, w: &[f64]) -> Vec<(f64, f64)> {
    let l = fit.layout;
    let idx: Vec<usize> = l.f().chain(l.b()).collect();
    let p = DMatrix::from_fn(idx.len(), idx.len(), |i, j| {
        fit.covariance[(idx[i], idx[j])]
    });
    let k_db = 20.0 / std::f64::consts::LN_10;
    w.iter()
        .map(|&x| {
            let g = response(fit, &fit.theta, x);
            let mut grad_db = DVector::zeros(idx.len());
            let mut grad_ph = DVector::zeros(idx.len());
            for (i, &k) in idx.iter().enumerate() {
                let h = 1e-6 * fit.theta[k].abs().max(1.0);
                let mut up = fit.theta.clone();
                up[k] += h;
                let mut down = fit.theta.clone();
                down[k] -= h;
                let dg = (response(fit, &up, x) - response(fit, &down, x)) / (2.0 * h);
                grad_db[i] = k_db * (g.conj() * dg).re / g.norm_sqr();
                grad_ph[i] = (dg / g).im.to_degrees();
            }
            let var = |v: &DVector<f64>| (v.transpose() * &p * v)[(0, 0)].max(0.0).sqrt();
            (var(&grad_db), var(&grad_ph))
        })
        .collect()
}
