//! The two borders `P_a(u)`, `P_d(u)` with their ±2σ bands, the true loop of a simulated
//! plant, and the measured points: the partial residuals of the record (see `partial.rs`), the
//! model's `H[u(t)]` plus the least-squares departure of `h(t)` that the simulation residual
//! shows. Where the model's border is right the points scatter around it by the noise; where
//! it is wrong they leave it.

use hsid::Direction;

use super::csv::{Table, band_label, save_svg};
use super::error::FigureError;
use super::partial::departures;
use super::{Context, RecordView, Written};
use crate::numerics::direction::directions;
use crate::plot::{Dash, Figure, Marker, PALETTE, Series};

/// Grid points over the input interval (the knots are added).
const GRID: usize = 401;

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
                c_asc,
                "points-asc",
                "partial residuals, u rising",
            ),
            (
                Direction::Descending,
                c_desc,
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
                    .size(1.3)
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
    if let Some(unc) = cx.uncertainty
        && let Some((sa, sd)) = unc.border_std(m, &grid)
    {
        for (v, sd, color, name, col) in [
            (&asc, &sa, c_asc, "band-asc", "P_a"),
            (&desc, &sd, c_desc, "band-desc", "P_d"),
        ] {
            let lo: Vec<f64> = v.iter().zip(sd).map(|(v, s)| v - 2.0 * s).collect();
            let hi: Vec<f64> = v.iter().zip(sd).map(|(v, s)| v + 2.0 * s).collect();
            fig.push(
                Series::band(&grid, &lo, &hi)
                    .color(color)
                    .opacity(0.3)
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
                .width(1.4)
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
            .width(2.4)
            .class("border-asc")
            .label("P_a"),
    );
    fig.push(
        Series::line(&grid, &desc)
            .color(c_desc)
            .width(2.4)
            .class("border-desc")
            .label("P_d"),
    );
    out.files.push(table.save(cx.dir, "borders")?);
    out.files.push(save_svg(&fig, cx.dir, "borders")?);
    Ok(())
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
