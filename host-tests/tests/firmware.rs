//! The firmware example (`examples/firmware`) under QEMU, on both its targets, checked against
//! the host.
//!
//! The firmware is built in release with `--features dump-samples` (its own target directory,
//! `examples/firmware/target`) for the Cortex-M4F (`thumbv7em-none-eabihf`, run under
//! `qemu-system-arm -machine mps2-an386`) and for RISC-V (`riscv32imafc-unknown-none-elf`, run
//! under `qemu-system-riscv32 -machine virt -bios none`), each in a scratch folder, where it
//! writes its checkpoint `hsid-state.bin` through semihosting. Then, for each target:
//!
//! * the on-target `f32` model is compared with the host's `f64` identification of the **same**
//!   sample sequence (the dumped `HSID s` lines, same settings): order equal, poles within
//!   0.005, borders within 0.02 RMS;
//! * the exported checkpoint is solved on the host (`hsid solve --state`, library and binary)
//!   and must give the on-target model: same order, poles, borders and singular values to
//!   1e-5 relative (in `f32` both, so only `libm` vs `std` float code differs);
//! * the `defmt` variant is built too (Cortex-M4F; and run, if `defmt-print` is installed);
//! * both targets accumulate the same state: their checkpoints are equal byte for byte (the
//!   same `f32` operations in the same order, IEEE-rounded on both).
//!
//! These tests are skipped, with a message on stderr, only where a target's QEMU or its Rust
//! target is missing (set `HSID_REQUIRE_FIRMWARE=1` to fail instead).
//! The checkpoint tests at the end need neither and always run.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use hsid::{CheckpointError, Direction, Excitation, Identifier, Knots, MuZero, Settings};
use hsid_host::identify::{
    HostModel, IdentifyError, IdentifyOptions, Solver, checkpoint_header, identify,
    solve_checkpoint, solve_checkpoint_with,
};
use nalgebra::DMatrix;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

const STATE_FILE: &str = "hsid-state.bin";

/// A target the firmware is built for, and the QEMU board it runs on.
struct Target {
    /// Rust target triple.
    triple: &'static str,
    /// QEMU system emulator.
    qemu: &'static str,
    /// Debian package that has it.
    package: &'static str,
    /// Board (and CPU) arguments.
    machine: &'static [&'static str],
    /// Why the firmware cannot run here, if it cannot (found once per target).
    missing: OnceLock<Option<String>>,
    /// The plain run shared by the tests of this target.
    run: OnceLock<Run>,
}

/// The Cortex-M4F on QEMU's MPS2-AN386.
static CORTEX_M4: Target = Target {
    triple: "thumbv7em-none-eabihf",
    qemu: "qemu-system-arm",
    package: "qemu-system-arm",
    machine: &["-machine", "mps2-an386", "-cpu", "cortex-m4"],
    missing: OnceLock::new(),
    run: OnceLock::new(),
};

/// RV32IMAFC on QEMU's `virt` board, machine mode without firmware.
static RISCV32: Target = Target {
    triple: "riscv32imafc-unknown-none-elf",
    qemu: "qemu-system-riscv32",
    package: "qemu-system-misc",
    machine: &["-machine", "virt", "-bios", "none"],
    missing: OnceLock::new(),
    run: OnceLock::new(),
};

// ---------------------------------------------------------------------------------------------
// Building and running the firmware
// ---------------------------------------------------------------------------------------------

fn firmware_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/firmware")
}

/// Prints straight to the process's stderr: libtest captures `eprintln!`, not this, so the
/// message shows in a normal `cargo test` run.
fn note(msg: &str) {
    let _ = writeln!(std::io::stderr(), "{msg}");
}

/// Why the firmware tests of `target` cannot run here, if they cannot.
fn missing_tools(target: &Target) -> Option<String> {
    let qemu = Command::new(target.qemu)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !matches!(qemu, Ok(s) if s.success()) {
        return Some(format!(
            "{} not found (Debian: apt-get install {}; .ci/run installs it)",
            target.qemu, target.package
        ));
    }
    // The sysroot of the toolchain that builds the firmware (run from its folder, so that a
    // toolchain file there would count) must hold the target's standard library.
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
    let sysroot = Command::new(rustc)
        .args(["--print", "sysroot"])
        .current_dir(firmware_dir())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    match sysroot {
        Some(root) if root.join("lib/rustlib").join(target.triple).is_dir() => None,
        _ => Some(format!(
            "the {0} target is not installed (rustup target add {0})",
            target.triple
        )),
    }
}

/// `false` (after printing why) where the firmware cannot be built and run for `target`.
fn firmware_available(test: &str, target: &Target) -> bool {
    match target.missing.get_or_init(|| missing_tools(target)) {
        None => true,
        Some(why) if std::env::var_os("HSID_REQUIRE_FIRMWARE").is_some() => {
            panic!("HSID_REQUIRE_FIRMWARE is set but {why}")
        }
        Some(why) => {
            note(&format!("SKIPPED firmware test {test}: {why}"));
            false
        }
    }
}

/// A scratch folder for one firmware run (QEMU's working directory: the state file lands here).
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("hsid-firmware-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Builds the firmware for `target` in release with `features` in its own target directory and
/// copies the ELF to `dir` (the variants share the ELF's path in the target directory, so
/// builds and copies are serialised).
fn build(target: &Target, features: &str, dir: &Path) -> PathBuf {
    static BUILD: Mutex<()> = Mutex::new(());
    let _guard = BUILD.lock().unwrap_or_else(|e| e.into_inner());
    let fw = firmware_dir();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let t0 = Instant::now();
    let out = Command::new(cargo)
        .current_dir(&fw)
        .env("CARGO_TARGET_DIR", fw.join("target"))
        // Host-wide flags would replace the firmware's own (`-Tlink.x` in .cargo/config.toml).
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        // The paper's configuration, whatever the environment says (scripts/firmware-fit.sh).
        .env_remove("HSID_FW_SEGMENTS")
        .env_remove("HSID_FW_F")
        .env_remove("HSID_FW_P")
        .args(["build", "--release", "--target", target.triple])
        .args(["--features", features])
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "cargo build --release --target {} --features {features} in {} failed:\n{log}",
        target.triple,
        fw.display()
    );
    note(&format!(
        "firmware ({}, {features}) built in {:.1} s",
        target.triple,
        t0.elapsed().as_secs_f64()
    ));
    let elf = fw
        .join("target")
        .join(target.triple)
        .join("release/hsid-firmware");
    let copy = dir.join("hsid-firmware.elf");
    std::fs::copy(&elf, &copy).unwrap();
    copy
}

/// Runs `elf` under the QEMU of `target` (the runners of `.cargo/config.toml`) in `dir`;
/// returns the exit status and the raw stdout. Killed after two minutes.
fn run_qemu(target: &Target, elf: &Path, dir: &Path) -> (Option<i32>, Vec<u8>) {
    let t0 = Instant::now();
    let mut child = Command::new(target.qemu)
        .current_dir(dir)
        .args(target.machine)
        .args([
            "-semihosting-config",
            "enable=on,target=native",
            "-nographic",
            "-monitor",
            "none",
            "-serial",
            "none",
            "-icount",
            "shift=0",
            "-kernel",
        ])
        .arg(elf)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut buf = Vec::new();
        let _ = stdout.read_to_end(&mut buf);
        buf
    });
    let deadline = t0 + Duration::from_secs(120);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the firmware did not finish within 120 s under QEMU");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = reader.join().unwrap();
    note(&format!(
        "firmware ran under {} in {:.1} s",
        target.qemu,
        t0.elapsed().as_secs_f64()
    ));
    (status.code(), out)
}

/// One run of the plain-text firmware with `dump-samples`: its output and its state file.
struct Run {
    text: String,
    state: Vec<u8>,
    dir: PathBuf,
}

/// The run of `target` shared by the tests of this file (built and run once).
fn plain_run(target: &'static Target) -> &'static Run {
    target.run.get_or_init(|| {
        let dir = scratch(&format!("plain-{}", target.triple));
        let elf = build(target, "dump-samples", &dir);
        let (code, out) = run_qemu(target, &elf, &dir);
        let text = String::from_utf8_lossy(&out).into_owned();
        let fail: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("HSID fail") || l.starts_with("HSID panic"))
            .collect();
        assert_eq!(
            code,
            Some(0),
            "{} firmware exit status; {fail:?}",
            target.triple
        );
        assert!(text.lines().any(|l| l == "HSID ok"), "no `HSID ok` line");
        let state = std::fs::read(dir.join(STATE_FILE)).unwrap();
        Run { text, state, dir }
    })
}

// ---------------------------------------------------------------------------------------------
// Parsing the HSID lines
// ---------------------------------------------------------------------------------------------

/// `key=value` pairs of the first line starting with `HSID <tag> `.
fn keys(text: &str, tag: &str) -> Vec<(String, String)> {
    let prefix = format!("HSID {tag} ");
    let line = text
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no `{prefix}` line"));
    line[prefix.len()..]
        .split_whitespace()
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn key<T: std::str::FromStr>(kv: &[(String, String)], k: &str) -> T {
    let v = &kv.iter().find(|(key, _)| key == k).unwrap().1;
    v.parse()
        .unwrap_or_else(|_| panic!("{k}={v} does not parse"))
}

/// Values of the line `HSID <tag> v v …` (plain text, or defmt's `[v, v, …]`), as `f32`
/// widened to `f64` (the firmware prints shortest round-trip decimals).
fn values(text: &str, tag: &str) -> Vec<f64> {
    let prefix = format!("HSID {tag} ");
    let line = text
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no `{prefix}` line"));
    line[prefix.len()..]
        .split(|c: char| c.is_whitespace() || c == ',' || c == '[' || c == ']')
        .filter(|s| !s.is_empty())
        .map(|s| f64::from(s.parse::<f32>().unwrap()))
        .collect()
}

/// The on-target model from the `HSID model/A/B/C/D/mu0/knots/border/sv` lines.
fn target_model(text: &str) -> HostModel {
    let m = keys(text, "model");
    let n: usize = key(&m, "order");
    let rows: Vec<Vec<f64>> = (0..n).map(|i| values(text, &format!("A {i}"))).collect();
    let cfg = keys(text, "config");
    HostModel {
        order: n,
        a: DMatrix::from_fn(n, n, |i, j| rows[i][j]),
        b: values(text, "B"),
        c: values(text, "C"),
        d: values(text, "D")[0],
        mu0: values(text, "mu0")[0],
        knots_asc: values(text, "knots ascending"),
        knots_desc: values(text, "knots descending"),
        border_asc: values(text, "border ascending"),
        border_desc: values(text, "border descending"),
        singular_values: values(text, "sv"),
        whitened_singular_values: values(text, "sv_white"),
        f: key(&cfg, "f"),
        p: key(&cfg, "p"),
        samples: key(&cfg, "samples"),
    }
}

/// The dumped samples `HSID s <t> <u bits> <y bits>`, in order, widened to `f64`.
fn samples(text: &str) -> (Vec<f64>, Vec<f64>) {
    let (mut u, mut y) = (Vec::new(), Vec::new());
    for line in text.lines().filter(|l| l.starts_with("HSID s ")) {
        let f: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(f.len(), 5, "sample line {line:?}");
        assert_eq!(
            f[2].parse::<usize>().unwrap(),
            u.len(),
            "samples out of order"
        );
        let bits = |s: &str| f64::from(f32::from_bits(u32::from_str_radix(s, 16).unwrap()));
        u.push(bits(f[3]));
        y.push(bits(f[4]));
    }
    (u, y)
}

// ---------------------------------------------------------------------------------------------
// Model comparisons
// ---------------------------------------------------------------------------------------------

/// Largest distance from a pole of `a` to its partner in `b` (greedy nearest matching).
fn pole_distance(a: &HostModel, b: &HostModel) -> f64 {
    let (pa, mut pb) = (a.poles(), b.poles());
    assert_eq!(pa.len(), pb.len());
    let mut worst = 0.0f64;
    for (re, im) in pa {
        let (k, d) = pb
            .iter()
            .enumerate()
            .map(|(k, (r, i))| (k, (r - re).hypot(i - im)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        pb.swap_remove(k);
        worst = worst.max(d);
    }
    worst
}

/// RMS difference of the borders of both paths on a grid of 601 points per path on the
/// models' interval.
fn border_rms(a: &HostModel, b: &HostModel) -> f64 {
    let (lo, hi) = (a.u_min(), a.u_max());
    let mut sum = 0.0;
    let mut n = 0usize;
    for i in 0..=600 {
        let u = lo + (hi - lo) * i as f64 / 600.0;
        for d in [
            a.border_asc_at(u) - b.border_asc_at(u),
            a.border_desc_at(u) - b.border_desc_at(u),
        ] {
            sum += d * d;
            n += 1;
        }
    }
    (sum / n as f64).sqrt()
}

/// Largest difference of two vectors relative to the largest magnitude of `b`.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

fn poles_flat(m: &HostModel) -> Vec<f64> {
    let mut p = m.poles();
    p.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    p.into_iter().flat_map(|(r, i)| [r, i]).collect()
}

/// Relative differences (poles, borders at the knots, singular values, μ0) of a model solved
/// from the checkpoint against the on-target one; all must stay below `tol`.
fn assert_same_model(host: &HostModel, target: &HostModel, what: &str, tol: f64) {
    assert_eq!(host.order, target.order, "{what}: order");
    let diffs = [
        ("poles", rel(&poles_flat(host), &poles_flat(target))),
        ("P_a", rel(&host.border_asc, &target.border_asc)),
        ("P_d", rel(&host.border_desc, &target.border_desc)),
        (
            "singular values",
            rel(&host.singular_values, &target.singular_values),
        ),
        ("mu0", rel(&[host.mu0], &[target.mu0])),
        (
            "Markov D, CB",
            rel(&markov(host), &markov(target)), // invariant to the state basis
        ),
    ];
    note(&format!(
        "{what} vs on-target model, largest relative differences: {}",
        diffs
            .iter()
            .map(|(k, v)| format!("{k} {v:.1e}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    for (k, v) in diffs {
        assert!(
            v <= tol,
            "{what}: {k} differ by {v:.2e} (relative) > {tol:.0e}"
        );
    }
}

/// `D, CB, CAB, …, CA⁸B`.
fn markov(m: &HostModel) -> Vec<f64> {
    let n = m.order;
    let b = nalgebra::DVector::from_column_slice(&m.b);
    let c = nalgebra::RowDVector::from_row_slice(&m.c);
    let mut x = b;
    let mut out = vec![m.d];
    for _ in 0..9 {
        out.push((&c * &x)[(0, 0)]);
        x = &m.a * x;
    }
    assert_eq!(x.len(), n);
    out
}

// ---------------------------------------------------------------------------------------------
// Firmware tests
// ---------------------------------------------------------------------------------------------

/// The Cortex-M4F's `f32` model agrees with the host's `f64` identification of the same samples.
#[test]
fn firmware_model_matches_host_identification_of_the_same_samples() {
    let test = "firmware_model_matches_host_identification_of_the_same_samples";
    if firmware_available(test, &CORTEX_M4) {
        model_matches_host_identification(&CORTEX_M4);
    }
}

/// The RISC-V firmware's `f32` model agrees with the host's `f64` identification of the same
/// samples.
#[test]
fn riscv_firmware_model_matches_host_identification_of_the_same_samples() {
    let test = "riscv_firmware_model_matches_host_identification_of_the_same_samples";
    if firmware_available(test, &RISCV32) {
        model_matches_host_identification(&RISCV32);
    }
}

/// The on-target `f32` model of `target` agrees with the host's `f64` identification of the
/// same samples: same order, poles within 0.005, borders within 0.02 RMS.
fn model_matches_host_identification(on: &'static Target) {
    let run = plain_run(on);
    let cfg = keys(&run.text, "config");
    let (u, y) = samples(&run.text);
    assert_eq!(u.len(), key::<usize>(&cfg, "samples"), "dumped samples");

    // The firmware's settings, as its config line states them (and as the paper's).
    let (u_min, u_max): (f64, f64) = (key(&cfg, "u_min"), key(&cfg, "u_max"));
    let segments: usize = key(&cfg, "segments");
    let hold: usize = key(&cfg, "hold");
    assert_eq!((u_min, u_max, segments, hold), (-3.0, 3.0, 7, 300));
    let mut opts = IdentifyOptions::uniform(u_min, u_max, segments, hold);
    opts.f = key(&cfg, "f");
    opts.p = key(&cfg, "p");
    opts.settle = key(&cfg, "settle");
    assert_eq!((opts.f, opts.p, opts.settle), (10, 10, 150));
    let host = identify(&u, &y, &opts).unwrap();
    let target = target_model(&run.text);

    assert_eq!(target.order, host.order, "order");
    let dp = pole_distance(&target, &host);
    let rms = border_rms(&target, &host);
    note(&format!(
        "{} f32 vs host f64 on the same {} samples: order {} both, poles {:.2e} apart, borders {:.2e} RMS",
        on.triple,
        u.len(),
        host.order,
        dp,
        rms
    ));
    assert!(dp <= 0.005, "poles differ by {dp}");
    assert!(rms <= 0.02, "borders differ by {rms} RMS");
}

/// The Cortex-M4F's exported checkpoint, solved on the host (library and `hsid solve --state`),
/// gives the on-target model.
#[test]
fn firmware_checkpoint_solved_on_host_matches_on_target_solve() {
    let test = "firmware_checkpoint_solved_on_host_matches_on_target_solve";
    if firmware_available(test, &CORTEX_M4) {
        checkpoint_solved_on_host_matches_on_target_solve(&CORTEX_M4);
    }
}

/// The RISC-V firmware's exported checkpoint, solved on the host, gives the on-target model.
#[test]
fn riscv_firmware_checkpoint_solved_on_host_matches_on_target_solve() {
    let test = "riscv_firmware_checkpoint_solved_on_host_matches_on_target_solve";
    if firmware_available(test, &RISCV32) {
        checkpoint_solved_on_host_matches_on_target_solve(&RISCV32);
    }
}

/// Both targets accumulate the same state from the same samples: the same `f32` additions and
/// multiplications in the same order, rounded by IEEE 754 on both (no fused multiply-adds:
/// Rust does not contract), so the checkpoints are equal byte for byte, and so are the
/// dumped samples (the plant's `libm` code is the same on both) and the printed model.
#[test]
fn both_targets_accumulate_the_same_state() {
    let test = "both_targets_accumulate_the_same_state";
    if !(firmware_available(test, &CORTEX_M4) && firmware_available(test, &RISCV32)) {
        return;
    }
    let (arm, riscv) = (plain_run(&CORTEX_M4), plain_run(&RISCV32));
    assert_eq!(samples(&arm.text), samples(&riscv.text), "dumped samples");
    assert!(
        arm.state == riscv.state,
        "the checkpoints differ ({} and {} bytes)",
        arm.state.len(),
        riscv.state.len()
    );
    // The solve's operations are the same too (`libm` for the functions, IEEE `sqrt`): the
    // model lines are equal character for character.
    let model = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| !l.starts_with("HSID s ") && !l.starts_with("HSID cost "))
            .filter(|l| !l.starts_with("HSID state "))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(model(&arm.text), model(&riscv.text), "model lines");
}

/// The exported checkpoint of `target`, solved on the host (library and `hsid solve --state`),
/// gives the on-target model.
fn checkpoint_solved_on_host_matches_on_target_solve(target: &'static Target) {
    let run = plain_run(target);
    let st = keys(&run.text, "state");
    assert_eq!(
        key::<usize>(&st, "bytes"),
        run.state.len(),
        "state file length"
    );
    // The checkpoint's own CRC-32 (its last four bytes), over everything before it.
    let crc = u32::from_str_radix(&key::<String>(&st, "crc"), 16).unwrap();
    let (body, tail) = run.state.split_at(run.state.len() - 4);
    assert_eq!(crc, hsid::crc32(body), "state file CRC");
    assert_eq!(crc.to_le_bytes(), tail, "stored CRC");
    assert_eq!(key::<String>(&st, "file"), STATE_FILE);

    let header = checkpoint_header(&run.state).unwrap();
    assert_eq!(
        (header.scalar_name(), header.channels, header.f, header.p),
        ("f32", 14, 10, 10)
    );
    let target = target_model(&run.text);
    // The library with the firmware's solve gives its model to f32 rounding; the other solve
    // within the f32 tolerances of the two solves (README: poles 1e-4, borders 1e-3).
    let cfg = keys(&run.text, "config");
    let name = key::<String>(&cfg, "solve");
    let same = Solver::from_name(&name).unwrap_or_else(|| panic!("unknown solve {name}"));
    let other = match same {
        Solver::Dense => Solver::Structured,
        Solver::Structured => Solver::Dense,
    };
    let solved = solve_checkpoint_with(&run.state, same).unwrap();
    assert_same_model(
        &solved.model,
        &target,
        "hsid solve (library, same solve)",
        1e-5,
    );
    let solved_other = solve_checkpoint_with(&run.state, other).unwrap();
    assert_same_model(
        &solved_other.model,
        &target,
        "hsid solve (library, other solve)",
        1e-3,
    );

    // The command line, on the file the firmware wrote.
    let json = run.dir.join("model.json");
    let solver = same.name();
    let out = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args(["solve", "--solver", solver, "--state"])
        .arg(run.dir.join(STATE_FILE))
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "hsid solve: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("f32 checkpoint"), "{stdout}");
    assert!(stdout.contains(&format!("({solver} solve)")), "{stdout}");
    assert!(stdout.contains("order n = 2"), "{stdout}");
    // The JSON holds the same model (serde_json parses floats to within an ulp or so).
    let from_json = HostModel::from_json(&hsid_host::model_file::ModelFile::load(&json).unwrap());
    assert_eq!(from_json.order, solved.model.order);
    assert!(rel(&from_json.border_asc, &solved.model.border_asc) < 1e-14);
    assert!(rel(&from_json.border_desc, &solved.model.border_desc) < 1e-14);
    assert!(rel(from_json.a.as_slice(), solved.model.a.as_slice()) < 1e-14);
}

/// The `defmt` variant builds; where `defmt-print` is installed it also runs and decodes to the
/// same model and the same checkpoint.
#[test]
fn firmware_defmt_variant() {
    if !firmware_available("firmware_defmt_variant", &CORTEX_M4) {
        return;
    }
    let dir = scratch("defmt");
    let elf = build(&CORTEX_M4, "defmt", &dir);
    let decoder = Command::new("defmt-print")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !matches!(decoder, Ok(s) if s.success()) {
        note(
            "firmware_defmt_variant: built; not run (defmt-print not installed: cargo install defmt-print)",
        );
        return;
    }
    let (code, raw) = run_qemu(&CORTEX_M4, &elf, &dir);
    let mut child = Command::new("defmt-print")
        .arg("-e")
        .arg(&elf)
        .args(["--log-format", "{s}"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(&raw));
    let decoded = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    let text = String::from_utf8_lossy(&decoded.stdout);
    assert_eq!(code, Some(0), "defmt firmware exit status:\n{text}");
    let plain = plain_run(&CORTEX_M4);
    let (a, b) = (target_model(&text), target_model(&plain.text));
    assert_eq!(a.order, b.order);
    assert_eq!(a.border_asc, b.border_asc);
    assert_eq!(a.border_desc, b.border_desc);
    assert_eq!(a.a, b.a);
    assert_eq!(std::fs::read(dir.join(STATE_FILE)).unwrap(), plain.state);
}

// ---------------------------------------------------------------------------------------------
// Checkpoint solves without the firmware
// ---------------------------------------------------------------------------------------------

/// The paper's backlash with a little noise, Table I excitation: `(u, y)`.
fn backlash_record(samples: usize, hold: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut noise = Pcg32::seed_from_u64(seed ^ 0xA5A5);
    let (mut w, mut y1, mut y2, mut w1, mut w2) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let u: Vec<f64> = Excitation::new(-3.0, 3.0, hold, Pcg32::seed_from_u64(seed))
        .unwrap()
        .take(samples)
        .collect();
    let y = u
        .iter()
        .map(|&u| {
            w = w.max((u - 1.0).atan()).min((u + 1.0).atan());
            let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
            (w2, w1, y2, y1) = (w1, w, y1, y);
            let r = |g: &mut Pcg32| f64::from(rand_core::Rng::next_u32(g)) / 4_294_967_296.0;
            y + 0.02 * (r(&mut noise) + r(&mut noise) - 1.0)
        })
        .collect();
    (u, y)
}

/// Settings of the checkpoint tests: uniform knots on [-3, 3] with `segments` per path,
/// horizons `f`, `p`, and the records' hold of 300 samples (the first 150 settling).
fn hold_settings<T: hsid::Real, const MM: usize>(
    segments: usize,
    f: usize,
    p: usize,
) -> Settings<T, MM> {
    let knots = Knots::uniform(T::of(-3.0), T::of(3.0), segments, segments).unwrap();
    Settings::new(
        knots,
        f,
        p,
        MuZero::Hold {
            len: 300,
            settle: 150,
        },
    )
}

/// Pushes the record into `id`, rounded to its scalar type.
fn feed<
    T: hsid::Real,
    const MM: usize,
    const KK: usize,
    S: hsid::Summation<T, MM, KK>,
    const H: usize,
>(
    id: &mut Identifier<T, MM, KK, S, H>,
    u: &[f64],
    y: &[f64],
) {
    for (&u, &y) in u.iter().zip(y) {
        id.push(T::of(u), T::of(y));
    }
}

/// An `f64` checkpoint solved by `solve_checkpoint` is bit for bit the direct identification.
#[test]
fn f64_checkpoint_solves_to_the_direct_identification() {
    let (u, y) = backlash_record(4319, 300, 3);
    let opts = IdentifyOptions::uniform(-3.0, 3.0, 7, 300);
    let direct = identify(&u, &y, &opts).unwrap();

    let mut id = Box::new(Identifier::<f64, 14, 20>::new(hold_settings(7, 10, 10)).unwrap());
    feed(&mut id, &u, &y);
    let mut bytes = vec![0u8; hsid::checkpoint_capacity(14, 20, 8)];
    let len = id.save(&mut bytes).unwrap();
    bytes.truncate(len);
    let solved = solve_checkpoint(&bytes).unwrap();
    assert_eq!(solved.header.scalar_name(), "f64");
    assert!(!solved.shared_knots);
    assert_eq!(solved.model, direct);
}

/// A desktop-size checkpoint (`f = p = 30`, 20 + 20 segments, `f64`), saved by an identifier
/// of exactly its sizes (`Identifier<f64, 40, 60, Plain, 30>`), is restored into the host's
/// largest capacity and solves bit for bit to the direct identification.
#[test]
fn desktop_size_checkpoint_solves_to_the_direct_identification() {
    let (u, y) = backlash_record(300 + 6000, 300, 8);
    let mut opts = IdentifyOptions::uniform(-3.0, 3.0, 20, 300);
    (opts.f, opts.p) = (30, 30);
    let direct = identify(&u, &y, &opts).unwrap();
    // 0.8 MB of sums: built on a thread with room for them.
    let bytes = std::thread::scope(|s| {
        std::thread::Builder::new()
            .stack_size(64 << 20)
            .spawn_scoped(s, || {
                let mut id = Box::new(
                    Identifier::<f64, 40, 60, hsid::Plain, 30>::new(hold_settings(20, 30, 30))
                        .unwrap(),
                );
                feed(&mut id, &u, &y);
                let mut bytes = vec![0u8; id.checkpoint_len()];
                id.save(&mut bytes).unwrap();
                bytes
            })
            .unwrap()
            .join()
            .unwrap()
    });
    let solved = solve_checkpoint(&bytes).unwrap();
    assert_eq!(
        (solved.header.channels, solved.header.f, solved.header.p),
        (40, 30, 30)
    );
    assert_eq!(solved.model, direct);
}

/// An `f32` checkpoint with compensated output sums (format flag bit 2) is restored into a
/// compensated identifier and solves bit for bit to the direct solve of the same state;
/// the plain state of the same samples solves differently (its sums round otherwise).
#[test]
fn compensated_f32_checkpoint_solves_to_the_direct_solve() {
    let (u, y) = backlash_record(4319, 300, 4);
    let mut comp = Box::new(
        Identifier::<f32, 14, 20, hsid::Compensated>::new(hold_settings(7, 10, 10)).unwrap(),
    );
    let mut plain = Box::new(Identifier::<f32, 14, 20>::new(hold_settings(7, 10, 10)).unwrap());
    feed(&mut comp, &u, &y);
    feed(&mut plain, &u, &y);
    let mut ws = vec![0.0f32; comp.workspace_len()];
    let direct = comp.solve(&mut ws).unwrap();
    let mut bytes = vec![0u8; hsid::compensated_checkpoint_capacity(14, 20, 4)];
    let len = comp.save(&mut bytes).unwrap();
    bytes.truncate(len);
    let solved = solve_checkpoint(&bytes).unwrap();
    assert!(solved.header.compensated);
    assert_eq!(solved.header.scalar_name(), "f32");
    let wide = |v: &[f32]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
    assert_eq!(solved.model.singular_values, wide(direct.singular_values()));
    assert_eq!(
        solved.model.border_asc,
        wide(direct.border_values(Direction::Ascending))
    );
    let mut plain_bytes = vec![0u8; hsid::checkpoint_capacity(14, 20, 4)];
    let len = plain.save(&mut plain_bytes).unwrap();
    plain_bytes.truncate(len);
    let plain_solved = solve_checkpoint(&plain_bytes).unwrap();
    assert!(!plain_solved.header.compensated);
    assert_ne!(
        plain_solved.model.singular_values,
        solved.model.singular_values
    );
}

/// A checkpoint larger than the small capacity (12 segments per path, 24 channels, `f32`)
/// goes to the `<32, 48, 47>` identifier on a big-stack thread and gives the direct solve, also
/// with padding after it (a flash sector dump).
#[test]
fn large_f32_checkpoint_restores_into_a_larger_capacity() {
    let (u, y) = backlash_record(300 + 8000, 300, 5);
    let mut id = Box::new(Identifier::<f32, 24, 22>::new(hold_settings(12, 10, 12)).unwrap());
    feed(&mut id, &u, &y);
    let mut ws = vec![0.0f32; id.workspace_len()];
    let direct = id.solve(&mut ws).unwrap();
    let mut bytes = vec![0u8; hsid::checkpoint_capacity(24, 22, 4)];
    let len = id.save(&mut bytes).unwrap();
    // A dump of a whole flash sector: bytes after the checkpoint are ignored.
    let mut sector = bytes[..len].to_vec();
    sector.resize(len + 1000, 0xFF);
    let solved = solve_checkpoint(&sector).unwrap();
    assert_eq!(
        (solved.header.channels, solved.header.f, solved.header.p),
        (24, 10, 12)
    );
    let m = &solved.model;
    assert_eq!(m.order, direct.order());
    let wide = |v: &[f32]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
    assert_eq!(
        m.border_asc,
        wide(direct.border_values(Direction::Ascending))
    );
    assert_eq!(
        m.border_desc,
        wide(direct.border_values(Direction::Descending))
    );
    assert_eq!(m.singular_values, wide(direct.singular_values()));
}

fn small_checkpoint() -> Vec<u8> {
    let (u, y) = backlash_record(4319, 300, 7);
    let mut id = Box::new(Identifier::<f32, 14, 20>::new(hold_settings(7, 10, 10)).unwrap());
    feed(&mut id, &u, &y);
    let mut bytes = vec![0u8; hsid::checkpoint_capacity(14, 20, 4)];
    let len = id.save(&mut bytes).unwrap();
    bytes.truncate(len);
    bytes
}

fn checkpoint_error(bytes: &[u8]) -> CheckpointError {
    match solve_checkpoint(bytes) {
        Err(IdentifyError::Core(hsid::Error::Checkpoint(e))) => e,
        other => panic!("expected a checkpoint error, got {other:?}"),
    }
}

/// Truncated, corrupted and foreign files are typed errors, and one line from the CLI.
#[test]
fn bad_checkpoints_are_typed_errors() {
    let good = small_checkpoint();
    assert!(solve_checkpoint(&good).is_ok());
    for len in [0, 3, 5, 11, 40, good.len() / 2, good.len() - 1] {
        assert_eq!(
            checkpoint_error(&good[..len]),
            CheckpointError::Truncated,
            "{len} bytes"
        );
    }
    for at in [7, 20, 60, good.len() / 2, good.len() - 1] {
        let mut bad = good.clone();
        bad[at] ^= 0x10;
        assert_eq!(
            checkpoint_error(&bad),
            CheckpointError::Checksum,
            "byte {at}"
        );
    }
    let mut bad = good.clone();
    bad[6] = 2; // scalar size neither 4 nor 8
    assert_eq!(checkpoint_error(&bad), CheckpointError::Invalid);
    let mut bad = good.clone();
    bad[4] = 9; // version
    assert_eq!(checkpoint_error(&bad), CheckpointError::Version);
    assert_eq!(
        checkpoint_error(b"\x7fELF\x01\x01\x01\0\0\0\0\0"),
        CheckpointError::NotACheckpoint
    );
    assert_eq!(
        checkpoint_error(b"HSID config u_min=-3 u_max=3\nHSID ok\n"),
        CheckpointError::NotACheckpoint
    );

    let dir = scratch("bad-checkpoints");
    for (name, bytes, says) in [
        ("truncated.bin", &good[..100], "truncated"),
        ("text.txt", &b"HSID ok\n"[..], "not an hsid checkpoint"),
        ("empty.bin", &[][..], "truncated"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_hsid"))
            .args(["solve", "--state"])
            .arg(&path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}: succeeded");
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        assert!(
            err.starts_with("hsid: ") && err.contains(says),
            "{name}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
