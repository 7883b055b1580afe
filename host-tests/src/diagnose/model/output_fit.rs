//! The output map fitted from the simulated Hammerstein output (non-negative least squares
//! on its increments).

use nalgebra::{DMatrix, DVector};

use crate::diagnose::output_map::OutputMap;
use crate::validation::stats::nnls;

use super::fit_options::Saturation;

/// Fits the monotone output map with `segments` segments from `x` to `y`, clipped at the
/// saturation levels; samples at a saturation level do not take part in the fit of the
/// piecewise-linear part (their value says only that the unclipped output is beyond it).
pub(super) fn fit_output_map(
    x: &[f64],
    y: &[f64],
    skip: &[bool],
    segments: usize,
    sat: &Saturation,
) -> Option<OutputMap> {
    let idx: Vec<usize> = (0..x.len())
        .filter(|&i| !skip[i] && !sat.at_limit(y[i]))
        .collect();
    if idx.len() < 4 * (segments + 1) {
        return None;
    }
    let mut sorted: Vec<f64> = idx.iter().map(|&i| x[i]).collect();
    sorted.sort_by(f64::total_cmp);
    let mut knots: Vec<f64> = (0..=segments)
        .map(|k| sorted[((sorted.len() - 1) * k) / segments])
        .collect();
    knots.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * (1.0 + b.abs()));
    if knots.len() < 2 {
        return None;
    }
    let s = knots.len() - 1;
    let mut design = DMatrix::<f64>::zeros(idx.len(), s + 1);
    for (r, &i) in idx.iter().enumerate() {
        let xi = x[i];
        let j = match knots.iter().rposition(|&k| k <= xi) {
            None => 0,
            Some(j) => j.min(s - 1),
        };
        let t = (xi - knots[j]) / (knots[j + 1] - knots[j]);
        design[(r, 0)] = 1.0;
        for c in 0..j {
            design[(r, 1 + c)] = 1.0;
        }
        design[(r, 1 + j)] = t;
    }
    let target = DVector::from_iterator(idx.len(), idx.iter().map(|&i| y[i]));
    let beta = nnls(&design, &target, 1)?;
    let mut v = Vec::with_capacity(s + 1);
    let mut acc = beta[0];
    v.push(acc);
    for c in 0..s {
        acc += beta[1 + c];
        v.push(acc);
    }
    Some(OutputMap {
        x: knots,
        v,
        ceiling: sat.ceiling,
        floor: sat.floor,
    })
}
