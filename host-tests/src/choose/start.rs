//! The subspace start on a record the method was not designed for: horizons the input can
//! support, and a stable start for the refinement when the subspace model is not stable.
//!
//! A band-limited input (a multisine, filtered noise, a smooth command, quantised levels)
//! excites fewer directions than the input Hankel Gram `[Z_f; Z_p]` has rows at the horizons
//! the plant's memory asks for, and the Gram is then numerically singular. When the horizons
//! are the desktop's own choice (not given), they are shortened, `f = p` by a third at a
//! time down to [`MIN_REDUCED_HORIZON`], until the Gram is of full rank; a line says so. Given
//! horizons are kept and the refusal stands.
//!
//! On the paper's experiment the subspace estimate is stable. On a slow plant, a plant in
//! closed loop or a record shorter than the plant's memory it can put a pole just outside the
//! unit circle, and the model is then refused although the record responds. When the model is
//! refined anyway, the subspace model is only the start: its poles outside the unit circle are
//! reflected inside (`z → 1/z̄`, which keeps the magnitude response's shape), every pole is
//! brought within [`MAX_START_RADIUS`], the numerator is rescaled so that `G(1) = 1` still
//! holds (the borders keep their static meaning), and the prediction-error refinement fits
//! poles, numerator, borders and noise model from there. The paper's estimator (no refinement)
//! keeps the strict refusal: its subspace model is the answer.

use crate::identify::{HostModel, IdentifyError, IdentifyOptions, identify};
use crate::numerics::poly::{from_roots, observer_form, roots, tf_from_ss};

use super::ModelStage;

/// The largest pole modulus of a stable start.
pub const MAX_START_RADIUS: f64 = 0.995;

/// What was done to the subspace model to start the refinement.
#[derive(Clone, Debug, PartialEq)]
pub struct StableStart {
    /// The subspace model's largest pole modulus.
    pub radius: f64,
    /// Poles reflected inside the unit circle.
    pub reflected: usize,
    /// Poles brought within [`MAX_START_RADIUS`] (after the reflection).
    pub shrunk: usize,
}

impl StableStart {
    /// One line for a report.
    pub fn report(&self) -> String {
        format!(
            "stable start: the subspace model had a pole of modulus {:.6} (not stable); {} \
             pole(s) reflected inside the unit circle and {} brought within {MAX_START_RADIUS}, \
             G(1) = 1 kept, and the refinement started from there",
            self.radius, self.reflected, self.shrunk
        )
    }
}

/// The shortest horizon tried when the input Hankel Gram is rank deficient.
pub const MIN_REDUCED_HORIZON: usize = 3;

/// Horizons shortened because the input Hankel Gram was rank deficient.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReducedHorizons {
    /// `f = p` asked for.
    pub from: usize,
    /// `f = p` at which the Gram was of full rank.
    pub to: usize,
}

impl ReducedHorizons {
    /// One line for a report.
    pub fn report(&self) -> String {
        format!(
            "horizons reduced to f = p = {}: the input Hankel Gram [Z_f; Z_p] was rank deficient \
             at f = p = {} (the input excites fewer directions than those horizons ask for: a \
             band-limited, smooth or quantised input)",
            self.to, self.from
        )
    }
}

/// The start of the refinement, or the paper's model: the subspace model, what was done to
/// get it.
pub(crate) struct SubspaceStart {
    /// The model.
    pub model: HostModel,
    /// Its poles moved inside the unit circle.
    pub stable: Option<StableStart>,
    /// Its horizons shortened.
    pub reduced: Option<ReducedHorizons>,
}

/// The subspace model of `(u, y)` with `opts`: with `reduce`, at horizons shortened until the
/// input Hankel Gram is of full rank (`opts.f`, `opts.p` set to them); when it is not stable
/// and `stage` refines it, the model with stable poles ([`stabilised`]) to start the
/// refinement from.
pub(crate) fn subspace_start(
    u: &[f64],
    y: &[f64],
    opts: &mut IdentifyOptions,
    stage: ModelStage,
    reduce: bool,
) -> Result<SubspaceStart, IdentifyError> {
    let from = opts.f.min(opts.p);
    let mut first_error = None;
    loop {
        match stable_start(u, y, opts, stage) {
            Ok((model, stable)) => {
                let reduced = (opts.f.min(opts.p) < from).then(|| ReducedHorizons {
                    from,
                    to: opts.f.min(opts.p),
                });
                return Ok(SubspaceStart {
                    model,
                    stable,
                    reduced,
                });
            }
            Err(e @ IdentifyError::Core(hsid::Error::RankDeficient { .. }))
                if reduce && opts.f.min(opts.p) > MIN_REDUCED_HORIZON =>
            {
                first_error.get_or_insert(e);
                let h = (opts.f.min(opts.p) * 2 / 3).max(MIN_REDUCED_HORIZON);
                (opts.f, opts.p) = (h, h);
            }
            Err(e) => return Err(first_error.unwrap_or(e)),
        }
    }
}

/// The subspace model of `(u, y)` with `opts`, and, when it is not stable and `stage` refines
/// it, the model with stable poles ([`stabilised`]) to start the refinement from.
fn stable_start(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    stage: ModelStage,
) -> Result<(HostModel, Option<StableStart>), IdentifyError> {
    match identify(u, y, opts) {
        Err(e @ IdentifyError::Core(hsid::Error::UnstableModel { .. }))
            if stage == ModelStage::Refined =>
        {
            let mut any = opts.clone();
            any.poles = hsid::Poles::Any;
            let model = identify(u, y, &any)?;
            match stabilised(&model) {
                Some((m, s)) => Ok((m, Some(s))),
                None => Err(e),
            }
        }
        other => other.map(|m| (m, None)),
    }
}

/// `model` with its poles reflected inside the unit circle and brought within
/// [`MAX_START_RADIUS`], the numerator rescaled to `G(1) = 1`; `None` when the roots cannot be
/// found or the numerator vanishes at `z = 1`.
pub fn stabilised(model: &HostModel) -> Option<(HostModel, StableStart)> {
    let (num, den) = tf_from_ss(&model.a, &model.b, &model.c, model.d);
    let poles = roots(&den)?;
    let radius = poles.iter().map(|(a, b)| a.hypot(*b)).fold(0.0, f64::max);
    let (mut reflected, mut shrunk) = (0, 0);
    let moved: Vec<(f64, f64)> = poles
        .iter()
        .map(|&(a, b)| {
            let mut m = a.hypot(b);
            let (mut a, mut b) = (a, b);
            if m > 1.0 {
                (a, b) = (a / (m * m), b / (m * m));
                m = 1.0 / m;
                reflected += 1;
            }
            if m > MAX_START_RADIUS {
                (a, b) = (a * MAX_START_RADIUS / m, b * MAX_START_RADIUS / m);
                shrunk += 1;
            }
            (a, b)
        })
        .collect();
    let den: Vec<f64> = from_roots(&moved);
    let (num_1, den_1) = (num.iter().sum::<f64>(), den.iter().sum::<f64>());
    let scale = num.iter().map(|v| v.abs()).sum::<f64>();
    let vanishes = num_1.abs() <= f64::EPSILON * scale;
    if vanishes || !num_1.is_finite() || !den_1.is_finite() {
        return None;
    }
    let num: Vec<f64> = num.iter().map(|v| v * den_1 / num_1).collect();
    let (a, b, c, d) = observer_form(&num, &den);
    let start = HostModel {
        a,
        b,
        c,
        d,
        ..model.clone()
    };
    Some((
        start,
        StableStart {
            radius,
            reflected,
            shrunk,
        },
    ))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::numerics::poly::spectral_radius;

    fn model(num: &[f64], den: &[f64]) -> HostModel {
        let (a, b, c, d) = observer_form(num, den);
        HostModel {
            order: den.len() - 1,
            a,
            b,
            c,
            d,
            mu0: 0.0,
            knots_asc: vec![0.0, 1.0],
            knots_desc: vec![0.0, 1.0],
            border_asc: vec![0.0, 1.0],
            border_desc: vec![0.0, 1.0],
            singular_values: vec![],
            whitened_singular_values: vec![],
            f: 10,
            p: 10,
            samples: 0,
        }
    }

    #[test]
    fn an_unstable_pole_is_reflected_and_g1_kept() {
        // Poles 1.25 and 0.5: z² − 1.75 z + 0.625, den(1) = −0.125; the numerator
        // 0.1 z − 0.225 has num(1) = −0.125, so G(1) = 1.
        let m = model(&[0.0, 0.1, -0.225], &[1.0, -1.75, 0.625]);
        let (s, what) = stabilised(&m).unwrap();
        assert_eq!((what.reflected, what.shrunk), (1, 0));
        assert!((what.radius - 1.25).abs() < 1e-9);
        let (num, den) = tf_from_ss(&s.a, &s.b, &s.c, s.d);
        // 1/1.25 = 0.8: (z − 0.8)(z − 0.5) = z² − 1.3 z + 0.4.
        for (x, y) in den.iter().zip([1.0, -1.3, 0.4]) {
            assert!((x - y).abs() < 1e-9, "{den:?}");
        }
        let g1 = num.iter().sum::<f64>() / den.iter().sum::<f64>();
        assert!((g1 - 1.0).abs() < 1e-9, "{g1}");
        assert!(spectral_radius(&den) < 1.0);
        assert_eq!(s.border_asc, m.border_asc);
    }

    #[test]
    fn a_pole_on_the_circle_is_brought_within_the_bound() {
        // Poles 1.0 (exactly) and 0.3: G(1) undefined there, so a numerator with num(1) ≠ 0
        // that the rescaling makes G(1) = 1 for the moved poles.
        let m = model(&[0.0, 1.0, 0.0], &[1.0, -1.3, 0.3]);
        let (s, what) = stabilised(&m).unwrap();
        assert_eq!((what.reflected, what.shrunk), (0, 1));
        let (num, den) = tf_from_ss(&s.a, &s.b, &s.c, s.d);
        assert!((spectral_radius(&den) - MAX_START_RADIUS).abs() < 1e-9);
        let g1 = num.iter().sum::<f64>() / den.iter().sum::<f64>();
        assert!((g1 - 1.0).abs() < 1e-9, "{g1}");
        // A stable model is returned as it is (nothing moved).
        let stable = model(&[0.0, 0.5], &[1.0, -0.5]);
        let (_, what) = stabilised(&stable).unwrap();
        assert_eq!((what.reflected, what.shrunk), (0, 0));
    }
}
