//! `hsid paper`: the Monte Carlo of Section IV, optionally with the other methods.

use crate::failure::{Failure, outln};
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use hsid_host::html::Reproduction;
use hsid_host::html::figures::captioned;
use hsid_host::html::paper_captions::paper_caption;
use hsid_host::html::paper_page::PaperRun;
use hsid_host::html::reproduce::InputFile;
use hsid_host::io::StagedDir;
use hsid_host::paper::method_figures::write_method_figures;
use hsid_host::paper::methods::{Method, methods_json, methods_table, run_methods};
use hsid_host::paper::{Case, PaperConfig, paper_table, run_case, write_figures};
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::BasisArg;

/// Arguments of `hsid paper`.
#[derive(Args)]
pub struct PaperArgs {
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
    /// Also write the run as one self-contained HTML page: what was run beside the paper's
    /// settings, the Monte Carlo table, the figures with captions, the command line.
    #[arg(long, value_name = "FILE")]
    html: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum CaseArg {
    Switch,
    Backlash,
    Both,
}

/// Identification method of `hsid paper --method` (see `hsid_host::paper::methods`).
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

fn progress(len: usize, unit: &str) -> Result<ProgressBar, String> {
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{msg:>9}} [{{bar:40}}] {{pos}}/{{len}} {unit} ({{elapsed}})"
        ))
        .map_err(|e| e.to_string())?
        .progress_chars("=> "),
    );
    Ok(bar)
}

/// Runs the cases, prints the tables, writes summary.json and the figures.
pub fn run(a: &PaperArgs) -> Result<(), Failure> {
    let cfg = PaperConfig {
        runs: a.runs,
        seed: a.seed,
        order: a.order,
        basis: a.basis.into(),
        hold: a.hold,
        settle: a.hold / 2,
        ..PaperConfig::default()
    };
    let cases: Vec<Case> = match a.case {
        CaseArg::Switch => vec![Case::Switch],
        CaseArg::Backlash => vec![Case::Backlash],
        CaseArg::Both => vec![Case::Switch, Case::Backlash],
    };
    // The figures and the summary are written into a staging folder inside --out and moved
    // into place together at the end: a run that fails or is stopped leaves the previous ones.
    let at = |e: std::io::Error| format!("{}: {e}", a.out.display());
    let stage = StagedDir::create(&a.out).map_err(at)?;
    let out = stage.path();
    let bar = progress(a.runs * cases.len(), "runs")?;
    let mut results = Vec::new();
    for &c in &cases {
        bar.set_message(c.name());
        let tick = || bar.inc(1);
        results.push(run_case(c, &cfg, &tick));
    }
    bar.finish_and_clear();
    outln!("{}", paper_table(&cfg, &results))?;
    let mut files = Vec::new();
    for r in &results {
        files.extend(write_figures(r, out)?);
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
    let mut methods_text = None;
    if let Some(method) = a.method {
        let methods = method.methods();
        let bar = progress(a.runs * cases.len() * methods.len(), "identifications")?;
        let mut all = Vec::new();
        for &c in &cases {
            bar.set_message(c.name());
            let tick = || bar.inc(1);
            all.push(run_methods(c, &cfg, &methods, &tick).map_err(|e| e.to_string())?);
        }
        bar.finish_and_clear();
        let table = methods_table(&cfg, &all);
        outln!("{table}")?;
        methods_text = Some(table);
        for c in &all {
            files.extend(write_method_figures(c, out)?);
            if let Some(serde_json::Value::Object(o)) = summary.get_mut(c.case.name()) {
                o.insert("methods".to_string(), methods_json(c));
            }
        }
    }
    let staged = out.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    hsid_host::io::write_atomic(&staged, text).map_err(at)?;
    files.push(staged);
    let mut files = stage.commit(&files).map_err(at)?;
    let path = files.pop().unwrap_or_default();
    outln!("wrote {}", path.display())?;
    for f in &files {
        outln!("wrote {}", f.display())?;
    }
    if let Some(page) = &a.html {
        let run = PaperRun {
            cfg: &cfg,
            results: &results,
            methods: methods_text.as_deref(),
        };
        write_page(&run, &path, &files, page)?;
        outln!("wrote {}", page.display())?;
    }
    Ok(())
}

/// The HTML page of `run` at `page`: the figures read back from `files`, the summary and the
/// figures listed as the outputs.
fn write_page(
    run: &PaperRun<'_>,
    summary: &Path,
    paths: &[PathBuf],
    page: &Path,
) -> Result<(), Failure> {
    let figures = captioned(paths, "", paper_caption).map_err(|e| e.to_string())?;
    let mut rep = Reproduction::of_this_run::<&Path>(&[]);
    rep.settings = run.settings();
    rep.outputs = std::iter::once(summary)
        .chain(paths.iter().map(PathBuf::as_path))
        .map(InputFile::at)
        .collect();
    run.page(figures, rep)
        .write(page)
        .map_err(|e| e.to_string())?;
    Ok(())
}
