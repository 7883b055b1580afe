//! A power-loss-safe checkpoint store: two slots on a board's flash, so that a power loss at
//! any point of a save leaves either the previous checkpoint or the new one loadable — never a
//! corrupt one, and never none when one had been saved.
//!
//! Each slot is whole flash pages: a header (magic, format version, sequence number, payload
//! length, the payload's CRC-32 and the header's own CRC-32) and the payload (the bytes of
//! [`Identifier::save`](crate::Identifier::save), stored as they are). [`Store::save`] writes
//! into the slot that does *not* hold the newest valid checkpoint, in this order: erase its
//! pages (the header's page first), program the payload, program the header last. Until the
//! header's last unit is programmed the slot fails its header checksum and is ignored, so the
//! other slot's checkpoint stays the newest valid one; once it is, the new checkpoint is
//! complete. [`Store::load`] returns the valid slot with the newest sequence number (wrapping
//! at 2³²) and reports what the other slot holds, so a damaged slot is known. The layout is in
//! [`layout`](self#layout) below and in `docs/reliability.md`.
//!
//! ```
//! use hsid::store::{Flash, RamFlash, Region, Slot, Store};
//! use hsid::{Identifier, Knots, MuZero, Settings};
//!
//! type Id = Identifier<f32, 4, 6>;
//! let knots = Knots::<f32, 4>::uniform(-1.0, 1.0, 2, 2)?;
//! let mut id = Id::new(Settings::new(knots, 3, 3, MuZero::Known(0.0)))?;
//! let mut ckpt = [0u8; Id::CHECKPOINT_CAPACITY];
//!
//! // 4 KiB of flash in 256-byte pages programmed 8 bytes at a time, in RAM.
//! type Board = RamFlash<4096, 256, 8>;
//! let region = Region::for_payload(0, Id::CHECKPOINT_CAPACITY, Board::PAGE, Board::WRITE);
//! let mut store = Store::new(Board::new(), region).unwrap();
//!
//! id.push(0.5, 0.1);
//! let len = id.save(&mut ckpt)?;
//! store.save(&ckpt[..len]).unwrap();
//! id.push(0.25, 0.2);
//! let len = id.save(&mut ckpt)?;
//! let saved = store.save(&ckpt[..len]).unwrap();
//! assert_eq!((saved.slot, saved.sequence), (1, 1));
//!
//! // After a reset: the newest checkpoint, and what the other slot holds.
//! let mut buf = [0u8; Id::CHECKPOINT_CAPACITY];
//! let loaded = store.load(&mut buf).unwrap();
//! assert_eq!(loaded.sequence, 1);
//! assert!(matches!(loaded.other, Slot::Valid { sequence: 0, .. }));
//! let back = Id::restore(&buf[..loaded.len])?;
//! assert_eq!(back.samples(), 2);
//! # Ok::<(), hsid::Error>(())
//! ```
//!
//! # Layout
//!
//! Slot 0 is `pages_per_slot` pages from [`Region::first_page`], slot 1 the same number of
//! pages right after. In a slot, little-endian: magic `HSST` (4 bytes), [`STORE_VERSION`]
//! (`u16`), 0 (`u16`), sequence number (`u32`), payload length (`u32`), CRC-32 of the payload
//! (`u32`), CRC-32 of the 20 bytes before (`u32`); `0xFF` up to a multiple of
//! [`Flash::WRITE`]; the payload; `0xFF` up to a multiple of `Flash::WRITE`. The CRC-32 is
//! [`crc32`](crate::crc32), the checkpoints' own.

mod error;
mod flash;
mod inspect;
mod layout;
mod load;
mod ram;
mod save;
mod two_slots;

pub use error::{Fault, Geometry, Slot, StoreError};
pub use flash::{Flash, MAX_WRITE};
pub use layout::{HEADER_FIELDS, Region, STORE_VERSION, header_len};
pub use load::Loaded;
pub use ram::{PowerCut, RamFlash, RamFlashError, Wear};
pub use save::Saved;
pub use two_slots::Store;
