//! `hsid identify --fit simulation`: the element fitted by simulation error
//! (`hsid_host::workflow::element_fit`), printed and written as the model file's `"element"`.

use clap::ValueEnum;
use hsid_host::hysteresis::{ElementKind, HysteresisFit, Start};
use hsid_host::report::fit_report;
use hsid_host::units::UnitReport;
use hsid_host::workflow::{ElementFit, Identified};

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

impl From<FitArg> for ElementFit {
    fn from(f: FitArg) -> Self {
        match f {
            FitArg::Auto => ElementFit::Auto,
            FitArg::None => ElementFit::None,
            FitArg::Simulation => ElementFit::Simulation,
        }
    }
}

/// Prints the fitted element `fit` of `id`: the fit, the model, its simulation fit and its
/// reading in units.
pub fn print(fit: &HysteresisFit, id: &Identified) -> Result<(), Failure> {
    let name = match fit.model.kind {
        ElementKind::Backlash => "play operator (backlash)",
        ElementKind::Switch => "relay with borders (switch)",
    };
    let origin = match fit.start {
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
    for line in text(fit) {
        outln!("{line}")?;
    }
    let r = &id.record;
    let sim = fit.simulate(&r.u);
    outln!("{}", fit_report(&r.y[r.hold..], &sim[r.hold..])?)?;
    outln!("the fitted element in units:")?;
    for line in in_units(fit, id).lines() {
        outln!("{line}")?;
    }
    Ok(())
}

/// The fitted element read in units: `G`'s poles and bandwidth, the static gain, and the gap
/// of the borders `H_a`, `H_d` (input units) and the loop height (output units). Without the
/// pole covariance: the delta-method text of the report speaks of the refinement's.
pub fn in_units(fit: &HysteresisFit, id: &Identified) -> UnitReport {
    let host = fit.model.to_host(id.record.len());
    host.unit_report(id.record.ts, id.record.units.clone(), None, true)
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
