//! Fixtures of the tests of dynamics beyond the linear `G`: a small order-2 model and a
//! staircase input. Shared with
//! the tests of the example `tanks_dynamics`, which includes this file (the parent module
//! brings `HostModel` into scope).

use nalgebra::DMatrix;

use super::HostModel;

/// An order-2 model with the given matrices (borders the identity on [0, 1]).
pub(crate) fn model(a: [[f64; 2]; 2], b: [f64; 2], c: [f64; 2], d: f64) -> HostModel {
    HostModel {
        order: 2,
        a: DMatrix::from_fn(2, 2, |i, j| a[i][j]),
        b: b.to_vec(),
        c: c.to_vec(),
        d,
        mu0: 0.0,
        knots_asc: vec![0.0, 1.0],
        knots_desc: vec![0.0, 1.0],
        border_asc: vec![0.0, 1.0],
        border_desc: vec![0.0, 1.0],
        singular_values: Vec::new(),
        whitened_singular_values: Vec::new(),
        f: 10,
        p: 10,
        samples: 0,
    }
}

/// A staircase of pseudo-random levels in [0, 1], 20 samples each.
pub(crate) fn levels(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    let mut level = 0.0;
    (0..n)
        .map(|t| {
            if t % 20 == 0 {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                level = (s >> 11) as f64 / (1u64 << 53) as f64;
            }
            level
        })
        .collect()
}
