//! Shared numerics of the host: one implementation per operation, below every analysis that
//! uses them (refinement, paper evaluation, simulation, diagnosis).
//!
//! * [`lm`]: Levenberg–Marquardt with forward-difference Jacobians, settings and a typed failure;
//! * [`lstsq`]: linear least squares through the (optionally equilibrated) normal equations;
//! * [`ar`]: autoregressive noise models and their order by BIC;
//! * [`select`]: the information criteria and the choice of the best candidate;
//! * [`poly`]: polynomials in `q⁻¹`, their roots, and the observer form;
//! * [`direction`]: the paper's direction signal δ(t) through the core's [`hsid::Direction`];
//! * [`hat`]: the hat basis on a knot sequence (segment and weights of an input).

pub mod ar;
pub mod direction;
pub mod hat;
pub mod lm;
pub mod lstsq;
pub mod poly;
pub mod select;
