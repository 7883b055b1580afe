//! Where the two slots lie and what a slot's header holds.
//!
//! A slot is whole pages: the header at its start, padded with `0xFF` to a multiple of the
//! program unit, then the payload, its last unit padded with `0xFF`. The header, little-endian:
//!
//! | bytes | field |
//! |---|---|
//! | 0..4 | magic `HSST` |
//! | 4..6 | store format version ([`STORE_VERSION`]) |
//! | 6..8 | reserved, 0 |
//! | 8..12 | sequence number (wrapping `u32`) |
//! | 12..16 | payload length in bytes |
//! | 16..20 | CRC-32 of the payload |
//! | 20..24 | CRC-32 of bytes 0..20 |

use super::error::{Geometry, StoreError};
use super::flash::{Flash, MAX_WRITE};
use crate::checkpoint::crc32;

/// Format version of the slot header.
pub const STORE_VERSION: u16 = 1;
/// Bytes of the header's fields (before its padding to the program unit).
pub const HEADER_FIELDS: usize = 24;
pub(super) const MAGIC: [u8; 4] = *b"HSST";

/// The flash pages the store uses: two slots of `pages_per_slot` pages each, from
/// `first_page` on (slot 0 first).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Region {
    /// First page of slot 0.
    pub first_page: usize,
    /// Pages of each slot.
    pub pages_per_slot: usize,
}

impl Region {
    /// The smallest region from `first_page` whose slots hold payloads of `max_len` bytes
    /// (e.g. [`Identifier::CHECKPOINT_CAPACITY`](crate::Identifier::CHECKPOINT_CAPACITY)) on
    /// a flash with pages of `page` bytes and program units of `write` bytes.
    pub const fn for_payload(first_page: usize, max_len: usize, page: usize, write: usize) -> Self {
        let page = if page == 0 { 1 } else { page };
        let bytes = header_len(write) + round_up(max_len, write);
        Self {
            first_page,
            pages_per_slot: bytes.div_ceil(page),
        }
    }
}

/// Bytes the header takes in a slot: [`HEADER_FIELDS`] rounded up to the program unit.
pub const fn header_len(write: usize) -> usize {
    round_up(HEADER_FIELDS, write)
}

const fn round_up(n: usize, unit: usize) -> usize {
    if unit == 0 {
        n
    } else {
        n.div_ceil(unit) * unit
    }
}

/// A region checked against a flash's page and program unit: byte offsets of the slots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Slots {
    /// Byte offset of each slot.
    pub start: [usize; 2],
    /// Bytes of a slot.
    pub bytes: usize,
    /// Bytes of the header (the payload starts there).
    pub header: usize,
    /// First page of each slot.
    pub first_page: [usize; 2],
    /// Pages of a slot.
    pub pages: usize,
}

impl Slots {
    /// The slots of `region` on `F`, or what is wrong with the geometry.
    pub fn of<F: Flash>(region: Region) -> Result<Self, StoreError<F::Error>> {
        let (page, write) = (F::PAGE, F::WRITE);
        if write == 0 || write > MAX_WRITE || !write.is_power_of_two() {
            return Err(StoreError::Geometry(Geometry::WriteUnit { write }));
        }
        if page < write || !page.is_multiple_of(write) {
            return Err(StoreError::Geometry(Geometry::PageSize { page, write }));
        }
        let header = header_len(write);
        let too_small = Geometry::SlotTooSmall {
            pages_per_slot: region.pages_per_slot,
        };
        let bytes = region
            .pages_per_slot
            .checked_mul(page)
            .filter(|&b| b > header)
            .ok_or(StoreError::Geometry(too_small))?;
        let overflow = StoreError::Geometry(Geometry::Overflow);
        let start0 = region.first_page.checked_mul(page).ok_or(overflow)?;
        let start1 = start0.checked_add(bytes).ok_or(overflow)?;
        start1.checked_add(bytes).ok_or(overflow)?;
        let pages = region.pages_per_slot;
        Ok(Self {
            start: [start0, start1],
            bytes,
            header,
            first_page: [region.first_page, region.first_page + pages],
            pages,
        })
    }

    /// Byte offset of slot `index` (0 or 1).
    pub fn start(&self, index: usize) -> usize {
        self.start[index & 1]
    }

    /// Largest payload a slot holds.
    pub fn capacity(&self) -> usize {
        self.bytes - self.header
    }
}

/// A slot's header fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Header {
    pub sequence: u32,
    pub len: u32,
    pub crc: u32,
}

/// What reading a header found.
pub(super) enum Parsed {
    /// All `0xFF`: the header was never written since the erase.
    Erased,
    /// Its own checksum fails.
    Checksum,
    /// The checksum holds but the magic is not the store's.
    Magic,
    /// Another format version (or a reserved field set).
    Version,
    /// A valid header.
    Header(Header),
}

impl Header {
    /// The header's fields, its checksum last.
    pub fn encode(&self) -> [u8; HEADER_FIELDS] {
        let mut b = [0u8; HEADER_FIELDS];
        let fields = [
            u32::from_le_bytes(MAGIC),
            u32::from(STORE_VERSION),
            self.sequence,
            self.len,
            self.crc,
        ];
        for (dst, v) in b.chunks_exact_mut(4).zip(fields) {
            dst.copy_from_slice(&v.to_le_bytes());
        }
        let crc = crc32(b.get(..HEADER_FIELDS - 4).unwrap_or(&[]));
        if let Some(dst) = b.get_mut(HEADER_FIELDS - 4..) {
            dst.copy_from_slice(&crc.to_le_bytes());
        }
        b
    }

    /// Reads the fields back, checksum first.
    pub fn parse(b: &[u8; HEADER_FIELDS]) -> Parsed {
        if b.iter().all(|&x| x == 0xFF) {
            return Parsed::Erased;
        }
        let word = |i: usize| {
            let mut w = [0u8; 4];
            if let Some(src) = b.get(4 * i..4 * i + 4) {
                w.copy_from_slice(src);
            }
            u32::from_le_bytes(w)
        };
        if crc32(b.get(..HEADER_FIELDS - 4).unwrap_or(&[])) != word(5) {
            return Parsed::Checksum;
        }
        if word(0) != u32::from_le_bytes(MAGIC) {
            return Parsed::Magic;
        }
        if word(1) != u32::from(STORE_VERSION) {
            return Parsed::Version;
        }
        Parsed::Header(Header {
            sequence: word(2),
            len: word(3),
            crc: word(4),
        })
    }
}

/// Whether sequence number `a` comes after `b` (serial-number arithmetic: wraps at 2³²).
pub(super) fn newer(a: u32, b: u32) -> bool {
    a != b && a.wrapping_sub(b) < 1 << 31
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequence_order_wraps() {
        assert!(newer(1, 0));
        assert!(!newer(0, 1));
        assert!(newer(0, u32::MAX));
        assert!(!newer(u32::MAX, 0));
        assert!(newer(5, u32::MAX - 5));
        assert!(!newer(7, 7));
    }

    #[test]
    fn header_round_trips_and_every_single_bit_flip_is_refused() {
        let h = Header {
            sequence: 0xDEAD_BEEF,
            len: 18_668,
            crc: 0x1234_5678,
        };
        let b = h.encode();
        assert!(matches!(Header::parse(&b), Parsed::Header(x) if x == h));
        for bit in 0..HEADER_FIELDS * 8 {
            let mut c = b;
            c[bit / 8] ^= 1 << (bit % 8);
            assert!(matches!(Header::parse(&c), Parsed::Checksum), "bit {bit}");
        }
    }

    #[test]
    fn region_for_payload_fits_header_and_padding() {
        // 24-byte header + 18,668 bytes rounded to 8 = 18,696 bytes: 10 pages of 2 KiB.
        let r = Region::for_payload(4, 18_668, 2048, 8);
        assert_eq!(r.pages_per_slot, 10);
        // 256-byte units: 256 + 18,688 = 18,944 bytes, still 10 pages.
        assert_eq!(Region::for_payload(0, 18_668, 2048, 256).pages_per_slot, 10);
        assert_eq!(Region::for_payload(0, 2048 - 24, 2048, 8).pages_per_slot, 1);
        assert_eq!(Region::for_payload(0, 2048 - 23, 2048, 8).pages_per_slot, 2);
    }
}
