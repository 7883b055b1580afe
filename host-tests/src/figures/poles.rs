//! Poles of the LTI part in the z-plane with the unit circle and, when the uncertainty is
//! known, the 2σ ellipse of each pole: `{p + 2 L (cos φ, sin φ)}` with `L Lᵀ` the 2 × 2
//! covariance of `(re, im)` (a segment along the real axis for a real pole). Ellipses are
//! usually far smaller than the unit circle, so each pole on or above the real axis (the
//! others are their mirror images) also gets a zoomed figure, `poles-zoom-K.svg`, K from 1.

use super::csv::{Table, save_svg};
use super::error::FigureError;
use super::{Context, Written};
use crate::plot::{Figure, Marker, PALETTE, Series};

/// Points per ellipse and on the unit circle.
const ROUND: usize = 181;

/// The 2σ ellipse of a pole: `ROUND` points of `p + 2 L (cos φ, sin φ)` with `L` the
/// Cholesky-like square root of `cov` from its eigen-decomposition.
pub(super) fn ellipse(p: (f64, f64), cov: [[f64; 2]; 2]) -> Vec<(f64, f64)> {
    let (a, b, c) = (cov[0][0], cov[0][1], cov[1][1]);
    let mean = 0.5 * (a + c);
    let diff = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = ((mean + diff).max(0.0), (mean - diff).max(0.0));
    let theta = 0.5 * (2.0 * b).atan2(a - c);
    let (ct, st) = (theta.cos(), theta.sin());
    (0..ROUND)
        .map(|i| {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / (ROUND - 1) as f64;
            let (x, y) = (2.0 * l1.sqrt() * phi.cos(), 2.0 * l2.sqrt() * phi.sin());
            (p.0 + ct * x - st * y, p.1 + st * x + ct * y)
        })
        .collect()
}

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let poles = cx.model.poles();
    let (re, im): (Vec<f64>, Vec<f64>) = poles.iter().copied().unzip();
    let circle: Vec<(f64, f64)> = (0..ROUND)
        .map(|i| {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / (ROUND - 1) as f64;
            (phi.cos(), phi.sin())
        })
        .collect();
    let (cx_, cy): (Vec<f64>, Vec<f64>) = circle.into_iter().unzip();
    let mut fig = Figure::new("LTI part: poles in the z-plane")
        .x_label("Re z")
        .y_label("Im z")
        .equal_aspect(true);
    fig.push(
        Series::line(&cx_, &cy)
            .color("#888888")
            .width(1.0)
            .class("unit-circle")
            .label("|z| = 1"),
    );
    let mut table = Table::default();
    table.col("re", re.clone());
    table.col("im", im.clone());
    let covs = cx.uncertainty.and_then(|u| u.pole_covariances(&poles));
    let mut extent = poles
        .iter()
        .fold(1.0f64, |m, p| m.max(p.0.abs()).max(p.1.abs()));
    if let Some(covs) = &covs {
        let mut e = Table::default();
        let (mut idx, mut ex, mut ey) = (Vec::new(), Vec::new(), Vec::new());
        for (k, (p, cov)) in poles.iter().zip(covs).enumerate() {
            let pts = ellipse(*p, *cov);
            let (x, y): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
            extent = pts
                .iter()
                .fold(extent, |m, p| m.max(p.0.abs()).max(p.1.abs()));
            let mut line = Series::line(&x, &y)
                .color(PALETTE[1])
                .width(1.4)
                .class("ellipse");
            if k == 0 {
                line = line.label("2σ ellipse");
            }
            fig.push(line);
            idx.extend(std::iter::repeat_n(k as f64, x.len()));
            ex.extend(x);
            ey.extend(y);
        }
        table.col(
            "sd re",
            covs.iter().map(|c| c[0][0].max(0.0).sqrt()).collect(),
        );
        table.col(
            "sd im",
            covs.iter().map(|c| c[1][1].max(0.0).sqrt()).collect(),
        );
        table.col("cov re im", covs.iter().map(|c| c[0][1]).collect());
        e.col("pole (0-based row of poles.csv)", idx);
        e.col("re", ex).col("im", ey);
        out.files.push(e.save(cx.dir, "poles-ellipses")?);
        zooms(cx, &poles, covs, out)?;
    }
    let r = 1.1 * extent;
    fig = fig.x_range(-r, r).y_range(-r, r);
    fig.push(
        Series::scatter(&re, &im, Marker::Cross)
            .color(PALETTE[0])
            .size(6.0)
            .width(2.2)
            .class("poles")
            .label("poles"),
    );
    out.files.push(table.save(cx.dir, "poles")?);
    out.files.push(save_svg(&fig, cx.dir, "poles")?);
    Ok(())
}

/// One zoomed figure per pole with `im >= 0`: the pole, its ellipse, and the unit circle
/// when it passes by.
fn zooms(
    cx: &Context,
    poles: &[(f64, f64)],
    covs: &[[[f64; 2]; 2]],
    out: &mut Written,
) -> Result<(), FigureError> {
    let upper = poles.iter().zip(covs).filter(|(p, _)| p.1 >= 0.0);
    for (k, (p, cov)) in upper.enumerate() {
        let pts = ellipse(*p, *cov);
        let half = pts.iter().fold(0.0f64, |m, q| {
            m.max((q.0 - p.0).abs()).max((q.1 - p.1).abs())
        });
        let r = if half > 0.0 { 1.6 * half } else { 0.01 };
        let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
        let arc: Vec<(f64, f64)> = (0..=2000)
            .map(|i| {
                let phi = 2.0 * std::f64::consts::PI * i as f64 / 2000.0;
                (phi.cos(), phi.sin())
            })
            .filter(|q| (q.0 - p.0).abs() < 2.0 * r && (q.1 - p.1).abs() < 2.0 * r)
            .collect();
        let (ax, ay): (Vec<f64>, Vec<f64>) = arc.into_iter().unzip();
        let fig = Figure::new(format!(
            "Pole {:.4} {} {:.4}j with its 2σ ellipse",
            p.0,
            if p.1 < 0.0 { '−' } else { '+' },
            p.1.abs()
        ))
        .x_label("Re z")
        .y_label("Im z")
        .equal_aspect(true)
        .x_range(p.0 - r, p.0 + r)
        .y_range(p.1 - r, p.1 + r)
        .with(
            Series::line(&ax, &ay)
                .color("#888888")
                .width(1.0)
                .class("unit-circle")
                .label("|z| = 1"),
        )
        .with(
            Series::line(&x, &y)
                .color(PALETTE[1])
                .width(1.6)
                .class("ellipse")
                .label("2σ ellipse"),
        )
        .with(
            Series::scatter(&[p.0], &[p.1], Marker::Cross)
                .color(PALETTE[0])
                .size(6.0)
                .width(2.2)
                .class("poles")
                .label("pole"),
        );
        out.files
            .push(save_svg(&fig, cx.dir, &format!("poles-zoom-{}", k + 1))?);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn the_ellipse_has_the_two_sigma_axes_of_the_covariance() {
        // Variances 4 and 1, rotated by 30°: semi-axes 2·2 = 4 and 2·1 = 2.
        let t = 30f64.to_radians();
        let (c, s) = (t.cos(), t.sin());
        let cov = [
            [4.0 * c * c + s * s, 3.0 * c * s],
            [3.0 * c * s, 4.0 * s * s + c * c],
        ];
        let pts = ellipse((0.5, 0.2), cov);
        let r: Vec<f64> = pts.iter().map(|p| (p.0 - 0.5).hypot(p.1 - 0.2)).collect();
        let max = r.iter().copied().fold(0.0, f64::max);
        let min = r.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            (max - 4.0).abs() < 1e-9 && (min - 2.0).abs() < 2e-3,
            "{max} {min}"
        );
        // The long axis points at 30°.
        let far = pts
            .iter()
            .max_by(|a, b| {
                (a.0 - 0.5)
                    .hypot(a.1 - 0.2)
                    .total_cmp(&(b.0 - 0.5).hypot(b.1 - 0.2))
            })
            .unwrap();
        let ang = (far.1 - 0.2).atan2(far.0 - 0.5).to_degrees();
        assert!(
            (ang - 30.0).abs() < 1e-6 || (ang + 150.0).abs() < 1e-6,
            "{ang}"
        );
    }
}
