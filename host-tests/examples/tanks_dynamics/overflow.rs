//! Internal overflow: an order-2 model with real poles written as a cascade of two stores, the
//! first one overflowing into the second above a level `L`:
//!
//! ```text
//! s1 = p1 x1 + h,   s2 = p2 x2 + x1
//! x1(t+1) = min(s1, L),   x2(t+1) = s2 + k · max(s1 − L, 0),   y = g( c1 x1 + c2 x2 + d h )
//! ```
//!
//! With `L` above every level the first store reaches this is the linear model (any stable
//! order-2 `G` with real poles has this cascade form). `p1, p2, c1, c2, d, L, k` and the
//! initial state are fitted on the simulation error by Levenberg–Marquardt: a step is
//! accepted only if its simulation is finite and the poles stay stable; iterations are
//! bounded.

use hsid_host::diagnose::dynamics::{Cascade, DynamicsError, DynamicsFit};
use hsid_host::identify::HostModel;
use hsid_host::numerics::lm::{Settings, levenberg_marquardt};

use crate::error::ClassError;

/// An order-2 model as a cascade of two stores, the first overflowing into the second (see
/// the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Overflow {
    /// Pole of the first store.
    pub p1: f64,
    /// Pole of the second store.
    pub p2: f64,
    /// Output weight of the first store.
    pub c1: f64,
    /// Output weight of the second store.
    pub c2: f64,
    /// Direct feed-through.
    pub d: f64,
    /// Level `L` of the first store above which it overflows.
    pub level: f64,
    /// Fraction `k` of the overflow that reaches the second store.
    pub spill: f64,
    /// Initial state `(x1, x2)`.
    pub x0: [f64; 2],
}

impl Overflow {
    fn from_theta(t: &[f64]) -> Self {
        let g = |i: usize| t.get(i).copied().unwrap_or(0.0);
        Overflow {
            p1: g(0),
            p2: g(1),
            c1: g(2),
            c2: g(3),
            d: g(4),
            level: g(5),
            spill: g(6),
            x0: [g(7), g(8)],
        }
    }

    fn theta(&self) -> Vec<f64> {
        vec![
            self.p1, self.p2, self.c1, self.c2, self.d, self.level, self.spill, self.x0[0],
            self.x0[1],
        ]
    }

    /// The linear part's output `c1 x1 + c2 x2 + d h` along `h`, from [`Overflow::x0`];
    /// `None` if it is not finite.
    pub fn simulate(&self, h: &[f64]) -> Option<Vec<f64>> {
        let [mut x1, mut x2] = self.x0;
        let mut out = Vec::with_capacity(h.len());
        for &hi in h {
            let y = self.c1 * x1 + self.c2 * x2 + self.d * hi;
            if !y.is_finite() {
                return None;
            }
            out.push(y);
            let s1 = self.p1 * x1 + hi;
            let s2 = self.p2 * x2 + x1;
            let over = (s1 - self.level).max(0.0);
            x1 = s1 - over;
            x2 = s2 + self.spill * over;
        }
        Some(out)
    }

    /// The lowest and the highest level the first store reaches along `h` without
    /// overflowing.
    pub fn first_store_range(&self, h: &[f64]) -> (f64, f64) {
        let mut x1 = self.x0[0];
        let (mut low, mut high) = (x1, x1);
        for &hi in h {
            x1 = self.p1 * x1 + hi;
            low = low.min(x1);
            high = high.max(x1);
        }
        (low, high)
    }
}

/// The two cascade forms (one per assignment of the poles to the stores) of an order-2 model
/// with real poles; they have the same transfer function `G − D` as the model.
pub fn cascade_forms(m: &HostModel) -> Result<[Cascade; 2], ClassError> {
    let poles = m.poles();
    if m.order != 2 || poles.len() != 2 || poles.iter().any(|p| p.1 != 0.0) {
        return Err(ClassError::NotTwoRealPoles { poles });
    }
    Ok(m.cascade_forms_with(poles[0].0, poles[1].0))
}

/// Fits the internal-overflow class to an order-2 model with real poles (`A`, `B`, `C`, `D`
/// give the start; the borders and the output map are held). Both assignments of the poles
/// to the stores and three starting levels (60, 75, 90 % of the way from the lowest to the
/// highest level the first store reaches without overflow) are tried; the fit with the least
/// squared simulation error is returned.
pub fn fit_overflow(m: &HostModel, x0: &[f64], data: &DynamicsFit) -> Result<Overflow, ClassError> {
    let c = &m.c;
    let cascades = cascade_forms(m)?;
    let y0 = m.d * data.h.first().copied().unwrap_or(0.0)
        + c.iter().zip(x0).map(|(c, x)| c * x).sum::<f64>();
    let residual = |t: &[f64]| -> Option<Vec<f64>> {
        data.residual(&Overflow::from_theta(t).simulate(data.h)?)
    };
    let limit = data.radius_limit;
    let admissible = |t: &[f64]| t[0].abs() < limit && t[1].abs() < limit;
    let settings = Settings {
        iterations: data.iterations,
        ..Settings::default()
    };
    let mut best: Option<(f64, Overflow)> = None;
    for Cascade { p1, p2, c1, c2 } in cascades {
        // The cascade at rest at the level that gives the starting model's first output.
        let gain = c1 / (1.0 - p1) + c2 / ((1.0 - p1) * (1.0 - p2)) + m.d;
        let h0 = if gain != 0.0 { y0 / gain } else { 0.0 };
        let x1 = h0 / (1.0 - p1);
        let mut start = Overflow {
            p1,
            p2,
            c1,
            c2,
            d: m.d,
            level: f64::INFINITY,
            spill: 1.0,
            x0: [x1, x1 / (1.0 - p2)],
        };
        let (low, top) = start.first_store_range(data.h);
        for frac in [0.6, 0.75, 0.9] {
            start.level = low + frac * (top - low);
            let theta0 = start.theta();
            let typical: Vec<f64> = theta0.iter().map(|v| v.abs().max(1e-3)).collect();
            // A held initial state: its entries of θ are ignored (zero Jacobian columns).
            let fit_x0 = |t: &[f64]| {
                let mut t = t.to_vec();
                if !data.fit_x0 {
                    t[7..].copy_from_slice(&theta0[7..]);
                }
                t
            };
            let res = |t: &[f64]| residual(&fit_x0(t));
            let Some((theta, r)) =
                levenberg_marquardt(&theta0, &typical, &settings, &res, &admissible).ok()
            else {
                continue;
            };
            let e: f64 = r.iter().map(|v| v * v).sum();
            if best.as_ref().is_none_or(|(b, _)| e < *b) {
                best = Some((e, Overflow::from_theta(&fit_x0(&theta))));
            }
        }
    }
    best.map(|(_, o)| o)
        .ok_or(ClassError::Fit(DynamicsError::NotSimulating))
}
