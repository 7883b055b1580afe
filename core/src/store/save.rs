//! Saving a checkpoint into the slot that does not hold the newest one.

use super::error::{Slot, StoreError};
use super::flash::{Flash, MAX_WRITE};
use super::inspect::newest;
use super::layout::Header;
use super::two_slots::Store;
use crate::checkpoint::crc32;

/// Where [`Store::save`] put a checkpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Saved {
    /// The slot written (0 or 1).
    pub slot: usize,
    /// Its sequence number: the previous newest one plus 1 (wrapping), or 0 on an empty
    /// store.
    pub sequence: u32,
}

impl<F: Flash> Store<F> {
    /// Saves `payload` (e.g. the bytes of [`Identifier::save`](crate::Identifier::save)) as
    /// the newest checkpoint.
    ///
    /// It goes into the slot not holding the newest valid checkpoint: that slot's pages are
    /// erased (the header's first), the payload programmed, then the header, and the slot read
    /// back. If power fails at any point, [`load`](Self::load) returns the previous newest
    /// checkpoint (or this one if its header was complete). Errors: [`StoreError::TooLarge`],
    /// the flash's own ([`StoreError::Flash`]), or [`StoreError::Verify`] if the written slot
    /// does not read back valid.
    pub fn save(&mut self, payload: &[u8]) -> Result<Saved, StoreError<F::Error>> {
        let capacity = self.capacity();
        let len = payload.len();
        let too_large = StoreError::TooLarge { len, capacity };
        let len32 = u32::try_from(len).map_err(|_| too_large)?;
        if len > capacity {
            return Err(too_large);
        }
        let (slot, sequence) = match newest(&self.slots()?) {
            Some((index, sequence, _)) => ((index + 1) & 1, sequence.wrapping_add(1)),
            None => (0, 0),
        };
        self.erase_slot(slot)?;
        let start = self.geometry.start(slot);
        self.program(start + self.geometry.header, payload)?;
        let header = Header {
            sequence,
            len: len32,
            crc: crc32(payload),
        };
        self.program(start, &header.encode())?;
        let found = self.inspect(slot)?.slot;
        if found != (Slot::Valid { sequence, len }) {
            return Err(StoreError::Verify { found });
        }
        Ok(Saved { slot, sequence })
    }

    /// Erases the pages of slot `index`, its first page (the header's) first.
    fn erase_slot(&mut self, index: usize) -> Result<(), StoreError<F::Error>> {
        let first = self.geometry.first_page[index & 1];
        for page in first..first + self.geometry.pages {
            self.flash.erase(page).map_err(StoreError::Flash)?;
        }
        Ok(())
    }

    /// Programs `data` at `at` (a multiple of the program unit): whole units straight from
    /// `data`, the last partial unit padded with `0xFF`.
    fn program(&mut self, at: usize, data: &[u8]) -> Result<(), StoreError<F::Error>> {
        let unit = F::WRITE;
        let whole = data.len() / unit * unit;
        let (body, tail) = data.split_at_checked(whole).unwrap_or((data, &[]));
        if !body.is_empty() {
            self.flash.write(at, body).map_err(StoreError::Flash)?;
        }
        if !tail.is_empty() {
            let mut last = [0xFFu8; MAX_WRITE];
            if let Some(dst) = last.get_mut(..tail.len()) {
                dst.copy_from_slice(tail);
            }
            let last = last.get(..unit).unwrap_or(&[]);
            self.flash
                .write(at + whole, last)
                .map_err(StoreError::Flash)?;
        }
        Ok(())
    }
}
