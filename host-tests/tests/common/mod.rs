//! Helpers shared by the command-line tests: a scratch folder per test and a runner for the
//! built `hsid` binary that captures its exit status and output.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, dead_code)]

pub mod servo_poles;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use hsid_host::io::write_columns;
use quick_xml::Reader;
use quick_xml::events::Event;
use std::collections::BTreeSet;

/// A fresh scratch folder under the system temp dir, unique per test, removed on drop.
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(test: &str) -> Self {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "hsid-test-{}-{}-{test}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes `text` to `name` in the folder and returns its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    /// Writes `u,y` columns to `name` in the folder and returns its path.
    pub fn write_uy(&self, name: &str, u: &[f64], y: &[f64]) -> PathBuf {
        let path = self.join(name);
        write_columns(&path, &["u", "y"], &[u, y]).unwrap();
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// What a run of the binary produced.
pub struct Run {
    pub ok: bool,
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub args: String,
}

impl Run {
    /// Asserts a zero exit status and returns `self`.
    pub fn success(self) -> Self {
        assert!(
            self.ok,
            "hsid {} failed with {:?}\nstdout:\n{}\nstderr:\n{}",
            self.args, self.code, self.stdout, self.stderr
        );
        self
    }

    /// Asserts the run failed cleanly: non-zero exit, a single stderr line starting with
    /// `hsid:` that contains every string of `needles`, and no panic or backtrace.
    /// Returns the stderr line. The stages a run over a second shows (`hsid: [1.0 s] …`,
    /// [`is_progress`]) are not that line: how long a run takes is not what it says.
    pub fn clean_error(&self, needles: &[&str]) -> String {
        let ctx = format!(
            "hsid {}\nexit {:?}\nstdout:\n{}\nstderr:\n{}",
            self.args, self.code, self.stdout, self.stderr
        );
        assert!(!self.ok, "expected a failure: {ctx}");
        assert_eq!(self.code, Some(1), "expected exit code 1: {ctx}");
        let lower = self.stderr.to_lowercase();
        assert!(!lower.contains("panicked"), "panic: {ctx}");
        assert!(!lower.contains("backtrace"), "backtrace: {ctx}");
        let lines: Vec<&str> = self.stderr.lines().filter(|l| !is_progress(l)).collect();
        assert_eq!(lines.len(), 1, "expected one stderr line: {ctx}");
        let line = lines[0];
        assert!(
            line.starts_with("hsid: "),
            "stderr must start with `hsid: `: {ctx}"
        );
        for n in needles {
            assert!(line.contains(n), "stderr should mention {n:?}: {ctx}");
        }
        line.to_string()
    }
}

/// Whether `line` is a stage line of the progress a run over a second shows on standard error
/// when it is not a terminal: `hsid: [<seconds> s] <stage>`.
pub fn is_progress(line: &str) -> bool {
    line.strip_prefix("hsid: [")
        .and_then(|rest| rest.split_once(" s] "))
        .is_some_and(|(secs, _)| secs.parse::<f64>().is_ok())
}

/// Runs the `hsid` binary with `args`.
pub fn hsid<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE")
        .output()
        .expect("cannot run the hsid binary");
    let run = Run {
        ok: out.status.success(),
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).expect("stdout is not UTF-8"),
        stderr: String::from_utf8(out.stderr).expect("stderr is not UTF-8"),
        args: args
            .iter()
            .map(|a| a.as_ref().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join(" "),
    };
    assert!(
        !run.stderr.contains("panicked"),
        "hsid {} panicked:\n{}",
        run.args,
        run.stderr
    );
    run
}

/// The EMPS positioning drive's training record (`../shared/data/emps/`, the benchmark's own
/// files, read in place and never copied into the project).
pub const EMPS_TRAIN: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/emps/emps_train.csv"
);

/// The EMPS test record (with its disturbance pulses).
pub const EMPS_TEST: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/emps/emps_test_pulses.csv"
);

/// The diagnosis of a static model of order 2 with 6 uniform segments on `[-range, range]`
/// after a hold of `hold` samples: the start the element-with-memory tests diagnose from.
pub fn static_order_two(range: f64, hold: usize) -> hsid_host::diagnose::DiagnoseOptions {
    let id = hsid_host::identify::IdentifyOptions {
        static_nonlinearity: true,
        order: Some(2),
        ..hsid_host::identify::IdentifyOptions::uniform(-range, range, 6, hold)
    };
    hsid_host::diagnose::DiagnoseOptions::new(id, hsid_host::model::Element::Static)
}

/// The bundled servo record (`examples/data/servo.csv`, input in [-1, 1]).
pub fn servo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/servo.csv")
}

/// The arguments of `hsid COMMAND` on the bundled servo record (`--umin -1 --umax 1`), then
/// `extra`.
pub fn servo_args(command: &str, extra: &[&str]) -> Vec<String> {
    let servo = servo();
    [command, "--data", p(&servo), "--umin", "-1", "--umax", "1"]
        .iter()
        .chain(extra)
        .map(|s| s.to_string())
        .collect()
}

/// A model file of the servo record (`hsid identify --no-refine --json`, then `extra`),
/// written in `dir` as `m.json`.
pub fn servo_model(dir: &Scratch, extra: &[&str]) -> PathBuf {
    let model = dir.join("m.json");
    let json = ["--no-refine", "--json", p(&model)];
    hsid(&servo_args("identify", &[&json[..], extra].concat())).success();
    model
}

/// `hsid fleet simulate` of `devices` × `weeks` checkpoints (2,000 samples each) into `dir`:
/// the states folder and the truth table.
pub fn simulate_fleet(dir: &Scratch, devices: usize, weeks: usize) -> (PathBuf, PathBuf) {
    let (states, truth) = (dir.join("states"), dir.join("truth.csv"));
    let (devices, weeks) = (devices.to_string(), weeks.to_string());
    hsid(&[
        "fleet",
        "simulate",
        "--devices",
        &devices,
        "--weeks",
        &weeks,
        "--samples",
        "2000",
        "--out",
        p(&states),
        "--truth",
        p(&truth),
    ])
    .success();
    (states, truth)
}

pub fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// `hsid identify --data DATA --umin -3 --umax 3` plus `extra` arguments (the defaults are the
/// paper's settings: 7 segments per path, f = p = 10, a hold of 300 samples).
pub fn identify(data: &Path, extra: &[&str]) -> Run {
    let mut args = vec!["identify", "--data", p(data), "--umin", "-3", "--umax", "3"];
    args.extend_from_slice(extra);
    hsid(&args)
}

/// The messages of every way `instance` breaks the model file's JSON Schema
/// (`docs/model-format.schema.json`); empty when it conforms.
pub fn schema_errors(instance: &serde_json::Value) -> Vec<String> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/model-format.schema.json"
    );
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let validator = jsonschema::draft202012::new(&schema).unwrap();
    validator
        .iter_errors(instance)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect()
}

/// The `class` attribute of every element of an SVG file, after checking it parses as XML.
pub fn classes(path: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut reader = Reader::from_str(&text);
    let mut out = BTreeSet::new();
    let mut root = None;
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Start(e) | Event::Empty(e)) => {
                root.get_or_insert_with(|| AsRef::<str>::as_ref(&e.name()).to_string());
                for a in e.attributes() {
                    let a = a.unwrap();
                    if AsRef::<str>::as_ref(&a.key) == "class" {
                        out.insert(a.value.to_string());
                    }
                }
            }
            Ok(_) => {}
            Err(e) => panic!("{}: not XML: {e}", path.display()),
        }
    }
    assert_eq!(root.as_deref(), Some("svg"), "{}", path.display());
    out
}

pub fn has(path: &Path, expected: &[&str]) {
    let found = classes(path);
    for c in expected {
        assert!(
            found.contains(*c),
            "{}: no series {c:?} in {found:?}",
            path.display()
        );
    }
}

/// A small generator of the tests' records (xorshift, Box–Muller), apart from the library's.
pub struct XorShift(pub u64);

impl XorShift {
    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// SplitMix64 with Box–Muller normals: the generator of the saturation and spring records.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// `y(t) = a₁ y(t−1) + a₂ y(t−2) + (1 − a₁ − a₂) v(t−1)` (unit static gain, one sample of
/// delay), at rest at `v[0]`: the second-order plant of records written in the tests.
pub fn second_order(v: &[f64], a1: f64, a2: f64) -> Vec<f64> {
    let b = 1.0 - a1 - a2;
    let v0 = v.first().copied().unwrap_or(0.0);
    let (mut y1, mut y2, mut v1) = (v0, v0, v0);
    v.iter()
        .map(|&x| {
            let y = a1 * y1 + a2 * y2 + b * v1;
            (y2, y1, v1) = (y1, y, x);
            y
        })
        .collect()
}

/// The validation NRMSE of a model file on `[u, y, clean y]` (simulated from rest at the
/// record's first input: a hold there put before it, its output dropped; the borders extended
/// where the record leaves the identified interval), and the noise floor (the clean
/// output's NRMSE).
pub fn validate_file(file: &hsid_host::model_file::ModelFile, v: &[Vec<f64>; 3]) -> (f64, f64) {
    use hsid_host::model::{FileModel, Simulate, for_input};
    const PREFIX: usize = 500;
    let mut u = vec![v[0][0]; PREFIX];
    u.extend(&v[0]);
    let (model, _) = for_input(&FileModel::from_file(file), &u);
    let sim = model.simulate(&u);
    (nrmse(&v[1], &sim[PREFIX..]), nrmse(&v[1], &v[2]))
}

/// `‖y − ŷ‖ / ‖y − mean(y)‖`: the simulation error normalised by the output's spread.
pub fn nrmse(y: &[f64], yhat: &[f64]) -> f64 {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let e: f64 = y.iter().zip(yhat).map(|(a, b)| (a - b).powi(2)).sum();
    let d: f64 = y.iter().map(|a| (a - mean).powi(2)).sum();
    (e / d).sqrt()
}

/// `hsid diagnose` of the record `est` validated on `val` (both `u,y` files opening with a
/// hold of `hold` samples at −1, the input in [−1, 1]) with the static element of six segments
/// and order 2, then `extra`: the command the friction tests write the model file with.
pub fn diagnose_static_six(est: &Path, val: &Path, hold: usize, extra: &[&str]) -> Run {
    let hold = hold.to_string();
    let args = [
        "diagnose",
        "--data",
        p(est),
        "--validation",
        p(val),
        "--validation-skip",
        &hold,
        "--umin",
        "-1",
        "--umax",
        "1",
        "--hold",
        &hold,
        "--nonlinearity",
        "static",
        "--segments",
        "6",
        "--order",
        "2",
    ];
    hsid(&[&args[..], extra].concat())
}

/// The RMSE of the line of `hsid validate`'s output that starts with `start` (`simulation fit
/// on`, `one-step prediction fit on`), printed.
pub fn validate_rmse(stdout: &str, start: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("{start}: {stdout}"));
    println!("validate: {line}");
    line.split("RMSE ")
        .nth(1)
        .and_then(|r| r.split(',').next())
        .and_then(|r| r.parse().ok())
        .unwrap_or_else(|| panic!("no RMSE in {line}"))
}
