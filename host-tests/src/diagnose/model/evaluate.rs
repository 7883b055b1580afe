//! A model scored on a stretch of a record: simulation or one-step prediction error.

use std::ops::Range;

use serde::Serialize;

use crate::report::fit;

use super::extended::ExtendedModel;
use super::outliers::detect_outliers;
use crate::model::Record;

/// Which error a score measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// Simulation error: the model is driven by the input only.
    Simulation,
    /// One-step-ahead prediction error (the noise model uses past measured outputs).
    Prediction,
}

/// A model's error on a scored range of a record.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Model output over the whole record (simulation or prediction).
    pub output: Vec<f64>,
    /// Residual `y − output` over the scored range (0 at excluded samples).
    pub residual: Vec<f64>,
    /// Samples of the scored range excluded as outliers (robust models only).
    pub excluded: Vec<bool>,
    /// RMSE over the samples used, output units.
    pub rmse: f64,
    /// RMSE / standard deviation of the measured output over the samples used.
    pub nrmse: f64,
    /// Fit in percent, `100 (1 − NRMSE)`.
    pub fit_percent: f64,
    /// Samples used.
    pub used: usize,
}

impl Evaluation {
    /// Squared errors over the scored range (`None` at excluded samples).
    pub(crate) fn losses(&self) -> Vec<Option<f64>> {
        self.residual
            .iter()
            .zip(&self.excluded)
            .map(|(r, &e)| (!e).then_some(r * r))
            .collect()
    }
}

/// Evaluates a model on `range` of `rec`, simulating (or predicting) over the whole record.
pub fn evaluate(
    model: &ExtendedModel,
    rec: &Record,
    range: Range<usize>,
    metric: Metric,
) -> Evaluation {
    let output = match metric {
        Metric::Simulation => model.simulate(&rec.u, &rec.time),
        Metric::Prediction => model.predict(&rec.u, &rec.y, &rec.time),
    };
    let range = range.start.min(rec.len())..range.end.min(rec.len());
    let raw: Vec<f64> = range.clone().map(|t| rec.y[t] - output[t]).collect();
    let excluded = if model.structure.robust {
        detect_outliers(&raw, model.outlier_k)
    } else {
        vec![false; raw.len()]
    };
    let residual: Vec<f64> = raw
        .iter()
        .zip(&excluded)
        .map(|(&r, &e)| if e { 0.0 } else { r })
        .collect();
    let (meas, sim): (Vec<f64>, Vec<f64>) = range
        .clone()
        .zip(&excluded)
        .filter(|(_, e)| !**e)
        .map(|(t, _)| (rec.y[t], output[t]))
        .unzip();
    let f = fit(&meas, &sim);
    Evaluation {
        output,
        residual,
        excluded,
        rmse: f.rmse,
        nrmse: f.nrmse,
        fit_percent: f.fit_percent,
        used: meas.len(),
    }
}
