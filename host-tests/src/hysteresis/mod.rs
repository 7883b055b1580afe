//! Backlash and switch from any input: a Hammerstein model whose element is the true play
//! operator (backlash) or relay with borders (switch), fitted by simulation-error minimisation.
//!
//! The two-path model of the paper represents the element by the paths `P_a`, `P_d` travelled
//! under the Table I excitation (every run from `u_min` to `u_max` and back). An ordinary input
//! reverses inside the range, and the play operator then runs on inner loops that no pair of
//! paths describes. This model keeps the element itself:
//!
//! * [`params`]: the ascending and descending borders `H_a`, `H_d` as values at the same
//!   piecewise-linear knots as the two-path model, the linear part `G(q) = B(q)/F(q)` with
//!   `G(1) = 1` (the borders carry the scale, as in the paper's assumption A.2), and the
//!   element's initial output `w(−1)` (for a relay, the level the plant rests at).
//! * [`simulate`]: the simulator's own play operator / relay on those borders feeding `G`,
//!   which starts in the steady state of `w(−1)`.
//! * [`fit`]: the simulation error, its Jacobian by forward differences (justified there), the
//!   shared Levenberg–Marquardt from the two-path or the static subspace estimate, bounded
//!   iterations and typed errors.
//! * [`uncertainty`]: parameter standard deviations from `σ̂² (JᵀJ)⁻¹`, the poles' and the
//!   gap's by the delta method.
//! * [`gap`]: the play of a backlash model (input units) read from its borders.
//! * [`file`](mod@file): the model in the project's model file (the key `"element"`).

pub mod error;
pub mod file;
pub mod fit;
pub mod gap;
pub mod params;
pub mod servo;
pub mod simulate;
pub mod start;
pub mod uncertainty;

pub use error::HysteresisError;
pub use fit::{ElementFitOptions, HysteresisFit, fit_hysteresis, fit_hysteresis_skipping};
pub use params::{HysteresisModel, Layout};
pub use start::Start;
