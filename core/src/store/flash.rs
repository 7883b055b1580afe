//! The flash a board gives the store: erase a page, program bytes, read bytes.

use core::fmt::Debug;

/// Largest program unit ([`Flash::WRITE`]) the store supports, in bytes.
pub const MAX_WRITE: usize = 256;

/// A NOR-flash region as a board exposes it, addressed in bytes from its start.
///
/// The store relies on the rules real parts impose and nothing more:
///
/// - an erase sets a whole page ([`PAGE`](Self::PAGE) bytes) to `0xFF`;
/// - a write programs whole units of [`WRITE`](Self::WRITE) bytes at an offset that is a
///   multiple of `WRITE`, and can only turn 1-bits into 0-bits, so a unit is written once
///   between erases (parts with ECC refuse a second write; the store never asks for one);
/// - writes and erases take effect in the order they are issued; a power loss can leave the
///   operation in progress partly done (a torn write or erase), never an earlier one undone.
///
/// [`RamFlash`](super::ram::RamFlash) implements it in RAM, with simulated power cuts.
pub trait Flash {
    /// Erase unit in bytes (a multiple of [`WRITE`](Self::WRITE)).
    const PAGE: usize;
    /// Program unit in bytes (a power of two up to [`MAX_WRITE`], e.g. 8 on parts that program
    /// double words).
    const WRITE: usize;
    /// What the board's driver reports when an operation fails.
    type Error: Copy + Debug;

    /// Erases page `page` (bytes `page * PAGE .. (page + 1) * PAGE`) to `0xFF`.
    fn erase(&mut self, page: usize) -> Result<(), Self::Error>;

    /// Programs `data` at `offset`; `offset` and `data.len()` are multiples of
    /// [`WRITE`](Self::WRITE) and the bytes were erased since they were last written.
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error>;

    /// Reads `buf.len()` bytes from `offset` (any offset and length).
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error>;
}

/// A flash borrowed: a store can work on a board's flash it does not own.
impl<F: Flash> Flash for &mut F {
    const PAGE: usize = F::PAGE;
    const WRITE: usize = F::WRITE;
    type Error = F::Error;

    fn erase(&mut self, page: usize) -> Result<(), Self::Error> {
        (**self).erase(page)
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error> {
        (**self).write(offset, data)
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error> {
        (**self).read(offset, buf)
    }
}
