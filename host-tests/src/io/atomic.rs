//! Outputs that are whole or untouched: every file hsid writes goes to a temporary file in the
//! same folder, is flushed to the disk and only then renamed over the path. A full disk, a
//! second writer, a signal or a reader that goes away leaves the previous file as it was, or
//! no file, never a part of one.
//!
//! A path that already names something other than a regular file (`/dev/null`, a FIFO, a
//! terminal) cannot be replaced by a rename: it is written in place. A symbolic link is
//! followed, so the file it names is replaced and the link kept.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use super::partial::Partial;

/// Where the bytes for `path` go before they are complete.
enum Target {
    /// A temporary file beside the destination, renamed over it by [`AtomicFile::commit`].
    Staged(BufWriter<NamedTempFile>),
    /// A destination that is not a regular file, written in place.
    InPlace(BufWriter<fs::File>),
}

/// A file written whole or not at all: write to it, then [`commit`](Self::commit). Dropped
/// without a commit (an error, a panic), the temporary file is removed and the destination
/// is untouched.
pub struct AtomicFile {
    target: Target,
    path: PathBuf,
    /// The temporary's registration, so that a signal removes it ([`super::abandon`]).
    partial: Option<Partial>,
}

/// The destination `path` resolved through a symbolic link, and whether it is something other
/// than a regular file already (a device, a FIFO); a folder is refused.
fn destination(path: &Path) -> io::Result<(PathBuf, bool)> {
    let path = match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => fs::canonicalize(path)?,
        _ => path.to_path_buf(),
    };
    match fs::metadata(&path) {
        Ok(m) if m.is_dir() => Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "is a folder, not a file",
        )),
        Ok(m) => Ok((path, !m.is_file())),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok((path, false)),
        Err(e) => Err(e),
    }
}

impl AtomicFile {
    /// Starts the file that will replace `path` (created in `path`'s folder, which must exist).
    pub fn create(path: impl AsRef<Path>) -> io::Result<Self> {
        let (path, special) = destination(path.as_ref())?;
        let (target, partial) = match special {
            true => (
                Target::InPlace(BufWriter::new(
                    fs::OpenOptions::new().write(true).open(&path)?,
                )),
                None,
            ),
            false => {
                let dir = match path.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d,
                    _ => Path::new("."),
                };
                let mut builder = tempfile::Builder::new();
                builder.prefix(".hsid-").suffix(".partial");
                #[cfg(unix)]
                {
                    use std::os::unix::fs::PermissionsExt;
                    // As `File::create` would make it (the umask applies).
                    builder.permissions(fs::Permissions::from_mode(0o666));
                }
                let (file, partial) =
                    Partial::create(|| builder.tempfile_in(dir), NamedTempFile::path)?;
                (Target::Staged(BufWriter::new(file)), Some(partial))
            }
        };
        Ok(Self {
            target,
            path,
            partial,
        })
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the bytes to the disk and renames the file over the destination.
    pub fn commit(self) -> io::Result<()> {
        let Self {
            target,
            path,
            partial,
        } = self;
        match target {
            Target::InPlace(w) => {
                w.into_inner().map_err(io::IntoInnerError::into_error)?;
                Ok(())
            }
            Target::Staged(w) => {
                let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
                file.as_file().sync_all()?;
                let persist = || file.persist(&path).map(drop).map_err(|e| e.error);
                match partial {
                    Some(partial) => partial.finish(persist)?,
                    None => persist()?,
                }
                // The rename itself reaches the disk with the folder's entry.
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    let _ = fs::File::open(dir).and_then(|d| d.sync_all());
                }
                Ok(())
            }
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.target {
            Target::Staged(w) => w.write(buf),
            Target::InPlace(w) => w.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.target {
            Target::Staged(w) => w.flush(),
            Target::InPlace(w) => w.flush(),
        }
    }
}

/// Writes `bytes` to `path` whole or not at all ([`AtomicFile`]): the replacement for
/// [`std::fs::write`] for every output.
pub fn write_atomic(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes.as_ref())?;
    file.commit()
}

/// Files for one folder written together: each is written into a staging folder inside it
/// ([`path`](Self::path)), and [`commit`](Self::commit) moves them into place one rename each
/// once all are written. A run that fails or is stopped before then leaves the folder's
/// previous files as they were (a failed run removes the staging folder; a killed one leaves
/// it, hidden, as `.hsid-staging-…`).
pub struct StagedDir {
    dir: PathBuf,
    stage: tempfile::TempDir,
    /// The staging folder's registration, so that a signal removes it ([`super::abandon`]).
    partial: Partial,
}

impl StagedDir {
    /// Stages files for `dir` (created if missing).
    pub fn create(dir: impl AsRef<Path>) -> io::Result<Self> {
        let dir = dir.as_ref().to_path_buf();
        fs::create_dir_all(&dir)?;
        let (stage, partial) = Partial::create(
            || {
                tempfile::Builder::new()
                    .prefix(".hsid-staging-")
                    .tempdir_in(&dir)
            },
            tempfile::TempDir::path,
        )?;
        Ok(Self {
            dir,
            stage,
            partial,
        })
    }

    /// The folder to write the files into.
    pub fn path(&self) -> &Path {
        self.stage.path()
    }

    /// Moves `files` (paths inside [`path`](Self::path), as the writer returned them) into
    /// the folder and gives their paths there; the staging folder is removed. A destination that is a folder is refused before anything is moved.
    pub fn commit(self, files: &[PathBuf]) -> io::Result<Vec<PathBuf>> {
        let moves: Vec<(&PathBuf, Option<PathBuf>)> = files
            .iter()
            .map(|f| {
                (
                    f,
                    f.strip_prefix(self.stage.path())
                        .ok()
                        .map(|r| self.dir.join(r)),
                )
            })
            .collect();
        for to in moves.iter().filter_map(|(_, to)| to.as_ref()) {
            if to.is_dir() {
                return Err(io::Error::new(
                    io::ErrorKind::IsADirectory,
                    format!("{} is a folder: no figure was replaced", to.display()),
                ));
            }
            if let Some(parent) = to.parent() {
                fs::create_dir_all(parent)?;
            }
        }
        let Self {
            dir,
            stage,
            partial,
        } = self;
        // The renames and the removal of the staging folder under the registry's lock: a
        // signal meanwhile waits for them, so the folder is never left half replaced.
        let placed = partial.finish(|| -> io::Result<Vec<PathBuf>> {
            let mut placed = Vec::with_capacity(files.len());
            for (file, to) in moves {
                match to {
                    Some(to) => {
                        fs::rename(file, &to)?;
                        placed.push(to);
                    }
                    None => placed.push(file.clone()),
                }
            }
            stage.close()?;
            Ok(placed)
        })?;
        if let Ok(d) = fs::File::open(&dir) {
            let _ = d.sync_all();
        }
        Ok(placed)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hsid-atomic-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn an_uncommitted_file_leaves_the_old_one_and_no_temporary() {
        let dir = scratch("drop");
        let path = dir.join("m.json");
        fs::write(&path, "old").unwrap();
        {
            let mut f = AtomicFile::create(&path).unwrap();
            f.write_all(b"new, half").unwrap();
            f.flush().unwrap();
            assert_eq!(entries(&dir).len(), 2, "the temporary sits beside it");
        }
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(entries(&dir), vec!["m.json".to_string()]);
        write_atomic(&path, "new").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(entries(&dir), vec!["m.json".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_kept_and_a_device_written_in_place() {
        let dir = scratch("link");
        let real = dir.join("real.json");
        fs::write(&real, "old").unwrap();
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomic(&link, "new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read_to_string(&real).unwrap(), "new");
        write_atomic("/dev/null", "discarded").unwrap();
        assert!(!fs::metadata("/dev/null").unwrap().is_file());
        let e = write_atomic(&dir, "x").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::IsADirectory);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_staged_folder_keeps_its_old_files_until_the_commit() {
        let dir = scratch("staged");
        fs::write(dir.join("a.svg"), "old a").unwrap();
        fs::write(dir.join("b.svg"), "old b").unwrap();
        {
            let stage = StagedDir::create(&dir).unwrap();
            write_atomic(stage.path().join("a.svg"), "new a").unwrap();
            // Stopped here (an error): nothing of the new run is left.
        }
        assert_eq!(
            entries(&dir),
            vec!["a.svg".to_string(), "b.svg".to_string()]
        );
        assert_eq!(fs::read_to_string(dir.join("a.svg")).unwrap(), "old a");
        let stage = StagedDir::create(&dir).unwrap();
        let files = ["a.svg", "b.svg"].map(|n| stage.path().join(n));
        for f in &files {
            write_atomic(f, "new").unwrap();
        }
        assert_eq!(fs::read_to_string(dir.join("b.svg")).unwrap(), "old b");
        let placed = stage.commit(&files).unwrap();
        assert_eq!(placed, vec![dir.join("a.svg"), dir.join("b.svg")]);
        assert_eq!(
            entries(&dir),
            vec!["a.svg".to_string(), "b.svg".to_string()]
        );
        assert_eq!(fs::read_to_string(dir.join("b.svg")).unwrap(), "new");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_gets_the_permissions_of_a_created_one() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("mode");
        let plain = dir.join("plain");
        fs::write(&plain, "x").unwrap();
        let atomic = dir.join("atomic");
        write_atomic(&atomic, "x").unwrap();
        let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&atomic), mode(&plain));
        fs::remove_dir_all(&dir).unwrap();
    }
}
