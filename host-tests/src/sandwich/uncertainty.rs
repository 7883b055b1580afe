//! The play's standard deviation: the asymptotic covariance `P = σ̂² (JᵀJ)⁻¹` of the
//! least-squares fit on the simulation error (white output noise; for coloured noise it is
//! optimistic), `σ̂² = Σe²/(N − d)`, as for the element fit
//! ([`crate::hysteresis::uncertainty`]). The Jacobian is the forward-difference one of the
//! fit, at the optimum.

use nalgebra::DMatrix;

use super::model::HALF_WIDTH;
use crate::numerics::lm::Problem;

/// The standard deviations of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Uncertainty {
    /// `σ̂²`, the residual variance.
    pub sigma2: f64,
    /// The covariance of the parameter vector
    /// ([`TwoMassPlay::theta`](super::model::TwoMassPlay::theta)).
    pub covariance: DMatrix<f64>,
    /// The play's, `2α` (the model's angle units).
    pub gap: f64,
}

impl Uncertainty {
    /// The standard deviation of parameter `j` of the vector.
    pub fn std(&self, j: usize) -> Option<f64> {
        (j < self.covariance.nrows()).then(|| self.covariance[(j, j)].max(0.0).sqrt())
    }
}

/// The standard deviations at the optimum `theta` with residual `r`; `None` when a
/// difference step does not simulate, `JᵀJ` is singular or there are no spare samples.
pub fn uncertainty(
    problem: &Problem<'_>,
    theta: &[f64],
    r: &[f64],
    typical: &[f64],
) -> Option<Uncertainty> {
    let d = theta.len();
    if r.len() <= d || typical.len() != d {
        return None;
    }
    let jac = crate::hysteresis::uncertainty::jacobian(problem, theta, r, typical)?;
    let sigma2 = r.iter().map(|v| v * v).sum::<f64>() / (r.len() - d) as f64;
    let covariance = jac.tr_mul(&jac).cholesky()?.inverse() * sigma2;
    // `α` enters by its magnitude, so its variance is the parameter's.
    let gap = 2.0 * covariance[(HALF_WIDTH, HALF_WIDTH)].max(0.0).sqrt();
    Some(Uncertainty {
        sigma2,
        covariance,
        gap,
    })
}
