//! The catalog of effects: their names, the residual tests that are their evidence, their
//! complexity, and their settings in words.

use serde::Serialize;

use crate::diagnose::end_stop::EndStop;
use crate::diagnose::model::{Dynamics, ExtendedModel, Structure};
use crate::model::MemoryElement;
use crate::validation::residual::{Test, TestSet};

/// The effects the diagnosis can name and add.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    /// Output offset or slow drift: a polynomial trend in time.
    OffsetDrift,
    /// Extra transport delay: the input shifted by `d` samples.
    InputDelay,
    /// Order too low: a higher model order.
    UnmodeledDynamics,
    /// A static output map (saturation, overflow, sensor curve): Hammerstein–Wiener.
    OutputNonlinearity,
    /// A sinusoidal disturbance at a frequency detected in the residual.
    PeriodicDisturbance,
    /// Coloured noise: an AR noise model for one-step-ahead prediction.
    ColoredNoise,
    /// Isolated outliers: left out of the error, the model re-estimated if that pays.
    Outliers,
    /// State-dependent dynamics: level-dependent stores instead of the linear `G`. Beyond the
    /// seven-effect catalog the simulated scenarios cover ([`Effect::ALL`]); proposed with
    /// them ([`Effect::PROPOSED`]).
    StateDependentDynamics,
    /// An element with memory the static model lacks: the play operator (backlash) or the
    /// relay with borders (switch) on the knots, simulated itself. Beyond the seven-effect
    /// catalog the simulated scenarios cover ([`Effect::ALL`]); proposed with them
    /// ([`Effect::PROPOSED`]) on a static model.
    Hysteresis,
    /// Coulomb friction and an offset on the output's velocity, fed back into `G`'s input
    /// ([`crate::friction`]). Beyond the seven-effect catalog; proposed with them
    /// ([`Effect::PROPOSED`]) on a model without an element with memory, stores or an output
    /// map, where the sign of its simulated velocity explains its equation error.
    Friction,
    /// Play between two dynamic parts: the two-mass drive whose shaft has a dead zone of the
    /// gear play ([`crate::sandwich`]) in place of `G` and any input element. Beyond the
    /// seven-effect catalog; proposed with them ([`Effect::PROPOSED`]) on a model of order
    /// at most 3 where the error depends on the direction of motion, and kept only when the
    /// play carries the gain (not the drive's order alone).
    PlayBetween,
}

impl Effect {
    /// Every effect of the catalog.
    pub const ALL: [Effect; 7] = [
        Effect::OffsetDrift,
        Effect::InputDelay,
        Effect::UnmodeledDynamics,
        Effect::OutputNonlinearity,
        Effect::PeriodicDisturbance,
        Effect::ColoredNoise,
        Effect::Outliers,
    ];

    /// Every effect the diagnosis proposes: the catalog, then the level-dependent stores
    /// for state-dependent dynamics, then the element with memory, then friction, then play
    /// between motor and load.
    pub const PROPOSED: [Effect; 11] = {
        let mut all = [Effect::StateDependentDynamics; 11];
        all[8] = Effect::Hysteresis;
        all[9] = Effect::Friction;
        all[10] = Effect::PlayBetween;
        let mut i = 0;
        while i < Effect::ALL.len() {
            all[i] = Effect::ALL[i];
            i += 1;
        }
        all
    };

    /// The catalog name (`offset_drift`, …).
    pub fn name(self) -> &'static str {
        match self {
            Effect::OffsetDrift => "offset_drift",
            Effect::InputDelay => "input_delay",
            Effect::UnmodeledDynamics => "unmodeled_dynamics",
            Effect::OutputNonlinearity => "output_nonlinearity",
            Effect::PeriodicDisturbance => "periodic_disturbance",
            Effect::ColoredNoise => "colored_noise",
            Effect::Outliers => "outliers",
            Effect::StateDependentDynamics => "state_dependent_dynamics",
            Effect::Hysteresis => "hysteresis",
            Effect::Friction => "friction",
            Effect::PlayBetween => "play_between",
        }
    }

    /// The effect with this catalog name.
    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::PROPOSED.into_iter().find(|e| e.name() == name)
    }

    /// The residual tests that point at this effect (at least one must fire).
    pub(crate) fn evidence_tests(self) -> &'static [Test] {
        match self {
            Effect::OffsetDrift => &[Test::Trend],
            Effect::InputDelay => &[
                Test::InputCorrelation,
                Test::DirectionCorrelation,
                Test::RegressorCorrelation,
            ],
            Effect::UnmodeledDynamics => &[
                Test::InputCorrelation,
                Test::DirectionCorrelation,
                Test::RegressorCorrelation,
                Test::Whiteness,
            ],
            Effect::OutputNonlinearity => &[Test::StructureOutput, Test::StructureInput],
            Effect::PeriodicDisturbance => &[Test::SpectralLine],
            Effect::ColoredNoise => &[Test::Whiteness],
            Effect::Outliers => &[Test::HeavyTails],
            // Dynamics of another class: the evidence of wrong dynamics (as for a higher
            // order), and a residual that follows the level (its increment, or its mean).
            Effect::StateDependentDynamics => &[
                Test::StateDependence,
                Test::StructureOutput,
                Test::InputCorrelation,
                Test::RegressorCorrelation,
                Test::Whiteness,
            ],
            // A residual that depends on the direction of the input's last move (what a
            // single border for both directions cannot follow), or one that is not white:
            // behind a static model the element's memory leaves a slow, coloured error
            // whose correlation with δ the prewhitened test often cannot resolve (as for a
            // missing order, whiteness is the evidence that something deterministic lacks).
            Effect::Hysteresis => &[Test::DirectionCorrelation, Test::Whiteness],
            // An error that depends on the direction of motion leaves a residual correlated
            // with the direction or a coloured one; the proposal then asks its own question
            // (the sign of the simulated velocity in the model's equation).
            Effect::Friction => &[Test::DirectionCorrelation, Test::Whiteness],
            // The same; the proposal then asks whether the play carries the gain.
            Effect::PlayBetween => &[Test::DirectionCorrelation, Test::Whiteness],
        }
    }

    /// The model extension, in words.
    pub fn extension(self) -> &'static str {
        match self {
            Effect::OffsetDrift => {
                "polynomial output trend in time, or an offset with an exponential settling, chosen on the estimation hold-out"
            }
            Effect::InputDelay => "input shifted by d samples, d chosen on the estimation hold-out",
            Effect::UnmodeledDynamics => "higher model order, chosen on the estimation hold-out",
            Effect::OutputNonlinearity => {
                "monotone piecewise-linear output map (Hammerstein–Wiener), segments chosen on the estimation hold-out"
            }
            Effect::PeriodicDisturbance => {
                "sinusoid at the residual's spectral line, frequency refined by least squares"
            }
            Effect::ColoredNoise => "AR noise model (order by BIC) for one-step-ahead prediction",
            Effect::Outliers => {
                "outliers by the MAD rule left out of the error; the model re-estimated with them replaced by its output when that improves the estimation hold-out significantly and by the minimum gain"
            }
            Effect::StateDependentDynamics => {
                "level-dependent stores: the order-2 linear part as a cascade of two stores with power-law outflows, the first overflowing into the second, borders refitted with them on the simulation error"
            }
            Effect::Hysteresis => {
                "the element itself: play operator (backlash) or relay with borders (switch) on the knots, with G, fitted by simulation error from the static model"
            }
            Effect::Friction => {
                "Coulomb friction (a tanh of the output's velocity) and an offset subtracted from G's input, with G, fitted by simulation error from the current model"
            }
            Effect::PlayBetween => {
                "two-mass drive with the gear play between motor and load (a dead zone in the shaft's stiffness), the motor's speed the output, in place of G and any input element, fitted by simulation error from G's poles"
            }
        }
    }

    /// Whether the effect changes the deterministic (simulated) model; the noise model only
    /// changes predictions.
    pub fn deterministic(self) -> bool {
        self != Effect::ColoredNoise
    }

    /// Rough count of parameters the extension adds (ties go to the simpler one).
    pub(crate) fn complexity(self, s: &Structure, base_order: usize) -> f64 {
        match self {
            Effect::InputDelay => 1.0,
            Effect::OffsetDrift => {
                (s.trend_degree.map_or(1, |d| d + 1) + 2 * usize::from(s.settling.is_some())) as f64
            }
            Effect::PeriodicDisturbance => 3.0,
            Effect::Outliers => 2.0,
            Effect::OutputNonlinearity => s.output_map_segments.unwrap_or(3) as f64 + 1.0,
            Effect::UnmodeledDynamics => {
                let n = s.order.unwrap_or(base_order + 1);
                ((n.saturating_sub(base_order)) * (2 * n + 2)) as f64
            }
            Effect::ColoredNoise => s.noise_ar_order.unwrap_or(1) as f64,
            // Exponents, offsets, overflow level and spill beyond the linear cascade.
            Effect::StateDependentDynamics => 6.0,
            // A second border on the knots (7 for the usual 6 segments) and w(−1).
            Effect::Hysteresis => 8.0,
            // Coulomb force, velocity scale, offset.
            Effect::Friction => 3.0,
            // Seven parameters of the two mass drive, less the order-2 G's four they replace,
            // and the play.
            Effect::PlayBetween => 4.0,
        }
    }

    /// Whether structure `s` already has the effect.
    pub(crate) fn is_in(self, s: &Structure) -> bool {
        match self {
            Effect::OffsetDrift => s.trend_degree.is_some(),
            Effect::InputDelay => s.delay > 0,
            Effect::UnmodeledDynamics => s.order.is_some(),
            Effect::OutputNonlinearity => s.output_map_segments.is_some(),
            Effect::PeriodicDisturbance => s.frequencies.len() >= 3,
            Effect::ColoredNoise => s.noise_ar_order.is_some(),
            Effect::Outliers => s.robust,
            Effect::StateDependentDynamics => s.dynamics != Dynamics::Linear,
            Effect::Hysteresis => s.element.is_some(),
            Effect::Friction => s.friction,
            Effect::PlayBetween => s.play_between,
        }
    }
}

/// Whether any of the effect's evidence tests fired.
pub fn has_evidence(effect: Effect, tests: &TestSet) -> bool {
    effect.evidence_tests().iter().any(|&t| tests.fired(t))
}

/// The effect's setting, in words, for a structure that has it.
pub fn setting(effect: Effect, s: &Structure, model: Option<&ExtendedModel>) -> String {
    match effect {
        Effect::OffsetDrift => {
            match model.and_then(|m| m.additive.settling.map(|(k, _)| k * m.additive.scale)) {
                Some(t) => format!("offset and exponential settling, time constant {t:.0} samples"),
                None if s.settling.is_some() => "offset and exponential settling".to_string(),
                None => format!("trend degree {}", s.trend_degree.unwrap_or(0)),
            }
        }
        Effect::InputDelay => format!("delay {} samples", s.delay),
        Effect::UnmodeledDynamics => match s.horizon {
            Some(h) => format!("order {}, horizons f = p = {h}", s.order.unwrap_or(0)),
            None => format!("order {}", s.order.unwrap_or(0)),
        },
        Effect::OutputNonlinearity if s.end_stop.is_some() => {
            let at = |l: Option<f64>| l.map_or("none".to_string(), |l| format!("{l:.4}"));
            let stop = s.end_stop.unwrap_or(EndStop {
                levels: Default::default(),
                held: false,
            });
            let sat = stop.levels;
            format!(
                "end stop: {} at levels fitted to the data (upper {}, lower {}; no sample sits at a level exactly)",
                match (stop.held, s.element.is_some()) {
                    (true, _) => "mechanical, the model's state held at rest",
                    (false, true) => "the element's simulation clamped",
                    (false, false) => "the output clamped",
                },
                at(sat.ceiling),
                at(sat.floor)
            )
        }
        Effect::OutputNonlinearity if s.element.is_some() => {
            "output saturation: the element's simulation clamped at the pinned levels".into()
        }
        Effect::OutputNonlinearity => format!(
            "output map with {} segments",
            s.output_map_segments.unwrap_or(0)
        ),
        Effect::PeriodicDisturbance => match s.frequencies.last() {
            Some(w) => format!(
                "sinusoid at ω = {w:.5} rad/sample (period {:.2} samples)",
                2.0 * std::f64::consts::PI / w
            ),
            None => String::new(),
        },
        Effect::ColoredNoise => format!("AR({}) noise model", s.noise_ar_order.unwrap_or(0)),
        Effect::Outliers => match model {
            Some(m) => format!(
                "MAD rule at {} robust σ, {} estimation samples flagged, model {}",
                m.outlier_k,
                m.flagged,
                if s.robust_refit {
                    "re-estimated"
                } else {
                    "kept"
                }
            ),
            None => "MAD rule".into(),
        },
        Effect::Hysteresis => {
            let element: String = match model.and_then(|m| m.hysteresis.as_ref()) {
                Some(h) => match (h.kind, h.gap()) {
                    (MemoryElement::Play, Some(g)) => format!("play operator, gap {g:.4}"),
                    (MemoryElement::Play, None) => "play operator".into(),
                    (MemoryElement::Relay, _) => "relay with borders".into(),
                },
                None => match s.element {
                    Some(MemoryElement::Relay) => "relay with borders".into(),
                    _ => "play operator".into(),
                },
            };
            if s.end_stop.is_some() {
                format!("{element}, with the end stop at the fitted levels")
            } else if s.output_map_segments.is_some() {
                format!("{element}, with the output saturation at the pinned levels")
            } else {
                element
            }
        }
        Effect::Friction => match model.and_then(|m| m.friction.as_ref()) {
            Some(fm) => format!(
                "Coulomb {:.4} and offset {:.4} (the element's output's units), the sign smoothed \
                 over {:.3e} of {}, the element's output {} sample(s) late",
                fm.friction.coulomb,
                fm.friction.offset,
                fm.friction.velocity_scale,
                match fm.friction.speed {
                    true => "the output (a speed)",
                    false => "the output's change per sample",
                },
                fm.friction.delay
            ),
            None => "Coulomb friction and an offset on the output's velocity".into(),
        },
        Effect::PlayBetween => match model.and_then(|m| m.two_mass.as_ref()) {
            Some(tm) => format!("two-mass drive: {}", tm.describe(None, None)),
            None => "two-mass drive with play between motor and load".into(),
        },
        Effect::StateDependentDynamics => {
            let map = match s.output_map_segments {
                Some(k) => format!(", output map with {k} segments"),
                None => String::new(),
            };
            match model.and_then(|m| m.stores.as_ref()) {
                Some(st) => format!(
                    "level-dependent stores: outflow exponents {:.2}, {:.2}; overflow at {:.3} with {:.0} % spilled{map}",
                    st.alpha[0],
                    st.alpha[1],
                    st.level,
                    100.0 * st.spill
                ),
                None => format!("level-dependent stores{map}"),
            }
        }
    }
}
