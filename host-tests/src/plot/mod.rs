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

mod axis;
mod error;
mod figure;
mod layout;
mod legend;
mod render;
mod series;
mod style;
mod svg;
mod ticks;

pub use error::PlotError;
pub use figure::Figure;
pub use series::Series;
pub use style::{Dash, LegendPosition, Marker, PALETTE};
pub use svg::escape;
pub use ticks::{log_ticks, nice_step, nice_ticks};
