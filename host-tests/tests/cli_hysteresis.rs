//! `hsid identify --fit simulation` through the built binary on a simulated backlash servo
//! driven by a smoothed random input (inner loops, no Table I sweeps), 20 dB: the gap it
//! prints, the model file it writes (`"element": "play"`), and `validate` and
//! `simulate --model` running that file through the play operator, against the simulator's
//! noise-free output and the noise floor. `--fit auto` (the default): the same fit, with a
//! note, on that record, and none on Table I records (the same model file as `--fit none`);
//! `--out` and `--html` with the fitted element draw the element, in `identify` and in
//! `validate` on a fresh record.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hsid_host::hysteresis::servo::{HOLD, Servo};
use hsid_host::io::parse_columns;
use hsid_host::model::MemoryElement;
use hsid_host::report::fit;
use hsid_host::table1::{count_runs, end_tolerance};

use crate::common;

use common::{Scratch, hsid, identify, p, schema_errors};

const SERVO: Servo = Servo {
    kind: MemoryElement::Play,
    width: 0.6,
    snr_db: 20.0,
};

/// The number after `key` on the first line that has it.
fn number_after(text: &str, key: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.contains(key))
        .unwrap_or_else(|| panic!("no {key:?} in:\n{text}"));
    let tail = &line[line.find(key).unwrap() + key.len()..];
    let word: String = tail
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | 'e'))
        .collect();
    word.parse()
        .unwrap_or_else(|e| panic!("cannot parse {key:?} in {line:?}: {e}"))
}

/// `identify` on the servo record `data` with the settings of these tests (the hold, 6
/// segments, order 2, f = p = 10, the subspace model starting the fit) and `extra`.
fn servo_identify(data: &std::path::Path, extra: &[&str]) -> common::Run {
    let hold = HOLD.to_string();
    let mut args = vec![
        "--hold",
        &hold,
        "--segments",
        "6",
        "--order",
        "2",
        "--f",
        "10",
        "--p",
        "10",
        "--no-refine",
    ];
    args.extend_from_slice(extra);
    identify(data, &args)
}

#[test]
fn a_backlash_fitted_by_simulation_error_validates_within_the_noise_floor() {
    let dir = Scratch::new("cli-hysteresis");
    let est = SERVO.record(3000, 1);
    let val = SERVO.record(3000, 1001);
    let data = dir.write_uy("est.csv", &est.u, &est.y);
    let check = dir.write_uy("val.csv", &val.u, &val.y);
    let model = dir.join("m.json");
    let run = servo_identify(&data, &["--fit", "simulation", "--json", p(&model)]).success();
    let out = &run.stdout;
    assert!(
        out.contains("simulation-error fit of the play operator"),
        "{out}"
    );
    // The gap within 10 % of the servo's 0.6.
    let gap = number_after(out, "fitted gap ");
    assert!((gap - 0.6).abs() < 0.06, "gap {gap}:\n{out}");
    let text = std::fs::read_to_string(&model).unwrap();
    assert!(text.contains("\"element\": \"play\""), "{text}");
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(schema_errors(&value), Vec::<String>::new(), "{text}");

    // validate runs the file through the play operator: within 1.3× the noise floor (the
    // two-path model of the same file is far off on this input, see docs/hysteresis.md).
    let floor = fit(&val.y, &val.y_clean).nrmse;
    let v = hsid(&["validate", "--model", p(&model), "--data", p(&check)]).success();
    let nrmse = number_after(&v.stdout, "NRMSE ");
    assert!(
        nrmse < 1.3 * floor,
        "NRMSE {nrmse}, floor {floor}:\n{}",
        v.stdout
    );
    assert!(nrmse > 0.9 * floor, "NRMSE {nrmse} below the floor {floor}");
    println!("validate: NRMSE {nrmse:.4}, noise floor {floor:.4}, gap {gap:.4}");

    // simulate --model gives the same model's output: close to the noise-free output.
    let s = hsid(&["simulate", "--model", p(&model), "--input", p(&check)]).success();
    let y = parse_columns("<stdout>", &s.stdout, &["y"])
        .unwrap()
        .remove(0);
    assert_eq!(y.len(), val.u.len());
    let off = fit(&val.y_clean, &y).nrmse;
    assert!(off < 0.3 * floor, "model error {off}, floor {floor}");
    println!("simulate: NRMSE against the noise-free output {off:.4}");

    // What the element's file cannot do is refused, in one line.
    hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&check),
        "--noise-snr",
        "20",
    ])
    .clean_error(&["element", "noise"]);
    // A second record that may be joined (it does not start at rest at u_min).
    let tail = dir.write_uy("tail.csv", &val.u[HOLD..], &val.y[HOLD..]);
    servo_identify(&data, &["--data", p(&tail), "--fit", "simulation"])
        .clean_error(&["--fit simulation", "one record"]);
}

/// The numeric rows of a CSV file written by `--out` (header and comment lines skipped).
fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.split(',').map(|v| v.trim().parse().ok()).collect())
        .collect()
}

/// The `(inside, runs)` counts of the `--fit auto` note.
fn auto_counts(out: &str) -> (usize, usize) {
    let line = out
        .lines()
        .find(|l| l.starts_with("--fit auto: "))
        .unwrap_or_else(|| panic!("no --fit auto note in:\n{out}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(words[3], "of", "{line}");
    (words[2].parse().unwrap(), words[4].parse().unwrap())
}

#[test]
fn the_default_fits_the_element_on_a_servo_input_and_draws_it() {
    let dir = Scratch::new("cli-hysteresis-auto");
    let est = SERVO.record(3000, 1);
    let val = SERVO.record(3000, 1001);
    let data = dir.write_uy("est.csv", &est.u, &est.y);
    let check = dir.write_uy("val.csv", &val.u, &val.y);
    let (model, figures) = (dir.join("m.json"), dir.join("fig"));
    let units = ["--ts", "0.01", "--input-unit", "V", "--output-unit", "deg"];
    let page = dir.join("page.html");
    let mut extra = vec![
        "--json",
        p(&model),
        "--out",
        p(&figures),
        "--html",
        p(&page),
    ];
    extra.extend_from_slice(&units);
    let out = servo_identify(&data, &extra).success().stdout;
    // The smoothed random input reverses inside the range on nearly every run.
    let (inside, runs) = auto_counts(&out);
    assert!(inside * 10 > runs * 9 && runs > 100, "{inside} of {runs}");
    assert!(
        out.contains("(--fit none keeps the two-path model)"),
        "{out}"
    );
    assert!(
        out.contains("simulation-error fit of the play operator"),
        "{out}"
    );
    let gap = number_after(&out, "fitted gap ");
    assert!((gap - 0.6).abs() < 0.06, "gap {gap}:\n{out}");
    // The element's reading in units: the gap of its borders in V.
    let element_part = &out[out.find("the fitted element in units:").unwrap()..];
    let mean_gap = number_after(element_part, "mean gap ");
    assert!(
        (mean_gap - gap).abs() < 0.02,
        "mean gap {mean_gap}, gap {gap}:\n{out}"
    );
    assert!(
        element_part.contains(&format!("mean gap {mean_gap:.5} V")),
        "{out}"
    );
    let text = std::fs::read_to_string(&model).unwrap();
    assert!(text.contains("\"element\": \"play\""), "{text}");
    // The HTML page is the element's: its fit, gap and reading in units as printed.
    let html = std::fs::read_to_string(&page).unwrap();
    element_page(&html, &out, fitted_fit_line(&out), gap);
    let floor = fit(&val.y, &val.y_clean).nrmse;
    let v = hsid(&["validate", "--model", p(&model), "--data", p(&check)]).success();
    let nrmse = number_after(&v.stdout, "NRMSE ");
    assert!(nrmse < 1.3 * floor, "NRMSE {nrmse}, floor {floor}");
    println!("auto: {inside} of {runs} runs inside, NRMSE {nrmse:.4}, floor {floor:.4}");

    // The figures are the element's: its gap in the sidecar and the title, units on the axes,
    // the output simulated by the play (its fit is the one printed).
    let drawn = rows(&figures.join("element.csv"))[0][0];
    assert!(
        (drawn - gap).abs() < 5e-7,
        "drawn gap {drawn}, printed {gap}"
    );
    let svg = std::fs::read_to_string(figures.join("borders.svg")).unwrap();
    assert!(svg.contains(&format!("gap {gap:.4} V")), "title");
    assert!(
        svg.contains("u [V]") && svg.contains("w [deg]"),
        "axis labels"
    );
    let knots = rows(&figures.join("borders-knots.csv"));
    let h_a = number_after(&out, "H_a: ");
    assert_eq!(knots.len(), 7, "6 segments");
    assert!(
        (knots[0][1] - h_a).abs() < 5e-7,
        "H_a(u_min) {h_a}, drawn {:?}",
        knots[0]
    );
    let simulated: Vec<f64> = rows(&figures.join("output.csv"))
        .iter()
        .map(|r| r[2])
        .collect();
    assert_eq!(simulated.len(), est.y.len());
    let printed = number_after(fitted_fit_line(&out), "NRMSE ");
    let drawn_fit = fit(&est.y[HOLD..], &simulated[HOLD..]).nrmse;
    assert!(
        (drawn_fit - printed).abs() < 1e-3,
        "drawn {drawn_fit}, printed {printed}"
    );
}

#[test]
fn table1_records_keep_the_two_path_model_bit_for_bit() {
    let dir = Scratch::new("cli-hysteresis-table1");
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    // The paper's plant under the Table I excitation, made by the binary itself.
    let excite = hsid(&[
        "excite",
        "--umin",
        "-3",
        "--umax",
        "3",
        "--samples",
        "2300",
        "--hold",
        "300",
        "--seed",
        "4",
    ])
    .success();
    let input = dir.write("input.csv", &excite.stdout);
    let plant = repo.join("examples/data/paper-backlash.json");
    let sim = hsid(&[
        "simulate",
        "--plant",
        p(&plant),
        "--input",
        p(&input),
        "--seed",
        "4",
    ]);
    let paper = dir.write("paper.csv", &sim.success().stdout);
    let servo = repo.join("examples/data/servo.csv");
    for (data, range, element) in [
        (&paper, "3", "backlash"),
        (&paper, "3", "switch"),
        (&servo, "1", "backlash"),
    ] {
        // Independently of the binary: no run after the hold starts inside the range.
        let u = &parse_columns("", &std::fs::read_to_string(data).unwrap(), &["u"]).unwrap()[0];
        let r: f64 = range.parse().unwrap();
        let runs = count_runs(&u[HOLD - 1..], -r, r, end_tolerance(-r, r));
        assert_eq!(runs.inside, 0, "{runs:?}");
        assert!(runs.runs > 10, "{runs:?}");
        let neg = format!("-{range}");
        let files = [dir.join("auto.json"), dir.join("none.json")];
        let outs: Vec<String> = [None, Some("none")]
            .iter()
            .zip(&files)
            .map(|(fit, json)| {
                let mut args = vec![
                    "identify",
                    "--data",
                    p(data),
                    "--umin",
                    &neg,
                    "--umax",
                    range,
                    "--nonlinearity",
                    element,
                    "--no-refine",
                    "--json",
                    p(json),
                ];
                if let Some(f) = fit {
                    args.extend(["--fit", f]);
                }
                hsid(&args).success().stdout
            })
            .collect();
        assert!(!outs[0].contains("--fit auto"), "{}", outs[0]);
        assert!(!outs[0].contains("simulation-error fit"), "{}", outs[0]);
        let bytes: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
        assert!(
            bytes[0] == bytes[1],
            "{} {element}: model files differ",
            data.display()
        );
        let strip = |s: &str| s.replace(p(&files[0]), "").replace(p(&files[1]), "");
        assert_eq!(strip(&outs[0]), strip(&outs[1]));
    }
}

#[test]
fn where_the_fit_cannot_run_the_default_notes_it_and_goes_on() {
    let dir = Scratch::new("cli-hysteresis-blocked");
    let est = SERVO.record(3000, 1);
    let data = dir.write_uy("est.csv", &est.u, &est.y);
    let tail = dir.write_uy("tail.csv", &est.u[2000..], &est.y[2000..]);
    let (head_u, head_y) = (&est.u[..2000], &est.y[..2000]);
    let head = dir.write_uy("head.csv", head_u, head_y);
    for (extra, why) in [
        (vec!["--stream"], "not --stream: not run"),
        (vec!["--integrating"], "with --integrating: not run"),
    ] {
        let out = servo_identify(&data, &extra).success().stdout;
        let (inside, runs) = auto_counts(&out);
        assert!(inside * 10 > runs * 9, "{inside} of {runs}");
        assert!(out.contains(why), "{out}");
        assert!(!out.contains("simulation-error fit"), "{out}");
        // Asked for explicitly, the fit is refused instead.
        let mut explicit = extra.clone();
        explicit.extend(["--fit", "simulation"]);
        servo_identify(&data, &explicit).clean_error(&["--fit simulation", extra[0]]);
    }
    let out = servo_identify(&head, &["--data", p(&tail)])
        .success()
        .stdout;
    assert!(
        out.contains("takes one record (one --data): not run"),
        "{out}"
    );
    assert!(!out.contains("simulation-error fit"), "{out}");
}

/// The simulation fit line `identify` prints after the element's fit.
fn fitted_fit_line(out: &str) -> &str {
    let fitted = &out[out.find("simulation-error fit of the").unwrap()..];
    let at = fitted.find("simulation fit on ").unwrap();
    fitted[at..].lines().next().unwrap()
}

/// The element's reading in units as `identify` prints it after the fit (from the sample
/// time to the mean gap).
fn element_units(out: &str) -> Vec<&str> {
    let part = &out[out.find("the fitted element in units:").unwrap()..];
    part.lines()
        .skip(1)
        .take_while(|l| !l.starts_with("wrote"))
        .collect()
}

/// Checks that the page `html` shows the element model: its simulation fit `fit_line`
/// (RMSE, NRMSE), the gap `gap` of the play (printed with six decimals), each line of its
/// reading in units as `identify` printed it in `out`, and the element's figure.
fn element_page(html: &str, out: &str, fit_line: &str, gap: f64) {
    let numbers = fit_line.split(':').nth(1).unwrap().trim();
    assert!(
        html.contains(numbers),
        "page without the fit {numbers:?}:\n{html}"
    );
    assert!(
        html.contains(&format!("{gap:.6}")),
        "page without gap {gap}"
    );
    assert!(html.contains("A play operator (backlash"), "sentence");
    assert!(html.contains("Play operator (backlash): borders H_a, H_d, gap"));
    let poles: Vec<&str> = element_units(out)
        .into_iter()
        .filter(|l| l.starts_with("pole ") || l.starts_with("mean gap"))
        .collect();
    assert!(!poles.is_empty(), "{out}");
    for line in poles {
        let value = line.split_once(": ").map_or(line, |p| p.1);
        let value = value.trim_start_matches("mean gap ");
        assert!(html.contains(value), "page without {value:?}");
    }
    assert!(!html.contains("two-path model it started from"));
}

#[test]
fn validate_draws_an_element_file_on_a_fresh_record() {
    let dir = Scratch::new("cli-hysteresis-validate");
    let est = SERVO.record(3000, 1);
    let val = SERVO.record(3000, 2002);
    let data = dir.write_uy("est.csv", &est.u, &est.y);
    let check = dir.write_uy("val.csv", &val.u, &val.y);
    let model = dir.join("m.json");
    let units = ["--ts", "0.01", "--input-unit", "V", "--output-unit", "deg"];
    let mut extra = vec!["--fit", "simulation", "--json", p(&model)];
    extra.extend_from_slice(&units);
    let out = servo_identify(&data, &extra).success().stdout;
    let gap = number_after(&out, "fitted gap ");
    let (figures, page) = (dir.join("fig"), dir.join("page.html"));
    let hold = HOLD.to_string();
    let validate = |model: &std::path::Path, page: &std::path::Path| {
        hsid(&[
            "validate",
            "--model",
            p(model),
            "--data",
            p(&check),
            "--skip",
            &hold,
            "--out",
            p(&figures),
            "--html",
            p(page),
        ])
        .success()
        .stdout
    };
    let v = validate(&model, &page);
    // validate reads the element in units as identify printed it after the fit.
    let printed = element_units(&out);
    let read: Vec<&str> = v
        .lines()
        .skip_while(|l| !l.starts_with("sample time"))
        .take(printed.len())
        .collect();
    assert_eq!(read, printed, "{v}");
    // The figures are the element's on the fresh record: the fitted gap, the borders of the
    // file, and the output simulated by the play, whose fit is the one validate printed.
    let drawn = rows(&figures.join("element.csv"))[0][0];
    assert!(
        (drawn - gap).abs() < 5e-7,
        "drawn gap {drawn}, printed {gap}"
    );
    let svg = std::fs::read_to_string(figures.join("borders.svg")).unwrap();
    assert!(svg.contains(&format!("gap {gap:.4} V")), "title");
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let knots = rows(&figures.join("borders-knots.csv"));
    for (i, row) in knots.iter().enumerate() {
        let h_d = file["border_desc"][i].as_f64().unwrap();
        assert!(
            (row[2] - h_d).abs() < 1e-9,
            "H_d at knot {i}: {row:?}, file {h_d}"
        );
    }
    let simulated: Vec<f64> = rows(&figures.join("output.csv"))
        .iter()
        .map(|r| r[2])
        .collect();
    assert_eq!(simulated.len(), val.y.len());
    let fit_line = v
        .lines()
        .find(|l| l.starts_with("simulation fit on "))
        .unwrap();
    let drawn_fit = fit(&val.y[HOLD..], &simulated[HOLD..]).nrmse;
    let nrmse = number_after(fit_line, "NRMSE ");
    assert!(
        (drawn_fit - nrmse).abs() < 1e-3,
        "drawn {drawn_fit}, printed {nrmse}"
    );
    let floor = fit(&val.y, &val.y_clean).nrmse;
    assert!(nrmse < 1.3 * floor, "NRMSE {nrmse}, floor {floor}");
    // The page shows the same: the fit, the gap, the reading in units, the element's figure.
    let html = std::fs::read_to_string(&page).unwrap();
    element_page(&html, &out, fit_line, gap);
    assert!(html.contains("out of sample, on the validation record"));
    println!("validate --out/--html: NRMSE {nrmse:.4}, floor {floor:.4}, gap {gap:.4}");

    // The same file without its "element" is a two-path model: its page fails those checks.
    let text = std::fs::read_to_string(&model).unwrap();
    let two_path = dir.join("two-path.json");
    std::fs::write(&two_path, text.replace(",\n  \"element\": \"play\"", "")).unwrap();
    let other = dir.join("two-path.html");
    let w = validate(&two_path, &other);
    let html = std::fs::read_to_string(&other).unwrap();
    let numbers = fit_line.split(':').nth(1).unwrap().trim();
    assert!(
        !html.contains(numbers) && !html.contains("A play operator"),
        "{w}"
    );
}
