//! Shared by the store tests: the paper configuration's checkpoints and the power-cut sweep.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use hsid::store::{Flash, PowerCut, RamFlash, RamFlashError, Region, Store, StoreError};
use hsid::{Excitation, Identifier, Knots, MuZero, Settings};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// The paper configuration: 7 segments per path (`n_p = 7`), `f = p = 10`, `f32`, a 300-sample
/// hold, in the firmware's identifier type.
pub type PaperId = Identifier<f32, 14, 20>;

pub fn paper_settings() -> Settings<f32, 14> {
    let knots = Knots::<f32, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    Settings::new(
        knots,
        10,
        10,
        MuZero::Hold {
            len: 300,
            settle: 150,
        },
    )
}

/// The checkpoints of one run of the paper configuration after each of `samples` (ascending)
/// samples of the Table I excitation through a backlash and a second-order plant.
pub fn paper_checkpoints(samples: &[usize]) -> Vec<Vec<u8>> {
    let mut id = PaperId::new(paper_settings()).unwrap();
    let mut ex = Excitation::<f32, _>::new(-3.0, 3.0, 300, Pcg32::seed_from_u64(7)).unwrap();
    let (mut w, mut y1, mut y2, mut w1, mut w2) = (0.0f32, 0.0, 0.0, 0.0, 0.0);
    let mut pushed = 0;
    let mut out = Vec::new();
    for &n in samples {
        while pushed < n {
            let u = ex.next().unwrap();
            w = w.max(u - 1.0).min(u + 1.0);
            let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
            (w2, w1, y2, y1) = (w1, w, y1, y);
            id.push(u, y);
            pushed += 1;
        }
        let mut buf = vec![0u8; PaperId::CHECKPOINT_CAPACITY];
        let len = id.save(&mut buf).unwrap();
        buf.truncate(len);
        out.push(buf);
    }
    out
}

/// Restores a loaded checkpoint into the paper configuration's identifier (must succeed).
pub fn restores(bytes: &[u8]) {
    PaperId::restore_with(&paper_settings(), bytes).expect("the loaded checkpoint restores");
}

/// What a sweep tried.
#[derive(Debug, PartialEq, Eq)]
pub struct Sweep {
    /// Bytes the interrupted save programs when it runs to the end.
    pub bytes: usize,
    /// Pages it erases.
    pub erases: usize,
    /// Power cuts tried: two per programmed byte (a clean cut before it, and a cut that
    /// tears it) and two per erase (before it, and half-way through it).
    pub cuts: usize,
    /// Cuts after which `load` gave the new checkpoint (the rest gave the old one).
    pub new_loaded: usize,
    /// Cuts after which the store saved and loaded the new checkpoint again.
    pub recoveries: usize,
}

/// Bits left programmed in a torn byte, varied with the cut point.
const TORN: [u8; 8] = [0x01, 0x80, 0x55, 0xAA, 0x0F, 0xF0, 0x3C, 0xFE];

/// Saves `prior` into a fresh flash, then cuts the power at every point of saving `new` —
/// before and inside every programmed byte, before and inside every erase — and after each
/// cut powers up, loads and checks. `load` must give the last of `prior` or `new` byte for
/// byte (the new one only once its header is being written) and `check` must accept it. After
/// every erase cut, every cut in the header and every 16th other cut, the store must then
/// save and load `new` (the recovery).
pub fn sweep<const N: usize, const P: usize, const W: usize>(
    region: Region,
    prior: &[&[u8]],
    new: &[u8],
    check: &dyn Fn(&[u8]),
) -> Sweep {
    let old = *prior.last().expect("a previous checkpoint");
    assert_ne!(old, new);
    let mut base = Box::new(RamFlash::<N, P, W>::new());
    for p in prior {
        Store::new(&mut *base, region).unwrap().save(p).unwrap();
    }
    let mut reference = base.clone();
    Store::new(&mut *reference, region)
        .unwrap()
        .save(new)
        .unwrap();
    let bytes = reference.wear().bytes - base.wear().bytes;
    let erases = reference.wear().erases - base.wear().erases;
    let header = hsid::store::header_len(W);
    let mut sweep = Sweep {
        bytes,
        erases,
        cuts: 0,
        new_loaded: 0,
        recoveries: 0,
    };
    let mut run = |cut: PowerCut, may_be_new: bool, recover: bool| {
        let mut flash = base.clone();
        flash.cut_power(cut);
        let mut store = Store::new(&mut *flash, region).unwrap();
        assert_eq!(
            store.save(new),
            Err(StoreError::Flash(RamFlashError::PowerLost)),
            "{cut:?}"
        );
        store.flash_mut().restore_power();
        let mut buf = vec![0u8; store.capacity()];
        let got = store.load(&mut buf).expect("a checkpoint existed");
        let loaded = &buf[..got.len];
        let is_new = loaded == new;
        assert!(is_new || loaded == old, "{cut:?}: neither checkpoint");
        assert!(!is_new || may_be_new, "{cut:?}: new before its header");
        check(loaded);
        if recover {
            store.save(new).unwrap();
            let again = store.load(&mut buf).unwrap();
            assert_eq!(&buf[..again.len], new, "{cut:?}: the save after the cut");
            sweep.recoveries += 1;
        }
        sweep.cuts += 1;
        sweep.new_loaded += usize::from(is_new);
    };
    for erases in 0..erases {
        for torn_erase in [false, true] {
            let cut = PowerCut {
                bytes: usize::MAX,
                torn_bits: 0,
                erases,
                torn_erase,
            };
            run(cut, false, true);
        }
    }
    for n in 0..bytes {
        for torn_bits in [0, TORN[n % TORN.len()]] {
            let cut = PowerCut {
                bytes: n,
                torn_bits,
                erases: usize::MAX,
                torn_erase: false,
            };
            let in_header = n >= bytes - header;
            run(cut, in_header, in_header || n % 16 == 0);
        }
    }
    sweep
}

/// A region of `pages` pages per slot from `first` on a flash like `F`.
pub fn region<F: Flash>(first: usize, max_len: usize) -> Region {
    Region::for_payload(first, max_len, F::PAGE, F::WRITE)
}
