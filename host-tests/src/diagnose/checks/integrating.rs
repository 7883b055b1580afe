//! An integrating plant or a drifting output, seen in the base model: a pole whose time
//! constant exceeds twice the record (the rule of [`too_slow`](crate::diagnose::effects::too_slow))
//! is a mode the record cannot validate; the method's normalisation `G(1) = 1` then divides by
//! nearly zero and the borders lose their meaning.

use super::warning::{Check, Warning, warn};
use crate::diagnose::model::ExtendedModel;

/// A warning when `base`, fitted on `samples` samples, has a pole of modulus at least
/// `1 − 1/(2·samples)`.
pub fn integrating(base: &ExtendedModel, samples: usize) -> Option<Warning> {
    let radius = base.spectral_radius();
    let limit = 1.0 - 0.5 / samples.max(4) as f64;
    (radius >= limit).then(|| {
        warn(
            Check::Integrating,
            format!(
                "the base model has a pole of modulus {radius:.5}, a time constant beyond twice the record's {samples} samples: the plant may integrate (voltage → position, a level loop), and its gain normalisation and borders are then meaningless; `hsid diagnose --integrating` diagnoses its stable part on the output's increments (or, for a drifting sensor, offset_drift models the drift)"
            ),
        )
    })
}
