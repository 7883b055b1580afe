//! The horizon capacity `H` is a bound, not a parameter of the method: the same data give the
//! same model, bit for bit, for every `H >= f`; `f > H` is a typed error naming the capacity;
//! and horizons beyond the default capacity identify the plant.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use hsid::{
    Basis, Direction, Error, Excitation, Identifier, Knots, Method, Model, MuZero, Order, Plain,
    Real, Settings,
};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// A backlash + second-order plant (poles `0.9512 e^{±j·0.1}`, unit static gain) with a
/// little deterministic noise.
fn data<T: Real>(n: usize) -> Vec<(T, T)> {
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

/// Every number of a model, as bits.
fn bits<T: Real, const M: usize, const H: usize>(m: &Model<T, M, H>) -> Vec<u64> {
    let n = m.order();
    let mut v = vec![n as u64, m.horizon() as u64, m.columns()];
    v.extend((0..n * n).map(|i| m.a(i / n, i % n).to_f64().to_bits()));
    v.extend(m.b().iter().chain(m.c()).map(|x| x.to_f64().to_bits()));
    v.push(m.d().to_f64().to_bits());
    v.push(m.static_gain().to_f64().to_bits());
    v.extend(m.singular_values().iter().map(|x| x.to_f64().to_bits()));
    v.extend(
        m.whitened_singular_values()
            .iter()
            .map(|x| x.to_f64().to_bits()),
    );
    for d in [Direction::Ascending, Direction::Descending] {
        v.extend(m.border_values(d).iter().map(|x| x.to_f64().to_bits()));
    }
    v.push(m.mu0().to_f64().to_bits());
    let mut state = m.rest_state();
    v.extend(
        [0.5, 1.5, -2.0, 2.9, 0.1]
            .iter()
            .map(|&u| m.step(&mut state, T::of(u)).to_f64().to_bits()),
    );
    v
}

fn settings<T: Real>(f: usize, p: usize, method: Method, basis: Basis) -> Settings<T, 14> {
    let knots = Knots::<T, 14>::uniform(T::of(-3.0), T::of(3.0), 7, 7).unwrap();
    let mut s = Settings::new(knots, f, p, MuZero::Estimate);
    s.method = method;
    s.basis = basis;
    s
}

/// The model of an identifier with horizon capacity `H` (and block rows `K`).
fn solve<T: Real, const K: usize, const H: usize>(
    s: &Settings<T, 14>,
    d: &[(T, T)],
) -> Result<Model<T, 14, H>, Error> {
    let mut id = Box::new(Identifier::<T, 14, K, Plain, H>::new(s.clone())?);
    for &(u, y) in d {
        id.push(u, y);
    }
    let mut ws = vec![T::zero(); id.workspace_len()];
    id.solve(&mut ws)
}

fn same_model_for_every_capacity<T: Real>() {
    let d = data::<T>(6000);
    for method in [Method::PiMoesp, Method::PoMoesp, Method::N4sid, Method::Cva] {
        for basis in [Basis::Hat, Basis::Ramp] {
            // The paper's f = p = 10: the exact capacity, the default and a desktop one.
            let s = settings::<T>(10, 10, method, basis);
            let default = bits(&solve::<T, 20, 12>(&s, &d).unwrap());
            assert_eq!(default, bits(&solve::<T, 20, 10>(&s, &d).unwrap()));
            assert_eq!(default, bits(&solve::<T, 40, 40>(&s, &d).unwrap()));
            // The default's largest f, padded into a larger capacity.
            let s = settings::<T>(12, 8, method, basis);
            let full = bits(&solve::<T, 20, 12>(&s, &d).unwrap());
            assert_eq!(full, bits(&solve::<T, 24, 17>(&s, &d).unwrap()));
        }
    }
}

#[test]
fn same_model_for_every_capacity_f64() {
    same_model_for_every_capacity::<f64>();
}

#[test]
fn same_model_for_every_capacity_f32() {
    same_model_for_every_capacity::<f32>();
}

/// A checkpoint of a device's exact capacity restores into a larger one and solves to the
/// same bits.
#[test]
fn checkpoint_restores_into_a_larger_capacity() {
    let d = data::<f32>(5000);
    let s = settings::<f32>(10, 10, Method::PiMoesp, Basis::Hat);
    let mut device = Identifier::<f32, 14, 20, Plain, 10>::new(s).unwrap();
    for &(u, y) in &d {
        device.push(u, y);
    }
    let mut flash = vec![0u8; device.checkpoint_len()];
    device.save(&mut flash).unwrap();
    let host = Box::new(Identifier::<f32, 32, 48, Plain, 40>::restore(&flash).unwrap());
    let mut ws = vec![0.0f32; device.workspace_len()];
    let on_device = bits(&device.solve(&mut ws).unwrap());
    let mut ws = vec![0.0f32; host.workspace_len()];
    assert_eq!(on_device, bits(&host.solve(&mut ws).unwrap()));
}

/// `f` above `H` or `f + p` above `K` is `InvalidHorizon` with both capacities, and the
/// message says which bound and what to change.
#[test]
fn horizon_beyond_capacity_is_a_typed_error() {
    let s = settings::<f64>(11, 5, Method::PiMoesp, Basis::Hat);
    let err = Identifier::<f64, 14, 40, Plain, 10>::new(s).unwrap_err();
    assert_eq!(
        err,
        Error::InvalidHorizon {
            f: 11,
            k: 16,
            max_f: 10,
            max_k: 40
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("2 <= f <= 10 (the horizon capacity H)"),
        "{text}"
    );
    assert!(
        text.contains("f + p <= 40 (the block-row capacity K)"),
        "{text}"
    );
    let s = settings::<f64>(10, 31, Method::PiMoesp, Basis::Hat);
    let err = Identifier::<f64, 14, 40, Plain, 40>::new(s).unwrap_err();
    assert_eq!(
        err,
        Error::InvalidHorizon {
            f: 10,
            k: 41,
            max_f: 40,
            max_k: 40
        }
    );
}

/// At `f = p = 30`, far beyond the default capacity, second order: the poles of the plant,
/// `0.9512 e^{±j·0.1}` (`z² − 1.8858 z + 0.9048`), and unit static gain.
#[test]
fn long_horizons_identify_the_plant() {
    let d = data::<f64>(20000);
    let mut s = settings::<f64>(30, 30, Method::PiMoesp, Basis::Hat);
    s.order = Order::Fixed(2);
    let m = solve::<f64, 60, 32>(&s, &d).unwrap();
    assert_eq!(
        (m.order(), m.horizon(), m.singular_values().len()),
        (2, 30, 30)
    );
    let trace = m.a(0, 0) + m.a(1, 1);
    let det = m.a(0, 0) * m.a(1, 1) - m.a(0, 1) * m.a(1, 0);
    assert!((trace - 1.8858).abs() < 5e-3, "trace {trace}");
    assert!((det - 0.9048).abs() < 5e-3, "det {det}");
    assert!((m.static_gain() - 1.0).abs() < 1e-9);
}
