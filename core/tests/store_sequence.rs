//! Sequence numbers (alternating slots, wrap-around at 2³²), the store's typed errors, and
//! power cuts on other flash geometries (program units of 1 to 256 bytes).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use crate::store_common;

use hsid::store::{Flash, Geometry, RamFlash, RamFlashError, Region, Slot, Store, StoreError};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

type Small = RamFlash<{ 8 * 256 }, 256, 8>;

fn payload(len: usize, seed: u64) -> Vec<u8> {
    let mut rng = Pcg32::seed_from_u64(seed);
    (0..len).map(|_| rng.next_u32() as u8).collect()
}

fn region() -> Region {
    Region {
        first_page: 0,
        pages_per_slot: 4,
    }
}

#[test]
fn saves_alternate_slots_with_increasing_sequence_numbers() {
    let mut store = Store::new(Small::new(), region()).unwrap();
    let mut buf = [0u8; 1024];
    assert_eq!(
        store.load(&mut buf),
        Err(StoreError::NoCheckpoint {
            slots: [Slot::Unwritten, Slot::Unwritten]
        })
    );
    for i in 0..10u32 {
        let p = payload(100 + 37 * i as usize, u64::from(i));
        let saved = store.save(&p).unwrap();
        assert_eq!((saved.slot, saved.sequence), (i as usize % 2, i));
        let got = store.load(&mut buf).unwrap();
        assert_eq!((got.slot, got.sequence), (saved.slot, i));
        assert_eq!(&buf[..got.len], &p[..]);
        let previous = (i > 0).then(|| Slot::Valid {
            sequence: i - 1,
            len: 100 + 37 * (i as usize - 1),
        });
        assert_eq!(got.other, previous.unwrap_or(Slot::Unwritten));
    }
    // 4 erases of the target slot per save.
    assert_eq!(store.flash().wear().erases, 40);
}

/// Sets slot `slot`'s sequence number by rewriting its header from the documented layout.
fn set_sequence(flash: &mut Small, slot: usize, sequence: u32) {
    let h = &mut flash.bytes_mut()[slot * 1024..slot * 1024 + 24];
    h[8..12].copy_from_slice(&sequence.to_le_bytes());
    let crc = hsid::crc32(&h[..20]);
    h[20..24].copy_from_slice(&crc.to_le_bytes());
}

#[test]
fn the_newest_is_found_across_the_wrap_around() {
    let (a, b) = (payload(300, 1), payload(500, 2));
    let cases = [
        (u32::MAX, 0, 1),
        (0, u32::MAX, 0),
        (u32::MAX - 1, u32::MAX, 1),
        (7, 6, 0),
        (0x7FFF_FFFF, 0x8000_0000, 1),
    ];
    for (s0, s1, newest) in cases {
        let mut store = Store::new(Small::new(), region()).unwrap();
        store.save(&a).unwrap();
        store.save(&b).unwrap();
        set_sequence(store.flash_mut(), 0, s0);
        set_sequence(store.flash_mut(), 1, s1);
        let mut buf = [0u8; 1024];
        let got = store.load(&mut buf).unwrap();
        let want = [(&a, s0), (&b, s1)][newest];
        assert_eq!((got.slot, got.sequence), (newest, want.1), "{s0} {s1}");
        assert_eq!(&buf[..got.len], &want.0[..]);
        // The next save goes to the other slot, numbered one more (wrapping).
        let c = payload(200, 3);
        let saved = store.save(&c).unwrap();
        assert_eq!(
            (saved.slot, saved.sequence),
            (1 - newest, want.1.wrapping_add(1))
        );
        let got = store.load(&mut buf).unwrap();
        assert_eq!((got.slot, &buf[..got.len]), (1 - newest, &c[..]));
    }
}

#[test]
fn bad_geometry_sizes_and_buffers_are_typed_errors() {
    let geometry = |e| StoreError::<RamFlashError>::Geometry(e);
    let r = region();
    assert_eq!(
        err(Store::new(RamFlash::<2048, 256, 3>::new(), r)),
        geometry(Geometry::WriteUnit { write: 3 })
    );
    assert_eq!(
        err(Store::new(RamFlash::<2048, 512, 512>::new(), r)),
        geometry(Geometry::WriteUnit { write: 512 })
    );
    assert_eq!(
        err(Store::new(RamFlash::<2048, 12, 8>::new(), r)),
        geometry(Geometry::PageSize { page: 12, write: 8 })
    );
    let none = Region {
        first_page: 0,
        pages_per_slot: 0,
    };
    assert_eq!(
        err(Store::new(Small::new(), none)),
        geometry(Geometry::SlotTooSmall { pages_per_slot: 0 })
    );
    let far = Region {
        first_page: usize::MAX / 2,
        pages_per_slot: 1,
    };
    assert_eq!(
        err(Store::new(Small::new(), far)),
        geometry(Geometry::Overflow)
    );
    // A region beyond the flash: the driver's range error, nothing written.
    let beyond = Region {
        first_page: 6,
        pages_per_slot: 2,
    };
    let mut store = Store::new(Small::new(), beyond).unwrap();
    assert_eq!(
        store.save(&[1, 2, 3]),
        Err(StoreError::Flash(RamFlashError::Range))
    );
    let mut store = Store::new(Small::new(), region()).unwrap();
    assert_eq!(store.capacity(), 1024 - 24);
    assert_eq!(
        store.save(&payload(1001, 0)),
        Err(StoreError::TooLarge {
            len: 1001,
            capacity: 1000
        })
    );
    store.save(&payload(1000, 0)).unwrap();
    let mut short = [0u8; 999];
    assert_eq!(
        store.load(&mut short),
        Err(StoreError::BufferTooSmall {
            need: 1000,
            have: 999
        })
    );
    assert!(store.flash().wear().bytes == 1024);
}

fn err<F: Flash<Error = RamFlashError>>(
    res: Result<Store<F>, StoreError<RamFlashError>>,
) -> StoreError<RamFlashError> {
    res.err().unwrap()
}

fn no_check(_: &[u8]) {}

/// Power cuts at every point of a save on geometries from 1-byte to 256-byte program units.
fn sweep_on<const N: usize, const P: usize, const W: usize>(len: usize) -> store_common::Sweep {
    let region = store_common::region::<RamFlash<N, P, W>>(0, len);
    let (old, new) = (payload(len - 5, 11), payload(len, 12));
    let s = store_common::sweep::<N, P, W>(region, &[&old], &new, &no_check);
    let header = hsid::store::header_len(W);
    assert_eq!(s.bytes, header + len.div_ceil(W) * W);
    assert_eq!(s.erases, region.pages_per_slot);
    assert_eq!(s.cuts, 2 * s.bytes + 2 * s.erases);
    s
}

#[test]
fn power_cuts_on_program_units_of_1_4_16_32_and_256_bytes() {
    let counts = [
        sweep_on::<4096, 512, 1>(1500).cuts,
        sweep_on::<4096, 512, 4>(1501).cuts,
        sweep_on::<4096, 512, 16>(1502).cuts,
        sweep_on::<8192, 1024, 32>(1503).cuts,
        sweep_on::<8192, 1024, 256>(1504).cuts,
    ];
    // 2 × (header + payload rounded to the unit) + 2 × pages: 2 × (24 + 1500) + 2 × 3,
    // 2 × (24 + 1504) + 2 × 3, 2 × (32 + 1504) + 2 × 3, 2 × (32 + 1504) + 2 × 2,
    // 2 × (256 + 1536) + 2 × 2.
    assert_eq!(counts, [3054, 3062, 3078, 3076, 3588]);
    assert_eq!(<RamFlash<8192, 1024, 256> as Flash>::WRITE, 256);
}
