//! The linear part of a plant specification as a discrete transfer function: given directly,
//! or continuous-time sections discretised exactly by a zero-order hold (the matrix exponential
//! of the state-space form).

use nalgebra::DMatrix;

use super::error::SimulateError;
use super::spec::{LinearSpec, SectionSpec};
use crate::numerics::poly::{spectral_radius, tf_from_ss};
use crate::sim::Lti;

/// A continuous-time state-space model `(A, B, C)` with one input and one output.
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    /// `A` (`n × n`).
    pub a: DMatrix<f64>,
    /// `B` (`n × 1`).
    pub b: DMatrix<f64>,
    /// `C` (`1 × n`).
    pub c: DMatrix<f64>,
}

impl StateSpace {
    /// `wn² / (s² + 2 ζ wn s + wn²)` in controllable form.
    pub(crate) fn second_order(wn: f64, zeta: f64) -> Self {
        Self {
            a: DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -wn * wn, -2.0 * zeta * wn]),
            b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
            c: DMatrix::from_row_slice(1, 2, &[wn * wn, 0.0]),
        }
    }

    /// `1 / (τ s + 1)`.
    pub(crate) fn first_order(tau: f64) -> Self {
        Self {
            a: DMatrix::from_element(1, 1, -1.0 / tau),
            b: DMatrix::from_element(1, 1, 1.0),
            c: DMatrix::from_element(1, 1, 1.0 / tau),
        }
    }

    /// `next` after `self` (the output of `self` drives `next`).
    pub fn then(&self, next: &Self) -> Self {
        let (n1, n2) = (self.a.nrows(), next.a.nrows());
        let mut a = DMatrix::zeros(n1 + n2, n1 + n2);
        a.view_mut((0, 0), (n1, n1)).copy_from(&self.a);
        a.view_mut((n1, n1), (n2, n2)).copy_from(&next.a);
        a.view_mut((n1, 0), (n2, n1))
            .copy_from(&(&next.b * &self.c));
        let mut b = DMatrix::zeros(n1 + n2, 1);
        b.view_mut((0, 0), (n1, 1)).copy_from(&self.b);
        let mut c = DMatrix::zeros(1, n1 + n2);
        c.view_mut((0, n1), (1, n2)).copy_from(&next.c);
        Self { a, b, c }
    }

    /// Zero-order-hold discretisation at `ts`: `A_d = e^{A ts}`, `B_d = ∫₀^ts e^{A s} ds B`,
    /// both read off the exponential of `[[A, B], [0, 0]] ts`. Returns `(A_d, B_d)`.
    pub(crate) fn zoh(&self, ts: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.a.nrows();
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n)).copy_from(&(&self.a * ts));
        m.view_mut((0, n), (n, 1)).copy_from(&(&self.b * ts));
        let e = m.exp();
        (
            e.view((0, 0), (n, n)).into_owned(),
            e.view((0, n), (n, 1)).into_owned(),
        )
    }

    /// The discrete transfer function `(num, den)` in `q⁻¹` of the zero-order-hold model, with
    /// the static gain `gain` (`num[0] = 0`: one sample of delay, as a sampled plant has).
    pub(crate) fn discrete(&self, ts: f64, gain: f64) -> (Vec<f64>, Vec<f64>) {
        let (ad, bd) = self.zoh(ts);
        let c: Vec<f64> = self.c.iter().map(|v| v * gain).collect();
        let b: Vec<f64> = bd.iter().copied().collect();
        tf_from_ss(&ad, &b, &c, 0.0)
    }
}

fn positive(field: String, v: f64) -> Result<f64, SimulateError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SimulateError::OutOfRange {
            field,
            value: v,
            must: "finite and > 0",
        })
    }
}

/// One section's state space; `at` is its dotted path (`plant` or `plant.cascade[i]`).
fn section(s: &SectionSpec, at: &str) -> Result<StateSpace, SimulateError> {
    let f = |name: &str| format!("{at}.{name}");
    if let Some(tau) = s.tau {
        for (name, given) in [
            ("wn", s.wn.is_some()),
            ("fn_hz", s.fn_hz.is_some()),
            ("zeta", s.zeta.is_some()),
        ] {
            if given {
                return Err(SimulateError::Conflict {
                    field: f(name),
                    why: "a first-order section (tau) has no natural frequency or damping".into(),
                });
            }
        }
        return Ok(StateSpace::first_order(positive(f("tau"), tau)?));
    }
    let wn = match (s.wn, s.fn_hz) {
        (Some(wn), None) => positive(f("wn"), wn)?,
        (None, Some(hz)) => 2.0 * std::f64::consts::PI * positive(f("fn_hz"), hz)?,
        (Some(_), Some(_)) => {
            return Err(SimulateError::Conflict {
                field: f("fn_hz"),
                why: "give the natural frequency once, as wn (rad/s) or fn_hz (Hz)".into(),
            });
        }
        (None, None) => {
            return Err(SimulateError::Missing {
                field: f("wn"),
                why: "a second-order section needs wn (rad/s) or fn_hz (Hz); a first-order one needs tau (s)",
            });
        }
    };
    let zeta = s.zeta.ok_or(SimulateError::Missing {
        field: f("zeta"),
        why: "a second-order section needs its damping ratio",
    })?;
    if !(zeta.is_finite() && zeta >= 0.0) {
        return Err(SimulateError::OutOfRange {
            field: f("zeta"),
            value: zeta,
            must: "finite and >= 0",
        });
    }
    Ok(StateSpace::second_order(wn, zeta))
}

/// The continuous sections in series, or `None` when the plant is given in discrete time.
fn continuous(spec: &LinearSpec) -> Result<Option<StateSpace>, SimulateError> {
    let inline = spec.inline_section();
    let sections: Vec<(SectionSpec, String)> = match (&inline, &spec.cascade) {
        (Some(_), Some(_)) => {
            return Err(SimulateError::Conflict {
                field: "plant.cascade".into(),
                why: "give one section inline or all sections in the cascade, not both".into(),
            });
        }
        (Some(s), None) => vec![(s.clone(), "plant".into())],
        (None, Some(c)) => c
            .iter()
            .enumerate()
            .map(|(i, s)| (s.clone(), format!("plant.cascade[{i}]")))
            .collect(),
        (None, None) => return Ok(None),
    };
    let mut ss: Option<StateSpace> = None;
    for (s, at) in &sections {
        let next = section(s, at)?;
        ss = Some(match ss {
            Some(prev) => prev.then(&next),
            None => next,
        });
    }
    ss.map(Some).ok_or(SimulateError::Missing {
        field: "plant.cascade[0]".into(),
        why: "an empty cascade has no dynamics",
    })
}

/// The linear part as a discrete transfer function, checked stable; `ts` is the sample time
/// of the specification (required for a continuous plant).
pub fn linear_part(spec: &LinearSpec, ts: Option<f64>) -> Result<Lti, SimulateError> {
    let (num, den, field) = match (continuous(spec)?, &spec.num, &spec.den) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(SimulateError::Conflict {
                field: "plant.num".into(),
                why: "a plant is given either in discrete time (num, den) or in continuous time, not both".into(),
            });
        }
        (Some(ss), None, None) => {
            let ts = ts.ok_or(SimulateError::Missing {
                field: "ts".into(),
                why: "a continuous-time plant is discretised at the sample time (seconds)",
            })?;
            let gain = spec.gain.unwrap_or(1.0);
            if !gain.is_finite() {
                return Err(SimulateError::OutOfRange {
                    field: "plant.gain".into(),
                    value: gain,
                    must: "finite",
                });
            }
            let (num, den) = ss.discrete(ts, gain);
            (num, den, "plant")
        }
        (None, Some(num), Some(den)) => {
            if spec.gain.is_some() {
                return Err(SimulateError::Conflict {
                    field: "plant.gain".into(),
                    why: "a discrete plant's gain is in its num".into(),
                });
            }
            (num.clone(), den.clone(), "plant.den")
        }
        (None, None, _) | (None, _, None) => {
            return Err(SimulateError::Missing {
                field: if spec.num.is_some() {
                    "plant.den"
                } else {
                    "plant.num"
                }
                .into(),
                why: "a plant is num and den (discrete), or wn/fn_hz with zeta, tau, or a cascade of them (continuous, with ts)",
            });
        }
    };
    let mut num = num;
    num.splice(0..0, std::iter::repeat_n(0.0, spec.delay.unwrap_or(0)));
    transfer(num, den, field)
}

/// A stable discrete transfer function; `field` names it in errors.
pub fn transfer(num: Vec<f64>, den: Vec<f64>, field: &str) -> Result<Lti, SimulateError> {
    let lti = Lti::new(num, den).map_err(|e| SimulateError::TransferFunction {
        field: field.to_string(),
        reason: e.to_string(),
    })?;
    let radius = spectral_radius(lti.den());
    if radius.is_finite() && radius < 1.0 {
        Ok(lti)
    } else {
        Err(SimulateError::Unstable {
            field: field.to_string(),
            radius,
        })
    }
}

/// Checks a sample time: finite and positive.
pub fn sample_time(ts: Option<f64>) -> Result<Option<f64>, SimulateError> {
    ts.map(|v| positive("ts".into(), v)).transpose()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::numerics::poly::roots;

    #[test]
    fn first_order_pole_is_exp_minus_ts_over_tau() {
        let (tau, ts) = (0.05, 0.01);
        let (num, den) = StateSpace::first_order(tau).discrete(ts, 2.0);
        let p = (-ts / tau).exp();
        assert!((den[1] + p).abs() < 1e-14, "{den:?}");
        // ZOH of a first-order lag: b₁ = gain (1 − p), b₀ = 0.
        assert!(num[0].abs() < 1e-15);
        assert!((num[1] - 2.0 * (1.0 - p)).abs() < 1e-14, "{num:?}");
    }

    #[test]
    fn second_order_poles_have_the_analytic_radius_and_angle() {
        let (wn, zeta, ts) = (2.0 * std::f64::consts::PI * 3.0, 0.4, 0.01);
        let (num, den) = StateSpace::second_order(wn, zeta).discrete(ts, 1.0);
        let r = (-zeta * wn * ts).exp();
        let th = wn * (1.0 - zeta * zeta).sqrt() * ts;
        for (re, im) in roots(&den).unwrap() {
            assert!((re.hypot(im) - r).abs() < 1e-12);
            assert!((im.abs().atan2(re) - th).abs() < 1e-12);
        }
        // Unit static gain.
        let g = num.iter().sum::<f64>() / den.iter().sum::<f64>();
        assert!((g - 1.0).abs() < 1e-12, "{g}");
    }

    #[test]
    fn a_cascade_multiplies_the_poles() {
        let ss = StateSpace::first_order(0.1).then(&StateSpace::first_order(0.02));
        let (_, den) = ss.discrete(0.01, 1.0);
        let mut p: Vec<f64> = roots(&den).unwrap().iter().map(|r| r.0).collect();
        p.sort_by(f64::total_cmp);
        assert!((p[0] - (-0.5f64).exp()).abs() < 1e-12);
        assert!((p[1] - (-0.1f64).exp()).abs() < 1e-12);
    }
}
