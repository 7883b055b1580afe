//! `hsid diagnose`: arguments and the run.

mod integrating;

use crate::failure::{Failure, note, outln};
use hsid_host::hold::read_hold;
use hsid_host::model::{Element, Record};
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use hsid_host::diagnose::report::ModelSummary;
use hsid_host::diagnose::{
    DiagnoseError, DiagnoseOptions, Effect, InitialState, PoleRefinement, Validation, diagnose,
    figures, report,
};
use hsid_host::html::Reproduction;
use hsid_host::html::diagnosis_page::{diagnosis_figures, diagnosis_page};
use hsid_host::identify::IdentifyOptions;
use hsid_host::integrating::increments_options;
use hsid_host::model_file::Units;
use hsid_host::refine::knots::SegmentCount;
use hsid_host::units::{Origin, resolve_ts};
use hsid_host::workflow::{Field, IdentifyRequest, Syntax};

use crate::args::{CsvArgs, HoldArgs, Horizons, KnotArgs, UnitArgs, finite_f64, read_record};

/// Initial state of the simulations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InitialArg {
    /// At rest at u_min (after a hold).
    Rest,
    /// Least squares on the estimation record; every record starts from it.
    Estimate,
}

/// Where the poles are refined.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RefineArg {
    /// Never.
    Never,
    /// In the reported models only.
    Final,
    /// In every fit.
    Always,
}

/// Arguments of `hsid diagnose`.
#[derive(Args, Clone, Debug)]
pub struct DiagnoseArgs {
    /// Estimation data: CSV file with a header (`-`: standard input).
    #[arg(long)]
    pub data: PathBuf,
    /// Validation data (CSV); without it the estimation file is split (see --split, --holdout).
    #[arg(long)]
    pub validation: Option<PathBuf>,
    /// Without --validation: fraction of the samples after the hold used for estimation; the
    /// rest validates.
    #[arg(long, default_value_t = 0.7, value_parser = finite_f64)]
    pub split: f64,
    /// Without --validation: hold out samples START..END (0-based, END exclusive) for
    /// validation instead, and estimate on the rest.
    #[arg(long)]
    pub holdout: Option<String>,
    /// Samples at the start of the validation file not scored (default: the hold).
    #[arg(long)]
    pub validation_skip: Option<usize>,
    /// Input column name (both files).
    #[arg(long, default_value = "u")]
    pub input_column: String,
    /// Output column name (both files).
    #[arg(long, default_value = "y")]
    pub output_column: String,
    /// Input column of the validation file (default: --input-column).
    #[arg(long)]
    pub validation_input_column: Option<String>,
    /// Output column of the validation file (default: --output-column).
    #[arg(long)]
    pub validation_output_column: Option<String>,
    /// The input element.
    #[arg(long, value_enum, default_value = "backlash")]
    pub nonlinearity: Element,
    /// Lower end of the input interval (default: the smallest input of the data).
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    pub umin: Option<f64>,
    /// Upper end of the input interval (default: the largest input of the data).
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    pub umax: Option<f64>,
    /// Uniform segments per path (ignored when knots are given).
    #[arg(long, default_value_t = 7)]
    pub segments: usize,
    /// Choose the uniform segments per path in MIN..MAX (inclusive) by the BIC of the
    /// estimation simulation error instead (e.g. `3..8`).
    #[arg(long)]
    pub select_segments: Option<String>,
    /// Knots of both paths (or of the static border), comma separated, u_min first, u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, value_parser = finite_f64)]
    pub knots: Option<Vec<f64>>,
    #[command(flatten)]
    pub paths: KnotArgs,
    /// Model order (default: automatic).
    #[arg(long)]
    pub order: Option<usize>,
    #[command(flatten)]
    pub hold: HoldArgs,
    /// Known μ0 = H(u_min) for data without a hold; without it μ0 is estimated.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    pub mu0: Option<f64>,
    #[command(flatten)]
    pub horizons: Horizons,
    /// Initial state of the simulations (default: rest with a hold, estimate without).
    #[arg(long, value_enum)]
    pub initial_state: Option<InitialArg>,
    /// Most effects added.
    #[arg(long, default_value_t = 4)]
    pub max_steps: usize,
    /// Least relative reduction of the estimation hold-out MSE for an effect to be added.
    #[arg(long, default_value_t = 0.20, value_parser = finite_f64)]
    pub min_gain: f64,
    /// Largest extra input delay tried (samples).
    #[arg(long, default_value_t = 10)]
    pub max_delay: usize,
    /// Fraction of the estimation samples (after the hold) the inner hold-out fits on; the
    /// rest, one block, scores every setting and effect.
    #[arg(long, default_value_t = 0.7, value_parser = finite_f64)]
    pub inner_fraction: f64,
    /// Where the poles are refined by the simulation error (variable projection) after the
    /// subspace step: never, in the reported models only, or in every fit.
    #[arg(long, value_enum, default_value = "final")]
    pub refine_poles: RefineArg,
    /// Folder for the figures.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// File name prefix of the figures (a name, not a path: no `/`, `\\` or control
    /// characters, so the figures stay in --out).
    #[arg(long, default_value = "", value_parser = file_prefix)]
    pub prefix: String,
    /// Title of the figures.
    #[arg(long, default_value = "diagnosis")]
    pub title: String,
    /// Write the JSON report here.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write a self-contained HTML report (verdict, before/after, figures, checks and tests,
    /// the command line) to this file.
    #[arg(long, value_name = "FILE")]
    pub html: Option<PathBuf>,
    /// Write the final model's Hammerstein part here, as a model file (format hsid-model/1);
    /// the extensions the diagnosis added are in the JSON report only.
    #[arg(long)]
    pub model_out: Option<PathBuf>,
    /// The plant integrates (voltage → position, a level loop): diagnose its stable part on
    /// the output's increments y(t) − y(t − 1), one pole fixed at z = 1, as `identify
    /// --integrating` identifies it; every error is then of the increments (output units per
    /// sample), and the model file of --model-out records the integrator.
    #[arg(long)]
    pub integrating: bool,
    /// Column of the estimation file holding the controller's reference (setpoint) of a
    /// closed-loop record: the base model and every refit are then the closed-loop consistent
    /// estimate (PI-MOESP on instruments from the reference, order of the open-loop estimate
    /// unless --order; poles not refined by the output error) instead of the open-loop one,
    /// which feedback biases (docs/closed-loop.md). Needs a two-path element (not
    /// --nonlinearity static), a hold or --mu0, and no --integrating; the validation file
    /// needs no reference.
    #[arg(long, value_name = "NAME")]
    pub reference_column: Option<String>,
    #[command(flatten)]
    pub csv: CsvArgs,
    /// Sample time and units (checked against the records' time columns), stored in the
    /// model file of --model-out.
    #[command(flatten)]
    pub units: UnitArgs,
}

fn parse_range(s: &str) -> Result<std::ops::Range<usize>, String> {
    let (a, b) = s
        .split_once("..")
        .or_else(|| s.split_once(':'))
        .ok_or_else(|| format!("--holdout {s}: expected START..END"))?;
    let p = |v: &str| {
        v.trim()
            .parse::<usize>()
            .map_err(|_| format!("--holdout {s}: {v:?} is not a sample index"))
    };
    Ok(p(a)?..p(b)?)
}

/// A record read for diagnosis, with the sample times and units its file states.
struct Stated {
    record: Record,
    ts: Vec<(Origin, f64)>,
    units: Vec<(hsid_host::units::UnitsOrigin, Units)>,
}

/// Reads the input and output columns (and the reference column, when named) of a CSV file
/// as a record, with the sample times of its time column and header comment and the units of
/// its header comments.
fn record(
    path: &std::path::Path,
    names: [&str; 2],
    reference: Option<&str>,
    csv: &CsvArgs,
    units: &UnitArgs,
) -> Result<Stated, String> {
    let all: Vec<&str> = names.into_iter().chain(reference).collect();
    let r = read_record(path, &all, csv, units)?;
    let mut columns = r.table.columns.into_iter();
    let (Some(u), Some(y)) = (columns.next(), columns.next()) else {
        return Err("internal: two columns expected".to_string());
    };
    let record = Record::new(u, y)
        .and_then(|rec| match columns.next() {
            Some(r) => rec.with_reference(r),
            None => Ok(rec),
        })
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Stated {
        record,
        ts: r.ts,
        units: r.units,
    })
}

/// The identification settings: the interval (given, from the knots or from the data), the
/// knots, the order, horizons, hold and μ0; the estimation record (the first of `all_u`)
/// checked to outlast the hold.
fn identify_options(a: &DiagnoseArgs, all_u: &[&Record]) -> Result<IdentifyOptions, String> {
    let (lo, hi) = all_u
        .iter()
        .flat_map(|r| r.u.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let knots_all = a.knots.clone();
    let umin = a
        .umin
        .or_else(|| knots_all.as_ref().and_then(|k| k.first().copied()))
        .unwrap_or(lo);
    let umax = a
        .umax
        .or_else(|| knots_all.as_ref().and_then(|k| k.last().copied()))
        .unwrap_or(hi);
    // The library's request check, as identify's: the interval, the segments, the knots.
    let mut r = IdentifyRequest::new(umin, umax, Syntax::Cli);
    r.segments = Some(SegmentCount::Fixed(a.segments));
    r.knots_asc = a.paths.knots_asc.clone().or_else(|| knots_all.clone());
    r.knots_desc = a.paths.knots_desc.clone().or_else(|| knots_all.clone());
    r.order = a.order;
    r.horizons = Some(a.horizons.or_paper());
    r.settle = a.hold.settle;
    r.mu0 = a.mu0;
    r.element = a.nonlinearity;
    let plan = r.validate(a.hold.hold).map_err(|e| {
        // Knots given once for both paths are `--knots`.
        let own = match e.field {
            Field::KnotsAsc => a.paths.knots_asc.is_some(),
            Field::KnotsDesc => a.paths.knots_desc.is_some(),
            _ => true,
        };
        match own {
            true => e.message,
            false => {
                let name = Syntax::Cli.name(e.field);
                e.message.replacen(name, "--knots", 1)
            }
        }
    })?;
    // The estimation record must outlast the hold, checked as identify checks it.
    r.integrating = a.integrating;
    let samples = all_u.first().map_or(0, |r| r.len());
    r.check_hold(samples, a.hold.hold)
        .map_err(|e| format!("{}: {}", a.data.display(), e.message))?;
    Ok(plan.options)
}

/// The diagnosis settings around the identification's.
fn options(a: &DiagnoseArgs, id: IdentifyOptions) -> Result<DiagnoseOptions, String> {
    let mut opts = DiagnoseOptions::new(id, a.nonlinearity);
    opts.initial = a.initial_state.map(|i| match i {
        InitialArg::Rest => InitialState::Rest,
        InitialArg::Estimate => InitialState::Estimated,
    });
    opts.max_steps = a.max_steps;
    opts.min_gain = a.min_gain;
    opts.max_delay = a.max_delay;
    opts.inner_fraction = a.inner_fraction;
    if let Some(r) = &a.select_segments {
        let r = parse_range(r).map_err(|e| e.replace("--holdout", "--select-segments"))?;
        opts.select_segments = Some(r.start..=r.end);
    }
    opts.refine_poles = match a.refine_poles {
        RefineArg::Never => PoleRefinement::Never,
        RefineArg::Final => PoleRefinement::Final,
        RefineArg::Always => PoleRefinement::Always,
    };
    // The library's bounds, before the record is diagnosed, in the command line's words.
    opts.check().map_err(|e| match e {
        DiagnoseError::Setting { name, value, why } => {
            format!("--{} {value}: {why}", name.replace('_', "-"))
        }
        e => e.to_string(),
    })?;
    Ok(opts)
}

/// Whether an added effect changes the model beyond what a model file holds (the order, the
/// noise model, a robust refit, the element with memory and friction it does hold).
fn not_in_the_model_file(e: Effect) -> bool {
    match e {
        Effect::UnmodeledDynamics
        | Effect::ColoredNoise
        | Effect::Outliers
        | Effect::Hysteresis
        | Effect::Friction => false,
        Effect::OffsetDrift
        | Effect::InputDelay
        | Effect::OutputNonlinearity
        | Effect::PeriodicDisturbance
        | Effect::StateDependentDynamics
        | Effect::PlayBetween => true,
    }
}

/// Refuses what the closed-loop estimate from `--reference-column` does not cover: a static
/// element, the increments of an integrating plant.
fn refuse_bad_flags(a: &DiagnoseArgs) -> Result<(), Failure> {
    let Some(name) = &a.reference_column else {
        return Ok(());
    };
    if a.nonlinearity == Element::Static {
        return Err(crate::identify::reference::static_refused(name));
    }
    if a.integrating {
        return Err(format!(
            "--reference-column {name} is not available with --integrating (the closed-loop estimate is for the output itself, not its increments): drop one of them"
        )
        .into());
    }
    Ok(())
}

/// Runs `hsid diagnose`: prints the text report, writes the figures, the JSON report and the
/// model file.
pub fn run(a: &DiagnoseArgs) -> Result<(), Failure> {
    refuse_bad_flags(a)?;
    let Stated {
        record: est,
        ts: est_ts,
        units: est_units,
    } = record(
        &a.data,
        [&a.input_column, &a.output_column],
        a.reference_column.as_deref(),
        &a.csv,
        &a.units,
    )?;
    let mut stated: Vec<(Origin, f64)> = a
        .units
        .ts()?
        .map(|v| (Origin::Flag, v))
        .into_iter()
        .collect();
    stated.extend(est_ts);
    let mut unit_comments = est_units;
    let val = match &a.validation {
        Some(path) => {
            let ic = a
                .validation_input_column
                .as_ref()
                .unwrap_or(&a.input_column);
            let oc = a
                .validation_output_column
                .as_ref()
                .unwrap_or(&a.output_column);
            let r = record(path, [ic, oc], None, &a.csv, &a.units)?;
            stated.extend(r.ts);
            unit_comments.extend(r.units);
            Some(r.record)
        }
        None => None,
    };
    let ts = resolve_ts(&stated).map_err(|e| e.to_string())?;
    let units = a.units.resolve_units(unit_comments)?;
    let records: Vec<&Record> = std::iter::once(&est).chain(val.as_ref()).collect();
    let mut opts = options(a, identify_options(a, &records)?)?;
    drop(records);
    let mut est = est;
    if let Some(&u_min) = opts.identify.knots_asc.first() {
        let tolerance = a.hold.hold_tolerance.unwrap_or(0.0);
        let sample = |i: usize| format!("sample {i}");
        let read = read_hold(&mut est.u, u_min, a.hold.hold, tolerance)
            .map_err(|e| format!("{} {}", a.data.display(), e.describe(&sample)))?;
        if let (Some(largest), true) = (read.largest, read.replaced > 0) {
            note(&format!(
                "{}: {} inputs of the hold are within --hold-tolerance {tolerance} of u_min = \
                 {u_min} (the largest deviation {:.2e}, sample {}) and are read as u_min",
                a.data.display(),
                read.replaced,
                largest.deviation,
                largest.index
            ));
        }
    }
    let mut validation = match (val, &a.holdout) {
        (Some(v), _) => Validation::Separate {
            record: v,
            skip: a.validation_skip.unwrap_or(a.hold.hold),
        },
        (None, Some(r)) => Validation::Holdout(parse_range(r)?),
        (None, None) => Validation::Split(a.split),
    };
    let est = if a.integrating {
        outln!(
            "--integrating: the stable part G0 of the plant (one pole fixed at z = 1) on the output's increments y(t) - y(t-1); every error below is of the increments, output units per sample"
        )?;
        opts.identify = increments_options(&opts.identify);
        opts.increments = true;
        validation = integrating::validation(validation);
        est.increments()
    } else {
        est
    };
    let d = diagnose(&est, &validation, &opts).map_err(|e| format!("{}: {e}", a.data.display()))?;
    outln!("{}", report::text(&d))?;
    if let Some(dir) = &a.out {
        // Written together: a run that fails or is stopped leaves the previous figures.
        let files = crate::figures::in_stage(dir, |stage| {
            figures::write_figures(&d, stage, &a.prefix, &a.title)
        })?;
        for f in files {
            outln!("wrote {}", f.display())?;
        }
    }
    if let Some(path) = &a.json {
        let text = serde_json::to_string_pretty(&report::to_json(&d))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        hsid_host::io::write_atomic(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        outln!("wrote {}", path.display())?;
    }
    if let Some(path) = &a.html {
        let figures = diagnosis_figures(&d, &a.title).map_err(|e| e.to_string())?;
        let inputs: Vec<&PathBuf> = std::iter::once(&a.data).chain(&a.validation).collect();
        let title = format!("hsid diagnose: {}", a.data.display());
        let rep = Reproduction::of_this_run(&inputs);
        diagnosis_page(&d, title, ts, units.clone(), figures, rep)
            .write(path)
            .map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
    }
    if let Some(path) = &a.model_out {
        let mut file = ModelSummary::of(&d.model, d.nonlinearity).model;
        file.integrating = a.integrating;
        file.sample_time = ts;
        file.units = units;
        file.save(path).map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
        let outside: Vec<&str> = d
            .steps
            .iter()
            .map(|s| s.effect)
            .filter(|&e| not_in_the_model_file(e))
            .map(Effect::name)
            .collect();
        if !outside.is_empty() {
            outln!(
                "note: {} holds the Hammerstein part; {} only in the JSON report's model_after",
                path.display(),
                outside.join(", ")
            )?;
        }
    }
    Ok(())
}

/// `--prefix`: the start of a file name, so that no figure is written outside `--out`.
fn file_prefix(s: &str) -> Result<String, String> {
    match s.chars().find(|&c| c == '/' || c == '\\' || c.is_control()) {
        Some(c) => Err(format!(
            "{:?} is not a file-name prefix: it holds {:?} (figures are written inside --out; \
             give a name such as \"run1-\")",
            s, c
        )),
        None => Ok(s.to_string()),
    }
}
