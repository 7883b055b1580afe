//! With the `store` feature: the experiment checkpoints the identifier every [`EVERY`] samples
//! into the power-loss-safe store (`hsid::store`) on a simulated flash in RAM, loses power in
//! the middle of the save at sample [`CUT_AT`], and resumes: it loads the newest valid
//! checkpoint, restores the identifier from it and replays the plant and the excitation (both
//! seeded) up to the restored sample count, then carries on. The model at the end is the
//! uninterrupted run's, bit for bit (compare the `HSID` model lines of a build without the
//! feature).

use hsid::store::{Flash, PowerCut, RamFlash, Region, Slot, Store, StoreError};
use static_cell::ConstStaticCell;

use hsid::Excitation;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

use crate::plant::{self, Plant};
use crate::report::{self, out};
use crate::{EXCITATION_LEN, EXCITATION_SEED, HOLD_LEN, Id, U_MAX, U_MIN, cost, fail, fail_with};

/// Samples between checkpoints.
pub const EVERY: usize = 500;
/// The save after this many samples loses power half-way through its payload.
pub const CUT_AT: usize = 2500;
/// A flash of 2 KiB pages programmed 8 bytes at a time (an STM32F4/L4-class part), in RAM.
type Board = RamFlash<{ 2 * PAGES * 2048 }, 2048, 8>;
/// Pages per slot for the identifier's checkpoint (10 for the paper configuration).
const PAGES: usize = Region::for_payload(0, Id::CHECKPOINT_CAPACITY, 2048, 8).pages_per_slot;

static FLASH: ConstStaticCell<Board> = ConstStaticCell::new(Board::new());

/// The store and what its use cost.
pub struct Checkpoints {
    store: Store<&'static mut Board>,
    saves: u32,
    save_ticks_max: u64,
    save_ticks_sum: u64,
    cut_done: bool,
}

/// A save lost power: the device "resets".
pub struct PowerLoss;

impl Checkpoints {
    /// The store on the whole simulated flash.
    pub fn new() -> Self {
        let region = Region {
            first_page: 0,
            pages_per_slot: PAGES,
        };
        let store = Store::new(FLASH.take(), region).unwrap_or_else(|_| fail("store geometry"));
        Self {
            store,
            saves: 0,
            save_ticks_max: 0,
            save_ticks_sum: 0,
            cut_done: false,
        }
    }

    /// After `samples` samples: every [`EVERY`] samples saves `id` (through `buf`) into the
    /// store; the save at [`CUT_AT`] loses power (once).
    pub fn after(&mut self, samples: usize, id: &Id, buf: &mut [u8]) -> Result<(), PowerLoss> {
        if samples == 0 || !samples.is_multiple_of(EVERY) {
            return Ok(());
        }
        let len = id.save(buf).unwrap_or_else(|e| fail_with("save", &e));
        let bytes = buf.get(..len).unwrap_or(&[]);
        let cut = samples == CUT_AT && !self.cut_done;
        if cut {
            self.cut_done = true;
            self.store.flash_mut().cut_power(PowerCut {
                bytes: len / 2,
                torn_bits: 0x5A,
                erases: usize::MAX,
                torn_erase: false,
            });
        }
        let (saved, ticks) = cost::measure_with(|| self.store.save(bytes));
        match saved {
            Ok(_) => {
                self.saves += 1;
                self.save_ticks_max = self.save_ticks_max.max(ticks);
                self.save_ticks_sum += ticks;
                Ok(())
            }
            Err(StoreError::Flash(hsid::store::RamFlashError::PowerLost)) if cut => {
                self.store.flash_mut().restore_power();
                Err(PowerLoss)
            }
            Err(e) => {
                out!("HSID fail store save: {}", e);
                fail("store save")
            }
        }
    }

    /// After the reset: loads the newest valid checkpoint into `buf`, restores `id` from it,
    /// prints `HSID resume ...` and returns the samples it holds.
    pub fn resume(&mut self, id: &mut Id, buf: &mut [u8]) -> usize {
        let (loaded, ticks) = cost::measure_with(|| self.store.load(buf));
        let loaded = loaded.unwrap_or_else(|e| {
            out!("HSID fail store load: {}", e);
            fail("store load")
        });
        let bytes = buf.get(..loaded.len).unwrap_or(&[]);
        // `restore` and a fingerprint check rather than `restore_with`, which builds a probe
        // identifier on the stack to fingerprint the settings.
        let fingerprint = id.fingerprint();
        let (restored, restore_ticks) = cost::measure_with(|| Id::restore(bytes));
        *id = restored.unwrap_or_else(|e| fail_with("restore", &e));
        if id.fingerprint() != fingerprint {
            fail("restore: the checkpoint has other settings");
        }
        let samples = id.samples() as usize;
        let other = match loaded.other {
            Slot::Unwritten => "unwritten",
            Slot::Valid { .. } => "valid",
            Slot::Corrupt(_) => "corrupt",
        };
        out!(
            "HSID resume interrupted_at={} sequence={} slot={} other_slot={} samples={} load_instr={} restore_instr={}",
            CUT_AT,
            loaded.sequence,
            loaded.slot,
            other,
            samples,
            ticks * cost::INSTR_PER_TICK,
            restore_ticks * cost::INSTR_PER_TICK
        );
        samples
    }

    /// Prints `HSID store ...`: the checkpoints saved and their cost.
    pub fn report(&self) {
        let mean = self.save_ticks_sum / u64::from(self.saves.max(1));
        out!(
            "HSID store every={} saves={} flash_bytes={} page={} write={} save_instr_mean={} save_instr_max={}",
            EVERY,
            self.saves,
            2 * PAGES * Board::PAGE,
            Board::PAGE,
            Board::WRITE,
            mean * cost::INSTR_PER_TICK,
            self.save_ticks_max * cost::INSTR_PER_TICK
        );
    }
}

/// The experiment with checkpoints, a power loss and the resumption; `ws` (the idle solve
/// workspace) holds each checkpoint's bytes on their way to the store. Returns `ws`.
pub fn experiment(
    id: &mut Id,
    push: &mut report::PushCost,
    ws: &'static mut [f32; crate::WORKSPACE_LEN],
) -> &'static mut [f32; crate::WORKSPACE_LEN] {
    let mut store = Checkpoints::new();
    let buf: &mut [u8] = bytemuck::cast_slice_mut(&mut ws[..]);
    if run(id, 0, push, |t, id| store.after(t, id, buf)).is_err() {
        let from = store.resume(id, buf);
        if run(id, from, push, |t, id| store.after(t, id, buf)).is_err() {
            fail("second power loss");
        }
    }
    store.report();
    ws
}

/// Runs the experiment from sample `from` to the end — the plant and the excitation (both
/// seeded) replayed up to `from` without pushing — calling `after(samples pushed, id)` after
/// each push; stops at the first error of `after`.
fn run(
    id: &mut Id,
    from: usize,
    push: &mut report::PushCost,
    mut after: impl FnMut(usize, &Id) -> Result<(), PowerLoss>,
) -> Result<(), PowerLoss> {
    let mut excitation = Excitation::new(
        U_MIN,
        U_MAX,
        HOLD_LEN,
        Pcg32::seed_from_u64(EXCITATION_SEED),
    )
    .unwrap_or_else(|e| fail_with("excitation", &e));
    let mut servo = plant::plant();
    for t in 0..HOLD_LEN + EXCITATION_LEN {
        let u = excitation.next().unwrap_or(U_MIN); // endless iterator: never None
        servo.apply(u);
        let y = servo.read();
        if t < from {
            continue;
        }
        let ticks = cost::measure(|| id.push(u, y));
        let overhead = cost::measure(|| {});
        if t >= HOLD_LEN {
            push.add(ticks, overhead);
        }
        after(t + 1, id)?;
    }
    Ok(())
}
