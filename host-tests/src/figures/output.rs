//! Measured and simulated output over the whole record (the simulation runs from rest at
//! `u_min`, with no measured output fed back), and, for a long record, the first `DETAIL`
//! samples after the skipped ones in `output-detail.svg`, where the two curves can be told
//! apart.

use super::csv::{Table, save_svg};
use super::error::FigureError;
use super::{Context, Written};
use crate::plot::{Figure, PALETTE, Series};

/// Samples in the detail figure.
const DETAIL: usize = 400;

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let s = cx.settings;
    let y = cx.record.y;
    let t = s.times(0, y.len());
    let skip = cx.record.skip;
    out.files.push(save_svg(
        &figure(cx, "Output: measured and simulated", &t, 0..y.len()),
        cx.dir,
        "output",
    )?);
    if y.len() - skip > 2 * DETAIL {
        let title = format!("Output: measured and simulated, {DETAIL} samples");
        let fig = figure(cx, &title, &t, skip..skip + DETAIL);
        out.files.push(save_svg(&fig, cx.dir, "output-detail")?);
    }
    let mut table = Table::default();
    table.col(s.time_axis().1, t);
    table.col(s.output("y measured"), y.to_vec());
    table.col(s.output("y simulated"), cx.simulated.clone());
    out.files.push(table.save(cx.dir, "output")?);
    Ok(())
}

/// The measured and simulated output over the samples `range`.
fn figure(cx: &Context, title: &str, t: &[f64], range: std::ops::Range<usize>) -> Figure {
    let s = cx.settings;
    let (t, y, sim) = (
        &t[range.clone()],
        &cx.record.y[range.clone()],
        &cx.simulated[range],
    );
    Figure::new(title)
        .size(1000, 480)
        .x_label(s.time_axis().0)
        .y_label(s.output("y"))
        .with(
            Series::line(t, y)
                .color("#9a9a9a")
                .width(1.0)
                .class("measured")
                .label("measured"),
        )
        .with(
            Series::line(t, sim)
                .color(PALETTE[0])
                .width(1.3)
                .class("simulated")
                .label("simulated"),
        )
}
