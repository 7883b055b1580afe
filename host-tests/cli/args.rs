//! Argument groups shared by several subcommands (`#[command(flatten)]`) and the value enums.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use hsid::Basis;
use hsid_host::io::{
    CsvOptions, Decimal, Delimiter, Table, header_names, parse_table, read_source, split_unit,
};
use hsid_host::model_file::Units;
use hsid_host::units::time::TS_TOLERANCE;
use hsid_host::units::{
    Jitter, Origin, TimeUnit, UnitsOrigin, check_unit_text, checked_ts, is_time_name,
    resolve_units, time_unit_of, ts_from_column, ts_from_comments, units_from_comments,
    units_from_names,
};

use crate::failure::note;

/// The value parser of every number flag: a number that is finite. `NaN` and the infinities
/// parse as `f64` but are no interval end, gain, noise level or sample time, so they are
/// refused at the flag, before any work.
pub fn finite_f64(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    match v.is_finite() {
        true => Ok(v),
        false => Err(format!("{s} is not a finite number: give a finite value")),
    }
}

/// How the CSV files are read.
#[derive(Args, Clone, Debug)]
pub struct CsvArgs {
    /// Field delimiter of the CSV files (default: sniffed from the header line: tab if it has a
    /// tab, else `;` if it has a `;` and no `,`, else `,`).
    #[arg(long, value_enum)]
    pub delimiter: Option<DelimiterArg>,
    /// Decimal separator of the numbers: `point` (3.25) or `comma` (3,25, as European loggers
    /// write; the fields are then separated by `;`, or tabs when the header has them). A
    /// number in the other notation is refused, never guessed.
    #[arg(long, value_enum, default_value = "point")]
    pub decimal: DecimalArg,
}

/// The decimal separator.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DecimalArg {
    /// `3.25`.
    Point,
    /// `3,25`.
    Comma,
}

impl CsvArgs {
    /// How the CSV files are read.
    pub fn options(&self) -> CsvOptions {
        CsvOptions {
            delimiter: self.delimiter(),
            decimal: match self.decimal {
                DecimalArg::Point => Decimal::Point,
                DecimalArg::Comma => Decimal::Comma,
            },
        }
    }

    /// The delimiter to use, `None` to sniff it.
    pub fn delimiter(&self) -> Option<Delimiter> {
        self.delimiter.map(|d| match d {
            DelimiterArg::Comma => Delimiter::Comma,
            DelimiterArg::Semicolon => Delimiter::Semicolon,
            DelimiterArg::Tab => Delimiter::Tab,
        })
    }
}

/// An answer to a yes-or-no flag that may also be left out (then the data decide).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum YesNo {
    /// Yes.
    Yes,
    /// No.
    No,
}

/// A CSV field delimiter.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DelimiterArg {
    /// `,`
    Comma,
    /// `;`
    Semicolon,
    /// A tab character.
    Tab,
}

/// The input and output columns of a record.
#[derive(Args, Clone, Debug)]
pub struct Columns {
    /// Input column name.
    #[arg(long, default_value = "u")]
    pub input_column: String,
    /// Output column name.
    #[arg(long, default_value = "y")]
    pub output_column: String,
}

/// Knots given per path.
#[derive(Args, Clone, Debug)]
pub struct KnotArgs {
    /// Ascending knots, comma separated, u_min first and u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, value_parser = finite_f64)]
    pub knots_asc: Option<Vec<f64>>,
    /// Descending knots, comma separated, u_min first and u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, value_parser = finite_f64)]
    pub knots_desc: Option<Vec<f64>>,
}

/// The default hold (samples at u_min at the start): `--hold` of identify and diagnose, and
/// the samples validate leaves out of its fits (`--skip`).
pub const DEFAULT_HOLD: usize = 300;

/// The initial hold at u_min.
#[derive(Args, Clone, Debug)]
pub struct HoldArgs {
    /// Samples of the initial hold at u_min (0: no hold).
    #[arg(long, default_value_t = DEFAULT_HOLD)]
    pub hold: usize,
    /// Samples of the hold skipped while the plant settles (default: half the hold).
    #[arg(long)]
    pub settle: Option<usize>,
    /// Largest |u − u_min| accepted during the hold (input units; default 0: exactly
    /// u_min). For an input logged with a little noise while it rests at its minimum: the
    /// hold's samples within it are read as u_min, and one beyond it is refused.
    #[arg(long, value_name = "ABS", value_parser = tolerance)]
    pub hold_tolerance: Option<f64>,
}

/// The value parser of `--hold-tolerance`: a finite number ≥ 0.
fn tolerance(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    match v >= 0.0 {
        true => Ok(v),
        false => Err(format!("{s} is negative: give a deviation ≥ 0")),
    }
}

impl HoldArgs {
    /// The settle length: given, or half the hold.
    pub fn settle(&self) -> usize {
        self.settle.unwrap_or(self.hold / 2)
    }
}

/// The horizons of the Hankel matrices.
#[derive(Args, Clone, Debug)]
pub struct Horizons {
    /// Future horizon f (default: from the data for `identify`, shortened where the input's
    /// Hankel Gram is rank deficient, 10 for `diagnose`; with only one of --f and --p given,
    /// the other equals it).
    #[arg(long)]
    pub f: Option<usize>,
    /// Past horizon p.
    #[arg(long)]
    pub p: Option<usize>,
}

impl Horizons {
    /// `(f, p)` when at least one is given.
    pub fn given(&self) -> Option<(usize, usize)> {
        match (self.f, self.p) {
            (Some(f), Some(p)) => Some((f, p)),
            (Some(h), None) | (None, Some(h)) => Some((h, h)),
            (None, None) => None,
        }
    }

    /// `(f, p)`, the paper's 10 when neither is given.
    pub fn or_paper(&self) -> (usize, usize) {
        self.given().unwrap_or((10, 10))
    }
}

/// Where a model file goes.
#[derive(Args, Clone, Debug)]
pub struct ModelOut {
    /// Write the model here, as a model file (format hsid-model/1, see docs/model-format.md).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// Border basis of the regressor.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BasisArg {
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

/// The sample time and the units of the signals.
#[derive(Args, Clone, Debug)]
pub struct UnitArgs {
    /// Sample time in seconds (> 0). Given, it wins over the record's time column, which is
    /// then not used (a note on standard error gives the column's step and jitter). Without
    /// it, the step of the time column when the record has one, or its header comment
    /// `# ts = 0.01 s` (as `hsid simulate` writes it); every one stated must agree within
    /// 0.1 %. With none, times are in samples and frequencies in rad/sample.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    pub ts: Option<f64>,
    /// Unit of the input u (free text, e.g. `V`), for the reports and the model file. Without
    /// it, the record's column names `u [V]`, `y [deg]` (or `u (V)`), or its header comments
    /// `# input unit = V` and `# output unit = deg` (as `hsid simulate` writes them); every
    /// one stated must agree.
    #[arg(long, requires = "output_unit")]
    pub input_unit: Option<String>,
    /// Unit of the output y (free text, e.g. `deg`).
    #[arg(long, requires = "input_unit")]
    pub output_unit: Option<String>,
    /// Time column: when the record has it, it must increase with a uniform step (within
    /// 0.1 %), which is the sample time [default: a column named `t` or `time`, alone, with
    /// a unit suffix (`t_ms`, `t_us`) or a unit in brackets (`time [ms]`, `t (s)`), used only
    /// when present].
    #[arg(long)]
    pub time_column: Option<String>,
    /// Unit of the time column's numbers: s, ms or us; wins over the unit its name states
    /// (`t_ms`, `time [ms]`), which is otherwise used [default: seconds].
    #[arg(long, value_enum)]
    pub time_unit: Option<TimeUnitArg>,
}

/// A time column's unit.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TimeUnitArg {
    /// Seconds.
    S,
    /// Milliseconds.
    Ms,
    /// Microseconds.
    Us,
}

impl From<TimeUnitArg> for TimeUnit {
    fn from(u: TimeUnitArg) -> Self {
        match u {
            TimeUnitArg::S => TimeUnit::Seconds,
            TimeUnitArg::Ms => TimeUnit::Milliseconds,
            TimeUnitArg::Us => TimeUnit::Microseconds,
        }
    }
}

impl UnitArgs {
    /// `--ts`, checked positive.
    pub fn ts(&self) -> Result<Option<f64>, String> {
        self.ts
            .map(|v| checked_ts(v, Origin::Flag))
            .transpose()
            .map_err(|e| e.to_string())
    }

    /// `--input-unit` and `--output-unit`, checked non-empty and free of the characters a unit
    /// may not hold (double quotes, control characters: [`check_unit_text`]).
    pub fn units(&self) -> Result<Option<Units>, String> {
        let (Some(input), Some(output)) = (&self.input_unit, &self.output_unit) else {
            return Ok(None);
        };
        for (flag, v) in [("--input-unit", input), ("--output-unit", output)] {
            if v.trim().is_empty() {
                return Err(format!(
                    "{flag} is empty: give the unit's name, e.g. V or deg"
                ));
            }
            check_unit_text(v).map_err(|e| format!("{flag} {v:?}: {e}"))?;
        }
        Ok(Some(Units {
            input: input.trim().to_string(),
            output: output.trim().to_string(),
        }))
    }

    /// The time column `simulate` reads and writes back: `--time-column`, else `t`; and
    /// whether it was named (then it must be there).
    pub fn simulate_time_column(&self) -> (&str, bool) {
        self.time_column
            .as_deref()
            .map_or(("t", false), |name| (name, true))
    }

    /// The time column of a record whose header is `header`: the one `--time-column` names
    /// (it must be there, as written or as the name of `name [unit]`), else the one header
    /// name that reads as time ([`is_time_name`]), not one of `taken` (the signals); `None`
    /// when there is none. Two candidates are an error naming them.
    pub fn time_column(
        &self,
        source: &Path,
        header: &[String],
        taken: &[&str],
    ) -> Result<Option<String>, String> {
        if let Some(name) = &self.time_column {
            return Ok(Some(name.clone()));
        }
        let free = |h: &&String| {
            !taken
                .iter()
                .any(|t| h.as_str() == *t || split_unit(h).0 == *t)
        };
        let found: Vec<&String> = header
            .iter()
            .filter(free)
            .filter(|h| is_time_name(h))
            .collect();
        match found.as_slice() {
            [] => Ok(None),
            [one] => Ok(Some((*one).clone())),
            [a, b, ..] => Err(format!(
                "{}: the columns \"{a}\" and \"{b}\" both read as time: name the time column \
                 with --time-column",
                source.display()
            )),
        }
    }

    /// The units every source states — the flags first, then `others` (a model file's, the
    /// records' header comments) — checked to agree; `None` when none states them.
    pub fn resolve_units(
        &self,
        others: impl IntoIterator<Item = (UnitsOrigin, Units)>,
    ) -> Result<Option<Units>, String> {
        let stated: Vec<(UnitsOrigin, Units)> = self
            .units()?
            .map(|u| (UnitsOrigin::Flags, u))
            .into_iter()
            .chain(others)
            .collect();
        resolve_units(&stated).map_err(|e| e.to_string())
    }
}

/// What reading a record from CSV gives: the requested columns, the sample times the file
/// states and the units its header comments and column names state.
pub struct CsvRead {
    /// The requested columns and the line of each row.
    pub table: Table,
    /// The sample times the record states, with where each came from: its header comment
    /// `# ts = … s` and its time column (none, one or both; `resolve_ts` checks agreement).
    /// With `--ts` the time column states none: it is not used.
    pub ts: Vec<(Origin, f64)>,
    /// The units the record states, with where: its header comments (`# input unit = …`,
    /// `# output unit = …`) and its column names (`u [V]`, `y [deg]`).
    pub units: Vec<(UnitsOrigin, Units)>,
}

/// Reads the columns `names` from `data` (a file, or `-` for standard input) and its time
/// column ([`UnitArgs::time_column`]) when it has one: its step in its unit
/// (`--time-unit`, else its name's, else seconds) is the sample time, checked uniform; with
/// `--ts` the column is not used, and a note gives its step and jitter. The first two names
/// are the input and the output, whose column names may state their units.
pub fn read_record(
    data: &Path,
    names: &[&str],
    csv: &CsvArgs,
    units: &UnitArgs,
) -> Result<CsvRead, String> {
    let options = csv.options();
    // Checked before the record is read: a bad --ts is refused before any note about it.
    let given_ts = units.ts()?;
    let (source, text) = read_source(data).map_err(|e| e.to_string())?;
    let mut ts: Vec<(Origin, f64)> = ts_from_comments(&source, &text)
        .map_err(|e| e.to_string())?
        .map(|v| (Origin::Comment(source.clone()), v))
        .into_iter()
        .collect();
    let mut stated_units: Vec<(UnitsOrigin, Units)> = units_from_comments(&source, &text)
        .map_err(|e| e.to_string())?
        .map(|u| (UnitsOrigin::Comment(source.clone()), u))
        .into_iter()
        .collect();
    let header = header_names(&source, &text, &options).map_err(|e| e.to_string())?;
    let time = units.time_column(&source, &header, names)?;
    let mut all = names.to_vec();
    all.extend(time.as_deref());
    let parsed = parse_table(&source, &text, &all, &options);
    let mut table = match (&time, parsed) {
        (None, parsed) => parsed.map_err(|e| e.to_string())?,
        // With --ts an automatically found time column is not needed: one that does not
        // read as numbers is passed over, with a note.
        (Some(name), Err(e)) if given_ts.is_some() && units.time_column.is_none() => {
            note(&format!(
                "--ts is given: the time column \"{name}\" of {} is not used ({e})",
                source.display()
            ));
            parse_table(&source, &text, names, &options).map_err(|e| e.to_string())?
        }
        (Some(_), parsed) => parsed.map_err(|e| e.to_string())?,
    };
    if table.columns.len() > names.len() {
        let name = time.as_deref().unwrap_or("t");
        // The header name the column answers to (`t [ms]` for `--time-column t`): its unit.
        let written = header
            .iter()
            .find(|h| h.as_str() == name)
            .or_else(|| header.iter().find(|h| split_unit(h).0 == name))
            .map_or(name, String::as_str);
        let raw = table.columns.pop().unwrap_or_default();
        table.units.pop();
        let unit = match units.time_unit {
            Some(u) => TimeUnit::from(u),
            None => time_unit_of(&source, written)
                .map_err(|e| e.to_string())?
                .unwrap_or_default(),
        };
        let t: Vec<f64> = raw.iter().map(|v| v / unit.per_second()).collect();
        match given_ts {
            Some(given) => {
                let spread = Jitter::of(&t).map_or_else(
                    || "a single row".to_string(),
                    |j| match (j.mean - given).abs() > TS_TOLERANCE * given {
                        true => format!(
                            "{j}; its mean step differs from --ts by {:.1} %",
                            100.0 * (j.mean - given).abs() / given
                        ),
                        false => j.to_string(),
                    },
                );
                note(&format!(
                    "--ts {given} s is used; the time column \"{name}\" of {} is not ({spread}, \
                     read in {})",
                    source.display(),
                    unit.symbol()
                ));
            }
            None => {
                ts_from_column(source.clone(), &t, &table.lines).map_err(|e| e.to_string())?;
                // The step in the column's unit, then in seconds: 10 ms is 0.01 s, not the
                // 0.009999999999999998 of the mean of steps each rounded to seconds.
                let (first, last) = (raw[0], raw[raw.len() - 1]);
                let column = (last - first) / (raw.len() - 1) as f64 / unit.per_second();
                ts.push((Origin::TimeColumn(source.clone()), column));
            }
        }
    }
    if names.len() >= 2 {
        let stated = units_from_names(
            &source,
            [names[0], names[1]],
            table.units[0].as_deref(),
            table.units[1].as_deref(),
        )
        .map_err(|e| e.to_string())?;
        stated_units.extend(stated.map(|u| (UnitsOrigin::ColumnNames(source.clone()), u)));
    }
    Ok(CsvRead {
        table,
        ts,
        units: stated_units,
    })
}

/// Reads the columns `u, y` named by `columns` from `data` (a file, or `-` for standard input),
/// with the sample time of its time column (see [`read_record`]).
pub fn read_uy(
    data: &Path,
    columns: &Columns,
    csv: &CsvArgs,
    units: &UnitArgs,
) -> Result<CsvRead, String> {
    let names = [
        columns.input_column.as_str(),
        columns.output_column.as_str(),
    ];
    read_record(data, &names, csv, units)
}
