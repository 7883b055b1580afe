//! `hsid validate`: a model file simulated (and, with a noise model, predicted) on a record.

use crate::failure::{Failure, outln};
use hsid_host::model::{Element, Simulate, Syntax, first_outside, for_input};
use std::path::{Path, PathBuf};

use clap::Args;
use hsid_host::figures::{
    FigureSettings, RecordView, UncertaintySource, write_element_model_figures,
};
use hsid_host::friction::{FrictionModel, Initial};
use hsid_host::html::model_page::ModelRun;
use hsid_host::html::model_words::{ModelElement, element_facts};
use hsid_host::html::{Reproduction, figures};
use hsid_host::hysteresis::{self, HysteresisModel};
use hsid_host::identify::HostModel;
use hsid_host::model_file::{ModelFile, Units};
use hsid_host::refine::poly::is_stable;
use hsid_host::refine::stochastic::prediction_report;
use hsid_host::refine::{InnovationForm, NoiseModel};
use hsid_host::report::{Fit, fit, fit_report};
use hsid_host::units::{Origin, UnitReport, UnitsOrigin, resolve_ts};
use serde::Serialize;

use crate::args::{Columns, CsvArgs, DEFAULT_HOLD, UnitArgs, read_uy};

/// Arguments of `hsid validate`.
#[derive(Args)]
pub struct ValidateArgs {
    /// Model file written by `hsid identify --json` (format hsid-model/1).
    #[arg(long)]
    model: PathBuf,
    /// CSV file with a header (`-`: standard input).
    #[arg(long)]
    data: PathBuf,
    /// Samples at the start left out of the fits (the hold) [default: 300, the default
    /// --hold of identify and diagnose, whose validation skips the hold too; --skip 0 scores
    /// every sample].
    #[arg(long)]
    skip: Option<usize>,
    #[command(flatten)]
    columns: Columns,
    #[command(flatten)]
    csv: CsvArgs,
    /// Noise model JSON (`c`, `d`, `sigma2`) for one-step-ahead predictions, in place of the
    /// model file's own `noise` (default: the model file's, when it has one).
    #[arg(long)]
    noise: Option<PathBuf>,
    /// Sample time and units: taken from the model file; a flag given as well must agree
    /// with it (and with the record's time column).
    #[command(flatten)]
    units: UnitArgs,
    #[command(flatten)]
    figures: crate::figures::FigureArgs,
    /// Write a self-contained HTML report (model in units, fit, figures, residual tests, the
    /// command line) to this file.
    #[arg(long, value_name = "FILE")]
    html: Option<PathBuf>,
    /// Refuse a record whose input leaves the model's [u_min, u_max] (naming its line and
    /// value). By default the borders are extended linearly beyond it on the end segments'
    /// lines, and a line `note: …` says how many samples lie outside.
    #[arg(long)]
    strict_interval: bool,
    /// Write what validate prints as a JSON document (format hsid-validate/1) to this file:
    /// the fits (RMSE, NRMSE, fit %), the samples scored, the sample time, the units, the
    /// model read in them and the warnings.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// For a model with friction of an integrating plant (`identify --integrating
    /// --friction`): the first samples of the record whose output sets the initial position
    /// and velocity (least squares on their simulation; the benchmark protocols of
    /// positioning drives allow the first 20). The position is then simulated from the input
    /// and scored.
    #[arg(long, value_name = "SAMPLES", default_value_t = 20)]
    initial_samples: usize,
}

/// A fit in the JSON document of `validate --json`.
#[derive(Serialize)]
struct FitJson {
    rmse: f64,
    nrmse: f64,
    fit_percent: f64,
}

impl From<Fit> for FitJson {
    fn from(f: Fit) -> Self {
        Self {
            rmse: f.rmse,
            nrmse: f.nrmse,
            fit_percent: f.fit_percent,
        }
    }
}

/// The JSON document of `validate --json`: what validate prints, as numbers.
#[derive(Serialize)]
struct ValidateJson<'a> {
    format: &'static str,
    model: String,
    data: String,
    /// Samples of the record (after the integrating model's differencing).
    samples: usize,
    /// Samples at the start not scored.
    skip: usize,
    /// Samples scored: `samples − skip`.
    samples_scored: usize,
    simulation: FitJson,
    /// The one-step prediction fit, with a noise model.
    prediction: Option<FitJson>,
    /// The innovation standard deviation of the noise model.
    innovation_std: Option<f64>,
    sample_time: Option<f64>,
    units: Option<&'a Units>,
    /// The model read in units (poles in continuous time, gains, gap).
    reading: &'a UnitReport,
    /// The notes validate printed (input outside the interval, an integrating model, …).
    warnings: Vec<String>,
}

/// Prints the simulation fit and, with a noise model, the one-step prediction fit.
pub fn run(a: &ValidateArgs) -> Result<(), Failure> {
    a.figures.check_true_plant(a.html.is_some())?;
    let file = ModelFile::load(&a.model).map_err(|e| e.to_string())?;
    let noise = noise(a, &file)?;
    let m = HostModel::from_json(&file);
    let record = read_uy(&a.data, &a.columns, &a.csv, &a.units)?;
    let stored = file
        .units
        .clone()
        .map(|u| (UnitsOrigin::ModelFile(a.model.clone()), u));
    let units = a
        .units
        .resolve_units(stored.into_iter().chain(record.units))?;
    let stated: Vec<(Origin, f64)> = a
        .units
        .ts()?
        .map(|v| (Origin::Flag, v))
        .into_iter()
        .chain(
            file.sample_time
                .map(|v| (Origin::ModelFile(a.model.clone()), v)),
        )
        .chain(record.ts)
        .collect();
    let ts = resolve_ts(&stated).map_err(|e| e.to_string())?;
    let mut table = record.table;
    let mut warnings: Vec<String> = Vec::new();
    let friction = FrictionModel::from_file(&file);
    if friction.is_some() && (a.figures.dir().is_some() || a.html.is_some()) {
        return Err(
            "the figures and the page do not draw a model with friction yet: drop --out and \
             --html (the fit is printed)"
                .to_string()
                .into(),
        );
    }
    if let Some(f) = friction.as_ref().filter(|f| f.integrating) {
        let k = a.initial_samples;
        if k == 0 || k > table.columns[1].len() {
            return Err(format!(
                "--initial-samples {k}: give between 1 and the record's {} samples",
                table.columns[1].len()
            )
            .into());
        }
        let w = format!(
            "integrating model with friction: the position simulated from the input, from the \
             position and velocity that fit the first {k} samples (Coulomb {:.6}, offset {:.6} \
             in the element's output units)",
            f.friction.coulomb, f.friction.offset
        );
        outln!("{w}")?;
        warnings.push(w);
    } else if file.integrating {
        // The file holds the stable part: it is validated on the output's increments.
        let w = "integrating model (one pole at z = 1): validated on the output's increments";
        outln!("{w}")?;
        warnings.push(w.to_string());
        table.columns[1] = hsid_host::integrating::difference(&table.columns[1]);
        table.lines.drain(..table.lines.len().min(1));
        let first = table.columns[0].len().min(1);
        table.columns[0].drain(..first);
    }
    let (u, y) = (&table.columns[0], &table.columns[1]);
    let skip = a.skip.unwrap_or(DEFAULT_HOLD);
    if skip >= u.len() {
        let default = match a.skip {
            Some(_) => "",
            None => " (the default, the hold of identify's and diagnose's default --hold)",
        };
        return Err(format!(
            "--skip {skip}{default} leaves no samples of {} to score: give a smaller --skip \
             (0 scores every sample)",
            u.len()
        )
        .into());
    }
    let (lo, hi) = (m.u_min(), m.u_max());
    if a.strict_interval
        && let Some(i) = first_outside(u, lo, hi)
    {
        return Err(format!(
            "{} line {}: u = {} lies outside the model's interval [{lo}, {hi}]",
            a.data.display(),
            table.lines[i],
            u[i]
        )
        .into());
    }
    let element = HysteresisModel::from_file(&file);
    // Beyond the interval the borders continue on their end segments' lines: the model as it
    // simulates and predicts the record (the reading, the two-path figures and the page keep
    // the file's knots, which its standard deviations belong to).
    let (extended, outside) = for_input(&m, u);
    if let Some(o) = outside {
        let w = o.note(Syntax::Cli);
        outln!("note: {w}")?;
        warnings.push(w);
    }
    let element = element.map(|h| for_input(&h, u).0.model);
    let sim = match (&element, &friction) {
        (Some(h), _) => hysteresis::simulate::simulate(h, u),
        (None, Some(f)) => {
            let f = FrictionModel {
                plant: extended.model.clone(),
                ..f.clone()
            };
            match f.integrating {
                true => f.simulate_after(u, &y[..a.initial_samples.min(y.len())]),
                false => f.simulate_from(
                    u,
                    Initial::Rest {
                        u_start: extended.u_start,
                    },
                ),
            }
        }
        (None, None) => extended.simulate(u),
    };
    outln!("{}", fit_report(&y[skip..], &sim[skip..])?)?;
    let mut prediction = None;
    if let Some(nm) = &noise {
        let pred = match element.is_some() || friction.is_some() {
            // A simulation that is not `G`'s alone: the noise model predicts its residual.
            true => nm.predict_around(&sim, y),
            false => {
                let mut predictor = InnovationForm::new(&extended.model, nm);
                predictor.u_start = extended.u_start;
                predictor.predict(u, y)
            }
        };
        outln!(
            "{}",
            prediction_report(&y[skip..], &pred[skip..], nm.sigma2)?
        )?;
        prediction = Some(fit(&y[skip..], &pred[skip..]));
    }
    let in_units = reading(&file, &m, ts, units.clone(), &mut warnings)?;
    if let Some(path) = &a.json {
        let doc = ValidateJson {
            format: "hsid-validate/1",
            model: a.model.display().to_string(),
            data: a.data.display().to_string(),
            samples: u.len(),
            skip,
            samples_scored: u.len() - skip,
            simulation: fit(&y[skip..], &sim[skip..]).into(),
            prediction: prediction.map(FitJson::from),
            innovation_std: noise.as_ref().map(|n| n.sigma2.max(0.0).sqrt()),
            sample_time: ts,
            units: units.as_ref(),
            reading: &in_units,
            warnings,
        };
        let text =
            serde_json::to_string_pretty(&doc).map_err(|e| format!("{}: {e}", path.display()))?;
        hsid_host::io::write_atomic(path, text + "\n")
            .map_err(|e| format!("{}: {e}", path.display()))?;
        outln!("wrote {}", path.display())?;
    }
    let shown = Shown {
        file: &file,
        model: &m,
        element: element.as_ref(),
        units: &in_units,
        ts,
        record: RecordView { u, y, skip },
    };
    match &element {
        Some(h) => draw_element(a, h, &shown)?,
        None => crate::figures::validate(&a.figures, &file, &m, u, y, skip)?,
    }
    if let Some(path) = &a.html {
        write_page(a, path, &shown)?;
    }
    Ok(())
}

/// The noise model of `--noise`, else the model file's (its predictor checked stable).
fn noise(a: &ValidateArgs, file: &ModelFile) -> Result<Option<NoiseModel>, Failure> {
    if let Some(p) = &a.noise {
        return Ok(Some(NoiseModel::load(p)?));
    }
    match &file.noise {
        Some(n) if !is_stable(&n.c, 1.0) => Err(format!(
            "{}: field \"noise.c\": a root on or outside the unit circle (unstable predictor)",
            a.model.display()
        )
        .into()),
        Some(n) => Ok(Some(NoiseModel {
            c: n.c.clone(),
            d: n.d.clone(),
            sigma2: n.sigma2,
        })),
        None => Ok(None),
    }
}

/// The model read in units (for an element file, its `G` and borders: the reading `identify`
/// prints after the fit), printed; the pole standard deviations are the file's.
fn reading(
    file: &ModelFile,
    m: &HostModel,
    ts: Option<f64>,
    units: Option<Units>,
    warnings: &mut Vec<String>,
) -> Result<UnitReport, Failure> {
    // The file keeps the standard deviations of re and im of each pole, not their
    // correlation: taken as uncorrelated.
    let cov: Option<Vec<[[f64; 2]; 2]>> = file.std.as_ref().map(|s| {
        s.poles
            .iter()
            .map(|[a, b]| [[a * a, 0.0], [0.0, b * b]])
            .collect()
    });
    if cov.is_some() {
        let w = "pole standard deviations from the model file (re and im taken as uncorrelated)";
        outln!("{w}")?;
        warnings.push(w.to_string());
    }
    let two_path = file.nonlinearity != Some(Element::Static);
    let gap_std = file.std.as_ref().and_then(|s| s.mean_gap);
    let in_units = m
        .unit_report(ts, units, cov.as_deref(), two_path)
        .with_gap_std(gap_std);
    for line in in_units.lines() {
        outln!("{line}")?;
    }
    Ok(in_units)
}

/// The model and the record the figures and the page show.
struct Shown<'a> {
    file: &'a ModelFile,
    model: &'a HostModel,
    /// The play or relay model of a file with `"element"`.
    element: Option<&'a HysteresisModel>,
    units: &'a UnitReport,
    ts: Option<f64>,
    record: RecordView<'a>,
}

impl Shown<'_> {
    /// The figure settings: the sample time and units as resolved, the true loop of
    /// `--true-plant`.
    fn settings(&self, a: &ValidateArgs) -> Result<FigureSettings, Failure> {
        crate::figures::settings(&a.figures, self.ts, self.units.units.as_ref(), self.model)
    }
}

/// `--out` for an element model: the element's figures on the record, its borders without
/// bands (the model file keeps no covariance of them).
fn draw_element(a: &ValidateArgs, h: &HysteresisModel, s: &Shown<'_>) -> Result<(), Failure> {
    let Some(dir) = a.figures.dir() else {
        return Ok(());
    };
    let written = write_element_model_figures(dir, h, None, &s.record, &s.settings(a)?)
        .map_err(|e| e.to_string())?;
    for note in &written.notes {
        outln!("figures: {note}")?;
    }
    outln!(
        "wrote {} figure files (SVG and CSV) to {}",
        written.files.len(),
        dir.display()
    )?;
    Ok(())
}

/// Writes the HTML report to `path`: the element's simulation and figures for an element
/// model, else the model's.
fn write_page(a: &ValidateArgs, path: &Path, s: &Shown<'_>) -> Result<(), Failure> {
    let settings = s.settings(a)?;
    let (element, figures) = match s.element {
        Some(h) => (
            ModelElement::from(h.kind),
            figures::of_element(h, None, &s.record, &settings),
        ),
        None => (
            s.file
                .nonlinearity
                .map_or(ModelElement::TwoPath, ModelElement::from),
            figures::of_model(
                s.model,
                &s.record,
                UncertaintySource::from_file(s.file),
                &settings,
            ),
        ),
    };
    let run = ModelRun {
        title: format!(
            "hsid validate: {} on {}",
            a.model.display(),
            a.data.display()
        ),
        element,
        model: s.model,
        memory: s.element,
        units: s.units,
        parts: &[(s.record.u, s.record.y)],
        skip: s.record.skip,
        estimation: None,
        extra: s
            .element
            .map_or_else(Vec::new, |h| element_facts(h, None, s.units)),
        truth: settings.truth.as_ref(),
    };
    run.page(
        figures.map_err(|e| e.to_string())?,
        Reproduction::of_this_run(&[&a.model, &a.data]),
    )
    .write(path)
    .map_err(|e| e.to_string())?;
    outln!("wrote {}", path.display())?;
    Ok(())
}
