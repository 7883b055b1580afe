//! Shared numerics of the host: one implementation per operation, below every analysis that
//! uses them (refinement, paper evaluation, simulation, diagnosis).
//!
//! * [`lm`]: Levenberg–Marquardt with forward-difference Jacobians, settings and a typed failure;
//! * [`lstsq`]: linear least squares through the (optionally equilibrated) normal equations;
//! * [`ar`]: autoregressive noise models and their order by BIC;
//! * [`select`]: the information criteria and the choice of the best candidate;
//! * [`poly`]: polynomials in `q⁻¹`, their roots, and the observer form;
//! * [`direction`]: the paper's direction signal δ(t) through the core's [`hsid::Direction`];
//! * [`spectrum`]: the numerical rank and extreme eigenvalues of a Gram matrix;
//! * [`hat`]: the hat basis on a knot sequence (segment and weights of an input);
//! * [`rms`], [`rms_error`]: the root mean square of a signal and of a difference of two.

pub mod ar;
pub mod direction;
pub mod hat;
pub mod lm;
pub mod lstsq;
pub mod poly;
pub mod select;
pub mod spectrum;

/// The root mean square of `x`, `sqrt(Σ x² / n)`; 0 for an empty slice.
pub fn rms(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// The root mean square of the difference `a − b` over the pairs of samples ([`rms`] of the
/// differences); 0 when there are none.
pub fn rms_error(a: &[f64], b: &[f64]) -> f64 {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    rms(&d)
}
