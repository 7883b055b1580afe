//! Small self-contained SVG figures: line plots, scatter markers, filled bands, log-x axes and
//! equal-aspect axes, written as plain SVG text (no system libraries, no fonts needed to write
//! them; the viewer picks a sans-serif font).
//!
//! ```no_run
//! use hsid_host::plot::{Dash, Figure, Marker, Series};
//! let x = [0.0, 1.0, 2.0, 3.0];
//! let y = [0.0, 1.0, 4.0, 9.0];
//! let mut fig = Figure::new("Squares").x_label("x").y_label("x²");
//! fig.push(Series::line(&x, &y).label("exact").dash(Dash::Dashed));
//! fig.push(Series::scatter(&x, &y, Marker::Circle).label("samples"));
//! fig.save("/tmp/squares.svg")?;
//! # Ok::<(), hsid_host::plot::PlotError>(())
//! ```
//!
//! # Missing data
//!
//! Points with a NaN or infinite coordinate (and, on a logarithmic x axis, points with `x <= 0`)
//! are skipped: they are left out of the automatic axis ranges, a line is broken at them (so a
//! gap shows where the data is missing, and a valid point with invalid neighbours on both sides
//! is not drawn), a marker is not drawn, and a band is interrupted. They never reach the SVG
//! text. Series of mismatched lengths are an error, not truncated.
//!
//! Anything drawn outside the axis ranges is clipped to the plot area.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The default colour cycle (Tableau 10): series without an explicit colour take the colour of
/// their position in the figure.
pub const PALETTE: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

const FONT_FAMILY: &str = "DejaVu Sans, Liberation Sans, Arial, Helvetica, sans-serif";
const TITLE_SIZE: f64 = 17.0;
const LABEL_SIZE: f64 = 14.0;
const TICK_SIZE: f64 = 12.0;
const LEGEND_SIZE: f64 = 12.0;
const TICK_LEN: f64 = 5.0;
const LEGEND_PAD: f64 = 8.0;
const LEGEND_SWATCH: f64 = 30.0;
const LEGEND_ROW: f64 = LEGEND_SIZE + 7.0;
const GRID_COLOR: &str = "#dcdcdc";
const MINOR_GRID_COLOR: &str = "#efefef";
const AXIS_COLOR: &str = "#333333";
/// Pixel coordinates are clamped to this magnitude so that far-away points stay printable.
const MAX_PX: f64 = 1e6;

/// Errors from building or saving a figure.
#[derive(Debug)]
pub enum PlotError {
    /// The coordinate vectors of a series have different lengths.
    LengthMismatch {
        /// 0-based position of the series in the figure.
        series: usize,
        /// Its legend label, if any.
        label: Option<String>,
        /// Description of the mismatch, e.g. `x has 10 values, y has 9`.
        detail: String,
    },
    /// An explicit axis range is not finite, empty or reversed, or not positive on a log axis.
    InvalidRange {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
    /// The figure is too small to hold its axes (minimum 200×150 px).
    InvalidSize {
        /// Requested width in px.
        width: u32,
        /// Requested height in px.
        height: u32,
    },
    /// The SVG file could not be written.
    Io {
        /// Target file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlotError::LengthMismatch {
                series,
                label,
                detail,
            } => match label {
                Some(l) => write!(f, "series {series} (\"{l}\"): {detail}"),
                None => write!(f, "series {series}: {detail}"),
            },
            PlotError::InvalidRange { axis, min, max } => {
                write!(f, "invalid {axis} axis range [{min}, {max}]")
            }
            PlotError::InvalidSize { width, height } => {
                write!(f, "figure size {width}×{height} px is below 200×150 px")
            }
            PlotError::Io { path, source } => {
                write!(f, "{}: cannot write figure: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for PlotError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PlotError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Dash pattern of a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dash {
    /// Continuous line.
    #[default]
    Solid,
    /// Long dashes.
    Dashed,
    /// Dots.
    Dotted,
    /// Alternating dashes and dots.
    DashDot,
}

/// Shape of scatter markers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// Upright cross `+`.
    Plus,
    /// Diagonal cross `x`.
    Cross,
    /// Asterisk `*` (a `+` and an `x` on top of each other).
    Star,
    /// Open circle.
    Circle,
    /// Filled disc.
    Dot,
}

/// Where the legend box goes; it is drawn only if some series has a label.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPosition {
    /// The inner corner of the plot area that covers the fewest data points.
    #[default]
    Best,
    /// Upper right corner of the plot area.
    TopRight,
    /// Upper left corner of the plot area.
    TopLeft,
    /// Lower right corner of the plot area.
    BottomRight,
    /// Lower left corner of the plot area.
    BottomLeft,
    /// Right of the plot area, top-aligned (the plot area gets narrower); for long legends.
    OutsideRight,
    /// No legend.
    Hidden,
}

#[derive(Debug, Clone)]
enum Kind {
    Line {
        x: Vec<f64>,
        y: Vec<f64>,
    },
    Scatter {
        x: Vec<f64>,
        y: Vec<f64>,
        marker: Marker,
    },
    Band {
        x: Vec<f64>,
        lower: Vec<f64>,
        upper: Vec<f64>,
    },
}

/// One data series of a [`Figure`]: a line, a set of markers or a filled band.
///
/// Built with [`Series::line`], [`Series::scatter`] or [`Series::band`] and styled with the
/// chained setters. The data is copied.
#[derive(Debug, Clone)]
pub struct Series {
    kind: Kind,
    label: Option<String>,
    color: Option<String>,
    width: f64,
    dash: Dash,
    size: f64,
    opacity: f64,
}

impl Series {
    fn new(kind: Kind, width: f64) -> Self {
        Series {
            kind,
            label: None,
            color: None,
            width,
            dash: Dash::Solid,
            size: 4.0,
            opacity: 0.25,
        }
    }

    /// A polyline through `(x[i], y[i])` (default width 1.8 px, solid).
    pub fn line(x: &[f64], y: &[f64]) -> Self {
        Series::new(
            Kind::Line {
                x: x.to_vec(),
                y: y.to_vec(),
            },
            1.8,
        )
    }

    /// Markers at `(x[i], y[i])` (default half-size 4 px, stroke width 1.4 px).
    pub fn scatter(x: &[f64], y: &[f64], marker: Marker) -> Self {
        Series::new(
            Kind::Scatter {
                x: x.to_vec(),
                y: y.to_vec(),
                marker,
            },
            1.4,
        )
    }

    /// The area between `lower[i]` and `upper[i]` over `x[i]` (default opacity 0.25).
    pub fn band(x: &[f64], lower: &[f64], upper: &[f64]) -> Self {
        Series::new(
            Kind::Band {
                x: x.to_vec(),
                lower: lower.to_vec(),
                upper: upper.to_vec(),
            },
            0.0,
        )
    }

    /// Legend text; series without a label are not listed in the legend.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }

    /// Any SVG colour (`"#1f77b4"`, `"black"`, `"rgb(0,0,0)"`); default: the palette.
    pub fn color(mut self, color: impl Into<String>) -> Self {
        self.color = Some(color.into());
        self
    }

    /// Line width, or marker stroke width, in px.
    pub fn width(mut self, width: f64) -> Self {
        self.width = width;
        self
    }

    /// Dash pattern of a line (ignored for markers and bands).
    pub fn dash(mut self, dash: Dash) -> Self {
        self.dash = dash;
        self
    }

    /// Marker half-size (radius) in px.
    pub fn size(mut self, size: f64) -> Self {
        self.size = size;
        self
    }

    /// Fill opacity of a band, 0 to 1.
    pub fn opacity(mut self, opacity: f64) -> Self {
        self.opacity = opacity;
        self
    }

    fn check(&self, index: usize) -> Result<(), PlotError> {
        let detail = match &self.kind {
            Kind::Line { x, y } | Kind::Scatter { x, y, .. } if x.len() != y.len() => {
                Some(format!("x has {} values, y has {}", x.len(), y.len()))
            }
            Kind::Band { x, lower, upper } if x.len() != lower.len() || x.len() != upper.len() => {
                Some(format!(
                    "x has {} values, lower {}, upper {}",
                    x.len(),
                    lower.len(),
                    upper.len()
                ))
            }
            _ => None,
        };
        match detail {
            Some(detail) => Err(PlotError::LengthMismatch {
                series: index,
                label: self.label.clone(),
                detail,
            }),
            None => Ok(()),
        }
    }

    /// All (x, y) pairs of the series (for ranges and legend placement).
    fn points(&self) -> Vec<(f64, f64)> {
        match &self.kind {
            Kind::Line { x, y } | Kind::Scatter { x, y, .. } => {
                x.iter().copied().zip(y.iter().copied()).collect()
            }
            Kind::Band { x, lower, upper } => x
                .iter()
                .zip(lower)
                .map(|(&a, &b)| (a, b))
                .chain(x.iter().zip(upper).map(|(&a, &b)| (a, b)))
                .collect(),
        }
    }
}

/// A figure with one set of axes.
///
/// Settings are chained on construction (`Figure::new(..).x_label(..)`), series are added with
/// [`push`](Figure::push) or [`with`](Figure::with) and drawn in that order. Defaults: 800×560
/// px, linear axes whose automatic ranges are widened to tick values, light grey grid, legend in
/// the best corner.
#[derive(Debug, Clone)]
pub struct Figure {
    title: String,
    x_label: String,
    y_label: String,
    width: u32,
    height: u32,
    log_x: bool,
    log_y: bool,
    equal_aspect: bool,
    x_range: Option<(f64, f64)>,
    y_range: Option<(f64, f64)>,
    legend: LegendPosition,
    series: Vec<Series>,
}

impl Figure {
    /// An empty 800×560 figure with a title (an empty title leaves no space for it).
    pub fn new(title: impl Into<String>) -> Self {
        Figure {
            title: title.into(),
            x_label: String::new(),
            y_label: String::new(),
            width: 800,
            height: 560,
            log_x: false,
            log_y: false,
            equal_aspect: false,
            x_range: None,
            y_range: None,
            legend: LegendPosition::Best,
            series: Vec::new(),
        }
    }

    /// Label under the x axis.
    pub fn x_label(mut self, label: impl Into<String>) -> Self {
        self.x_label = label.into();
        self
    }

    /// Label left of the y axis (rotated).
    pub fn y_label(mut self, label: impl Into<String>) -> Self {
        self.y_label = label.into();
        self
    }

    /// Size in px (at least 200×150).
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.width = width;
        self.height = height;
        self
    }

    /// Logarithmic x axis (decades labelled `10ⁿ`); points with `x <= 0` are skipped.
    pub fn log_x(mut self, log: bool) -> Self {
        self.log_x = log;
        self
    }

    /// Logarithmic y axis (e.g. for singular values); points with `y <= 0` are skipped.
    pub fn log_y(mut self, log: bool) -> Self {
        self.log_y = log;
        self
    }

    /// Same scale on both axes (one unit is as long in x as in y); the axis with room to spare
    /// is widened symmetrically. Ignored with a logarithmic axis.
    pub fn equal_aspect(mut self, equal: bool) -> Self {
        self.equal_aspect = equal;
        self
    }

    /// Fixed x range instead of the automatic one.
    pub fn x_range(mut self, min: f64, max: f64) -> Self {
        self.x_range = Some((min, max));
        self
    }

    /// Fixed y range instead of the automatic one.
    pub fn y_range(mut self, min: f64, max: f64) -> Self {
        self.y_range = Some((min, max));
        self
    }

    /// Legend placement.
    pub fn legend(mut self, position: LegendPosition) -> Self {
        self.legend = position;
        self
    }

    /// Adds a series (chained form).
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a series.
    pub fn push(&mut self, series: Series) -> &mut Self {
        self.series.push(series);
        self
    }

    /// Writes the SVG file.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        let path = path.as_ref();
        let svg = self.to_svg()?;
        std::fs::write(path, svg).map_err(|source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        })
    }

    /// The SVG document as text (starts with `<svg`).
    pub fn to_svg(&self) -> Result<String, PlotError> {
        if self.width < 200 || self.height < 150 {
            return Err(PlotError::InvalidSize {
                width: self.width,
                height: self.height,
            });
        }
        for (i, s) in self.series.iter().enumerate() {
            s.check(i)?;
        }
        if let Some((a, b)) = self.x_range
            && !(a.is_finite() && b.is_finite() && a < b && (!self.log_x || a > 0.0))
        {
            return Err(PlotError::InvalidRange {
                axis: "x",
                min: a,
                max: b,
            });
        }
        if let Some((a, b)) = self.y_range
            && !(a.is_finite() && b.is_finite() && a < b && (!self.log_y || a > 0.0))
        {
            return Err(PlotError::InvalidRange {
                axis: "y",
                min: a,
                max: b,
            });
        }
        let layout = self.layout();
        Ok(self.render(&layout))
    }

    fn valid(&self, x: f64, y: f64) -> bool {
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

    fn layout(&self) -> Layout {
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
    fn axes(
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

    fn render(&self, layout: &Layout) -> String {
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
        let mut minor = String::new();
        for &v in &x.minor {
            let _ = write!(
                minor,
                "M{} {}V{}",
                num(px(v)),
                num(plot.y),
                num(plot.y + plot.h)
            );
        }
        for &v in &y.minor {
            let _ = write!(
                minor,
                "M{} {}H{}",
                num(plot.x),
                num(py(v)),
                num(plot.x + plot.w)
            );
        }
        if !minor.is_empty() {
            let _ = writeln!(
                s,
                r#"<path d="{minor}" stroke="{MINOR_GRID_COLOR}" stroke-width="1" fill="none"/>"#
            );
        }
        let mut grid = String::new();
        for &v in &x.major {
            let _ = write!(
                grid,
                "M{} {}V{}",
                num(px(v)),
                num(plot.y),
                num(plot.y + plot.h)
            );
        }
        for &v in &y.major {
            let _ = write!(
                grid,
                "M{} {}H{}",
                num(plot.x),
                num(py(v)),
                num(plot.x + plot.w)
            );
        }
        if !grid.is_empty() {
            let _ = writeln!(
                s,
                r#"<path d="{grid}" stroke="{GRID_COLOR}" stroke-width="1" fill="none"/>"#
            );
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
            match &series.kind {
                Kind::Line { x: xs, y: ys } => {
                    let d = polyline(xs.iter().zip(ys).map(|(&a, &b)| to_px(a, b)));
                    if !d.is_empty() {
                        let _ = writeln!(
                            s,
                            r#"<path d="{d}" fill="none" stroke="{color}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round"{}/>"#,
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
                        let _ =
                            writeln!(s, "{}", marker_element(&d, *marker, &color, series.width));
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
                            r#"<path d="{d}" fill="{color}" fill-opacity="{}" stroke="none"/>"#,
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

    /// Width and height of the legend box, `None` if there is no legend.
    fn legend_size(&self) -> Option<(f64, f64)> {
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

    fn render_legend(
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
                let samples = self.pixel_samples(to_px);
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
                    let _ = writeln!(s, "{}", marker_element(&d, *marker, &color, series.width));
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

    /// Pixel positions along all drawn data, about every 5 px along lines, for legend placement.
    fn pixel_samples(&self, to_px: &dyn Fn(f64, f64) -> Option<(f64, f64)>) -> Vec<(f64, f64)> {
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

// ---------------------------------------------------------------------------------------------
// Axes and ticks
// ---------------------------------------------------------------------------------------------

/// A closed interval `(min, max)`.
type Span = (f64, f64);
/// A point in px.
type Point = (f64, f64);

struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

impl Rect {
    fn contains(&self, px: f64, py: f64, margin: f64) -> bool {
        px >= self.x - margin
            && px <= self.x + self.w + margin
            && py >= self.y - margin
            && py <= self.y + self.h + margin
    }
}

struct Layout {
    plot: Rect,
    x: Axis,
    y: Axis,
}

/// A tick label: plain text or a power of ten.
enum TickLabel {
    Text(String),
    Pow10(i32),
}

impl TickLabel {
    fn width(&self, size: f64) -> f64 {
        match self {
            TickLabel::Text(t) => text_width(t, size),
            TickLabel::Pow10(e) => {
                text_width("10", size) + text_width(&minus(&e.to_string()), 0.75 * size)
            }
        }
    }

    fn svg(&self) -> String {
        match self {
            TickLabel::Text(t) => escape(t),
            TickLabel::Pow10(e) => format!(
                r#"10<tspan dy="-{}" font-size="{}">{}</tspan>"#,
                num(0.45 * TICK_SIZE),
                num(0.75 * TICK_SIZE),
                minus(&e.to_string())
            ),
        }
    }
}

/// One axis: range in axis coordinates (log10 of the value for a log axis), tick positions in
/// axis coordinates, and labels for the major ticks.
struct Axis {
    lo: f64,
    hi: f64,
    major: Vec<f64>,
    minor: Vec<f64>,
    labels: Vec<TickLabel>,
}

impl Axis {
    fn to_unit(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }

    /// Range widened to multiples of a nice step.
    ///
    /// An end is only moved to a tick if that adds at most 8 % of the span; otherwise it stays
    /// (so [-1.02, 1.02] does not become [-1.5, 1.5]).
    fn linear_extended(lo: f64, hi: f64, target: f64) -> Axis {
        let span = hi - lo;
        let step = nice_step(span, target);
        let mut a = snap((lo / step + 1e-9).floor() * step, step);
        let mut b = snap((hi / step - 1e-9).ceil() * step, step);
        if lo - a > 0.08 * span {
            a = lo;
        }
        if b - hi > 0.08 * span {
            b = hi;
        }
        Axis::linear_within(a, b, step)
    }

    /// Range as given, ticks at the multiples of `step` inside it.
    fn linear_within(lo: f64, hi: f64, step: f64) -> Axis {
        let (major, step) = at_least_two_ticks(lo, hi, step);
        let labels = tick_labels(&major, step);
        Axis {
            lo,
            hi,
            major,
            minor: Vec::new(),
            labels,
        }
    }

    /// Halves the number of labelled ticks until the labels do not overlap.
    fn thin_to_fit(mut self, px_len: f64) -> Axis {
        for _ in 0..6 {
            if self.major.len() < 3 {
                break;
            }
            let widest = self
                .labels
                .iter()
                .map(|l| l.width(TICK_SIZE))
                .fold(0.0, f64::max);
            let spacing = px_len * (self.major[1] - self.major[0]) / (self.hi - self.lo);
            if widest + 10.0 <= spacing {
                break;
            }
            let step = nice_step(2.01 * (self.major[1] - self.major[0]), 1.0);
            let (lo, hi) = (self.lo, self.hi);
            self = Axis::linear_within(lo, hi, step);
            self.lo = lo;
            self.hi = hi;
        }
        self
    }

    /// A log axis over `[lo, hi]` given as log10 values.
    fn log(lo: f64, hi: f64, target: f64) -> Axis {
        let (ticks, minor_values) = log_ticks(10f64.powf(lo), 10f64.powf(hi), target);
        let all_pow10 = ticks.iter().all(|t| is_pow10(*t));
        let labels = ticks
            .iter()
            .map(|&t| {
                if all_pow10 {
                    TickLabel::Pow10(t.log10().round() as i32)
                } else {
                    TickLabel::Text(minus(&format!("{}", t)))
                }
            })
            .collect();
        Axis {
            lo,
            hi,
            major: ticks.iter().map(|t| t.log10()).collect(),
            minor: minor_values.iter().map(|t| t.log10()).collect(),
            labels,
        }
    }
}

fn is_pow10(v: f64) -> bool {
    let e = v.log10().round();
    (v / 10f64.powf(e) - 1.0).abs() < 1e-9
}

/// The "nice" step (1, 2 or 5 times a power of ten) that splits `span` into at most about
/// `target` intervals. Returns 1 for a non-finite or non-positive span.
pub fn nice_step(span: f64, target: f64) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    let raw = span / target.max(1.0);
    let mag = 10f64.powf(raw.log10().floor());
    let norm = raw / mag;
    let m = if norm <= 1.0 + 1e-9 {
        1.0
    } else if norm <= 2.0 + 1e-9 {
        2.0
    } else if norm <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    m * mag
}

/// Nice tick values inside `[min, max]`: multiples of [`nice_step`]`(max - min, target)`,
/// rounded so that they print exactly (`0.3`, not `0.30000000000000004`). Empty if the range is
/// not finite or `min > max`; `[min]` if `min == max`.
pub fn nice_ticks(min: f64, max: f64, target: usize) -> Vec<f64> {
    if !(min.is_finite() && max.is_finite()) || min > max {
        return Vec::new();
    }
    if min == max {
        return vec![min];
    }
    at_least_two_ticks(min, max, nice_step(max - min, target as f64)).0
}

/// Ticks at multiples of `step`, with the step lowered (5 → 2 → 1 → 0.5 ...) until at least two
/// fall inside the range. Returns the ticks and the step used.
fn at_least_two_ticks(lo: f64, hi: f64, mut step: f64) -> (Vec<f64>, f64) {
    for _ in 0..6 {
        let ticks = ticks_with_step(lo, hi, step);
        if ticks.len() >= 2 {
            return (ticks, step);
        }
        let mag = 10f64.powf((step.log10() + 1e-9).floor());
        let m = (step / mag).round();
        step = if m >= 5.0 {
            2.0 * mag
        } else if m >= 2.0 {
            mag
        } else {
            0.5 * mag
        };
    }
    (ticks_with_step(lo, hi, step), step)
}

/// Ticks of a logarithmic axis over `[min, max]` (both > 0): the powers of ten inside the range
/// (every k-th decade if there are more than about `target`), or 1-2-5 multiples when the range
/// spans less than about two decades. The second vector holds the minor ticks (2..9 × 10ⁿ).
pub fn log_ticks(min: f64, max: f64, target: f64) -> (Vec<f64>, Vec<f64>) {
    if !(min.is_finite() && max.is_finite() && min > 0.0 && min < max) {
        return (Vec::new(), Vec::new());
    }
    let lo = min.log10();
    let hi = max.log10();
    let e0 = (lo - 1e-9).floor() as i32;
    let e1 = (hi + 1e-9).ceil() as i32;
    let inside = |v: f64| v.log10() >= lo - 1e-9 && v.log10() <= hi + 1e-9;
    let decades: Vec<i32> = (e0..=e1).filter(|&e| inside(pow10(e))).collect();
    let mut minor = Vec::new();
    if decades.len() >= 2 {
        let every = ((decades.len() as f64 / target.max(2.0)).ceil() as i32).max(1);
        let mut major = Vec::new();
        for &e in &decades {
            if e.rem_euclid(every) == 0 {
                major.push(pow10(e));
            } else {
                minor.push(pow10(e));
            }
        }
        if every == 1 {
            for e in e0..e1 {
                for m in 2..10 {
                    let v = snap(f64::from(m) * pow10(e), pow10(e));
                    if inside(v) {
                        minor.push(v);
                    }
                }
            }
        }
        return (major, minor);
    }
    // Less than two decades: label 1, 2 and 5 times the powers of ten.
    let mut major = Vec::new();
    for e in e0..=e1 {
        for m in 1..10 {
            let v = snap(f64::from(m) * pow10(e), pow10(e));
            if inside(v) {
                if m == 1 || m == 2 || m == 5 {
                    major.push(v);
                } else {
                    minor.push(v);
                }
            }
        }
    }
    (major, minor)
}

fn pow10(e: i32) -> f64 {
    format!("1e{e}").parse().unwrap_or(10f64.powi(e))
}

fn ticks_with_step(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && step.is_finite() && step > 0.0) {
        return Vec::new();
    }
    let k0 = (lo / step - 1e-9).ceil();
    let k1 = (hi / step + 1e-9).floor();
    if k1 < k0 || k1 - k0 > 1000.0 {
        return Vec::new();
    }
    let n = (k1 - k0) as usize;
    (0..=n)
        .map(|i| snap((k0 + i as f64) * step, step))
        .collect()
}

/// Rounds `v` to the decimal precision of `step` so that it prints exactly.
fn snap(v: f64, step: f64) -> f64 {
    let d = decimals(step);
    if d == 0 {
        return v.round();
    }
    let text = format!("{v:.d$}");
    let snapped: f64 = text.parse().unwrap_or(v);
    if snapped == 0.0 { 0.0 } else { snapped }
}

/// Number of decimals needed to print multiples of a 1-2-5 `step`.
fn decimals(step: f64) -> usize {
    if step >= 1.0 {
        0
    } else {
        ((-step.log10() - 1e-9).ceil().max(0.0) as usize).min(17)
    }
}

fn tick_labels(ticks: &[f64], step: f64) -> Vec<TickLabel> {
    let biggest = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let scientific = step < 1e-4 || biggest >= 1e6;
    ticks
        .iter()
        .map(|&t| {
            let text = if t == 0.0 {
                "0".to_string()
            } else if scientific {
                format!("{t:e}")
            } else {
                format!("{t:.*}", decimals(step))
            };
            TickLabel::Text(minus(&text))
        })
        .collect()
}

/// Replaces ASCII hyphen-minus by the typographic minus sign.
fn minus(s: &str) -> String {
    s.replace('-', "\u{2212}")
}

/// Rough rendered width of a text in a sans-serif font.
fn text_width(s: &str, size: f64) -> f64 {
    s.chars()
        .map(|c| match c {
            '0'..='9' => 0.64,
            '.' | ',' | ':' | ';' | '|' | 'i' | 'j' | 'l' | '!' | '\'' => 0.32,
            ' ' => 0.32,
            '\u{2212}' | '+' | '=' | '<' | '>' => 0.84,
            '-' | '(' | ')' | '[' | ']' | 'f' | 't' | 'r' => 0.40,
            'm' | 'w' | 'M' | 'W' => 0.95,
            'A'..='Z' => 0.72,
            _ => 0.60,
        })
        .sum::<f64>()
        * size
}

// ---------------------------------------------------------------------------------------------
// SVG helpers
// ---------------------------------------------------------------------------------------------

fn series_color(series: &Series, index: usize) -> String {
    series
        .color
        .clone()
        .unwrap_or_else(|| PALETTE[index % PALETTE.len()].to_string())
}

/// A pixel coordinate with at most two decimals and no trailing zeros.
fn num(v: f64) -> String {
    if !v.is_finite() {
        return "0".to_string();
    }
    let s = format!("{:.2}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => out.push(c),
        }
    }
    out
}

fn dash_attr(dash: Dash, width: f64) -> String {
    let k = (width / 1.5).max(1.0);
    let pattern = match dash {
        Dash::Solid => return String::new(),
        Dash::Dashed => vec![7.0, 4.0],
        Dash::Dotted => vec![0.5, 3.5],
        Dash::DashDot => vec![8.0, 3.5, 0.5, 3.5],
    };
    let p: Vec<String> = pattern.iter().map(|v| num(v * k)).collect();
    format!(r#" stroke-dasharray="{}""#, p.join(" "))
}

/// Path data through the points, starting a new sub-path after every missing point.
fn polyline(points: impl Iterator<Item = Option<(f64, f64)>>) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for p in points {
        match p {
            Some((x, y)) => {
                let _ = write!(
                    d,
                    "{}{} {}",
                    if pen_down { "L" } else { "M" },
                    num(x),
                    num(y)
                );
                pen_down = true;
            }
            None => pen_down = false,
        }
    }
    d
}

fn band_path(
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    to_px: &dyn Fn(f64, f64) -> Option<(f64, f64)>,
) -> String {
    let mut d = String::new();
    let mut run: Vec<(Point, Point)> = Vec::new();
    let flush = |run: &mut Vec<(Point, Point)>, d: &mut String| {
        if run.len() >= 2 {
            for (k, (u, _)) in run.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{} {}",
                    if k == 0 { "M" } else { "L" },
                    num(u.0),
                    num(u.1)
                );
            }
            for (_, l) in run.iter().rev() {
                let _ = write!(d, "L{} {}", num(l.0), num(l.1));
            }
            d.push('Z');
        }
        run.clear();
    };
    for i in 0..x.len() {
        match (to_px(x[i], upper[i]), to_px(x[i], lower[i])) {
            (Some(u), Some(l)) => run.push((u, l)),
            _ => flush(&mut run, &mut d),
        }
    }
    flush(&mut run, &mut d);
    d
}

fn marker_path(d: &mut String, marker: Marker, x: f64, y: f64, r: f64) {
    let mut seg = |x0: f64, y0: f64, x1: f64, y1: f64| {
        let _ = write!(d, "M{} {}L{} {}", num(x0), num(y0), num(x1), num(y1));
    };
    let a = r * std::f64::consts::FRAC_1_SQRT_2;
    match marker {
        Marker::Plus => {
            seg(x - r, y, x + r, y);
            seg(x, y - r, x, y + r);
        }
        Marker::Cross => {
            seg(x - a, y - a, x + a, y + a);
            seg(x - a, y + a, x + a, y - a);
        }
        Marker::Star => {
            seg(x - r, y, x + r, y);
            seg(x, y - r, x, y + r);
            seg(x - a, y - a, x + a, y + a);
            seg(x - a, y + a, x + a, y - a);
        }
        Marker::Circle | Marker::Dot => {
            let (rs, d2) = (num(r), num(2.0 * r));
            let _ = write!(
                d,
                "M{} {}a{rs} {rs} 0 1 0 {d2} 0a{rs} {rs} 0 1 0 -{d2} 0",
                num(x - r),
                num(y)
            );
        }
    }
}

fn marker_element(d: &str, marker: Marker, color: &str, width: f64) -> String {
    match marker {
        Marker::Dot => format!(r#"<path d="{d}" fill="{color}" stroke="none"/>"#),
        _ => format!(
            r#"<path d="{d}" fill="none" stroke="{color}" stroke-width="{}" stroke-linecap="round"/>"#,
            num(width)
        ),
    }
}
