//! What the figures know about the record beyond its numbers: the sample time, the units and,
//! for a simulated record, the true borders; and the axis labels and CSV column names made
//! from them.

use hsid::Direction;

use super::error::FigureError;
use crate::identify::HostModel;

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

impl TrueBorders {
    /// The true borders as a model (its linear part the unit gain): the knots the grid, the
    /// borders the true ones between them.
    fn as_model(&self) -> HostModel {
        HostModel {
            order: 0,
            a: nalgebra::DMatrix::zeros(0, 0),
            b: Vec::new(),
            c: Vec::new(),
            d: 1.0,
            mu0: self.asc.first().copied().unwrap_or(f64::NAN),
            knots_asc: self.u.clone(),
            knots_desc: self.u.clone(),
            border_asc: self.asc.clone(),
            border_desc: self.desc.clone(),
            singular_values: Vec::new(),
            whitened_singular_values: Vec::new(),
            f: 0,
            p: 0,
            samples: 0,
        }
    }

    /// The true gap at `u` after arriving in direction `dir`, by the definition of
    /// [`HostModel::gap_at`] on the true borders (linear between the grid's points).
    pub fn gap_at(&self, dir: Direction, u: f64) -> Option<f64> {
        self.as_model().gap_at(dir, u)
    }

    /// The true mean gap, by the definition of [`HostModel::mean_gap`] on the true borders
    /// (the same inputs as the identified model's when the grid spans its input interval).
    pub fn mean_gap(&self) -> Option<f64> {
        self.as_model().mean_gap()
    }
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
    fn the_true_gap_is_read_on_the_true_borders() {
        // A backlash of gap 0.2 and slope 1 on [−1, 1]: P_a = u − 0.1, P_d = u + 0.1.
        let u: Vec<f64> = (0..=40).map(|i| -1.0 + 0.05 * f64::from(i)).collect();
        let t = TrueBorders {
            asc: u.iter().map(|u| u - 0.1).collect(),
            desc: u.iter().map(|u| u + 0.1).collect(),
            u,
        };
        for dir in [Direction::Ascending, Direction::Descending] {
            let g = t.gap_at(dir, 0.3).unwrap_or(f64::NAN);
            assert!((g - 0.2).abs() < 1e-12, "{g}");
        }
        let mean = t.mean_gap().unwrap_or(f64::NAN);
        assert!((mean - 0.2).abs() < 1e-12, "{mean}");
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
