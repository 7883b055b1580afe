//! The paper's figures: the pole map (Figs. 6 and 9), the Bode magnitude (Figs. 7 and 10) and
//! the borders (Figs. 8 and 11) of a case, drawn with the generic [`plot`](crate::plot).

use std::path::{Path, PathBuf};

use super::case::Case;
use super::monte_carlo::CaseResult;
use crate::plot::{Dash, Figure, Marker, PALETTE, PlotError, Series};

/// Writes the three figures of a case (pole scatter, Bode magnitude, borders) into `dir`,
/// named after the paper's figure numbers. Returns the paths written.
pub fn write_figures(res: &CaseResult, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let name = res.case.name();
    let (fp, fb, fh, title_case) = match res.case {
        Case::Switch => (6, 7, 8, "Switch"),
        Case::Backlash => (9, 10, 11, "Backlash"),
    };
    let est: Vec<(f64, f64)> = res.models.iter().flat_map(|m| m.poles()).collect();
    let truth: Vec<(f64, f64)> = res
        .summary
        .true_poles
        .iter()
        .map(|p| (p[0], p[1]))
        .collect();
    let mut out = Vec::new();
    let p1 = dir.join(format!("fig{fp}-{name}-poles.svg"));
    pole_figure(
        &format!(
            "{title_case} nonlinearity: eigenvalues of the estimated A ({} runs)",
            res.models.len()
        ),
        &truth,
        &est,
        Some((0.88, 1.0, -0.19, 0.19)),
    )
    .save(&p1)?;
    out.push(p1);
    let p2 = dir.join(format!("fig{fb}-{name}-bode.svg"));
    bode_magnitude_figure(
        &format!("{title_case} nonlinearity: Bode magnitude, true and average model"),
        &res.w,
        &[("true G", &res.true_db), ("average estimate", &res.avg_db)],
    )
    .save(&p2)?;
    out.push(p2);
    let p3 = dir.join(format!("fig{fh}-{name}-borders.svg"));
    border_figure(
        &format!("{title_case} nonlinearity: H[·] and its average estimate"),
        &res.grid,
        &[
            ("true P_a", &res.true_asc),
            ("true P_d", &res.true_desc),
            ("average estimate P_a", &res.avg_asc),
            ("average estimate P_d", &res.avg_desc),
        ],
    )
    .save(&p3)?;
    out.push(p3);
    Ok(out)
}

/// Pole map as in the paper's Figs. 6 and 9: estimated poles as small `*` markers (blue), true
/// poles as big `+` crosses (red) drawn on top, the unit circle (the part inside the window)
/// and the real and imaginary axes, with equal scales.
///
/// `zoom = Some((x_min, x_max, y_min, y_max))` shows at least that window (one side is widened
/// for the equal aspect ratio); `None` shows the whole unit circle and all poles. Poles are
/// `(re, im)` pairs; non-finite ones are skipped.
pub fn pole_figure(
    title: &str,
    true_poles: &[(f64, f64)],
    estimated: &[(f64, f64)],
    zoom: Option<(f64, f64, f64, f64)>,
) -> Figure {
    let (x0, x1, y0, y1) = zoom.unwrap_or_else(|| {
        let r = true_poles
            .iter()
            .chain(estimated)
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .fold(1.0f64, |m, (a, b)| m.max(a.abs()).max(b.abs()))
            * 1.1;
        (-r, r, -r, r)
    });
    let mut fig = Figure::new(title)
        .x_label("Real part")
        .y_label("Imaginary part")
        .equal_aspect(true)
        .x_range(x0, x1)
        .y_range(y0, y1);

    // The window actually shown can be wider than requested (equal aspect), so draw the axes
    // and the circle over a generous neighbourhood; the plot area clips the rest.
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let half = 0.5 * (x1 - x0).abs().max((y1 - y0).abs()) * 1.6;
    let (wx0, wx1, wy0, wy1) = (cx - half, cx + half, cy - half, cy + half);
    let axis_color = "#8a8a8a";
    if wy0 <= 0.0 && wy1 >= 0.0 {
        fig.push(
            Series::line(&[wx0, wx1], &[0.0, 0.0])
                .color(axis_color)
                .width(0.8),
        );
    }
    if wx0 <= 0.0 && wx1 >= 0.0 {
        fig.push(
            Series::line(&[0.0, 0.0], &[wy0, wy1])
                .color(axis_color)
                .width(0.8),
        );
    }
    let (ux, uy) = unit_circle_arc(wx0, wx1, wy0, wy1);
    if ux.iter().any(|v| v.is_finite()) {
        fig.push(
            Series::line(&ux, &uy)
                .color("#555555")
                .width(1.0)
                .dash(Dash::Dashed)
                .label("unit circle"),
        );
    }
    if !estimated.is_empty() {
        let (ex, ey): (Vec<f64>, Vec<f64>) = estimated.iter().copied().unzip();
        fig.push(
            Series::scatter(&ex, &ey, Marker::Star)
                .color(PALETTE[0])
                .size(3.5)
                .width(1.1)
                .label("estimated poles"),
        );
    }
    if !true_poles.is_empty() {
        let (tx, ty): (Vec<f64>, Vec<f64>) = true_poles.iter().copied().unzip();
        fig.push(
            Series::scatter(&tx, &ty, Marker::Plus)
                .color(PALETTE[1])
                .size(11.0)
                .width(2.4)
                .label("true poles"),
        );
    }
    fig
}

/// Points of the unit circle inside the window, with NaN where the circle leaves it.
fn unit_circle_arc(x0: f64, x1: f64, y0: f64, y1: f64) -> (Vec<f64>, Vec<f64>) {
    let span = (x1 - x0).min(y1 - y0);
    if !(span.is_finite() && span > 0.0) {
        return (Vec::new(), Vec::new());
    }
    let tau = std::f64::consts::TAU;
    let dtheta = (span / 600.0).clamp(1e-5, tau / 1440.0);
    let n = (tau / dtheta).ceil() as usize;
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    let mut inside_prev = false;
    for k in 0..=n {
        let t = tau * k as f64 / n as f64;
        let (s, c) = t.sin_cos();
        let inside = c >= x0 && c <= x1 && s >= y0 && s <= y1;
        if inside {
            xs.push(c);
            ys.push(s);
        } else if inside_prev {
            // Step one point past the edge so the clip makes the arc reach the border.
            xs.push(c);
            ys.push(s);
            xs.push(f64::NAN);
            ys.push(f64::NAN);
        }
        inside_prev = inside;
    }
    (xs, ys)
}

/// Writes [`pole_figure`] as SVG to `path`.
pub fn pole_plot(
    path: impl AsRef<Path>,
    title: &str,
    true_poles: &[(f64, f64)],
    estimated: &[(f64, f64)],
    zoom: Option<(f64, f64, f64, f64)>,
) -> Result<(), PlotError> {
    pole_figure(title, true_poles, estimated, zoom).save(path)
}

/// Bode magnitude plot as in Figs. 7 and 10: one line per `(label, magnitude in dB)` curve over
/// the frequencies `w` (rad/sample, log axis; `w <= 0` and non-finite dB values are skipped).
/// Curves take the palette colours in order, the first one solid and the others dashed,
/// dotted and dash-dotted in turn so that overlapping curves stay visible.
pub fn bode_magnitude_figure(title: &str, w: &[f64], curves: &[(&str, &[f64])]) -> Figure {
    let mut fig = Figure::new(title)
        .x_label("Frequency (rad/sample)")
        .y_label("Magnitude (dB)")
        .log_x(true);
    for (i, (label, db)) in curves.iter().enumerate() {
        fig.push(styled_curve(i, Series::line(w, db).label(*label)));
    }
    fig
}

/// Writes [`bode_magnitude_figure`] as SVG to `path`.
pub fn bode_magnitude_plot(
    path: impl AsRef<Path>,
    title: &str,
    w: &[f64],
    curves: &[(&str, &[f64])],
) -> Result<(), PlotError> {
    bode_magnitude_figure(title, w, curves).save(path)
}

/// Nonlinearity plot as in Figs. 8 and 11: one line per `(label, values)` curve over the input
/// values `u` (e.g. true P_a, true P_d, estimated average P_a, P_d), styled as in
/// [`bode_magnitude_figure`].
pub fn border_figure(title: &str, u: &[f64], curves: &[(&str, &[f64])]) -> Figure {
    let mut fig = Figure::new(title).x_label("u").y_label("H[u]");
    for (i, (label, values)) in curves.iter().enumerate() {
        fig.push(styled_curve(i, Series::line(u, values).label(*label)));
    }
    fig
}

/// Writes [`border_figure`] as SVG to `path`.
pub fn border_plot(
    path: impl AsRef<Path>,
    title: &str,
    u: &[f64],
    curves: &[(&str, &[f64])],
) -> Result<(), PlotError> {
    border_figure(title, u, curves).save(path)
}

fn styled_curve(i: usize, series: Series) -> Series {
    let dash = [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::DashDot][i % 4];
    let width = if dash == Dash::Dotted { 2.6 } else { 1.8 };
    series
        .color(PALETTE[i % PALETTE.len()])
        .dash(dash)
        .width(width)
}
