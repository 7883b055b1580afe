//! Power loss: save the identifier mid-run, restore it, finish; the model must be bit for bit
//! the model of the uninterrupted run. Damaged checkpoints must be refused.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use hsid::{
    CheckpointError, Compensated, Error, Excitation, Identifier, Knots, MuZero, Plain, Settings,
    Summation, checkpoint_capacity, compensated_checkpoint_capacity,
};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

fn settings<T: hsid::Real>(mu0: MuZero<T>) -> Settings<T, 14> {
    let knots = Knots::<T, 14>::uniform(T::of(-3.0), T::of(3.0), 7, 7).unwrap();
    Settings::new(knots, 10, 10, mu0)
}

/// A backlash + second-order plant with a little deterministic noise.
fn data<T: hsid::Real>(n: usize) -> Vec<(T, T)> {
    let (mut w, mut y1, mut y2, mut w1, mut w2) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let mut noise = Pcg32::seed_from_u64(9);
    Excitation::<f64, _>::new(-3.0, 3.0, 300, Pcg32::seed_from_u64(4))
        .unwrap()
        .take(n)
        .map(|u| {
            w = w.max((u - 1.0).atan()).min((u + 1.0).atan());
            let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
            (w2, w1, y2, y1) = (w1, w, y1, y);
            let e = (noise.next_u32() as f64 / 4294967296.0 - 0.5) * 0.05;
            (T::of(u), T::of(y + e))
        })
        .collect()
}

fn bits<T: hsid::Real, const M: usize>(m: &hsid::Model<T, M>) -> Vec<u64> {
    let mut v: Vec<u64> = (0..30).map(|k| m.markov(k).to_f64().to_bits()).collect();
    v.extend(m.singular_values().iter().map(|x| x.to_f64().to_bits()));
    for d in [hsid::Direction::Ascending, hsid::Direction::Descending] {
        v.extend(m.border_values(d).iter().map(|x| x.to_f64().to_bits()));
    }
    v.push(m.mu0().to_f64().to_bits());
    v
}

fn resume_is_bit_identical<T: hsid::Real>(mu0: MuZero<T>) {
    resume_is_bit_identical_with::<T, Plain>(
        settings(mu0),
        300 + 4019,
        &[0, 1, 137, 300, 301, 305, 319, 320, 2000, 4318],
    );
}

fn resume_is_bit_identical_with<T: hsid::Real, S: Summation<T, 14, 20>>(
    settings: Settings<T, 14>,
    len: usize,
    cuts: &[usize],
) {
    let settings = |_: MuZero<T>| settings.clone();
    let mu0 = MuZero::Estimate;
    let d = data::<T>(len);
    let mut full = Identifier::<T, 14, 20, S>::new(settings(mu0)).unwrap();
    for &(u, y) in &d {
        full.push(u, y);
    }
    let mut ws = vec![T::zero(); full.workspace_len()];
    let reference = bits(&full.solve(&mut ws).unwrap());
    // Interrupt during the hold, right after it, inside the first k samples and late.
    for &cut in cuts {
        let mut a = Identifier::<T, 14, 20, S>::new(settings(mu0)).unwrap();
        for &(u, y) in &d[..cut] {
            a.push(u, y);
        }
        let mut flash = vec![0u8; a.checkpoint_len()];
        // The settings use the capacities exactly: the capacity is the length.
        assert_eq!(flash.len(), Identifier::<T, 14, 20, S>::CHECKPOINT_CAPACITY);
        a.save(&mut flash).unwrap();
        drop(a);
        let mut b = Identifier::<T, 14, 20, S>::restore_with(&settings(mu0), &flash).unwrap();
        for &(u, y) in &d[cut..] {
            b.push(u, y);
        }
        let got = bits(&b.solve(&mut ws).unwrap());
        assert_eq!(got, reference, "resume after {cut} samples differs");
    }
}

#[test]
fn resume_is_bit_identical_f32_hold() {
    resume_is_bit_identical::<f32>(MuZero::Hold {
        len: 300,
        settle: 150,
    });
}

#[test]
fn resume_is_bit_identical_f64_hold() {
    resume_is_bit_identical::<f64>(MuZero::Hold {
        len: 300,
        settle: 150,
    });
}

#[test]
fn resume_is_bit_identical_f64_estimated_mu0() {
    resume_is_bit_identical::<f64>(MuZero::Estimate);
}

/// Forgetting keeps a running scale that is folded back into the sums every
/// `ln(65536)/ln(1/λ)` samples (λ = 0.999: every 11,085); checkpoints before and after a
/// renormalisation resume bit for bit too.
#[test]
fn resume_is_bit_identical_f32_with_forgetting() {
    let mut s = settings::<f32>(MuZero::Estimate);
    s.forgetting = hsid::Forgetting::Exponential { lambda: 0.999 };
    resume_is_bit_identical_with::<f32, Plain>(s, 14_000, &[5000, 11_084, 11_086, 13_000]);
}

/// Compensated sums: the carries are part of the state, so a resumed run is bit for bit the
/// uninterrupted one (hold, and forgetting across a renormalisation, which scales the carries).
#[test]
fn resume_is_bit_identical_f32_compensated() {
    resume_is_bit_identical_with::<f32, Compensated>(
        settings(MuZero::Hold {
            len: 300,
            settle: 150,
        }),
        300 + 4019,
        &[0, 300, 301, 319, 320, 2000, 4318],
    );
    let mut s = settings::<f32>(MuZero::Estimate);
    s.forgetting = hsid::Forgetting::Exponential { lambda: 0.999 };
    resume_is_bit_identical_with::<f32, Compensated>(s, 14_000, &[5000, 11_084, 11_086, 13_000]);
}

/// The capacities of both kinds, from the sizes of the sums: the compensated checkpoint holds
/// `k·(2m + 1) + 1` more scalars (the carries of the output sums).
#[test]
fn checkpoint_capacities() {
    for (m, k, b) in [(14, 20, 4), (14, 20, 8), (2, 2, 4)] {
        assert_eq!(
            compensated_checkpoint_capacity(m, k, b) - checkpoint_capacity(m, k, b),
            (k * (2 * m + 1) + 1) * b
        );
    }
    assert_eq!(
        Identifier::<f32, 14, 20>::CHECKPOINT_CAPACITY,
        checkpoint_capacity(14, 20, 4)
    );
    assert_eq!(
        Identifier::<f64, 14, 20, Compensated>::CHECKPOINT_CAPACITY,
        compensated_checkpoint_capacity(14, 20, 8)
    );
}

/// A checkpoint of plain sums restored into a compensated identifier (or the other way) is
/// refused with `CheckpointError::Summation`, by `restore` and by `restore_with`.
#[test]
fn a_checkpoint_of_the_other_summation_is_refused() {
    let mu0 = MuZero::Known(0.0f32);
    let d = data::<f32>(500);
    let mut plain = Identifier::<f32, 14, 20>::new(settings(mu0)).unwrap();
    let mut comp = Identifier::<f32, 14, 20, Compensated>::new(settings(mu0)).unwrap();
    for &(u, y) in &d {
        plain.push(u, y);
        comp.push(u, y);
    }
    let mut p = vec![0u8; plain.checkpoint_len()];
    plain.save(&mut p).unwrap();
    let mut c = vec![0u8; comp.checkpoint_len()];
    comp.save(&mut c).unwrap();
    let want = Some(Error::Checkpoint(CheckpointError::Summation));
    assert_eq!(
        Identifier::<f32, 14, 20, Compensated>::restore(&p).err(),
        want
    );
    assert_eq!(Identifier::<f32, 14, 20>::restore(&c).err(), want);
    assert_eq!(
        Identifier::<f32, 14, 20, Compensated>::restore_with(&settings(mu0), &p).err(),
        want
    );
    assert_eq!(
        Identifier::<f32, 14, 20>::restore_with(&settings(mu0), &c).err(),
        want
    );
    // Each restores into its own kind, and the two states differ in their sums.
    assert!(Identifier::<f32, 14, 20>::restore(&p).is_ok());
    assert!(Identifier::<f32, 14, 20, Compensated>::restore(&c).is_ok());
    let msg = Error::Checkpoint(CheckpointError::Summation).to_string();
    assert!(msg.contains("compensated"), "{msg}");
}

#[test]
fn restores_into_a_larger_capacity_with_the_same_model() {
    let d = data::<f32>(300 + 4019);
    let mut small = Identifier::<f32, 14, 20>::new(settings(MuZero::Hold {
        len: 300,
        settle: 150,
    }))
    .unwrap();
    for &(u, y) in &d {
        small.push(u, y);
    }
    let mut flash = vec![0u8; small.checkpoint_len()];
    small.save(&mut flash).unwrap();
    let big = Box::new(Identifier::<f32, 16, 24>::restore(&flash).unwrap());
    let mut ws = vec![0.0f32; small.workspace_len()];
    let a = bits(&small.solve(&mut ws).unwrap());
    let b = bits(&big.solve(&mut ws).unwrap());
    assert_eq!(a, b);
}

#[test]
fn damaged_checkpoints_are_refused() {
    let d = data::<f32>(1000);
    let s = settings(MuZero::Hold {
        len: 300,
        settle: 150,
    });
    let mut id = Identifier::<f32, 14, 20>::new(s.clone()).unwrap();
    for &(u, y) in &d {
        id.push(u, y);
    }
    let mut good = vec![0u8; id.checkpoint_len()];
    id.save(&mut good).unwrap();
    // Every single-bit flip, at every byte (one bit per byte, rotating), is caught.
    for i in 0..good.len() {
        let mut bad = good.clone();
        bad[i] ^= 1 << (i % 8);
        let r = Identifier::<f32, 14, 20>::restore(&bad);
        assert!(r.is_err(), "flip at byte {i} not detected");
    }
    // Truncation at every length.
    for n in 0..good.len() {
        assert!(
            Identifier::<f32, 14, 20>::restore(&good[..n]).is_err(),
            "truncated to {n}"
        );
    }
    // Too small a buffer to save into.
    let mut small = vec![0u8; good.len() - 1];
    assert_eq!(
        id.save(&mut small),
        Err(Error::Checkpoint(CheckpointError::Truncated))
    );
    // Another configuration, another scalar type, another capacity.
    let other = Settings::new(
        Knots::<f32, 14>::uniform(-3.0, 3.0, 6, 8).unwrap(),
        10,
        10,
        s.mu0,
    );
    assert_eq!(
        Identifier::<f32, 14, 20>::restore_with(&other, &good).err(),
        Some(Error::Checkpoint(CheckpointError::SettingsMismatch))
    );
    assert_eq!(
        Identifier::<f64, 14, 20>::restore(&good).err(),
        Some(Error::Checkpoint(CheckpointError::ScalarType))
    );
    assert_eq!(
        Identifier::<f32, 14, 12>::restore(&good).err(),
        Some(Error::Checkpoint(CheckpointError::Capacity))
    );
    let mut wrong = good.clone();
    wrong[0] = b'X';
    assert_eq!(
        Identifier::<f32, 14, 20>::restore(&wrong).err(),
        Some(Error::Checkpoint(CheckpointError::NotACheckpoint))
    );
}

/// A fault recorded before the checkpoint survives it.
#[test]
fn faults_survive_a_checkpoint() {
    let mut id =
        Identifier::<f64, 14, 20>::new(settings(MuZero::Hold { len: 3, settle: 1 })).unwrap();
    id.push(-3.0, 0.0);
    id.push(-3.0, f64::NAN);
    let mut buf = vec![0u8; id.checkpoint_len()];
    id.save(&mut buf).unwrap();
    let back = Identifier::<f64, 14, 20>::restore(&buf).unwrap();
    assert_eq!(back.fault(), id.fault());
    assert!(matches!(
        back.fault(),
        Some(Error::NonFinite { index: 1, .. })
    ));
}
