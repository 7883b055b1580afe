//! An input that leaves a model's interval: by default the borders continue linearly on the
//! lines through their two end knots (a two-path model and a play both), the samples outside
//! are counted in one note, and the strict flag refuses with the message it always gave.
//! Checked against values worked out here by hand: the output while the input stays inside
//! equals the strict simulation of that part, and held beyond the interval the output settles
//! on the line through the end knots (the linear part has unit static gain).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use hsid_host::hysteresis::HysteresisModel;
use hsid_host::hysteresis::simulate::simulate as simulate_element;
use hsid_host::identify::HostModel;
use hsid_host::io::parse_columns;
use hsid_host::model::{Element, MemoryElement, Simulate, Syntax, for_input};
use hsid_host::simulate::{InputRecord, ModelOptions, SimulateError, simulate_model};

use crate::common;

use common::{Scratch, hsid, p};

const KNOTS: [f64; 3] = [-1.0, 0.0, 1.0];
const ASC: [f64; 3] = [-1.2, -0.1, 0.8];
const DESC: [f64; 3] = [-0.8, 0.1, 1.2];
/// Samples at the start that stay inside [-1, 1].
const INSIDE: usize = 60;

/// The value at `u` on the line through `(k0, v0)` and `(k1, v1)`.
fn line(k0: f64, v0: f64, k1: f64, v1: f64, u: f64) -> f64 {
    v0 + (v1 - v0) * (u - k0) / (k1 - k0)
}

/// 10 samples held at u_min, 50 inside, then 40 at 1.5, 5 at 1.4 and 40 at -1.4: 85 of 145
/// samples outside [-1, 1].
fn input() -> Vec<f64> {
    let mut u = vec![-1.0; 10];
    u.extend((0..50).map(|t| 0.9 * (0.2 * t as f64).sin()));
    u.extend([1.5; 40]);
    u.extend([1.4; 5]);
    u.extend([-1.4; 40]);
    u
}

fn record(u: &[f64]) -> InputRecord {
    InputRecord {
        source: PathBuf::from("u.csv"),
        u: u.to_vec(),
        t: None,
        lines: (2..u.len() + 2).collect(),
    }
}

/// Two paths on [-1, 1], then `G = 0.5 / (z − 0.5)` (unit static gain), at rest on the
/// descending border at u_min.
fn two_path() -> HostModel {
    HostModel {
        order: 1,
        a: nalgebra::DMatrix::from_element(1, 1, 0.5),
        b: vec![1.0],
        c: vec![0.5],
        d: 0.0,
        mu0: DESC[0],
        knots_asc: KNOTS.to_vec(),
        knots_desc: KNOTS.to_vec(),
        border_asc: ASC.to_vec(),
        border_desc: DESC.to_vec(),
        singular_values: vec![],
        whitened_singular_values: vec![],
        f: 1,
        p: 1,
        samples: 0,
    }
}

/// A play on the same borders and the same `G`, resting at the descending border's u_min.
fn play() -> HysteresisModel {
    HysteresisModel {
        kind: MemoryElement::Play,
        f: vec![1.0, -0.5],
        b: vec![0.0, 0.5],
        feedthrough: false,
        knots: KNOTS.to_vec(),
        border_asc: ASC.to_vec(),
        border_desc: DESC.to_vec(),
        w0: DESC[0],
    }
}

const NOTE: &str = "85 of 145 samples (58.62 %) lie outside the model's interval [-1, 1] \
                    (lowest -1.4, highest 1.5): the borders are extended linearly beyond it";

fn close(a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= tol, "sample {i}: {x} against {y}");
    }
}

/// The borders' lines beyond the ends, by hand.
fn asc_above(u: f64) -> f64 {
    line(KNOTS[1], ASC[1], KNOTS[2], ASC[2], u)
}
fn desc_below(u: f64) -> f64 {
    line(KNOTS[0], DESC[0], KNOTS[1], DESC[1], u)
}

#[test]
fn a_two_path_model_continues_its_borders_beyond_the_interval() {
    let m = two_path();
    let u = input();
    let (out, outside) = simulate_model(&m, None, &record(&u), &ModelOptions::default()).unwrap();
    let outside = outside.expect("the input leaves the interval");
    assert_eq!((outside.count, outside.total), (85, 145));
    assert_eq!(
        outside.note(Syntax::Cli),
        format!("{NOTE} (--strict-interval refuses instead)")
    );
    assert_eq!(
        outside.note(Syntax::Python),
        format!("{NOTE} (strict_interval=True refuses instead)")
    );
    // Inside, the output is the strict simulation of the part that never left (the hold at
    // u_min on the descending border included).
    let strict = ModelOptions {
        strict_interval: true,
        ..ModelOptions::default()
    };
    let (inside, none) = simulate_model(&m, None, &record(&u[..INSIDE]), &strict).unwrap();
    assert_eq!(none, None);
    close(&out.y[..INSIDE], &inside.y, 1e-12);
    assert!((out.y[0] - DESC[0]).abs() < 1e-12, "{}", out.y[0]);
    // Held at 1.5 the output settles on the ascending line (1.25), held at -1.4 on the
    // descending one (-1.16).
    assert!((asc_above(1.5) - 1.25).abs() < 1e-12);
    assert!((out.y[99] - asc_above(1.5)).abs() < 1e-9, "{}", out.y[99]);
    assert!(
        (out.y[144] - desc_below(-1.4)).abs() < 1e-9,
        "{}",
        out.y[144]
    );
    // The extended borders themselves.
    let (e, _) = for_input(&m, &u);
    assert_eq!(e.u_start, -1.0);
    assert!((e.model.border_asc_at(1.5) - 1.25).abs() < 1e-12);
    assert!((e.model.border_desc_at(-1.4) - desc_below(-1.4)).abs() < 1e-12);
    assert!((e.model.border_desc_at(1.5) - line(0.0, 0.1, 1.0, 1.2, 1.5)).abs() < 1e-12);
    // Strict: refused with the message it always gave, at the first sample outside.
    let err = simulate_model(&m, None, &record(&u), &strict).unwrap_err();
    assert!(matches!(
        err,
        SimulateError::InputOutsideModel { line: 62, .. }
    ));
    assert_eq!(
        err.to_string(),
        "u.csv line 62: u = 1.5 lies outside the model's interval [-1, 1]; keep the input inside it or pass --extrapolate"
    );
}

#[test]
fn a_play_keeps_its_gap_beyond_the_interval() {
    let h = play();
    let u = input();
    let (e, outside) = for_input(&h, &u);
    assert_eq!(outside.map(|o| (o.count, o.total)), Some((85, 145)));
    // One set of knots for both borders, the added ones too.
    assert_eq!(e.model.knots, vec![-1.4, -1.0, 0.0, 1.0, 1.5]);
    assert!((e.model.border_asc[4] - asc_above(1.5)).abs() < 1e-12);
    assert!((e.model.border_desc[0] - desc_below(-1.4)).abs() < 1e-12);
    let y = e.simulate(&u);
    close(&y[..INSIDE], &simulate_element(&h, &u[..INSIDE]), 1e-12);
    // Up to 1.5: on the ascending line. Back to 1.4: inside the gap (the descending line is
    // at 1.64 there), the output holds. Down to -1.4: on the descending line.
    assert!((y[99] - 1.25).abs() < 1e-9, "{}", y[99]);
    assert!(line(0.0, 0.1, 1.0, 1.2, 1.4) > 1.25 + 0.3);
    assert!((y[104] - 1.25).abs() < 1e-9, "{}", y[104]);
    assert!((y[144] - desc_below(-1.4)).abs() < 1e-9, "{}", y[144]);
}

/// The model files of both models, the input and a record `u, y` with `y` the model's own
/// extended output.
fn files(s: &Scratch) -> (PathBuf, PathBuf, PathBuf, PathBuf, Vec<f64>, Vec<f64>) {
    let u = input();
    let mut text = String::from("u\n");
    for v in &u {
        text.push_str(&format!("{v}\n"));
    }
    let input = s.write("u.csv", &text);
    let two = two_path().to_json(Some(Element::Backlash));
    let two = s.write("two.json", &two.to_json_string("two.json").unwrap());
    let mut el = play()
        .to_host(145)
        .to_json(Some(MemoryElement::Play.element()));
    el.element = Some(MemoryElement::Play);
    let el = s.write("play.json", &el.to_json_string("play.json").unwrap());
    let y_two = for_input(&two_path(), &u).0.simulate(&u);
    let y_play = for_input(&play(), &u).0.simulate(&u);
    (
        input,
        two,
        el,
        s.write_uy("uy.csv", &u, &y_two),
        y_two,
        y_play,
    )
}

#[test]
fn simulate_and_validate_extend_by_default_and_refuse_when_strict() {
    let s = Scratch::new("outside-interval");
    let (input, two, el, uy, y_two, y_play) = files(&s);
    let note = format!("{NOTE} (--strict-interval refuses instead)");
    for (model, y) in [(&two, &y_two), (&el, &y_play)] {
        let run = hsid(&["simulate", "--model", p(model), "--input", p(&input)]).success();
        assert!(
            run.stdout.contains(&format!("# note: {note}\n")),
            "{}",
            run.stdout
        );
        let got = parse_columns("<stdout>", &run.stdout, &["y"])
            .unwrap()
            .remove(0);
        close(&got, y, 1e-9);
        let strict = hsid(&[
            "simulate",
            "--model",
            p(model),
            "--input",
            p(&input),
            "--strict-interval",
        ]);
        strict.clean_error(&["u.csv line 62: u = 1.5 lies outside the model's interval [-1, 1]"]);
    }
    // The play's file: --extrapolate names the default, the noise options stay refused.
    let run = hsid(&[
        "simulate",
        "--model",
        p(&el),
        "--input",
        p(&input),
        "--extrapolate",
    ])
    .success();
    assert!(run.stdout.contains("# note: 85 of 145"), "{}", run.stdout);
    hsid(&[
        "simulate",
        "--model",
        p(&el),
        "--input",
        p(&input),
        "--noise-snr",
        "20",
    ])
    .clean_error(&["element", "noise"]);

    // validate: the note before the fit, and the model's own extended output fits it exactly
    // (every sample scored: the record has no hold to skip).
    let run = hsid(&[
        "validate",
        "--model",
        p(&two),
        "--data",
        p(&uy),
        "--skip",
        "0",
    ])
    .success();
    let first = run.stdout.lines().next().unwrap_or_default();
    assert_eq!(first, format!("note: {note}"), "{}", run.stdout);
    assert!(run.stdout.contains("fit 100.00 %"), "{}", run.stdout);
    hsid(&[
        "validate",
        "--model",
        p(&two),
        "--data",
        p(&uy),
        "--skip",
        "0",
        "--strict-interval",
    ])
    .clean_error(&["uy.csv line 62: u = 1.5 lies outside the model's interval [-1, 1]"]);
    let run = hsid(&[
        "validate",
        "--model",
        p(&el),
        "--data",
        p(&uy),
        "--skip",
        "0",
    ])
    .success();
    assert!(
        run.stdout.starts_with(&format!("note: {note}")),
        "{}",
        run.stdout
    );
    hsid(&[
        "validate",
        "--model",
        p(&el),
        "--data",
        p(&uy),
        "--skip",
        "0",
        "--strict-interval",
    ])
    .clean_error(&["uy.csv line 62: u = 1.5 lies outside the model's interval [-1, 1]"]);
}
