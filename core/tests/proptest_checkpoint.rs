//! Property tests of checkpoints (power loss), in `f32` and `f64`.
//!
//! * Random states — random valid settings (knots, horizons, bases, weightings, μ0 modes,
//!   forgetting) after a random record, faults included — round-trip bit for bit: the
//!   restored identifier saves the same bytes, solves to the same bits (or the same error),
//!   and after the same further samples still saves the same bytes and solves to the same
//!   bits as the original; it also restores with its own settings and into larger
//!   capacities.
//! * Restoring random bytes, random bytes behind a valid header, truncated checkpoints and
//!   corrupted checkpoints never panics; every truncation and every single corrupted byte is
//!   refused with a typed error.
//! * Checkpoints corrupted *with the checksums recomputed* (what a buggy writer or a forger
//!   would produce) never panic on restore, and whatever they restore to never panics on
//!   `push` or `solve`: a finite model or a typed error.
//!
//! Cases: 2 × 1,000 round trips and 2 × 3,000 damaged checkpoints (seeded, see
//! `proptest_common::config`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::proptest_common;

use hsid::{
    Basis, CheckpointError, Error, Forgetting, Identifier, Knots, Method, MuZero, Order, Real,
    Settings,
};
use proptest::prelude::*;
use proptest_common::{
    Id, K, M, PwlSwitch, Tally, all_finite, check_model, enough_instruments, fix_checksums,
    knot_vector, outcome_bits, plant, run_cases, settings_end, table1,
};

/// Cases per property and scalar type.
const CASES: u32 = 1_000;

/// A valid configuration and a record (with optional bad samples) to bring it to a state.
#[derive(Clone, Debug)]
struct State {
    asc: Vec<f64>,
    desc: Vec<f64>,
    f: usize,
    p: usize,
    ramp: bool,
    method: u8,
    mu0: u8,
    order: Option<usize>,
    lambda: Option<f64>,
    hold: usize,
    cut: usize,
    more: usize,
    bad: Option<(usize, u8)>,
    seed: u64,
    plant: proptest_common::Lti,
}

fn state() -> impl Strategy<Value = State> {
    (1usize..=3, 1usize..=3)
        .prop_flat_map(|(na, nd)| {
            (
                knot_vector(-3.0, 3.0, na, 0.1),
                knot_vector(-3.0, 3.0, nd, 0.1),
                (2usize..=4).prop_flat_map(|f| (Just(f), f.div_ceil(2)..=K - f)),
                (any::<bool>(), 0u8..4, 0u8..3),
                prop_oneof![Just(None), Just(Some(1))],
                prop_oneof![3 => Just(None), 1 => (0.9f64..1.0).prop_map(Some)],
                (
                    5usize..40,
                    prop_oneof![0usize..60, 60usize..500],
                    0usize..100,
                ),
                prop_oneof![3 => Just(None), 1 => (0usize..500, 0u8..4).prop_map(Some)],
                any::<u64>(),
                plant(),
            )
        })
        .prop_map(
            |(
                asc,
                desc,
                (f, p),
                (ramp, method, mu0),
                order,
                lambda,
                (hold, cut, more),
                bad,
                seed,
                plant,
            )| State {
                asc,
                desc,
                f,
                p,
                ramp,
                method,
                mu0,
                order,
                lambda,
                hold,
                cut,
                more,
                bad,
                seed,
                plant,
            },
        )
}

impl State {
    fn settings<T: Real>(&self) -> Settings<T, M> {
        let a: Vec<T> = self.asc.iter().map(|&v| T::of(v)).collect();
        let d: Vec<T> = self.desc.iter().map(|&v| T::of(v)).collect();
        let mu0 = match self.mu0 {
            0 => MuZero::Hold {
                len: self.hold,
                settle: self.hold / 2,
            },
            1 => MuZero::Known(T::of(0.1)),
            _ => MuZero::Estimate,
        };
        let mut s = Settings::new(Knots::new(&a, &d).unwrap(), self.f, self.p, mu0);
        s.basis = if self.ramp { Basis::Ramp } else { Basis::Hat };
        s.method =
            [Method::PiMoesp, Method::PoMoesp, Method::N4sid, Method::Cva][self.method as usize];
        s.order = self.order.map_or(Order::Auto, Order::Fixed);
        if let Some(l) = self.lambda {
            s.forgetting = Forgetting::Exponential { lambda: T::of(l) };
        }
        s
    }

    /// The whole record: the hold (if any), the excitation, one bad sample if asked.
    fn record<T: Real>(&self, s: &Settings<T, M>) -> Vec<(T, T)> {
        let v = |k: &[f64]| -> Vec<f64> { (0..k.len()).map(|i| 0.1 + 0.3 * i as f64).collect() };
        let mut sw = PwlSwitch::new(
            self.asc.clone(),
            v(&self.asc),
            self.desc.clone(),
            v(&self.desc),
        );
        let mut plant = self.plant.clone();
        let hold = s.mu0.hold_len();
        let mut data = table1(
            &s.knots,
            hold,
            hold + self.cut + self.more,
            self.seed,
            &mut sw,
            &mut plant,
        );
        if let Some((at, kind)) = self.bad
            && let Some(d) = data.get_mut(at)
        {
            match kind {
                0 => d.0 = T::of(f64::NAN),
                1 => d.1 = T::of(f64::INFINITY),
                2 => d.0 = s.knots.u_max() + T::one(),
                _ => d.0 = (s.knots.u_min() + s.knots.u_max()) / T::of(2.0),
            }
        }
        data
    }
}

fn save<T: Real, const MM: usize, const KK: usize>(id: &Identifier<T, MM, KK>) -> Vec<u8> {
    let mut buf = vec![0u8; id.checkpoint_len()];
    let n = id.save(&mut buf).unwrap();
    assert_eq!(n, buf.len());
    buf
}

fn solve_bits<T: Real, const MM: usize, const KK: usize>(
    id: &Identifier<T, MM, KK>,
) -> Result<Vec<u64>, Error> {
    let mut ws = vec![T::zero(); id.workspace_len()];
    outcome_bits(&id.solve(&mut ws))
}

fn round_trip<T: Real>(st: State, tally: &Tally) -> Result<(), TestCaseError> {
    let s = st.settings::<T>();
    if !enough_instruments(&s) {
        // Refused by `new` (`TooFewInstruments`; the oracle of `proptest_config.rs`).
        let refused = matches!(
            Identifier::<T, M, K>::new(s.clone()),
            Err(Error::TooFewInstruments { .. })
        );
        prop_assert!(refused, "not refused with TooFewInstruments");
        tally.count("settings refused: too few instruments");
        return Ok(());
    }
    let data = st.record(&s);
    let hold = s.mu0.hold_len();
    let cut = (hold + st.cut).min(data.len());
    let mut a = Id::<T>::new(s.clone()).unwrap();
    for &(u, y) in &data[..cut] {
        a.push(u, y);
    }
    let bytes = save(&a);
    let b = Id::<T>::restore(&bytes).map_err(|e| TestCaseError::fail(format!("restore: {e}")))?;
    let b2 = Id::<T>::restore_with(&s, &bytes)
        .map_err(|e| TestCaseError::fail(format!("restore_with: {e}")))?;
    prop_assert_eq!(&save(&b), &bytes);
    prop_assert_eq!(&save(&b2), &bytes);
    prop_assert_eq!(b.fault(), a.fault());
    prop_assert_eq!(b.samples(), a.samples());
    let before = solve_bits(&a);
    prop_assert_eq!(&solve_bits(&b), &before);
    tally.count(if before.is_ok() {
        "state solves"
    } else {
        "state refuses to solve"
    });
    // Larger capacities restore the same state and solve to the same bits.
    let big = Box::new(
        Identifier::<T, { M + 2 }, { K + 3 }>::restore(&bytes)
            .map_err(|e| TestCaseError::fail(format!("restore into larger capacity: {e}")))?,
    );
    prop_assert_eq!(&solve_bits(&*big), &before);
    // Continue both with the same samples.
    let (mut a, mut b) = (a, b);
    for &(u, y) in &data[cut..] {
        a.push(u, y);
        b.push(u, y);
    }
    prop_assert_eq!(save(&a), save(&b));
    prop_assert_eq!(solve_bits(&a), solve_bits(&b));
    if a.fault().is_some() {
        tally.count("with a fault");
    }
    Ok(())
}

/// Whatever a checkpoint restores to must behave: push and solve never panic, and a model is
/// finite with `G(1) = 1`.
fn exercise<T: Real, const MM: usize, const KK: usize>(
    id: &mut Identifier<T, MM, KK>,
    tally: &Tally,
) -> Result<(), TestCaseError> {
    let s = id.settings().clone();
    let mut ws = vec![T::zero(); id.workspace_len().min(1 << 20)];
    match id.solve(&mut ws) {
        Ok(m) => {
            tally.count("restored: solves");
            prop_assert!(
                all_finite(&m),
                "non-finite model from a restored state: {m:?}"
            );
            check_model(&m, s.f)?;
        }
        Err(_) => tally.count("restored: typed error from solve"),
    }
    let (lo, hi) = (s.knots.u_min(), s.knots.u_max());
    for i in 0..20 {
        let u = lo + (hi - lo) * T::of(f64::from(i % 5) / 4.0);
        id.push(u, T::of(0.1 * f64::from(i)));
    }
    let _ = id.solve(&mut ws);
    Ok(())
}

#[derive(Clone, Debug)]
enum Damage {
    /// Arbitrary bytes.
    Random(Vec<u8>),
    /// A valid header (magic, version, scalar size) followed by arbitrary bytes.
    Header(Vec<u8>),
    /// A real checkpoint cut at a fraction of its length.
    Truncate(State, f64),
    /// A real checkpoint with one byte changed.
    Flip(State, prop::sample::Index, u8),
    /// A real checkpoint with bytes changed and the checksums recomputed.
    Forge(State, Vec<(prop::sample::Index, u8)>, bool),
    /// A real checkpoint with the sample counters (count, index) set to extreme values, or a
    /// scalar of the state set to NaN, ±inf or a huge value, checksums recomputed.
    ForgeField(State, u8, u64, prop::sample::Index),
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        proptest::collection::vec(any::<u8>(), 0..600).prop_map(Damage::Random),
        proptest::collection::vec(any::<u8>(), 0..600).prop_map(Damage::Header),
        (state(), 0.0f64..1.0).prop_map(|(s, f)| Damage::Truncate(s, f)),
        (state(), any::<prop::sample::Index>(), 1u8..=255)
            .prop_map(|(s, i, x)| Damage::Flip(s, i, x)),
        (
            state(),
            proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
            any::<bool>()
        )
            .prop_map(|(s, v, in_settings)| Damage::Forge(s, v, in_settings)),
        (
            state(),
            0u8..4,
            prop_oneof![
                Just(0u64),
                Just(1),
                Just(7),
                Just(u64::MAX),
                Just(u64::MAX / 2),
                Just(u64::from(u32::MAX) + 1),
                any::<u64>()
            ],
            any::<prop::sample::Index>(),
        )
            .prop_map(|(s, which, v, at)| Damage::ForgeField(s, which, v, at)),
    ]
}

/// A genuine checkpoint of the state (and its identifier type's scalar size).
fn genuine<T: Real>(st: &State) -> Vec<u8> {
    let s = st.settings::<T>();
    let data = st.record(&s);
    let mut id = Id::<T>::new(s.clone()).unwrap();
    for &(u, y) in data.iter().take(s.mu0.hold_len() + st.cut) {
        id.push(u, y);
    }
    save(&id)
}

fn restore_any<T: Real>(
    bytes: &[u8],
    tally: &Tally,
    expect_err: bool,
) -> Result<(), TestCaseError> {
    match Id::<T>::restore(bytes) {
        Ok(mut id) => {
            prop_assert!(!expect_err, "a damaged checkpoint was accepted");
            tally.count("accepted");
            exercise(&mut id, tally)?;
        }
        Err(e) => {
            let d = format!("{e:?}");
            tally.count(format!(
                "refused: {}",
                d.split([' ', '{']).next().unwrap_or("")
            ));
            prop_assert!(!e.to_string().is_empty());
        }
    }
    // Other capacities and the other scalar type must not panic either.
    let _ = Identifier::<T, 2, 2>::restore(bytes);
    if let Ok(mut big) = Identifier::<T, { M + 4 }, { K + 4 }>::restore(bytes).map(Box::new) {
        exercise(&mut *big, tally)?;
    }
    Ok(())
}

fn damaged<T: Real>(d: Damage, tally: &Tally) -> Result<(), TestCaseError> {
    let b = T::BYTES;
    match d {
        Damage::Random(bytes) => restore_any::<T>(&bytes, tally, false),
        Damage::Header(mut rest) => {
            let mut bytes = b"HSID".to_vec();
            bytes.extend_from_slice(&hsid::CHECKPOINT_VERSION.to_le_bytes());
            bytes.push(b as u8);
            bytes.append(&mut rest);
            restore_any::<T>(&bytes, tally, false)
        }
        Damage::Truncate(st, frac) => {
            let bytes = genuine::<T>(&st);
            let n = ((bytes.len() as f64) * frac) as usize;
            let r = Id::<T>::restore(&bytes[..n]);
            prop_assert_eq!(
                r.err(),
                Some(Error::Checkpoint(CheckpointError::Truncated)),
                "cut at {} of {}",
                n,
                bytes.len()
            );
            tally.count("truncation refused");
            Ok(())
        }
        Damage::Flip(st, at, x) => {
            let mut bytes = genuine::<T>(&st);
            let i = at.index(bytes.len());
            bytes[i] ^= x;
            // CRC-32 detects every error confined to one byte.
            restore_any::<T>(&bytes, tally, true)
        }
        Damage::Forge(st, edits, in_settings) => {
            let mut bytes = genuine::<T>(&st);
            let end = settings_end(&bytes, b).unwrap();
            for (at, v) in edits {
                let i = if in_settings {
                    11 + at.index(end - 11)
                } else {
                    end + at.index(bytes.len() - 4 - end)
                };
                bytes[i] = v;
            }
            fix_checksums(&mut bytes, b);
            restore_any::<T>(&bytes, tally, false)
        }
        Damage::ForgeField(st, which, v, at) => {
            let mut bytes = genuine::<T>(&st);
            let end = settings_end(&bytes, b).unwrap();
            match which {
                // The accumulated count, then the pushed-sample index (u64 each).
                0 => bytes[end..end + 8].copy_from_slice(&v.to_le_bytes()),
                1 => bytes[end + 8..end + 16].copy_from_slice(&v.to_le_bytes()),
                // A scalar anywhere in the state (aligned to the scalar size from the start
                // of the state), set to a special value.
                _ => {
                    let slots = (bytes.len() - 4 - end - 16) / b;
                    let i = end + 16 + b * at.index(slots.max(1));
                    let x = [
                        f64::NAN,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        1e300,
                        -1e30,
                        0.0,
                    ][(v % 6) as usize];
                    let mut tmp = [0u8; 8];
                    T::of(x).write_le(&mut tmp);
                    if i + b <= bytes.len() - 4 {
                        bytes[i..i + b].copy_from_slice(&tmp[..b]);
                    }
                }
            }
            fix_checksums(&mut bytes, b);
            restore_any::<T>(&bytes, tally, false)
        }
    }
}

fn suite<T: Real>(seed: u64, name: &str) {
    let tally = Tally::default();
    run_cases(CASES, seed, state(), |st| round_trip::<T>(st, &tally));
    tally.print(&format!("{name}: round trips"));
    let tally = Tally::default();
    run_cases(3 * CASES, seed + 1, damage(), |d| damaged::<T>(d, &tally));
    tally.print(&format!("{name}: damaged checkpoints"));
    assert!(
        tally.get("accepted") > 0,
        "no forged checkpoint got through to the state checks"
    );
}

#[test]
fn checkpoints_f64() {
    suite::<f64>(0x4853_4944_0031, "checkpoints, f64");
}

#[test]
fn checkpoints_f32() {
    suite::<f32>(0x4853_4944_0033, "checkpoints, f32");
}
