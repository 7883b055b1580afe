//! The starting model of the fit, from a subspace estimate: its linear part with `G(1) = 1`,
//! and borders either the estimate's own paths or its centre line opened into a play.
//!
//! The two-path estimate's paths `P_a`, `P_d` are the borders travelled on full sweeps; on an
//! ordinary input they are smeared by the inner loops, and the static estimate has no gap at
//! all. So the start is the best, by simulation error on the record, of the estimate's paths
//! and of the centre line `c = (P_a + P_d)/2` shifted by `∓g/2` along the input for a ladder
//! of plays `g` (2 % to 30 % of the input range): one simulation per candidate, which puts
//! the gap within the Levenberg–Marquardt basin whatever the start. On a slow ordinary input
//! the subspace estimate's poles are good but its border values can be far off (neighbouring
//! hat regressors are nearly collinear within its horizons); so the centre line is also
//! refitted by least squares through the estimate's `G` over the whole record, and the
//! ladder is built on both centre lines.

use super::error::HysteresisError;
use super::params::HysteresisModel;
use super::simulate::simulate;
use crate::identify::HostModel;
use crate::model::MemoryElement;
use crate::numerics::hat::hat_weights;
use crate::numerics::lstsq::{Scaling, lstsq_columns};
use crate::numerics::poly::tf_from_ss;
use crate::refine::signal::filter;
use crate::sim::{Backlash, Nonlinearity, Switch};

/// Which subspace estimate started the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// The two-path model (the paper's structure).
    TwoPath,
    /// The static model (one border for both directions).
    Static,
}

/// The plays tried, as fractions of the input range.
const PLAYS: [f64; 12] = [
    0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.12, 0.15, 0.2, 0.3,
];

/// The element of `kind` with borders `u ∓ g/2` applied to the input.
fn input_play(kind: MemoryElement, g: f64, u: &[f64]) -> Vec<f64> {
    let h = 0.5 * g;
    let mut el: Box<dyn Nonlinearity> = match kind {
        MemoryElement::Play => Box::new(
            Backlash::from_fns(move |x| x - h, move |x| x + h)
                .with_initial_output(u.first().copied().unwrap_or(0.0)),
        ),
        MemoryElement::Relay => Box::new(Switch::from_fns(move |x| x - h, move |x| x + h)),
    };
    u.iter().map(|&x| el.step(x)).collect()
}

/// Linear interpolation through `(k, v)`, extended linearly beyond the ends.
fn extended(k: &[f64], v: &[f64], u: f64) -> f64 {
    let last = k.len() - 1;
    let i = k.partition_point(|&x| x <= u).clamp(1, last);
    v[i - 1] + (v[i] - v[i - 1]) * (u - k[i - 1]) / (k[i] - k[i - 1])
}

/// Checks the estimate and returns its normalised linear part `(F, B)` and the gain `G(1)`.
fn linear_part(
    m: &HostModel,
    feedthrough: bool,
) -> Result<(Vec<f64>, Vec<f64>, f64), HysteresisError> {
    if m.order == 0 || m.a.nrows() != m.order || m.b.len() != m.order || m.c.len() != m.order {
        return Err(HysteresisError::InvalidStart(format!(
            "order {} with A {}×{}, B {} and C {} entries",
            m.order,
            m.a.nrows(),
            m.a.ncols(),
            m.b.len(),
            m.c.len()
        )));
    }
    let (mut num, den) = tf_from_ss(&m.a, &m.b, &m.c, m.d);
    if !feedthrough {
        num[0] = 0.0;
    }
    let gain = num.iter().sum::<f64>() / den.iter().sum::<f64>();
    if !gain.is_finite() || gain.abs() < 1e-12 {
        return Err(HysteresisError::InvalidStart(format!(
            "its static gain G(1) = {gain} cannot be normalised to 1"
        )));
    }
    let b = num.iter().map(|v| v / gain).collect();
    Ok((den, b, gain))
}

/// Knots, `P_a` and `P_d` at them.
type Paths = (Vec<f64>, Vec<f64>, Vec<f64>);

/// The estimate's borders on its ascending knots, in the units of `G(1) = 1`.
fn paths(m: &HostModel, gain: f64) -> Result<Paths, HysteresisError> {
    let k = m.knots_asc.clone();
    let ok = k.len() >= 2
        && k.windows(2).all(|w| w[0] < w[1])
        && m.border_asc.len() == k.len()
        && m.knots_desc.len() == m.border_desc.len()
        && m.knots_desc.len() >= 2;
    if !ok {
        return Err(HysteresisError::InvalidStart(
            "its knots do not increase strictly or do not match its border values".into(),
        ));
    }
    let a: Vec<f64> = m.border_asc.iter().map(|v| v * gain).collect();
    let d: Vec<f64> = k
        .iter()
        .map(|&u| gain * extended(&m.knots_desc, &m.border_desc, u))
        .collect();
    Ok((k, a, d))
}

/// The static border through `G = B/F` that fits the record best by least squares: the
/// regressors are the hat functions of the input filtered by `G`, and the free response of a
/// plant resting at an unknown level before the record (`1 − G·1`). Then `B` and the border
/// alternately (the output is bilinear in them; `F` is kept, the subspace poles being good),
/// `B` renormalised to `G(1) = 1` each round. Returns the border, `B` and the resting level.
fn least_squares_centre(
    knots: &[f64],
    f: &[f64],
    b0: &[f64],
    u: &[f64],
    y: &[f64],
) -> Option<Centre> {
    let mut hats = vec![vec![0.0; u.len()]; knots.len()];
    for (t, &x) in u.iter().enumerate() {
        let (s, th) = hat_weights(knots, x);
        hats[s][t] = 1.0 - th;
        hats[s + 1][t] = th;
    }
    let mut b = b0.to_vec();
    let mut beta = Vec::new();
    let mut level = f64::NAN;
    for round in 0..4 {
        let mut cols: Vec<Vec<f64>> = hats.iter().map(|h| filter(&b, f, h)).collect();
        let step = filter(&b, f, &vec![1.0; u.len()]);
        cols.push(step.iter().map(|v| 1.0 - v).collect());
        beta = lstsq_columns(&cols, y, Scaling::UnitDiagonal)?;
        level = beta.pop()?;
        if round == 3 {
            break;
        }
        // B given the border: y − level = Σ b_i q⁻ⁱ (1/F)(w − level).
        let w: Vec<f64> = u
            .iter()
            .map(|&x| crate::identify::interpolate(knots, &beta, x) - level)
            .collect();
        let fw = filter(&[1.0], f, &w);
        let first = usize::from(b0[0] == 0.0);
        let cols: Vec<Vec<f64>> = (first..b.len())
            .map(|i| crate::refine::signal::delay(&fw, i))
            .collect();
        let yl: Vec<f64> = y.iter().map(|v| v - level).collect();
        let free = lstsq_columns(&cols, &yl, Scaling::UnitDiagonal)?;
        let mut nb = vec![0.0; b.len()];
        nb[first..].copy_from_slice(&free);
        let gain = nb.iter().sum::<f64>() / f.iter().sum::<f64>();
        if !gain.is_finite() || gain.abs() < 1e-9 {
            return None;
        }
        b = nb.iter().map(|v| v / gain).collect();
    }
    (beta.iter().chain(&b).all(|v| v.is_finite()) && level.is_finite()).then_some(Centre {
        border: beta,
        b,
        level: Some(level),
        play: None,
    })
}

/// A centre line for the ladder of plays: the border values at the knots, the numerator `B`
/// that goes with it, the level the plant rested at before the record if it was estimated, and
/// the play it was fitted for (`None`: the subspace estimate's, tried with every play).
struct Centre {
    border: Vec<f64>,
    b: Vec<f64>,
    level: Option<f64>,
    play: Option<f64>,
}

/// The sum of squared simulation errors of `m` on the record.
fn sse(m: &HysteresisModel, u: &[f64], y: &[f64]) -> f64 {
    let s: f64 = simulate(m, u)
        .iter()
        .zip(y)
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    if s.is_finite() { s } else { f64::INFINITY }
}

/// The starting hysteresis model of `kind` from the subspace estimate `m` on the record.
pub(crate) fn start_model(
    m: &HostModel,
    kind: MemoryElement,
    feedthrough: bool,
    u: &[f64],
    y: &[f64],
) -> Result<HysteresisModel, HysteresisError> {
    let (f, b, gain) = linear_part(m, feedthrough)?;
    let (knots, pa, pd) = paths(m, gain)?;
    let mut centres = vec![Centre {
        border: pa.iter().zip(&pd).map(|(a, d)| 0.5 * (a + d)).collect(),
        b: b.clone(),
        level: None,
        play: None,
    }];
    let u0 = u.first().copied().unwrap_or(knots[0]);
    let with = |asc: Vec<f64>, desc: Vec<f64>, w0: f64, b: &[f64]| HysteresisModel {
        kind,
        f: f.clone(),
        b: b.to_vec(),
        feedthrough,
        w0,
        knots: knots.clone(),
        border_asc: asc,
        border_desc: desc,
    };
    let range = knots[knots.len() - 1] - knots[0];
    for p in PLAYS {
        // A play of constant width g composed with a monotone centre line c is c applied to
        // the play of the input itself, so c is linear in y for each g: least squares.
        let z = input_play(kind, p * range, u);
        if let Some(c) = least_squares_centre(&knots, &f, &b, &z, y) {
            centres.push(Centre { play: Some(p), ..c });
        }
    }
    // The model's first output is w(−1) (G strictly proper, resting in the steady state of
    // w(−1)): besides the centre line at the first input, the first measured output and the
    // least-squares resting level are tried for it. A w(−1) inside the play at the first input
    // holds the element still and is a local minimum of the simulation error that a plant
    // which starts away from the element's first output (at rest at 0 with the element at
    // u_min, say) cannot leave by Levenberg–Marquardt steps.
    let y0 = y.first().copied().unwrap_or(0.0);
    let ordered = |a: &[f64], d: &[f64]| -> (Vec<f64>, Vec<f64>) {
        a.iter().zip(d).map(|(a, d)| (a.min(*d), a.max(*d))).unzip()
    };
    let mut candidates = Vec::new();
    let mut push = |asc: Vec<f64>, desc: Vec<f64>, c: &Centre| {
        let mut w0s = vec![extended(&knots, &c.border, u0), y0];
        w0s.extend(c.level);
        for w0 in w0s {
            candidates.push(with(asc.clone(), desc.clone(), w0, &c.b));
        }
    };
    // The estimate's own paths (for a backlash ordered where they cross: H_a ≤ H_d).
    let (a0, d0) = match kind {
        MemoryElement::Play => ordered(&pa, &pd),
        MemoryElement::Relay => (pa.clone(), pd.clone()),
    };
    push(a0, d0, &centres[0]);
    for c in &centres {
        let plays = match c.play {
            Some(p) => vec![p],
            None => PLAYS.to_vec(),
        };
        for g in plays.iter().map(|p| 0.5 * p * range) {
            let lo: Vec<f64> = knots
                .iter()
                .map(|&x| extended(&knots, &c.border, x - g))
                .collect();
            let hi: Vec<f64> = knots
                .iter()
                .map(|&x| extended(&knots, &c.border, x + g))
                .collect();
            let (asc, desc) = ordered(&lo, &hi);
            push(asc, desc, c);
        }
    }
    candidates
        .into_iter()
        .map(|c| (sse(&c, u, y), c))
        .filter(|(e, _)| e.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
        .ok_or(HysteresisError::StartDoesNotSimulate)
}
