//! An order-2 model with real poles as a cascade of two stores.

use crate::identify::HostModel;

/// An order-2 model with real poles written as a cascade of two stores:
/// `x1(t+1) = p1 x1 + h`, `x2(t+1) = p2 x2 + x1`, `y = c1 x1 + c2 x2 (+ D h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    /// Pole of the first store.
    pub p1: f64,
    /// Pole of the second store.
    pub p2: f64,
    /// Output weight of the first store.
    pub c1: f64,
    /// Output weight of the second store.
    pub c2: f64,
}

impl HostModel {
    /// The two cascade forms (one per assignment of the poles to the stores) of an order-2
    /// model's numerator `G − D = (β1 z + β0) / (…)` over the real poles `p1`, `p2` (the model's
    /// own, or real ones near them); with the model's own poles they have its transfer function
    /// `G − D`.
    pub fn cascade_forms_with(&self, p1: f64, p2: f64) -> [Cascade; 2] {
        let (a, b, c) = (&self.a, &self.b, &self.c);
        let at = |i: usize, j: usize| a.get((i, j)).copied().unwrap_or(0.0);
        let v = |x: &[f64], i: usize| x.get(i).copied().unwrap_or(0.0);
        // G(z) − D = (β1 z + β0) / ((z − p1)(z − p2)).
        let beta1 = v(c, 0) * v(b, 0) + v(c, 1) * v(b, 1);
        let mb = [
            -at(1, 1) * v(b, 0) + at(0, 1) * v(b, 1),
            at(1, 0) * v(b, 0) - at(0, 0) * v(b, 1),
        ];
        let beta0 = v(c, 0) * mb[0] + v(c, 1) * mb[1];
        let form = |p1: f64, p2: f64| Cascade {
            p1,
            p2,
            c1: beta1,
            c2: beta0 + beta1 * p2,
        };
        [form(p1, p2), form(p2, p1)]
    }
}
