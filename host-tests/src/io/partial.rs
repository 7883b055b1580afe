//! The outputs this process has in progress (the temporary files of [`AtomicFile`] and the
//! staging folders of [`StagedDir`]), so that a run stopped by a signal removes them instead
//! of leaving `.hsid-*.partial` files and `.hsid-staging-*` folders behind.
//!
//! A temporary is registered while it is created and forgotten while it is renamed into place,
//! both under one lock; [`abandon`] takes that lock, removes what is registered and keeps the
//! lock, so that no output starts or finishes after it. A file is thus either in place whole
//! (its rename came first) or gone with its temporary (the removal came first), never half
//! written.
//!
//! [`AtomicFile`]: super::AtomicFile
//! [`StagedDir`]: super::StagedDir

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The registered temporaries: files and staging folders.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    // A thread that panicked while holding the lock left the list as it was between two
    // whole operations (a push or a retain): it is still right.
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// One registered temporary; dropped, it is forgotten (its owner removes it).
pub(crate) struct Partial {
    path: Option<PathBuf>,
}

impl Partial {
    /// Creates a temporary with `make` and registers the path `path_of` gives, both under the
    /// lock, so that [`abandon`] sees it as soon as it exists.
    pub(crate) fn create<T>(
        make: impl FnOnce() -> io::Result<T>,
        path_of: impl FnOnce(&T) -> &Path,
    ) -> io::Result<(T, Self)> {
        let mut list = live();
        let made = make()?;
        let path = path_of(&made).to_path_buf();
        list.push(path.clone());
        Ok((made, Self { path: Some(path) }))
    }

    /// Runs `finish` (the renames into place) under the lock, then forgets the temporary.
    pub(crate) fn finish<R>(mut self, finish: impl FnOnce() -> R) -> R {
        let mut list = live();
        let out = finish();
        if let Some(path) = self.path.take() {
            list.retain(|p| *p != path);
        }
        out
    }
}

impl Drop for Partial {
    fn drop(&mut self) {
        if let Some(path) = self.path.take() {
            live().retain(|p| *p != path);
        }
    }
}

/// Removes every temporary file and staging folder of the outputs in progress and keeps every
/// other output from starting or finishing until the process ends: for a signal handler that
/// exits the process next. Returns how many were removed.
pub fn abandon() -> usize {
    let list = live();
    let n = list.len();
    for path in list.iter() {
        let _ = match fs::symlink_metadata(path) {
            Ok(m) if m.is_dir() => fs::remove_dir_all(path),
            Ok(_) => fs::remove_file(path),
            Err(_) => Ok(()),
        };
    }
    // The lock stays taken: an output that would start or be renamed into place now waits
    // for the exit.
    std::mem::forget(list);
    n
}

/// How many temporaries are registered now (for tests).
pub fn in_progress() -> usize {
    live().len()
}
