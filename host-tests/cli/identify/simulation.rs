//! `hsid identify --fit simulation`: after the subspace identification, the model whose
//! element is the play operator (backlash) or the relay with borders (switch) itself on the
//! same knots, fitted by simulation error from the identified model; for inputs that reverse
//! inside the range, where the two paths do not describe the element.

use std::path::Path;

use clap::ValueEnum;
use hsid_host::hysteresis::{ElementKind, FitOptions, HysteresisFit, Start, fit_hysteresis};
use hsid_host::identify::HostModel;
use hsid_host::model_file::Units;
use hsid_host::report::fit_report;
use hsid_host::units::{UnitReport, unit_report};

use crate::args::NonlinearityArg;
use crate::failure::{Failure, outln};

/// What `--fit` fits after the subspace identification.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FitArg {
    /// The simulation fit, with a note, when the input breaks the Table I structure
    /// (backlash and switch: more than one and more than a tenth of the monotone runs start
    /// inside the range); else none.
    Auto,
    /// Keep the identified model (two paths or static).
    None,
    /// The play operator or relay on the borders by simulation-error minimisation.
    Simulation,
}

/// The record and what the model file records besides the model.
pub struct Fitting<'a> {
    /// Input.
    pub u: &'a [f64],
    /// Output.
    pub y: &'a [f64],
    /// Samples of the hold, left out of the printed fit.
    pub hold: usize,
    /// The element the identification assumed.
    pub nonlinearity: NonlinearityArg,
    /// Sample time.
    pub ts: Option<f64>,
    /// Units.
    pub units: Option<Units>,
}

/// The element fitted, and the subspace model it starts from.
fn element(nl: NonlinearityArg) -> (ElementKind, Start) {
    match nl {
        NonlinearityArg::Backlash => (ElementKind::Backlash, Start::TwoPath),
        NonlinearityArg::Switch => (ElementKind::Switch, Start::TwoPath),
        NonlinearityArg::Static => (ElementKind::Backlash, Start::Static),
    }
}

/// Fits, prints the model, its fit and its reading in units; returns the fit.
pub fn run(r: &Fitting<'_>, start: &HostModel) -> Result<HysteresisFit, Failure> {
    let (kind, from) = element(r.nonlinearity);
    let fit = fit_hysteresis(r.u, r.y, start, from, &FitOptions::new(kind))
        .map_err(|e| format!("--fit simulation: {e}"))?;
    let name = match kind {
        ElementKind::Backlash => "play operator (backlash)",
        ElementKind::Switch => "relay with borders (switch)",
    };
    let origin = match from {
        Start::TwoPath => "the two-path model above",
        Start::Static => "the static model above (a play: --nonlinearity switch for a relay)",
    };
    outln!(
        "simulation-error fit of the {name} on the knots, from {origin}: {} iterations{}, Σe² {:.6} -> {:.6}",
        fit.iterations,
        if fit.budget_reached {
            " (the limit; the last step still gained)"
        } else {
            ""
        },
        fit.initial_cost,
        fit.cost
    )?;
    for line in text(&fit) {
        outln!("{line}")?;
    }
    let sim = fit.simulate(r.u);
    outln!("{}", fit_report(&r.y[r.hold..], &sim[r.hold..])?)?;
    outln!("the fitted element in units:")?;
    for line in in_units(&fit, r).lines() {
        outln!("{line}")?;
    }
    Ok(fit)
}

/// The fitted element read in units: `G`'s poles and bandwidth, the static gain, and the gap
/// of the borders `H_a`, `H_d` (input units) and the loop height (output units). Without the
/// pole covariance: the delta-method text of the report speaks of the refinement's.
pub fn in_units(fit: &HysteresisFit, r: &Fitting<'_>) -> UnitReport {
    let host = fit.model.to_host(r.u.len());
    unit_report(&host, r.ts, r.units.clone(), None, true)
}

/// Writes the fitted model's file (key `"element"`) with the record's sample time and units.
pub fn save(fit: &HysteresisFit, r: &Fitting<'_>, path: &Path) -> Result<(), Failure> {
    let mut file = fit.model.to_file(r.u.len());
    file.sample_time = r.ts;
    file.units = r.units.clone();
    file.save(path).map_err(|e| e.to_string())?;
    outln!("wrote {}", path.display())?;
    Ok(())
}

/// The fitted model: `G`, its poles, `w(−1)`, the borders and the gap, with standard
/// deviations where the data determine them.
fn text(fit: &HysteresisFit) -> Vec<String> {
    let m = &fit.model;
    let u = fit.uncertainty.as_ref();
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let sd = |v: Option<f64>| v.map_or(String::new(), |s| format!(" ± {s:.6}"));
    let mut lines = vec![
        format!(
            "G(q) = B/F, G(1) = 1: F = [{}], B = [{}]",
            list(&m.f),
            list(&m.b)
        ),
        format!(
            "poles: {}",
            m.poles()
                .iter()
                .map(|(re, im)| format!("{re:.6}{im:+.6}i"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!("w(-1) = {:.6}{}", m.w0, sd(u.map(|u| u.w0))),
        format!("knots: {}", list(&m.knots)),
        format!("H_a: {}", list(&m.border_asc)),
        format!("H_d: {}", list(&m.border_desc)),
    ];
    if let Some(u) = u {
        lines.push(format!("sd H_a: {}", list(&u.border_asc)));
        lines.push(format!("sd H_d: {}", list(&u.border_desc)));
    } else {
        lines.push(
            "no standard deviations: the data do not determine every border value (singular JᵀJ)"
                .to_string(),
        );
    }
    if m.kind == ElementKind::Backlash {
        lines.push(match m.gap() {
            Some(g) => format!("fitted gap {g:.6}{}", sd(u.and_then(|u| u.gap))),
            None => "fitted gap: none, the borders do not meet at mid-range".to_string(),
        });
    }
    lines
}
