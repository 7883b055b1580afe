//! A figure: its settings, its series, and writing it as SVG.

use std::path::Path;

use super::error::PlotError;
use super::series::Series;
use super::style::LegendPosition;

/// A figure with one set of axes.
///
/// Settings are chained on construction (`Figure::new(..).x_label(..)`), series are added with
/// [`push`](Figure::push) or [`with`](Figure::with) and drawn in that order. Defaults: 800×560
/// px, linear axes whose automatic ranges are widened to tick values, light grey grid, legend in
/// the best corner.
#[derive(Debug, Clone)]
pub struct Figure {
    pub(super) title: String,
    pub(super) x_label: String,
    pub(super) y_label: String,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) log_x: bool,
    pub(super) log_y: bool,
    pub(super) equal_aspect: bool,
    pub(super) x_range: Option<(f64, f64)>,
    pub(super) y_range: Option<(f64, f64)>,
    pub(super) legend: LegendPosition,
    pub(super) series: Vec<Series>,
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

    /// The title.
    pub fn title(&self) -> &str {
        &self.title
    }

    /// The figure with another title.
    pub fn retitle(mut self, title: impl Into<String>) -> Self {
        self.title = title.into();
        self
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
    pub(crate) fn equal_aspect(mut self, equal: bool) -> Self {
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
        crate::io::write_atomic(path, svg).map_err(|source| PlotError::Io {
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
}
