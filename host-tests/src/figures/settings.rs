//! What the figures know about the record beyond its numbers: the sample time, the units and,
//! for a simulated record, the true borders; and the axis labels and CSV column names made
//! from them.

use super::error::FigureError;

/// The true borders of a simulated plant, sampled on a grid of inputs, drawn as the true loop.
#[derive(Debug, Clone, PartialEq)]
pub struct TrueBorders {
    /// Inputs, increasing.
    pub u: Vec<f64>,
    /// The true ascending border at `u`.
    pub asc: Vec<f64>,
    /// The true descending border at `u`.
    pub desc: Vec<f64>,
}

/// Settings of the figures (configuration only; the model and record are passed separately).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FigureSettings {
    /// Sample time in seconds: time axes in s and frequencies in Hz; without it, samples and
    /// rad/sample.
    pub ts: Option<f64>,
    /// Units of the input and the output, e.g. `("deg", "rad/s")`.
    pub units: Option<(String, String)>,
    /// The true borders, when the record was simulated.
    pub truth: Option<TrueBorders>,
}

impl FigureSettings {
    /// Checks the sample time.
    pub fn check(&self) -> Result<(), FigureError> {
        match self.ts {
            Some(ts) if !(ts.is_finite() && ts > 0.0) => Err(FigureError::InvalidSampleTime(ts)),
            _ => Ok(()),
        }
    }

    /// Times of `n` samples starting at sample `start` (seconds or sample numbers).
    pub(super) fn times(&self, start: usize, n: usize) -> Vec<f64> {
        let ts = self.ts.unwrap_or(1.0);
        (start..start + n).map(|t| t as f64 * ts).collect()
    }

    /// Time axis label and CSV column name.
    pub(super) fn time_axis(&self) -> (&'static str, &'static str) {
        match self.ts {
            Some(_) => ("time [s]", "t_s"),
            None => ("time [samples]", "t_samples"),
        }
    }

    /// A frequency in rad/sample in the figure's unit (Hz or rad/sample).
    pub(super) fn frequency(&self, w: f64) -> f64 {
        match self.ts {
            Some(ts) => w / (2.0 * std::f64::consts::PI * ts),
            None => w,
        }
    }

    /// Frequency axis label and CSV column name.
    pub(super) fn frequency_axis(&self) -> (&'static str, &'static str) {
        match self.ts {
            Some(_) => ("frequency [Hz]", "f_Hz"),
            None => ("frequency [rad/sample]", "w_rad_per_sample"),
        }
    }

    /// `name [unit]` for the input, or `name` without units.
    pub(super) fn input(&self, name: &str) -> String {
        with_unit(name, self.units.as_ref().map(|u| u.0.as_str()))
    }

    /// `name [unit]` for the output, or `name` without units.
    pub(super) fn output(&self, name: &str) -> String {
        with_unit(name, self.units.as_ref().map(|u| u.1.as_str()))
    }
}

fn with_unit(name: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) if !u.trim().is_empty() => format!("{name} [{}]", u.trim()),
        _ => name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_the_sample_time_and_units() {
        let s = FigureSettings {
            ts: Some(0.01),
            units: Some(("deg".into(), "rad/s".into())),
            truth: None,
        };
        assert_eq!(s.input("u"), "u [deg]");
        assert_eq!(s.output("y"), "y [rad/s]");
        assert_eq!(s.times(2, 2), vec![0.02, 0.03]);
        assert!((s.frequency(std::f64::consts::PI) - 50.0).abs() < 1e-12);
        let bare = FigureSettings::default();
        assert_eq!(bare.input("u"), "u");
        assert_eq!(bare.frequency(0.5), 0.5);
        assert_eq!(bare.time_axis().1, "t_samples");
    }

    #[test]
    fn a_bad_sample_time_is_an_error() {
        for ts in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let s = FigureSettings {
                ts: Some(ts),
                ..FigureSettings::default()
            };
            assert!(matches!(s.check(), Err(FigureError::InvalidSampleTime(_))));
        }
    }
}
