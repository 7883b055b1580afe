//! One data series: a line, scatter markers, a filled band or an arrow, with its style.

use super::error::PlotError;
use super::style::{Dash, Marker};

#[derive(Debug, Clone)]
pub(super) enum Kind {
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
    Arrow {
        from: (f64, f64),
        to: (f64, f64),
        text: String,
    },
}

/// One data series of a [`Figure`](super::Figure): a line, a set of markers, a filled band or
/// an arrow.
///
/// Built with [`Series::line`], [`Series::scatter`], [`Series::band`] or [`Series::arrow`] and
/// styled with the chained setters. The data is copied.
#[derive(Debug, Clone)]
pub struct Series {
    pub(super) kind: Kind,
    pub(super) label: Option<String>,
    pub(super) color: Option<String>,
    pub(super) width: f64,
    pub(super) dash: Dash,
    pub(super) size: f64,
    pub(super) opacity: f64,
    pub(super) class: Option<String>,
}

impl Series {
    pub(super) fn new(kind: Kind, width: f64) -> Self {
        Series {
            kind,
            label: None,
            color: None,
            width,
            dash: Dash::Solid,
            size: 4.0,
            opacity: 0.25,
            class: None,
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

    /// A two-headed arrow from `from` to `to` (data coordinates) with a short bar across each
    /// end, as a dimension line marks a distance on a drawing, and `text` below it: centred
    /// under an arrow longer than the text, else starting at the `to` end (moved left to stay
    /// in the plot), on a white halo so that it reads over the data (default width
    /// 1.6 px; an empty `text` draws no text). Its SVG element is a `<g>` whose `data-from` and
    /// `data-to` attributes hold the ends in data coordinates, `x y`.
    pub fn arrow(from: (f64, f64), to: (f64, f64), text: impl Into<String>) -> Self {
        Series::new(
            Kind::Arrow {
                from,
                to,
                text: text.into(),
            },
            1.6,
        )
    }

    /// Legend text; series without a label are not listed in the legend.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }

    /// Any SVG colour (`"#1f77b4"`, `"black"`, `"rgb(0,0,0)"`); default: the palette.
    pub(crate) fn color(mut self, color: impl Into<String>) -> Self {
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
    pub(crate) fn opacity(mut self, opacity: f64) -> Self {
        self.opacity = opacity;
        self
    }

    /// A name written as the `class` attribute of the series' SVG element, so that programs
    /// reading the figure can find the series (e.g. `"border-asc"`).
    pub fn class(mut self, class: impl Into<String>) -> Self {
        self.class = Some(class.into());
        self
    }

    pub(super) fn check(&self, index: usize) -> Result<(), PlotError> {
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
    pub(super) fn points(&self) -> Vec<(f64, f64)> {
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
            Kind::Arrow { from, to, .. } => vec![*from, *to],
        }
    }
}
