//! Writing a file on the host through semihosting (`SYS_OPEN`, `SYS_WRITE`, `SYS_CLOSE`).
//!
//! Under QEMU with `-semihosting-config enable=on,target=native` the file is created relative
//! to QEMU's working directory; under a debug probe (OpenOCD, probe-rs) relative to the
//! debugger's. The firmware uses it to export the identifier's checkpoint (`hsid-state.bin`),
//! which `hsid solve --state FILE` solves on the host. On a board without a debugger attached,
//! send the same bytes over a UART or keep them in flash instead (README.md).

use crate::board::{nr, syscall};

/// Why the host did not take the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HostFileError {
    /// The name is not NUL-terminated (a programming error).
    Name,
    /// The host refused to open (create) the file.
    Open,
    /// The host accepted only part of the bytes.
    Write,
    /// Closing failed (the data may not be flushed).
    Close,
}

impl HostFileError {
    /// A short description for the `HSID` output.
    pub fn as_str(self) -> &'static str {
        match self {
            HostFileError::Name => "file name not NUL-terminated",
            HostFileError::Open => {
                "the host refused to create the file (semihosting file access off?)"
            }
            HostFileError::Write => "the host did not take all the bytes",
            HostFileError::Close => "the host failed to close the file",
        }
    }
}

/// Creates (or truncates) the host file `name` (NUL-terminated, e.g. `b"hsid-state.bin\0"`)
/// and writes `bytes` into it, in binary mode.
pub fn write(name: &[u8], bytes: &[u8]) -> Result<(), HostFileError> {
    let len = match name.split_last() {
        Some((0, rest)) if !rest.contains(&0) => rest.len(),
        _ => return Err(HostFileError::Name),
    };
    // SAFETY: SYS_OPEN reads `len` bytes of the name (plus its NUL) from the pointer; `name` is a
    // live, NUL-terminated slice for the whole call.
    let fd = unsafe { syscall!(OPEN, name.as_ptr(), nr::open::W_TRUNC_BINARY, len) };
    if fd as isize == -1 {
        return Err(HostFileError::Open);
    }
    // SAFETY: SYS_WRITE reads `bytes.len()` bytes from the pointer; `bytes` is a live slice for
    // the whole call. It returns the number of bytes *not* written.
    let left = unsafe { syscall!(WRITE, fd, bytes.as_ptr(), bytes.len()) };
    // SAFETY: SYS_CLOSE only takes the handle SYS_OPEN returned.
    let closed = unsafe { syscall!(CLOSE, fd) };
    if left != 0 {
        return Err(HostFileError::Write);
    }
    if closed != 0 {
        return Err(HostFileError::Close);
    }
    Ok(())
}
