//! The command line of the refinement: `hsid paper --method`, `hsid identify --refine`,
//! `--segments auto`, the noise model in the model file and the one-step predictions of
//! `hsid validate`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use hsid_host::io::write_columns;
use hsid_host::paper::{Case, PaperConfig, experiment};
use serde_json::Value;

use crate::common;

use common::{Scratch, hsid, identify, p};

/// The `fit … %` of the line starting with `prefix`.
fn fit_of(stdout: &str, prefix: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no {prefix:?} line in:\n{stdout}"));
    let (_, tail) = line.split_once(", fit ").unwrap();
    tail.split_whitespace().next().unwrap().parse().unwrap()
}

fn data(dir: &Scratch, case: Case, run: usize) -> PathBuf {
    let e = experiment(case, &PaperConfig::default(), run).unwrap();
    let path = dir.join(&format!("{}-{run}.csv", case.name()));
    write_columns(&path, &["u", "y"], &[&e.u, &e.y]).unwrap();
    path
}

#[test]
fn paper_method_pem_adds_the_methods_object_and_figures() {
    let dir = Scratch::new("paper");
    let out = dir.join("out");
    let r = hsid(&[
        "paper",
        "--case",
        "switch",
        "--runs",
        "6",
        "--method",
        "pem",
        "--out",
        p(&out),
    ]);
    assert!(r.ok, "{}", r.stderr);
    assert!(r.stdout.contains("| switch | pem |"), "{}", r.stdout);
    assert!(r.stdout.contains("Cramér–Rao bound"), "{}", r.stdout);
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let pem = &s["switch"]["methods"]["pem"];
    let ratio = pem["pole_std_over_crb"].as_f64().unwrap();
    assert!(ratio > 0.3 && ratio < 2.5, "{ratio}");
    // The foundation's fields are there too.
    for f in [
        "pole_std",
        "pole_bias",
        "border_rms_single_median",
        "order_counts",
    ] {
        assert!(!pem[f].is_null(), "{f}");
    }
    // The foundation's summary is unchanged around it.
    assert!(s["switch"]["pole_std"].is_array());
    for f in [
        "pem-switch-poles.svg",
        "pem-switch-bode-band.svg",
        "pem-switch-borders-band.svg",
    ] {
        let text = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(text.starts_with("<svg") || text.starts_with("<?xml"), "{f}");
    }
    // Without --method: no methods object, no refinement figures.
    let out2 = dir.join("out2");
    let r = hsid(&[
        "paper",
        "--case",
        "switch",
        "--runs",
        "3",
        "--out",
        p(&out2),
    ]);
    assert!(r.ok);
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(out2.join("summary.json")).unwrap()).unwrap();
    assert!(s["switch"].get("methods").is_none());
    assert!(!out2.join("pem-switch-poles.svg").exists());
}

#[test]
fn identify_refine_writes_the_noise_model_and_validate_predicts() {
    let dir = Scratch::new("refine");
    let est = data(&dir, Case::Backlash, 0);
    let val = data(&dir, Case::Backlash, 1);
    let model = dir.join("m.json");
    let r = identify(&est, &["--refine", "--json", p(&model)]);
    assert!(r.ok, "{}", r.stderr);
    assert!(
        r.stdout.contains("refined by the prediction-error method"),
        "{}",
        r.stdout
    );
    assert!(
        r.stdout
            .contains("noise model (innovation form): ARMA(1, 1)"),
        "{}",
        r.stdout
    );
    let sim = fit_of(&r.stdout, "simulation fit on ");
    let pred = fit_of(&r.stdout, "one-step prediction fit on ");
    assert!(
        pred > sim + 10.0,
        "prediction {pred} % vs simulation {sim} %"
    );
    // The model file holds the noise model and, refined, the standard deviations.
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let noise = &m["noise"];
    let c1 = noise["c"][1].as_f64().unwrap();
    let d1 = noise["d"][1].as_f64().unwrap();
    assert!(
        (c1 - 0.5).abs() < 0.1 && (d1 + 0.85).abs() < 0.05,
        "{noise}"
    );
    assert!(!dir.join("m.noise.json").exists());
    assert_eq!(m["format"], "hsid-model/1");
    assert_eq!(m["order"], 2);
    let re = m["poles"][0][0].as_f64().unwrap();
    assert!((re - 0.9429).abs() < 0.006, "{re}");
    // The pole's standard deviation covers its error and is of the size of the Monte Carlo's
    // (a few thousandths at this noise level).
    let sd = m["std"]["poles"][0][0].as_f64().unwrap();
    assert!(
        sd > 2e-4 && sd < 5e-3 && (re - 0.9429).abs() < 4.0 * sd,
        "{re} ± {sd}"
    );
    assert_eq!(
        m["std"]["border_asc"].as_array().unwrap().len(),
        m["border_asc"].as_array().unwrap().len()
    );
    assert_eq!(m["std"]["mu0"], m["std"]["border_asc"][0]);
    // validate on fresh data: both fits, the noise model from the model file.
    let r = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&val),
        "--skip",
        "300",
    ]);
    assert!(r.ok, "{}", r.stderr);
    let sim = fit_of(&r.stdout, "simulation fit on ");
    let pred = fit_of(&r.stdout, "one-step prediction fit on ");
    assert!(
        pred > sim + 10.0 && sim > 40.0,
        "prediction {pred} % vs simulation {sim} %"
    );
    // A bad noise file is a clean error.
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"c": [1.0, 2.0], "d": [1.0, -0.5], "sigma2": 0.1}"#,
    )
    .unwrap();
    let r = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&val),
        "--noise",
        p(&bad),
    ]);
    assert!(!r.ok);
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(
        r.stderr.starts_with("hsid: ") && r.stderr.contains("unstable predictor"),
        "{}",
        r.stderr
    );
}

#[test]
fn identify_without_refine_has_the_remark6_noise_model() {
    let dir = Scratch::new("remark6");
    let est = data(&dir, Case::Switch, 2);
    let model = dir.join("m.json");
    let r = identify(&est, &["--no-refine", "--json", p(&model)]);
    assert!(r.ok, "{}", r.stderr);
    assert!(!r.stdout.contains("refined"), "{}", r.stdout);
    let sim = fit_of(&r.stdout, "simulation fit on ");
    let pred = fit_of(&r.stdout, "one-step prediction fit on ");
    assert!(pred > sim, "prediction {pred} % vs simulation {sim} %");
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert!(m["noise"]["c"].is_array(), "{m}");
    assert!(m["std"].is_null(), "not refined: no standard deviations");
}

#[test]
fn identify_chooses_the_knot_count_when_asked() {
    let dir = Scratch::new("knots");
    let est = data(&dir, Case::Switch, 0);
    let model = dir.join("m.json");
    let r = identify(&est, &["--segments", "auto", "--json", p(&model)]);
    assert!(r.ok, "{}", r.stderr);
    let line = r
        .stdout
        .lines()
        .find(|l| l.starts_with("segments per path: "))
        .unwrap_or_else(|| panic!("{}", r.stdout));
    let n: usize = line["segments per path: ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((5..=8).contains(&n), "{line}");
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(m["knots_asc"].as_array().unwrap().len(), n + 1);
    let r = identify(&est, &["--segments", "many"]);
    assert!(!r.ok && r.stderr.contains("auto"), "{}", r.stderr);
}
