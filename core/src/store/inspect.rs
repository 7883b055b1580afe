//! Reading a slot back: is it unwritten, valid, or corrupt, and why.

use super::error::{Fault, Slot, StoreError};
use super::flash::Flash;
use super::layout::{HEADER_FIELDS, Header, Parsed, newer};
use super::two_slots::Store;
use crate::checkpoint::crc32_update;

/// Bytes read at a time to checksum a payload on the flash.
const CHUNK: usize = 64;

/// A slot's state and, when valid, the payload checksum its header holds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Found {
    pub slot: Slot,
    pub crc: u32,
}

impl<F: Flash> Store<F> {
    /// What each slot holds, checksums verified (reads both slots whole).
    pub fn slots(&mut self) -> Result<[Slot; 2], StoreError<F::Error>> {
        let [a, b] = self.inspect_both()?;
        Ok([a.slot, b.slot])
    }

    pub(super) fn inspect_both(&mut self) -> Result<[Found; 2], StoreError<F::Error>> {
        Ok([self.inspect(0)?, self.inspect(1)?])
    }

    /// Reads slot `index` (0 or 1): header, then the payload's checksum, streamed.
    pub(super) fn inspect(&mut self, index: usize) -> Result<Found, StoreError<F::Error>> {
        let corrupt = |fault| Found {
            slot: Slot::Corrupt(fault),
            crc: 0,
        };
        let start = self.geometry.start(index);
        let mut h = [0u8; HEADER_FIELDS];
        self.flash.read(start, &mut h).map_err(StoreError::Flash)?;
        let header = match Header::parse(&h) {
            Parsed::Erased => {
                return Ok(Found {
                    slot: Slot::Unwritten,
                    crc: 0,
                });
            }
            Parsed::Checksum => return Ok(corrupt(Fault::HeaderChecksum)),
            Parsed::Magic => return Ok(corrupt(Fault::Magic)),
            Parsed::Version => return Ok(corrupt(Fault::Version)),
            Parsed::Header(header) => header,
        };
        let len = header.len as usize;
        if len > self.geometry.capacity() {
            return Ok(corrupt(Fault::Length));
        }
        let mut crc = 0xFFFF_FFFF;
        let mut chunk = [0u8; CHUNK];
        let mut at = start + self.geometry.header;
        let end = at + len;
        while at < end {
            let n = CHUNK.min(end - at);
            let part = chunk.get_mut(..n).unwrap_or(&mut []);
            self.flash.read(at, part).map_err(StoreError::Flash)?;
            crc = crc32_update(crc, part);
            at += n;
        }
        if !crc != header.crc {
            return Ok(corrupt(Fault::PayloadChecksum));
        }
        Ok(Found {
            slot: Slot::Valid {
                sequence: header.sequence,
                len,
            },
            crc: header.crc,
        })
    }
}

/// The slot holding the newest valid payload: its index, sequence number and length (slot 0
/// on a tie, which no sequence of saves produces).
pub(super) fn newest(slots: &[Slot; 2]) -> Option<(usize, u32, usize)> {
    let valid = |i: usize| match slots.get(i) {
        Some(&Slot::Valid { sequence, len }) => Some((i, sequence, len)),
        _ => None,
    };
    match (valid(0), valid(1)) {
        (Some(a), Some(b)) => Some(if newer(b.1, a.1) { b } else { a }),
        (a, b) => a.or(b),
    }
}
