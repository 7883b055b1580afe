//! The figures of a run as inline figures: read from the SVG files a figure writer made, in
//! its order, each captioned by [`caption`]; or drawn into a scratch folder that is removed
//! afterwards, for a run without `--out`.

use std::path::{Path, PathBuf};

use super::captions::{caption, element_caption};
use super::error::HtmlError;
use super::figure::{InlineFigure, inline_svg};

/// The SVG files among `files` as inline figures, each titled and captioned by `caption` from
/// its file name (without `.svg` and `prefix`); `None` shows the name and says it has no
/// caption.
pub fn captioned(
    files: &[PathBuf],
    prefix: &str,
    caption: impl Fn(&str) -> Option<(String, String)>,
) -> Result<Vec<InlineFigure>, HtmlError> {
    let svgs = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "svg"));
    let mut out = Vec::new();
    for path in svgs {
        let text = std::fs::read_to_string(path).map_err(|source| HtmlError::ReadFigure {
            path: path.clone(),
            source,
        })?;
        let stem = path.file_stem().map_or_else(String::new, |s| {
            s.to_string_lossy().trim_start_matches(prefix).to_string()
        });
        let svg = inline_svg(&text, &format!("fig{}", out.len() + 1))
            .ok_or_else(|| HtmlError::NotSvg { path: path.clone() })?;
        let (title, caption) = caption(&stem).unwrap_or_else(|| {
            (
                stem.clone(),
                format!("{stem}.svg (no caption for this figure)"),
            )
        });
        out.push(InlineFigure {
            title,
            caption,
            svg,
        });
    }
    Ok(out)
}

/// The figures `write` draws into a fresh scratch folder, inlined; the folder is removed
/// afterwards. `write` returns the files it wrote, or its error in words.
pub fn drawn(
    write: impl FnOnce(&Path) -> Result<Vec<PathBuf>, String>,
) -> Result<Vec<InlineFigure>, HtmlError> {
    drawn_captioned(write, |stem| {
        caption(stem).map(|(t, c)| (t.to_string(), c.to_string()))
    })
}

/// [`drawn`], each figure titled and captioned by `caption` (as in [`captioned`]).
pub(crate) fn drawn_captioned(
    write: impl FnOnce(&Path) -> Result<Vec<PathBuf>, String>,
    caption: impl Fn(&str) -> Option<(String, String)>,
) -> Result<Vec<InlineFigure>, HtmlError> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let dir = std::env::temp_dir().join(format!("hsid-report-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| HtmlError::Scratch {
        path: dir.clone(),
        source,
    })?;
    let figures = write(&dir)
        .map_err(HtmlError::Figures)
        .and_then(|files| captioned(&files, "", caption));
    let removed = std::fs::remove_dir_all(&dir);
    let figures = figures?;
    removed.map_err(|source| HtmlError::Scratch { path: dir, source })?;
    Ok(figures)
}

/// The figures of `model` on `record` (those `--out` writes), inlined.
pub fn of_model(
    model: &crate::identify::HostModel,
    record: &crate::figures::RecordView<'_>,
    uncertainty: Option<crate::figures::UncertaintySource<'_>>,
    settings: &crate::figures::FigureSettings,
) -> Result<Vec<InlineFigure>, HtmlError> {
    drawn(|dir| {
        crate::figures::write_figures(dir, model, record, uncertainty, settings)
            .map(|w| w.files)
            .map_err(|e| e.to_string())
    })
}

/// The figures of the element model `model` on `record` (those `--out` writes for it, with
/// the element's caption of `borders`), inlined.
pub fn of_element(
    model: &crate::hysteresis::HysteresisModel,
    uncertainty: Option<&crate::hysteresis::uncertainty::Uncertainty>,
    record: &crate::figures::RecordView<'_>,
    settings: &crate::figures::FigureSettings,
) -> Result<Vec<InlineFigure>, HtmlError> {
    drawn_captioned(
        |dir| {
            crate::figures::write_element_model_figures(dir, model, uncertainty, record, settings)
                .map(|w| w.files)
                .map_err(|e| e.to_string())
        },
        |stem| element_caption(stem).map(|(t, c)| (t.to_string(), c.to_string())),
    )
}
