//! How a structure is fitted: the initial state, the options, the output's saturation.

use serde::Serialize;

use crate::identify::IdentifyOptions;
pub use crate::validation::checks::Saturation;

/// How the simulation of a record starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialState {
    /// At rest at `u_min` (as after the identification hold).
    Rest,
    /// At rest at a level fitted by least squares on the estimation record (the state
    /// `(I − A)⁻¹ B c`, one parameter `c`); every record simulated starts from it (for records
    /// that do not start at rest at `u_min`, assumed to start alike).
    Estimated,
}

/// Everything the fit needs besides the structure and the data.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The base identification options (knots, horizons, hold, μ0, static or not; the order
    /// here is the base order, overridden by [`Structure::order`](super::structure::Structure::order)).
    pub identify: IdentifyOptions,
    /// Initial state of simulations.
    pub initial: InitialState,
    /// Centre of the time axis for the polynomial trend (samples).
    pub time_center: f64,
    /// Half-width of the time axis for the polynomial trend (samples).
    pub time_scale: f64,
    /// MAD rule threshold for outliers, in robust standard deviations.
    pub outlier_k: f64,
    /// Backfitting rounds when the structure has more than the Hammerstein part.
    pub rounds: usize,
    /// Refit the border values (and μ0, and the initial state when estimated) by least squares
    /// on the output with `A, B, C, D` fixed (the paper's Remark 5), after the subspace step.
    pub refit: bool,
    /// Refine the poles too: the characteristic polynomial of `A` by Levenberg–Marquardt on the
    /// simulation error, the rest (`B`, `D`, borders, μ0, initial level) by least squares for
    /// every candidate (variable projection). With an output map, the poles are refined by a
    /// bounded simplex search with the borders, `B`, `D` and the map refit for every candidate.
    pub refine_poles: bool,
    /// Saturation levels of the output (from the data checks): the output map is clipped there.
    pub saturation: Saturation,
}
