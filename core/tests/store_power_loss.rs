//! Power loss during a save, exhaustively, for the paper configuration's checkpoint
//! (`Identifier<f32, 14, 20>`, `n_p = 7`, `f = p = 10`: 18,668 bytes) on a flash of 2 KiB pages
//! programmed 8 bytes at a time: every byte of the save cut cleanly and torn, every erase cut
//! before and half-way. After each cut `load` gives the previous checkpoint or the new one,
//! byte for byte, which restores; never a corrupt one, never none.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use crate::store_common;

use hsid::store::{RamFlash, Region, Slot, Store};
use store_common::{PaperId, Sweep, paper_checkpoints, restores, sweep};

type Board = RamFlash<{ 22 * 2048 }, 2048, 8>;

/// Slots from page 1 on, leaving page 0 and page 21 for other data.
fn region() -> Region {
    store_common::region::<Board>(1, PaperId::CHECKPOINT_CAPACITY)
}

/// Bytes one save programs: the 24-byte header and the payload rounded up to 8 bytes.
const SAVE_BYTES: usize = 24 + 18_672;
/// Cut points per sweep: 2 per programmed byte and 2 per erased page (10 pages per slot).
const CUTS: usize = 2 * SAVE_BYTES + 2 * 10;

#[test]
fn the_paper_checkpoint_is_18668_bytes_in_10_pages_per_slot() {
    assert_eq!(PaperId::CHECKPOINT_CAPACITY, 18_668);
    assert_eq!(region().pages_per_slot, 10);
    let c = paper_checkpoints(&[1000]);
    assert_eq!(c[0].len(), 18_668);
}

#[test]
fn power_cut_at_each_of_37412_points_of_a_save_after_one_good_save_loads_old_or_new() {
    let c = paper_checkpoints(&[1500, 2500]);
    let s = sweep::<{ 22 * 2048 }, 2048, 8>(region(), &[&c[0]], &c[1], &restores);
    println!("after one save: {s:?}");
    check(&s);
}

#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: exhaustive power cuts, about 45 s"]
fn power_cut_at_each_of_37412_points_of_a_save_over_the_older_slot_loads_old_or_new() {
    // Both slots hold a checkpoint; the save erases and rewrites the older one.
    let c = paper_checkpoints(&[700, 1500, 2500]);
    let s = sweep::<{ 22 * 2048 }, 2048, 8>(region(), &[&c[0], &c[1]], &c[2], &restores);
    println!("over the older slot: {s:?}");
    check(&s);
}

fn check(s: &Sweep) {
    assert_eq!((s.bytes, s.erases, s.cuts), (SAVE_BYTES, 10, CUTS));
    assert_eq!(CUTS, 37_412);
    // Only a cut inside the header's last byte can leave it complete (when the torn bits or
    // the erased value happen to be the ones written).
    assert!(s.new_loaded <= 2, "{s:?}");
}

#[test]
fn the_store_leaves_the_pages_around_its_region_alone() {
    let c = paper_checkpoints(&[1500, 2500, 3500]);
    let mut flash = Box::new(Board::new());
    flash.bytes_mut()[..2048].fill(0x5A);
    flash.bytes_mut()[21 * 2048..].fill(0xA5);
    let mut store = Store::new(&mut *flash, region()).unwrap();
    for ck in &c {
        store.save(ck).unwrap();
    }
    let mut buf = vec![0u8; PaperId::CHECKPOINT_CAPACITY];
    let got = store.load(&mut buf).unwrap();
    assert_eq!(&buf[..got.len], &c[2][..]);
    assert_eq!((got.slot, got.sequence), (0, 2));
    assert_eq!(
        got.other,
        Slot::Valid {
            sequence: 1,
            len: 18_668
        }
    );
    restores(&buf[..got.len]);
    assert!(flash.bytes()[..2048].iter().all(|&b| b == 0x5A));
    assert!(flash.bytes()[21 * 2048..].iter().all(|&b| b == 0xA5));
}
