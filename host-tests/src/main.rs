//! `hsid`: identify backlash/switch Hammerstein systems from data, reproduce the paper.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use hsid::{Basis, Excitation};
use hsid_host::identify::{IdentifyOptions, identify};
use hsid_host::io::{load_json, read_columns, save_json, write_columns_to};
use hsid_host::paper::{Case, PaperConfig, run_case, write_figures};
use hsid_host::reference::uniform_knots;
use hsid_host::refine::knots::{AUTO_CANDIDATES, Criterion, SegmentCount, select_segments};
use hsid_host::refine::methods::{
    Method, methods_json, methods_table, run_methods, write_method_figures,
};
use hsid_host::refine::refine as refine_model;
use hsid_host::refine::stochastic::{estimate_noise, noise_text, prediction_report, sidecar_path};
use hsid_host::refine::{InnovationForm, NoiseModel, NoiseOrder, PemOptions};
use hsid_host::report::{fit_report, model_text, paper_table};
use indicatif::{ProgressBar, ProgressStyle};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

#[derive(Parser)]
#[command(
    name = "hsid",
    version,
    about = "Subspace identification of Hammerstein systems with backlash or switch input nonlinearities"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Clone, Copy, ValueEnum)]
enum CaseArg {
    Switch,
    Backlash,
    Both,
}

#[derive(Clone, Copy, ValueEnum)]
enum BasisArg {
    /// Linear B-splines (hat functions): sparse, better conditioned.
    Hat,
    /// The paper's ramp functions P_i.
    Ramp,
}

impl From<BasisArg> for Basis {
    fn from(b: BasisArg) -> Self {
        match b {
            BasisArg::Hat => Basis::Hat,
            BasisArg::Ramp => Basis::Ramp,
        }
    }
}

/// Identification method of `hsid paper --method` (see `hsid_host::refine::methods`).
#[derive(Clone, Copy, ValueEnum)]
enum MethodArg {
    /// The paper's weighting.
    PiMoesp,
    /// PO-MOESP weighting (from the core, when available).
    PoMoesp,
    /// N4SID weighting (from the core, when available).
    N4sid,
    /// CVA weighting (from the core, when available).
    Cva,
    /// PI-MOESP with B, D and the borders by alternating least squares (Remark 5).
    PiMoespAls,
    /// PI-MOESP refined by the prediction-error method (noise model, μ0, borders, plant).
    Pem,
    /// Every method, one table.
    All,
}

impl MethodArg {
    fn methods(self) -> Vec<Method> {
        match self {
            MethodArg::PiMoesp => vec![Method::PiMoesp],
            MethodArg::PoMoesp => vec![Method::PoMoesp],
            MethodArg::N4sid => vec![Method::N4sid],
            MethodArg::Cva => vec![Method::Cva],
            MethodArg::PiMoespAls => vec![Method::PiMoespAls],
            MethodArg::Pem => vec![Method::Pem],
            MethodArg::All => Method::ALL.into_iter().filter(|m| m.available()).collect(),
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum NonlinearityArg {
    /// Backlash (play operator): two paths.
    Backlash,
    /// Switch (hysteresis relay with borders): two paths.
    Switch,
    /// Static, memoryless: one border for both directions.
    Static,
}

impl NonlinearityArg {
    fn name(self) -> &'static str {
        match self {
            NonlinearityArg::Backlash => "backlash",
            NonlinearityArg::Switch => "switch",
            NonlinearityArg::Static => "static",
        }
    }
}

/// A core error about sample `index` (0 = first data row) as a file position: the CSV's line
/// is `index + 2` (one header line, 1-based lines).
fn locate_sample_error(data: &std::path::Path, e: &hsid_host::identify::IdentifyError) -> String {
    use hsid::Error;
    use hsid_host::identify::IdentifyError;
    let line = |i: u64| i + 2;
    match e {
        IdentifyError::Core(Error::NonFinite { index, signal }) => {
            format!(
                "{} line {}: {signal} is NaN or infinite",
                data.display(),
                line(*index)
            )
        }
        IdentifyError::Core(Error::InputOutOfRange { index, value }) => format!(
            "{} line {}: u = {value} lies outside [--umin, --umax]: widen the interval or fix the data",
            data.display(),
            line(*index)
        ),
        IdentifyError::Core(Error::HoldNotAtMin { index, value }) => format!(
            "{} line {}: u = {value} is not --umin but the hold (--hold) is not over: check the hold length",
            data.display(),
            line(*index)
        ),
        // The settings, not the data, are wrong: no file position to give.
        IdentifyError::Core(e) if e.concerns_settings() => format!("settings: {e}"),
        other => format!("{}: {other}", data.display()),
    }
}

#[derive(Subcommand)]
enum Cmd {
    /// Reproduce Section IV: Monte Carlo on the switch and backlash examples.
    Paper {
        /// Which example.
        #[arg(long, value_enum, default_value = "both")]
        case: CaseArg,
        /// Runs per case.
        #[arg(long, default_value_t = 100)]
        runs: usize,
        /// Base seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output folder for summary.json and the figures.
        #[arg(long, default_value = "out/paper")]
        out: PathBuf,
        /// Fixed model order (default: automatic).
        #[arg(long)]
        order: Option<usize>,
        /// Border basis (coordinates of the regressor and of the rank-1 split).
        #[arg(long, value_enum, default_value = "hat")]
        basis: BasisArg,
        /// Also run these methods on the same experiments: a table of pole bias, pole std,
        /// std/CRB, border error and time, a `methods` object per case in summary.json, and
        /// the refinement's figures with uncertainty bands.
        #[arg(long, value_enum)]
        method: Option<MethodArg>,
        /// Samples of the initial hold at u_min (0: no hold, μ0 estimated with the model).
        #[arg(long, default_value_t = 300)]
        hold: usize,
    },
    /// Print the Table I excitation as CSV (column `u`).
    Excite {
        /// Lower end of the input interval.
        #[arg(long, allow_hyphen_values = true)]
        umin: f64,
        /// Upper end of the input interval.
        #[arg(long, allow_hyphen_values = true)]
        umax: f64,
        /// Samples in all (hold included).
        #[arg(long)]
        samples: usize,
        /// Initial hold at u_min (samples).
        #[arg(long, default_value_t = 300)]
        hold: usize,
        /// Seed of the PCG32 generator.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Identify a model from a CSV file with columns `u,y`.
    Identify {
        /// CSV file with a header.
        #[arg(long)]
        data: PathBuf,
        /// Lower end of the input interval.
        #[arg(long, allow_hyphen_values = true)]
        umin: f64,
        /// Upper end of the input interval.
        #[arg(long, allow_hyphen_values = true)]
        umax: f64,
        /// Uniform segments per path (ignored when knots are given), or `auto` to choose the
        /// count from the data (BIC of the refined model over 2 to 14).
        #[arg(long, default_value = "7")]
        segments: SegmentCount,
        /// Ascending knots, comma separated, u_min first and u_max last.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        knots_asc: Option<Vec<f64>>,
        /// Descending knots, comma separated, u_min first and u_max last.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        knots_desc: Option<Vec<f64>>,
        /// Model order (default: automatic).
        #[arg(long)]
        order: Option<usize>,
        /// Samples of the initial hold at u_min.
        #[arg(long, default_value_t = 300)]
        hold: usize,
        /// Samples of the hold skipped while the plant settles (default: half the hold).
        #[arg(long)]
        settle: Option<usize>,
        /// Future horizon f.
        #[arg(long, default_value_t = 10)]
        f: usize,
        /// Past horizon p.
        #[arg(long, default_value_t = 10)]
        p: usize,
        /// Input column name.
        #[arg(long, default_value = "u")]
        input_column: String,
        /// Output column name.
        #[arg(long, default_value = "y")]
        output_column: String,
        /// Border basis (coordinates of the regressor and of the rank-1 split).
        #[arg(long, value_enum, default_value = "hat")]
        basis: BasisArg,
        /// The input element: backlash or switch (two paths, Table I data), or static (one
        /// memoryless border for both directions, any input).
        #[arg(long, value_enum, default_value = "backlash")]
        nonlinearity: NonlinearityArg,
        /// Known μ0 = H(u_min), for data without a hold (`--hold 0`). Without it, and without a
        /// hold, μ0 is estimated with the model.
        #[arg(long, allow_hyphen_values = true)]
        mu0: Option<f64>,
        /// Refine the subspace model by the prediction-error method: plant, μ0, borders and
        /// noise model jointly (lower variance; see docs/beyond-the-paper.md).
        #[arg(long)]
        refine: bool,
        /// Write the model as JSON here (and its noise model next to it, as NAME.noise.json,
        /// for the one-step predictions of `hsid validate`).
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Close the loop: check the data, identify, test the validation residual, trace it to a
    /// missing effect, add it, and report the error before and after each step.
    Diagnose(Box<hsid_host::diagnose::cli::DiagnoseArgs>),
    /// Solve an identifier's checkpoint (e.g. exported by the firmware) on the host, in the
    /// checkpoint's precision (f32 or f64), and print the model.
    Solve {
        /// Checkpoint file written by `Identifier::save` (the firmware's `hsid-state.bin`).
        #[arg(long)]
        state: PathBuf,
        /// Write the model as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Simulate a model on a CSV file with columns `u,y` and print the fit.
    Validate {
        /// Model JSON written by `hsid identify`.
        #[arg(long)]
        model: PathBuf,
        /// CSV file with a header.
        #[arg(long)]
        data: PathBuf,
        /// Samples at the start left out of the fit (e.g. the hold).
        #[arg(long, default_value_t = 0)]
        skip: usize,
        /// Input column name.
        #[arg(long, default_value = "u")]
        input_column: String,
        /// Output column name.
        #[arg(long, default_value = "y")]
        output_column: String,
        /// Noise model JSON for one-step-ahead predictions (default: MODEL.noise.json next to
        /// the model, when it exists).
        #[arg(long)]
        noise: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hsid: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `hsid solve --state FILE [--json OUT]`.
fn solve_state(state: &std::path::Path, json: Option<&std::path::Path>) -> Result<(), String> {
    let bytes = std::fs::read(state).map_err(|e| format!("{}: {e}", state.display()))?;
    let solved = hsid_host::identify::solve_checkpoint(&bytes)
        .map_err(|e| {
            use hsid::{CheckpointError, Error};
            use hsid_host::identify::IdentifyError;
            let hint = match e {
                IdentifyError::Core(Error::Checkpoint(CheckpointError::NotACheckpoint)) => {
                    ": give the binary state file Identifier::save wrote (the firmware's hsid-state.bin), not the printed output"
                }
                _ => "",
            };
            format!("{} ({} bytes): {e}{hint}", state.display(), bytes.len())
        })?;
    let h = &solved.header;
    println!(
        "{}: {} checkpoint, {} bytes, {} channels, f = {}, p = {}; solved in {}",
        state.display(),
        h.scalar_name(),
        bytes.len(),
        h.channels,
        h.f,
        h.p,
        h.scalar_name()
    );
    println!("{}", model_text(&solved.model));
    if let Some(path) = json {
        let kind = solved.shared_knots.then(|| "static".to_string());
        save_json(path, &solved.model.to_json(kind)).map_err(|e| e.to_string())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Paper {
            case,
            runs,
            seed,
            out,
            order,
            basis,
            method,
            hold,
        } => {
            let cfg = PaperConfig {
                runs,
                seed,
                order,
                basis: basis.into(),
                hold,
                settle: hold / 2,
                ..PaperConfig::default()
            };
            let cases: Vec<Case> = match case {
                CaseArg::Switch => vec![Case::Switch],
                CaseArg::Backlash => vec![Case::Backlash],
                CaseArg::Both => vec![Case::Switch, Case::Backlash],
            };
            std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
            let bar = ProgressBar::new((runs * cases.len()) as u64);
            bar.set_style(
                ProgressStyle::with_template("{msg:>9} [{bar:40}] {pos}/{len} runs ({elapsed})")
                    .map_err(|e| e.to_string())?
                    .progress_chars("=> "),
            );
            let mut results = Vec::new();
            for &c in &cases {
                bar.set_message(c.name());
                let tick = || bar.inc(1);
                results.push(run_case(c, &cfg, &tick));
            }
            bar.finish_and_clear();
            println!("{}", paper_table(&cfg, &results));
            let mut files = Vec::new();
            for r in &results {
                files.extend(write_figures(r, &out)?);
            }
            let mut summary: serde_json::Map<String, serde_json::Value> = results
                .iter()
                .map(|r| {
                    (
                        r.summary.case.clone(),
                        serde_json::to_value(&r.summary).unwrap_or_default(),
                    )
                })
                .collect();
            if let Some(method) = method {
                let methods = method.methods();
                let bar = ProgressBar::new((runs * cases.len() * methods.len()) as u64);
                bar.set_style(
                    ProgressStyle::with_template(
                        "{msg:>9} [{bar:40}] {pos}/{len} identifications ({elapsed})",
                    )
                    .map_err(|e| e.to_string())?
                    .progress_chars("=> "),
                );
                let mut all = Vec::new();
                for &c in &cases {
                    bar.set_message(c.name());
                    let tick = || bar.inc(1);
                    all.push(run_methods(c, &cfg, &methods, &tick).map_err(|e| e.to_string())?);
                }
                bar.finish_and_clear();
                println!("{}", methods_table(&cfg, &all));
                for c in &all {
                    files.extend(write_method_figures(c, &out)?);
                    if let Some(serde_json::Value::Object(o)) = summary.get_mut(c.case.name()) {
                        o.insert("methods".to_string(), methods_json(c));
                    }
                }
            }
            let path = out.join("summary.json");
            let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
            std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
            println!("wrote {}", path.display());
            for f in files {
                println!("wrote {f}");
            }
            Ok(())
        }
        Cmd::Excite {
            umin,
            umax,
            samples,
            hold,
            seed,
        } => {
            let u: Vec<f64> = Excitation::new(umin, umax, hold, Pcg32::seed_from_u64(seed))
                .map_err(|e| e.to_string())?
                .take(samples)
                .collect();
            let stdout = std::io::stdout();
            write_columns_to("<stdout>", stdout.lock(), &["u"], &[u]).map_err(|e| e.to_string())
        }
        Cmd::Identify {
            data,
            umin,
            umax,
            segments,
            knots_asc,
            knots_desc,
            order,
            hold,
            settle,
            f,
            p,
            input_column,
            output_column,
            basis,
            nonlinearity,
            mu0,
            refine,
            json,
        } => {
            if !(umin.is_finite() && umax.is_finite() && umin < umax) {
                return Err(format!(
                    "invalid input interval [{umin}, {umax}]: --umin must be finite and below --umax"
                ));
            }
            if segments == SegmentCount::Fixed(0) {
                return Err("--segments 0: each path needs at least one segment".to_string());
            }
            let cols = read_columns(&data, &[input_column.as_str(), output_column.as_str()])
                .map_err(|e| e.to_string())?;
            let (u, y) = (&cols[0], &cols[1]);
            if hold >= u.len() {
                return Err(format!(
                    "{}: {} samples, all inside the hold of {hold} (--hold): nothing left to identify from",
                    data.display(),
                    u.len()
                ));
            }
            let fixed = match segments {
                SegmentCount::Fixed(n) => n,
                SegmentCount::Auto => 7,
            };
            let mut opts = IdentifyOptions::uniform(umin, umax, fixed, hold);
            opts.mu0 = mu0;
            opts.static_nonlinearity = matches!(nonlinearity, NonlinearityArg::Static);
            let knots_given = knots_asc.as_ref().or(knots_desc.as_ref()).map(|_| ());
            if let Some(k) = knots_asc {
                opts.knots_asc = k;
            }
            if let Some(k) = knots_desc {
                opts.knots_desc = k;
            }
            for (name, k) in [
                ("--knots-asc", &opts.knots_asc),
                ("--knots-desc", &opts.knots_desc),
            ] {
                if k.first() != Some(&umin) || k.last() != Some(&umax) {
                    return Err(format!(
                        "{name} must start at --umin {umin} and end at --umax {umax}"
                    ));
                }
            }
            opts.f = f;
            opts.p = p;
            opts.order = order;
            opts.basis = basis.into();
            opts.settle = settle.unwrap_or(hold / 2);
            if segments == SegmentCount::Auto && knots_given.is_none() {
                let choice = select_segments(u, y, &opts, AUTO_CANDIDATES, Criterion::Bic)
                    .map_err(|e| format!("{}: {e}", data.display()))?;
                println!("{}", choice.report());
                let k = uniform_knots(umin, umax, choice.segments);
                opts.knots_asc = k.clone();
                opts.knots_desc = k;
            }
            let model = identify(u, y, &opts).map_err(|e| locate_sample_error(&data, &e))?;
            let pem = PemOptions::for_identify(&opts);
            let (model, noise) = if refine {
                let fit = refine_model(u, y, &model, &pem)
                    .map_err(|e| format!("{}: {e}", data.display()))?;
                println!(
                    "refined by the prediction-error method: {} iterations, {} parameters, D {}",
                    fit.iterations,
                    fit.parameters(),
                    if fit.layout.feedthrough {
                        "estimated"
                    } else {
                        "= 0 (not significant)"
                    }
                );
                (fit.model, Some(fit.noise))
            } else {
                // Remark 6 for the subspace model; without it only the simulation is reported.
                let nf = estimate_noise(&model, u, y, pem.start, NoiseOrder::default());
                if let Err(e) = &nf {
                    println!("no noise model: {e}");
                }
                (model, nf.ok().map(|f| f.model))
            };
            println!("{}", model_text(&model));
            let sim = model.simulate(u);
            println!("{}", fit_report(&y[hold..], &sim[hold..])?);
            if let Some(noise) = &noise {
                println!("{}", noise_text(noise));
                let pred = InnovationForm::new(&model, noise).predict(u, y);
                println!(
                    "{}",
                    prediction_report(&y[hold..], &pred[hold..], noise.sigma2)?
                );
            }
            if let Some(path) = json {
                save_json(&path, &model.to_json(Some(nonlinearity.name().to_string())))
                    .map_err(|e| e.to_string())?;
                println!("wrote {}", path.display());
                let side = sidecar_path(&path);
                match &noise {
                    Some(noise) => {
                        noise.save(&side)?;
                        println!("wrote {}", side.display());
                    }
                    // A stale noise model must not be paired with the new model.
                    None => {
                        let _ = std::fs::remove_file(&side);
                    }
                }
            }
            Ok(())
        }
        Cmd::Diagnose(args) => hsid_host::diagnose::cli::run(&args),
        Cmd::Solve { state, json } => solve_state(&state, json.as_deref()),
        Cmd::Validate {
            model,
            data,
            skip,
            input_column,
            output_column,
            noise,
        } => {
            let noise_path = noise.or_else(|| Some(sidecar_path(&model)).filter(|p| p.exists()));
            let noise_model = match &noise_path {
                Some(p) => Some(NoiseModel::load(p)?),
                None => None,
            };
            let m = load_json(&model).map_err(|e| e.to_string())?;
            let m = hsid_host::identify::HostModel::from_json(&m);
            let cols = read_columns(&data, &[input_column.as_str(), output_column.as_str()])
                .map_err(|e| e.to_string())?;
            let (u, y) = (&cols[0], &cols[1]);
            if skip >= u.len() {
                return Err(format!("--skip {skip} leaves no samples of {}", u.len()));
            }
            let (lo, hi) = (m.u_min(), m.u_max());
            if let Some((i, v)) = u.iter().enumerate().find(|(_, v)| **v < lo || **v > hi) {
                return Err(format!(
                    "{} line {}: u = {v} lies outside the model's interval [{lo}, {hi}]",
                    data.display(),
                    i + 2
                ));
            }
            let sim = m.simulate(u);
            println!("{}", fit_report(&y[skip..], &sim[skip..])?);
            if let Some(nm) = noise_model {
                let pred = InnovationForm::new(&m, &nm).predict(u, y);
                println!(
                    "{}",
                    prediction_report(&y[skip..], &pred[skip..], nm.sigma2)?
                );
            }
            Ok(())
        }
    }
}
