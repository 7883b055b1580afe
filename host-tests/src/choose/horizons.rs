//! The horizons `f` and `p` from the record when the user gives none.
//!
//! The rule: identify once at the paper's `f = p = 10`, read the slowest pole `ρ` of that
//! model, and give the past horizon the plant's memory — the samples its impulse response takes
//! to fall to 5 % (`ln 0.05 / ln ρ`) — within `[10, 40]`, and `f = p`. PI-MOESP's instruments
//! are the past `p` inputs: the part of the state they do not explain decays as `ρ^p`, so a
//! slow plant at a short past horizon leaves a bias the paper's `f = p = 10` cannot remove (a
//! pole at 0.97 keeps 74 % of its memory after 10 samples, 30 % after 40). The upper bound
//! keeps the Gram's rows (`(p + f) · (channels + 1)`) below the columns of a few thousand
//! samples; with fewer samples the horizons shrink so that there are at least
//! [`COLUMNS_PER_ROW`] columns per row (the subspace model is only the refinement's start,
//! so a loose ratio is enough).

use crate::identify::{HostModel, IdentifyOptions};

/// The smallest horizon chosen.
pub const MIN_HORIZON: usize = 10;
/// The largest horizon chosen.
pub const MAX_HORIZON: usize = 40;
/// The part of the impulse response the past horizon must cover: it ends where the slowest
/// mode has fallen to this fraction.
pub const MEMORY_LEVEL: f64 = 0.05;
/// Columns of the data matrices per row of the Gram, at least.
pub const COLUMNS_PER_ROW: usize = 4;

/// The horizons chosen and why.
#[derive(Clone, Debug, PartialEq)]
pub struct HorizonChoice {
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
    /// The slowest pole's modulus of the first model.
    pub slowest: f64,
    /// The plant's memory in samples (to [`MEMORY_LEVEL`]).
    pub memory: f64,
    /// The bound the record's length puts on `f = p`.
    pub record_bound: usize,
}

impl HorizonChoice {
    /// One line for a report.
    pub fn report(&self) -> String {
        format!(
            "horizons f = p = {} chosen from the data: slowest pole {:.4} of the f = p = 10 model, \
             memory to {:.0} % in {:.0} samples, bounds [{MIN_HORIZON}, {}]",
            self.f,
            self.slowest,
            100.0 * MEMORY_LEVEL,
            self.memory,
            MAX_HORIZON.min(self.record_bound)
        )
    }
}

/// The horizons for a record of `samples` samples (after the hold) whose first model is
/// `first`, for the channels of `opts`.
pub fn choose_horizons(first: &HostModel, opts: &IdentifyOptions, samples: usize) -> HorizonChoice {
    let slowest = first.spectral_radius();
    let memory = if slowest > 0.0 && slowest < 1.0 {
        MEMORY_LEVEL.ln() / slowest.ln()
    } else {
        f64::INFINITY
    };
    let segments = |k: &[f64]| k.len().saturating_sub(1);
    let channels = segments(&opts.knots_asc)
        + if opts.static_nonlinearity {
            0
        } else {
            segments(&opts.knots_desc)
        };
    let rows_per_lag = channels + 1;
    // 2h rows, j ≈ samples columns: j ≥ COLUMNS_PER_ROW · 2h · rows_per_lag.
    let record_bound = samples / (COLUMNS_PER_ROW * 2 * rows_per_lag);
    let hi = MAX_HORIZON.min(record_bound).max(MIN_HORIZON);
    // `as` saturates: an unbounded memory gives `hi`.
    let h = (memory.ceil() as usize).clamp(MIN_HORIZON, hi);
    HorizonChoice {
        f: h,
        p: h,
        slowest,
        memory,
        record_bound,
    }
}
