//! The per-sample update in the hat basis against the definition of the lagged sums,
//! `R_τ = Σ_t w_t · z(t−τ) z(t)ᵀ` (and the products with ȳ), formed here from the terms
//! `for_each_nonzero` visits, sample by sample in the order they arrive. (Not from the dense
//! regressor: a compensated sum changes when a zero is added with a carry pending.) The update keeps each sample's two hat terms
//! from when it entered and walks the ring in two stretches; the sums must agree bit for bit,
//! with and without forgetting, with samples on the first segment (one term), on a knot, and
//! with shared knots, for plain and compensated sums.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::needless_range_loop,
    missing_docs
)]

use hsid::accumulation::{Accumulator, Carries};
use hsid::regressor::for_each_nonzero;
use hsid::{Basis, Direction, Knots, Located};

const M: usize = 8;
const K: usize = 6;

/// Samples covering every segment of both paths, the first segment (one hat term), the
/// interval's ends and an interior knot exactly.
fn samples(knots: &Knots<f32, M>, n: usize) -> Vec<(Located<f32>, f32)> {
    let mut state = 0x9e37_79b9_u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    (0..n)
        .map(|t| {
            let dir = if next() < 0.5 {
                Direction::Ascending
            } else {
                Direction::Descending
            };
            let u = match t % 7 {
                0 => 0.0,
                1 => 1.0,
                2 => 0.25,
                _ => next(),
            };
            (knots.locate(dir, u), 3.0 * next() - 1.5)
        })
        .collect()
}

/// `s += x` compensated, as the accumulator does it.
fn kahan(s: &mut f32, c: &mut f32, x: f32) {
    let y = x - *c;
    let t = *s + y;
    *c = (t - *s) - y;
    *s = t;
}

/// Pushes `data` and checks every lagged sum, `Σ z` and `Σ ȳ` against the definition.
fn check(knots: &Knots<f32, M>, lambda: f32, compensated: bool, data: &[(Located<f32>, f32)]) {
    let k = 5;
    let m = knots.channels();
    let mut acc = Accumulator::<f32, M, K>::new(k).unwrap();
    acc.set_forgetting(lambda).unwrap();
    let mut carries = Carries::<f32, M, K>::ZERO;
    let z: Vec<Vec<(usize, f32)>> = data
        .iter()
        .map(|(at, _)| {
            let mut terms = Vec::new();
            for_each_nonzero(knots, Basis::Hat, at, |i, v| terms.push((i, v)));
            terms
        })
        .collect();
    // Reference: [τ][i][j] for z zᵀ, [τ][i] for z ȳ and ȳ z, [τ] for ȳ ȳ, with carries.
    let mut zz = vec![[[0.0f32; M]; M]; k];
    let (mut zy, mut zy_c) = (vec![[0.0f32; M]; k], vec![[0.0f32; M]; k]);
    let (mut yz, mut yz_c) = (vec![[0.0f32; M]; k], vec![[0.0f32; M]; k]);
    let (mut yy, mut yy_c) = (vec![0.0f32; k], vec![0.0f32; k]);
    let mut sum_z = [0.0f32; M];
    let mut w = 1.0f32;
    for (t, &(at, y)) in data.iter().enumerate() {
        if compensated {
            acc.push_compensated(&mut carries, knots, Basis::Hat, at, y);
        } else {
            acc.push(knots, Basis::Hat, at, y);
        }
        if lambda != 1.0 {
            w /= lambda;
        }
        for tau in 0..k.min(t + 1) {
            let (ze, ye) = (&z[t - tau], data[t - tau].1 * w);
            let add = |s: &mut f32, c: &mut f32, x: f32| {
                if compensated { kahan(s, c, x) } else { *s += x }
            };
            for &(i, zi) in ze {
                for &(j, zj) in &z[t] {
                    zz[tau][i][j] += zi * w * zj;
                }
                add(&mut zy[tau][i], &mut zy_c[tau][i], zi * w * y);
            }
            for &(j, zj) in &z[t] {
                add(&mut yz[tau][j], &mut yz_c[tau][j], ye * zj);
            }
            add(&mut yy[tau], &mut yy_c[tau], ye * y);
        }
        for &(i, v) in &z[t] {
            sum_z[i] += v * w;
        }
    }
    for tau in 0..k {
        let lag = acc.lag(tau).unwrap();
        for i in 0..m {
            for j in 0..m {
                assert_eq!(
                    lag.zz[i][j].to_bits(),
                    zz[tau][i][j].to_bits(),
                    "zz τ={tau} {i},{j}"
                );
            }
            assert_eq!(lag.zy[i].to_bits(), zy[tau][i].to_bits(), "zy τ={tau} {i}");
            assert_eq!(lag.yz[i].to_bits(), yz[tau][i].to_bits(), "yz τ={tau} {i}");
            if compensated {
                let c = &carries.lags[tau];
                assert_eq!(
                    c.zy[i].to_bits(),
                    zy_c[tau][i].to_bits(),
                    "zy carry τ={tau} {i}"
                );
                assert_eq!(
                    c.yz[i].to_bits(),
                    yz_c[tau][i].to_bits(),
                    "yz carry τ={tau} {i}"
                );
            }
        }
        assert_eq!(lag.yy.to_bits(), yy[tau].to_bits(), "yy τ={tau}");
    }
    let (sz, _) = acc.sums();
    for i in 0..m {
        assert_eq!(sz[i].to_bits(), sum_z[i].to_bits(), "Σ z {i}");
    }
}

#[test]
fn hat_update_matches_the_definition_bit_for_bit() {
    let paths = Knots::<f32, M>::new(&[0.0, 0.25, 0.5, 1.0], &[0.0, 0.25, 0.4, 0.7, 1.0]).unwrap();
    let shared = Knots::<f32, M>::shared(&[0.0, 0.25, 0.6, 1.0]).unwrap();
    for knots in [&paths, &shared] {
        let data = samples(knots, 300);
        // Some samples lie on the first segment, where z has a single term.
        assert!(data.iter().any(|(at, _)| at.segment == 0));
        for lambda in [1.0, 0.995] {
            for compensated in [false, true] {
                check(knots, lambda, compensated, &data);
            }
        }
    }
}
