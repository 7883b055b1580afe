//! `--out DIR` of `hsid identify` and `hsid validate`: the figures of the model and of its fit
//! to the record, as SVG with a CSV of every plotted curve (see docs/figures.md).

use std::path::{Path, PathBuf};

use clap::Args;
use hsid_host::figures::{
    FigureError, FigureSettings, RecordView, TrueBorders, UncertaintySource, Written,
    write_figures, write_identified,
};
use hsid_host::identify::HostModel;
use hsid_host::io::StagedDir;
use hsid_host::model_file::{ModelFile, Units};
use hsid_host::simulate::{PlantSpec, true_loop};
use hsid_host::workflow::Identified;

use crate::failure::{Failure, outln};

/// Where the figures go.
#[derive(Args)]
pub struct FigureArgs {
    /// Write SVG figures of the model (borders, Bode magnitude and phase, poles) and of its fit
    /// to this record (output, residual, residual autocorrelation), each with a CSV of its
    /// curves, into this directory (created if missing).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// With --out or --html, for a simulated record: the plant specification it was simulated
    /// from (`hsid simulate --plant`); its element's loop under the Table I sweeps, times the
    /// linear part's static gain, is drawn dashed beside the identified borders (in the
    /// figures of --out and in the HTML report).
    #[arg(long, value_name = "SPEC")]
    true_plant: Option<PathBuf>,
}

impl FigureArgs {
    /// Refuses `--true-plant` when nothing draws it: neither `--out` nor `--html` (`html`)
    /// is given.
    pub fn check_true_plant(&self, html: bool) -> Result<(), Failure> {
        match (&self.true_plant, &self.out, html) {
            (Some(_), None, false) => Err(
                "--true-plant draws the true loop in the figures: give --out DIR or --html FILE"
                    .to_string()
                    .into(),
            ),
            _ => Ok(()),
        }
    }

    /// The directory of `--out`, if given.
    pub fn dir(&self) -> Option<&Path> {
        self.out.as_deref()
    }
}

/// The figures' settings: the sample time and units as stated, the true borders of
/// `--true-plant` read against `model`.
pub fn settings(
    a: &FigureArgs,
    ts: Option<f64>,
    units: Option<&Units>,
    model: &HostModel,
) -> Result<FigureSettings, Failure> {
    Ok(FigureSettings {
        ts,
        units: units.map(|u| (u.input.clone(), u.output.clone())),
        truth: truth(a, model)?,
    })
}

/// The true loop of `--true-plant` on `[u_min, u_max]`, or none (also drawn in the HTML report).
pub fn truth(a: &FigureArgs, model: &HostModel) -> Result<Option<TrueBorders>, Failure> {
    let Some(path) = &a.true_plant else {
        return Ok(None);
    };
    let spec = PlantSpec::load(path).map_err(|e| e.to_string())?;
    let t = true_loop(&spec, model.u_min(), model.u_max(), 401)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Some(TrueBorders {
        u: t.u,
        asc: t.asc,
        desc: t.desc,
    }))
}

/// The figures of the identification `id` on its estimation record (the fitted element's
/// when it was fitted, else the model's); the hold is left out of the residual and the
/// measured border points. Axes are in seconds/Hz and in units when the sample time and
/// units are known. Returns the lines to print after the model report (none without
/// `--out`).
pub fn identified(
    a: &FigureArgs,
    id: &Identified,
    settings: &FigureSettings,
) -> Result<Vec<String>, Failure> {
    let Some(dir) = &a.out else {
        return Ok(Vec::new());
    };
    staged(dir, |stage| write_identified(stage, id, settings))
}

/// The figures of a model file on a validation record; `skip` samples at the start are left
/// out of the residual and the measured border points. Sample time and units come from the
/// file when it has them.
pub fn validate(
    a: &FigureArgs,
    file: &ModelFile,
    model: &HostModel,
    u: &[f64],
    y: &[f64],
    skip: usize,
) -> Result<(), Failure> {
    let Some(dir) = &a.out else {
        return Ok(());
    };
    let settings = settings(a, file.sample_time, file.units.as_ref(), model)?;
    let record = RecordView { u, y, skip };
    let uncertainty = UncertaintySource::from_file(file);
    let written = staged(dir, |stage| {
        write_figures(stage, model, &record, uncertainty, &settings)
    })?;
    for line in written {
        outln!("{line}")?;
    }
    Ok(())
}

/// The figures that `write` writes into a folder, moved into `dir` together once all are
/// written ([`StagedDir`]: a run that fails or is stopped leaves `dir`'s previous figures as
/// they were); the lines that say what was written.
pub fn staged(
    dir: &Path,
    write: impl FnOnce(&Path) -> Result<Written, FigureError>,
) -> Result<Vec<String>, Failure> {
    let mut notes = Vec::new();
    let files = in_stage(dir, |stage| {
        write(stage).map(|w| {
            notes = w.notes;
            w.files
        })
    })?;
    Ok(lines(dir, &Written { files, notes }))
}

/// The files that `write` writes into the folder it is given, moved into `dir` together once
/// all are written ([`StagedDir`]); their paths in `dir`. Errors name `dir`, not the staging
/// folder inside it.
pub fn in_stage<E: std::fmt::Display>(
    dir: &Path,
    write: impl FnOnce(&Path) -> Result<Vec<PathBuf>, E>,
) -> Result<Vec<PathBuf>, Failure> {
    let stage = StagedDir::create(dir).map_err(|source| {
        FigureError::CreateDir {
            path: dir.to_path_buf(),
            source,
        }
        .to_string()
    })?;
    let inside = stage.path().display().to_string();
    let files = write(stage.path())
        .map_err(|e| e.to_string().replace(&inside, &dir.display().to_string()))?;
    Ok(stage
        .commit(&files)
        .map_err(|e| format!("{}: {e}", dir.display()))?)
}

/// What was written, as lines: the notes, then the count and the directory.
fn lines(dir: &Path, written: &Written) -> Vec<String> {
    let mut out: Vec<String> = written
        .notes
        .iter()
        .map(|n| format!("figures: {n}"))
        .collect();
    out.push(format!(
        "wrote {} figure files (SVG and CSV) to {}",
        written.files.len(),
        dir.display()
    ));
    out
}
