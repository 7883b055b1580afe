//! The two borders `P_a(u)`, `P_d(u)` with their ±2σ bands, the true loop of a simulated
//! plant, and the measured points: the partial residuals of the record (see `partial.rs`), the
//! model's `H[u(t)]` plus the least-squares departure of `h(t)` that the simulation residual
//! shows. Where the model's border is right the points scatter around it by the noise; where
//! it is wrong they leave it. The borders are drawn over the points, which are light and
//! small, and the gap is marked at the middle of the input interval (`gap_marker.rs`).
//! `borders-detail.svg` shows the same around the marker, where the loop, its ±2σ bands and
//! the gap are wide enough to read.

use hsid::Direction;

use super::csv::{Table, band_label, save_svg};
use super::error::FigureError;
use super::gap_marker::GapMarker;
use super::partial::departures;
use super::{Context, RecordView, Written};
use crate::identify::HostModel;
use crate::numerics::direction::directions;
use crate::plot::{Dash, Figure, Marker, PALETTE, Series};

/// Grid points over the input interval (the knots are added).
const GRID: usize = 401;

/// The light colours of the measured points, rising and falling (`PALETTE[0]`, `PALETTE[1]`
/// mixed with white), so that the borders drawn over them stand out.
pub(super) const POINTS: [&str; 2] = ["#a9c9e4", "#eea9a9"];

/// Widths of the identified borders and of the true loop, and the half-size of a point.
pub(super) const BORDER_WIDTH: f64 = 3.0;
pub(super) const TRUE_WIDTH: f64 = 1.6;
pub(super) const POINT_SIZE: f64 = 1.1;

/// Opacity of the ±2σ bands.
pub(super) const BAND_OPACITY: f64 = 0.35;

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let m = cx.model;
    let s = cx.settings;
    let grid = grid(m.u_min(), m.u_max(), &m.knots_asc, &m.knots_desc);
    let asc: Vec<f64> = grid.iter().map(|&u| m.border_asc_at(u)).collect();
    let desc: Vec<f64> = grid.iter().map(|&u| m.border_desc_at(u)).collect();
    let (u_label, h_label) = (s.input("u"), s.output("H"));
    let mut fig = Figure::new("Input element: borders P_a (u rising), P_d (u falling)")
        .x_label(u_label.clone())
        .y_label(h_label.clone());
    let mut table = Table::default();
    table.col(u_label, grid.clone());
    table.col(s.output("P_a"), asc.clone());
    table.col(s.output("P_d"), desc.clone());
    let (c_asc, c_desc) = (PALETTE[0], PALETTE[1]);
    let points = measured_points(cx);
    {
        for (dir, color, name, label) in [
            (
                Direction::Ascending,
                POINTS[0],
                "points-asc",
                "partial residuals, u rising",
            ),
            (
                Direction::Descending,
                POINTS[1],
                "points-desc",
                "partial residuals, u falling",
            ),
        ] {
            let (x, y): (Vec<f64>, Vec<f64>) = points
                .iter()
                .filter(|p| p.2 == dir)
                .map(|p| (p.0, p.1))
                .unzip();
            fig.push(
                Series::scatter(&x, &y, Marker::Dot)
                    .size(POINT_SIZE)
                    .color(color)
                    .class(name)
                    .label(label),
            );
        }
        let mut pts = Table::default();
        pts.col(s.input("u"), points.iter().map(|p| p.0).collect());
        pts.col(s.output("h_measured"), points.iter().map(|p| p.1).collect());
        pts.col(
            "direction (+1 rising, -1 falling)",
            points
                .iter()
                .map(|p| match p.2 {
                    Direction::Ascending => 1.0,
                    Direction::Descending => -1.0,
                })
                .collect(),
        );
        out.files.push(pts.save(cx.dir, "borders-points")?);
    }
    let mut detail_y = span(&asc, &desc, &grid, detail_x(m));
    if let Some(unc) = cx.uncertainty
        && let Some((sa, sd)) = unc.border_std(m, &grid)
    {
        for (v, sd, color, name, col) in [
            (&asc, &sa, c_asc, "band-asc", "P_a"),
            (&desc, &sd, c_desc, "band-desc", "P_d"),
        ] {
            let lo: Vec<f64> = v.iter().zip(sd).map(|(v, s)| v - 2.0 * s).collect();
            let hi: Vec<f64> = v.iter().zip(sd).map(|(v, s)| v + 2.0 * s).collect();
            let (a, b) = span(&lo, &hi, &grid, detail_x(m));
            detail_y = (detail_y.0.min(a), detail_y.1.max(b));
            fig.push(
                Series::band(&grid, &lo, &hi)
                    .color(color)
                    .opacity(BAND_OPACITY)
                    .class(name)
                    .label(band_label(col, sd, "")),
            );
            table.col(s.output(&format!("{col} - 2sd")), lo);
            table.col(s.output(&format!("{col} + 2sd")), hi);
        }
    }
    if let Some(t) = &s.truth {
        for (v, name, label) in [
            (&t.asc, "true-asc", "true loop"),
            (&t.desc, "true-desc", ""),
        ] {
            let mut line = Series::line(&t.u, v)
                .color("black")
                .dash(Dash::Dashed)
                .width(TRUE_WIDTH)
                .class(name);
            if !label.is_empty() {
                line = line.label(label);
            }
            fig.push(line);
        }
        let mut tt = Table::default();
        tt.col(s.input("u"), t.u.clone());
        tt.col(s.output("true P_a"), t.asc.clone());
        tt.col(s.output("true P_d"), t.desc.clone());
        out.files.push(tt.save(cx.dir, "borders-true")?);
    }
    fig.push(
        Series::line(&grid, &asc)
            .color(c_asc)
            .width(BORDER_WIDTH)
            .class("border-asc")
            .label("P_a"),
    );
    fig.push(
        Series::line(&grid, &desc)
            .color(c_desc)
            .width(BORDER_WIDTH)
            .class("border-desc")
            .label("P_d"),
    );
    let cov = cx.uncertainty.and_then(|u| u.border_covariance(m));
    let marker = GapMarker::at_middle(m, |u| {
        cov.as_ref()
            .and_then(|c| m.gap_std_at(Direction::Descending, u, c))
    });
    if let Some(g) = &marker {
        fig.push(g.series(s));
        out.files.push(g.table(s).save(cx.dir, "borders-gap")?);
    }
    out.files.push(table.save(cx.dir, "borders")?);
    out.files.push(save_svg(&fig, cx.dir, "borders")?);
    if marker.is_some() {
        let detail = detail(fig, detail_x(m), detail_y);
        out.files.push(save_svg(&detail, cx.dir, "borders-detail")?);
    }
    Ok(())
}

/// The inputs of the detail figure: an eighth of the input interval on each side of its
/// middle, where the gap is marked.
pub(super) fn detail_x(m: &HostModel) -> (f64, f64) {
    let (lo, hi) = (m.u_min(), m.u_max());
    let (mid, half) = (0.5 * (lo + hi), 0.125 * (hi - lo));
    (mid - half, mid + half)
}

/// The range of `a` and `b` over the inputs of `grid` in `x`.
pub(super) fn span(a: &[f64], b: &[f64], grid: &[f64], x: (f64, f64)) -> (f64, f64) {
    grid.iter()
        .zip(a.iter().zip(b))
        .filter(|(u, _)| (x.0..=x.1).contains(*u))
        .fold(
            (f64::INFINITY, f64::NEG_INFINITY),
            |(lo, hi), (_, (a, b))| (lo.min(*a).min(*b), hi.max(*a).max(*b)),
        )
}

/// `fig` cut to the inputs `x` and the outputs `y` (widened by a tenth on each side): the
/// borders figure around the gap marker.
pub(super) fn detail(fig: Figure, x: (f64, f64), y: (f64, f64)) -> Figure {
    let pad = 0.1 * (y.1 - y.0);
    let title = format!("{}, around the gap", fig.title());
    fig.retitle(title)
        .x_range(x.0, x.1)
        .y_range(y.0 - pad, y.1 + pad)
}

/// `GRID` evenly spaced inputs over `[lo, hi]` and every knot, increasing.
pub(super) fn grid(lo: f64, hi: f64, knots_a: &[f64], knots_d: &[f64]) -> Vec<f64> {
    let mut g: Vec<f64> = (0..GRID)
        .map(|i| lo + (hi - lo) * i as f64 / (GRID - 1) as f64)
        .chain(knots_a.iter().chain(knots_d).copied())
        .collect();
    g.sort_by(f64::total_cmp);
    g.dedup();
    g
}

/// `(u(t), ĥ(t), direction)` for every sample after the skipped ones: the model's `H[u(t)]`
/// plus the departure of `h(t)` the simulation residual shows (the last samples, whose
/// remaining record holds too little of the impulse response, are left out).
fn measured_points(cx: &Context) -> Vec<(f64, f64, Direction)> {
    let m = cx.model;
    let RecordView { u, y, skip } = cx.record;
    let residual: Vec<f64> = y.iter().zip(&cx.simulated).map(|(y, s)| y - s).collect();
    let back = departures(&m.impulse_response(), &residual);
    u.iter()
        .zip(directions(u, m.u_min()))
        .zip(&back)
        .skip(skip)
        .filter_map(|((&ut, dir), db)| {
            let h = match dir {
                Direction::Ascending => m.border_asc_at(ut),
                Direction::Descending => m.border_desc_at(ut),
            };
            db.map(|db| (ut, h + db, dir))
        })
        .collect()
}
