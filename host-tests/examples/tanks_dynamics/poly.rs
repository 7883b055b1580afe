//! The polynomial state term, in the spirit of polynomial nonlinear state-space models (NLSS):
//!
//! ```text
//! x(t+1) = A x(t) + B h(t) + S E ψ(z(t)),   y = g( C x(t) + D h(t) ) + additive
//! z      = clip( (x − x̄) / σ_x ,  (h − h̄) / σ_h )      (normalised, clipped to the range
//!                                                      the estimation data visit)
//! ψ(z)   = every monomial of degree 2 … `degree` in z except the pure powers of h
//! ```
//!
//! `S = diag(σ_x)` keeps `E` dimensionless. The pure powers of `h` are left out: they would
//! change the input nonlinearity, not the dynamics. Clipping `z` to the visited range keeps
//! the polynomial from extrapolating, and with `A` stable (checked) every simulation stays
//! bounded. On the cascaded tanks the fit the cross-validation ranks first has more than one
//! steady state for one constant input ([`unique_steady_states`]), which the plant does not
//! have.

use hsid_host::diagnose::dynamics::DynamicsError;
use hsid_host::identify::HostModel;

use crate::error::ClassError;

/// The polynomial state term of a model with nonlinear dynamics.
#[derive(Clone, Debug, PartialEq)]
pub struct StatePoly {
    /// Highest total degree of the monomials (2 or 3).
    pub degree: usize,
    /// Centres of the normalised variables: the states, then `h`.
    pub center: Vec<f64>,
    /// Scales of the normalised variables.
    pub scale: Vec<f64>,
    /// Lower clip of every normalised variable.
    pub low: Vec<f64>,
    /// Upper clip of every normalised variable.
    pub high: Vec<f64>,
    /// Exponents of every monomial, one per variable (states, then `h`).
    pub monomials: Vec<Vec<u8>>,
    /// `E`, row-major `n × k` (`k` monomials), in units of the state scales.
    pub e: Vec<f64>,
}

/// Every exponent vector over `vars` variables of total degree 2 … `degree`, except the pure
/// powers of the last variable (`h`).
pub fn monomials(vars: usize, degree: usize) -> Vec<Vec<u8>> {
    fn rec(vars: usize, left: usize, prefix: &mut Vec<u8>, out: &mut Vec<Vec<u8>>) {
        if prefix.len() + 1 == vars {
            prefix.push(left as u8);
            out.push(prefix.clone());
            prefix.pop();
            return;
        }
        for k in (0..=left).rev() {
            prefix.push(k as u8);
            rec(vars, left - k, prefix, out);
            prefix.pop();
        }
    }
    let mut out = Vec::new();
    if vars == 0 {
        return out;
    }
    for d in 2..=degree {
        let mut all = Vec::new();
        rec(vars, d, &mut Vec::new(), &mut all);
        out.extend(
            all.into_iter()
                .filter(|m| m[..vars - 1].iter().any(|&e| e > 0)),
        );
    }
    out
}

impl StatePoly {
    /// Number of monomials.
    pub fn terms(&self) -> usize {
        self.monomials.len()
    }

    /// `ψ` of the state `x` and the input nonlinearity's output `h`, into `out` (length
    /// [`StatePoly::terms`]).
    fn psi(&self, x: &[f64], h: f64, z: &mut [f64], out: &mut [f64]) {
        let n = x.len();
        for (i, zi) in z.iter_mut().enumerate() {
            let v = if i < n { x[i] } else { h };
            let s = (v - self.center[i]) / self.scale[i];
            *zi = s.clamp(self.low[i], self.high[i]);
        }
        for (o, m) in out.iter_mut().zip(&self.monomials) {
            let mut p = 1.0;
            for (zi, &e) in z.iter().zip(m) {
                for _ in 0..e {
                    p *= zi;
                }
            }
            *o = p;
        }
    }
}

/// The linear part's output `C x + D h` of the model with the polynomial state term, from
/// `x0`. With `A` stable the state stays bounded (`ψ` is clipped); a non-finite value
/// still ends the simulation with `None`.
pub fn simulate(
    m: &HostModel,
    poly: Option<&StatePoly>,
    h: &[f64],
    x0: &[f64],
) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(h.len());
    let finite = walk(m, poly, h, x0, |x, hi| {
        let y = m.d * hi + m.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>();
        out.push(y);
        y.is_finite()
    });
    finite.then_some(out)
}

/// The states of the (linear or extended) model along a record, before each sample's update.
pub fn states(m: &HostModel, poly: Option<&StatePoly>, h: &[f64], x0: &[f64]) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(h.len());
    walk(m, poly, h, x0, |x, _| {
        out.push(x.to_vec());
        true
    });
    out
}

/// Steps the model along `h` from `x0` (missing entries 0), calling `visit(x, h)` with every
/// state before its update; stops early, returning `false`, when `visit` does.
fn walk(
    m: &HostModel,
    poly: Option<&StatePoly>,
    h: &[f64],
    x0: &[f64],
    mut visit: impl FnMut(&[f64], f64) -> bool,
) -> bool {
    let n = m.order;
    let mut x: Vec<f64> = x0
        .iter()
        .copied()
        .chain(std::iter::repeat(0.0))
        .take(n)
        .collect();
    let mut next = vec![0.0; n];
    let k = poly.map_or(0, StatePoly::terms);
    let mut psi = vec![0.0; k];
    let mut z = vec![0.0; n + 1];
    for &hi in h {
        if !visit(&x, hi) {
            return false;
        }
        if let Some(p) = poly {
            p.psi(&x, hi, &mut z, &mut psi);
        }
        for (i, nx) in next.iter_mut().enumerate() {
            let mut v = m.b[i] * hi + (0..n).map(|j| m.a[(i, j)] * x[j]).sum::<f64>();
            if let Some(p) = poly {
                let row = &p.e[i * k..(i + 1) * k];
                v += p.scale[i] * row.iter().zip(&psi).map(|(e, s)| e * s).sum::<f64>();
            }
            *nx = v;
        }
        std::mem::swap(&mut x, &mut next);
    }
    true
}

/// Checks that a model with a polynomial state term settles at one output for every
/// constant `h` of the record's range (nine levels), as the plant is assumed to (one steady
/// state per input level: the static gain curve). The model is simulated along the record
/// (`h` from `x0`); from the states where its output is lowest and highest there, held at
/// each level for `3 × 10⁴` steps, it must end at outputs that agree within 10⁻³ of the range
/// of the steady outputs. [`ClassError::Multistable`] names the first level where they
/// do not.
pub fn unique_steady_states(
    m: &HostModel,
    poly: &StatePoly,
    h: &[f64],
    x0: &[f64],
) -> Result<(), ClassError> {
    let xs = states(m, Some(poly), h, x0);
    if xs.iter().flatten().any(|v| !v.is_finite()) {
        return Err(ClassError::Fit(DynamicsError::NotSimulating));
    }
    let (lo, hi) = h
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let output = |x: &[f64], hv: f64| m.d * hv + m.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>();
    let visited: Vec<(f64, &Vec<f64>)> = xs
        .iter()
        .zip(h)
        .map(|(x, &hv)| (output(x, hv), x))
        .collect();
    let state_at =
        |v: Option<&(f64, &Vec<f64>)>| v.map_or_else(|| vec![0.0; m.order], |v| v.1.clone());
    let low = state_at(visited.iter().min_by(|a, b| a.0.total_cmp(&b.0)));
    let high = state_at(visited.iter().max_by(|a, b| a.0.total_cmp(&b.0)));
    let steps = 30_000;
    let mut outputs = Vec::new();
    for j in 0..9 {
        let level = lo + (hi - lo) * j as f64 / 8.0;
        let hh = vec![level; steps];
        let end = |x0: &[f64]| {
            simulate(m, Some(poly), &hh, x0)
                .and_then(|y| y.last().copied())
                .unwrap_or(f64::NAN)
        };
        let (a, b) = (end(&low), end(&high));
        outputs.push((level, a, b));
    }
    let range = outputs
        .iter()
        .flat_map(|o| [o.1, o.2])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let tol = 1e-3 * (range.1 - range.0).max(1e-12);
    for (level, a, b) in outputs {
        if !(a.is_finite() && b.is_finite()) {
            return Err(ClassError::Fit(DynamicsError::NotSimulating));
        }
        if (a - b).abs() > tol {
            return Err(ClassError::Multistable {
                level,
                outputs: (a, b),
            });
        }
    }
    Ok(())
}
