//! The figures of the method comparison: the Monte Carlo poles of PI-MOESP and PEM with the
//! Cramér–Rao bound's 2σ ellipse, and one run's Bode magnitude and borders with ±2σ bands.

use std::path::{Path, PathBuf};

use super::figures::pole_figure;
use super::methods::{CaseMethods, Method, MethodResult};
use crate::plot::{Dash, Figure, LegendPosition, Marker, PALETTE, PlotError, Series};
use crate::refine::uncertainty::{bode_db_std, border_std_on_grid};

fn ellipse(center: (f64, f64), cov: [[f64; 2]; 2], k: f64) -> (Vec<f64>, Vec<f64>) {
    // Cholesky of the 2 × 2 covariance.
    let l11 = cov[0][0].max(0.0).sqrt();
    let l21 = if l11 > 0.0 { cov[1][0] / l11 } else { 0.0 };
    let l22 = (cov[1][1] - l21 * l21).max(0.0).sqrt();
    (0..=100)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 100.0;
            let (a, b) = (k * t.cos(), k * t.sin());
            (center.0 + l11 * a, center.1 + l21 * a + l22 * b)
        })
        .unzip()
}

/// The figures of the refinement for one case, written into `dir`: the Monte Carlo poles of
/// PI-MOESP and PEM with the bound's 2σ ellipse, and one run's Bode magnitude and borders
/// with their ±2σ bands. Returns the paths written.
pub fn write_method_figures(c: &CaseMethods, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let mut out = Vec::new();
    let Some(pem) = c.methods.iter().find(|m| m.method == Method::Pem) else {
        return Ok(out);
    };
    let name = c.case.name();
    let truth: Vec<(f64, f64)> = pem
        .summary
        .base
        .true_poles
        .iter()
        .map(|p| (p[0], p[1]))
        .collect();
    // Poles.
    let mut fig = pole_figure(
        &format!("{name}: estimated poles, PI-MOESP and PEM, with the Cramér–Rao 2σ ellipse"),
        &[],
        &[],
        Some((0.925, 0.962, 0.108, 0.142)),
    );
    // The upper poles of a method's Monte Carlo models.
    let upper_poles = |r: &MethodResult| -> (Vec<f64>, Vec<f64>) {
        r.case
            .models
            .iter()
            .flat_map(|m| m.poles())
            .filter(|p| p.1 > 0.0)
            .unzip()
    };
    if let Some(pi) = c.methods.iter().find(|m| m.method == Method::PiMoesp) {
        let (x, y) = upper_poles(pi);
        fig.push(
            Series::scatter(&x, &y, Marker::Circle)
                .color(PALETTE[7])
                .size(2.5)
                .label("PI-MOESP"),
        );
    }
    let (x, y) = upper_poles(pem);
    fig.push(
        Series::scatter(&x, &y, Marker::Star)
            .color(PALETTE[0])
            .size(3.0)
            .label("PEM"),
    );
    let (ex, ey) = ellipse(c.crb.pole.pole, c.crb.pole.cov, 2.0);
    fig.push(
        Series::line(&ex, &ey)
            .color(PALETTE[1])
            .width(1.6)
            .label("Cramér–Rao 2σ"),
    );
    let (tx, ty): (Vec<f64>, Vec<f64>) = truth.iter().copied().unzip();
    fig.push(
        Series::scatter(&tx, &ty, Marker::Plus)
            .color("black")
            .size(11.0)
            .width(2.4)
            .label("true poles"),
    );
    let p = dir.join(format!("pem-{name}-poles.svg"));
    fig.save(&p)?;
    out.push(p);

    let Some(fit) = pem.fits.first() else {
        return Ok(out);
    };
    // Bode magnitude of run 0 with its band.
    let w = &pem.case.w;
    let bs = bode_db_std(fit, w);
    let db: Vec<f64> = bs.iter().map(|v| v.0).collect();
    let lo: Vec<f64> = bs.iter().map(|v| v.0 - 2.0 * v.1).collect();
    let hi: Vec<f64> = bs.iter().map(|v| v.0 + 2.0 * v.1).collect();
    let mut fig = Figure::new(format!(
        "{name}: Bode magnitude of one run (PEM) with its ±2σ band"
    ))
    .x_label("Frequency (rad/sample)")
    .y_label("Magnitude (dB)")
    .log_x(true)
    .legend(LegendPosition::BottomLeft);
    fig.push(
        Series::band(w, &lo, &hi)
            .color(PALETTE[0])
            .opacity(0.3)
            .label("±2σ (reported)"),
    );
    fig.push(Series::line(w, &db).color(PALETTE[0]).label("PEM, run 0"));
    if let Some(pi) = c.methods.iter().find(|m| m.method == Method::PiMoesp)
        && let Some(m0) = pi.case.models.first()
    {
        let v: Vec<f64> = w.iter().map(|&x| m0.magnitude_db(x)).collect();
        fig.push(
            Series::line(w, &v)
                .color(PALETTE[7])
                .dash(Dash::Dotted)
                .width(2.2)
                .label("PI-MOESP, run 0"),
        );
    }
    fig.push(
        Series::line(w, &pem.case.true_db)
            .color(PALETTE[1])
            .dash(Dash::Dashed)
            .label("true G"),
    );
    let p = dir.join(format!("pem-{name}-bode-band.svg"));
    fig.save(&p)?;
    out.push(p);

    // Borders of run 0 with their bands.
    let grid = &pem.case.grid;
    let (sa, sd) = border_std_on_grid(fit, grid);
    let ea: Vec<f64> = grid.iter().map(|&u| fit.model.border_asc_at(u)).collect();
    let ed: Vec<f64> = grid.iter().map(|&u| fit.model.border_desc_at(u)).collect();
    let band = |e: &[f64], s: &[f64], k: f64| -> Vec<f64> {
        e.iter().zip(s).map(|(a, b)| a + k * b).collect()
    };
    let mut fig = Figure::new(format!(
        "{name}: borders of one run (PEM) with their ±2σ bands"
    ))
    .x_label("u")
    .y_label("H[u]")
    .legend(LegendPosition::TopLeft);
    fig.push(
        Series::band(grid, &band(&ea, &sa, -2.0), &band(&ea, &sa, 2.0))
            .color(PALETTE[0])
            .opacity(0.3)
            .label("P_a ±2σ"),
    );
    fig.push(
        Series::band(grid, &band(&ed, &sd, -2.0), &band(&ed, &sd, 2.0))
            .color(PALETTE[2])
            .opacity(0.3)
            .label("P_d ±2σ"),
    );
    fig.push(Series::line(grid, &ea).color(PALETTE[0]).label("PEM P_a"));
    fig.push(Series::line(grid, &ed).color(PALETTE[2]).label("PEM P_d"));
    fig.push(
        Series::line(grid, &pem.case.true_asc)
            .color(PALETTE[1])
            .dash(Dash::Dashed)
            .label("true P_a"),
    );
    fig.push(
        Series::line(grid, &pem.case.true_desc)
            .color(PALETTE[3])
            .dash(Dash::Dashed)
            .label("true P_d"),
    );
    let p = dir.join(format!("pem-{name}-borders-band.svg"));
    fig.save(&p)?;
    out.push(p);
    Ok(out)
}
