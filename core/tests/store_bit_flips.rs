//! Damaged slots: a flipped bit anywhere in a stored header (every bit) or payload (sampled
//! bits) makes `load` return the other slot's checkpoint and report the damaged slot, or a
//! typed error when both are damaged — never a wrong checkpoint. Headers forged with a valid
//! checksum (another magic, version or an impossible length) are refused with their fault.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use crate::store_common;

use hsid::store::{Fault, RamFlash, Region, Slot, Store, StoreError};
use store_common::{PaperId, paper_checkpoints, restores};

const PAGE: usize = 2048;
type Board = RamFlash<{ 20 * PAGE }, PAGE, 8>;
/// Slot `s` starts at byte `s * SLOT`; its header has 24 bytes, then the payload.
const SLOT: usize = 10 * PAGE;
const LEN: usize = 18_668;

fn region() -> Region {
    store_common::region::<Board>(0, PaperId::CHECKPOINT_CAPACITY)
}

/// Slot 0 holds `c[0]` (sequence 0), slot 1 `c[1]` (sequence 1).
fn two_slots() -> (Box<Board>, Vec<Vec<u8>>) {
    let c = paper_checkpoints(&[1500, 2500]);
    let mut flash = Box::new(Board::new());
    let mut store = Store::new(&mut *flash, region()).unwrap();
    store.save(&c[0]).unwrap();
    store.save(&c[1]).unwrap();
    (flash, c)
}

fn load(
    flash: &mut Board,
) -> Result<(Vec<u8>, hsid::store::Loaded), StoreError<hsid::store::RamFlashError>> {
    let mut store = Store::new(flash, region()).unwrap();
    let mut buf = vec![0u8; PaperId::CHECKPOINT_CAPACITY];
    let got = store.load(&mut buf)?;
    buf.truncate(got.len);
    Ok((buf, got))
}

#[test]
fn every_header_bit_and_every_61st_payload_bit_flipped_in_either_slot_is_caught() {
    let (clean, c) = two_slots();
    let mut tried = 0;
    for slot in 0..2 {
        let header_bits = (0..24 * 8).map(|b| slot * SLOT * 8 + b);
        let payload_bits = (0..LEN * 8).step_by(61).map(|b| (slot * SLOT + 24) * 8 + b);
        for bit in header_bits.chain(payload_bits) {
            let mut flash = clean.clone();
            flash.bytes_mut()[bit / 8] ^= 1 << (bit % 8);
            let (bytes, got) = load(&mut flash).unwrap();
            // The other slot's checkpoint, whichever was newer.
            let other = 1 - slot;
            assert_eq!(got.slot, other, "bit {bit}");
            assert_eq!(bytes, c[other], "bit {bit}");
            let fault = if bit / 8 < slot * SLOT + 24 {
                Fault::HeaderChecksum
            } else {
                Fault::PayloadChecksum
            };
            assert_eq!(got.other, Slot::Corrupt(fault), "bit {bit}");
            tried += 1;
        }
        restores(&c[1 - slot]);
    }
    // 192 header bits and ceil(149,344 / 61) = 2,449 payload bits per slot.
    assert_eq!(tried, 2 * (192 + 2_449));
}

#[test]
fn a_flip_in_each_slot_is_no_checkpoint_with_both_faults() {
    let (mut flash, _) = two_slots();
    flash.bytes_mut()[3] ^= 0x10; // slot 0's magic
    flash.bytes_mut()[SLOT + 24 + 9_000] ^= 0x01; // slot 1's payload
    assert_eq!(
        load(&mut flash).unwrap_err(),
        StoreError::NoCheckpoint {
            slots: [
                Slot::Corrupt(Fault::HeaderChecksum),
                Slot::Corrupt(Fault::PayloadChecksum)
            ]
        }
    );
}

#[test]
fn the_padding_after_the_payload_is_not_data() {
    // 18,668 bytes end 4 bytes short of a program unit: those 4 bytes stay 0xFF and are not
    // part of the payload or its checksum.
    let (clean, c) = two_slots();
    for byte in 24 + LEN..24 + LEN + 4 {
        let mut flash = clean.clone();
        flash.bytes_mut()[SLOT + byte] = 0;
        let (bytes, got) = load(&mut flash).unwrap();
        assert_eq!((got.slot, bytes), (1, c[1].clone()));
        assert!(matches!(got.other, Slot::Valid { sequence: 0, .. }));
    }
}

/// A header with a valid checksum, written from the documented layout.
fn forged(magic: &[u8; 4], version: u16, sequence: u32, len: u32, crc: u32) -> [u8; 24] {
    let mut h = [0u8; 24];
    h[..4].copy_from_slice(magic);
    h[4..6].copy_from_slice(&version.to_le_bytes());
    h[8..12].copy_from_slice(&sequence.to_le_bytes());
    h[12..16].copy_from_slice(&len.to_le_bytes());
    h[16..20].copy_from_slice(&crc.to_le_bytes());
    let hc = hsid::crc32(&h[..20]);
    h[20..].copy_from_slice(&hc.to_le_bytes());
    h
}

#[test]
fn forged_headers_are_refused_with_their_fault() {
    let (clean, c) = two_slots();
    let crc = hsid::crc32(&c[1]);
    let capacity = (SLOT - 24) as u32;
    let cases = [
        (forged(b"HSST", 1, 1, LEN as u32, crc), None),
        (forged(b"HSCK", 1, 1, LEN as u32, crc), Some(Fault::Magic)),
        (forged(b"HSST", 2, 1, LEN as u32, crc), Some(Fault::Version)),
        (
            forged(b"HSST", 1, 1, capacity + 1, crc),
            Some(Fault::Length),
        ),
        (
            forged(b"HSST", 1, 1, LEN as u32 - 1, crc),
            Some(Fault::PayloadChecksum),
        ),
        (
            forged(b"HSST", 1, 1, LEN as u32, crc ^ 1),
            Some(Fault::PayloadChecksum),
        ),
    ];
    for (header, fault) in cases {
        let mut flash = clean.clone();
        flash.bytes_mut()[SLOT..SLOT + 24].copy_from_slice(&header);
        let (bytes, got) = load(&mut flash).unwrap();
        match fault {
            // The layout as documented: the slot is read as it was written.
            None => assert_eq!((got.slot, bytes), (1, c[1].clone())),
            Some(f) => {
                assert_eq!((got.slot, bytes), (0, c[0].clone()));
                assert_eq!(got.other, Slot::Corrupt(f));
            }
        }
    }
}
