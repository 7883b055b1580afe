//! Input the command line used to accept although it is wrong, or panicked on: each is now
//! refused with one line that says what was wrong and what to do (a clap error at the flag
//! for a number that is not finite), before any work, and never with a panic or a message that
//! blames something else.
#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common;

use std::path::PathBuf;

use common::{Run, Scratch, hsid, p, servo, servo_args, servo_model};

/// A model of the servo record written by `hsid identify --json` (with units), in `dir`.
fn identified(dir: &Scratch) -> PathBuf {
    let units = [
        "--segments",
        "3",
        "--input-unit",
        "V",
        "--output-unit",
        "deg",
    ];
    servo_model(dir, &units)
}

/// `hsid validate` of the model file `name` (`text`, written to `dir`) on the servo record.
fn validate_text(dir: &Scratch, name: &str, text: &str) -> Run {
    let model = dir.write(name, text);
    let data = servo();
    hsid(&["validate", "--model", p(&model), "--data", p(&data)])
}

/// The model file `text` with `edit` applied to its JSON object.
fn edited(text: &str, edit: impl FnOnce(&mut serde_json::Value)) -> String {
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    edit(&mut v);
    serde_json::to_string_pretty(&v).unwrap()
}

/// The file's plant replaced by a first-order one `x+ = a x + b v, y = c x`, its poles
/// `poles` (its standard deviations dropped).
fn first_order(v: &mut serde_json::Value, a: f64, b: f64, poles: &[f64]) {
    v["order"] = serde_json::json!(1);
    v["A"] = serde_json::json!([[a]]);
    v["B"] = serde_json::json!([b]);
    v["C"] = serde_json::json!([1.0 - a]);
    v["D"] = serde_json::json!(0.0);
    v["poles"] = poles.iter().map(|&r| serde_json::json!([r, 0.0])).collect();
    v["std"] = serde_json::Value::Null;
}

/// A clap refusal of a flag's value: exit code 2, the flag and the value named, no panic.
fn refused_at_flag(run: &Run, flag: &str, value: &str) {
    let ctx = format!("hsid {}\nstderr:\n{}", run.args, run.stderr);
    assert_eq!(run.code, Some(2), "{ctx}");
    assert!(!run.stderr.contains("panicked"), "{ctx}");
    let first = run.stderr.lines().next().unwrap_or_default();
    assert!(
        first.contains(&format!("invalid value '{value}' for '{flag}"))
            && first.contains("not a finite number"),
        "{ctx}"
    );
}

#[test]
fn a_hold_longer_than_the_record_is_refused_by_diagnose_as_by_identify() {
    let hold = usize::MAX.to_string();
    let diagnose = hsid(&servo_args("diagnose", &["--hold", &hold]));
    let line = diagnose.clean_error(&["servo.csv", "all inside the hold", "(--hold)", &hold]);
    let identify = hsid(&servo_args("identify", &["--hold", &hold]));
    assert_eq!(
        identify.clean_error(&[]),
        line,
        "the same check, the same line"
    );
}

#[test]
fn horizons_and_delays_near_the_largest_count_are_refused_not_overflowed() {
    let huge = usize::MAX.to_string();
    let f = hsid(&servo_args("diagnose", &["--f", &huge]));
    f.clean_error(&["samples are too few"]);
    let delay = hsid(&servo_args("diagnose", &["--max-delay", &huge]));
    delay.clean_error(&["--max-delay", &huge]);
}

#[test]
fn a_number_flag_that_is_not_finite_is_refused_at_the_flag() {
    let dir = Scratch::new("nan-flags");
    let data = servo();
    let out = dir.join("states");
    let truth = dir.join("truth.csv");
    let fleet = hsid(&[
        "fleet",
        "simulate",
        "--devices",
        "1",
        "--weeks",
        "1",
        "--noise",
        "NaN",
        "--out",
        p(&out),
        "--truth",
        p(&truth),
    ]);
    refused_at_flag(&fleet, "--noise", "NaN");
    assert!(!out.exists(), "nothing is written");
    let diagnose = hsid(&["diagnose", "--data", p(&data), "--min-gain", "NaN"]);
    refused_at_flag(&diagnose, "--min-gain", "NaN");
    let mu0 = hsid(&servo_args("identify", &["--mu0", "inf"]));
    refused_at_flag(&mu0, "--mu0", "inf");
    let knots = hsid(&["diagnose", "--data", p(&data), "--knots=-1,NaN,1"]);
    refused_at_flag(&knots, "--knots", "NaN");

    // A model and an input for `simulate`: --noise-snr NaN is the flag's fault, not the
    // output's.
    let model = identified(&dir);
    let input = dir.write("u.csv", "u\n0\n0.5\n1\n");
    let snr = hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&input),
        "--noise-snr",
        "NaN",
    ]);
    refused_at_flag(&snr, "--noise-snr", "NaN");
    assert!(!snr.stderr.contains("<stdout>"), "{}", snr.stderr);
}

#[test]
fn a_unit_with_a_double_quote_or_a_control_character_is_refused_before_any_work() {
    let dir = Scratch::new("unit-chars");
    let data = servo();
    let html = dir.join("r.html");
    let base = [
        "identify",
        "--data",
        p(&data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--html",
        p(&html),
    ];
    let quote = hsid(&[&base[..], &["--input-unit", "V\"", "--output-unit", "deg"]].concat());
    quote.clean_error(&["--input-unit", "double quote"]);
    assert!(
        quote.stdout.is_empty(),
        "no work before the refusal: {}",
        quote.stdout
    );
    assert!(!html.exists());
    let newline = hsid(&[&base[..], &["--input-unit", "V", "--output-unit", "de\ng"]].concat());
    newline.clean_error(&["--output-unit", "U+000A"]);

    // The same characters in a record's unit comment: the record is named.
    let text = std::fs::read_to_string(&data).unwrap();
    let commented = dir.write(
        "commented.csv",
        &format!("# input unit = V\n# output unit = d\"eg\n{text}"),
    );
    let comment = hsid(&[
        "identify",
        "--data",
        p(&commented),
        "--umin",
        "-1",
        "--umax",
        "1",
    ]);
    comment.clean_error(&["commented.csv line 2", "output unit", "double quote"]);
}

#[test]
fn a_model_file_that_is_unstable_unbounded_or_inconsistent_is_refused_on_reading() {
    let dir = Scratch::new("model-checks");
    let model = identified(&dir);
    let text = std::fs::read_to_string(&model).unwrap();
    // hsid's own file reads back, its poles within the tolerance.
    validate_text(&dir, "own.json", &text).success();

    let unstable = edited(&text, |v| first_order(v, 1.5, 1.0, &[1.5]));
    let run = validate_text(&dir, "unstable.json", &unstable);
    let line = run.clean_error(&["unstable.json", "\"A\"", "modulus 1.5", "stable"]);
    assert!(!line.contains("constant"), "{line}");

    let huge = edited(&text, |v| first_order(v, 0.5, 1e308, &[0.5]));
    validate_text(&dir, "huge.json", &huge).clean_error(&["huge.json", "\"B\"", "1e150"]);

    let stale = edited(&text, |v| first_order(v, 0.5, 1.0, &[0.9]));
    validate_text(&dir, "stale.json", &stale).clean_error(&[
        "stale.json",
        "\"poles\"",
        "eigenvalue",
    ]);

    // An integrating model's A is its stable part: stable, its pole at 1 not stored.
    let integrating = edited(&text, |v| {
        first_order(v, 0.5, 1.0, &[0.5]);
        v["integrating"] = serde_json::json!(true);
        v["noise"] = serde_json::Value::Null;
    });
    validate_text(&dir, "integrating.json", &integrating).success();
    let with_unit_root = edited(&integrating, |v| first_order(v, 1.0, 1.0, &[1.0]));
    validate_text(&dir, "root.json", &with_unit_root).clean_error(&[
        "root.json",
        "\"A\"",
        "stable part G0",
    ]);

    let quoted = edited(&text, |v| v["units"]["input"] = serde_json::json!("V\""));
    validate_text(&dir, "quoted.json", &quoted).clean_error(&[
        "quoted.json",
        "\"units\"",
        "double quote",
    ]);
}

#[test]
fn a_key_repeated_in_a_model_file_is_refused_at_any_depth() {
    let dir = Scratch::new("model-duplicates");
    let model = identified(&dir);
    let text = std::fs::read_to_string(&model).unwrap();
    assert!(
        text.contains("\"D\":") && text.contains("\"input\":"),
        "{text}"
    );
    let top = text.replacen("\"D\":", "\"D\": 100, \"D\":", 1);
    validate_text(&dir, "top.json", &top).clean_error(&["top.json", "key \"D\"", "twice"]);
    let nested = text.replacen("\"input\":", "\"input\": \"A\", \"input\":", 1);
    validate_text(&dir, "nested.json", &nested).clean_error(&[
        "nested.json",
        "key \"units.input\"",
        "twice",
    ]);
}

#[cfg(unix)]
#[test]
fn fleet_names_what_it_skips_and_shows_names_that_are_not_utf8_apart() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;

    let dir = Scratch::new("fleet-listing");
    let states = dir.join("states");
    std::fs::create_dir_all(states.join("sub")).unwrap();
    for name in [&b"dev\xff.bin"[..], &b"dev\xfe.bin"[..]] {
        std::fs::write(states.join(OsStr::from_bytes(name)), b"not a checkpoint").unwrap();
    }
    let out = dir.join("models.jsonl");
    let run = hsid(&["fleet", "--states", p(&states), "--out", p(&out)]).success();
    assert!(run.stdout.starts_with("2 devices"), "{}", run.stdout);
    let note = run
        .stdout
        .lines()
        .find(|l| l.starts_with("note:"))
        .unwrap_or_else(|| panic!("no note of the subdirectory: {}", run.stdout));
    assert!(
        note.contains("skipped sub") && note.contains("subdirector"),
        "{note}"
    );
    let devices: Vec<String> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            v["device"].as_str().unwrap().to_string()
        })
        .collect();
    assert_eq!(devices, ["dev\\xFE.bin", "dev\\xFF.bin"]);
}

#[test]
fn a_segment_count_near_the_largest_count_is_refused_not_allocated() {
    let data = servo();
    let huge = usize::MAX.to_string();
    let base = ["--data", p(&data), "--umin", "-1", "--umax", "1"];
    let identify = hsid(&[&["identify"][..], &base[..], &["--segments", &huge]].concat());
    identify.clean_error(&["--segments", &huge, "give fewer"]);
    let diagnose = hsid(&[&["diagnose"][..], &base[..], &["--segments", &huge]].concat());
    diagnose.clean_error(&["--segments", &huge, "give fewer"]);
    let range = format!("1..{huge}");
    let select = hsid(&[&["diagnose"][..], &base[..], &["--select-segments", &range]].concat());
    select.clean_error(&["--select-segments", &range]);
}
