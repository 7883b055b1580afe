//! The poles refined by the simulation error (observer form, Levenberg–Marquardt), and the
//! spectral radius.

use nalgebra::{DMatrix, DVector};

use crate::diagnose::output_map::OutputMap;
use crate::identify::HostModel;
use crate::numerics::lm::{Damping, DampingLimit, JacobianFailure, Settings, levenberg_marquardt};
use crate::numerics::lstsq::lstsq_min_norm;
use crate::numerics::poly::{from_roots, observer_a};

use super::borders::border_channels;
use super::fit_options::{InitialState, Saturation};
use super::refine_linear::{LinearFitParams, refine_linear};

impl HostModel {
    /// The linear part in observer canonical form (`C = e₁`): the same transfer function.
    pub(super) fn to_observer(&self) -> Option<(Vec<f64>, HostModel)> {
        let n = self.order;
        if n == 0 {
            return None;
        }
        let poles = self.poles();
        if poles.len() != n {
            return None;
        }
        let a = from_roots(&poles)[1..].to_vec();
        // Markov parameters h_k = C A^{k−1} B, k = 1…n.
        let mut h = Vec::with_capacity(n);
        let mut v = DVector::from_column_slice(&self.b);
        for _ in 0..n {
            h.push(self.c.iter().zip(v.iter()).map(|(c, x)| c * x).sum::<f64>());
            v = &self.a * v;
        }
        let b: Vec<f64> = (0..n)
            .map(|k| h[k] + (0..k).map(|i| a[i] * h[k - 1 - i]).sum::<f64>())
            .collect();
        let mut out = self.clone();
        out.a = observer_a(&a);
        out.b = b;
        out.c = (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect();
        Some((a, out))
    }
}

/// Residual of the over-parameterised model with `A` fixed: the output is linear in the
/// products `B_i v_c`, `D v_c` (and `B_i c` for an estimated initial level), which makes the
/// residual a smooth function of `A` (the paper's eq. 7 with `A`, `C` given). `m` is in
/// observer canonical form with characteristic polynomial `a`: the response of `y` to an input
/// into state `i` is `q^{−i} / A(q⁻¹)`, so one filter per channel and shifts give every column.
pub(super) fn overparameterised_residual(
    m: &HostModel,
    a: &[f64],
    phi: &[Vec<f64>],
    y: &[f64],
    skip: &[bool],
    initial: InitialState,
) -> Option<Vec<f64>> {
    let n = m.order;
    let len = y.len();
    let ia = DMatrix::<f64>::identity(n, n) - &m.a;
    let ia_inv = ia.try_inverse()?;
    // Free responses from rest, ρ_i(t) = C A^t (I − A)⁻¹ e_i.
    let mut rho = vec![vec![0.0; len]; n];
    for (i, r) in rho.iter_mut().enumerate() {
        let mut x: Vec<f64> = (0..n).map(|j| ia_inv[(j, i)]).collect();
        for v in r.iter_mut() {
            *v = x[0];
            x = (0..n)
                .map(|row| (0..n).map(|k| m.a[(row, k)] * x[k]).sum())
                .collect();
        }
    }
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(phi.len() * (n + 1) + n);
    for (c, ph) in phi.iter().enumerate() {
        // w = φ / A(q⁻¹) from rest.
        let mut w = vec![0.0; len];
        for t in 0..len {
            let mut v = ph[t];
            for (k, ak) in a.iter().enumerate() {
                if t > k {
                    v -= ak * w[t - 1 - k];
                }
            }
            w[t] = v;
        }
        for i in 1..=n {
            let col: Vec<f64> = (0..len)
                .map(|t| {
                    let base = if t >= i { w[t - i] } else { 0.0 };
                    if c == 0 && initial == InitialState::Rest {
                        base + rho[i - 1][t]
                    } else {
                        base
                    }
                })
                .collect();
            cols.push(col);
        }
        cols.push(ph.clone());
    }
    if initial == InitialState::Estimated {
        cols.extend(rho);
    }
    let rows: Vec<usize> = (0..len).filter(|&t| !skip[t]).collect();
    let x = DMatrix::from_fn(rows.len(), cols.len(), |r, c| cols[c][rows[r]]);
    let yy = DVector::from_iterator(rows.len(), rows.iter().map(|&t| y[t]));
    let beta = lstsq_min_norm(&x, &yy)?;
    let fit = &x * beta;
    Some((0..rows.len()).map(|r| yy[r] - fit[r]).collect())
}

/// Largest root modulus of `z^n + a_1 z^{n−1} + …`.
pub(super) fn root_radius(a: &[f64]) -> f64 {
    crate::numerics::poly::eigenvalues(observer_a(a)).map_or(f64::INFINITY, |ev| {
        ev.iter().map(|(r, i)| r.hypot(*i)).fold(0.0, f64::max)
    })
}

/// Levenberg–Marquardt on the characteristic polynomial of `A` (variable projection: the
/// residual of the over-parameterised least squares for every `A`), kept stable with time
/// constants below twice the record; then `B`, `D`, borders by [`refine_linear`].
/// The output map's segments and saturation in `p` are not used.
pub(super) fn refine_poles(
    m: &HostModel,
    x0: &[f64],
    p: &LinearFitParams<'_>,
) -> Option<(HostModel, Vec<f64>)> {
    let (u, y, skip, initial) = (p.u, p.y, p.skip, p.initial);
    let (mut a, obs) = m.to_observer()?;
    let n = a.len();
    let limit = 1.0 - 0.5 / u.len().max(4) as f64;
    if root_radius(&a) >= limit {
        // Start from the subspace poles pulled inside: |p| ≤ 0.99 · limit.
        let poles: Vec<(f64, f64)> = m
            .poles()
            .into_iter()
            .map(|(re, im)| {
                let r = re.hypot(im);
                let k = if r >= 0.99 * limit {
                    0.99 * limit / r
                } else {
                    1.0
                };
                (re * k, im * k)
            })
            .collect();
        a = from_roots(&poles)[1..].to_vec();
    }
    let phi = border_channels(m, u, p.shared)?;
    let resid = |a: &[f64]| -> Option<Vec<f64>> {
        let mut mm = obs.clone();
        mm.a = observer_a(a);
        overparameterised_residual(&mm, a, &phi, y, skip, initial)
    };
    let defaults = Settings::default();
    let settings = Settings {
        iterations: 12,
        damping: Damping {
            initial: 1e-3,
            limit: DampingLimit::Tries(5),
            ..defaults.damping
        },
        min_gain: 1e-5,
        jacobian_failure: JacobianFailure::Fail,
        ..defaults
    };
    let (a, _) = levenberg_marquardt(&a, &vec![1e-2; n], &settings, &resid, &|trial: &[f64]| {
        root_radius(trial) < limit
    })
    .ok()?;
    let mut mm = obs;
    mm.a = observer_a(&a);
    let x0 = match initial {
        InitialState::Rest => mm.rest_state(),
        InitialState::Estimated => {
            let c = m.level_of(x0);
            mm.steady_state().iter().map(|v| v * c).collect()
        }
    };
    let sat = Saturation::default();
    let unmapped = LinearFitParams {
        map_segments: None,
        sat: &sat,
        ..*p
    };
    let (m2, x2, _) = refine_linear(&mm, &x0, &unmapped);
    Some((m2, x2))
}

/// The poles of a model with an output map refined on the simulation error: a bounded
/// Nelder–Mead search over the characteristic polynomial of `A` (stable, time constants below
/// twice the record), with the borders, `B`, `D`, the initial level and the map refit by
/// [`refine_linear`] for every candidate. Returns `None` when nothing improves.
pub(super) fn refine_poles_mapped(
    m: &HostModel,
    x0: &[f64],
    p: &LinearFitParams<'_>,
) -> Option<(HostModel, Vec<f64>, Option<OutputMap>)> {
    let (u, y, skip, initial) = (p.u, p.y, p.skip, p.initial);
    let (a0, obs) = m.to_observer()?;
    let n = a0.len();
    let limit = 1.0 - 0.5 / u.len().max(4) as f64;
    let level = m.level_of(x0);
    let eval = |a: &[f64]| -> Option<(f64, HostModel, Vec<f64>, Option<OutputMap>)> {
        if root_radius(a) >= limit {
            return None;
        }
        let mut mm = obs.clone();
        mm.a = observer_a(a);
        let xs = match initial {
            InitialState::Rest => mm.rest_state(),
            InitialState::Estimated => mm.steady_state().iter().map(|v| v * level).collect(),
        };
        let (m2, x2, g) = refine_linear(&mm, &xs, p);
        let lin = m2.linear_response(&m2.nonlinearity_output(u), &x2);
        let sse: f64 = lin
            .iter()
            .zip(y)
            .zip(skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| (y - g.as_ref().map_or(*l, |g| g.eval(*l))).powi(2))
            .sum();
        sse.is_finite().then_some((sse, m2, x2, g))
    };
    let start = eval(&a0)?;
    let mut simplex: Vec<(Vec<f64>, f64)> = vec![(a0.clone(), start.0)];
    for k in 0..n {
        let mut v = a0.clone();
        v[k] += 2e-3 * a0[k].abs().max(0.1);
        let f = eval(&v).map_or(f64::INFINITY, |e| e.0);
        simplex.push((v, f));
    }
    for _ in 0..40 * n {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        if worst.is_finite() && worst - best <= 1e-7 * best.max(1e-300) {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|k| simplex[..n].iter().map(|v| v.0[k]).sum::<f64>() / n as f64)
            .collect();
        let along = |t: f64| -> Vec<f64> {
            (0..n)
                .map(|k| centroid[k] + t * (simplex[n].0[k] - centroid[k]))
                .collect()
        };
        let score = |v: &[f64]| eval(v).map_or(f64::INFINITY, |e| e.0);
        let r = along(-1.0);
        let fr = score(&r);
        if fr < simplex[0].1 {
            let e = along(-2.0);
            let fe = score(&e);
            simplex[n] = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (r, fr);
        } else {
            let c = along(0.5);
            let fc = score(&c);
            if fc < simplex[n].1 {
                simplex[n] = (c, fc);
            } else {
                let b = simplex[0].0.clone();
                for v in simplex.iter_mut().skip(1) {
                    let s: Vec<f64> = v.0.iter().zip(&b).map(|(x, b)| b + 0.5 * (x - b)).collect();
                    let f = score(&s);
                    *v = (s, f);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    if simplex[0].1.partial_cmp(&start.0) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let (_, m2, x2, g) = eval(&simplex[0].0)?;
    Some((m2, x2, g))
}
