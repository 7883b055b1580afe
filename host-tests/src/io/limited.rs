//! Reading a whole file that is known to be small, refusing it before it is read when it is
//! not: a file whose size exceeds a limit gives a [`TooLarge`] naming its size and the limit,
//! and nothing beyond `limit + 1` bytes is ever read (a pipe or a growing file included).

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::FileError;

/// A file larger than what its reader accepts.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {} the {limit} bytes accepted", size_text(*.bytes))]
pub struct TooLarge {
    /// The file.
    pub path: PathBuf,
    /// Its size in bytes, when the file system reports it (a regular file); otherwise more
    /// than `limit`.
    pub bytes: Option<u64>,
    /// The largest size accepted, in bytes.
    pub limit: u64,
}

/// `1234 bytes, larger than` a limit, or `more than` it when the size is unknown.
fn size_text(bytes: Option<u64>) -> String {
    match bytes {
        Some(b) => format!("{b} bytes, larger than"),
        None => "more than".to_owned(),
    }
}

/// Why [`read_to_string_limited`] failed.
#[derive(Debug, thiserror::Error)]
pub enum LimitedReadError {
    /// The file could not be opened or read, or is not UTF-8.
    #[error(transparent)]
    File(FileError),
    /// The file is larger than the limit; nothing of it was kept.
    #[error(transparent)]
    TooLarge(TooLarge),
}

/// [`read_to_string_limited`] with its failure as one I/O error, for readers whose error
/// keeps the path beside an I/O cause: a file larger than `limit` is
/// [`FileTooLarge`](std::io::ErrorKind::FileTooLarge), saying its size and the limit.
pub fn read_text_bounded(path: &Path, limit: u64) -> Result<String, std::io::Error> {
    read_to_string_limited(path, limit).map_err(|e| match e {
        LimitedReadError::File(f) => f.source,
        LimitedReadError::TooLarge(t) => std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("{} the {} bytes accepted", size_text(t.bytes), t.limit),
        ),
    })
}

/// `path` opened for reading if it is a regular file (through a symbolic link); a folder, a
/// FIFO, a socket or a device is refused before it is opened (opening a FIFO would wait for a
/// writer; a device such as `/dev/zero` never ends), with an error that says what it is.
pub fn open_regular(path: &Path) -> std::io::Result<(fs::File, u64)> {
    let meta = fs::metadata(path)?;
    if !meta.is_file() {
        #[cfg(unix)]
        let what = {
            use std::os::unix::fs::FileTypeExt;
            let t = meta.file_type();
            match () {
                _ if t.is_dir() => "a folder",
                _ if t.is_fifo() => "a FIFO (named pipe)",
                _ if t.is_socket() => "a socket",
                _ if t.is_char_device() || t.is_block_device() => "a device",
                _ => "not a regular file",
            }
        };
        #[cfg(not(unix))]
        let what = match meta.is_dir() {
            true => "a folder",
            false => "not a regular file",
        };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("it is {what}: give the path of a file"),
        ));
    }
    let file = fs::File::open(path)?;
    let len = file.metadata()?.len();
    Ok((file, len))
}

/// The bytes of the regular file `path` ([`open_regular`]) if it holds at most `limit` bytes,
/// checked before reading (from the file's size) and again while reading: memory stays within
/// `limit + 1` bytes whatever the file is.
pub fn read_file_limited(path: &Path, limit: u64) -> Result<Vec<u8>, LimitedReadError> {
    let (file, len) =
        open_regular(path).map_err(|e| LimitedReadError::File(FileError::read(path, e)))?;
    read_limited(path, file, Some(len), limit)
}

/// The whole text of the regular file `path` ([`open_regular`]) if it holds at most `limit`
/// bytes. The size is checked before reading (from the file's metadata) and again while
/// reading, so memory stays within `limit + 1` bytes whatever the file is.
pub fn read_to_string_limited(path: &Path, limit: u64) -> Result<String, LimitedReadError> {
    let read_err = |e| LimitedReadError::File(FileError::read(path, e));
    let bytes = read_file_limited(path, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        read_err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not valid UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ),
        ))
    })
}

/// All bytes of `reader` if they are at most `limit`; `size` is what the file system reports
/// for a regular file (`None` for a pipe), checked before anything is read. `path` names the
/// source in errors. Memory stays within `limit + 1` bytes whatever the reader gives.
pub fn read_limited<R: Read>(
    path: &Path,
    reader: R,
    size: Option<u64>,
    limit: u64,
) -> Result<Vec<u8>, LimitedReadError> {
    let too_large = |bytes| {
        LimitedReadError::TooLarge(TooLarge {
            path: path.to_path_buf(),
            bytes,
            limit,
        })
    };
    if let Some(size) = size.filter(|&s| s > limit) {
        return Err(too_large(Some(size)));
    }
    // A regular file's size, when it is within the limit, is the capacity: the text is read
    // into one block of its size (a file that grows meanwhile still stops at the limit).
    let mut bytes =
        Vec::with_capacity(size.map_or(0, |s| usize::try_from(s.saturating_add(1)).unwrap_or(0)));
    reader
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| LimitedReadError::File(FileError::read(path, e)))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(None));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use super::*;

    fn temp(name: &str, bytes: &[u8]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hsid-limited-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        fs::write(&path, bytes).unwrap();
        path
    }

    #[test]
    fn a_file_at_the_limit_is_read_one_byte_more_is_refused_with_its_size() {
        let at = temp("at.txt", &[b'x'; 100]);
        assert_eq!(read_to_string_limited(&at, 100).unwrap().len(), 100);
        let over = temp("over.txt", &[b'x'; 101]);
        match read_to_string_limited(&over, 100) {
            Err(LimitedReadError::TooLarge(e)) => {
                assert_eq!((e.bytes, e.limit), (Some(101), 100));
                assert!(
                    e.to_string()
                        .ends_with("101 bytes, larger than the 100 bytes accepted")
                );
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
    }

    #[test]
    fn a_reader_without_a_size_is_cut_one_byte_past_the_limit() {
        let path = Path::new("pipe");
        let at = read_limited(path, &[b'x'; 100][..], None, 100).unwrap();
        assert_eq!(at.len(), 100);
        match read_limited(path, &[b'x'; 5000][..], None, 100) {
            Err(LimitedReadError::TooLarge(e)) => {
                assert_eq!((e.bytes, e.limit), (None, 100));
                assert_eq!(e.to_string(), "pipe: more than the 100 bytes accepted");
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
        // A size the file system reports is refused before anything is read.
        match read_limited(path, std::io::empty(), Some(101), 100) {
            Err(LimitedReadError::TooLarge(e)) => assert_eq!(e.bytes, Some(101)),
            other => panic!("expected TooLarge, got {other:?}"),
        }
    }
}
