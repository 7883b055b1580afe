//! Pictures of an identified model and of how it fits a record, each an SVG with a CSV of
//! every plotted curve (header naming the series and their units):
//!
//! | files | what |
//! |---|---|
//! | `borders.svg`, `borders.csv`, `borders-points.csv`, `borders-gap.csv` | `P_a`, `P_d` against `u`, ±2σ bands, the true loop when known, the measured points (partial residuals of the record given the LTI part) and the gap marked at the middle of the input interval (a reversal after a descent: the arrow from `P_d` to `P_a`, `borders-gap.csv`) |
//! | `borders-detail.svg` | the borders figure around the gap marker (an eighth of the input interval each side), where the loop and its bands are wide |
//! | `bode-magnitude.svg`, `bode-phase.svg`, `bode.csv` | `G(e^{jω})` in dB and degrees, in Hz when the sample time is known, ±2σ bands |
//! | `poles.svg`, `poles.csv`, `poles-ellipses.csv` | poles in the z-plane with the unit circle and 2σ ellipses |
//! | `output.svg`, `output.csv` | measured and simulated output over time |
//! | `residual.svg`, `residual.csv`, `residual-acf.svg`, `residual-acf.csv` | measured − simulated over time and its autocorrelation with the ±1.96/√N bounds |
//!
//! [`write_element_figures`] draws a fitted play/relay model (`crate::hysteresis`) with the
//! same files, `borders.*` then being the element's borders `H_a`, `H_d` with its output on
//! the record, plus `borders-knots.csv` (values and standard deviations at the knots),
//! `element-output.csv` (the element's output on the record) and, for a play, `element.csv`
//! (the gap in input units).
//!
//! ```no_run
//! # fn demo(model: &hsid_host::identify::HostModel, u: &[f64], y: &[f64])
//! #     -> Result<(), hsid_host::figures::FigureError> {
//! use hsid_host::figures::{FigureSettings, RecordView, write_figures};
//! let settings = FigureSettings { ts: Some(0.01), ..FigureSettings::default() };
//! let record = RecordView { u, y, skip: 300 };
//! let written = write_figures("figs".as_ref(), model, &record, None, &settings)?;
//! println!("{} files", written.files.len());
//! # Ok(()) }
//! ```

mod bode;
mod borders;
mod csv;
mod element;
mod element_borders;
mod error;
mod gap_marker;
mod identified;
mod output;
mod partial;
mod poles;
mod residual;
mod settings;
mod uncertainty;

use std::path::{Path, PathBuf};

pub use element::{write_element_figures, write_element_model_figures};
pub use error::FigureError;
pub use identified::write_identified;
pub use partial::{MIN_ENERGY, departures};
pub use settings::{FigureSettings, TrueBorders};
pub use uncertainty::UncertaintySource;

use crate::identify::HostModel;

/// A measured record: input, output, and how many samples at the start (the hold) are left
/// out of the residual, its autocorrelation and the measured border points.
#[derive(Debug, Clone, Copy)]
pub struct RecordView<'a> {
    /// Input samples.
    pub u: &'a [f64],
    /// Output samples.
    pub y: &'a [f64],
    /// Samples left out at the start.
    pub skip: usize,
}

/// What [`write_figures`] wrote, and what it could not draw and why.
#[derive(Debug, Default)]
pub struct Written {
    /// Every file written, in order.
    pub files: Vec<PathBuf>,
    /// One line per part of a figure left out (e.g. measured border points of a plant whose
    /// inverse is unstable).
    pub notes: Vec<String>,
}

/// Everything a figure draws from (state, not settings).
struct Context<'a> {
    dir: &'a Path,
    model: &'a HostModel,
    record: RecordView<'a>,
    simulated: Vec<f64>,
    settings: &'a FigureSettings,
    uncertainty: Option<UncertaintySource<'a>>,
}

/// The settings' sample time, and a record of equal lengths with two samples after the skip.
fn check_record(record: &RecordView<'_>, settings: &FigureSettings) -> Result<(), FigureError> {
    settings.check()?;
    let (nu, ny, skip) = (record.u.len(), record.y.len(), record.skip);
    if nu != ny || skip + 2 > nu {
        return Err(FigureError::InvalidRecord { u: nu, y: ny, skip });
    }
    Ok(())
}

/// Writes every figure of `model` on `record` into `dir` (created if missing).
pub fn write_figures(
    dir: &Path,
    model: &HostModel,
    record: &RecordView<'_>,
    uncertainty: Option<UncertaintySource<'_>>,
    settings: &FigureSettings,
) -> Result<Written, FigureError> {
    check_record(record, settings)?;
    std::fs::create_dir_all(dir).map_err(|source| FigureError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let cx = Context {
        dir,
        model,
        record: *record,
        simulated: model.simulate(record.u),
        settings,
        uncertainty,
    };
    let mut out = Written::default();
    borders::write(&cx, &mut out)?;
    bode::write(&cx, &mut out)?;
    poles::write(&cx, &mut out)?;
    output::write(&cx, &mut out)?;
    residual::write(&cx, &mut out)?;
    Ok(out)
}
