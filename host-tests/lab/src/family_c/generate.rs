//! A scenario's records: the estimation and the validation record (each after its hold at
//! `u_min`), the diagnosis's options, and the truth.
//!
//! In closed loop the records do not carry the controller's reference: the library's
//! closed-loop estimate is for a two-path element and refuses a reference with the static
//! element the family diagnoses with ([`Record::with_reference`] would make the diagnosis
//! fail). The references are kept in [`Data::references`].

use super::class::Loop;
use super::closed_loop::Controller;
use super::design::{Design, ESTIMATION, HOLD, HORIZON, Pin, Scenario, VALIDATION};
use super::mass::Mass;
use super::noise::{noise, sigma_for, variance};
use super::servo::{Mechanics, Servo};
use hsid_host::diagnose::{DiagnoseOptions, Validation};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model::{Element as ModelElement, Record};

/// What the scenario really is.
#[derive(Clone, Debug, PartialEq)]
pub struct Truth {
    /// The design drawn from the seed.
    pub design: Design,
    /// The servo simulated (the end stop in place).
    pub servo: Servo,
    /// The controller, closed loop only.
    pub controller: Option<Controller>,
    /// The end stop's level, when there is one.
    pub stop_level: Option<f64>,
    /// Fraction of the samples after the hold at the end stop (estimation, validation).
    pub pinned: (f64, f64),
    /// The plant's order as declared to the diagnosis.
    pub declared_order: usize,
    /// Realised ratio after the holds (estimation, validation), dB.
    pub snr_realised: (f64, f64),
    /// RMS of the noise over the scored validation samples.
    pub noise_floor: f64,
}

/// A generated scenario.
#[derive(Clone, Debug)]
pub struct Data {
    /// The estimation record.
    pub record: Record,
    /// The validation record, its hold not scored.
    pub validation: Validation,
    /// The closed loop's references (estimation, validation); empty in open loop.
    pub references: Vec<Vec<f64>>,
    /// The diagnosis's options.
    pub options: DiagnoseOptions,
    /// The truth.
    pub truth: Truth,
}

/// The `q`-quantile of `x` (by sorting).
pub fn quantile(x: &[f64], q: f64) -> f64 {
    let mut v = x.to_vec();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    let i = ((v.len().saturating_sub(1)) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// The servo with its end stop at `level`.
fn with_stop(servo: &Servo, level: f64) -> Servo {
    let mechanics = match &servo.mechanics {
        Mechanics::Mass(m) => Mechanics::Mass(Mass {
            stop: Some(level),
            ..m.clone()
        }),
        other => other.clone(),
    };
    Servo {
        mechanics,
        input_play: servo.input_play,
    }
}

/// One record of the servo (the end stop, if any, at `pin`'s level): the command, the
/// noise-free output and the reading, for the command `sig` (open loop) or the reference
/// `sig` (closed loop) and the noise `v`.
fn record(
    d: &Design,
    controller: Option<&Controller>,
    pin: Option<(Pin, f64)>,
    sig: &[f64],
    v: &[f64],
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let servo = match pin {
        Some((Pin::Stop, l)) => with_stop(&d.servo, l),
        _ => d.servo.clone(),
    };
    let sensor = |y: f64, v: f64| match pin {
        Some((Pin::Sensor, l)) => (y + v).min(l),
        _ => y + v,
    };
    let (u, y) = match controller {
        None => (sig.to_vec(), servo.simulate(sig, d.ts)),
        Some(c) => c.run(&servo, d, sig, v, HOLD, &sensor),
    };
    let measured = y.iter().zip(v).map(|(&a, &b)| sensor(a, b)).collect();
    (u, y, measured)
}

/// The fraction of the samples after the hold at the end stop: the reading at the level
/// (a saturated sensor), or the position at the stop.
fn pinned_fraction(pin: Option<(Pin, f64)>, y: &[f64], measured: &[f64]) -> f64 {
    let at = match pin {
        None => 0,
        Some((Pin::Sensor, l)) => measured[HOLD..].iter().filter(|&&m| m >= l).count(),
        Some((Pin::Stop, l)) => y[HOLD..].iter().filter(|&&a| a >= l).count(),
    };
    at as f64 / (y.len() - HOLD).max(1) as f64
}

/// Bisections of the end stop's level.
const LEVEL_BISECTIONS: usize = 30;

/// Simulates a scenario. The end stop's level is set by bisection so that the estimation
/// record (with its noise, and in closed loop with the controller pushing into the stop) is
/// pinned in the design's fraction of its samples.
pub fn generate(s: &Scenario) -> Data {
    let d = s.design();
    let controller = Controller::tune(&d);
    let lens = [ESTIMATION, VALIDATION];
    let tau = d.tau_samples();
    // The commands (open loop) or the references (closed loop), each after the hold.
    let signals: Vec<Vec<f64>> = lens
        .iter()
        .enumerate()
        .map(|(k, &len)| {
            let mut rng = s.rng(2 + k as u64);
            match &controller {
                None => d
                    .input
                    .generate(&mut rng, d.range, HOLD, len, tau, d.level_hold),
                Some(c) => {
                    let mut r =
                        d.input
                            .generate(&mut rng, c.reference_range(&d), HOLD, len, tau, 1);
                    let rest = d.servo.output(&d.servo.rest(d.range.0));
                    r[..HOLD].iter_mut().for_each(|v| *v = rest);
                    r
                }
            }
        })
        .collect();
    // The estimation record without noise and end stop: the noise's level.
    let (_, free, _) = record(&d, controller.as_ref(), None, &signals[0], &[]);
    let free = &free[..signals[0].len()];
    let sigma = sigma_for(variance(&free[HOLD..]), d.snr_db);
    let noises: Vec<Vec<f64>> = signals
        .iter()
        .enumerate()
        .map(|(k, sig)| noise(&mut s.rng(4 + k as u64), d.colour, sigma, sig.len()))
        .collect();
    let pin = d.pin.map(|(kind, target)| {
        let fraction = |l: f64| {
            let (_, y, m) = record(
                &d,
                controller.as_ref(),
                Some((kind, l)),
                &signals[0],
                &noises[0],
            );
            pinned_fraction(Some((kind, l)), &y, &m)
        };
        let top = free.iter().cloned().fold(f64::MIN, f64::max) + 3.0 * sigma;
        let (mut lo, mut hi) = (quantile(&free[HOLD..], 0.3), top);
        for _ in 0..LEVEL_BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if fraction(mid) > target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (kind, hi)
    });
    let mut records = Vec::new();
    let mut pinned = Vec::new();
    let mut snr = Vec::new();
    let mut floor = 0.0;
    for (k, (sig, v)) in signals.iter().zip(&noises).enumerate() {
        let (u, y, measured) = record(&d, controller.as_ref(), pin, sig, v);
        pinned.push(pinned_fraction(pin, &y, &measured));
        snr.push(10.0 * (variance(&y[HOLD..]) / variance(&v[HOLD..])).log10());
        if k == 1 {
            let n = (v.len() - HOLD) as f64;
            floor = (v[HOLD..].iter().map(|x| x * x).sum::<f64>() / n).sqrt();
        }
        records.push(Record::from_samples(u.into_iter().zip(measured)));
    }
    let validation = records.pop().unwrap_or_else(|| Record::from_samples([]));
    let record = records.pop().unwrap_or_else(|| Record::from_samples([]));
    let stop_level = pin.map(|(_, l)| l);
    let truth = Truth {
        declared_order: d.servo.order(),
        servo: match pin {
            Some((Pin::Stop, l)) => with_stop(&d.servo, l),
            _ => d.servo.clone(),
        },
        controller,
        stop_level,
        pinned: (pinned[0], pinned[1]),
        snr_realised: (snr[0], snr[1]),
        noise_floor: floor,
        design: d,
    };
    Data {
        options: options(&truth, s.lp),
        record,
        validation: Validation::Separate {
            record: validation,
            skip: HOLD,
        },
        references: match truth.controller {
            Some(_) => signals,
            None => Vec::new(),
        },
        truth,
    }
}

/// The diagnosis's options: a static element on uniform knots over the command's range
/// ([`Design::segments`]), the declared order, horizons [`HORIZON`], the hold.
pub fn options(t: &Truth, lp: Loop) -> DiagnoseOptions {
    let d = &t.design;
    let mut id = IdentifyOptions::uniform(d.range.0, d.range.1, d.segments(lp), HOLD);
    id.order = Some(t.declared_order);
    id.f = HORIZON;
    id.p = HORIZON;
    DiagnoseOptions::new(id, ModelElement::Static)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family_c::class::Class;

    #[test]
    fn records_have_their_holds_and_the_asked_noise() {
        let mut pins = Vec::new();
        for (class, lp, seed) in [
            (Class::Clean, Loop::Open, 2),
            (Class::EndStop, Loop::Open, 1),
            (Class::EndStop, Loop::Open, 2),
            (Class::EndStop, Loop::Closed, 1),
            (Class::EndStop, Loop::Closed, 2),
            (Class::Friction, Loop::Closed, 2),
        ] {
            let s = Scenario::new(class, lp, seed);
            let data = generate(&s);
            assert_eq!(data.record.len(), HOLD + ESTIMATION);
            let lo = data.truth.design.range.0;
            assert!(data.record.u[..HOLD].iter().all(|&u| u == lo));
            let (a, b) = data.truth.snr_realised;
            let want = data.truth.design.snr_db;
            assert!(
                (a - want).abs() < 3.0 && (b - want).abs() < 6.0,
                "{class:?}: {a} {b} {want}"
            );
            if let Some(l) = data.truth.stop_level {
                let top = data.record.y.iter().cloned().fold(f64::MIN, f64::max);
                if data.truth.design.pin.map(|p| p.0) == Some(Pin::Sensor) {
                    assert_eq!(top, l);
                }
                // The level is set so that the estimation record is pinned as designed.
                pins.extend(data.truth.design.pin.map(|p| p.0));
                let want = data.truth.design.level;
                assert!(
                    (data.truth.pinned.0 - want).abs() < 0.01,
                    "{:?} {want}",
                    data.truth.pinned
                );
            }
        }
        assert!(pins.contains(&Pin::Sensor) && pins.contains(&Pin::Stop));
    }

    #[test]
    fn quantile_picks_by_rank() {
        let x = [5.0, 1.0, 3.0, 2.0, 4.0];
        assert_eq!(quantile(&x, 0.0), 1.0);
        assert_eq!(quantile(&x, 0.5), 3.0);
        assert_eq!(quantile(&x, 1.0), 5.0);
    }
}
