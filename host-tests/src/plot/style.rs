//! Colours, fonts, sizes and the line, marker and legend styles of a figure.

/// The default colour cycle (Tableau 10): series without an explicit colour take the colour of
/// their position in the figure.
pub const PALETTE: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

pub(super) const FONT_FAMILY: &str = "DejaVu Sans, Liberation Sans, Arial, Helvetica, sans-serif";
pub(super) const TITLE_SIZE: f64 = 17.0;
pub(super) const LABEL_SIZE: f64 = 14.0;
pub(super) const TICK_SIZE: f64 = 12.0;
pub(super) const LEGEND_SIZE: f64 = 12.0;
pub(super) const ARROW_TEXT_SIZE: f64 = 14.0;
pub(super) const TICK_LEN: f64 = 5.0;
pub(super) const LEGEND_PAD: f64 = 8.0;
pub(super) const LEGEND_SWATCH: f64 = 30.0;
pub(super) const LEGEND_ROW: f64 = LEGEND_SIZE + 7.0;
pub(super) const GRID_COLOR: &str = "#dcdcdc";
pub(super) const MINOR_GRID_COLOR: &str = "#efefef";
pub(super) const AXIS_COLOR: &str = "#333333";
/// Pixel coordinates are clamped to this magnitude so that far-away points stay printable.
pub(super) const MAX_PX: f64 = 1e6;

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
