//! Drawing a laid-out figure as SVG: frame, grid, ticks, labels and the series.

use std::fmt::Write as _;

use super::axis::Layout;
use super::figure::Figure;
use super::series::Kind;
use super::style::{
    AXIS_COLOR, FONT_FAMILY, GRID_COLOR, LABEL_SIZE, MAX_PX, MINOR_GRID_COLOR, TICK_LEN, TICK_SIZE,
    TITLE_SIZE,
};
use super::svg::{
    arrow_element, band_path, dash_attr, escape, marker_element, marker_path, num, polyline,
    series_color,
};

impl Figure {
    pub(super) fn render(&self, layout: &Layout) -> String {
        let Layout { plot, x, y } = layout;
        let w = self.width;
        let h = self.height;
        let mut s = String::with_capacity(16_384);
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT_FAMILY}" font-size="{TICK_SIZE}">"#
        );
        let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
        let _ = writeln!(
            s,
            r#"<defs><clipPath id="plot-area"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath></defs>"#,
            num(plot.x),
            num(plot.y),
            num(plot.w),
            num(plot.h)
        );

        // Grid.
        let px = |v: f64| plot.x + x.to_unit(v) * plot.w;
        let py = |v: f64| plot.y + plot.h - y.to_unit(v) * plot.h;
        // One path of vertical lines at `xs` and horizontal lines at `ys`.
        let lines = |xs: &[f64], ys: &[f64]| {
            let mut d = String::new();
            for &v in xs {
                let _ = write!(
                    d,
                    "M{} {}V{}",
                    num(px(v)),
                    num(plot.y),
                    num(plot.y + plot.h)
                );
            }
            for &v in ys {
                let _ = write!(
                    d,
                    "M{} {}H{}",
                    num(plot.x),
                    num(py(v)),
                    num(plot.x + plot.w)
                );
            }
            d
        };
        for (d, color) in [
            (lines(&x.minor, &y.minor), MINOR_GRID_COLOR),
            (lines(&x.major, &y.major), GRID_COLOR),
        ] {
            if !d.is_empty() {
                let _ = writeln!(
                    s,
                    r#"<path d="{d}" stroke="{color}" stroke-width="1" fill="none"/>"#
                );
            }
        }

        // Data.
        let to_px = |xv: f64, yv: f64| -> Option<(f64, f64)> {
            if !self.valid(xv, yv) {
                return None;
            }
            let ax = if self.log_x { xv.log10() } else { xv };
            let ay = if self.log_y { yv.log10() } else { yv };
            Some((px(ax).clamp(-MAX_PX, MAX_PX), py(ay).clamp(-MAX_PX, MAX_PX)))
        };
        let _ = writeln!(s, r#"<g clip-path="url(#plot-area)">"#);
        for (i, series) in self.series.iter().enumerate() {
            let color = escape(&series_color(series, i));
            let class = series
                .class
                .as_ref()
                .map_or_else(String::new, |c| format!(r#" class="{}""#, escape(c)));
            match &series.kind {
                Kind::Line { x: xs, y: ys } => {
                    let d = polyline(xs.iter().zip(ys).map(|(&a, &b)| to_px(a, b)));
                    if !d.is_empty() {
                        let _ = writeln!(
                            s,
                            r#"<path{class} d="{d}" fill="none" stroke="{color}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round"{}/>"#,
                            num(series.width),
                            dash_attr(series.dash, series.width)
                        );
                    }
                }
                Kind::Scatter {
                    x: xs,
                    y: ys,
                    marker,
                } => {
                    let mut d = String::new();
                    let r = series.size;
                    for (a, b) in xs.iter().zip(ys) {
                        if let Some((cx, cy)) = to_px(*a, *b)
                            && plot.contains(cx, cy, r + 2.0)
                        {
                            marker_path(&mut d, *marker, cx, cy, r);
                        }
                    }
                    if !d.is_empty() {
                        let _ = writeln!(
                            s,
                            "{}",
                            marker_element(&d, *marker, &color, series.width, &class)
                        );
                    }
                }
                Kind::Arrow { from, to, text } => {
                    if let (Some(p0), Some(p1)) = (to_px(from.0, from.1), to_px(to.0, to.1)) {
                        let data = (*from, *to);
                        let _ = writeln!(
                            s,
                            "{}",
                            arrow_element(
                                (p0, p1),
                                data,
                                text,
                                plot.x + plot.w,
                                &color,
                                series.width,
                                &class
                            )
                        );
                    }
                }
                Kind::Band {
                    x: xs,
                    lower,
                    upper,
                } => {
                    let d = band_path(xs, lower, upper, &to_px);
                    if !d.is_empty() {
                        let _ = writeln!(
                            s,
                            r#"<path{class} d="{d}" fill="{color}" fill-opacity="{}" stroke="none"/>"#,
                            num(series.opacity.clamp(0.0, 1.0))
                        );
                    }
                }
            }
        }
        let _ = writeln!(s, "</g>");

        // Frame, ticks, tick labels.
        let _ = writeln!(
            s,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{AXIS_COLOR}" stroke-width="1"/>"#,
            num(plot.x),
            num(plot.y),
            num(plot.w),
            num(plot.h)
        );
        let mut ticks = String::new();
        let bottom = plot.y + plot.h;
        for &v in &x.major {
            let _ = write!(ticks, "M{} {}v{TICK_LEN}", num(px(v)), num(bottom));
        }
        for &v in &y.major {
            let _ = write!(ticks, "M{} {}h-{TICK_LEN}", num(plot.x), num(py(v)));
        }
        let _ = writeln!(
            s,
            r#"<path d="{ticks}" stroke="{AXIS_COLOR}" stroke-width="1" fill="none"/>"#
        );
        let _ = writeln!(s, r#"<g fill="{AXIS_COLOR}">"#);
        for (&v, label) in x.major.iter().zip(&x.labels) {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
                num(px(v)),
                num(bottom + TICK_LEN + 4.0 + TICK_SIZE),
                label.svg()
            );
        }
        for (&v, label) in y.major.iter().zip(&y.labels) {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" text-anchor="end">{}</text>"#,
                num(plot.x - TICK_LEN - 4.0),
                num(py(v) + 0.36 * TICK_SIZE),
                label.svg()
            );
        }
        let _ = writeln!(s, "</g>");

        // Axis labels and title.
        if !self.x_label.is_empty() {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" text-anchor="middle" font-size="{LABEL_SIZE}" fill="black">{}</text>"#,
                num(plot.x + 0.5 * plot.w),
                num(bottom + TICK_LEN + 4.0 + TICK_SIZE + 10.0 + LABEL_SIZE),
                escape(&self.x_label)
            );
        }
        if !self.y_label.is_empty() {
            let cx = 10.0 + LABEL_SIZE * 0.8;
            let cy = plot.y + 0.5 * plot.h;
            let _ = writeln!(
                s,
                r#"<text transform="translate({},{}) rotate(-90)" text-anchor="middle" font-size="{LABEL_SIZE}" fill="black">{}</text>"#,
                num(cx),
                num(cy),
                escape(&self.y_label)
            );
        }
        if !self.title.is_empty() {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" text-anchor="middle" font-size="{TITLE_SIZE}" font-weight="bold" fill="black">{}</text>"#,
                num(f64::from(w) / 2.0),
                num(8.0 + TITLE_SIZE),
                escape(&self.title)
            );
        }

        self.render_legend(&mut s, plot, &to_px);
        s.push_str("</svg>\n");
        s
    }
}
