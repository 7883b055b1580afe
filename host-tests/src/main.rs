//! `hsid`: identify backlash/switch Hammerstein systems from data, reproduce the paper.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use hsid::{Basis, Excitation};
use hsid_host::identify::{IdentifyOptions, identify};
use hsid_host::io::{load_json, read_columns, save_json, write_columns_to};
use hsid_host::paper::{Case, PaperConfig, run_case, write_figures};
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
        /// Uniform segments per path (ignored when knots are given).
        #[arg(long, default_value_t = 7)]
        segments: usize,
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

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Paper {
            case,
            runs,
            seed,
            out,
            order,
            basis,
        } => {
            let cfg = PaperConfig {
                runs,
                seed,
                order,
                basis: basis.into(),
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
            for c in cases {
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
            let summary: serde_json::Map<String, serde_json::Value> = results
                .iter()
                .map(|r| {
                    (
                        r.summary.case.clone(),
                        serde_json::to_value(&r.summary).unwrap_or_default(),
                    )
                })
                .collect();
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
            json,
        } => {
            if !(umin.is_finite() && umax.is_finite() && umin < umax) {
                return Err(format!(
                    "invalid input interval [{umin}, {umax}]: --umin must be finite and below --umax"
                ));
            }
            if segments == 0 {
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
            let mut opts = IdentifyOptions::uniform(umin, umax, segments, hold);
            opts.mu0 = mu0;
            opts.static_nonlinearity = matches!(nonlinearity, NonlinearityArg::Static);
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
            let model = identify(u, y, &opts).map_err(|e| locate_sample_error(&data, &e))?;
            println!("{}", model_text(&model));
            let sim = model.simulate(u);
            println!("{}", fit_report(&y[hold..], &sim[hold..])?);
            if let Some(path) = json {
                save_json(&path, &model.to_json(Some(nonlinearity.name().to_string())))
                    .map_err(|e| e.to_string())?;
                println!("wrote {}", path.display());
            }
            Ok(())
        }
        Cmd::Validate {
            model,
            data,
            skip,
            input_column,
            output_column,
        } => {
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
            Ok(())
        }
    }
}
