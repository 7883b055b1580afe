//! The input nonlinearities: borders piecewise linear on a grid of knots, and the element
//! that uses them — a memoryless curve (static), the play operator (backlash) or the switch
//! (the border of the input's last direction, the paper's δ).

use super::rng::Rng;
use hsid_host::model;

/// Borders piecewise linear on `knots` (ascending), each non-decreasing.
#[derive(Clone, Debug, PartialEq)]
pub struct Borders {
    /// Knots, `u_min` … `u_max`.
    pub knots: Vec<f64>,
    /// Ascending border `H_a` at the knots.
    pub asc: Vec<f64>,
    /// Descending border `H_d` at the knots.
    pub desc: Vec<f64>,
}

/// Linear interpolation of `v` on `x` at `u` (held at the ends).
pub fn interpolate(x: &[f64], v: &[f64], u: f64) -> f64 {
    let last = x.len().saturating_sub(1);
    if x.is_empty() {
        return f64::NAN;
    }
    if u <= x[0] {
        return v[0];
    }
    if u >= x[last] {
        return v[last];
    }
    let i = x
        .partition_point(|&k| k <= u)
        .saturating_sub(1)
        .min(last - 1);
    let s = (u - x[i]) / (x[i + 1] - x[i]);
    v[i] + s * (v[i + 1] - v[i])
}

impl Borders {
    /// Random borders on `segments` uniform segments of `[u_min, u_max]`: a centre line of
    /// slopes in `[0.6, 1.6]` through 0 at the middle, and a half-width `h sin(π i/segments)`
    /// (zero at both ends, so the borders meet there) with `h` in `[0.15, 0.4]`, added to the
    /// ascending border for a switch (`sign = 1`) or taken from it for a backlash
    /// (`sign = −1`). The half-width's increments stay under half the centre line's, so both
    /// borders rise. `width = 0` gives one curve (a static element).
    pub fn random(
        rng: &mut Rng,
        range: (f64, f64),
        segments: usize,
        width: bool,
        sign: f64,
    ) -> Self {
        let (lo, hi) = range;
        let dx = (hi - lo) / segments as f64;
        let knots: Vec<f64> = (0..=segments)
            .map(|i| {
                if i == segments {
                    hi
                } else {
                    lo + dx * i as f64
                }
            })
            .collect();
        let mut centre = vec![0.0; segments + 1];
        for i in 1..=segments {
            centre[i] = centre[i - 1] + rng.between(0.6, 1.6) * dx;
        }
        let mid = centre[segments / 2];
        centre.iter_mut().for_each(|c| *c -= mid);
        let h = if width { rng.between(0.15, 0.4) } else { 0.0 };
        // Largest increment of h sin(πi/s) is about h π/s; keep it under 0.3 dx.
        let h = h.min(0.3 * dx * segments as f64 / std::f64::consts::PI);
        let half: Vec<f64> = (0..=segments)
            .map(|i| h * (std::f64::consts::PI * i as f64 / segments as f64).sin())
            .collect();
        let asc = centre
            .iter()
            .zip(&half)
            .map(|(c, w)| c + sign * w)
            .collect();
        let desc = centre
            .iter()
            .zip(&half)
            .map(|(c, w)| c - sign * w)
            .collect();
        Self { knots, asc, desc }
    }

    /// `H_a(u)`.
    pub fn asc_at(&self, u: f64) -> f64 {
        interpolate(&self.knots, &self.asc, u)
    }

    /// `H_d(u)`.
    pub fn desc_at(&self, u: f64) -> f64 {
        interpolate(&self.knots, &self.desc, u)
    }
}

/// An element with its state.
#[derive(Clone, Debug)]
pub struct Element {
    /// Kind.
    pub kind: model::Element,
    /// Borders.
    pub borders: Borders,
    last_u: Option<f64>,
    rising: bool,
    w: f64,
}

impl Element {
    /// An element at rest at `u0` (the play at the borders' common value there, the switch
    /// on the descending border, as δ starts at 0).
    pub fn new(kind: model::Element, borders: Borders, u0: f64) -> Self {
        let w = borders.desc_at(u0);
        Self {
            kind,
            borders,
            last_u: None,
            rising: false,
            w,
        }
    }

    /// The output for the next input sample.
    pub fn next(&mut self, u: f64) -> f64 {
        if let Some(p) = self.last_u {
            if u > p {
                self.rising = true;
            } else if u < p {
                self.rising = false;
            }
        }
        self.last_u = Some(u);
        let b = &self.borders;
        self.w = match self.kind {
            model::Element::Static => b.asc_at(u),
            model::Element::Backlash => self.w.max(b.asc_at(u)).min(b.desc_at(u)),
            model::Element::Switch if self.rising => b.asc_at(u),
            model::Element::Switch => b.desc_at(u),
        };
        self.w
    }
}
