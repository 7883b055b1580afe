//! The two estimators the benchmark compares, and one case run through them.

use super::BenchError;
use super::case::{Case, HOLD};
use super::score::{Estimate, Row, score};
use hsid_host::choose::{Choices, best_model};
use hsid_host::diagnose::{DiagnoseOptions, Validation, diagnose};
use hsid_host::identify::{IdentifyOptions, identify};
use hsid_host::model::Record;

/// Samples of each record after the hold.
pub const SAMPLES: usize = 6000;

/// An estimator: the case (for its interval) and the estimation record's `(u, y)`.
pub type Estimator = fn(&Case, &[f64], &[f64]) -> Result<Estimate, String>;

/// The paper's estimator: PI-MOESP, 7 uniform segments per path, `f = p = 10`, the order from
/// the singular values.
pub fn paper_estimate(case: &Case, u: &[f64], y: &[f64]) -> Result<Estimate, String> {
    let e = &case.element;
    let opts = IdentifyOptions::uniform(e.u_min, e.u_max, 7, HOLD);
    let model = identify(u, y, &opts).map_err(|e| e.to_string())?;
    Ok(Estimate {
        model,
        note: "f = p = 10, 7 segments".into(),
    })
}

/// The desktop default of `hsid identify` ([`Choices::default`]).
pub fn default_estimate(case: &Case, u: &[f64], y: &[f64]) -> Result<Estimate, String> {
    let e = &case.element;
    let opts = IdentifyOptions::uniform(e.u_min, e.u_max, 7, HOLD);
    let best = best_model(u, y, &opts, &Choices::default()).map_err(|e| e.to_string())?;
    Ok(Estimate {
        note: format!(
            "f = p = {}, {} segments",
            best.options.f,
            best.options.knots_asc.len() - 1
        ),
        model: best.model,
    })
}

/// The base model of `hsid diagnose` at its defaults (the paper's estimator at f = p = 10 and 7
/// segments per path, then borders, `B`, `D` refit and the poles refined by the simulation
/// error): the model its steps start from and its "before" error is of.
pub fn diagnose_estimate(case: &Case, u: &[f64], y: &[f64]) -> Result<Estimate, String> {
    let e = &case.element;
    let opts = DiagnoseOptions::new(
        IdentifyOptions::uniform(e.u_min, e.u_max, 7, HOLD),
        e.kind.element(),
    );
    let record = Record::new(u.to_vec(), y.to_vec()).map_err(|e| e.to_string())?;
    // The base model is fitted on the estimation record alone; the validation given here only
    // sets what diagnose reports as its error, which the benchmark does not use.
    let validation = Validation::Separate {
        record: record.clone(),
        skip: HOLD,
    };
    let d = diagnose(&record, &validation, &opts).map_err(|e| e.to_string())?;
    Ok(Estimate {
        model: d.base.hammerstein,
        note: "diagnose's base model".into(),
    })
}

/// Case `index` of the family `seed`, scored for every estimator on its validation record.
pub fn run_case(seed: u64, index: usize, estimators: &[Estimator]) -> Result<Row, BenchError> {
    let case = Case::draw(seed, index, SAMPLES)?;
    let est = case.record(0)?;
    let val = case.record(1)?;
    let scores = estimators
        .iter()
        .map(|f| score(&val, f(&case, &est.u, &est.y)))
        .collect();
    Ok(Row { case, scores })
}
