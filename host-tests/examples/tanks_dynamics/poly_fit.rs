//! The fit of the polynomial state term ([`crate::poly`]): the model starts from the current
//! (linear) one with `E = 0`; `A`, `B`, `D`, `E`, an estimated initial state and, if asked
//! ([`Borders`]), the border values are then fitted on the **simulation** error by
//! Levenberg–Marquardt (the output map, `C` and the additive terms held). A step is accepted
//! only if its simulation is finite and `A` stays stable; iterations are bounded.

use hsid_host::diagnose::dynamics::{Borders, DynamicsError, DynamicsFit};
use hsid_host::identify::HostModel;
use hsid_host::numerics::lm::{Settings, levenberg_marquardt};
use nalgebra::DMatrix;

use crate::poly::{StatePoly, monomials, simulate, states};

/// The parameters `θ = [A, B, D, E, x0, borders]` packed, and unpacked into a model.
struct Packing<'a> {
    n: usize,
    fit_x0: bool,
    /// Border values refitted, appended last ([`Borders::pack`]).
    borders: Option<Borders<'a>>,
}

impl Packing<'_> {
    fn pack(&self, m: &HostModel, p: &StatePoly, x0: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                t.push(m.a[(i, j)]);
            }
        }
        t.extend_from_slice(&m.b);
        t.push(m.d);
        t.extend_from_slice(&p.e);
        if self.fit_x0 {
            t.extend_from_slice(x0);
        }
        if let Some(b) = self.borders {
            b.pack(m, &mut t);
        }
        t
    }

    fn unpack(&self, t: &[f64], m: &mut HostModel, p: &mut StatePoly, x0: &mut [f64]) {
        let n = self.n;
        let mut it = t.iter().copied();
        for i in 0..n {
            for j in 0..n {
                m.a[(i, j)] = it.next().unwrap_or(0.0);
            }
        }
        let fields = m.b.iter_mut().chain([&mut m.d]).chain(p.e.iter_mut());
        for v in fields {
            *v = it.next().unwrap_or(0.0);
        }
        if self.fit_x0 {
            for x in x0.iter_mut() {
                *x = it.next().unwrap_or(0.0);
            }
        }
        if let Some(b) = self.borders {
            b.unpack(&mut it, m);
        }
    }
}

/// Fits the polynomial state term of `degree` to a model, starting from `E = 0`. Returns the
/// model with `A`, `B`, `D` refit, the polynomial and the initial state. An error when the
/// starting model's own simulation is not finite (nothing to start from).
pub fn fit(
    m: &HostModel,
    x0: &[f64],
    degree: usize,
    data: &DynamicsFit,
) -> Result<(HostModel, StatePoly, Vec<f64>), DynamicsError> {
    let n = m.order;
    let len = data.h.len();
    if n == 0 || len == 0 {
        return Err(DynamicsError::Empty {
            order: n,
            samples: len,
        });
    }
    // Normalisation from the starting model's states.
    let xs = states(m, None, data.h, x0);
    let mut center = Vec::with_capacity(n + 1);
    let mut scale = Vec::with_capacity(n + 1);
    let mut low = Vec::with_capacity(n + 1);
    let mut high = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let v: Vec<f64> = if i < n {
            xs.iter().map(|x| x[i]).collect()
        } else {
            data.h.to_vec()
        };
        if v.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::NotSimulating);
        }
        let mean = v.iter().sum::<f64>() / len as f64;
        let sd = (v.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / len as f64).sqrt();
        let sd = if sd.is_finite() && sd > 0.0 { sd } else { 1.0 };
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min((x - mean) / sd), b.max((x - mean) / sd))
            });
        let margin = 0.1 * (hi - lo).max(1e-6);
        center.push(mean);
        scale.push(sd);
        low.push(lo - margin);
        high.push(hi + margin);
    }
    let mons = monomials(n + 1, degree);
    let k = mons.len();
    let mut poly = StatePoly {
        degree,
        center,
        scale,
        low,
        high,
        monomials: mons,
        e: vec![0.0; n * k],
    };
    let pack = Packing {
        n,
        fit_x0: data.fit_x0,
        borders: data.borders,
    };
    let mut model = m.clone();
    let mut state = x0.to_vec();
    state.resize(n, 0.0);
    let residual = |t: &[f64]| -> Option<Vec<f64>> {
        let mut mm = m.clone();
        let mut pp = poly.clone();
        let mut xx = state.clone();
        pack.unpack(t, &mut mm, &mut pp, &mut xx);
        // Refitted borders give a new `h` (the same input nonlinearity, new values).
        let refitted = data.refitted_h(&mm);
        let lin = simulate(&mm, Some(&pp), refitted.as_deref().unwrap_or(data.h), &xx)?;
        data.residual(&lin)
    };
    let radius = |t: &[f64]| -> f64 {
        let a = DMatrix::from_fn(n, n, |i, j| t[i * n + j]);
        hsid_host::numerics::poly::eigenvalues(a).map_or(f64::INFINITY, |ev| {
            ev.iter().map(|(r, i)| r.hypot(*i)).fold(0.0, f64::max)
        })
    };
    let theta0 = pack.pack(&model, &poly, &state);
    // Typical sizes for the difference steps: A, B, D, x0 relative; E dimensionless.
    let typical: Vec<f64> = theta0
        .iter()
        .enumerate()
        .map(|(j, v)| {
            let in_e = j > n * n + n && j < n * n + n + 1 + n * k;
            if in_e { 1e-2 } else { v.abs().max(1e-3) }
        })
        .collect();
    let admissible = |t: &[f64]| radius(t) < data.radius_limit;
    let settings = Settings {
        iterations: data.iterations,
        ..Settings::default()
    };
    let Some((theta, _)) =
        levenberg_marquardt(&theta0, &typical, &settings, &residual, &admissible).ok()
    else {
        return Err(DynamicsError::NotSimulating);
    };
    pack.unpack(&theta, &mut model, &mut poly, &mut state);
    Ok((model, poly, state))
}
