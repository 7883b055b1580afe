//! Text reports: the model, fit figures and the paper's table.

use std::fmt::Write;

use crate::identify::HostModel;
use crate::paper::{CaseResult, PaperConfig};

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

/// One-line fit report; an error when the measurement is constant (the NRMSE and fit are
/// undefined) or empty.
pub fn fit_report(meas: &[f64], sim: &[f64]) -> Result<String, String> {
    let f = fit(meas, sim);
    if !f.nrmse.is_finite() {
        return Err(format!(
            "the measured output is constant over the {} samples compared: NRMSE and fit are undefined",
            meas.len()
        ));
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

/// The model as text.
pub fn model_text(m: &HostModel) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "order n = {} (f = {}, p = {}, {} samples)",
        m.order, m.f, m.p, m.samples
    );
    let _ = writeln!(s, "singular values: {}", row(&m.singular_values));
    for i in 0..m.order {
        let r: Vec<f64> = (0..m.order).map(|j| m.a[(i, j)]).collect();
        let _ = writeln!(s, "A[{i}] = {}", row(&r));
    }
    let _ = writeln!(s, "B    = {}", row(&m.b));
    let _ = writeln!(s, "C    = {}", row(&m.c));
    let _ = writeln!(s, "D    = {:>11.6}", m.d);
    let poles: Vec<String> = m
        .poles()
        .iter()
        .map(|(r, i)| format!("{r:.5}{i:+.5}j"))
        .collect();
    let _ = writeln!(s, "poles: {}", poles.join(", "));
    let _ = writeln!(s, "mu0 = {:.6}", m.mu0);
    let _ = writeln!(s, "ascending knots : {}", row(&m.knots_asc));
    let _ = writeln!(s, "P_a at knots    : {}", row(&m.border_asc));
    let _ = writeln!(s, "descending knots: {}", row(&m.knots_desc));
    let _ = write!(s, "P_d at knots    : {}", row(&m.border_desc));
    s
}

/// The Monte Carlo table (Markdown).
pub fn paper_table(cfg: &PaperConfig, results: &[CaseResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Monte Carlo: {} runs per case, j = {}, f = p = {}, SNR = {} dB, {} uniform segments per path on [{}, {}], {:?} basis, seed {}",
        cfg.runs, cfg.j, cfg.f, cfg.snr_db, cfg.segments, cfg.u_min, cfg.u_max, cfg.basis, cfg.seed
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| case | true pole | mean pole | pole std (re, im) | orders selected | Bode max error of average (dB) | border RMS of average | best PWL fit | median single-run border RMS | failures |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for r in results {
        let c = &r.summary;
        let tp = c.true_poles.first().copied().unwrap_or([f64::NAN; 2]);
        let orders: Vec<String> = c
            .order_counts
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(o, n)| format!("n={o}: {n}"))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {:.4} ± {:.4}j | {:.4} ± {:.4}j | ({:.4}, {:.4}) | {} | {:.3} | {:.4} | {:.4} | {:.4} | {} |",
            c.case,
            tp[0],
            tp[1].abs(),
            c.pole_mean[0],
            c.pole_mean[1].abs(),
            c.pole_std[0],
            c.pole_std[1],
            orders.join(", "),
            c.bode_max_db_error_of_average,
            c.border_rms_of_average,
            c.border_rms_best_pwl,
            c.border_rms_single_median,
            c.failures.len()
        );
    }
    s
}
