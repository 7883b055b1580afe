//! The initial hold at `u_min`, checked before identification: every input of the hold must
//! be `u_min`, or within a tolerance of it (an input logged with a little noise while it
//! rests at its minimum). Within the tolerance the hold's inputs are read as `u_min` (the
//! core identifier only checks them and averages the outputs, so this is what a tolerance in
//! it would do); beyond it [`HoldError`] names the first sample off `u_min`, the largest
//! deviation, and whether the excitation seems to start inside the hold (the hold is too
//! long) or the input is merely not exact (a tolerance is wanted).

use std::fmt::Write as _;

/// A sample of the hold and its distance from `u_min`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoldSample {
    /// Its index (0 = the first sample).
    pub index: usize,
    /// The input there.
    pub value: f64,
    /// `|value − u_min|`.
    pub deviation: f64,
}

/// A deviation from `u_min` beyond this fraction of the record's input span (its largest
/// input minus `u_min`) reads as the excitation, not as noise on the hold: 1 %.
pub const EXCITATION_FRACTION: f64 = 0.01;

/// A hold whose input is not at `u_min` within the tolerance.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.describe(&|i| format!("sample {i}")))]
pub struct HoldError {
    /// `u_min`.
    pub u_min: f64,
    /// The hold's length in samples.
    pub hold: usize,
    /// The tolerance applied (0: exactly `u_min`).
    pub tolerance: f64,
    /// The first sample beyond the tolerance.
    pub first: HoldSample,
    /// The sample of the hold farthest from `u_min`.
    pub largest: HoldSample,
    /// Whether the excitation seems to start in the hold: the largest deviation is more than
    /// [`EXCITATION_FRACTION`] of the input's span.
    pub excitation: bool,
}

impl HoldError {
    /// The message, each sample named by `at` (a line of its file for the command line).
    pub fn describe(&self, at: &dyn Fn(usize) -> String) -> String {
        let mut s = format!(
            "{}: u = {} is not u_min = {} but the hold (--hold {}) is not over",
            at(self.first.index),
            self.first.value,
            self.u_min,
            self.hold
        );
        if self.tolerance > 0.0 {
            let _ = write!(s, " (--hold-tolerance {})", self.tolerance);
        }
        let largest = format!(
            "the largest deviation in the hold is {} ({})",
            significant(self.largest.deviation),
            at(self.largest.index)
        );
        match self.excitation {
            true => {
                let _ = write!(
                    s,
                    "; the input leaves u_min there and {largest}: the excitation starts before \
                     the hold ends: give --hold {} or less",
                    self.first.index
                );
            }
            false => {
                let _ = write!(
                    s,
                    "; the input is not exactly at its minimum during the hold: {largest}; give \
                     --hold-tolerance {} to read the hold's inputs within it as u_min",
                    tolerance_for(self.largest.deviation)
                );
            }
        }
        s
    }
}

/// What a hold read within a tolerance found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoldRead {
    /// The sample of the hold farthest from `u_min` (none off it: `None`).
    pub largest: Option<HoldSample>,
    /// How many of the hold's inputs were not exactly `u_min` and are now.
    pub replaced: usize,
}

/// Checks the first `hold` inputs of `u` against `u_min`: each within `tolerance` (≥ 0; 0:
/// exactly) is set to `u_min`, and one beyond it is a [`HoldError`]. `u` is changed only when
/// the whole hold passes. A hold as long as the record or longer is not checked (nothing is
/// read, the identification refuses it: no sample is left after it).
pub fn read_hold(
    u: &mut [f64],
    u_min: f64,
    hold: usize,
    tolerance: f64,
) -> Result<HoldRead, HoldError> {
    if hold >= u.len() {
        return Ok(HoldRead {
            largest: None,
            replaced: 0,
        });
    }
    let n = hold;
    let sample = |index: usize| HoldSample {
        index,
        value: u[index],
        deviation: (u[index] - u_min).abs(),
    };
    let off = |i: &usize| !(u[*i] - u_min).abs().le(&tolerance);
    let largest = (0..n)
        .map(sample)
        .filter(|s| s.deviation > 0.0 || s.deviation.is_nan())
        .max_by(|a, b| a.deviation.total_cmp(&b.deviation));
    if let Some(first) = (0..n).find(off) {
        let span = u
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v - u_min));
        let largest = largest.unwrap_or(sample(first));
        // The samples before `first` are within the tolerance: it is the first one off.
        let excitation = largest.deviation > EXCITATION_FRACTION * span;
        return Err(HoldError {
            u_min,
            hold,
            tolerance,
            first: sample(first),
            largest,
            excitation,
        });
    }
    let mut replaced = 0;
    for v in &mut u[..n] {
        if *v != u_min {
            *v = u_min;
            replaced += 1;
        }
    }
    Ok(HoldRead { largest, replaced })
}

/// `deviation` rounded up to two significant digits: a tolerance that accepts it.
pub fn tolerance_for(deviation: f64) -> String {
    if !(deviation.is_finite() && deviation > 0.0) {
        return format!("{deviation}");
    }
    let step = 10f64.powi(deviation.log10().floor() as i32 - 1);
    // The quotient of two decimal values carries rounding noise (21.000000000000004).
    let mut v = (deviation / step * (1.0 - 1e-12)).ceil() * step;
    let mut text = format!("{v:.1e}");
    while text.parse::<f64>().is_ok_and(|t| t < deviation) {
        v += step;
        text = format!("{v:.1e}");
    }
    text
}

/// `v` with three significant digits.
fn significant(v: f64) -> String {
    format!("{v:.2e}")
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn a_hold_within_the_tolerance_is_read_as_u_min() {
        let mut u = vec![-1.0, -0.9999, -1.0002, -1.0, 0.5, 1.0];
        let r = read_hold(&mut u, -1.0, 4, 3e-4).unwrap();
        assert_eq!(u, [-1.0, -1.0, -1.0, -1.0, 0.5, 1.0]);
        assert_eq!(r.replaced, 2);
        let l = r.largest.unwrap();
        assert_eq!(l.index, 2);
        assert!((l.deviation - 2e-4).abs() < 1e-12, "{l:?}");
    }

    #[test]
    fn noise_in_the_hold_asks_for_a_tolerance() {
        let mut u = vec![5e-5, -2.1e-4, 0.0, 1e-4, 1.5, 3.0];
        let before = u.clone();
        let e = read_hold(&mut u, 0.0, 4, 0.0).unwrap_err();
        assert_eq!(u, before, "nothing changed on an error");
        assert_eq!(e.first.index, 0);
        assert_eq!(e.largest.index, 1);
        assert!(!e.excitation);
        let m = e.to_string();
        assert!(m.contains("not exactly at its minimum"), "{m}");
        assert!(
            m.contains("largest deviation in the hold is 2.10e-4 (sample 1)"),
            "{m}"
        );
        assert!(m.contains("--hold-tolerance 2.1e-4"), "{m}");
        assert!(!m.contains("hold length"), "{m}");
        assert!(read_hold(&mut u, 0.0, 4, 2.1e-4).is_ok());
        assert_eq!(u[..4], [0.0; 4]);
    }

    #[test]
    fn an_excitation_inside_the_hold_asks_for_a_shorter_hold() {
        let mut u = vec![-1.0, -1.0, -1.0, -0.5, 0.0, 0.5, 1.0];
        let e = read_hold(&mut u, -1.0, 5, 0.0).unwrap_err();
        assert!(e.excitation);
        assert_eq!(e.first.index, 3);
        let m = e.to_string();
        assert!(
            m.contains("the excitation starts before the hold ends: give --hold 3"),
            "{m}"
        );
    }

    #[test]
    fn the_tolerance_offered_accepts_the_deviation() {
        assert_eq!(tolerance_for(2.1e-4), "2.1e-4");
        assert_eq!(tolerance_for(3.71e-4), "3.8e-4");
        assert_eq!(tolerance_for(0.05), "5.0e-2");
    }
}
