//! Standard deviations of the fitted parameters, the poles and the gap: the asymptotic
//! covariance `P = σ̂² (JᵀJ)⁻¹` of a least-squares fit on the simulation error (white output
//! noise; for coloured noise it is optimistic), `σ̂² = Σe²/(N − d)`, mapped by the delta
//! method. The poles use the refinement's [`pole_std`].

use nalgebra::{DMatrix, DVector};

use super::params::{HysteresisModel, Layout};
use crate::numerics::lm::{Jacobian, Problem};
use crate::refine::uncertainty::{PoleStd, pole_std};

/// The standard deviations of a fit.
#[derive(Clone, Debug)]
pub struct Uncertainty {
    /// `σ̂²`, the residual variance.
    pub sigma2: f64,
    /// The covariance of `θ`.
    pub covariance: DMatrix<f64>,
    /// `H_a` at the knots.
    pub border_asc: Vec<f64>,
    /// `H_d` at the knots.
    pub border_desc: Vec<f64>,
    /// `w(−1)`.
    pub w0: f64,
    /// The poles with theirs.
    pub poles: Vec<PoleStd>,
    /// The gap's (backlash with a gap).
    pub gap: Option<f64>,
}

/// The forward-difference Jacobian of `problem` at `theta` (`None` if a step does not
/// simulate): steps of `10⁻⁶` of each parameter's size or its `typical` size.
pub(crate) fn jacobian(
    problem: &Problem<'_>,
    theta: &[f64],
    r: &[f64],
    typical: &[f64],
) -> Option<DMatrix<f64>> {
    if let Jacobian::Analytic(j) = problem.jacobian {
        return Some(j(theta));
    }
    let mut jac = DMatrix::<f64>::zeros(r.len(), theta.len());
    for j in 0..theta.len() {
        let step = 1e-6 * theta[j].abs().max(typical[j]);
        let mut t = theta.to_vec();
        t[j] += step;
        let rj = (problem.residual)(&t)?;
        for (i, (a, b)) in rj.iter().zip(r).enumerate() {
            jac[(i, j)] = (a - b) / step;
        }
    }
    Some(jac)
}

/// The standard deviations at the optimum `theta` with residual `r`, of which `used` samples
/// count (the others are left out of the error and are 0 in `r`); `None` when `JᵀJ` is
/// singular (a parameter the data do not determine) or there are no spare samples.
pub fn uncertainty(
    problem: &Problem<'_>,
    layout: &Layout,
    theta: &[f64],
    r: &[f64],
    used: usize,
    typical: &[f64],
) -> Option<Uncertainty> {
    let d = theta.len();
    if used <= d {
        return None;
    }
    let jac = jacobian(problem, theta, r, typical)?;
    let sigma2 = r.iter().map(|v| v * v).sum::<f64>() / (used - d) as f64;
    let inv = jac.tr_mul(&jac).cholesky()?.inverse();
    let cov = inv * sigma2;
    let sd = |i: usize| cov[(i, i)].max(0.0).sqrt();
    let lin = layout.linear();
    let f_idx: Vec<usize> = lin.f().collect();
    let cov_f = DMatrix::from_fn(f_idx.len(), f_idx.len(), |i, j| cov[(f_idx[i], f_idx[j])]);
    let knots_model = HysteresisModel::from_theta(layout, &vec![0.0; layout.knots], theta);
    Some(Uncertainty {
        sigma2,
        border_asc: layout.asc().map(sd).collect(),
        border_desc: layout.desc().map(sd).collect(),
        w0: sd(layout.w0()),
        poles: pole_std(&knots_model.f, &cov_f),
        gap: None,
        covariance: cov,
    })
}

impl Uncertainty {
    /// Adds the gap's standard deviation ([`std_of`](Self::std_of) [`HysteresisModel::gap`]).
    pub(crate) fn with_gap(mut self, layout: &Layout, model: &HysteresisModel) -> Self {
        self.gap = self.std_of(layout, model, HysteresisModel::gap);
        self
    }

    /// The standard deviation of `f(model)` to first order: the gradient of `f` with respect
    /// to the border values by central differences, through their covariance. `None` when a
    /// step leaves `f` undefined.
    pub fn std_of(
        &self,
        layout: &Layout,
        model: &HysteresisModel,
        f: impl Fn(&HysteresisModel) -> Option<f64>,
    ) -> Option<f64> {
        let th = model.theta(layout);
        let idx: Vec<usize> = layout.asc().chain(layout.desc()).collect();
        let h = 1e-6 * th.iter().fold(1e-3f64, |m, v| m.max(v.abs()));
        let grad: Option<Vec<f64>> = idx
            .iter()
            .map(|&i| {
                let at = |s: f64| {
                    let mut t = th.clone();
                    t[i] += s;
                    f(&HysteresisModel::from_theta(layout, &model.knots, &t))
                };
                Some((at(h)? - at(-h)?) / (2.0 * h))
            })
            .collect();
        grad.map(|g| {
            let g = DVector::from_vec(g);
            let p = DMatrix::from_fn(idx.len(), idx.len(), |i, j| {
                self.covariance[(idx[i], idx[j])]
            });
            (g.transpose() * p * g)[(0, 0)].max(0.0).sqrt()
        })
    }
}
