//! The model read in the record's sample time and units: one [`UnitReport`], as text lines
//! and as JSON.

use std::f64::consts::PI;
use std::fmt::Write;

use hsid::Direction;
use serde::Serialize;

use super::dead_band::{DeadBand, dead_band};
use super::poles::{ContinuousPole, Mode, ValueStd, continuous_pole};
use crate::identify::HostModel;
use crate::model_file::Units;

/// Interior points (of `GAP_POINTS + 1` equal parts of `[u_min, u_max]`) at which the gap is
/// reported.
pub const GAP_POINTS: usize = 5;

/// The gap and loop height at one input value.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GapAt {
    /// The input value.
    pub u: f64,
    /// The play after arriving at `u` on the descending path (input units).
    pub after_descent: Option<f64>,
    /// The play after arriving at `u` on the ascending path (input units).
    pub after_ascent: Option<f64>,
    /// The standard deviation of `after_descent`, when known; set with
    /// [`UnitReport::with_gap_stds`].
    pub after_descent_std: Option<f64>,
    /// The standard deviation of `after_ascent`, when known.
    pub after_ascent_std: Option<f64>,
    /// `G(1) (P_d(u) − P_a(u))`: the steady-state output difference between the two paths
    /// (output units).
    pub loop_height: f64,
}

/// The model in the record's sample time and units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnitReport {
    /// Sample time in seconds; `None`: the numbers are per sample.
    pub ts: Option<f64>,
    /// Units of the input and output, when known.
    pub units: Option<Units>,
    /// Each pole's continuous-time reading (time constants in s, frequencies in rad/s; per
    /// sample without a sample time), one entry per complex pair.
    pub poles: Vec<ContinuousPole>,
    /// −3 dB bandwidth of the linear part in rad/s (rad/sample without a sample time).
    pub bandwidth: Option<f64>,
    /// Static gain of the linear part, `G(1)`.
    pub lti_gain: f64,
    /// Static gain of the cascade, output units per input unit.
    pub cascade_gain: f64,
    /// The gap at [`GAP_POINTS`] inputs across the interval (two-path elements only).
    pub gap: Vec<GapAt>,
    /// The mean of the defined gaps in `gap`, both directions (input units).
    pub mean_gap: Option<f64>,
    /// The standard deviation of `mean_gap`, when the model has one
    /// ([`ModelStd::mean_gap`](crate::model_file::ModelStd::mean_gap)); set with
    /// [`with_gap_std`](Self::with_gap_std).
    pub mean_gap_std: Option<f64>,
    /// The widest flat interval of a static element's border (static elements only).
    pub dead_band: Option<DeadBand>,
}

impl HostModel {
    /// The report of model `m`; `pole_cov` holds the covariance of `(re, im)` of each pole of
    /// `m.poles()` when the model was refined; `two_path` is false for a static element (no gap).
    pub fn unit_report(
        &self,
        ts: Option<f64>,
        units: Option<Units>,
        pole_cov: Option<&[[[f64; 2]; 2]]>,
        two_path: bool,
    ) -> UnitReport {
        let scale = ts.unwrap_or(1.0);
        let poles = self
            .poles()
            .into_iter()
            .enumerate()
            .filter_map(|(i, z)| {
                continuous_pole(z, pole_cov.and_then(|c| c.get(i).copied()), scale)
            })
            .collect();
        let g = self.lti_gain();
        let (lo, hi) = (self.u_min(), self.u_max());
        let gap: Vec<GapAt> = if two_path {
            (1..=GAP_POINTS)
                .map(|k| {
                    let u = lo + (hi - lo) * k as f64 / (GAP_POINTS + 1) as f64;
                    GapAt {
                        u,
                        after_descent: self.gap_at(Direction::Descending, u),
                        after_ascent: self.gap_at(Direction::Ascending, u),
                        after_descent_std: None,
                        after_ascent_std: None,
                        loop_height: g * self.loop_height(u),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        UnitReport {
            ts,
            units,
            poles,
            bandwidth: self.bandwidth().map(|w| w / scale),
            lti_gain: g,
            cascade_gain: self.cascade_gain(),
            mean_gap: if two_path { self.mean_gap() } else { None },
            mean_gap_std: None,
            gap,
            dead_band: if two_path {
                None
            } else {
                dead_band(&self.knots_asc, &self.border_asc)
            },
        }
    }
}

impl UnitReport {
    /// The report with the standard deviation of its mean gap (none without a mean gap).
    pub fn with_gap_std(mut self, std: Option<f64>) -> Self {
        self.mean_gap_std = self.mean_gap.and(std);
        self
    }

    /// The report with the standard deviation of each gap in `gap`: `std_at(direction, u)`
    /// for the gap after arriving at `u` in that direction (none where the gap is not
    /// defined).
    pub fn with_gap_stds(mut self, std_at: impl Fn(Direction, f64) -> Option<f64>) -> Self {
        for g in &mut self.gap {
            g.after_descent_std = g
                .after_descent
                .and_then(|_| std_at(Direction::Descending, g.u));
            g.after_ascent_std = g
                .after_ascent
                .and_then(|_| std_at(Direction::Ascending, g.u));
        }
        self
    }

    /// The mean gap with its standard deviation, both rounded to the uncertainty
    /// ([`rounded_pm`]; `0.197 ± 0.004`), or with five decimals when it has none.
    pub fn mean_gap_text(&self) -> Option<String> {
        let g = self.mean_gap?;
        Some(match self.mean_gap_std {
            Some(s) => rounded_pm(g, s),
            None => format!("{g:.5}"),
        })
    }
}

/// A gap as the reports write it (`hsid identify`'s lines and the HTML page's gap table):
/// with its standard deviation, both rounded to it ([`rounded_pm`]), when known, else with
/// five decimals; `none` when the gap is not defined.
pub fn gap_text(gap: Option<f64>, std: Option<f64>) -> String {
    match (gap, std) {
        (Some(g), Some(s)) => rounded_pm(g, s),
        (Some(g), None) => format!("{g:.5}"),
        (None, _) => "none".to_string(),
    }
}

impl GapAt {
    /// The row's cells, as `hsid identify` prints them and the HTML page tabulates them: the
    /// input `u`, the gap after a descent and after an ascent ([`gap_text`], input units),
    /// and the loop height (output units).
    pub fn cells(&self) -> [String; 4] {
        [
            format!("{:.5}", self.u),
            gap_text(self.after_descent, self.after_descent_std),
            gap_text(self.after_ascent, self.after_ascent_std),
            format!("{:.5}", self.loop_height),
        ]
    }
}

/// `v ± s` with `s` to two significant digits when they start with 1 or 2 and to one
/// otherwise, and `v` to the same decimal place (`0.19698 ± 0.00423` reads `0.197 ± 0.004`,
/// `0.19698 ± 0.00123` reads `0.1970 ± 0.0012`); five decimals each when `s` is zero or not
/// finite.
pub fn rounded_pm(v: f64, s: f64) -> String {
    if !(s.is_finite() && s > 0.0 && v.is_finite()) {
        return format!("{v:.5} ± {s:.5}");
    }
    let exp = s.log10().floor() as i32;
    let lead = s / 10f64.powi(exp);
    let digits = if lead < 3.0 { 2 } else { 1 };
    let decimals = (digits - 1 - exp).max(0) as usize;
    format!("{v:.decimals$} ± {s:.decimals$}")
}

fn pm(e: &ValueStd) -> String {
    match e.std {
        Some(s) => format!("{:.5} ± {s:.5}", e.value),
        None => format!("{:.5}", e.value),
    }
}

/// `v` rounded to six significant digits and printed as briefly as it reads back, like the
/// sample time beside it (`100`, `333.333`, `0.5`): a rate derived from a decimal sample time
/// shows no trail of zeros or of rounding noise.
fn shortest(v: f64) -> String {
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    format!("{rounded}")
}

impl UnitReport {
    /// The report as text lines.
    pub fn lines(&self) -> Vec<String> {
        let (time, freq) = if self.ts.is_some() {
            ("s", "rad/s")
        } else {
            ("samples", "rad/sample")
        };
        let (u_unit, y_unit) = self
            .units
            .as_ref()
            .map_or(("input unit", "output unit"), |u| {
                (u.input.as_str(), u.output.as_str())
            });
        let mut out = vec![match self.ts {
            Some(ts) => format!("sample time {ts} s ({} Hz)", shortest(1.0 / ts)),
            None => "no sample time (give --ts or a time column): time constants in samples, frequencies in rad/sample".to_string(),
        }];
        let hz = |w: f64| {
            self.ts
                .map(|_| format!(" = {:.5} Hz", w / (2.0 * PI)))
                .unwrap_or_default()
        };
        for p in &self.poles {
            let mut s = format!("pole {:.5}{:+.5}j: ", p.z.0, p.z.1);
            let _ = match &p.mode {
                Mode::Real { tau } => write!(s, "time constant {} {time}", pm(tau)),
                Mode::Complex { wn, zeta } => write!(
                    s,
                    "pair with natural frequency {} {freq}{}, damping {}",
                    pm(wn),
                    hz(wn.value),
                    pm(zeta)
                ),
                Mode::NoEquivalent => {
                    write!(s, "real and not positive: no continuous-time equivalent")
                }
                Mode::NotDecaying => {
                    write!(s, "on or outside the unit circle: not a decaying mode")
                }
            };
            out.push(s);
        }
        if self.poles.iter().any(has_std) {
            out.push("± : standard deviations to first order (delta method) from the refinement's pole covariance".to_string());
        }
        out.push(match self.bandwidth {
            Some(w) => format!(
                "bandwidth (-3 dB) of the linear part: {w:.5} {freq}{}",
                hz(w)
            ),
            None => "bandwidth (-3 dB) of the linear part: above the Nyquist frequency".to_string(),
        });
        out.push(format!(
            "static gain: linear part {:.5}, cascade {:.5} {y_unit} per {u_unit}",
            self.lti_gain, self.cascade_gain
        ));
        for g in &self.gap {
            let [u, descent, ascent, height] = g.cells();
            out.push(format!(
                "gap at u = {u} {u_unit}: {descent} after a descent, {ascent} after an ascent ({u_unit}); loop height {height} {y_unit}"
            ));
        }
        if let Some(m) = self.mean_gap_text() {
            out.push(format!("mean gap {m} {u_unit}"));
        }
        if let Some(d) = &self.dead_band {
            out.push(format!(
                "dead band: the border is flat from u = {:.5} to {:.5} {u_unit} (width {:.5} {u_unit}, its ends at knots), output there {:.5} {y_unit}",
                d.from,
                d.to,
                d.width(),
                self.lti_gain * d.level
            ));
        }
        out
    }
}

fn has_std(p: &ContinuousPole) -> bool {
    match &p.mode {
        Mode::Real { tau } => tau.std.is_some(),
        Mode::Complex { wn, .. } => wn.std.is_some(),
        _ => false,
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::units::gain::tests::first_order;

    #[test]
    fn a_first_order_backlash_model_in_seconds_and_volts() {
        // z = 0.9 at ts = 0.01 s: τ = −0.01/ln 0.9 = 0.0949122 s. Borders on knots −1, 0, 1:
        // P_a = (−2.5, −0.5, 1.5), P_d = (−1.5, 0.5, 2.5): gap 0.5 wherever both are defined.
        let m = first_order(0.9, 0.1, vec![-2.5, -0.5, 1.5], vec![-1.5, 0.5, 2.5]);
        let units = Units {
            input: "V".into(),
            output: "deg".into(),
        };
        let r = m.unit_report(Some(0.01), Some(units), None, true);
        let Mode::Real { tau } = r.poles[0].mode else {
            unreachable!()
        };
        assert!((tau.value - 0.094_912_2).abs() < 1e-7, "{tau:?}");
        // Bandwidth ω = acos(1.79/1.8) rad/sample = 10.5458 rad/s.
        assert!((r.bandwidth.unwrap() - (1.79f64 / 1.8).acos() / 0.01).abs() < 1e-6);
        assert!((r.mean_gap.unwrap() - 0.5).abs() < 1e-12);
        assert_eq!(r.gap.len(), GAP_POINTS);
        // Loop height 1 in element units times G(1) = 1; cascade gain: slope 2 times 1.
        assert!((r.gap[2].loop_height - 1.0).abs() < 1e-12);
        assert!((r.cascade_gain - 2.0).abs() < 1e-12);
        let text = r.lines().join("\n");
        assert!(text.contains("time constant 0.09491 s"), "{text}");
        assert!(
            text.contains("deg per V") && text.contains("mean gap 0.50000 V"),
            "{text}"
        );
        assert!(text.starts_with("sample time 0.01 s (100 Hz)\n"), "{text}");
        assert_eq!(shortest(1.0 / 0.003), "333.333");
        assert_eq!(shortest(1.0 / 0.004), "250");
        // With its standard deviation, the gap is rounded to it.
        let with = r.with_gap_std(Some(0.00423));
        assert!(with.lines().join("\n").contains("mean gap 0.500 ± 0.004 V"));
    }

    #[test]
    fn a_value_is_rounded_to_its_uncertainty() {
        assert_eq!(rounded_pm(0.19698, 0.00423), "0.197 ± 0.004");
        assert_eq!(rounded_pm(0.19698, 0.00123), "0.1970 ± 0.0012");
        assert_eq!(rounded_pm(0.19698, 0.0299), "0.197 ± 0.030");
        assert_eq!(rounded_pm(12.345, 2.7), "12.3 ± 2.7");
        assert_eq!(rounded_pm(1234.5, 45.0), "1234 ± 45");
        assert_eq!(rounded_pm(0.2, 0.0), "0.20000 ± 0.00000");
    }

    #[test]
    fn without_a_sample_time_the_numbers_are_per_sample() {
        let m = first_order(0.9, 0.1, vec![-1.0, 1.0], vec![-1.0, 1.0]);
        // dτ/dz = 1/(0.9 ln²0.9) = 100.0921 samples per unit of z; σ_z = 1e-3.
        let r = m.unit_report(None, None, Some(&[[[1e-6, 0.0], [0.0, 0.0]]]), false);
        let text = r.lines().join("\n");
        assert!(
            text.contains("time constant 9.49122 ± 0.10009 samples"),
            "{text}"
        );
        assert!(
            text.contains("rad/sample") && !text.contains("Hz"),
            "{text}"
        );
        assert!(r.gap.is_empty() && r.mean_gap.is_none());
    }

    #[test]
    fn a_static_dead_zone_is_reported_in_units() {
        // Knots −1, −0.5, 0, 0.5, 1; flat between ±0.5; G(1) = 0.1/(1 − 0.9) = 1.
        let border = vec![-1.0, 0.0, 0.0, 0.0, 1.0];
        let m = first_order(0.9, 0.1, border.clone(), border);
        let units = Units {
            input: "V".to_string(),
            output: "rpm".to_string(),
        };
        let r = m.unit_report(Some(0.01), Some(units), None, false);
        let d = r.dead_band.unwrap();
        assert_eq!((d.from, d.to), (-0.5, 0.5));
        let text = r.lines().join("\n");
        assert!(
            text.contains("flat from u = -0.50000 to 0.50000 V (width 1.00000 V"),
            "{text}"
        );
        assert!(
            m.unit_report(Some(0.01), None, None, true)
                .dead_band
                .is_none()
        );
    }
}
