//! `hsid simulate`: a true plant from a specification, or an identified model, driven by an
//! input record; the record with the simulated output as CSV on standard output.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use hsid_host::hysteresis::HysteresisModel;
use hsid_host::hysteresis::simulate::simulate;
use hsid_host::identify::HostModel;
use hsid_host::io::{CsvOptions, write_columns_to};
use hsid_host::model::{Interval, OutsideInterval, Syntax, first_outside, for_input};
use hsid_host::model_file::{ModelFile, Units};
use hsid_host::refine::NoiseModel;
use hsid_host::simulate::{
    Colour, InputRecord, Level, ModelNoise, ModelOptions, Output, PlantSpec, header, read_input,
    simulate_model, simulate_plant,
};
use hsid_host::units::{Origin, UnitsOrigin, resolve_ts, ts_from_column};

use crate::args::{CsvArgs, UnitArgs, finite_f64};

/// Arguments of `hsid simulate`.
#[derive(Args)]
pub struct SimulateArgs {
    /// Model file (format hsid-model/1) to simulate.
    #[arg(long, required_unless_present = "plant", conflicts_with = "plant")]
    model: Option<PathBuf>,
    /// Plant specification (JSON, see docs/simulate.md) to simulate.
    #[arg(long)]
    plant: Option<PathBuf>,
    /// CSV file with the input column (and optionally a time column); `-`: standard input.
    #[arg(long)]
    input: PathBuf,
    /// Input column name.
    #[arg(long, default_value = "u")]
    input_column: String,
    #[command(flatten)]
    csv: CsvArgs,
    /// Sample time and units, written to the output's header. With --plant, --ts is the
    /// specification's `ts` when it has none and must agree with it when it has one; with
    /// --model, they must agree with the model file's. A time column of the input is passed
    /// through and must be uniform with the same step.
    #[command(flatten)]
    units: UnitArgs,
    /// Model only: output noise at this SNR (dB) over the record.
    #[arg(
        long,
        requires = "model",
        conflicts_with = "noise_std",
        allow_hyphen_values = true,
        value_parser = finite_f64
    )]
    noise_snr: Option<f64>,
    /// Model only: output noise with this standard deviation of the white noise e.
    #[arg(long, requires = "model", value_parser = finite_f64)]
    noise_std: Option<f64>,
    /// Model only: white noise, or coloured by the model file's noise model (at its stored
    /// variance unless --noise-snr or --noise-std is given).
    #[arg(long, value_enum, requires = "model")]
    noise_colour: Option<ColourArg>,
    /// Seed of the noise generator (with --plant: replaces the specification's seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Model only: what a model does by default, kept for scripts that pass it: inputs outside
    /// the model's [u_min, u_max] continue the end segments of the borders linearly.
    #[arg(long, requires = "model", conflicts_with = "strict_interval")]
    extrapolate: bool,
    /// Model only: refuse an input outside the model's [u_min, u_max] (naming its line and
    /// value) instead of extending the borders linearly beyond it, which is the default and
    /// is noted in a comment line `# note: …` before the columns.
    #[arg(long, requires = "model")]
    strict_interval: bool,
    /// Also write the noise-free output as a column `y_clean`.
    #[arg(long)]
    clean: bool,
}

/// The colour of a model's output noise.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ColourArg {
    /// White noise.
    White,
    /// The model file's noise model.
    Model,
}

/// Simulates and prints the record.
pub fn run(a: &SimulateArgs) -> Result<(), String> {
    let csv = a.csv.options();
    let (output, lines) = match (&a.plant, &a.model) {
        (Some(spec), _) => plant(a, spec, &csv)?,
        (None, Some(model)) => model_run(a, model, &csv)?,
        (None, None) => return Err("give --plant SPEC or --model MODEL.json".to_string()),
    };
    let (input, out) = output;
    print(&input, &out, &lines, a.clean)
}

type Run = ((InputRecord, Output), Vec<String>);

fn plant(a: &SimulateArgs, path: &Path, csv: &CsvOptions) -> Result<Run, String> {
    let mut spec = PlantSpec::load(path).map_err(|e| e.to_string())?;
    let name = path.to_path_buf();
    let input = input(a, csv)?;
    // The specification's own check names its field when `ts` is not positive.
    let stored = spec.ts.map(|v| (Origin::PlantSpec(name.clone()), v));
    spec.ts = sample_time(a, stored, &input)?;
    let given = a.units.units()?;
    let spec_units = spec.units.as_ref();
    let (ui, uo) = match (&given, spec_units) {
        (Some(g), Some(s)) => {
            for (flag, f, v) in [
                ("--input-unit", &g.input, &s.input),
                ("--output-unit", &g.output, &s.output),
            ] {
                if v.as_ref().is_some_and(|v| v != f) {
                    return Err(format!(
                        "{flag} {f} disagrees with the units of {}; drop the flag or make them agree",
                        name.display()
                    ));
                }
            }
            (Some(g.input.clone()), Some(g.output.clone()))
        }
        (Some(g), None) => (Some(g.input.clone()), Some(g.output.clone())),
        (None, s) => (
            s.and_then(|u| u.input.clone()),
            s.and_then(|u| u.output.clone()),
        ),
    };
    let out =
        simulate_plant(&spec, &input.u, a.seed).map_err(|e| format!("{}: {e}", name.display()))?;
    let lines = header(spec.ts, ui.as_deref(), uo.as_deref());
    Ok(((input, out), lines))
}

fn model_run(a: &SimulateArgs, path: &PathBuf, csv: &CsvOptions) -> Result<Run, String> {
    let file = ModelFile::load(path).map_err(|e| e.to_string())?;
    let model = HostModel::from_json(&file);
    let noise_model = file.noise.as_ref().map(|n| NoiseModel {
        c: n.c.clone(),
        d: n.d.clone(),
        sigma2: n.sigma2,
    });
    let level = match (a.noise_snr, a.noise_std) {
        (Some(db), _) => Some(Level::SnrDb(db)),
        (None, Some(s)) => Some(Level::Std(s)),
        (None, None) => None,
    };
    let noise = (level.is_some() || a.noise_colour.is_some()).then(|| ModelNoise {
        colour: match a.noise_colour {
            Some(ColourArg::Model) => Colour::Model,
            Some(ColourArg::White) | None => Colour::White,
        },
        level,
        seed: a.seed.unwrap_or(1),
    });
    let opts = ModelOptions {
        strict_interval: a.strict_interval,
        noise,
        integrating: file.integrating,
    };
    let input = input(a, csv)?;
    let stored = file
        .sample_time
        .map(|v| (Origin::ModelFile(path.clone()), v));
    let ts = sample_time(a, stored, &input)?;
    let stored = file
        .units
        .clone()
        .map(|u| (UnitsOrigin::ModelFile(path.clone()), u));
    let units: Option<Units> = a.units.resolve_units(stored)?;
    let (out, outside) = match HysteresisModel::from_file(&file) {
        Some(h) => {
            element_run(&h, &input, &opts).map_err(|e| format!("{}: {e}", path.display()))?
        }
        None => simulate_model(&model, noise_model.as_ref(), &input, &opts)
            .map_err(|e| format!("{}: {e}", path.display()))?,
    };
    let units = units.as_ref();
    let mut lines = header(
        ts,
        units.map(|u| u.input.as_str()),
        units.map(|u| u.output.as_str()),
    );
    lines.extend(outside.map(|o| format!("note: {}", o.note(Syntax::Cli))));
    Ok(((input, out), lines))
}

/// A model file with a play or relay element: the element itself on the borders, noise-free;
/// beyond the knots the borders are extended linearly (refused with `--strict-interval`).
fn element_run(
    h: &HysteresisModel,
    input: &InputRecord,
    opts: &ModelOptions,
) -> Result<(Output, Option<OutsideInterval>), String> {
    if opts.noise.is_some() {
        return Err(
            "a play or relay model (\"element\") is simulated noise-free: drop the noise options"
                .to_string(),
        );
    }
    let (lo, hi) = h.interval();
    if opts.strict_interval
        && let Some(i) = first_outside(&input.u, lo, hi)
    {
        return Err(format!(
            "{} line {}: u = {} lies outside the model's interval [{lo}, {hi}]",
            input.source.display(),
            input.lines[i],
            input.u[i]
        ));
    }
    let (h, outside) = for_input(h, &input.u);
    Ok((Output::clean(simulate(&h.model, &input.u)), outside))
}

/// The input record, with its time column when it has one (or it was named: then it must).
fn input(a: &SimulateArgs, csv: &CsvOptions) -> Result<InputRecord, String> {
    let (time, named) = a.units.simulate_time_column();
    let input = read_input(&a.input, &a.input_column, time, csv).map_err(|e| e.to_string())?;
    if named && input.t.is_none() {
        return Err(format!(
            "{}: no time column {time} (--time-column); drop the flag or name the column",
            input.source.display()
        ));
    }
    Ok(input)
}

/// The one sample time of `--ts`, the specification or model file (`stored`) and the input's
/// time column (checked uniform).
fn sample_time(
    a: &SimulateArgs,
    stored: Option<(Origin, f64)>,
    input: &InputRecord,
) -> Result<Option<f64>, String> {
    let column = match &input.t {
        Some(t) => Some((
            Origin::TimeColumn(input.source.clone()),
            ts_from_column(input.source.clone(), t, &input.lines).map_err(|e| e.to_string())?,
        )),
        None => None,
    };
    let stated: Vec<(Origin, f64)> = a
        .units
        .ts()?
        .map(|v| (Origin::Flag, v))
        .into_iter()
        .chain(stored)
        .chain(column)
        .collect();
    resolve_ts(&stated).map_err(|e| e.to_string())
}

/// Writes the header comments and the columns `t` (when read), `u`, `y` and `y_clean` (on
/// request) to standard output.
fn print(
    input: &InputRecord,
    out: &Output,
    comments: &[String],
    clean: bool,
) -> Result<(), String> {
    let mut text = Vec::new();
    for c in comments {
        writeln!(text, "# {c}").map_err(|e| e.to_string())?;
    }
    let mut names = Vec::new();
    let mut columns: Vec<&[f64]> = Vec::new();
    if let Some(t) = &input.t {
        names.push("t");
        columns.push(t);
    }
    names.extend(["u", "y"]);
    columns.extend([input.u.as_slice(), out.y.as_slice()]);
    if clean {
        names.push("y_clean");
        columns.push(&out.y_clean);
    }
    write_columns_to("<stdout>", &mut text, &names, &columns).map_err(|e| e.to_string())?;
    match std::io::stdout().lock().write_all(&text) {
        // The reader closed the pipe (e.g. `| head`): nothing more is wanted.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r.map_err(|e| format!("<stdout>: {e}")),
    }
}
