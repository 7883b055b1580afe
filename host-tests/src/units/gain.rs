//! Static gains and the −3 dB bandwidth of an identified model.

use std::f64::consts::PI;

use crate::identify::HostModel;

impl HostModel {
    /// Static gain of the linear part, `G(1) = C (I − A)⁻¹ B + D` (output units per unit of the
    /// element's output).
    pub(crate) fn lti_gain(&self) -> f64 {
        self.freq_response(0.0).0
    }

    /// Static gain of the whole cascade in output units per input unit: `G(1)` times the mean
    /// slope of the element, the secant `(P(u_max) − P(u_min)) / (u_max − u_min)` averaged over
    /// the two borders.
    pub(crate) fn cascade_gain(&self) -> f64 {
        let (lo, hi) = (self.u_min(), self.u_max());
        let secant = |p: fn(&HostModel, f64) -> f64| (p(self, hi) - p(self, lo)) / (hi - lo);
        let slope = 0.5 * (secant(HostModel::border_asc_at) + secant(HostModel::border_desc_at));
        self.lti_gain() * slope
    }

    /// The −3 dB bandwidth of the linear part in rad/sample: the lowest frequency at which
    /// `|G(e^{jω})|` falls to `|G(1)|/√2`, located on a grid of 2048 points up to π and refined by
    /// bisection; `None` when it stays above that level up to the Nyquist frequency or `G(1)` is 0.
    pub(crate) fn bandwidth(&self) -> Option<f64> {
        let mag = |w: f64| self.freq_response(w).0.hypot(self.freq_response(w).1);
        let level = mag(0.0) / 2f64.sqrt();
        if !(level.is_finite() && level > 0.0) {
            return None;
        }
        const GRID: usize = 2048;
        let step = PI / GRID as f64;
        let k = (1..=GRID).find(|&k| mag(k as f64 * step) < level)?;
        let (mut lo, mut hi) = ((k - 1) as f64 * step, k as f64 * step);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if mag(mid) < level {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
pub(crate) mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// A first-order model `y(t+1) = a y(t) + b h(t)` with the given borders on [−1, 1].
    pub(crate) fn first_order(a: f64, b: f64, asc: Vec<f64>, desc: Vec<f64>) -> HostModel {
        let knots = |n: usize| {
            (0..n)
                .map(|i| -1.0 + 2.0 * i as f64 / (n - 1) as f64)
                .collect()
        };
        HostModel {
            order: 1,
            a: DMatrix::from_element(1, 1, a),
            b: vec![b],
            c: vec![1.0],
            d: 0.0,
            mu0: asc[0],
            knots_asc: knots(asc.len()),
            knots_desc: knots(desc.len()),
            border_asc: asc,
            border_desc: desc,
            singular_values: vec![1.0],
            whitened_singular_values: Vec::new(),
            f: 10,
            p: 10,
            samples: 1000,
        }
    }

    #[test]
    fn first_order_gains_and_bandwidth_by_hand() {
        // G(z) = 0.1/(z − 0.9): G(1) = 1. |G(e^{jω})|² = 1/2 where
        // |e^{jω} − 0.9|² = 1.81 − 1.8 cos ω = 0.02, cos ω = 1.79/1.8.
        let m = first_order(0.9, 0.1, vec![-2.0, 2.0], vec![-1.0, 3.0]);
        assert!((m.lti_gain() - 1.0).abs() < 1e-12);
        let w = m.bandwidth().unwrap();
        assert!((w - (1.79f64 / 1.8).acos()).abs() < 1e-9, "{w}");
        // Both borders rise by 4 over [−1, 1]: slope 2.
        assert!((m.cascade_gain() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn an_all_pass_gain_has_no_bandwidth() {
        // G(z) = 1 (a = 0, b = 1 with one delay): |G| = 1 at every frequency.
        let m = first_order(0.0, 1.0, vec![0.0, 1.0], vec![0.0, 1.0]);
        assert_eq!(m.bandwidth(), None);
    }
}
