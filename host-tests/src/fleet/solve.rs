//! Many checkpoints solved across cores (rayon): one [`DeviceResult`] per device, in the order
//! given, whatever fails.

use std::path::{Path, PathBuf};

use hsid::compensated_checkpoint_capacity;

use rayon::prelude::*;

use super::device::{DeviceError, DeviceResult};
use crate::identify::{CheckpointSolve, MAX_BLOCK_ROWS, MAX_CHANNELS, solve_checkpoint};
use crate::io::{LimitedReadError, open_regular, read_limited};

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
#[derive(Debug, thiserror::Error)]
pub enum FleetError {
    /// Zero threads were asked for.
    #[error("threads = 0: give at least one thread")]
    ZeroThreads,
    /// More threads than [`MAX_THREADS`] were asked for.
    #[error(
        "threads = {0}: at most {MAX_THREADS} worker threads are started (give the cores to use)"
    )]
    TooManyThreads(usize),
    /// The thread pool could not be built (the operating system's reason).
    #[error("cannot start the worker threads: {0}")]
    Pool(String),
    /// A result could not be handed on (writing the output failed; the I/O error's text).
    #[error("cannot write the results: {0}")]
    Output(String),
    /// The directory of checkpoints could not be listed.
    #[error("{dir}: cannot list the checkpoints: {error}")]
    Directory {
        /// The directory.
        dir: String,
        /// The I/O error's text.
        error: String,
    },
}

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

/// The most worker threads a batch starts: each holds a checkpoint and its solve, and a
/// thread per core is the fastest.
pub const MAX_THREADS: usize = 512;

/// A pool of `threads` workers (`None`: rayon's default, one per core); more than
/// [`MAX_THREADS`] are refused before any starts.
pub(crate) fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool, FleetError> {
    let mut b = rayon::ThreadPoolBuilder::new();
    match threads {
        Some(0) => return Err(FleetError::ZeroThreads),
        Some(n) if n > MAX_THREADS => return Err(FleetError::TooManyThreads(n)),
        Some(n) => b = b.num_threads(n),
        None => {}
    }
    b.build().map_err(|e| FleetError::Pool(e.to_string()))
}

/// A directory entry: the device id, and the file's path or why it cannot be read.
pub(crate) type Entry = (String, Result<PathBuf, DeviceError>);

/// A directory's checkpoints as listed: its files, and the entries that are no device.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Listing {
    /// The files, sorted by file name (the device id, [`device_id`]); an entry that cannot
    /// be listed is that device's error (named `entry N`).
    pub files: Vec<Entry>,
    /// The subdirectories (by [`device_id`], sorted): a fleet's checkpoints are the files of
    /// the directory itself, so these are not searched, and the caller says so.
    pub skipped: Vec<String>,
}

/// The device id of a file name: the name itself when it is UTF-8, else the name with each
/// byte that is not part of a UTF-8 character written as `\xNN` (and each backslash as
/// `\\`): two such names that differ show differently, where a lossy conversion would show
/// both as the same `dev�.bin`.
pub fn device_id(name: &std::ffi::OsStr) -> String {
    if let Some(s) = name.to_str() {
        return s.to_owned();
    }
    escaped(name.as_encoded_bytes())
}

/// `bytes` (not UTF-8) as text: UTF-8 runs as they are (backslashes doubled), every other
/// byte as `\xNN`.
fn escaped(bytes: &[u8]) -> String {
    let mut out = String::new();
    for chunk in bytes.utf8_chunks() {
        out.push_str(&chunk.valid().replace('\\', "\\\\"));
        for b in chunk.invalid() {
            out.push_str(&format!("\\x{b:02X}"));
        }
    }
    out
}

/// The files of a directory, sorted by file name (the device id); an entry that cannot be
/// listed is that device's error (named `entry N`). Subdirectories are not searched: they are
/// listed in [`Listing::skipped`].
pub fn list_dir(dir: &Path) -> Result<Listing, FleetError> {
    let listing = std::fs::read_dir(dir).map_err(|e| FleetError::Directory {
        dir: dir.display().to_string(),
        error: e.to_string(),
    })?;
    let mut out = Listing::default();
    for (i, entry) in listing.enumerate() {
        match entry {
            Ok(entry) if entry.path().is_dir() => {
                out.skipped.push(device_id(&entry.file_name()));
            }
            Ok(entry) => out
                .files
                .push((device_id(&entry.file_name()), Ok(entry.path()))),
            Err(e) => out.files.push((
                format!("entry {i}"),
                Err(DeviceError::Unreadable(e.to_string())),
            )),
        }
    }
    out.files.sort_by(|a, b| a.0.cmp(&b.0));
    out.skipped.sort();
    Ok(out)
}

/// The largest checkpoint any capacity of the desktop front end can write (compensated sums,
/// which carry the plain checkpoint and more, in `f64` at the largest capacity): a larger file
/// is no checkpoint and is not read.
pub const MAX_CHECKPOINT_BYTES: usize =
    compensated_checkpoint_capacity(MAX_CHANNELS, MAX_BLOCK_ROWS, 8);

/// Checkpoints solved at once per worker thread: a chunk's results are handed on, in order,
/// before the next chunk is read, so memory holds the listing and at most this many results
/// per thread, whatever the size of the fleet.
const CHUNK_PER_THREAD: usize = 64;

/// A checkpoint file's bytes, read by the worker that solves it; a file larger than
/// [`MAX_CHECKPOINT_BYTES`] is refused unread (its size is checked before and while reading).
fn read_checkpoint(path: &Path) -> Result<Vec<u8>, DeviceError> {
    let unreadable = |e: std::io::Error| DeviceError::Unreadable(e.to_string());
    // Not a regular file (a FIFO would block the batch, a device never ends): refused unopened.
    let (file, len) = open_regular(path).map_err(unreadable)?;
    let limit = MAX_CHECKPOINT_BYTES as u64;
    read_limited(path, file, Some(len), limit).map_err(|e| match e {
        // A file that grew past the limit while it was read: the bytes read, `limit + 1`.
        LimitedReadError::TooLarge(t) => DeviceError::FileTooLarge {
            bytes: t.bytes.unwrap_or(limit + 1),
            limit: MAX_CHECKPOINT_BYTES,
        },
        LimitedReadError::File(e) => unreadable(e.source),
    })
}

/// How many devices a batch solved, how many of them have an error instead of a model, and
/// the entries of the directory that are no device.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FleetCount {
    /// Devices (files of the directory, and entries that could not be listed).
    pub devices: usize,
    /// Devices with an error.
    pub failed: usize,
    /// The subdirectories, not searched ([`Listing::skipped`]).
    pub skipped: Vec<String>,
}

/// Solves every checkpoint file of `dir` ([`list_dir`]; its subdirectories are not searched,
/// [`FleetCount::skipped`] names them) on `threads` workers and hands each
/// device's result to `each`, in the listing's order, as its chunk completes. Each file is
/// read by the worker that solves it, and only a chunk's results are held at once: memory is
/// the listing plus a bounded number of checkpoints and models, whatever the fleet's size. A
/// file that cannot be read, or is larger than any checkpoint, is that device's error; an error
/// of `each` (writing the results) stops the batch.
pub fn solve_dir_each(
    dir: &Path,
    fleet: Option<&FleetSettings>,
    threads: Option<usize>,
    each: &mut dyn FnMut(DeviceResult) -> std::io::Result<()>,
) -> Result<FleetCount, FleetError> {
    let Listing { files, skipped } = list_dir(dir)?;
    let pool = pool(threads)?;
    let chunk = CHUNK_PER_THREAD * pool.current_num_threads().max(1);
    let mut count = FleetCount {
        skipped,
        ..FleetCount::default()
    };
    for part in files.chunks(chunk) {
        let results: Vec<DeviceResult> = pool.install(|| {
            part.par_iter()
                .map(|(device, path)| {
                    match path
                        .as_ref()
                        .map_err(Clone::clone)
                        .and_then(|p| read_checkpoint(p))
                    {
                        Ok(bytes) => solve_one(device, &bytes, fleet),
                        Err(e) => DeviceResult {
                            device: device.clone(),
                            outcome: Err(e),
                        },
                    }
                })
                .collect()
        });
        for r in results {
            count.devices += 1;
            count.failed += usize::from(r.outcome.is_err());
            each(r).map_err(|e| FleetError::Output(e.to_string()))?;
        }
    }
    Ok(count)
}

/// [`solve_dir_each`], every result collected in a vector (memory grows with the fleet: for
/// a large fleet, hand the results on with [`solve_dir_each`]).
pub fn solve_dir(
    dir: &Path,
    fleet: Option<&FleetSettings>,
    threads: Option<usize>,
) -> Result<Vec<DeviceResult>, FleetError> {
    let mut out = Vec::new();
    solve_dir_each(dir, fleet, threads, &mut |r| {
        out.push(r);
        Ok(())
    })?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_that_is_not_utf8_shows_its_bytes() {
        assert_eq!(escaped(b"dev\xff.bin"), "dev\\xFF.bin");
        assert_eq!(escaped(b"dev\xfe.bin"), "dev\\xFE.bin");
        assert_eq!(escaped(b"a\\b\xc3"), "a\\\\b\\xC3");
        assert_eq!(device_id(std::ffi::OsStr::new("dev1.bin")), "dev1.bin");
    }
}
