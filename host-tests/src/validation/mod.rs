//! Validation beneath the diagnosis: the data against the method's assumptions and a model's
//! residual against the model's.
//!
//! * [`checks`]: the data checks of an estimation record, before any fit (Table I structure,
//!   both paths over the whole interval, persistent excitation, the hold for μ0, saturation,
//!   quantisation, input levels, feedback, an integrating plant);
//! * [`residual`]: the statistical tests of a residual, each at the 1 % level;
//! * [`stats`], [`noise`], [`arx`] and [`unit_root`]: the statistics they use (distributions,
//!   correlations, spectra, the AR model of a signal, least-squares ARX pieces and the
//!   unit-root test).
//!
//! The diagnosis runs both and acts on them; the pages of `identify` and `validate` show
//! them. Nothing here depends on the diagnosis.

pub mod arx;
pub mod checks;
pub mod noise;
pub mod residual;
pub mod stats;
pub mod unit_root;

pub use checks::{Check, CheckSetup, Nonlinearity, Saturation, Warning};
pub use residual::{Test, TestSet};
