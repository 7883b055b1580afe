//! The checkpoint store as a firmware uses it after a reset and every few samples: save the
//! identifier into the store, load the newest checkpoint, restore it.

use core::hint::black_box;

use hsid::Plain;
use hsid::store::{RamFlash, Region, Store};

use crate::Id;

/// A flash of 22 pages of 2 KiB programmed 8 bytes at a time.
type Board = RamFlash<{ 22 * 2048 }, 2048, 8>;
const CAPACITY: usize = Id::<f32, Plain>::CHECKPOINT_CAPACITY;

static mut FLASH: Board = Board::new();
static mut CKPT: [u8; CAPACITY] = [0; CAPACITY];

/// Saves `id` into the store, damages one unseen byte of the flash, loads the newest
/// checkpoint and restores it with the settings (everything the optimiser could use to drop a
/// check is hidden).
pub fn save_load_restore(id: &mut Id<f32, Plain>) {
    // SAFETY: single-threaded bare-metal entry point; these are the only references.
    #[allow(static_mut_refs)]
    let (flash, ckpt) = unsafe { (&mut FLASH, &mut CKPT) };
    let region = Region {
        first_page: black_box(1),
        pages_per_slot: black_box(10),
    };
    let Ok(mut store) = Store::new(&mut *flash, region) else {
        return;
    };
    let n = black_box(CAPACITY);
    let buf = ckpt.get_mut(..n).unwrap_or(&mut []);
    if let Ok(len) = id.save(buf) {
        black_box(store.save(buf.get(..black_box(len)).unwrap_or(&[])).is_ok());
    }
    if let Some(b) = store.flash_mut().bytes_mut().get_mut(black_box(4096)) {
        *b ^= black_box(1);
    }
    let settings = id.settings().clone();
    if let Ok(loaded) = store.load(buf) {
        let bytes = buf.get(..black_box(loaded.len)).unwrap_or(&[]);
        if let Ok(back) = Id::<f32, Plain>::restore_with(&settings, bytes) {
            *id = back;
        }
    }
}
