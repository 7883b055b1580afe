//! Why an effect was proposed ([`Evidence`]) and what was tried for it on the inner
//! validation ([`Tried`]): typed, so that the loop and the tests decide on the kind, and
//! rendered to the report's words by `Display` (the JSON holds the same words).

use std::fmt;

use serde::{Serialize, Serializer};

use super::delay::DeadTime;
use super::dynamics::DynamicsError;
use super::effects::Effect;
use super::end_stop::EndStops;
use crate::identify::IdentifyError;
use crate::validation::checks::{Check, Warning};
use crate::validation::residual::{TestResult, TestSet};

/// One piece of evidence that pointed at an effect.
#[derive(Clone, Debug, PartialEq)]
pub enum Evidence {
    /// A residual test of the effect that fired.
    Test(TestResult),
    /// The dead-time test found a delay beyond the model's (input delay).
    DeadTime(DeadTime),
    /// The data check found the output saturated (output nonlinearity).
    Saturation(Warning),
    /// The model's simulation goes beyond levels the output stays at, with noise on it (an
    /// end stop the data check cannot see: output nonlinearity).
    EndStop(EndStops),
}

impl fmt::Display for Evidence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Evidence::Test(t) => write!(f, "{}: {} (p = {:.2e})", t.name, t.detail, t.p_value),
            Evidence::DeadTime(d) => d.fmt(f),
            Evidence::Saturation(w) => write!(f, "data check output_saturation: {}", w.message),
            Evidence::EndStop(e) => e.fmt(f),
        }
    }
}

impl Serialize for Evidence {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Why a setting could not be scored.
#[derive(Clone, Debug, PartialEq)]
pub enum Unscored {
    /// The fitted model has a mode too slow to validate.
    TooSlow,
    /// The identification failed.
    Identify(IdentifyError),
    /// A model class beyond the linear dynamics could not be fitted.
    Dynamics(DynamicsError),
}

/// A setting tried on the inner validation, with its RMSE there.
#[derive(Clone, Debug, PartialEq)]
pub enum Tried {
    /// A setting of the effect (its label, e.g. `d = 3`), scored.
    Scored {
        /// The setting in words.
        label: String,
        /// Inner hold-out RMSE.
        rmse: f64,
    },
    /// A setting of the effect that could not be scored.
    Unscored {
        /// The setting in words.
        label: String,
        /// Why.
        why: Unscored,
    },
    /// The same stores with linear outflows, the reference the level-dependent stores must
    /// beat; `None` when they could not be fitted.
    LinearStores(Option<f64>),
    /// The delay of the dead-time test.
    DeadTime {
        /// Samples.
        delay: usize,
        /// Inner RMSE.
        rmse: f64,
        /// The blocks it was scored on: 1 for the inner hold-out's block, more for the
        /// cross-validation over the whole estimation record.
        blocks: usize,
    },
}

impl Tried {
    /// Inner hold-out RMSE (NaN when not scored).
    pub fn rmse(&self) -> f64 {
        match self {
            Tried::Scored { rmse, .. } | Tried::DeadTime { rmse, .. } => *rmse,
            Tried::Unscored { .. } => f64::NAN,
            Tried::LinearStores(rmse) => rmse.unwrap_or(f64::NAN),
        }
    }
}

impl fmt::Display for Tried {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tried::Scored { label, .. } => f.write_str(label),
            Tried::Unscored { label, why } => match why {
                Unscored::TooSlow => write!(f, "{label} (mode too slow)"),
                Unscored::Identify(e) => write!(f, "{label} (identification failed: {e})"),
                Unscored::Dynamics(e) => write!(f, "{label} (not fitted: {e})"),
            },
            Tried::LinearStores(Some(_)) => f.write_str("linear stores (the reference)"),
            Tried::LinearStores(None) => f.write_str("linear stores (the reference): not fitted"),
            Tried::DeadTime { delay, blocks, .. } if *blocks > 1 => write!(
                f,
                "d = {delay} (dead-time test; scored by cross-validation over {blocks} blocks of the record)"
            ),
            Tried::DeadTime { delay, .. } => write!(f, "d = {delay} (dead-time test)"),
        }
    }
}

/// As the pair `[setting in words, RMSE]` (`null` when not scored).
impl Serialize for Tried {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (self.to_string(), self.rmse()).serialize(s)
    }
}

/// The evidence of an effect: its tests that fired, the dead-time test for a delay, the
/// saturation check and the end stops fitted to the model's simulation for an output
/// nonlinearity.
pub fn evidence(
    e: Effect,
    tests: &TestSet,
    dead: &DeadTime,
    warnings: &[Warning],
    stops: Option<&EndStops>,
) -> Vec<Evidence> {
    let mut v: Vec<Evidence> = e
        .evidence_tests()
        .iter()
        .filter_map(|&t| tests.get(t))
        .filter(|t| t.fired)
        .cloned()
        .map(Evidence::Test)
        .collect();
    if e == Effect::InputDelay && dead.extra() > 0 {
        v.push(Evidence::DeadTime(dead.clone()));
    }
    if e == Effect::OutputNonlinearity {
        v.extend(
            warnings
                .iter()
                .filter(|w| w.check == Check::OutputSaturation)
                .cloned()
                .map(Evidence::Saturation),
        );
        v.extend(stops.copied().map(Evidence::EndStop));
    }
    v
}
