//! Model classes for state-dependent dynamics that no static input map, linear `G` and static
//! output map can reproduce, beyond the one [`super::diagnose`] proposes (the level-dependent
//! stores, [`super::stores`], which have one steady state per input by construction). The
//! example `tanks_dynamics` fits these on the cascaded tanks benchmark and reports what they
//! do (`docs/closing-the-loop.md`): there the polynomial fit the inner cross-validation ranks
//! first has more than one steady state for one constant input ([`unique_steady_states`]),
//! which the plant does not have, so the diagnosis does not propose them. Two classes:
//!
//! **Polynomial state term** ([`fit`]), in the spirit of polynomial nonlinear state-space
//! models (NLSS):
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
//! bounded. The model starts from the current (linear) model with `E = 0`; `A`, `B`, `D`, `E`,
//! an estimated initial state and, if asked ([`Borders`]), the border values are then fitted
//! on the **simulation** error (the output map, `C` and the additive terms held).
//!
//! **Internal overflow** ([`fit_overflow`]): an order-2 model with real poles written as a
//! cascade of two stores, the first one overflowing into the second above a level `L`:
//!
//! ```text
//! s1 = p1 x1 + h,   s2 = p2 x2 + x1
//! x1(t+1) = min(s1, L),   x2(t+1) = s2 + k · max(s1 − L, 0),   y = g( c1 x1 + c2 x2 + d h )
//! ```
//!
//! With `L` above every level the first store reaches this is the linear model (any stable
//! order-2 `G` with real poles has this cascade form). `p1, p2, c1, c2, d, L, k` and the
//! initial state are fitted on the simulation error.
//!
//! Both fits are Levenberg–Marquardt ([`crate::numerics::lm`]): a step is accepted only if its
//! simulation is finite and the model stays stable; iterations are bounded.

use nalgebra::DMatrix;
use serde::Serialize;

use crate::numerics::lm::{Settings, levenberg_marquardt};

use crate::identify::HostModel;

/// Why a model class beyond the catalog could not be fitted.
#[derive(Clone, Debug, PartialEq)]
pub enum DynamicsError {
    /// The model has no state or the record no samples.
    Empty {
        /// Model order.
        order: usize,
        /// Samples.
        samples: usize,
    },
    /// The starting model does not simulate the record (non-finite output).
    NotSimulating,
    /// The fitted model has more than one steady state for a constant input: from the lowest
    /// and the highest state the record visits it settles at different outputs (the plant
    /// is assumed to have one steady state per input level, the static gain curve).
    Multistable {
        /// The constant `h` where the steady states differ.
        level: f64,
        /// Two of the steady outputs it settles at.
        outputs: (f64, f64),
    },
    /// The internal-overflow class needs an order-2 model with real poles.
    NotTwoRealPoles {
        /// The model's poles `(re, im)`.
        poles: Vec<(f64, f64)>,
    },
    /// Level-dependent stores start from an order-2 model.
    NotOrderTwo {
        /// The model's order.
        order: usize,
    },
}

impl std::fmt::Display for DynamicsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DynamicsError::Empty { order, samples } => write!(
                f,
                "nonlinear dynamics need a model of order ≥ 1 and data (order {order}, {samples} samples)"
            ),
            DynamicsError::NotSimulating => write!(
                f,
                "the model to extend does not simulate the record (non-finite output); fit the linear model first"
            ),
            DynamicsError::Multistable { level, outputs } => write!(
                f,
                "the fitted polynomial state term has more than one steady state at h = {level:.4} (outputs {:.4} and {:.4}, from the lowest and the highest state the record visits): refused",
                outputs.0, outputs.1
            ),
            DynamicsError::NotTwoRealPoles { poles } => write!(
                f,
                "the internal-overflow class needs an order-2 model with two real poles; the model has {poles:?}"
            ),
            DynamicsError::NotOrderTwo { order } => write!(
                f,
                "level-dependent stores (a cascade of two stores) start from an order-2 model; the model has order {order}"
            ),
        }
    }
}

impl std::error::Error for DynamicsError {}

/// The polynomial state term of a model with nonlinear dynamics.
#[derive(Clone, Debug, PartialEq, Serialize)]
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
fn states(m: &HostModel, poly: Option<&StatePoly>, h: &[f64], x0: &[f64]) -> Vec<Vec<f64>> {
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
/// of the steady outputs. [`DynamicsError::Multistable`] names the first level where they
/// do not.
pub fn unique_steady_states(
    m: &HostModel,
    poly: &StatePoly,
    h: &[f64],
    x0: &[f64],
) -> Result<(), DynamicsError> {
    let xs = states(m, Some(poly), h, x0);
    if xs.iter().flatten().any(|v| !v.is_finite()) {
        return Err(DynamicsError::NotSimulating);
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
            return Err(DynamicsError::NotSimulating);
        }
        if (a - b).abs() > tol {
            return Err(DynamicsError::Multistable {
                level,
                outputs: (a, b),
            });
        }
    }
    Ok(())
}

/// What the fit holds fixed and what it fits to.
pub struct DynamicsFit<'a> {
    /// Output of the input nonlinearity (delay included).
    pub h: &'a [f64],
    /// Target of the linear part's output through the output map: the measured output minus
    /// the additive terms.
    pub y: &'a [f64],
    /// Samples left out of the error (outliers).
    pub skip: &'a [bool],
    /// Output map, held (`None`: identity).
    pub map: Option<&'a super::output_map::OutputMap>,
    /// Whether the initial state is fitted too.
    pub fit_x0: bool,
    /// Largest spectral radius of `A` allowed.
    pub radius_limit: f64,
    /// Iterations of Levenberg–Marquardt.
    pub iterations: usize,
    /// Refit the border values too (`None`: held, `h` as given).
    pub borders: Option<Borders<'a>>,
}

/// The input whose border values are refitted with the polynomial.
#[derive(Clone, Copy, Debug)]
pub struct Borders<'a> {
    /// Input (delay included), the record `h` came from.
    pub u: &'a [f64],
    /// One border for both directions (static nonlinearity).
    pub shared: bool,
}

impl DynamicsFit<'_> {
    /// The error the fit minimises for a linear part's output `lin`: the target minus
    /// `g(lin)`, the skipped samples left out; `None` if it is not finite.
    pub fn residual(&self, lin: &[f64]) -> Option<Vec<f64>> {
        let r: Vec<f64> = lin
            .iter()
            .zip(self.y)
            .zip(self.skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| y - self.map.map_or(*l, |g| g.eval(*l)))
            .collect();
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    /// The input nonlinearity's output for a model whose border values may be refitted:
    /// recomputed from [`Borders::u`] if they are (`None` if they are held: `h` as given).
    pub fn refitted_h(&self, m: &HostModel) -> Option<Vec<f64>> {
        self.borders
            .map(|b| super::simulate::nonlinearity_output(m, b.u))
    }
}

impl Borders<'_> {
    /// Appends a model's border values to `θ`: the ascending ones, then unless shared the
    /// descending ones.
    pub fn pack(&self, m: &HostModel, theta: &mut Vec<f64>) {
        theta.extend_from_slice(&m.border_asc);
        if !self.shared {
            theta.extend_from_slice(&m.border_desc);
        }
    }

    /// Reads the border values [`Borders::pack`] appended back into a model (a shared border
    /// is copied to both directions).
    pub fn unpack(&self, values: &mut impl Iterator<Item = f64>, m: &mut HostModel) {
        for v in m.border_asc.iter_mut() {
            *v = values.next().unwrap_or(*v);
        }
        if self.shared {
            m.border_desc.clone_from(&m.border_asc);
        } else {
            for v in m.border_desc.iter_mut() {
                *v = values.next().unwrap_or(*v);
            }
        }
    }
}

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
        crate::numerics::poly::eigenvalues(a).map_or(f64::INFINITY, |ev| {
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

/// An order-2 model as a cascade of two stores, the first overflowing into the second (see
/// the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize)]
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
    fn first_store_range(&self, h: &[f64]) -> (f64, f64) {
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

/// The two cascade forms (one per assignment of the poles to the stores) of an order-2 model
/// with real poles; they have the same transfer function `G − D` as the model.
pub fn cascade_forms(m: &HostModel) -> Result<[Cascade; 2], DynamicsError> {
    let poles = m.poles();
    if m.order != 2 || poles.len() != 2 || poles.iter().any(|p| p.1 != 0.0) {
        return Err(DynamicsError::NotTwoRealPoles { poles });
    }
    Ok(cascade_forms_with(m, poles[0].0, poles[1].0))
}

/// The cascade forms of an order-2 model's numerator `G − D = (β1 z + β0) / (…)` over the
/// real poles `p1`, `p2` (the model's own, or real ones near them).
pub fn cascade_forms_with(m: &HostModel, p1: f64, p2: f64) -> [Cascade; 2] {
    let (a, b, c) = (&m.a, &m.b, &m.c);
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

/// Fits the internal-overflow class to an order-2 model with real poles (`A`, `B`, `C`, `D`
/// give the start; the borders and the output map are held). Both assignments of the poles
/// to the stores and three starting levels (60, 75, 90 % of the way from the lowest to the
/// highest level the first store reaches without overflow) are tried; the fit with the least
/// squared simulation error is returned.
pub fn fit_overflow(
    m: &HostModel,
    x0: &[f64],
    data: &DynamicsFit,
) -> Result<Overflow, DynamicsError> {
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
    best.map(|(_, o)| o).ok_or(DynamicsError::NotSimulating)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// An order-2 model with the given matrices (borders the identity on [0, 1]).
    pub(crate) fn model(a: [[f64; 2]; 2], b: [f64; 2], c: [f64; 2], d: f64) -> HostModel {
        HostModel {
            order: 2,
            a: DMatrix::from_fn(2, 2, |i, j| a[i][j]),
            b: b.to_vec(),
            c: c.to_vec(),
            d,
            mu0: 0.0,
            knots_asc: vec![0.0, 1.0],
            knots_desc: vec![0.0, 1.0],
            border_asc: vec![0.0, 1.0],
            border_desc: vec![0.0, 1.0],
            singular_values: Vec::new(),
            whitened_singular_values: Vec::new(),
            f: 10,
            p: 10,
            samples: 0,
        }
    }

    /// A staircase of pseudo-random levels in [0, 1], 20 samples each.
    pub(crate) fn levels(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        let mut level = 0.0;
        (0..n)
            .map(|t| {
                if t % 20 == 0 {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    level = (s >> 11) as f64 / (1u64 << 53) as f64;
                }
                level
            })
            .collect()
    }

    pub(crate) fn rms(a: &[f64], b: &[f64]) -> f64 {
        (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
    }

    /// The plant of the polynomial class: the test's linear model plus a quadratic term in
    /// its first state.
    fn quadratic_plant(h: &[f64]) -> Vec<f64> {
        let mut x = [0.0f64; 2];
        h.iter()
            .map(|&hi| {
                let y = x[0] + 0.5 * x[1];
                x = [
                    0.9 * x[0] + 0.05 * x[1] + 0.1 * hi - 0.15 * x[0] * x[0],
                    0.8 * x[1] + 0.2 * hi,
                ];
                y
            })
            .collect()
    }

    /// Noise-free data, every sample fitted, the initial state held at zero.
    fn exact<'a>(
        h: &'a [f64],
        y: &'a [f64],
        skip: &'a [bool],
        iterations: usize,
        borders: Option<Borders<'a>>,
    ) -> DynamicsFit<'a> {
        DynamicsFit {
            h,
            y,
            skip,
            map: None,
            fit_x0: false,
            radius_limit: 0.999,
            iterations,
            borders,
        }
    }

    type Outcome = Result<(), Box<dyn std::error::Error>>;

    #[test]
    fn polynomial_term_fits_a_plant_of_its_class() -> Outcome {
        // The plant: the linear model plus a quadratic term in its first state. Started from
        // the linear model, the fit must explain what the linear model misses.
        let lin = model([[0.9, 0.05], [0.0, 0.8]], [0.1, 0.2], [1.0, 0.5], 0.0);
        let h = levels(1500, 7);
        let y = quadratic_plant(&h);
        let skip = vec![false; h.len()];
        let data = exact(&h, &y, &skip, 50, None);
        let before = rms(
            &simulate(&lin, None, &h, &[0.0, 0.0]).ok_or("not simulated")?,
            &y,
        );
        let (m, poly, x0) = fit(&lin, &[0.0, 0.0], 2, &data)?;
        let after = rms(
            &simulate(&m, Some(&poly), &h, &x0).ok_or("not simulated")?,
            &y,
        );
        // On another input of the same range (not fitted).
        let h2 = levels(1500, 99);
        let y2 = quadratic_plant(&h2);
        let before2 = rms(
            &simulate(&lin, None, &h2, &[0.0, 0.0]).ok_or("not simulated")?,
            &y2,
        );
        let after2 = rms(
            &simulate(&m, Some(&poly), &h2, &x0).ok_or("not simulated")?,
            &y2,
        );
        assert!(after < 0.02 * before, "fitted: {before:.3e} → {after:.3e}");
        assert!(
            after2 < 0.05 * before2,
            "new input: {before2:.3e} → {after2:.3e}"
        );
        Ok(())
    }

    #[test]
    fn borders_refitted_with_the_polynomial() -> Outcome {
        // The plant's element is h = u² on [0, 1] (static); the starting model holds the
        // identity border. With the borders held the fit cannot reach the plant; refitted
        // with the polynomial the error must at least halve.
        let mut lin = model([[0.9, 0.05], [0.0, 0.8]], [0.1, 0.2], [1.0, 0.5], 0.0);
        lin.knots_asc = (0..=8).map(|k| f64::from(k) / 8.0).collect();
        lin.knots_desc = lin.knots_asc.clone();
        lin.border_asc = lin.knots_asc.clone();
        lin.border_desc = lin.knots_asc.clone();
        let u = levels(2000, 5);
        let h_true: Vec<f64> = u.iter().map(|v| v * v).collect();
        let y = quadratic_plant(&h_true);
        let skip = vec![false; u.len()];
        let h_start = super::super::simulate::nonlinearity_output(&lin, &u);
        let fit_with = |borders: Option<Borders>| {
            fit(
                &lin,
                &[0.0, 0.0],
                2,
                &exact(&h_start, &y, &skip, 60, borders),
            )
        };
        let (m0, p0, x0) = fit_with(None)?;
        let held = rms(&simulate(&m0, Some(&p0), &h_start, &x0).ok_or("held")?, &y);
        let (m1, p1, x1) = fit_with(Some(Borders {
            u: &u,
            shared: true,
        }))?;
        let h1 = super::super::simulate::nonlinearity_output(&m1, &u);
        let refit = rms(&simulate(&m1, Some(&p1), &h1, &x1).ok_or("refit")?, &y);
        assert_eq!(
            m1.border_asc, m1.border_desc,
            "a shared border stays shared"
        );
        assert!(
            refit < 0.5 * held,
            "borders held {held:.3e}, refitted {refit:.3e}"
        );
        Ok(())
    }

    #[test]
    fn two_steady_states_are_found() -> Outcome {
        // x₁⁺ = 1.5 x₁ − 0.5 x₁³ + 0.1 h settles near −1 or +1 for small h depending on where
        // it starts; x₂ follows x₁. An input that visits both wells must expose it.
        let m = model([[1.5, 0.0], [0.5, 0.5]], [0.1, 0.0], [1.0, 0.0], 0.0);
        let monomials = monomials(3, 3);
        let k = monomials.len();
        let cube = monomials
            .iter()
            .position(|e| e.as_slice() == [3, 0, 0])
            .ok_or("x₁³ monomial")?;
        let mut e = vec![0.0; 2 * k];
        e[cube] = -0.5;
        let poly = StatePoly {
            degree: 3,
            center: vec![0.0; 3],
            scale: vec![1.0; 3],
            low: vec![-10.0; 3],
            high: vec![10.0; 3],
            monomials,
            e,
        };
        let h: Vec<f64> = (0..400)
            .map(|t| if (t / 100) % 2 == 0 { 2.0 } else { -2.0 })
            .collect();
        assert!(matches!(
            unique_steady_states(&m, &poly, &h, &[0.0, 0.0]),
            Err(DynamicsError::Multistable { .. })
        ));
        // Without the cubic term (and a stable A) there is one steady state per level.
        let mut stable = m.clone();
        stable.a[(0, 0)] = 0.5;
        let linear = StatePoly {
            e: vec![0.0; 2 * k],
            ..poly
        };
        unique_steady_states(&stable, &linear, &h, &[0.0, 0.0])?;
        Ok(())
    }

    #[test]
    fn overflow_fit_finds_the_level_and_the_spill() -> Outcome {
        // A cascade whose first store overflows at 3 with 60 % of the excess reaching the
        // second; the start is the same cascade without the overflow (a linear model).
        let truth = Overflow {
            p1: 0.9,
            p2: 0.85,
            c1: 0.0,
            c2: 0.2,
            d: 0.0,
            level: 3.0,
            spill: 0.6,
            x0: [0.0, 0.0],
        };
        let lin = model([[0.9, 0.0], [1.0, 0.85]], [1.0, 0.0], [0.0, 0.2], 0.0);
        let h: Vec<f64> = levels(2000, 3).iter().map(|v| 0.5 * v).collect();
        let y = truth.simulate(&h).ok_or("not simulated")?;
        let (_, peak) = truth.first_store_range(&h);
        assert!(
            peak > 3.5,
            "the test input must make the store overflow (peak {peak})"
        );
        let skip = vec![false; h.len()];
        let data = exact(&h, &y, &skip, 100, None);
        let o = fit_overflow(&lin, &[0.0, 0.0], &data)?;
        let after = rms(&o.simulate(&h).ok_or("not simulated")?, &y);
        assert!((o.level - 3.0).abs() < 1e-3, "{o:?}");
        assert!((o.spill - 0.6).abs() < 1e-3, "{o:?}");
        assert!(after < 1e-6, "{after:e}");
        // Complex poles are refused with what the class needs.
        let osc = model([[0.9, -0.3], [0.3, 0.9]], [1.0, 0.0], [0.0, 1.0], 0.0);
        assert!(matches!(
            fit_overflow(&osc, &[0.0, 0.0], &data),
            Err(DynamicsError::NotTwoRealPoles { .. })
        ));
        Ok(())
    }

    #[test]
    fn monomials_leave_out_pure_input_powers() {
        // Two states and h, degree 2: x1², x1x2, x1h, x2², x2h (h² left out).
        assert_eq!(monomials(3, 2).len(), 5);
        // Degree 3 adds the 10 cubic monomials but h³: 9.
        assert_eq!(monomials(3, 3).len(), 14);
        // One state: x², xh; cubic x³, x²h, xh².
        assert_eq!(monomials(2, 2).len(), 2);
        assert_eq!(monomials(2, 3).len(), 5);
        assert!(monomials(3, 3).iter().all(|m| m[0] + m[1] > 0));
    }
}
