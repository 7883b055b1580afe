//! Link-time proof of panic-freedom for the per-sample path.
//!
//! The panic handler below calls a function that exists nowhere. If any panic is reachable
//! from the code this binary runs — the Table I generator, δ(t), z(t) and the accumulation of
//! one sample, with inputs the optimiser cannot see (`black_box`) — the linker keeps the
//! handler and fails with an undefined reference to
//! `hsid_per_sample_path_reached_a_panic`. A successful build is the proof; `.ci/run` builds it.
//!
//! What is proven is the per-sample path as the firmware uses it, after `Identifier::new`
//! has validated the settings; the final solve is covered by property tests instead (see the
//! README's "Reliability" section).
#![no_std]
#![no_main]

use core::hint::black_box;
use core::panic::PanicInfo;

use cortex_m_rt::entry;
use hsid::{Excitation, Identifier, Knots, MuZero, Settings};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

type Id = Identifier<f32, 14, 20>;

static mut ID: Id = Id::EMPTY;

#[cfg(feature = "solve")]
static mut WS: [f32; hsid::workspace_len(14, 10, 10)] = [0.0; hsid::workspace_len(14, 10, 10)];

#[entry]
fn main() -> ! {
    // Configuration (validated, fallible) happens once, outside the per-sample path: a
    // configuration error simply parks the core here.
    let Ok(knots) = Knots::<f32, 14>::uniform(black_box(-3.0), black_box(3.0), 7, 7) else {
        park();
    };
    let settings = Settings::new(
        knots,
        black_box(10),
        black_box(10),
        MuZero::Hold {
            len: 300,
            settle: 150,
        },
    );
    // SAFETY: single-threaded bare-metal entry point; the only reference to ID.
    #[allow(static_mut_refs)]
    let id = unsafe { &mut ID };
    if id.reset(settings).is_err() {
        park();
    }
    let Ok(mut excitation) = Excitation::new(
        black_box(-3.0f32),
        black_box(3.0),
        300,
        Pcg32::seed_from_u64(black_box(1)),
    ) else {
        park();
    };
    loop {
        // The per-sample path: next excitation level, then push with an arbitrary output.
        let u = excitation.next().unwrap_or(0.0);
        id.push(black_box(u), black_box(u * 0.5));
        // Arbitrary, unseen inputs too (NaN, out of range, anything).
        id.push(
            black_box(f32::from_bits(black_box(0x7fc0_0000))),
            black_box(1.0),
        );
        black_box(id.fault());
        #[cfg(feature = "solve")]
        {
            // SAFETY: single-threaded; the only reference to WS.
            #[allow(static_mut_refs)]
            let ws = unsafe { &mut WS };
            black_box(id.solve(ws).is_ok());
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

/// With `--features list`, a real panic handler: the binary links and the panic locations
/// left in it (`strings`) list what keeps a panic reachable.
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
