//! Measured and simulated output over the whole record (the simulation runs from rest at
//! `u_min`, with no measured output fed back).

use super::csv::{Table, save_svg};
use super::error::FigureError;
use super::{Context, Written};
use crate::plot::{Figure, PALETTE, Series};

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let s = cx.settings;
    let y = cx.record.y;
    let t = s.times(0, y.len());
    let (t_label, t_col) = s.time_axis();
    let fig = Figure::new("Output: measured and simulated")
        .size(1000, 480)
        .x_label(t_label)
        .y_label(s.output("y"))
        .with(
            Series::line(&t, y)
                .color("#9a9a9a")
                .width(1.0)
                .class("measured")
                .label("measured"),
        )
        .with(
            Series::line(&t, &cx.simulated)
                .color(PALETTE[0])
                .width(1.3)
                .class("simulated")
                .label("simulated"),
        );
    let mut table = Table::default();
    table.col(t_col, t);
    table.col(s.output("y measured"), y.to_vec());
    table.col(s.output("y simulated"), cx.simulated.clone());
    out.files.push(table.save(cx.dir, "output")?);
    out.files.push(save_svg(&fig, cx.dir, "output")?);
    Ok(())
}
