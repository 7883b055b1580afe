//! Many checkpoints solved across cores (rayon): one [`DeviceResult`] per device, in the order
//! given, whatever fails.

use std::fmt;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::device::{DeviceError, DeviceResult};
use crate::identify::{CheckpointSolve, solve_checkpoint};

/// The settings every checkpoint of a fleet must have been written with: knots and horizons.
/// A checkpoint with others is reported as [`DeviceError::ForeignSettings`].
#[derive(Clone, Debug, PartialEq)]
pub struct FleetSettings {
    /// Ascending-path knots, as the checkpoints store them (widened to `f64`).
    pub knots_asc: Vec<f64>,
    /// Descending-path knots.
    pub knots_desc: Vec<f64>,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
}

impl FleetSettings {
    /// The settings of a solved reference checkpoint (a device known to be of the fleet).
    pub fn of(reference: &CheckpointSolve) -> Self {
        let m = &reference.model;
        Self {
            knots_asc: m.knots_asc.clone(),
            knots_desc: m.knots_desc.clone(),
            f: m.f,
            p: m.p,
        }
    }

    /// What differs between the fleet's settings and a solved checkpoint's, or `None`.
    fn difference(&self, solved: &CheckpointSolve) -> Option<String> {
        let m = &solved.model;
        if (m.f, m.p) != (self.f, self.p) {
            return Some(format!(
                "horizons f = {}, p = {} (fleet: f = {}, p = {})",
                m.f, m.p, self.f, self.p
            ));
        }
        if m.knots_asc != self.knots_asc || m.knots_desc != self.knots_desc {
            return Some(format!(
                "knots {:?} / {:?} (fleet: {:?} / {:?})",
                m.knots_asc, m.knots_desc, self.knots_asc, self.knots_desc
            ));
        }
        None
    }
}

/// One device's checkpoint, or why it could not be read.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// The device id.
    pub device: String,
    /// The checkpoint's bytes.
    pub bytes: Result<Vec<u8>, DeviceError>,
}

/// Why a batch could not start (a device's failure never stops it).
#[derive(Debug)]
pub enum FleetError {
    /// Zero threads were asked for.
    ZeroThreads,
    /// The thread pool could not be built (the operating system's reason).
    Pool(String),
    /// The directory of checkpoints could not be listed.
    Directory {
        /// The directory.
        dir: String,
        /// The I/O error's text.
        error: String,
    },
}

impl fmt::Display for FleetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FleetError::ZeroThreads => f.write_str("threads = 0: give at least one thread"),
            FleetError::Pool(e) => write!(f, "cannot start the worker threads: {e}"),
            FleetError::Directory { dir, error } => {
                write!(f, "{dir}: cannot list the checkpoints: {error}")
            }
        }
    }
}

impl std::error::Error for FleetError {}

/// Solves one device's checkpoint; with `fleet`, a checkpoint of other settings is refused.
pub fn solve_one(device: &str, bytes: &[u8], fleet: Option<&FleetSettings>) -> DeviceResult {
    let outcome = solve_checkpoint(bytes)
        .map_err(DeviceError::Solve)
        .and_then(|solved| match fleet.and_then(|s| s.difference(&solved)) {
            Some(what) => Err(DeviceError::ForeignSettings { what }),
            None => Ok(solved),
        });
    DeviceResult {
        device: device.to_owned(),
        outcome,
    }
}

/// Solves every checkpoint on `threads` worker threads (`None`: one per core), one result per
/// checkpoint in the order given.
pub fn solve_many(
    checkpoints: &[Checkpoint],
    fleet: Option<&FleetSettings>,
    threads: Option<usize>,
) -> Result<Vec<DeviceResult>, FleetError> {
    let pool = pool(threads)?;
    Ok(pool.install(|| {
        checkpoints
            .par_iter()
            .map(|c| match &c.bytes {
                Ok(bytes) => solve_one(&c.device, bytes, fleet),
                Err(e) => DeviceResult {
                    device: c.device.clone(),
                    outcome: Err(e.clone()),
                },
            })
            .collect()
    }))
}

/// A pool of `threads` workers (`None`: rayon's default, one per core).
pub fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool, FleetError> {
    let mut b = rayon::ThreadPoolBuilder::new();
    match threads {
        Some(0) => return Err(FleetError::ZeroThreads),
        Some(n) => b = b.num_threads(n),
        None => {}
    }
    b.build().map_err(|e| FleetError::Pool(e.to_string()))
}

/// A directory entry: the device id, and the file's path or why it cannot be read.
pub type Entry = (String, Result<PathBuf, DeviceError>);

/// The files of a directory, sorted by file name (the device id); an entry that cannot be
/// listed is that device's error (named `entry N`). Subdirectories are skipped.
pub fn list_dir(dir: &Path) -> Result<Vec<Entry>, FleetError> {
    let listing = std::fs::read_dir(dir).map_err(|e| FleetError::Directory {
        dir: dir.display().to_string(),
        error: e.to_string(),
    })?;
    let mut out = Vec::new();
    for (i, entry) in listing.enumerate() {
        match entry {
            Ok(entry) if entry.path().is_dir() => {}
            Ok(entry) => out.push((
                entry.file_name().to_string_lossy().into_owned(),
                Ok(entry.path()),
            )),
            Err(e) => out.push((
                format!("entry {i}"),
                Err(DeviceError::Unreadable(e.to_string())),
            )),
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(out)
}

/// Solves every checkpoint file of `dir` ([`list_dir`]) on `threads` workers, each file read
/// by the worker that solves it (a fleet's checkpoints need not fit in memory at once); a file
/// that cannot be read is that device's error.
pub fn solve_dir(
    dir: &Path,
    fleet: Option<&FleetSettings>,
    threads: Option<usize>,
) -> Result<Vec<DeviceResult>, FleetError> {
    let files = list_dir(dir)?;
    let pool = pool(threads)?;
    Ok(pool.install(|| {
        files
            .par_iter()
            .map(|(device, path)| {
                let bytes = path.as_ref().map_err(Clone::clone).and_then(|p| {
                    std::fs::read(p).map_err(|e| DeviceError::Unreadable(e.to_string()))
                });
                match bytes {
                    Ok(bytes) => solve_one(device, &bytes, fleet),
                    Err(e) => DeviceResult {
                        device: device.clone(),
                        outcome: Err(e),
                    },
                }
            })
            .collect()
    }))
}
