//! Remark 5: `B` and `μ` separately once `A` and `C` are known.
//!
//! Eq. (14) splits the over-parameterised `[D; B]` (an `(n+1) × m` matrix estimated with all
//! its `(n+1)·m` entries free) by a rank-1 SVD. With `A` and `C` fixed, the model output is
//! bilinear in `(B, D)` and the border coefficients `c` (hat basis, `cᵢ = vᵢ − μ0`):
//! `ȳ(t) = Σᵢ cᵢ [C (qI − A)⁻¹ B + D] wᵢ(t) + v(t)`. Alternating least squares on the whole
//! record — `(B, D)` with `c` fixed (regressors `C (qI − A)⁻¹ eᵢ (H − μ0)` and `H − μ0`),
//! then `c` with `(B, D)` fixed (regressors `G(q) wᵢ`) — decreases the output-error cost at
//! every half step and estimates `n + 1 + m` numbers instead of `(n + 1)·m`. The scale is
//! fixed at the end by `G(1) = 1`. The plant starts at rest at μ0 at `start` (inside the
//! settled hold), μ0 being the hold's.

use nalgebra::{DMatrix, DVector};

use super::RefineError;
use super::poly::tf_from_ss;
use super::signal::{HatRegressors, filter};
use crate::identify::HostModel;
use crate::numerics::lstsq::{Scaling, lstsq_columns};

/// The outcome of [`split`].
#[derive(Clone, Debug)]
pub struct BilinearFit {
    /// The model with the subspace `A`, `C`, μ0 and the new `B`, `D` and borders.
    pub model: HostModel,
    /// Alternations done.
    pub iterations: usize,
    /// Mean squared output error at the end.
    pub mse: f64,
}

/// Re-estimates `B`, `D` and the borders of `model` with its `A`, `C` and μ0 fixed, by
/// alternating least squares on `(u, y)` from `start` (see the [module docs](self)); `shared`
/// for a static nonlinearity (one border for both directions).
pub fn split(
    model: &HostModel,
    u: &[f64],
    y: &[f64],
    start: usize,
    max_iter: usize,
    shared: bool,
) -> Result<BilinearFit, RefineError> {
    if u.len() != y.len() {
        return Err(RefineError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let n = model.order;
    if n == 0 || model.a.nrows() != n || model.c.len() != n {
        return Err(RefineError::InvalidModel("order 0 or inconsistent sizes"));
    }
    let hat = HatRegressors::build(u, &model.knots_asc, &model.knots_desc, shared)?;
    let m = hat.channels() - 1;
    let start = start.min(u.len());
    if u.len() - start < 4 * (n + 1 + m) {
        return Err(RefineError::TooFewSamples {
            have: u.len() - start,
            need: 4 * (n + 1 + m),
        });
    }
    let w: Vec<Vec<f64>> = hat
        .dense()
        .into_iter()
        .skip(1)
        .map(|c| c[start..].to_vec())
        .collect();
    let yb: Vec<f64> = y[start..].iter().map(|v| v - model.mu0).collect();
    // Unit-input responses C (qI − A)⁻¹ e_i as transfer functions.
    let unit: Vec<(Vec<f64>, Vec<f64>)> = (0..n)
        .map(|i| {
            let mut e = vec![0.0; n];
            e[i] = 1.0;
            tf_from_ss(&model.a, &e, &model.c, 0.0)
        })
        .collect();
    let mut b = model.b.clone();
    let mut d = model.d;
    let mut c: Vec<f64> = hat
        .beta_of(model.mu0, &model.border_asc, &model.border_desc)
        .iter()
        .skip(1)
        .map(|v| v - model.mu0)
        .collect();
    let mut last = f64::INFINITY;
    let mut iterations = 0;
    let mut mse = f64::NAN;
    for it in 1..=max_iter.max(1) {
        iterations = it;
        // (B, D) with c fixed.
        let mut hd = vec![0.0; yb.len()];
        for (ci, wi) in c.iter().zip(&w) {
            hd.iter_mut().zip(wi).for_each(|(h, x)| *h += ci * x);
        }
        let mut cols: Vec<Vec<f64>> = unit.iter().map(|(nu, de)| filter(nu, de, &hd)).collect();
        cols.push(hd);
        let bd = lstsq_columns(&cols, &yb, Scaling::UnitDiagonal)
            .ok_or(RefineError::Singular("B, D given the borders"))?;
        b = bd[..n].to_vec();
        d = bd[n];
        // c with (B, D) fixed.
        let (num, den) = tf_from_ss(&model.a, &b, &model.c, d);
        let cols: Vec<Vec<f64>> = w.iter().map(|wi| filter(&num, &den, wi)).collect();
        c = lstsq_columns(&cols, &yb, Scaling::UnitDiagonal)
            .ok_or(RefineError::Singular("borders given B, D"))?;
        let mut fit = vec![0.0; yb.len()];
        for (ci, col) in c.iter().zip(&cols) {
            fit.iter_mut().zip(col).for_each(|(f, x)| *f += ci * x);
        }
        let cost: f64 = yb.iter().zip(&fit).map(|(a, b)| (a - b) * (a - b)).sum();
        if !cost.is_finite() {
            return Err(RefineError::Diverged { iteration: it });
        }
        mse = cost / yb.len() as f64;
        if (last - cost).abs() <= 1e-12 * cost {
            break;
        }
        last = cost;
    }
    // Scale: G(1) = C (I − A)⁻¹ B + D = 1.
    let ia = DMatrix::<f64>::identity(n, n) - &model.a;
    let x = ia
        .lu()
        .solve(&DVector::from_column_slice(&b))
        .ok_or(RefineError::InvalidModel("pole at 1"))?;
    let gain = model
        .c
        .iter()
        .zip(x.iter())
        .map(|(a, b)| a * b)
        .sum::<f64>()
        + d;
    if !(gain.is_finite() && gain.abs() > 1e-12) {
        return Err(RefineError::InvalidModel("zero static gain"));
    }
    let mut out = model.clone();
    out.b = b.iter().map(|v| v / gain).collect();
    out.d = d / gain;
    let beta: Vec<f64> = std::iter::once(model.mu0)
        .chain(c.iter().map(|v| model.mu0 + v * gain))
        .collect();
    let (ba, bd) = hat.borders_from_beta(&beta);
    out.border_asc = ba;
    out.border_desc = bd;
    Ok(BilinearFit {
        model: out,
        iterations,
        mse,
    })
}
