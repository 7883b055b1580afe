//! Small edges of the command line: `validate --json` holds what validate prints, validate
//! skips the hold by default as diagnose does, `--true-plant` draws into `--html` without
//! `--out`, and `fleet report` names the `DEVICE-wWEEK.bin` convention where it matters.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;

use common::{Scratch, hsid, p, servo_model};

fn examples(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/data")
        .join(name)
}

/// The number after `key ` in `line` (`NRMSE 0.1700,` gives 0.17).
fn after(line: &str, key: &str) -> f64 {
    line.split(key)
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .map(|v| v.trim_end_matches([',', '%']))
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn validate_json_holds_what_validate_prints() {
    let s = Scratch::new("validate-json");
    let model = servo_model(&s, &[]);
    let check = examples("servo-check.csv");
    let json = s.join("v.json");
    let run = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&check),
        "--json",
        p(&json),
    ])
    .success();
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["format"], "hsid-validate/1");
    let printed = run
        .stdout
        .lines()
        .find(|l| l.starts_with("simulation fit on "))
        .unwrap();
    let samples = v["samples"].as_u64().unwrap();
    assert_eq!(v["skip"], 300);
    assert_eq!(v["samples_scored"].as_u64().unwrap(), samples - 300);
    assert_eq!(after(printed, "fit on ") as u64, samples - 300);
    let sim = &v["simulation"];
    for (key, field, digits) in [
        ("RMSE ", "rmse", 1e-6),
        ("NRMSE ", "nrmse", 1e-4),
        ("fit ", "fit_percent", 1e-2),
    ] {
        let shown = after(printed.split(" samples:").nth(1).unwrap(), key);
        let stored = sim[field].as_f64().unwrap();
        assert!(
            (shown - stored).abs() <= digits,
            "{field}: {shown} vs {stored}"
        );
    }
    // The prediction fit is there exactly when validate printed one (a noise model).
    let pred = run
        .stdout
        .lines()
        .find(|l| l.starts_with("one-step prediction fit on "));
    match pred {
        Some(line) => {
            let nrmse = after(line, "NRMSE ");
            assert!((v["prediction"]["nrmse"].as_f64().unwrap() - nrmse).abs() <= 1e-4);
        }
        None => assert!(v["prediction"].is_null(), "{v}"),
    }
    assert_eq!(v["sample_time"].as_f64(), Some(0.01));
    assert_eq!(v["units"]["input"], "V");
    assert_eq!(v["units"]["output"], "deg");
    assert!(
        v["reading"]["poles"]
            .as_array()
            .is_some_and(|a| !a.is_empty())
    );
    assert!(v["warnings"].is_array());
    assert!(run.stdout.contains(&format!("wrote {}", p(&json))));
}

#[test]
fn validate_skips_the_hold_by_default_as_diagnose_does() {
    let s = Scratch::new("validate-skip");
    let model = servo_model(&s, &[]);
    let check = examples("servo-check.csv");
    let v = |extra: &[&str]| {
        let mut args = vec!["validate", "--model", p(&model), "--data", p(&check)];
        args.extend_from_slice(extra);
        hsid(&args).success().stdout
    };
    let default = v(&[]);
    assert_eq!(default, v(&["--skip", "300"]));
    assert_ne!(default, v(&["--skip", "0"]));
    let help = hsid(&["validate", "--help"]).success().stdout;
    assert!(
        help.contains("default: 300, the default --hold of identify and diagnose"),
        "{help}"
    );
    // A record no longer than the default skip says where the 300 comes from.
    let short = s.write("short.csv", "u,y\n-1,0\n");
    hsid(&["validate", "--model", p(&model), "--data", p(&short)])
        .clean_error(&["--skip 300 (the default", "leaves no samples of 1"]);
}

#[test]
fn true_plant_draws_into_the_html_report_without_out() {
    let s = Scratch::new("true-plant-html");
    let model = servo_model(&s, &[]);
    let check = examples("servo-check.csv");
    let spec = examples("servo-backlash.json");
    let page = s.join("page.html");
    let base = ["validate", "--model", p(&model), "--data", p(&check)];
    hsid(&[&base[..], &["--true-plant", p(&spec), "--html", p(&page)]].concat()).success();
    let with = std::fs::read_to_string(&page).unwrap();
    assert!(with.contains("true-asc"), "the true loop is drawn");
    hsid(&[&base[..], &["--html", p(&page)]].concat()).success();
    let without = std::fs::read_to_string(&page).unwrap();
    assert!(!without.contains("true-asc"));
    // Nothing to draw it in: refused, naming both.
    hsid(&[&base[..], &["--true-plant", p(&spec)]].concat())
        .clean_error(&["--true-plant", "give --out DIR or --html FILE"]);
}

#[test]
fn fleet_report_names_the_file_name_convention() {
    let s = Scratch::new("fleet-names");
    for help in [
        hsid(&["fleet", "report", "--help"]).success().stdout,
        hsid(&["fleet", "--help"]).success().stdout,
    ] {
        assert!(help.contains("DEVICE-wWEEK.bin"), "{help}");
    }
    // An empty directory: the solve says so, the report names the convention (no NaN %).
    let empty = s.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let models = s.join("models.jsonl");
    let run = hsid(&["fleet", "--states", p(&empty), "--out", p(&models)]).success();
    assert!(
        run.stdout
            .starts_with(&format!("no checkpoint in {}", p(&empty))),
        "{}",
        run.stdout
    );
    let truth = s.write("truth.csv", "device,week,wearing,gap,damage\n");
    let line = hsid(&[
        "fleet",
        "report",
        "--models",
        p(&models),
        "--truth",
        p(&truth),
    ])
    .clean_error(&[
        "no model of a checkpoint named DEVICE-wWEEK.bin",
        "pump17-w3.bin",
    ]);
    assert!(!line.contains("NaN"), "{line}");
    // A checkpoint under another name: the report names the convention and the fix.
    let (states, _) = common::simulate_fleet(&s, 1, 1);
    let only = std::fs::read_dir(&states)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    std::fs::rename(&only, states.join("pump.bin")).unwrap();
    hsid(&["fleet", "--states", p(&states), "--out", p(&models)]).success();
    hsid(&["fleet", "report", "--models", p(&models)]).clean_error(&[
        "device id \"pump.bin\" is not DEVICE-wWEEK.bin (e.g. pump17-w3.bin",
        "rename them",
    ]);
}
