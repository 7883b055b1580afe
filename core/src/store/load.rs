//! Loading the newest valid checkpoint.

use super::error::{Fault, Slot, StoreError};
use super::flash::Flash;
use super::inspect::newest;
use super::two_slots::Store;
use crate::checkpoint::crc32;

/// What [`Store::load`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Loaded {
    /// Bytes of the checkpoint, at the start of the buffer.
    pub len: usize,
    /// Its sequence number.
    pub sequence: u32,
    /// The slot it came from (0 or 1).
    pub slot: usize,
    /// What the other slot holds: the previous checkpoint ([`Slot::Valid`]), nothing, or a
    /// damaged or interrupted one ([`Slot::Corrupt`]) that the next save overwrites.
    pub other: Slot,
}

impl<F: Flash> Store<F> {
    /// Copies the newest valid checkpoint into the start of `buf` (size it with the
    /// identifier type's
    /// [`CHECKPOINT_CAPACITY`](crate::Identifier::CHECKPOINT_CAPACITY)).
    ///
    /// A slot whose checksums fail is skipped, and reported in [`Loaded::other`] or in
    /// [`StoreError::NoCheckpoint`]; the payload is checked again once in `buf`.
    pub fn load(&mut self, buf: &mut [u8]) -> Result<Loaded, StoreError<F::Error>> {
        let found = self.inspect_both()?;
        let mut slots = [found[0].slot, found[1].slot];
        // At most two candidates: a slot that fails the second check is marked corrupt.
        for _ in 0..2 {
            let Some((index, sequence, len)) = newest(&slots) else {
                break;
            };
            let have = buf.len();
            let dst = buf
                .get_mut(..len)
                .ok_or(StoreError::BufferTooSmall { need: len, have })?;
            let at = self.geometry.start(index) + self.geometry.header;
            self.flash.read(at, dst).map_err(StoreError::Flash)?;
            let expected = found[index & 1].crc;
            if crc32(dst) == expected {
                return Ok(Loaded {
                    len,
                    sequence,
                    slot: index,
                    other: slots[(index + 1) & 1],
                });
            }
            slots[index & 1] = Slot::Corrupt(Fault::PayloadChecksum);
        }
        Err(StoreError::NoCheckpoint { slots })
    }
}
