//! Typed errors: every way the identification can fail says what was wrong and what to change.

use core::fmt;

use crate::direction::Direction;

/// Which measured signal a per-sample fault concerns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Signal {
    /// The actuator command `u`.
    Input,
    /// The measured output `y`.
    Output,
}

/// An end of the knot vectors: the first knot (`u_min`) or the last (`u_max`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum KnotEnd {
    /// The first knot, `u_min`.
    First,
    /// The last knot, `u_max`.
    Last,
}

impl fmt::Display for KnotEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            KnotEnd::First => "first (u_min)",
            KnotEnd::Last => "last (u_max)",
        })
    }
}

/// What breaks the Gram's shift structure that the structured solve
/// ([`Identifier::solve_structured`](crate::Identifier::solve_structured)) relies on: its rows
/// must be lags of one sequence with equal weights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ShiftBreak {
    /// The rows are centred on their own means (μ0 estimated, `MuZero::Estimate`).
    Centred,
    /// Old samples are forgotten (a forgetting factor below 1).
    Forgetting,
    /// The weighting's instruments hold past outputs (only PI-MOESP's do not).
    PastOutputs,
}

impl fmt::Display for ShiftBreak {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ShiftBreak::Centred => "rows centred on their means (mu0 estimated)",
            ShiftBreak::Forgetting => "a forgetting factor below 1",
            ShiftBreak::PastOutputs => {
                "past outputs among the instruments (a weighting other than PI-MOESP)"
            }
        })
    }
}

/// The step of the solve an error comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Stage {
    /// The accumulated sums: the Gram of `[Z_f; Z_p; Ȳ_p; Ȳ_f]` and its Schur complement.
    Sums,
    /// Cholesky factor of the Gram of the input Hankel matrices `[Z_f; Z_p]`.
    InputHankel,
    /// SVD of the projection `O_f` (eq. 11).
    Projection,
    /// The CVA weighting `(Ȳ_f Π⊥ Ȳ_fᵀ)^{-1/2}`.
    CvaWeighting,
    /// Shift invariance for `A`.
    ShiftInvariance,
    /// Least squares for `[D; B]`.
    InputMatrices,
    /// Rank-1 split of `[D; B]` (eq. 14).
    RankOneSplit,
    /// `(I - A)` for the static gain.
    StaticGain,
}

/// What is wrong with a checkpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CheckpointError {
    /// The buffer is shorter than the checkpoint (truncated), or too small to save into.
    Truncated,
    /// Not a checkpoint (wrong magic).
    NotACheckpoint,
    /// Written by another format version.
    Version,
    /// Written with another scalar type (`f32` vs `f64`).
    ScalarType,
    /// The checksum does not match: the data are corrupted.
    Checksum,
    /// The settings differ from the ones expected (fingerprint mismatch).
    SettingsMismatch,
    /// The checkpoint needs more channels or block rows than this identifier's capacity.
    Capacity,
    /// A field holds an impossible value.
    Invalid,
    /// Written with the other summation (plain vs compensated sums): restore it into an
    /// identifier of the same [`Summation`](crate::Summation) type.
    Summation,
}

/// Everything that can go wrong, from configuration to the final solve.
///
/// Values are reported as `f64` whatever the scalar type, so that messages are comparable.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// `u_min` must be finite and strictly less than `u_max`.
    InvalidInterval {
        /// Lower end given.
        u_min: f64,
        /// Upper end given.
        u_max: f64,
    },
    /// A knot vector has fewer than two knots (one segment).
    TooFewKnots {
        /// The path concerned.
        path: Direction,
        /// Number of knots given.
        count: usize,
    },
    /// Knots must be finite and strictly increasing.
    KnotsNotIncreasing {
        /// The path concerned.
        path: Direction,
        /// Index of the first knot that is not larger than its predecessor (or not finite).
        index: usize,
    },
    /// Both paths must start at `u_min` and end at `u_max`: their first knots, or their last
    /// knots, differ.
    KnotEndpoints {
        /// Which end differs: the first knots (`u_min`) or the last knots (`u_max`).
        end: KnotEnd,
        /// The ascending path's knot at that end.
        ascending: f64,
        /// The descending path's knot at that end.
        descending: f64,
    },
    /// The segment counts of the two paths must add up to at most the type's capacity `M`.
    SegmentCount {
        /// `M`, the channel capacity of the type.
        expected: usize,
        /// Ascending segments given.
        ascending: usize,
        /// Descending segments given.
        descending: usize,
    },
    /// Horizons: `2 <= f <= H`, `p >= 1` and `f + p <= K`, within the identifier's horizon
    /// capacity `H` and block-row capacity `K`.
    InvalidHorizon {
        /// Future horizon requested.
        f: usize,
        /// Block rows `f + p` requested.
        k: usize,
        /// Largest `f` the type holds: its horizon capacity `H`.
        max_f: usize,
        /// Largest `f + p` the type holds: its block-row capacity `K`.
        max_k: usize,
    },
    /// The instruments (`p·m` rows of past inputs, plus `p` rows of past outputs for the
    /// weightings that use them) must have at least `f` rows: the SVD that gives `Γ_f` is of
    /// an `f × rows` matrix.
    TooFewInstruments {
        /// Future horizon `f`.
        f: usize,
        /// Past horizon `p`.
        p: usize,
        /// Regressor channels `m` (segments of both paths).
        channels: usize,
        /// Whether past outputs are among the instruments (every weighting but PI-MOESP).
        past_outputs: bool,
    },
    /// The requested model order must satisfy `1 <= n < f`.
    InvalidOrder {
        /// Order requested.
        order: usize,
        /// Future horizon.
        f: usize,
    },
    /// The hold at `u_min` must be longer than the samples skipped while the plant settles.
    HoldTooShort {
        /// Hold length in samples.
        len: usize,
        /// Samples skipped at its start.
        settle: usize,
    },
    /// A sample of the hold was not at `u_min`.
    HoldNotAtMin {
        /// Index of the sample (0 = first sample pushed).
        index: u64,
        /// The input value found.
        value: f64,
    },
    /// The known μ0 ([`MuZero::Known`](crate::MuZero::Known)) is NaN or infinite.
    InvalidMu0 {
        /// The value given.
        value: f64,
    },
    /// A sample was NaN or infinite.
    NonFinite {
        /// Index of the sample (0 = first sample pushed).
        index: u64,
        /// Which signal.
        signal: Signal,
    },
    /// An input sample lies outside `[u_min, u_max]`.
    InputOutOfRange {
        /// Index of the sample (0 = first sample pushed).
        index: u64,
        /// The value found.
        value: f64,
    },
    /// Not enough samples for the Hankel sizes.
    TooFewSamples {
        /// Samples accumulated after the hold.
        have: u64,
        /// Samples needed.
        need: u64,
    },
    /// A regressor channel was never excited: the path never visited that knot's segments.
    NoExcitation {
        /// The path concerned.
        path: Direction,
        /// Knot index (1-based, as in the paper's `P_i`) whose basis function stayed zero.
        knot: usize,
    },
    /// The data are rank deficient at the given stage.
    RankDeficient {
        /// Where.
        stage: Stage,
    },
    /// A sum or product overflowed the scalar type (e.g. `y²` above `f32::MAX` for outputs
    /// near 1e20): the accumulated statistics are not finite.
    Overflow {
        /// Where it was detected.
        stage: Stage,
    },
    /// An iterative step (SVD) did not converge within its iteration bound.
    NoConvergence {
        /// Where.
        stage: Stage,
    },
    /// No singular value rose above the noise floor: no input-to-output dynamics detected.
    NoDynamics,
    /// The static gain of the normalised linear part is (near) zero, so γ is undefined.
    ZeroStaticGain,
    /// The identified `A` has a pole on or outside the unit circle: the method assumes a stable
    /// `G`, normalised by `G(1) = 1`, which an unstable or integrating `G` does not have.
    UnstableModel {
        /// The spectral radius of `A` (largest pole modulus).
        spectral_radius: f64,
    },
    /// `I - A` is singular: the identified linear part integrates, so `G(1) = 1` cannot be imposed.
    IntegratingModel,
    /// A checkpoint could not be saved or restored.
    Checkpoint(CheckpointError),
    /// The forgetting factor must satisfy `0 < λ <= 1`.
    InvalidForgetting {
        /// The value given.
        lambda: f64,
    },
    /// The identifier was created with `Identifier::EMPTY` and not configured with `reset`.
    Unconfigured,
    /// The structured solve cannot take these settings (see [`ShiftBreak`]).
    NotShiftStructured {
        /// What breaks the structure.
        cause: ShiftBreak,
    },
    /// The caller-provided workspace is too small.
    WorkspaceTooSmall {
        /// Scalars needed.
        need: usize,
        /// Scalars given.
        have: usize,
    },
}

impl Error {
    /// `true` if the error is about the settings (knots, interval, horizons, order, hold,
    /// μ0, forgetting): a front end reports it against its configuration, not against a
    /// sample of the data. Every variant is classified here, so a new one must be too.
    ///
    /// ```
    /// use hsid::{Error, Knots};
    /// let e = Knots::<f64, 4>::new(&[-3.0, 3.0], &[-3.0, 2.0]).unwrap_err();
    /// assert!(e.concerns_settings());
    /// assert!(!Error::NoDynamics.concerns_settings());
    /// ```
    pub fn concerns_settings(&self) -> bool {
        match self {
            Error::InvalidInterval { .. }
            | Error::TooFewKnots { .. }
            | Error::KnotsNotIncreasing { .. }
            | Error::KnotEndpoints { .. }
            | Error::SegmentCount { .. }
            | Error::InvalidHorizon { .. }
            | Error::TooFewInstruments { .. }
            | Error::InvalidOrder { .. }
            | Error::HoldTooShort { .. }
            | Error::InvalidMu0 { .. }
            | Error::InvalidForgetting { .. }
            | Error::NotShiftStructured { .. }
            | Error::Unconfigured => true,
            Error::HoldNotAtMin { .. }
            | Error::NonFinite { .. }
            | Error::InputOutOfRange { .. }
            | Error::TooFewSamples { .. }
            | Error::NoExcitation { .. }
            | Error::RankDeficient { .. }
            | Error::Overflow { .. }
            | Error::NoConvergence { .. }
            | Error::NoDynamics
            | Error::ZeroStaticGain
            | Error::UnstableModel { .. }
            | Error::IntegratingModel
            | Error::Checkpoint(_)
            | Error::WorkspaceTooSmall { .. } => false,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidInterval { u_min, u_max } => write!(
                f,
                "invalid input interval [{u_min}, {u_max}]: u_min must be finite and below u_max"
            ),
            Error::TooFewKnots { path, count } => write!(
                f,
                "{path} path has {count} knot(s): give at least two (u_min and u_max)"
            ),
            Error::KnotsNotIncreasing { path, index } => write!(
                f,
                "{path} knots must be finite and strictly increasing: knot {index} is not above knot {}",
                index.saturating_sub(1)
            ),
            Error::KnotEndpoints {
                end,
                ascending,
                descending,
            } => write!(
                f,
                "the {end} knots differ: ascending {ascending}, descending {descending}; both paths must start at u_min and end at u_max"
            ),
            Error::SegmentCount {
                expected,
                ascending,
                descending,
            } => write!(
                f,
                "{ascending} ascending + {descending} descending segments, exceed the capacity of {expected} channels: use fewer knots or a larger M"
            ),
            Error::InvalidHorizon {
                f: fh,
                k,
                max_f,
                max_k,
            } => write!(
                f,
                "future horizon f = {fh} and f + p = {k} block rows: need 2 <= f <= {max_f} (the horizon capacity H), p >= 1 and f + p <= {max_k} (the block-row capacity K): lower f or p, or use an identifier with larger H or K"
            ),
            Error::TooFewInstruments {
                f: fh,
                p,
                channels,
                past_outputs,
            } => {
                let per = channels + usize::from(past_outputs);
                let rows = p * per;
                let what = if past_outputs { "p·(m + 1)" } else { "p·m" };
                write!(
                    f,
                    "the instruments have {what} = {rows} rows (p = {p}, m = {channels} channels), fewer than the future horizon f = {fh}: raise p to at least {}, or use more knots",
                    fh.div_ceil(per.max(1)),
                )?;
                if rows >= 2 {
                    write!(f, ", or lower f to at most {rows}")?;
                }
                Ok(())
            }
            Error::InvalidOrder { order: 0, .. } => {
                write!(f, "order 0 requested: the model order must be at least 1")
            }
            Error::InvalidOrder { order, f: fh } => write!(
                f,
                "order {order} needs a future horizon f > {order} (f = {fh}): lower the order or raise f"
            ),
            Error::HoldTooShort { len, settle } => write!(
                f,
                "hold of {len} samples with {settle} skipped to settle leaves nothing to average for mu0: lengthen the hold"
            ),
            Error::HoldNotAtMin { index, value } => write!(
                f,
                "sample {index} belongs to the hold but u = {value} is not u_min: either the excitation starts before the hold ends (shorten the hold) or the input is not exactly at u_min while it rests there (read the hold's inputs within a tolerance as u_min before pushing them)"
            ),
            Error::InvalidMu0 { value } => write!(
                f,
                "the known mu0 (border value at u_min) is {value}: give a finite value, or let the hold measure it"
            ),
            Error::NonFinite { index, signal } => {
                write!(f, "sample {index}: {signal} is NaN or infinite")
            }
            Error::InputOutOfRange { index, value } => write!(
                f,
                "sample {index}: u = {value} lies outside [u_min, u_max]: widen the interval or fix the data"
            ),
            Error::TooFewSamples { have, need } => write!(
                f,
                "{have} samples after the hold, {need} needed for these Hankel sizes: record longer or lower f, p or the knot count"
            ),
            Error::NoExcitation { path, knot } => write!(
                f,
                "{path} path: the basis function of knot {knot} was never excited: the input never visited the segments next to that knot; excite that range (for a backlash or switch, the Table I excitation sweeps both paths) or remove the knot"
            ),
            Error::RankDeficient {
                stage: Stage::CvaWeighting,
            } => write!(
                f,
                "the CVA weighting (Y_f P Y_f')^(-1/2) is singular to rounding: the outputs carry (almost) no noise beyond what the inputs explain (noise-free data), so the canonical correlations are undefined: use PI-MOESP (the default) or PO-MOESP"
            ),
            Error::RankDeficient { stage } => write!(
                f,
                "rank deficient data at {stage}: the input is not persistently exciting enough (use the Table I excitation, more samples or fewer knots)"
            ),
            Error::Overflow { stage } => write!(
                f,
                "overflow in {stage}: the values are too large for the scalar type (a square of y, or of the knot spacing in the ramp basis, exceeds its largest finite number): scale y (and u) towards 1, or use f64"
            ),
            Error::NoConvergence { stage } => {
                write!(f, "no convergence within the iteration bound at {stage}")
            }
            Error::NoDynamics => write!(
                f,
                "no singular value above the noise floor: the output does not respond to the input"
            ),
            Error::ZeroStaticGain => write!(
                f,
                "the linear part has (near) zero static gain (|G(1)| within the estimate's own error), so it cannot be normalised to G(1) = 1: a plant with a zero at z = 1 (differentiating) is outside the model class"
            ),
            Error::UnstableModel { spectral_radius } => write!(
                f,
                "the identified linear part has a pole of modulus {spectral_radius:.6} >= 1 (integrating or unstable): the method assumes a stable G normalised by G(1) = 1; check for an integrating plant or a drifting output (identify the differenced output instead)"
            ),
            Error::IntegratingModel => write!(
                f,
                "I - A is singular (integrating linear part): G(1) = 1 cannot be imposed"
            ),
            Error::Checkpoint(e) => write!(f, "checkpoint: {e}"),
            Error::InvalidForgetting { lambda } => write!(
                f,
                "forgetting factor {lambda}: it must lie in (0, 1]; 1 - 1/N keeps about N samples"
            ),
            Error::Unconfigured => write!(
                f,
                "the identifier is not configured: call reset with its settings first"
            ),
            Error::NotShiftStructured { cause } => write!(
                f,
                "the structured solve needs a Gram whose rows are lags of one sequence, which {cause} breaks: use the dense solve (Identifier::solve, hsid::workspace_len scalars)"
            ),
            Error::WorkspaceTooSmall { need, have } => write!(
                f,
                "workspace has {have} scalars, the solve needs {need}: size it with hsid::workspace_len"
            ),
        }
    }
}

impl fmt::Display for Signal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Signal::Input => "input u",
            Signal::Output => "output y",
        })
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stage::Sums => "the accumulated sums (the Gram of [Z_f; Z_p; Y_f])",
            Stage::InputHankel => "the input Hankel Gram [Z_f; Z_p]",
            Stage::Projection => "the projection O_f (eq. 11)",
            Stage::CvaWeighting => "the CVA weighting (Y_f P Y_f')^(-1/2)",
            Stage::ShiftInvariance => "the shift-invariance step for A",
            Stage::InputMatrices => "the least squares for B and D",
            Stage::RankOneSplit => "the rank-1 split of [D; B] (eq. 14)",
            Stage::StaticGain => "the static gain (I - A)",
        })
    }
}

impl core::error::Error for Error {}

impl fmt::Display for CheckpointError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use CheckpointError as C;
        f.write_str(match self {
            C::Truncated => {
                "the buffer is shorter than the checkpoint (truncated, or too small to save into)"
            }
            C::NotACheckpoint => "not an hsid checkpoint (wrong magic)",
            C::Version => "written by another checkpoint format version",
            C::ScalarType => "written with another scalar type (f32 vs f64)",
            C::Checksum => "checksum mismatch: the checkpoint is corrupted",
            C::SettingsMismatch => "written with other settings than this identifier's",
            C::Capacity => "needs more channels or block rows than this identifier's capacity",
            C::Invalid => "a field holds an impossible value",
            C::Summation => {
                "written with the other summation (plain vs compensated sums): restore it with the same Summation type"
            }
        })
    }
}
