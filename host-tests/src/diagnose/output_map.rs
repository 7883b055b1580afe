//! The output map `g` of a Hammerstein–Wiener extension: monotone, piecewise linear, clipped at
//! a saturation.

use serde::Serialize;

/// A monotone non-decreasing piecewise-linear map, extrapolated linearly with its end slopes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OutputMap {
    /// Knots (inputs of the map: Hammerstein outputs).
    pub x: Vec<f64>,
    /// Values at the knots (outputs).
    pub v: Vec<f64>,
    /// Level the output cannot exceed (a saturation found by the data checks): `g` is
    /// clipped there.
    pub ceiling: Option<f64>,
    /// Level the output cannot go below.
    pub floor: Option<f64>,
}

impl OutputMap {
    /// `g(x)`: the piecewise-linear map, clipped to `[floor, ceiling]`.
    pub fn eval(&self, x: f64) -> f64 {
        let v = self.eval_linear(x);
        let v = self.ceiling.map_or(v, |c| v.min(c));
        self.floor.map_or(v, |f| v.max(f))
    }

    /// Whether the output is clipped at `x`.
    fn clipped(&self, x: f64) -> bool {
        let v = self.eval_linear(x);
        self.ceiling.is_some_and(|c| v > c) || self.floor.is_some_and(|f| v < f)
    }

    /// The piecewise-linear map without the clipping.
    fn eval_linear(&self, x: f64) -> f64 {
        let n = self.x.len();
        if n < 2 {
            return x;
        }
        let j = match self.x.iter().rposition(|&k| k <= x) {
            None => 0,
            Some(j) => j.min(n - 2),
        };
        let t = (x - self.x[j]) / (self.x[j + 1] - self.x[j]);
        self.v[j] + t * (self.v[j + 1] - self.v[j])
    }

    /// `g⁻¹(y)` where `g` is invertible with a slope of at least `min_slope`, else `None`.
    pub(crate) fn invert(&self, y: f64, min_slope: f64) -> Option<f64> {
        if self.ceiling.is_some_and(|c| y >= c) || self.floor.is_some_and(|f| y <= f) {
            return None;
        }
        self.preimage(y, min_slope)
    }

    /// The input at which the map without its clipping reaches `y`, on a part with a slope of
    /// at least `min_slope` (extrapolated with the end slopes); `None` where none reaches it.
    pub(crate) fn preimage(&self, y: f64, min_slope: f64) -> Option<f64> {
        let min_slope = min_slope.max(1e-12);
        let n = self.x.len();
        if n < 2 {
            return Some(y);
        }
        let slope = |j: usize| (self.v[j + 1] - self.v[j]) / (self.x[j + 1] - self.x[j]);
        if y < self.v[0] {
            let s = slope(0);
            return (s >= min_slope).then(|| self.x[0] + (y - self.v[0]) / s);
        }
        if y > self.v[n - 1] {
            let s = slope(n - 2);
            return (s >= min_slope).then(|| self.x[n - 1] + (y - self.v[n - 1]) / s);
        }
        (0..n - 1).find_map(|j| {
            let s = slope(j);
            (self.v[j] <= y && y <= self.v[j + 1] && s >= min_slope)
                .then(|| self.x[j] + (y - self.v[j]) / s)
        })
    }

    /// Slope of `g` at `x` (end slopes outside the knots).
    pub(crate) fn slope_at(&self, x: f64) -> f64 {
        let n = self.x.len();
        if self.clipped(x) {
            return 0.0;
        }
        if n < 2 {
            return 1.0;
        }
        let j = match self.x.iter().rposition(|&k| k <= x) {
            None => 0,
            Some(j) => j.min(n - 2),
        };
        (self.v[j + 1] - self.v[j]) / (self.x[j + 1] - self.x[j])
    }

    /// Mean slope over the knots.
    pub(crate) fn mean_slope(&self) -> f64 {
        let n = self.x.len();
        if n < 2 {
            return 1.0;
        }
        (self.v[n - 1] - self.v[0]) / (self.x[n - 1] - self.x[0])
    }
}
