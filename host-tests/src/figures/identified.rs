//! The figures of one identification ([`Identified`]): the fitted element's when the element
//! was fitted, else the model's (the refined model with its standard deviations when it was
//! refined), on the record it was identified from.

use std::path::Path;

use super::{
    FigureError, FigureSettings, RecordView, UncertaintySource, Written, write_element_figures,
    write_figures,
};
use crate::model::Record;
use crate::workflow::Identified;

impl<'a> RecordView<'a> {
    /// The view of `record`: its samples, the hold left out.
    pub fn of(record: &'a Record) -> Self {
        RecordView {
            u: &record.u,
            y: &record.y,
            skip: record.hold,
        }
    }
}

/// Writes the figures of `id` on its record into `dir` (those `--out` writes).
pub fn write_identified(
    dir: &Path,
    id: &Identified,
    settings: &FigureSettings,
) -> Result<Written, FigureError> {
    let view = RecordView::of(&id.record);
    match &id.element {
        Some(fit) => write_element_figures(dir, fit, &view, settings),
        None => {
            let best = &id.best;
            let model = best.fit.as_ref().map_or(&best.model, |f| &f.model);
            let uncertainty = best
                .fit
                .as_ref()
                .filter(|f| !f.singular)
                .map(UncertaintySource::Refined);
            write_figures(dir, model, &view, uncertainty, settings)
        }
    }
}
