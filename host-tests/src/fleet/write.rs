//! A simulated fleet written to a directory: one checkpoint file per device and week, and the
//! truth table `truth.csv` beside it (outside the checkpoints' directory).

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::simulate::{Damage, DeviceTruth, FleetSpec, device_week, file_name, truth};
use super::solve::{FleetError, pool};

/// Why a fleet could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteFleetError {
    /// A file could not be written.
    #[error("{path}: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error's text.
        error: String,
    },
    /// The core refused the spec's settings.
    #[error("the fleet's settings: {0}")]
    Core(#[source] hsid::Error),
    /// The worker threads.
    #[error("{0}")]
    Fleet(#[source] FleetError),
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> WriteFleetError + '_ {
    move |e| WriteFleetError::Io {
        path: path.to_path_buf(),
        error: e.to_string(),
    }
}

/// Simulates the fleet of `spec` on `threads` workers, writes every checkpoint into `states`
/// (created) and the truth table to `truth_csv`; returns the truth.
pub fn write_fleet(
    spec: &FleetSpec,
    states: &Path,
    truth_csv: &Path,
    threads: Option<usize>,
) -> Result<Vec<DeviceTruth>, WriteFleetError> {
    spec.settings().map_err(WriteFleetError::Core)?;
    std::fs::create_dir_all(states).map_err(io(states))?;
    let truths: Vec<DeviceTruth> = (0..spec.devices).map(|i| truth(spec, i)).collect();
    let jobs: Vec<(usize, usize)> = (0..spec.devices)
        .flat_map(|d| (0..spec.weeks).map(move |w| (d, w)))
        .collect();
    pool(threads).map_err(WriteFleetError::Fleet)?.install(|| {
        jobs.par_iter().try_for_each(|&(d, w)| {
            let bytes = device_week(spec, &truths[d], w).map_err(WriteFleetError::Core)?;
            let path = states.join(file_name(d, w));
            crate::io::write_atomic(&path, bytes).map_err(io(&path))
        })
    })?;
    write_truth(&truths, truth_csv)?;
    Ok(truths)
}

/// `truth.csv`: `device,week,wearing,gap,damage`, one row per checkpoint.
fn write_truth(truths: &[DeviceTruth], path: &Path) -> Result<(), WriteFleetError> {
    let mut text = String::from("device,week,wearing,gap,damage\n");
    for t in truths {
        for (w, g) in t.gaps.iter().enumerate() {
            let damage = match t.damaged {
                Some((dw, d)) if dw == w => d,
                _ => Damage::None,
            };
            text.push_str(&format!(
                "{},{w},{},{g},{}\n",
                file_name(t.index, w),
                t.wearing,
                damage.name()
            ));
        }
    }
    crate::io::write_atomic(path, text).map_err(io(path))
}
