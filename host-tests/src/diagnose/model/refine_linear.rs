//! The linear part refined by least squares on the simulation error.

use crate::diagnose::output_map::OutputMap;
use crate::identify::HostModel;

use super::borders::{BdBasis, BorderBasis};
use super::fit_options::{InitialState, Saturation};
use super::output_fit::fit_output_map;

/// The record and the settings the linear part is refined on.
#[derive(Clone, Copy, Debug)]
pub(super) struct LinearFitParams<'a> {
    /// The (delayed) input.
    pub u: &'a [f64],
    /// The target output.
    pub y: &'a [f64],
    /// Samples left out of the squared error.
    pub skip: &'a [bool],
    /// Segments of a monotone output map fitted with the linear part, if any.
    pub map_segments: Option<usize>,
    /// The output map's saturation.
    pub sat: &'a Saturation,
    /// How the initial state is set.
    pub initial: InitialState,
    /// One border for both directions (a static nonlinearity).
    pub shared: bool,
}

/// Least-squares refinement with `A` and `C` fixed (the paper's Remark 5: `B` and `μ`
/// separately once `A` and `C` are known): alternately the border values (with μ0 and an
/// estimated initial state) and `[B; D]`, each a linear least squares; with an output map `g`,
/// alternately the monotone map by non-negative least squares and damped Gauss–Newton steps
/// of the borders and of `[B; D]` through the map (`ŷ = g(ℓ)`, Jacobian `g'(ℓ) ∂ℓ`: samples on a
/// flat part of `g` do not pull the linear part). Every step is kept only if it lowers the
/// squared error over the samples not skipped.
pub(super) fn refine_linear(
    m: &HostModel,
    x0: &[f64],
    p: &LinearFitParams<'_>,
) -> (HostModel, Vec<f64>, Option<OutputMap>) {
    let LinearFitParams {
        u,
        y,
        skip,
        map_segments,
        sat,
        initial,
        shared,
    } = *p;
    let lin_of = |m: &HostModel, x0: &[f64]| m.linear_response(&m.nonlinearity_output(u), x0);
    let fit_map = |lin: &[f64]| map_segments.and_then(|k| fit_output_map(lin, y, skip, k, sat));
    let sse = |lin: &[f64], g: &Option<OutputMap>| -> f64 {
        lin.iter()
            .zip(y)
            .zip(skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| (y - g.as_ref().map_or(*l, |g| g.eval(*l))).powi(2))
            .sum()
    };
    let mut model = m.clone();
    let mut state = x0.to_vec();
    let mut lin = lin_of(&model, &state);
    let mut g = fit_map(&lin);
    let mut best = sse(&lin, &g);
    if !best.is_finite() {
        return (model, state, g);
    }
    for _ in 0..4 {
        let mut improved = false;
        for part in 0..2 {
            let slope: Vec<f64> = lin
                .iter()
                .map(|&l| g.as_ref().map_or(1.0, |g| g.slope_at(l)))
                .collect();
            let rhs: Vec<f64> = (0..y.len())
                .map(|t| y[t] - g.as_ref().map_or(lin[t], |g| g.eval(lin[t])) + slope[t] * lin[t])
                .collect();
            let w = g.as_ref().map(|_| slope.as_slice());
            // The unknowns now and their least-squares solution.
            let (bb, bd) = if part == 0 {
                (BorderBasis::new(&model, u, initial, shared), None)
            } else {
                (None, BdBasis::new(&model, u, &state, initial))
            };
            let step = match (&bb, &bd) {
                (Some(b), _) => b
                    .solve(&rhs, w, skip)
                    .map(|next| (b.unknowns(&model, &state), next)),
                (_, Some(b)) => b
                    .solve(&rhs, w, skip)
                    .map(|next| (b.unknowns(&model), next)),
                _ => None,
            };
            let Some((now, next)) = step else { continue };
            let mut a = 1.0;
            for _ in 0..5 {
                let trial: Vec<f64> = now
                    .iter()
                    .zip(&next)
                    .map(|(b, n)| b + a * (n - b))
                    .collect();
                let built = match (&bb, &bd) {
                    (Some(b), _) => Some(b.apply(&model, &trial)),
                    (_, Some(b)) => b.apply(&model, &trial),
                    _ => None,
                };
                if let Some((m2, x2)) = built {
                    let l2 = lin_of(&m2, &x2);
                    let g2 = if g.is_some() { fit_map(&l2) } else { None };
                    let e = sse(&l2, &g2);
                    if e < best * (1.0 - 1e-9) {
                        best = e;
                        model = m2;
                        state = x2;
                        lin = l2;
                        g = g2;
                        improved = true;
                        break;
                    }
                }
                a *= 0.5;
            }
        }
        if !improved {
            break;
        }
    }
    (model, state, g)
}
