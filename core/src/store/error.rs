//! What the store reports: the state of each slot, and its errors.

use core::fmt;

/// What a slot holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Slot {
    /// No header: erased, or a save into it was interrupted before its header was written.
    Unwritten,
    /// A complete payload whose checksums hold.
    Valid {
        /// Its sequence number.
        sequence: u32,
        /// Its length in bytes.
        len: usize,
    },
    /// Something was written but it is not a valid payload; the store ignores it.
    Corrupt(Fault),
}

/// Why a slot is not valid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// The header's checksum fails (a torn header write, or damaged bits).
    HeaderChecksum,
    /// The header is intact but not the store's (another user of these pages).
    Magic,
    /// Written by another store format version.
    Version,
    /// The length in the header exceeds the slot.
    Length,
    /// The payload's checksum fails (damaged bits).
    PayloadChecksum,
}

/// Bad flash geometry for the store.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Geometry {
    /// The program unit must be a power of two up to [`MAX_WRITE`](super::flash::MAX_WRITE).
    WriteUnit {
        /// `Flash::WRITE`.
        write: usize,
    },
    /// The page must be a multiple of the program unit.
    PageSize {
        /// `Flash::PAGE`.
        page: usize,
        /// `Flash::WRITE`.
        write: usize,
    },
    /// A slot must hold its header and at least one byte more.
    SlotTooSmall {
        /// Pages per slot given.
        pages_per_slot: usize,
    },
    /// The region's byte offsets overflow `usize`.
    Overflow,
}

/// Why a save or a load failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError<E> {
    /// The flash driver failed (a power loss in a simulation); a save interrupted by it leaves
    /// the previous checkpoint loadable.
    Flash(E),
    /// The region does not fit the flash's page and program unit.
    Geometry(Geometry),
    /// The payload is larger than a slot holds: give the region more pages per slot
    /// ([`Region::for_payload`](super::layout::Region::for_payload)).
    TooLarge {
        /// Bytes given.
        len: usize,
        /// Largest payload a slot holds.
        capacity: usize,
    },
    /// The buffer to load into is shorter than the newest checkpoint: size it with the
    /// checkpoint capacity of the identifier type.
    BufferTooSmall {
        /// Bytes the checkpoint has.
        need: usize,
        /// Bytes the buffer has.
        have: usize,
    },
    /// No slot holds a valid checkpoint (none was saved yet, or both are damaged).
    NoCheckpoint {
        /// What each slot holds.
        slots: [Slot; 2],
    },
    /// Reading back the slot just written did not give a valid checkpoint (a failing flash):
    /// the previous checkpoint is still the newest valid one.
    Verify {
        /// What the written slot holds.
        found: Slot,
    },
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Fault::HeaderChecksum => "header checksum mismatch (torn write or damaged bits)",
            Fault::Magic => "not a checkpoint store slot (wrong magic)",
            Fault::Version => "written by another store format version",
            Fault::Length => "the header's length exceeds the slot",
            Fault::PayloadChecksum => "payload checksum mismatch (damaged bits)",
        })
    }
}

impl fmt::Display for Slot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Slot::Unwritten => f.write_str("unwritten"),
            Slot::Valid { sequence, len } => write!(f, "valid (sequence {sequence}, {len} bytes)"),
            Slot::Corrupt(fault) => write!(f, "corrupt: {fault}"),
        }
    }
}

impl<E: fmt::Debug> fmt::Display for StoreError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoreError::Flash(e) => write!(f, "flash driver failed: {e:?}"),
            StoreError::Geometry(g) => match g {
                Geometry::WriteUnit { write } => write!(
                    f,
                    "program unit of {write} bytes: must be a power of two up to {}",
                    super::flash::MAX_WRITE
                ),
                Geometry::PageSize { page, write } => write!(
                    f,
                    "page of {page} bytes is not a multiple of the {write}-byte program unit"
                ),
                Geometry::SlotTooSmall { pages_per_slot } => write!(
                    f,
                    "{pages_per_slot} pages per slot cannot hold the header and a payload"
                ),
                Geometry::Overflow => f.write_str("the region's byte offsets overflow"),
            },
            StoreError::TooLarge { len, capacity } => write!(
                f,
                "payload of {len} bytes exceeds the slot's {capacity}: give the region more pages per slot"
            ),
            StoreError::BufferTooSmall { need, have } => write!(
                f,
                "the checkpoint has {need} bytes but the buffer only {have}: size it with the checkpoint capacity"
            ),
            StoreError::NoCheckpoint { slots: [a, b] } => {
                write!(f, "no valid checkpoint (slot 0 {a}, slot 1 {b})")
            }
            StoreError::Verify { found } => {
                write!(f, "the slot just written does not read back valid: {found}")
            }
        }
    }
}

impl<E: fmt::Debug> core::error::Error for StoreError<E> {}
