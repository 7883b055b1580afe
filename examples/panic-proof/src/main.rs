//! Link-time proof of panic-freedom for the per-sample path and the final solve.
//!
//! The panic handler below calls a function that exists nowhere. If any panic is reachable
//! from the code this binary runs, the linker keeps the handler and fails with an undefined
//! reference to `hsid_per_sample_path_reached_a_panic`. A successful build is the proof;
//! `.ci/run` builds it twice:
//!
//! - `cargo build --release`: the per-sample path — the Table I generator, δ(t), the hold,
//!   z(t) and the accumulation of one sample — as the firmware runs it (`f32`, plain sums),
//!   with inputs the optimiser cannot see (`black_box`), NaN among them;
//! - `cargo build --release --features solve`: the same, plus `Identifier::solve` and
//!   `Identifier::solve_structured` on the accumulated statistics, for `f32` with plain and with compensated output sums and for
//!   `f64`, with every choice of the settings (method, order, basis, μ0, forgetting, `f`, `p`)
//!   and the workspace length hidden from the optimiser, so that every branch is kept.
//!
//! - `cargo build --release --features store`: the per-sample path, plus a checkpoint saved
//!   (`Identifier::save`) into the power-loss-safe store (`Store::save` on a RAM flash), the
//!   store's pages damaged at an unseen byte, `Store::load` and `Identifier::restore_with`,
//!   with the region and every length hidden from the optimiser.
//!
//! What is proven is the code after `Identifier::new`/`reset` has validated the settings
//! (those return `Err` for bad settings, which parks the core here). A third build with
//! `--features control` adds one unchecked index and must fail to link, which shows the proof
//! is not vacuous.
#![no_std]
#![no_main]

use core::hint::black_box;
use core::panic::PanicInfo;

use cortex_m_rt::entry;
#[cfg(feature = "solve")]
use hsid::Poles;
use hsid::{
    Basis, Excitation, Forgetting, Identifier, Knots, Method, MuZero, Order, Plain, Real, Settings,
    Summation,
};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// Channels (knots of both paths), lags and the horizon capacity, as in the firmware.
const M: usize = 14;
const K: usize = 20;
const H: usize = 10;
/// Workspace of the solve for `f = p = 10` at the default block width.
#[cfg(feature = "solve")]
const WS_LEN: usize = hsid::workspace_len(M, 10, 10);

type Id<T, S> = Identifier<T, M, K, S, H>;

static mut ID: Id<f32, Plain> = Id::EMPTY;

#[cfg(feature = "solve")]
static mut ID_COMPENSATED: Id<f32, hsid::Compensated> = Id::EMPTY;
#[cfg(feature = "solve")]
static mut ID_F64: Id<f64, Plain> = Id::EMPTY;
#[cfg(feature = "solve")]
static mut WS: [f32; WS_LEN] = [0.0; WS_LEN];
#[cfg(feature = "solve")]
static mut WS_F64: [f64; WS_LEN] = [0.0; WS_LEN];

#[cfg(feature = "store")]
mod store;

#[entry]
fn main() -> ! {
    // Configuration (validated, fallible) happens once, outside the per-sample path: a
    // configuration error simply parks the core here.
    // SAFETY (all `static mut` below): single-threaded bare-metal entry point; these are the
    // only references.
    #[allow(static_mut_refs)]
    let id = unsafe { &mut ID };
    let mut excitation = configure(id);
    #[cfg(feature = "solve")]
    #[allow(static_mut_refs)]
    let (id_c, id_64, ws, ws_64) =
        unsafe { (&mut ID_COMPENSATED, &mut ID_F64, &mut WS, &mut WS_F64) };
    #[cfg(feature = "solve")]
    let (mut ex_c, mut ex_64) = (configure(id_c), configure(id_64));
    loop {
        step(id, &mut excitation);
        #[cfg(feature = "store")]
        store::save_load_restore(id);
        #[cfg(feature = "solve")]
        {
            step(id_c, &mut ex_c);
            step(id_64, &mut ex_64);
            // Any workspace length, the too-short ones included.
            let n = black_box(WS_LEN);
            // Either pole policy (`solve` is `solve_with(.., Poles::Stable)`).
            let poles = if black_box(n).is_multiple_of(2) {
                Poles::Stable
            } else {
                Poles::Any
            };
            black_box(id.solve(ws.get_mut(..n).unwrap_or(&mut [])).is_ok());
            black_box(
                id_c.solve_with(ws.get_mut(..n).unwrap_or(&mut []), poles)
                    .is_ok(),
            );
            black_box(
                id_64
                    .solve_with(ws_64.get_mut(..n).unwrap_or(&mut []), poles)
                    .is_ok(),
            );
            // The structured solve, with the same hidden lengths and settings.
            black_box(
                id.solve_structured_with(ws.get_mut(..n).unwrap_or(&mut []), poles)
                    .is_ok(),
            );
            black_box(
                id_c.solve_structured(ws.get_mut(..n).unwrap_or(&mut []))
                    .is_ok(),
            );
            black_box(
                id_64
                    .solve_structured_with(ws_64.get_mut(..n).unwrap_or(&mut []), poles)
                    .is_ok(),
            );
        }
        // Negative control (`--features control`): an index the optimiser cannot check must
        // make the link fail, which shows the proof is not vacuous.
        #[cfg(feature = "control")]
        {
            let v = [1u8; 4];
            black_box(v[black_box(7usize)]);
        }
    }
}

/// Validates settings the optimiser cannot see into `id` and returns the excitation
/// generator; parks the core on a configuration error.
fn configure<T: Real, S: Summation<T, M, K>>(id: &mut Id<T, S>) -> Excitation<T, Pcg32> {
    let Ok(knots) = Knots::<T, M>::uniform(black_box(T::of(-3.0)), black_box(T::of(3.0)), 7, 7)
    else {
        park();
    };
    let mut settings = Settings::new(
        knots,
        black_box(10),
        black_box(10),
        black_box(MuZero::Hold {
            len: 300,
            settle: 150,
        }),
    );
    settings.basis = black_box(Basis::Hat);
    settings.order = black_box(Order::Auto);
    settings.method = black_box(Method::PiMoesp);
    settings.forgetting = black_box(Forgetting::None);
    if id.reset(settings).is_err() {
        park();
    }
    let Ok(excitation) = Excitation::new(
        black_box(T::of(-3.0)),
        black_box(T::of(3.0)),
        300,
        Pcg32::seed_from_u64(black_box(1)),
    ) else {
        park();
    };
    excitation
}

/// The per-sample path: next excitation level, then push with an arbitrary output, then
/// arbitrary, unseen inputs too (NaN, out of range, anything).
fn step<T: Real, S: Summation<T, M, K>>(id: &mut Id<T, S>, excitation: &mut Excitation<T, Pcg32>) {
    let u = excitation.next().unwrap_or(T::zero());
    id.push(black_box(u), black_box(u * T::of(0.5)));
    id.push(
        black_box(T::of(f64::from_bits(black_box(0x7ff8_0000_0000_0000)))),
        black_box(T::one()),
    );
    black_box(id.fault());
}

/// With `--features list`, a real panic handler: the binary links and the panic locations
/// left in it (`strings`, or the calls to `core::panicking` in the disassembly) list what
/// keeps a panic reachable.
#[cfg(feature = "list")]
#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    black_box(info);
    park();
}

#[cfg(not(feature = "list"))]
#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    unsafe extern "C" {
        /// Defined nowhere: referencing it fails the link if a panic is reachable.
        fn hsid_per_sample_path_reached_a_panic() -> !;
    }
    // SAFETY: never executed — the program only links if this call is unreachable.
    unsafe { hsid_per_sample_path_reached_a_panic() }
}

/// Parks the core (a configuration error, or the `list` panic handler).
fn park() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
