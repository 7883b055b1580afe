//! The class's own parameters, drawn once per scenario and applied to both records: the
//! delay, the sensor lag, the sensor curve, the disturbance, the drift, the spikes, the clip
//! and the integrator.

use super::class::Class;
use super::noise::{rms, variance};
use super::plant::{Plant, Section};
use super::rng::Rng;

/// The additions of one scenario (neutral values for the classes that do not use them).
#[derive(Clone, Debug, PartialEq)]
pub struct Additions {
    /// Extra samples of delay before the plant.
    pub delay: usize,
    /// The sensor lag's time constant as a fraction of the plant's slowest (`None`: no lag).
    pub sensor_lag: Option<f64>,
    /// Whether the sensor curve applies.
    pub curve: bool,
    /// Disturbance: period in samples, amplitude in σ_v, phase.
    pub periodic: Option<(f64, f64, f64)>,
    /// Drift: size in σ_v (signed) and time constant in samples.
    pub drift: Option<(f64, f64)>,
    /// Spikes: probability per sample, size range in σ_v.
    pub spikes: Option<(f64, f64, f64)>,
    /// Whether the output is clipped at its 85th percentile.
    pub clip: bool,
    /// Whether an integrator of gain `0.02/ts` ends the plant.
    pub integrator: bool,
}

impl Additions {
    /// The additions of `class`, drawn from `rng`.
    pub fn draw(class: Class, rng: &mut Rng) -> Self {
        let sign = if rng.chance(0.5) { 1.0 } else { -1.0 };
        Self {
            delay: if class == Class::Delay {
                2 + (rng.uniform() * 3.0) as usize
            } else {
                0
            },
            sensor_lag: (class == Class::ExtraPole).then(|| rng.between(0.4, 0.8)),
            curve: class == Class::OutputCurve,
            periodic: (class == Class::Periodic).then(|| {
                (
                    rng.between(8.0, 60.0),
                    rng.between(1.5, 2.5) * std::f64::consts::SQRT_2,
                    rng.between(0.0, std::f64::consts::TAU),
                )
            }),
            drift: (class == Class::Drift)
                .then(|| (sign * rng.between(5.0, 8.0), rng.between(600.0, 1500.0))),
            spikes: (class == Class::Outliers).then_some((0.01, 6.0, 12.0)),
            clip: class == Class::Saturation,
            integrator: class == Class::Integrating,
        }
    }

    /// The simulated plant: the design's, with the sensor lag or the integrator appended.
    pub fn plant(&self, base: &Plant, ts: f64) -> Plant {
        let mut p = base.clone();
        if let Some(f) = self.sensor_lag {
            p.sections.push(Section::Real {
                tau: f * slowest(base),
            });
        }
        if self.integrator {
            p.sections.push(Section::Integrator { k: 0.02 / ts });
        }
        p
    }

    /// The element's output delayed by `delay` samples (the first value held before).
    pub fn delayed(&self, w: &[f64]) -> Vec<f64> {
        (0..w.len())
            .map(|t| w[t.saturating_sub(self.delay)])
            .collect()
    }

    /// The deterministic output additions at sample `t` of a record: disturbance and drift,
    /// with noise standard deviation `sigma`.
    pub fn disturbance(&self, t: usize, sigma: f64) -> f64 {
        let tf = t as f64;
        let p = self.periodic.map_or(0.0, |(period, a, ph)| {
            a * sigma * (2.0 * std::f64::consts::PI * tf / period + ph).sin()
        });
        let d = self
            .drift
            .map_or(0.0, |(size, tau)| size * sigma * (1.0 - (-tf / tau).exp()));
        p + d
    }
}

/// The plant's slowest time constant, s (`1/(ζω)` for a complex pair).
pub fn slowest(p: &Plant) -> f64 {
    p.sections
        .iter()
        .map(|s| match *s {
            Section::Real { tau } => tau,
            Section::Complex { omega, zeta } => 1.0 / (zeta * omega),
            Section::Integrator { .. } => 0.0,
        })
        .fold(0.0, f64::max)
}

/// The sensor curve `c + s tanh((y − c)/s)` with `c` the mean and `s` the standard
/// deviation of the reference output.
pub fn curve_of(reference: &[f64]) -> impl Fn(f64) -> f64 {
    let c = reference.iter().sum::<f64>() / reference.len().max(1) as f64;
    let s = variance(reference).sqrt().max(1e-12);
    move |y| c + s * ((y - c) / s).tanh()
}

/// The 85th percentile of the reference output: the clip level.
pub fn clip_level(reference: &[f64]) -> f64 {
    let mut v = reference.to_vec();
    v.sort_by(f64::total_cmp);
    v.get((0.85 * v.len() as f64) as usize)
        .copied()
        .unwrap_or_else(|| rms(reference))
}
