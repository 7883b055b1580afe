//! The parameterisation: the linear part `G = B/F` with `G(1) = 1`, the two borders at the
//! knots, and the element's initial output.
//!
//! `θ = (f₁ … f_n, free b's, H_a(k₀) … H_a(k_K), H_d(k₀) … H_d(k_K), w(−1))`: `w(−1)` is the
//! element's output before the first sample, in whose steady state the plant rests (for a
//! relay, which has no continuous state, only the plant's resting level). The numerator
//! coefficient fixed by `G(1) = 1` is not a parameter, as in the prediction-error
//! refinement's layout.

use crate::model::MemoryElement;
use crate::refine::pem::ParamLayout;

/// Where each parameter group sits in `θ`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The element.
    pub kind: MemoryElement,
    /// Order of `G`.
    pub n: usize,
    /// Number of knots (both borders use the same knots).
    pub knots: usize,
    /// Whether `G` has a direct feed-through.
    pub feedthrough: bool,
}

impl Layout {
    /// The prediction-error layout of the linear part alone (no borders, no noise model).
    pub fn linear(&self) -> ParamLayout {
        ParamLayout {
            n: self.n,
            channels: 0,
            nv: 0,
            init: false,
            feedthrough: self.feedthrough,
            shared: false,
        }
    }
    /// `f₁ … f_n` and the free numerator coefficients.
    pub fn plant(&self) -> std::ops::Range<usize> {
        0..self.linear().b().end
    }
    /// `H_a` at the knots.
    pub fn asc(&self) -> std::ops::Range<usize> {
        let s = self.plant().end;
        s..s + self.knots
    }
    /// `H_d` at the knots.
    pub fn desc(&self) -> std::ops::Range<usize> {
        let s = self.asc().end;
        s..s + self.knots
    }
    /// `w(−1)`.
    pub fn w0(&self) -> usize {
        self.desc().end
    }
    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.w0() + 1
    }
    /// Never empty (the borders have at least two knots).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A hysteresis model: element on knots followed by `G(q) = B(q)/F(q)`, `G(1) = 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct HysteresisModel {
    /// The element.
    pub kind: MemoryElement,
    /// `F = [1, f₁ … f_n]`.
    pub f: Vec<f64>,
    /// `B = [b₀ … b_n]` with `B(1) = F(1)`.
    pub b: Vec<f64>,
    /// Whether `b₀` is free (else `b₀ = 0`, the plant strictly proper).
    pub feedthrough: bool,
    /// Knots `u_min … u_max` of both borders.
    pub knots: Vec<f64>,
    /// `H_a` at the knots.
    pub border_asc: Vec<f64>,
    /// `H_d` at the knots.
    pub border_desc: Vec<f64>,
    /// The element's output before the first sample, in whose steady state the plant starts
    /// (for a switch, whose relay has no state, only the plant's resting level).
    pub w0: f64,
}

impl HysteresisModel {
    /// The model of `θ` under `layout` on `knots`.
    pub fn from_theta(layout: &Layout, knots: &[f64], th: &[f64]) -> Self {
        let p = layout.linear().polynomials(&th[layout.plant()]);
        Self {
            kind: layout.kind,
            f: p.f,
            b: p.b,
            feedthrough: layout.feedthrough,
            knots: knots.to_vec(),
            border_asc: th[layout.asc()].to_vec(),
            border_desc: th[layout.desc()].to_vec(),
            w0: th[layout.w0()],
        }
    }

    /// The layout of this model.
    pub fn layout(&self) -> Layout {
        Layout {
            kind: self.kind,
            n: self.f.len() - 1,
            knots: self.knots.len(),
            feedthrough: self.feedthrough,
        }
    }

    /// `θ` of this model under `layout` (the eliminated numerator coefficient dropped).
    pub fn theta(&self, layout: &Layout) -> Vec<f64> {
        let l = layout.linear();
        let mut th = vec![0.0; layout.len()];
        th[l.f()].copy_from_slice(&self.f[1..]);
        th[l.b()].copy_from_slice(&self.b[1..=l.nb()]);
        th[layout.asc()].copy_from_slice(&self.border_asc);
        th[layout.desc()].copy_from_slice(&self.border_desc);
        th[layout.w0()] = self.w0;
        th
    }

    /// The poles of `G` as `(re, im)`.
    pub fn poles(&self) -> Vec<(f64, f64)> {
        crate::numerics::poly::roots(&self.f).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn theta_round_trips_and_fixes_the_static_gain() {
        let layout = Layout {
            kind: MemoryElement::Play,
            n: 2,
            knots: 3,
            feedthrough: false,
        };
        assert_eq!(layout.len(), 2 + 1 + 3 + 3 + 1);
        let relay = Layout {
            kind: MemoryElement::Relay,
            ..layout
        };
        assert_eq!(relay.len(), layout.len());
        let th = [-1.2, 0.5, 0.1, -1.0, 0.0, 1.0, -0.8, 0.2, 1.2, 0.3];
        let m = HysteresisModel::from_theta(&layout, &[-1.0, 0.0, 1.0], &th);
        // B = [0, 0.1, F(1) − 0.1] with F(1) = 1 − 1.2 + 0.5 = 0.3.
        assert_eq!(m.b.len(), 3);
        assert!((m.b[2] - 0.2).abs() < 1e-15, "{:?}", m.b);
        assert_eq!(m.w0, 0.3);
        assert_eq!(m.theta(&layout), th.to_vec());
    }
}
