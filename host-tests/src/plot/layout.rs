//! The layout of a figure: data extents, axis ranges and the plot area in pixels.

use super::axis::{Axis, Layout, Rect, Span};
use super::figure::Figure;
use super::series::Kind;
use super::style::{LABEL_SIZE, LegendPosition, TICK_LEN, TICK_SIZE, TITLE_SIZE};
use super::ticks::nice_step;

impl Figure {
    pub(super) fn valid(&self, x: f64, y: f64) -> bool {
        x.is_finite() && y.is_finite() && (!self.log_x || x > 0.0) && (!self.log_y || y > 0.0)
    }

    /// Extents of the valid data, in axis coordinates (log10 for a log x axis).
    fn extents(&self) -> (Option<Span>, Option<Span>, bool) {
        let mut xs: Option<(f64, f64)> = None;
        let mut ys: Option<(f64, f64)> = None;
        let mut has_markers = false;
        let grow = |r: &mut Option<(f64, f64)>, v: f64| {
            *r = Some(match *r {
                None => (v, v),
                Some((a, b)) => (a.min(v), b.max(v)),
            });
        };
        for s in &self.series {
            has_markers |= matches!(s.kind, Kind::Scatter { .. });
            for (x, y) in s.points() {
                if self.valid(x, y) {
                    grow(&mut xs, if self.log_x { x.log10() } else { x });
                    grow(&mut ys, if self.log_y { y.log10() } else { y });
                }
            }
        }
        (xs, ys, has_markers)
    }

    pub(super) fn layout(&self) -> Layout {
        let (data_x, data_y, has_markers) = self.extents();
        let w = f64::from(self.width);
        let h = f64::from(self.height);
        let top = if self.title.is_empty() {
            16.0
        } else {
            TITLE_SIZE + 26.0
        };
        let bottom = TICK_LEN
            + 6.0
            + TICK_SIZE
            + if self.x_label.is_empty() {
                12.0
            } else {
                LABEL_SIZE + 20.0
            };
        let y_label_space = if self.y_label.is_empty() {
            12.0
        } else {
            LABEL_SIZE + 22.0
        };
        let mut left = y_label_space + 40.0;
        let outside_legend = match (self.legend, self.legend_size()) {
            (LegendPosition::OutsideRight, Some((lw, _))) => lw + 22.0,
            _ => 0.0,
        };
        let mut right = 20.0f64.max(outside_legend);
        let mut result = None;
        for _ in 0..4 {
            let plot = Rect {
                x: left,
                y: top,
                w: (w - left - right).max(40.0),
                h: (h - top - bottom).max(40.0),
            };
            let (xa, ya) = self.axes(&plot, data_x, data_y, has_markers);
            let widest_y = ya
                .labels
                .iter()
                .map(|l| l.width(TICK_SIZE))
                .fold(0.0, f64::max);
            let new_left = y_label_space + widest_y + TICK_LEN + 6.0;
            let last_x = xa
                .major
                .iter()
                .zip(&xa.labels)
                .filter(|(v, _)| xa.to_unit(**v) > 0.97)
                .map(|(_, l)| l.width(TICK_SIZE) / 2.0 + 6.0)
                .fold(16.0, f64::max)
                .max(outside_legend);
            let done = (new_left - left).abs() < 0.5 && (last_x - right).abs() < 0.5;
            result = Some(Layout { plot, x: xa, y: ya });
            if done {
                break;
            }
            left = new_left;
            right = last_x;
        }
        result.unwrap_or_else(|| {
            let plot = Rect {
                x: left,
                y: top,
                w: (w - left - right).max(40.0),
                h: (h - top - bottom).max(40.0),
            };
            let (xa, ya) = self.axes(&plot, data_x, data_y, has_markers);
            Layout { plot, x: xa, y: ya }
        })
    }

    /// Axis ranges and ticks for a given plot area.
    pub(super) fn axes(
        &self,
        plot: &Rect,
        data_x: Option<(f64, f64)>,
        data_y: Option<(f64, f64)>,
        has_markers: bool,
    ) -> (Axis, Axis) {
        let tx = (plot.w / 95.0).clamp(3.0, 12.0);
        let ty = (plot.h / 55.0).clamp(4.0, 10.0);
        // Automatic ranges (in axis coordinates, log10 for a log x axis) get a margin of `frac`
        // of the span on each side: markers on both axes, lines only in y (x is usually time,
        // frequency or input and looks best tight). `linear_extended` then moves each end to a
        // tick if that is close.
        let widen = |r: (f64, f64), frac: f64, log: bool| -> (f64, f64) {
            let (a, b) = r;
            if b > a {
                let pad = frac * (b - a);
                (a - pad, b + pad)
            } else if log {
                (a - 1.0, b + 1.0)
            } else {
                let d = if a == 0.0 { 1.0 } else { 0.1 * a.abs() };
                (a - d, b + d)
            }
        };
        let x_frac = if has_markers { 0.04 } else { 0.0 };
        let y_frac = if has_markers { 0.04 } else { 0.03 };
        let xr = match self.x_range {
            Some((a, b)) if self.log_x => (a.log10(), b.log10()),
            Some(r) => r,
            None => widen(data_x.unwrap_or((0.0, 1.0)), x_frac, self.log_x),
        };
        let yr = match self.y_range {
            Some((a, b)) if self.log_y => (a.log10(), b.log10()),
            Some(r) => r,
            None => widen(data_y.unwrap_or((0.0, 1.0)), y_frac, self.log_y),
        };

        if self.equal_aspect && !self.log_x && !self.log_y {
            let (mut x0, mut x1) = xr;
            let (mut y0, mut y1) = yr;
            let scale = (plot.w / (x1 - x0)).min(plot.h / (y1 - y0));
            let dx = plot.w / scale;
            let dy = plot.h / scale;
            let cx = 0.5 * (x0 + x1);
            let cy = 0.5 * (y0 + y1);
            (x0, x1) = (cx - 0.5 * dx, cx + 0.5 * dx);
            (y0, y1) = (cy - 0.5 * dy, cy + 0.5 * dy);
            let step = nice_step(dx, tx).max(nice_step(dy, ty));
            return (
                Axis::linear_within(x0, x1, step),
                Axis::linear_within(y0, y1, step),
            );
        }
        let x = if self.log_x {
            Axis::log(xr.0, xr.1, tx)
        } else if self.x_range.is_some() {
            Axis::linear_within(xr.0, xr.1, nice_step(xr.1 - xr.0, tx)).thin_to_fit(plot.w)
        } else {
            Axis::linear_extended(xr.0, xr.1, tx).thin_to_fit(plot.w)
        };
        let y = if self.log_y {
            Axis::log(yr.0, yr.1, ty)
        } else if self.y_range.is_some() {
            Axis::linear_within(yr.0, yr.1, nice_step(yr.1 - yr.0, ty))
        } else {
            Axis::linear_extended(yr.0, yr.1, ty)
        };
        (x, y)
    }
}
