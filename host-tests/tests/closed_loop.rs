//! Closed-loop records: the feedback check on simulated backlash servos.

#![allow(clippy::unwrap_used)]

use crate::common;

use common::servo_poles::{true_pole, upper_pole};
use hsid_host::closed_loop::{ReferenceError, identify_closed_loop};
use hsid_host::closed_loop::{ServoSpec, simulate_servo};
use hsid_host::diagnose::Estimator;
use hsid_host::identify::{HostModel, IdentifyOptions, identify};
use hsid_host::validation::checks::feedback::{FeedbackTest, feedback_in_record, feedback_warning};

const SEEDS: u64 = 20;

fn options(spec: &ServoSpec) -> IdentifyOptions {
    IdentifyOptions::uniform(-3.0, 3.0, spec.knots.len() - 1, spec.hold)
}

/// The feedback test on the record of `spec` with `seed`.
fn test_record(spec: &ServoSpec, seed: u64) -> FeedbackTest {
    let servo = simulate_servo(spec, seed).unwrap();
    feedback_in_record(&servo.u, &servo.y, &options(spec))
        .unwrap()
        .unwrap()
}

#[test]
fn the_feedback_check_separates_closed_from_open_loop_servos() {
    // The same reference and noise draws per seed, with and without the controller's feedback.
    let closed = ServoSpec::paper();
    let open = closed.open_loop();
    let (mut fired_closed, mut fired_open, mut sum_open) = (0, 0, 0.0);
    for seed in 0..SEEDS {
        let (c, o) = (test_record(&closed, seed), test_record(&open, seed));
        eprintln!(
            "seed {seed:2}: closed χ² {:6.1} (lag {:2}), open χ² {:5.1} (lag {:2}), threshold {:.1}",
            c.statistic, c.lag, o.statistic, o.lag, c.threshold
        );
        if let Some(w) = feedback_warning(&c, Estimator::OpenLoop) {
            assert!(w.message.contains("hsid identify --reference-column NAME"));
        }
        fired_closed += usize::from(c.fires());
        fired_open += usize::from(o.fires());
        sum_open += o.statistic;
    }
    eprintln!(
        "fired: closed loop {fired_closed}/{SEEDS}, open loop {fired_open}/{SEEDS} (mean χ² {:.1})",
        sum_open / SEEDS as f64
    );
    assert!(
        fired_closed >= 19,
        "closed loop fired on {fired_closed}/{SEEDS}"
    );
    assert!(fired_open <= 1, "open loop fired on {fired_open}/{SEEDS}");
}

#[test]
fn a_weak_controller_is_found_less_often_than_a_strong_one() {
    // The statistic grows with the feedback gain: K_p = 0.3 against K_p = 1.5, same seeds.
    let strong = ServoSpec::paper();
    let weak = ServoSpec {
        kp: 0.3,
        feedforward: strong.feedforward + strong.kp - 0.3,
        ..strong.clone()
    };
    let mean = |s: &ServoSpec| {
        (0..5)
            .map(|seed| test_record(s, seed).statistic)
            .sum::<f64>()
            / 5.0
    };
    let (w, s) = (mean(&weak), mean(&strong));
    eprintln!("mean χ²: K_p = 0.3 {w:.1}, K_p = 1.5 {s:.1}");
    assert!(s > 3.0 * w, "weak {w}, strong {s}");
}

/// The element's borders at the knots as the two-path model sees them after the hold at
/// `u_min`: `max(atan(u − 1), atan(−2))` ascending, `min(atan(u + 1), atan(2))` descending.
fn true_borders(knots: &[f64]) -> Vec<f64> {
    let asc = knots
        .iter()
        .map(|k| (k - 1.0f64).atan().max((-2.0f64).atan()));
    let desc = knots.iter().map(|k| (k + 1.0f64).atan().min(2.0f64.atan()));
    asc.chain(desc).collect()
}

/// Mean and (sample) standard deviation.
fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

/// One estimate's errors over the seeds: upper pole (re, im), gap at `u = 0`, borders.
#[derive(Default)]
struct Errors {
    re: Vec<f64>,
    im: Vec<f64>,
    gap: Vec<f64>,
    borders: Vec<Vec<f64>>,
}

impl Errors {
    fn push(&mut self, m: &HostModel, knots: &[f64]) {
        let (p, t) = (upper_pole(m), true_pole());
        self.re.push(p.0 - t.0);
        self.im.push(p.1 - t.1);
        if let Some(g) = m.gap() {
            self.gap.push(g);
        }
        let b = m.border_asc.iter().chain(&m.border_desc);
        let t = true_borders(knots);
        self.borders.push(b.zip(&t).map(|(b, t)| b - t).collect());
    }

    /// `|mean(p̂ − p)|` of the upper pole, as a complex number.
    fn pole_bias(&self) -> f64 {
        mean_sd(&self.re).0.hypot(mean_sd(&self.im).0)
    }

    /// The largest `|mean error|` over the border values at the knots.
    fn border_bias(&self) -> f64 {
        let n = self.borders.len() as f64;
        (0..self.borders[0].len())
            .map(|k| (self.borders.iter().map(|b| b[k]).sum::<f64>() / n).abs())
            .fold(0.0, f64::max)
    }

    fn print(&self, name: &str) {
        let ((re, sre), (im, sim)) = (mean_sd(&self.re), mean_sd(&self.im));
        let (g, sg) = mean_sd(&self.gap);
        eprintln!(
            "{name}: pole bias re {re:+.4} (sd {sre:.4}) im {im:+.4} (sd {sim:.4}) |bias| {:.4}; gap {g:.3} (sd {sg:.3}, defined on {}); largest border bias {:.3}",
            self.pole_bias(),
            self.gap.len(),
            self.border_bias()
        );
    }
}

const BIAS_SEEDS: u64 = 20;

#[test]
fn the_reference_estimate_removes_the_closed_loop_bias() {
    // The servo with slowly coloured noise: the open-loop estimate's poles are biased.
    let spec = ServoSpec::coloured();
    let mut opts = options(&spec);
    opts.order = Some(2);
    let (mut open, mut closed) = (Errors::default(), Errors::default());
    for seed in 0..BIAS_SEEDS {
        let s = simulate_servo(&spec, 100 + seed).unwrap();
        open.push(&identify(&s.u, &s.y, &opts).unwrap(), &spec.knots);
        let m = identify_closed_loop(&s.u, &s.y, &s.r, &opts, 2).unwrap();
        closed.push(&m, &spec.knots);
    }
    open.print("open loop (PI-MOESP)");
    closed.print("reference (instruments from r)");
    assert!(closed.pole_bias() <= 0.01, "{}", closed.pole_bias());
    assert!(open.pole_bias() > 2.0 * closed.pole_bias());
    // The element's gap is 2 at u = 0 (both borders are exact at the knots −2, 0, 2). One
    // seed's gap has a standard deviation of about 0.3, so the mean of 20 has about 0.07:
    // 0.2 is three of those.
    let (g, _) = mean_sd(&closed.gap);
    assert!(
        closed.gap.len() >= 18,
        "gap defined on {}",
        closed.gap.len()
    );
    assert!((g - 2.0).abs() <= 0.2, "gap {g}");
}

#[test]
fn without_noise_the_reference_estimate_is_the_plant() {
    // No noise: the projected relation is exact, so the estimate is the plant up to the hold
    // not being quite settled (μ0 off by about 0.01).
    let spec = ServoSpec {
        noise_std: 0.0,
        ..ServoSpec::paper()
    };
    let mut opts = options(&spec);
    opts.order = Some(2);
    let s = simulate_servo(&spec, 3).unwrap();
    let m = identify_closed_loop(&s.u, &s.y, &s.r, &opts, 2).unwrap();
    let (p, t) = (upper_pole(&m), true_pole());
    assert!(
        (p.0 - t.0).abs() < 1e-3 && (p.1 - t.1).abs() < 1e-3,
        "{p:?}"
    );
    let b = m.border_asc.iter().chain(&m.border_desc);
    let worst = b
        .zip(true_borders(&spec.knots))
        .map(|(b, t)| (b - t).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.03, "border error {worst}");
}

#[test]
fn a_constant_or_short_reference_is_a_typed_error() {
    let spec = ServoSpec::paper();
    let mut opts = options(&spec);
    opts.order = Some(2);
    let s = simulate_servo(&spec, 1).unwrap();
    let flat = vec![0.5; s.r.len()];
    let e = identify_closed_loop(&s.u, &s.y, &flat, &opts, 2).unwrap_err();
    assert_eq!(e, ReferenceError::ConstantReference);
    assert!(e.to_string().contains("moves"));
    let e = identify_closed_loop(&s.u, &s.y, &s.r[1..], &opts, 2).unwrap_err();
    assert!(matches!(e, ReferenceError::LengthMismatch { .. }), "{e}");
    let n = spec.hold + 400;
    let e = identify_closed_loop(&s.u[..n], &s.y[..n], &s.r[..n], &opts, 2).unwrap_err();
    assert!(matches!(e, ReferenceError::TooShort { .. }), "{e}");
}

#[test]
fn hsid_identify_takes_the_reference_column() {
    let spec = ServoSpec::coloured();
    let s = simulate_servo(&spec, 7).unwrap();
    let dir = common::Scratch::new("reference-column");
    let data = dir.join("servo.csv");
    hsid_host::io::write_columns(&data, &["u", "y", "r"], &[&s.u, &s.y, &s.r]).unwrap();
    let json = dir.join("model.json");
    let fixed = [
        "--segments",
        "6",
        "--hold",
        "100",
        "--f",
        "10",
        "--p",
        "10",
        "--order",
        "2",
    ];
    let mut args = fixed.to_vec();
    args.extend(["--reference-column", "r", "--json", common::p(&json)]);
    let run = common::identify(&data, &args).success();
    eprintln!("{}", run.stdout);
    assert!(
        run.stdout
            .contains("instruments from the reference column \"r\"")
    );
    // The model written is the library's closed-loop estimate with the same options.
    let file = hsid_host::model_file::ModelFile::load(&json).unwrap();
    let mut opts = options(&spec);
    opts.order = Some(2);
    let lib = identify_closed_loop(&s.u, &s.y, &s.r, &opts, 2).unwrap();
    let (cli, lib) = (upper_pole(&HostModel::from_json(&file)), upper_pole(&lib));
    assert!((cli.0 - lib.0).abs() < 1e-9 && (cli.1 - lib.1).abs() < 1e-9);
    let t = true_pole();
    assert!((cli.0 - t.0).hypot(cli.1 - t.1) < 0.02, "{cli:?}");
    // An unknown column names the columns there are.
    let mut args = fixed.to_vec();
    args.extend(["--reference-column", "setpoint"]);
    common::identify(&data, &args).clean_error(&["no column \"setpoint\"", "\"u\", \"y\", \"r\""]);
}
