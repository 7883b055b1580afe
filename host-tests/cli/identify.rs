//! `hsid identify`: a model from a CSV record, optionally refined, written as a model file.

mod page;
mod prepare;
mod records;
pub mod reference;
mod simulation;
mod stream;

use crate::failure::{Failure, outln};
use hsid_host::model::Element;
use std::path::PathBuf;

use clap::Args;
use hsid_host::refine::knots::SegmentCount;
use hsid_host::workflow::{IdentifyRequest, Syntax, identify_record};

use crate::args::{
    BasisArg, Columns, CsvArgs, HoldArgs, Horizons, KnotArgs, ModelOut, UnitArgs, YesNo, finite_f64,
};
use prepare::read_records;

/// Arguments of `hsid identify`.
#[derive(Args)]
pub struct IdentifyArgs {
    /// CSV file with a header (`-`: standard input). Repeat it for several experiments on the
    /// same plant (`--data a.csv --data b.csv`): they are joined in the order given and
    /// identified as one record (--hold is the hold at the start of the first; later holds are
    /// data). Joining is exact for a record split into files, and for experiments that each
    /// end with a hold at u_min of at least --settle samples before the next starts at rest
    /// there; a record that starts at u_min after one that does not end there is refused.
    #[arg(long, required = true)]
    data: Vec<PathBuf>,
    /// Lower end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umin: f64,
    /// Upper end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umax: f64,
    /// Uniform segments per path (ignored when knots are given), or `auto` to choose the
    /// count from the data by BIC of the refined model over 2 to 14. Default: 7, 10 or 14 by
    /// BIC of the refined model (7, the paper's, with --no-refine). A segment with fewer than
    /// 10 samples of its path (ascending or descending) is merged into a neighbour, and a line
    /// says so; knots given are never moved.
    #[arg(long)]
    segments: Option<SegmentCount>,
    #[command(flatten)]
    knots: KnotArgs,
    /// Model order (default: automatic).
    #[arg(long)]
    order: Option<usize>,
    #[command(flatten)]
    hold: HoldArgs,
    #[command(flatten)]
    horizons: Horizons,
    #[command(flatten)]
    columns: Columns,
    #[command(flatten)]
    csv: CsvArgs,
    /// Border basis (coordinates of the regressor and of the rank-1 split).
    #[arg(long, value_enum, default_value = "hat")]
    basis: BasisArg,
    /// The input element: backlash or switch (two paths, Table I data), or static (one
    /// memoryless border for both directions, any input). Not given: backlash, with the static
    /// element identified beside it and reported when it simulates the inner hold-out better.
    #[arg(long, value_enum)]
    nonlinearity: Option<Element>,
    /// Known μ0 = H(u_min), for data without a hold (`--hold 0`). Without it, and without a
    /// hold, μ0 is estimated with the model.
    #[arg(
        long,
        allow_hyphen_values = true,
        conflicts_with = "detrend",
        value_parser = finite_f64
    )]
    mu0: Option<f64>,
    /// For data without a hold (`--hold 0`) whose output sits on an offset: subtract the mean
    /// of y over all records before identifying (the mean is printed). The model then
    /// describes y − mean(y): μ0 and the border values are shifted by −mean(y)/G(1) and the
    /// poles are unchanged. With a hold, μ0 is measured by the hold and --detrend is refused.
    #[arg(long)]
    detrend: bool,
    /// The plant integrates (voltage → position, a level loop): one pole is fixed at z = 1 and
    /// the stable part G₀ is identified on the output's increments y(t) − y(t − 1) of each
    /// record (its first sample has none, and the hold loses one sample). G₀(1) = 1: μ0, the
    /// borders and the fits printed are in output units per sample; the gap, in input units,
    /// is the element's. The model file records it (`"integrating": true`). Without the flag
    /// the record is tested for an output that integrates (a unit root that a Dickey–Fuller
    /// test with the input as covariate does not reject at 1 %) and identified so when it
    /// does, with a note; `--integrating no` identifies it as it is.
    #[arg(
        long,
        value_name = "yes|no",
        num_args = 0..=1,
        default_missing_value = "yes",
        conflicts_with = "detrend"
    )]
    integrating: Option<YesNo>,
    #[command(flatten)]
    units: UnitArgs,
    /// Keep the subspace model as it is (the paper's estimator; with `--f 10 --p 10`, exactly
    /// the paper's). By default it is refined by the prediction-error method (plant, μ0,
    /// borders and noise model jointly) and, without `--order`, the order of the refined model
    /// is chosen by BIC among the subspace order and its neighbours.
    #[arg(long, conflicts_with = "refine")]
    no_refine: bool,
    /// Refine (the default; accepted for scripts written before it was).
    #[arg(long)]
    refine: bool,
    #[command(flatten)]
    out: ModelOut,
    #[command(flatten)]
    figures: crate::figures::FigureArgs,
    /// Write a self-contained HTML report of the run (model in units, fit, figures, data
    /// checks and residual tests, the command line) to this file.
    #[arg(long, value_name = "FILE")]
    html: Option<PathBuf>,
    /// Read the record row by row and push each sample into the identifier without keeping
    /// it: memory does not grow with the record (for files too large to read whole, e.g. 10⁸
    /// rows). Gives the subspace model of one file with the given or default segments and
    /// horizons; what needs the whole record (refinement, fits, figures, the HTML report,
    /// --detrend, --segments auto, --integrating yes and the check for an integrator) is not
    /// available. Only the input and output columns are
    /// read (the time column is not checked).
    #[arg(long, conflicts_with_all = ["refine", "detrend", "html", "out", "true_plant"])]
    stream: bool,
    /// `simulation`: after the identification, fit the element itself, the play operator
    /// (backlash; also from --nonlinearity static) or the relay with borders (switch), on the
    /// same knots with G(1) = 1 and the plant's resting level w(-1), by simulation-error
    /// minimisation started from the identified model. For inputs that reverse inside the
    /// range (inner loops), where two paths do not describe the element. One record; --json
    /// writes this model (key "element") and --out draws it. `auto` (the default): the same
    /// fit, with a note, when the input breaks the Table I structure: with --nonlinearity
    /// backlash or switch, more than one and more than a tenth of the monotone input runs
    /// after the hold start inside [--umin, --umax] (Table I starts every run at an end);
    /// with several --data, --integrating or --stream, where the fit cannot run, the note
    /// says it was not run. `none`: never (the identified model as it is).
    #[arg(long, value_enum, default_value = "auto")]
    fit: simulation::FitArg,
    /// A closed-loop record: the column holding the controller's reference (setpoint), logged
    /// with u and y. The model is then the closed-loop consistent estimate (PI-MOESP on the
    /// data projected on instruments built from the reference, docs/closed-loop.md) with the
    /// knots, horizons and order of the open-loop estimate, not refined. Two-path elements,
    /// one --data file; not with --stream, --integrating or --refine.
    #[arg(long, value_name = "NAME", conflicts_with_all = ["stream", "integrating", "refine"])]
    reference_column: Option<String>,
    /// After the identification, fit friction on the model's velocity: the element's output
    /// less F_c·tanh(v/v_s) + F_0 drives G (Coulomb friction with its sign smoothed over a
    /// fitted velocity v_s, and a constant force; viscous friction is part of G), v the
    /// increment per sample of an integrating plant (force → position) or the output's change
    /// per sample, the element's output 0, 1 or 2 samples late; G, F_c, v_s, F_0 (and the
    /// initial position and velocity of an integrating plant) fitted by simulation error (of
    /// the position for an integrating plant) from the identified model. The model with
    /// friction is reported, and written by --json (key "friction"), when it simulates the
    /// last quarter of the record better than the identified model (fitted on the first three
    /// quarters); a line says which. With --integrating, a first-order stable part and a
    /// linear element (--nonlinearity static --segments 1) and a sample time, a line reads it
    /// as a rigid body: mass, viscous and Coulomb friction and the offset per unit of the
    /// input (kg, N s/m and N for a force in N and a position in m). Not with --stream.
    #[arg(long, conflicts_with = "stream")]
    friction: bool,
}

/// The request of these arguments, in the command line's words.
pub fn request(a: &IdentifyArgs) -> IdentifyRequest {
    let mut r = IdentifyRequest::new(a.umin, a.umax, Syntax::Cli);
    r.segments = a.segments;
    r.knots_asc = a.knots.knots_asc.clone();
    r.knots_desc = a.knots.knots_desc.clone();
    r.order = a.order;
    r.horizons = a.horizons.given();
    r.element = a.nonlinearity.unwrap_or(Element::Backlash);
    r.choose_element = a.nonlinearity.is_none();
    r.basis = a.basis.into();
    r.mu0 = a.mu0;
    r.detrend = a.detrend;
    r.integrating = a.integrating == Some(YesNo::Yes);
    r.detect_integrating = a.integrating.is_none();
    r.refine = !a.no_refine;
    r.fit = a.fit.into();
    r.reference = a.reference_column.clone();
    r.settle = a.hold.settle;
    r.friction = a.friction;
    r
}

/// Identifies, refines or fits the noise model, prints the model and its fits, writes the file.
pub fn run(a: &IdentifyArgs) -> Result<(), Failure> {
    let request = request(a);
    a.figures.check_true_plant(a.html.is_some())?;
    if a.stream {
        return stream::run(a, &request);
    }
    let mut records = read_records(a, &request)?;
    records.read_hold(a.umin, a.hold.hold, a.hold.hold_tolerance)?;
    let id = identify_record(&records.take_record(a.hold.hold), &request)
        .map_err(|e| records.workflow_error(e))?;
    for line in id.lines()? {
        outln!("{line}")?;
    }
    let record = &id.record;
    let friction = id.friction.as_ref().is_some_and(|f| f.reported);
    if friction && (a.figures.dir().is_some() || a.html.is_some()) {
        outln!(
            "note: the figures and the page draw the identified model without friction (they do \
             not draw friction yet); the lines above and --json give the model with it"
        )?;
    }
    let settings =
        crate::figures::settings(&a.figures, record.ts, record.units.as_ref(), &id.best.model)?;
    let figures = crate::figures::identified(&a.figures, &id, &settings)?;
    if let Some(path) = &a.html {
        page::write(a, path, &id, &settings)?;
    }
    if let Some(path) = &a.out.json {
        id.model_file().save(path).map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
    }
    for line in figures {
        outln!("{line}")?;
    }
    Ok(())
}
