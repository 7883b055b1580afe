//! The legend: its size, its placement (the corner covering the fewest data points) and
//! its drawing.

use std::fmt::Write as _;

use super::axis::Rect;
use super::figure::Figure;
use super::series::{Kind, Series};
use super::style::{
    ARROW_TEXT_SIZE, LEGEND_PAD, LEGEND_ROW, LEGEND_SIZE, LEGEND_SWATCH, LegendPosition,
};
use super::svg::{
    arrow_element, arrow_text_x, dash_attr, escape, marker_element, marker_path, num, series_color,
    text_width,
};

impl Figure {
    /// Width and height of the legend box, `None` if there is no legend.
    pub(super) fn legend_size(&self) -> Option<(f64, f64)> {
        if self.legend == LegendPosition::Hidden {
            return None;
        }
        let labels: Vec<&str> = self
            .series
            .iter()
            .filter_map(|s| s.label.as_deref())
            .collect();
        if labels.is_empty() {
            return None;
        }
        let text_w = labels
            .iter()
            .map(|l| text_width(l, LEGEND_SIZE))
            .fold(0.0, f64::max);
        let w = 2.0 * LEGEND_PAD + LEGEND_SWATCH + 8.0 + text_w;
        let h = 2.0 * LEGEND_PAD + LEGEND_ROW * labels.len() as f64 - 7.0;
        Some((w, h))
    }

    pub(super) fn render_legend(
        &self,
        s: &mut String,
        plot: &Rect,
        to_px: &dyn Fn(f64, f64) -> Option<(f64, f64)>,
    ) {
        if self.legend == LegendPosition::Hidden {
            return;
        }
        let entries: Vec<(usize, &Series, &str)> = self
            .series
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.label.as_deref().map(|l| (i, s, l)))
            .collect();
        if entries.is_empty() {
            return;
        }
        let (pad, swatch, row) = (LEGEND_PAD, LEGEND_SWATCH, LEGEND_ROW);
        let (bw, bh) = self.legend_size().unwrap_or((0.0, 0.0));
        let bw = if self.legend == LegendPosition::OutsideRight {
            bw
        } else {
            bw.min(plot.w - 20.0)
        };
        let inset = 10.0;
        let corner = |pos: LegendPosition| -> (f64, f64) {
            let l = plot.x + inset;
            let r = plot.x + plot.w - inset - bw;
            let t = plot.y + inset;
            let b = plot.y + plot.h - inset - bh;
            match pos {
                LegendPosition::TopLeft => (l, t),
                LegendPosition::BottomRight => (r, b),
                LegendPosition::BottomLeft => (l, b),
                _ => (r, t),
            }
        };
        let (bx, by) = match self.legend {
            LegendPosition::Best => {
                let samples = self.pixel_samples(to_px, plot.x + plot.w);
                let mut best = (usize::MAX, corner(LegendPosition::TopRight));
                for pos in [
                    LegendPosition::TopRight,
                    LegendPosition::TopLeft,
                    LegendPosition::BottomRight,
                    LegendPosition::BottomLeft,
                ] {
                    let (cx, cy) = corner(pos);
                    let r = Rect {
                        x: cx,
                        y: cy,
                        w: bw,
                        h: bh,
                    };
                    let n = samples
                        .iter()
                        .filter(|(px, py)| r.contains(*px, *py, 4.0))
                        .count();
                    if n < best.0 {
                        best = (n, (cx, cy));
                    }
                }
                best.1
            }
            LegendPosition::OutsideRight => (plot.x + plot.w + 12.0, plot.y),
            pos => corner(pos),
        };
        let _ = writeln!(
            s,
            r##"<g><rect x="{}" y="{}" width="{}" height="{}" rx="3" fill="white" fill-opacity="0.9" stroke="#b0b0b0" stroke-width="1"/>"##,
            num(bx),
            num(by),
            num(bw),
            num(bh)
        );
        for (k, (i, series, label)) in entries.iter().enumerate() {
            let cy = by + pad + row * k as f64 + 0.5 * LEGEND_SIZE;
            let x0 = bx + pad;
            let color = escape(&series_color(series, *i));
            match &series.kind {
                Kind::Line { .. } => {
                    let _ = writeln!(
                        s,
                        r#"<path d="M{} {}h{swatch}" stroke="{color}" stroke-width="{}" fill="none"{}/>"#,
                        num(x0),
                        num(cy),
                        num(series.width),
                        dash_attr(series.dash, series.width)
                    );
                }
                Kind::Scatter { marker, .. } => {
                    let mut d = String::new();
                    let r = series.size.min(0.5 * row);
                    marker_path(&mut d, *marker, x0 + 0.5 * swatch, cy, r);
                    let _ = writeln!(
                        s,
                        "{}",
                        marker_element(&d, *marker, &color, series.width, "")
                    );
                }
                Kind::Arrow { .. } => {
                    let _ = writeln!(
                        s,
                        "{}",
                        arrow_element(
                            ((x0, cy), (x0 + swatch, cy)),
                            ((0.0, 0.0), (0.0, 0.0)),
                            "",
                            f64::INFINITY,
                            &color,
                            series.width.min(2.0),
                            ""
                        )
                    );
                }
                Kind::Band { .. } => {
                    let _ = writeln!(
                        s,
                        r#"<rect x="{}" y="{}" width="{swatch}" height="{}" fill="{color}" fill-opacity="{}"/>"#,
                        num(x0),
                        num(cy - 0.4 * LEGEND_SIZE),
                        num(0.8 * LEGEND_SIZE),
                        num(series.opacity.clamp(0.0, 1.0))
                    );
                }
            }
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-size="{LEGEND_SIZE}" fill="black">{}</text>"#,
                num(x0 + swatch + 8.0),
                num(cy + 0.36 * LEGEND_SIZE),
                escape(label)
            );
        }
        let _ = writeln!(s, "</g>");
    }

    /// Pixel positions along all drawn data, about every 5 px along lines, and around an
    /// arrow's text, for legend placement (`right`: the plot's right edge, in px).
    fn pixel_samples(
        &self,
        to_px: &dyn Fn(f64, f64) -> Option<(f64, f64)>,
        right: f64,
    ) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut along = |pts: &mut dyn Iterator<Item = Option<(f64, f64)>>| {
            let mut prev: Option<(f64, f64)> = None;
            for p in pts {
                if let (Some((x0, y0)), Some((x1, y1))) = (prev, p) {
                    let n = ((x1 - x0).hypot(y1 - y0) / 5.0).ceil().clamp(1.0, 400.0) as usize;
                    for k in 1..n {
                        let t = k as f64 / n as f64;
                        out.push((x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
                    }
                }
                if let Some(q) = p {
                    out.push(q);
                }
                prev = p;
            }
        };
        for series in &self.series {
            match &series.kind {
                Kind::Line { x, y } => {
                    along(&mut x.iter().zip(y).map(|(&a, &b)| to_px(a, b)));
                }
                Kind::Scatter { x, y, .. } => {
                    // Markers are not connected: a missing point after each one.
                    along(&mut x.iter().zip(y).flat_map(|(&a, &b)| [to_px(a, b), None]));
                }
                Kind::Arrow { from, to, text } => {
                    let ends = [to_px(from.0, from.1), to_px(to.0, to.1)];
                    along(&mut ends.into_iter());
                    // The text's box, below the arrow.
                    if let [Some(p0), Some(p1)] = ends {
                        let (x, w) = arrow_text_x((p0, p1), text, right);
                        let top = p0.1.max(p1.1) + 8.0;
                        let bottom = top + ARROW_TEXT_SIZE;
                        let (l, r) = ((x, top), (x + w, top));
                        along(&mut [Some(l), Some(r), None].into_iter());
                        along(&mut [Some((l.0, bottom)), Some((r.0, bottom)), None].into_iter());
                    }
                }
                Kind::Band { x, lower, upper } => {
                    along(&mut x.iter().zip(lower).map(|(&a, &b)| to_px(a, b)));
                    along(&mut x.iter().zip(upper).map(|(&a, &b)| to_px(a, b)));
                    along(
                        &mut x
                            .iter()
                            .zip(lower.iter().zip(upper))
                            .map(|(&a, (&l, &u))| to_px(a, 0.5 * (l + u))),
                    );
                }
            }
        }
        out
    }
}
