//! The element of a fitted play/relay model: its borders `H_a`, `H_d` (output units against
//! input units) with ±2σ bands from the fit's covariance, the element's output `w(t)` on the
//! record against `u(t)` (the inner loops of a play, the jumps of a relay), the measured
//! points (the model's `w(t)` plus the least-squares departure the simulation residual shows,
//! as in `borders.rs`) and, for a play, the gap in the title and marked at the middle of the
//! input interval (`gap_marker.rs`, with `borders-detail.svg` around it, as in `borders.rs`).
//! `borders-knots.csv` holds the
//! border values at the knots with their standard deviations, `element.csv` the gap,
//! `element-output.csv` the element's output on the record.

use hsid::Direction;

use super::borders::{
    BAND_OPACITY, BORDER_WIDTH, POINT_SIZE, TRUE_WIDTH, detail, detail_x, grid, span,
};
use super::csv::{Table, band_label, save_svg};
use super::error::FigureError;
use super::gap_marker::GapMarker;
use super::partial::departures;
use super::{Context, Written};
use crate::hysteresis::HysteresisModel;
use crate::hysteresis::simulate::element_output;
use crate::hysteresis::uncertainty::Uncertainty;
use crate::identify::interpolate;
use crate::model::MemoryElement;
use crate::plot::{Dash, Figure, Marker, PALETTE, Series};

pub(super) fn write(
    cx: &Context,
    m: &HysteresisModel,
    uncertainty: Option<&Uncertainty>,
    out: &mut Written,
) -> Result<(), FigureError> {
    let s = cx.settings;
    let g = grid(m.knots[0], m.knots[m.knots.len() - 1], &m.knots, &m.knots);
    let asc: Vec<f64> = g
        .iter()
        .map(|&u| interpolate(&m.knots, &m.border_asc, u))
        .collect();
    let desc: Vec<f64> = g
        .iter()
        .map(|&u| interpolate(&m.knots, &m.border_desc, u))
        .collect();
    let gap = (m.kind == MemoryElement::Play).then(|| m.gap()).flatten();
    let unit = s.units.as_ref().map_or("", |u| u.0.trim());
    let mut fig = Figure::new(title(m.kind, gap, unit))
        .x_label(s.input("u"))
        .y_label(s.output("w"));
    trajectory(cx, m, &mut fig, out)?;
    let mut table = Table::default();
    table.col(s.input("u"), g.clone());
    table.col(s.output("H_a"), asc.clone());
    table.col(s.output("H_d"), desc.clone());
    let (c_asc, c_desc) = (PALETTE[0], PALETTE[1]);
    let host = m.to_host(0);
    let mut detail_y = span(&asc, &desc, &g, detail_x(&host));
    if let Some(unc) = uncertainty {
        let layout = m.layout();
        for (v, first, color, col) in [
            (&asc, layout.asc().start, c_asc, "H_a"),
            (&desc, layout.desc().start, c_desc, "H_d"),
        ] {
            let sd: Vec<f64> = g
                .iter()
                .map(|&u| border_sd(&m.knots, &unc.covariance, first, u))
                .collect();
            let lo: Vec<f64> = v.iter().zip(&sd).map(|(v, s)| v - 2.0 * s).collect();
            let hi: Vec<f64> = v.iter().zip(&sd).map(|(v, s)| v + 2.0 * s).collect();
            let (a, b) = span(&lo, &hi, &g, detail_x(&host));
            detail_y = (detail_y.0.min(a), detail_y.1.max(b));
            fig.push(
                Series::band(&g, &lo, &hi)
                    .color(color)
                    .opacity(BAND_OPACITY)
                    .class(format!("band-{col}"))
                    .label(band_label(col, &sd, "")),
            );
            table.col(s.output(&format!("{col} - 2sd")), lo);
            table.col(s.output(&format!("{col} + 2sd")), hi);
        }
    }
    if let Some(t) = &s.truth {
        fig.push(
            Series::line(&t.u, &t.asc)
                .color("black")
                .dash(Dash::Dashed)
                .width(TRUE_WIDTH)
                .class("true-asc")
                .label("true loop"),
        );
        fig.push(
            Series::line(&t.u, &t.desc)
                .color("black")
                .dash(Dash::Dashed)
                .width(TRUE_WIDTH)
                .class("true-desc"),
        );
    }
    fig.push(
        Series::line(&g, &asc)
            .color(c_asc)
            .width(BORDER_WIDTH)
            .class("border-asc")
            .label("H_a"),
    );
    fig.push(
        Series::line(&g, &desc)
            .color(c_desc)
            .width(BORDER_WIDTH)
            .class("border-desc")
            .label("H_d"),
    );
    out.files.push(table.save(cx.dir, "borders")?);
    out.files
        .push(knots_table(m, uncertainty, cx).save(cx.dir, "borders-knots")?);
    if let Some(gap) = gap {
        let mut t = Table::default();
        t.col(s.input("gap"), vec![gap]);
        if let Some(sd) = uncertainty.and_then(|u| u.gap) {
            t.col(s.input("sd gap"), vec![sd]);
        }
        out.files.push(t.save(cx.dir, "element")?);
    }
    let layout = m.layout();
    let marker = (m.kind == MemoryElement::Play)
        .then(|| {
            GapMarker::at_middle(&host, |u| {
                uncertainty.and_then(|unc| {
                    unc.std_of(&layout, m, |p| {
                        p.to_host(0).gap_at(Direction::Descending, u)
                    })
                })
            })
        })
        .flatten();
    if let Some(gm) = &marker {
        fig.push(gm.series(s));
        out.files.push(gm.table(s).save(cx.dir, "borders-gap")?);
    }
    out.files.push(save_svg(&fig, cx.dir, "borders")?);
    if marker.is_some() {
        let d = detail(fig, detail_x(&host), detail_y);
        out.files.push(save_svg(&d, cx.dir, "borders-detail")?);
    }
    Ok(())
}

/// The figure's title: the element and, for a play, its gap in input units.
fn title(kind: MemoryElement, gap: Option<f64>, unit: &str) -> String {
    match (kind, gap) {
        (MemoryElement::Play, Some(g)) => {
            format!("Play operator (backlash): borders H_a, H_d, gap {g:.4} {unit}")
                .trim_end()
                .to_string()
        }
        (MemoryElement::Play, None) => "Play operator (backlash): borders H_a, H_d".to_string(),
        (MemoryElement::Relay, _) => {
            "Relay with borders (switch): H_a (u rising), H_d (u falling)".to_string()
        }
    }
}

/// The element's output on the record against the input, and the measured points; both
/// after the skipped samples. Written to `element-output.csv` and `borders-points.csv` (the
/// last samples, whose remaining record holds too little of the impulse response, have no
/// measured point).
fn trajectory(
    cx: &Context,
    m: &HysteresisModel,
    fig: &mut Figure,
    out: &mut Written,
) -> Result<(), FigureError> {
    let s = cx.settings;
    let skip = cx.record.skip;
    let u = &cx.record.u[skip..];
    let w = &element_output(m, cx.record.u)[skip..];
    let residual: Vec<f64> = cx
        .record
        .y
        .iter()
        .zip(&cx.simulated)
        .map(|(y, s)| y - s)
        .collect();
    let back = departures(&cx.model.impulse_response(), &residual);
    let (pu, pw): (Vec<f64>, Vec<f64>) = u
        .iter()
        .zip(w)
        .zip(&back[skip..])
        .filter_map(|((&u, &w), d)| d.map(|d| (u, w + d)))
        .unzip();
    fig.push(
        Series::scatter(&pu, &pw, Marker::Dot)
            .size(POINT_SIZE)
            .color("#d2d2d2")
            .class("points")
            .label("partial residuals"),
    );
    // Light and thin: a play's inner loops fill the loop, and the borders and the gap
    // marker are drawn over them.
    let path = match m.kind {
        MemoryElement::Play => Series::line(u, w).width(0.5),
        MemoryElement::Relay => Series::scatter(u, w, Marker::Dot).size(1.6),
    };
    fig.push(
        path.color("#ababab")
            .class("element-output")
            .label("element output w(t) on the record"),
    );
    let mut t = Table::default();
    t.col(s.input("u"), u.to_vec());
    t.col(s.output("w"), w.to_vec());
    out.files.push(t.save(cx.dir, "element-output")?);
    let mut t = Table::default();
    t.col(s.input("u"), pu);
    t.col(s.output("w measured"), pw);
    out.files.push(t.save(cx.dir, "borders-points")?);
    Ok(())
}

/// The standard deviation of a border at `u`, linear between the knots: for
/// `H(u) = (1 − λ) H_i + λ H_{i+1}`, `var = (1 − λ)² C_ii + λ² C_jj + 2 λ (1 − λ) C_ij`, the
/// knot values at `first + i` in `cov`.
fn border_sd(knots: &[f64], cov: &nalgebra::DMatrix<f64>, first: usize, u: f64) -> f64 {
    let j = knots.partition_point(|&k| k < u).clamp(1, knots.len() - 1);
    let i = j - 1;
    let lam = ((u - knots[i]) / (knots[j] - knots[i])).clamp(0.0, 1.0);
    let (a, b) = (first + i, first + j);
    let var = (1.0 - lam).powi(2) * cov[(a, a)]
        + lam * lam * cov[(b, b)]
        + 2.0 * lam * (1.0 - lam) * cov[(a, b)];
    var.max(0.0).sqrt()
}

/// The border values at the knots, with their standard deviations when the fit gave them.
fn knots_table(m: &HysteresisModel, uncertainty: Option<&Uncertainty>, cx: &Context) -> Table {
    let s = cx.settings;
    let mut t = Table::default();
    t.col(s.input("knot"), m.knots.clone());
    t.col(s.output("H_a"), m.border_asc.clone());
    t.col(s.output("H_d"), m.border_desc.clone());
    if let Some(u) = uncertainty {
        t.col(s.output("sd H_a"), u.border_asc.clone());
        t.col(s.output("sd H_d"), u.border_desc.clone());
    }
    t
}
