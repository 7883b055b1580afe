//! The output's sensor: saturation and quantisation.

use serde::Serialize;

use super::warning::{Check, Warning, warn};

/// The smallest quantisation step looked for, relative to the output's largest magnitude: a
/// grid finer than 10⁻¹⁰ of it is the floating point's (an output differenced in floating
/// point keeps the rounding of the values it came from, 10⁻¹⁷ of a position of 0.3 in an
/// increment of 10⁻⁵), not a sensor's (a counter of 10¹⁰ steps is finer than any in use).
const GRID_RESOLUTION: f64 = 1e-10;

/// Levels at which the measured output saturates (found by the data checks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Saturation {
    /// Upper level.
    pub ceiling: Option<f64>,
    /// Lower level.
    pub floor: Option<f64>,
    /// Samples within this of a level are at it.
    pub tolerance: f64,
}

impl Saturation {
    /// Whether `y` sits at a saturation level.
    pub(crate) fn at_limit(&self, y: f64) -> bool {
        self.ceiling.is_some_and(|c| y >= c - self.tolerance)
            || self.floor.is_some_and(|f| y <= f + self.tolerance)
    }

    /// Whether any level is known.
    pub fn any(&self) -> bool {
        self.ceiling.is_some() || self.floor.is_some()
    }
}

/// The levels at which the output saturates: an extreme (maximum or minimum) at which more
/// than 2 % of the samples sit (within 0.1 % of the output's span).
pub fn saturation(y: &[f64]) -> Saturation {
    let (ymin, ymax) = y
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let tolerance = 1e-3 * (ymax - ymin).max(1e-300);
    let level = |ext: f64| {
        let at = y.iter().filter(|&&v| (v - ext).abs() <= tolerance).count();
        (ext.is_finite() && at * 50 > y.len()).then_some(ext)
    };
    Saturation {
        ceiling: level(ymax),
        floor: level(ymin),
        tolerance,
    }
}

/// An output that sits at an extreme, or takes values on a grid only.
pub(crate) fn output_sensor(y: &[f64]) -> Vec<Warning> {
    let mut out = Vec::new();
    let n = y.len();
    // Output saturation and quantisation.
    let sat = saturation(y);
    for (label, level) in [("maximum", sat.ceiling), ("minimum", sat.floor)] {
        if let Some(ext) = level {
            let at = y
                .iter()
                .filter(|&&v| (v - ext).abs() <= sat.tolerance)
                .count();
            out.push(warn(
                Check::OutputSaturation,
                format!(
                    "the output sits at its {label} {ext:.4} in {at} samples ({:.1} %): a saturating sensor or an overflow, an output nonlinearity the Hammerstein model does not have",
                    100.0 * at as f64 / n as f64
                ),
            ));
        }
    }
    let mut sorted = y.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    if sorted.len() >= 3 && sorted.len() * 5 < n {
        // Differences below `GRID_RESOLUTION` of the output's size are the floating point's,
        // not a sensor's (an output differenced or rescaled in floating point has them): they
        // are not the grid, and a step that small would put every value on it.
        let size = sorted.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let step = sorted
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|&d| d > GRID_RESOLUTION * size)
            .fold(f64::INFINITY, f64::min);
        let on_grid = step.is_finite()
            && y.iter()
                .all(|v| ((v / step) - (v / step).round()).abs() < 1e-6);
        if on_grid {
            out.push(warn(
                Check::OutputQuantisation,
                format!(
                    "the output is quantised in steps of {step} ({} distinct values): quantisation noise of RMS {:.3} is added, and it is not white where the output changes slowly",
                    sorted.len(),
                    step / 12f64.sqrt()
                ),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floating_point_differences_are_not_a_sensor_grid() {
        // Increments of a position on a 1e-6 grid, differenced in floating point: the
        // differences carry noise near 1e-22, the sensor's grid is 1e-6, and that is found.
        let pos: Vec<f64> = (0..4000)
            .map(|t| 0.3 + 1e-6 * ((t / 7) % 9) as f64)
            .collect();
        let inc: Vec<f64> = pos.windows(2).map(|w| w[1] - w[0]).collect();
        let out = output_sensor(&inc);
        let q: Vec<&Warning> = out
            .iter()
            .filter(|w| w.check == Check::OutputQuantisation)
            .collect();
        assert_eq!(q.len(), 1, "{out:?}");
        let step: f64 = q[0].message["the output is quantised in steps of ".len()..]
            .split_whitespace()
            .next()
            .and_then(|v| v.parse().ok())
            .unwrap_or(f64::NAN);
        assert!((step - 1e-6).abs() < 1e-9, "{}", q[0].message);
    }
}
