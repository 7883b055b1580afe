//! Exports the paper's experiments as the subspace step sees them, for a peer implementation:
//! `z(t)` (the hat-basis regressor channels of the core, excitation part only) and
//! `ȳ(t) = y(t) − μ0` (μ0 the mean of the settled hold), one CSV per run, plus hsid's own
//! estimate on the same runs with its time.
//!
//! ```text
//! cargo run --release -p hsid-host --example export_zy -- OUT_DIR [RUNS] [switch|backlash] [F] [METHOD]
//! ```
//!
//! Writes `OUT_DIR/zy-RUN.csv` (columns `z1 … zm, ybar`) and `OUT_DIR/hsid.json`: per run the
//! poles of hsid's subspace method `METHOD` (`po-moesp` by default, the instruments nfoursid
//! uses; `pi-moesp`, `n4sid`, `cva`) and the best-of-5 wall-clock seconds of one identification
//! from the raw record (regressor, accumulation and solve included). `F` is the horizon,
//! `f = p` (default 10; up to the desktop front end's capacity, `f + p <= 96`, and as far as
//! the record's Hankel columns allow). Used by `scripts/compare-nfoursid.sh`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use hsid_host::identify::{IdentifyOptions, identify};
use hsid_host::io::write_columns;
use hsid_host::paper::methods::Method;
use hsid_host::paper::{Case, PaperConfig, experiment, options};
use hsid_host::refine::signal::HatRegressors;

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .ok_or("usage: export_zy OUT_DIR [RUNS] [switch|backlash] [F] [METHOD]")?,
    );
    let runs: usize = match args.next() {
        Some(s) => s.parse().map_err(|_| format!("RUNS: not a number: {s}"))?,
        None => 10,
    };
    let case = match args.next().as_deref() {
        None | Some("switch") => Case::Switch,
        Some("backlash") => Case::Backlash,
        Some(other) => return Err(format!("unknown case {other}")),
    };
    let horizon: usize = match args.next() {
        Some(s) => s.parse().map_err(|_| format!("F: not a number: {s}"))?,
        None => 10,
    };
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let method = match args.next().as_deref() {
        None | Some("po-moesp") => Method::PoMoesp,
        Some("n4sid") => Method::N4sid,
        Some("pi-moesp") => Method::PiMoesp,
        Some("cva") => Method::Cva,
        Some(other) => return Err(format!("unknown subspace method {other}")),
    };
    let cfg = PaperConfig {
        f: horizon,
        p: horizon,
        ..PaperConfig::default()
    };
    let opts = IdentifyOptions {
        method: method.weighting().ok_or("not a subspace method")?,
        ..options(&cfg)
    };
    let mut entries = Vec::new();
    for r in 0..runs {
        let e = experiment(case, &cfg, r).map_err(|e| e.to_string())?;
        // hsid from the raw record, best of 5.
        let mut best = f64::INFINITY;
        let mut model = None;
        for _ in 0..5 {
            let t = Instant::now();
            let m = identify(&e.u, &e.y, &opts).map_err(|e| e.to_string())?;
            best = best.min(t.elapsed().as_secs_f64());
            model = Some(m);
        }
        let model = model.ok_or("no model")?;
        // The data the subspace step sees.
        let hat = HatRegressors::new(&e.u, &opts.knots_asc, &opts.knots_desc)
            .map_err(|e| e.to_string())?;
        let dense = hat.dense();
        let hold = cfg.hold;
        let tail = &e.y[cfg.settle..hold];
        let mu0 = tail.iter().sum::<f64>() / tail.len() as f64;
        let mut cols: Vec<Vec<f64>> = dense[1..].iter().map(|c| c[hold..].to_vec()).collect();
        cols.push(e.y[hold..].iter().map(|v| v - mu0).collect());
        let names: Vec<String> = (1..=cols.len() - 1)
            .map(|k| format!("z{k}"))
            .chain(std::iter::once("ybar".to_string()))
            .collect();
        let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let path = out.join(format!("zy-{r}.csv"));
        write_columns(&path, &name_refs, &cols).map_err(|e| e.to_string())?;
        entries.push(serde_json::json!({
            "run": r,
            "csv": path.display().to_string(),
            "poles": model.poles().iter().map(|p| [p.0, p.1]).collect::<Vec<_>>(),
            "order": model.order,
            "seconds": best,
        }));
    }
    let doc = serde_json::json!({
        "case": case.name(),
        "method": method.name(),
        "f": cfg.f,
        "p": cfg.p,
        "runs": entries,
    });
    let path = out.join("hsid.json");
    let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    println!(
        "wrote {} runs of {} to {}",
        runs,
        case.name(),
        out.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("export_zy: {e}");
            ExitCode::FAILURE
        }
    }
}
