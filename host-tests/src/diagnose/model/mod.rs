//! The extended model: the paper's Hammerstein model plus the catalog's extensions, fitted
//! together on the estimation data by backfitting.
//!
//! ```text
//! y(t) = g( G(q) H[u(t − d)] ) + trend(t) + Σ_k (a_k cos ω_k t + b_k sin ω_k t) + v(t)
//! v(t) = Σ_i c_i v(t − i) + e(t)                      (noise model, for prediction)
//! ```
//!
//! * `d` (`input_delay`) shifts the input before the Hammerstein model,
//! * the order of `G` (`unmodeled_dynamics`) is passed to the subspace identification,
//! * `g` (`output_nonlinearity`) is a monotone piecewise-linear output map on knots at
//!   quantiles of the Hammerstein output (a Hammerstein–Wiener model), fitted by non-negative
//!   least squares on its increments,
//! * `trend` (`offset_drift`) is a polynomial in time, the sinusoids (`periodic_disturbance`)
//!   have fixed frequencies and least-squares amplitudes,
//! * the AR noise model (`colored_noise`) gives one-step-ahead predictions,
//! * `hysteresis`: the element itself — the play operator (backlash) or the relay with
//!   borders (switch) on the knots — and `G`, fitted by simulation error from the static or
//!   two-path subspace estimate ([`element`]), replace the Hammerstein part's simulation, so
//!   inputs that reverse inside the range (inner loops) are represented; on an output pinned
//!   at a level, `g` with the element is the output saturation alone (the identity with flat
//!   ends at the pinned levels), `G` and the borders fitted through it,
//! * `friction`: Coulomb friction and an offset on the output's velocity fed back into `G`'s
//!   input ([`friction`]),
//! * `play_between`: the two-mass drive with gear play between motor and load, driven by the
//!   static output and fitted from `G`'s poles, in place of `G` and any element
//!   ([`two_mass`]),
//! * `outliers`: samples flagged by the MAD rule are replaced, in the identification target,
//!   by the model's own output (robust re-estimation), and left out of the error.
//!
//! Backfitting: the Hammerstein part is identified on `g⁻¹(y − additive)` (flagged samples and
//! samples on a flat part of `g` imputed from the previous iterate), then `g` is fitted from the
//! simulated Hammerstein output to `y − additive`, then the additive terms to `y − g(·)`, then
//! the outliers are flagged again; three rounds.
//!
//! The Hammerstein part is the open-loop subspace estimate, or, for a record that carries the
//! controller's reference, the closed-loop consistent estimate ([`estimator`]).

pub mod additive;
pub mod borders;
pub mod element;
pub mod estimator;
pub mod evaluate;
pub mod extended;
pub mod fit;
pub mod fit_options;
pub mod friction;
pub mod outliers;
pub mod output_fit;
pub mod poles;
pub mod refine_linear;
pub mod structure;
pub mod two_mass;

pub use additive::Additive;
pub use borders::{BorderBasis, refit_borders};
pub use estimator::Estimator;
pub use evaluate::{Evaluation, Metric, evaluate};
pub use extended::ExtendedModel;
pub use fit::{fit_structure, fit_structure_fold};
pub use fit_options::{FitOptions, InitialState, Saturation};
pub use outliers::detect_outliers;
pub use structure::{Dynamics, Structure};
