//! An end stop the data check cannot see: the output held at a level with the sensor's noise
//! on it (a mechanical stop, a sensor read after it). No sample sits exactly at an extreme, so
//! the data check's saturation ([`crate::validation::checks::saturation`]) finds nothing; the
//! current model's simulation, which goes beyond where the output stops, shows the level.
//!
//! [`fit_levels`] fits the level of each end by least squares: the simulation clamped at `L`
//! against the output, `L` searched over the output's upper (lower) quarter. An end is kept
//! when the model goes beyond it in at least [`MIN_SHARE`] of the samples and the clamp lowers
//! the squared error by at least [`MIN_REDUCTION`]; the scoring on the inner hold-out decides
//! whether the end stop is a step.

use std::fmt;

use serde::Serialize;

use crate::validation::checks::Saturation;

/// An end stop of the output at fitted levels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EndStop {
    /// The levels, and the tolerance within which a sample is at one.
    pub levels: Saturation,
    /// A mechanical stop: the model's state held at rest at the level while it pushes beyond
    /// (else a sensor: the output clamped).
    pub held: bool,
}

/// End stops fitted to a model's simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndStops {
    /// The levels, and the tolerance within which a sample is at one.
    pub levels: Saturation,
    /// Samples the simulation puts beyond a level.
    pub beyond: usize,
    /// Samples fitted on.
    pub samples: usize,
    /// Relative reduction of the squared error by the clamp at both levels.
    pub reduction: f64,
}

impl fmt::Display for EndStops {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |l: Option<f64>| l.map_or("none".to_string(), |l| format!("{l:.4}"));
        write!(
            f,
            "end stop: the model's simulation goes beyond levels the output stays at (upper {}, lower {}) in {} of {} samples ({:.1} %); clamped there, its squared error falls by {:.1} %",
            at(self.levels.ceiling),
            at(self.levels.floor),
            self.beyond,
            self.samples,
            100.0 * self.beyond as f64 / self.samples.max(1) as f64,
            100.0 * self.reduction
        )
    }
}

/// The least share of the samples the simulation must put beyond a level.
pub const MIN_SHARE: f64 = 0.01;
/// The least relative reduction of the squared error the clamp at a level must bring.
pub const MIN_REDUCTION: f64 = 0.05;
/// Levels tried per end: the output's quantiles over its outer quarter.
const LEVELS: usize = 101;

/// Whether `s` is beyond `level`: above it at the upper end, below it at the lower.
fn past(s: f64, level: f64, upper: bool) -> bool {
    if upper { s > level } else { s < level }
}

/// The squared error of `sim` clamped at `level` (above it for the upper end, below it for the
/// lower end) against `y` over `idx`, and how many samples the clamp moves.
fn clamped_sse(y: &[f64], sim: &[f64], idx: &[usize], level: f64, upper: bool) -> (f64, usize) {
    idx.iter().fold((0.0, 0), |(sse, n), &t| {
        let beyond = past(sim[t], level, upper);
        let s = if beyond { level } else { sim[t] };
        (sse + (y[t] - s).powi(2), n + usize::from(beyond))
    })
}

/// One end's level: `(level, samples beyond it, spread of the output there)`, or `None` when
/// no level passes the rules.
fn fit_end(y: &[f64], sim: &[f64], idx: &[usize], upper: bool) -> Option<(f64, usize, f64)> {
    let mut sorted: Vec<f64> = idx.iter().map(|&t| y[t]).collect();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    if n < 20 {
        return None;
    }
    let sse0: f64 = idx.iter().map(|&t| (y[t] - sim[t]).powi(2)).sum();
    let mut best: Option<(f64, f64, usize)> = None;
    for k in 0..LEVELS {
        let q = 0.25 * k as f64 / (LEVELS - 1) as f64;
        let q = if upper { 1.0 - q } else { q };
        let level = sorted[((n - 1) as f64 * q).round() as usize];
        let (sse, beyond) = clamped_sse(y, sim, idx, level, upper);
        if best.is_none_or(|(b, _, _)| sse < b) {
            best = Some((sse, level, beyond));
        }
    }
    let (sse, level, beyond) = best?;
    let enough = beyond as f64 >= MIN_SHARE * n as f64;
    let lowers = sse <= (1.0 - MIN_REDUCTION) * sse0;
    if !(enough && lowers) {
        return None;
    }
    // The output's spread about the level where the model is beyond it: the noise on the
    // stop (the level's tolerance).
    let (ss, m) = idx
        .iter()
        .filter(|&&t| past(sim[t], level, upper))
        .fold((0.0, 0usize), |(ss, m), &t| {
            (ss + (y[t] - level).powi(2), m + 1)
        });
    Some((level, beyond, (ss / m.max(1) as f64).sqrt()))
}

/// The end stops of the output: the levels at which `sim` (a model's simulation) clamped
/// fits `y` best over the samples `idx`, each end kept by the rules above; the tolerance is
/// twice the output's spread about the level where the model is beyond it (samples within
/// it are at the stop). `None` when neither end is kept.
pub fn fit_levels(y: &[f64], sim: &[f64], idx: &[usize]) -> Option<EndStops> {
    let hi = fit_end(y, sim, idx, true);
    let lo = fit_end(y, sim, idx, false);
    if hi.is_none() && lo.is_none() {
        return None;
    }
    let spread = [hi, lo]
        .iter()
        .flatten()
        .map(|&(_, _, s)| s)
        .fold(0.0, f64::max);
    let levels = Saturation {
        ceiling: hi.map(|(l, _, _)| l),
        floor: lo.map(|(l, _, _)| l),
        tolerance: 2.0 * spread,
    };
    let clamp = |s: f64| {
        let s = levels.ceiling.map_or(s, |c| s.min(c));
        levels.floor.map_or(s, |f| s.max(f))
    };
    let (sse0, sse): (f64, f64) = idx.iter().fold((0.0, 0.0), |(a, b), &t| {
        (
            a + (y[t] - sim[t]).powi(2),
            b + (y[t] - clamp(sim[t])).powi(2),
        )
    });
    Some(EndStops {
        levels,
        beyond: idx.iter().filter(|&&t| clamp(sim[t]) != sim[t]).count(),
        samples: idx.len(),
        reduction: 1.0 - sse / sse0.max(f64::MIN_POSITIVE),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::panic)]
    use super::*;

    /// A deterministic, roughly uniform noise in ±`a` (no random source needed).
    fn wobble(t: usize, a: f64) -> f64 {
        let x = ((t as f64 * 12.9898).sin() * 43_758.545_3).rem_euclid(1.0);
        a * (2.0 * x - 1.0)
    }

    #[test]
    fn the_level_of_a_noisy_stop_is_found_where_the_model_goes_beyond_it() {
        // A slow sinusoid of amplitude 1 stopped at 0.7, with noise of ±0.05 on the reading;
        // the model simulates the sinusoid itself.
        let n = 2000;
        let sim: Vec<f64> = (0..n).map(|t| (t as f64 * 0.01).sin()).collect();
        let y: Vec<f64> = sim
            .iter()
            .enumerate()
            .map(|(t, &s)| s.min(0.7) + wobble(t, 0.05))
            .collect();
        let idx: Vec<usize> = (0..n).collect();
        let Some(stops) = fit_levels(&y, &sim, &idx) else {
            panic!("no stop found");
        };
        let sat = stops.levels;
        let c = sat.ceiling.unwrap_or(f64::NAN);
        assert!((c - 0.7).abs() < 0.01, "{c}");
        assert_eq!(sat.floor, None, "{sat:?}");
        // Uniform noise of ±0.05 has the spread 0.05/√3 = 0.029: the tolerance twice that.
        assert!((sat.tolerance - 0.0577).abs() < 0.01, "{}", sat.tolerance);
        // The sinusoid is above 0.7 in acos(0.7)/π = 25.3 % of the time.
        let share = stops.beyond as f64 / stops.samples as f64;
        assert!((share - 0.253).abs() < 0.01, "{share}");
    }

    #[test]
    fn an_output_the_model_follows_has_no_stop() {
        let n = 2000;
        let sim: Vec<f64> = (0..n).map(|t| (t as f64 * 0.01).sin()).collect();
        let y: Vec<f64> = sim
            .iter()
            .enumerate()
            .map(|(t, &s)| s + wobble(t, 0.05))
            .collect();
        let idx: Vec<usize> = (0..n).collect();
        assert_eq!(fit_levels(&y, &sim, &idx), None);
    }
}
