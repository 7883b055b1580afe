//! The HTML report of `hsid identify`: the library's page of the identification, with the
//! figures `--out` draws.

use std::path::{Path, PathBuf};

use hsid_host::figures::FigureSettings;
use hsid_host::html::Reproduction;
use hsid_host::html::identified::identified_page;
use hsid_host::workflow::Identified;

use super::IdentifyArgs;
use crate::failure::{Failure, outln};

/// Writes the HTML report of the identification `id` to `path`: the fitted element's page
/// when the element was fitted, else the model's.
pub fn write(
    a: &IdentifyArgs,
    path: &Path,
    id: &Identified,
    settings: &FigureSettings,
) -> Result<(), Failure> {
    let title = format!("hsid identify: {}", names(&a.data));
    identified_page(id, title, settings, Reproduction::of_this_run(&a.data))
        .and_then(|page| page.write(path))
        .map_err(|e| e.to_string())?;
    outln!("wrote {}", path.display())?;
    Ok(())
}

/// The record files, comma-separated.
fn names(data: &[PathBuf]) -> String {
    let names: Vec<String> = data.iter().map(|p| p.display().to_string()).collect();
    names.join(", ")
}
