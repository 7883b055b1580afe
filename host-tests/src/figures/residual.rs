//! The simulation residual `e = y − ŷ` after the skipped samples, and its sample
//! autocorrelation `ρ(k) = Σ_t ẽ(t) ẽ(t + k) / Σ_t ẽ(t)²` (`ẽ` the residual less its mean)
//! with the ±1.96/√N bounds of a white residual. A coloured noise gives a correlated residual
//! even for the true plant; lags far outside the bounds at the plant's time scale point at
//! unmodelled dynamics.

use super::csv::{Table, save_svg};
use super::error::FigureError;
use super::{Context, Written};
use crate::plot::{Dash, Figure, Marker, PALETTE, Series};

/// Largest lag shown.
const MAX_LAG: usize = 50;

/// `ρ(0) … ρ(max_lag)` (biased estimator; `ρ(0) = 1`; all zero but `ρ(0)` for a constant).
pub(super) fn autocorrelation(x: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n.max(1) as f64;
    let e: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let c0: f64 = e.iter().map(|v| v * v).sum();
    (0..=max_lag)
        .map(|k| match k {
            0 => 1.0,
            _ if c0 <= 0.0 || k >= n => 0.0,
            _ => {
                e[..n - k]
                    .iter()
                    .zip(&e[k..])
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
                    / c0
            }
        })
        .collect()
}

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let s = cx.settings;
    let skip = cx.record.skip;
    let e: Vec<f64> = cx.record.y[skip..]
        .iter()
        .zip(&cx.simulated[skip..])
        .map(|(y, m)| y - m)
        .collect();
    let t = s.times(skip, e.len());
    let (t_label, t_col) = s.time_axis();
    let fig = Figure::new("Residual: measured − simulated")
        .size(1000, 420)
        .x_label(t_label)
        .y_label(s.output("y − ŷ"))
        .with(
            Series::line(&t, &e)
                .color(PALETTE[0])
                .width(1.0)
                .class("residual"),
        );
    let mut table = Table::default();
    table.col(t_col, t);
    table.col(s.output("residual"), e.clone());
    out.files.push(table.save(cx.dir, "residual")?);
    out.files.push(save_svg(&fig, cx.dir, "residual")?);

    let lags = MAX_LAG.min(e.len() - 1);
    let rho = autocorrelation(&e, lags);
    let bound = 1.96 / (e.len() as f64).sqrt();
    let lag: Vec<f64> = s.times(0, lags + 1);
    // Stems: one segment from 0 to ρ(k) per lag, broken by NaN.
    let (mut sx, mut sy) = (Vec::new(), Vec::new());
    for (l, r) in lag.iter().zip(&rho) {
        sx.extend([*l, *l, f64::NAN]);
        sy.extend([0.0, *r, f64::NAN]);
    }
    let ends = [lag[0], lag[lags]];
    let lag_label = match s.ts {
        Some(_) => "lag [s]",
        None => "lag [samples]",
    };
    let acf = Figure::new("Residual autocorrelation")
        .x_label(lag_label)
        .y_label("ρ(k)")
        .with(
            Series::band(&ends, &[-bound; 2], &[bound; 2])
                .color("#888888")
                .opacity(0.2)
                .class("bounds")
                .label(format!("±1.96/√N (N = {})", e.len())),
        )
        .with(Series::line(&ends, &[0.0; 2]).color("#555555").width(0.8))
        .with(
            Series::line(&sx, &sy)
                .color(PALETTE[0])
                .width(1.6)
                .class("acf-stems"),
        )
        .with(
            Series::scatter(&lag, &rho, Marker::Dot)
                .color(PALETTE[0])
                .size(3.0)
                .class("acf")
                .label("ρ(k)"),
        )
        .with(
            Series::line(&ends, &[bound; 2])
                .color("#555555")
                .dash(Dash::Dashed)
                .width(1.0)
                .class("bound-upper"),
        )
        .with(
            Series::line(&ends, &[-bound; 2])
                .color("#555555")
                .dash(Dash::Dashed)
                .width(1.0)
                .class("bound-lower"),
        );
    let mut table = Table::default();
    table.col(lag_label, lag);
    table.col("acf", rho);
    table.col("bound 1.96/sqrt(N)", vec![bound; lags + 1]);
    out.files.push(table.save(cx.dir, "residual-acf")?);
    out.files.push(save_svg(&acf, cx.dir, "residual-acf")?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn autocorrelation_of_an_alternating_sequence() {
        let x: Vec<f64> = (0..100)
            .map(|t| if t % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let r = autocorrelation(&x, 3);
        assert_eq!(r[0], 1.0);
        assert!((r[1] + 0.99).abs() < 1e-12, "{}", r[1]);
        assert!((r[2] - 0.98).abs() < 1e-12, "{}", r[2]);
        assert_eq!(autocorrelation(&[2.0; 5], 2), vec![1.0, 0.0, 0.0]);
    }
}
