//! Text reports: the model and fit figures (the paper's table is [`crate::paper::table`]).

use std::fmt::Write;

use crate::identify::HostModel;
use crate::model_file::ModelStd;

/// Normalised RMSE and fit in percent of a simulation against measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// Root mean square error, output units.
    pub rmse: f64,
    /// RMSE divided by the standard deviation of the measurement.
    pub nrmse: f64,
    /// `100 (1 − ‖y − ŷ‖ / ‖y − mean(y)‖)`, as MATLAB's `compare`.
    pub fit_percent: f64,
}

/// Computes the [`Fit`] of `sim` against `meas`.
pub fn fit(meas: &[f64], sim: &[f64]) -> Fit {
    let n = meas.len().min(sim.len()).max(1) as f64;
    let mean = meas.iter().sum::<f64>() / n;
    let err: f64 = meas.iter().zip(sim).map(|(a, b)| (a - b) * (a - b)).sum();
    let dev: f64 = meas.iter().map(|a| (a - mean) * (a - mean)).sum();
    Fit {
        rmse: (err / n).sqrt(),
        nrmse: (err / dev).sqrt(),
        fit_percent: 100.0 * (1.0 - (err / dev).sqrt()),
    }
}

/// The NRMSE and fit are undefined: the measurement is constant (or empty) over the samples
/// compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the measured output is constant over the {samples} samples compared: NRMSE and fit are undefined"
)]
pub struct UndefinedFit {
    /// The samples compared.
    pub samples: usize,
}

/// One-line fit report; an error when the measurement is constant (the NRMSE and fit are
/// undefined) or empty.
pub fn fit_report(meas: &[f64], sim: &[f64]) -> Result<String, UndefinedFit> {
    let f = fit(meas, sim);
    if !f.nrmse.is_finite() {
        return Err(UndefinedFit {
            samples: meas.len(),
        });
    }
    Ok(format!(
        "simulation fit on {} samples: RMSE {:.6}, NRMSE {:.4}, fit {:.2} %",
        meas.len(),
        f.rmse,
        f.nrmse,
        f.fit_percent
    ))
}

fn row(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:>11.6}"))
        .collect::<Vec<_>>()
        .join(" ")
}

impl HostModel {
    /// The model as text.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "order n = {} (f = {}, p = {}, {} samples)",
            self.order, self.f, self.p, self.samples
        );
        let _ = writeln!(s, "singular values: {}", row(&self.singular_values));
        for i in 0..self.order {
            let r: Vec<f64> = (0..self.order).map(|j| self.a[(i, j)]).collect();
            let _ = writeln!(s, "A[{i}] = {}", row(&r));
        }
        let _ = writeln!(s, "B    = {}", row(&self.b));
        let _ = writeln!(s, "C    = {}", row(&self.c));
        let _ = writeln!(s, "D    = {:>11.6}", self.d);
        let poles: Vec<String> = self
            .poles()
            .iter()
            .map(|(r, i)| format!("{r:.5}{i:+.5}j"))
            .collect();
        let _ = writeln!(s, "poles: {}", poles.join(", "));
        let _ = writeln!(s, "mu0 = {:.6}", self.mu0);
        let _ = writeln!(s, "ascending knots : {}", row(&self.knots_asc));
        let _ = writeln!(s, "P_a at knots    : {}", row(&self.border_asc));
        let _ = writeln!(s, "descending knots: {}", row(&self.knots_desc));
        let _ = write!(s, "P_d at knots    : {}", row(&self.border_desc));
        s
    }
}

/// The standard deviations of a refined model's μ0 and border values, as text.
pub(crate) fn std_text(s: &ModelStd) -> String {
    format!(
        "std of mu0 = {:.6}\nstd of P_a at knots: {}\nstd of P_d at knots: {}",
        s.mu0,
        row(&s.border_asc),
        row(&s.border_desc)
    )
}
