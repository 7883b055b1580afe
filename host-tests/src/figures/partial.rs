//! Partial residuals of the input element: what one record says about `h(t)`, the output of
//! the input element, sample by sample, given the identified LTI part.
//!
//! The model's output is `ŷ(t) = Σ_k g_k Ĥ(t − k)` with `g_k` the impulse response of `G`.
//! Holding every other sample of `h` at the model's value, the least-squares estimate of
//! `h(τ)` from the simulation residual `e = y − ŷ` is
//! `ĥ(τ) = Ĥ(τ) + Σ_k g_k e(τ + k) / Σ_k g_k²` (a matched filter: a departure `δ` of `h` at a
//! single sample is recovered exactly, and white noise of variance `σ²` enters with variance
//! `σ² / Σ_k g_k²`). Unlike `G⁻¹ y` it does not amplify the noise where `|G|` is small.

use crate::identify::HostModel;

/// Impulse response length cap, and the fraction of its energy the kept part must hold.
const MAX_TAPS: usize = 5000;
const ENERGY: f64 = 1.0 - 1e-9;

impl HostModel {
    /// `g_0 … g_K` of the model, cut where the remaining energy falls below `1 − ENERGY` of the
    /// whole (at most `MAX_TAPS` values; the remaining energy of a stable `G` decays
    /// geometrically, so the whole is estimated from twice the kept length).
    pub fn impulse_response(&self) -> Vec<f64> {
        let n = self.order;
        let mut g = vec![self.d];
        let mut x = nalgebra::DVector::from_column_slice(&self.b);
        let c = nalgebra::DVector::from_column_slice(&self.c);
        for _ in 0..2 * MAX_TAPS {
            if n == 0 {
                break;
            }
            g.push(c.dot(&x));
            x = &self.a * x;
        }
        let total: f64 = g.iter().map(|v| v * v).sum();
        let mut acc = 0.0;
        let keep = g
            .iter()
            .position(|v| {
                acc += v * v;
                acc >= ENERGY * total
            })
            .map_or(g.len(), |i| i + 1)
            .min(MAX_TAPS);
        g.truncate(keep);
        g
    }
}

/// Share of the impulse response energy the record must still hold after `τ` for `ĥ(τ)` to be
/// given: near the end of the record the sums are cut and the noise would enter enlarged.
pub const MIN_ENERGY: f64 = 0.9;

/// `Σ_k g_k e(τ + k) / Σ_k g_k²` for every `τ` whose remaining record holds at least
/// [`MIN_ENERGY`] of the impulse response energy (`None` for the others, at the end).
pub fn departures(g: &[f64], e: &[f64]) -> Vec<Option<f64>> {
    let total: f64 = g.iter().map(|g| g * g).sum();
    (0..e.len())
        .map(|tau| {
            let m = g.len().min(e.len() - tau);
            let num: f64 = g[..m]
                .iter()
                .zip(&e[tau..tau + m])
                .map(|(g, e)| g * e)
                .sum();
            let den: f64 = g[..m].iter().map(|g| g * g).sum();
            (den > 0.0 && den >= MIN_ENERGY * total).then(|| num / den)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use nalgebra::DMatrix;

    fn first_order(pole: f64, gain: f64) -> HostModel {
        HostModel {
            order: 1,
            a: DMatrix::from_element(1, 1, pole),
            b: vec![gain],
            c: vec![1.0],
            d: 0.0,
            mu0: 0.0,
            knots_asc: vec![0.0, 1.0],
            knots_desc: vec![0.0, 1.0],
            border_asc: vec![0.0, 1.0],
            border_desc: vec![0.0, 1.0],
            singular_values: Vec::new(),
            whitened_singular_values: Vec::new(),
            f: 1,
            p: 1,
            samples: 0,
        }
    }

    #[test]
    fn impulse_response_of_a_first_order_plant() {
        let g = first_order(0.5, 2.0).impulse_response();
        assert_eq!(&g[..4], &[0.0, 2.0, 1.0, 0.5]);
        // Energy 4/(1 − 0.25) = 16/3; the kept part holds all but 1e-9 of it.
        let kept: f64 = g.iter().map(|v| v * v).sum();
        assert!(((1.0 - 1e-9) * 16.0 / 3.0..16.0 / 3.0).contains(&kept));
    }

    #[test]
    fn a_single_departure_is_recovered_exactly() {
        let m = first_order(0.8, 1.0);
        let g = m.impulse_response();
        // h departs by 0.3 at τ = 10 only: the residual is 0.3 g shifted by 10.
        let mut e = vec![0.0; 400];
        for (k, gk) in g.iter().enumerate().take(390) {
            e[10 + k] = 0.3 * gk;
        }
        let d = departures(&g, &e);
        assert!((d[10].unwrap() - 0.3).abs() < 1e-6, "{:?}", d[10]);
        assert!(d[200].unwrap().abs() < 1e-12);
        // g_0 = 0 and g_k² = 0.64^(k−1): from τ = 394 the record holds g_0 … g_5, which
        // carry 1 − 0.64⁵ = 89 % of the energy, too little; from τ = 393, 1 − 0.64⁶ = 93 %.
        assert_eq!(d[399], None);
        assert_eq!(d[394], None);
        assert!(d[393].is_some());
    }
}
