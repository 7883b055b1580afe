//! Figures of a diagnosis (SVG): residual autocorrelation and input cross-correlation with
//! their 99 % bounds, the residual against the input and against the simulated output, the
//! residual spectrum with the line test's threshold, and measured against simulated output
//! before and after.

use std::path::{Path, PathBuf};

use super::diagnosis::Diagnosis;
use super::error::DiagnoseError;
use crate::plot::{Dash, Figure, LegendPosition, Marker, Series};
use crate::validation::residual::TestSet;

const BEFORE: &str = "#d62728";
const AFTER: &str = "#1f77b4";
const MEASURED: &str = "#555555";
const BOUND: &str = "#2ca02c";

fn save(fig: &Figure, dir: &Path, name: &str, out: &mut Vec<PathBuf>) -> Result<(), DiagnoseError> {
    let path = dir.join(name);
    fig.save(&path)
        .map_err(|e| DiagnoseError::Output(e.to_string()))?;
    out.push(path);
    Ok(())
}

fn lags(k: usize, symmetric: bool) -> Vec<f64> {
    if symmetric {
        (-(k as i64)..=k as i64).map(|v| v as f64).collect()
    } else {
        (0..=k).map(|v| v as f64).collect()
    }
}

/// Every sample index up to `n`, thinned to at most `max` (every k-th).
fn thin(n: usize, max: usize) -> Vec<usize> {
    let step = n.div_ceil(max.max(1)).max(1);
    (0..n).step_by(step).collect()
}

fn acf_figure(before: &TestSet, after: &TestSet, title: &str) -> Figure {
    let k = before.curves.acf.len().saturating_sub(1);
    let x = lags(k, false);
    let b = before.curves.acf_bound;
    let mut f = Figure::new(format!("{title}: residual autocorrelation"))
        .x_label("lag (samples)")
        .y_label("ρ(k)")
        .size(720, 420)
        .legend(LegendPosition::TopRight);
    f.push(
        Series::line(&x, &vec![b; x.len()])
            .color(BOUND)
            .dash(Dash::Dashed)
            .label("99 % bounds ±2.58/√N"),
    );
    f.push(
        Series::line(&x, &vec![-b; x.len()])
            .color(BOUND)
            .dash(Dash::Dashed),
    );
    f.push(
        Series::scatter(&x, &before.curves.acf, Marker::Circle)
            .color(BEFORE)
            .label("before"),
    );
    if after.curves.acf.len() == x.len() {
        f.push(
            Series::scatter(&x, &after.curves.acf, Marker::Dot)
                .color(AFTER)
                .label("after"),
        );
    }
    f
}

fn ccf_figure(before: &TestSet, after: &TestSet, title: &str) -> Figure {
    let k = before.curves.ccf_input.len().saturating_sub(1) / 2;
    let x = lags(k, true);
    let mut f = Figure::new(format!("{title}: input–residual cross-correlation"))
        .x_label("lag k (samples; k > 0: the residual follows the input)")
        .y_label("r_uε(k)")
        .size(720, 420)
        .legend(LegendPosition::TopRight);
    let bound = &before.curves.ccf_input_bound;
    if bound.len() == x.len() {
        let neg: Vec<f64> = bound.iter().map(|v| -v).collect();
        f.push(
            Series::band(&x, &neg, bound)
                .color(BOUND)
                .opacity(0.15)
                .label("99 % bounds (before)"),
        );
    }
    f.push(
        Series::line(&x, &before.curves.ccf_input)
            .color(BEFORE)
            .label("before"),
    );
    if after.curves.ccf_input.len() == x.len() {
        f.push(
            Series::line(&x, &after.curves.ccf_input)
                .color(AFTER)
                .label("after"),
        );
    }
    f
}

fn spectrum_figure(before: &TestSet, after: &TestSet, title: &str) -> Figure {
    let c = &before.curves;
    let mut f = Figure::new(format!("{title}: residual spectrum"))
        .x_label("ω (rad/sample)")
        .y_label("periodogram (Hann)")
        .size(720, 420)
        .log_y(true)
        .legend(LegendPosition::TopRight);
    let idx = thin(c.omega.len(), 1200);
    let pick = |v: &[f64]| idx.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    if c.omega.is_empty() {
        return f;
    }
    let w = pick(&c.omega);
    f.push(
        Series::line(&w, &pick(&c.power))
            .color(BEFORE)
            .width(1.0)
            .label("before"),
    );
    let a = &after.curves;
    if a.omega.len() == c.omega.len() {
        f.push(
            Series::line(&w, &pick(&a.power))
                .color(AFTER)
                .width(1.0)
                .label("after"),
        );
    }
    if c.power_threshold.len() == c.omega.len() {
        f.push(
            Series::line(&w, &pick(&c.power_threshold))
                .color(BOUND)
                .dash(Dash::Dashed)
                .label("99 % line threshold (before)"),
        );
    }
    f
}

/// Writes the figures into `dir` with file names starting with `prefix`; returns the paths.
pub fn write_figures(
    d: &Diagnosis,
    dir: &Path,
    prefix: &str,
    title: &str,
) -> Result<Vec<PathBuf>, DiagnoseError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| DiagnoseError::Output(format!("{}: {e}", dir.display())))?;
    let mut out = Vec::new();
    save(
        &acf_figure(&d.tests_before, &d.tests_after, title),
        dir,
        &format!("{prefix}autocorrelation.svg"),
        &mut out,
    )?;
    save(
        &ccf_figure(&d.tests_before, &d.tests_after, title),
        dir,
        &format!("{prefix}input-correlation.svg"),
        &mut out,
    )?;
    save(
        &spectrum_figure(&d.tests_before, &d.tests_after, title),
        dir,
        &format!("{prefix}spectrum.svg"),
        &mut out,
    )?;

    let rec = &d.validation_record;
    let r = d.validation_range.clone();
    let u: Vec<f64> = rec.u[r.clone()].to_vec();
    let idx = thin(u.len(), 800);
    let after_res = d
        .after_prediction
        .as_ref()
        .map_or(&d.after.residual, |p| &p.residual);
    let pick = |v: &[f64]| idx.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let mut fu = Figure::new(format!("{title}: residual against the input"))
        .x_label("u")
        .y_label("residual (validation)")
        .size(720, 460)
        .legend(LegendPosition::TopRight);
    fu.push(
        Series::scatter(&pick(&u), &pick(&d.before.residual), Marker::Dot)
            .color(BEFORE)
            .size(1.6)
            .label("before"),
    );
    fu.push(
        Series::scatter(&pick(&u), &pick(after_res), Marker::Dot)
            .color(AFTER)
            .size(1.6)
            .label("after"),
    );
    save(
        &fu,
        dir,
        &format!("{prefix}residual-vs-input.svg"),
        &mut out,
    )?;

    let sim_b: Vec<f64> = d.before.output[r.clone()].to_vec();
    let sim_a: Vec<f64> = d.after.output[r.clone()].to_vec();
    let mut fy = Figure::new(format!("{title}: residual against the simulated output"))
        .x_label("simulated output")
        .y_label("residual (validation)")
        .size(720, 460)
        .legend(LegendPosition::TopRight);
    fy.push(
        Series::scatter(&pick(&sim_b), &pick(&d.before.residual), Marker::Dot)
            .color(BEFORE)
            .size(1.6)
            .label("before (against its simulation)"),
    );
    fy.push(
        Series::scatter(&pick(&sim_a), &pick(&d.after.residual), Marker::Dot)
            .color(AFTER)
            .size(1.6)
            .label("after (against its simulation)"),
    );
    save(
        &fy,
        dir,
        &format!("{prefix}residual-vs-output.svg"),
        &mut out,
    )?;

    let t: Vec<f64> = rec.time[r.clone()].to_vec();
    let yv: Vec<f64> = rec.y[r.clone()].to_vec();
    // Long records: the first 300 validation samples, so that the lines stay readable.
    let shown = if t.len() > 1200 { 300 } else { t.len() };
    let idx_t: Vec<usize> = (0..shown).collect();
    let pt = |v: &[f64]| idx_t.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let what = if shown < t.len() {
        format!("first {shown} validation samples")
    } else {
        "validation".to_string()
    };
    let mut fo = Figure::new(format!("{title}: measured and simulated output ({what})"))
        .x_label("sample")
        .y_label("output")
        .size(900, 440)
        .legend(LegendPosition::OutsideRight);
    fo.push(
        Series::line(&pt(&t), &pt(&yv))
            .color(MEASURED)
            .width(1.2)
            .label("measured"),
    );
    fo.push(
        Series::line(&pt(&t), &pt(&sim_b))
            .color(BEFORE)
            .width(1.2)
            .label(format!("before, RMSE {:.4}", d.before.rmse)),
    );
    fo.push(
        Series::line(&pt(&t), &pt(&sim_a))
            .color(AFTER)
            .width(1.2)
            .label(format!("after, RMSE {:.4}", d.after.rmse)),
    );
    save(&fo, dir, &format!("{prefix}output.svg"), &mut out)?;
    Ok(out)
}
