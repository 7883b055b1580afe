//! The data against the method's assumptions, before any fit. Every violation is a warning
//! that says what was found and what it costs.

use nalgebra::DMatrix;
use serde::Serialize;

use super::Nonlinearity;
use super::model::Saturation;
use super::residual::regressor;
use super::stats::{mean, newey_west_var_of_mean, normal_sf};

/// A violated assumption.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Warning {
    /// Which check (`table1_structure`, `path_coverage`, `persistent_excitation`, `hold`,
    /// `output_saturation`, `output_quantisation`, `input_levels`).
    pub check: String,
    /// What was found and its consequence, one sentence.
    pub message: String,
}

/// The levels at which the output saturates: an extreme (maximum or minimum) at which more
/// than 2 % of the samples sit (within 0.1 % of the output's span).
pub fn saturation(y: &[f64]) -> Saturation {
    let (ymin, ymax) = y
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let tolerance = 1e-3 * (ymax - ymin).max(1e-300);
    let level = |ext: f64| {
        let at = y.iter().filter(|&&v| (v - ext).abs() <= tolerance).count();
        (ext.is_finite() && at * 50 > y.len()).then_some(ext)
    };
    Saturation {
        ceiling: level(ymax),
        floor: level(ymin),
        tolerance,
    }
}

fn warn(check: &str, message: String) -> Warning {
    Warning {
        check: check.into(),
        message,
    }
}

/// What the checks need to know about the identification.
#[derive(Clone, Debug)]
pub struct CheckSetup<'a> {
    /// Nonlinearity kind.
    pub kind: Nonlinearity,
    /// Ascending knots.
    pub knots_asc: &'a [f64],
    /// Descending knots.
    pub knots_desc: &'a [f64],
    /// Hold samples at `u_min` (0: none).
    pub hold: usize,
    /// Samples of the hold skipped.
    pub settle: usize,
    /// A known μ0 was given.
    pub mu0_known: bool,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
}

/// Runs all checks on an estimation record.
pub fn check_data(u: &[f64], y: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let n = u.len();
    if n < 10 {
        return out;
    }
    let u_min = s.knots_asc.first().copied().unwrap_or(f64::NAN);
    let u_max = s.knots_asc.last().copied().unwrap_or(f64::NAN);
    let tol = 1e-9 * (u_max - u_min).abs().max(1e-300);
    let ex = &u[s.hold.min(n)..];

    // Table I: every monotone run starts at u_min (ascending) or u_max (descending).
    if s.kind != Nonlinearity::Static {
        let (mut runs, mut bad) = (0usize, 0usize);
        let mut dir = 0i8;
        for w in ex.windows(2) {
            let d = if w[1] > w[0] {
                1
            } else if w[1] < w[0] {
                -1
            } else {
                0
            };
            if d != 0 && d != dir {
                runs += 1;
                let ok = if d > 0 {
                    (w[0] - u_min).abs() <= tol
                } else {
                    (w[0] - u_max).abs() <= tol
                };
                if !ok {
                    bad += 1;
                }
                dir = d;
            }
        }
        if bad > 0 {
            let msg = match s.kind {
                Nonlinearity::Backlash => format!(
                    "{bad} of {runs} monotone input runs do not start at u_min (ascending) or u_max (descending), as the Table I excitation does: a backlash is then on inner loops, not on its paths P_a/P_d, and the identified borders are biased there"
                ),
                _ => format!(
                    "{bad} of {runs} monotone input runs do not start at u_min or u_max (not the Table I excitation): a switch only needs the direction, but the paths are then visited unevenly"
                ),
            };
            out.push(warn("table1_structure", msg));
        }
    }

    // Both paths over the whole interval.
    let shared = s.kind == Nonlinearity::Static;
    let (_, _, bins, count) = regressor(ex, s.knots_asc, s.knots_desc, shared);
    let na = s.knots_asc.len().saturating_sub(1);
    let mut counts = vec![0usize; count];
    for &b in &bins {
        if let Some(c) = counts.get_mut(b) {
            *c += 1;
        }
    }
    let need = 20.max(ex.len() / (5 * count.max(1)));
    let mut poor = Vec::new();
    for (b, &c) in counts.iter().enumerate() {
        if c < need {
            let (path, k, j) = if b < na || shared {
                ("ascending", s.knots_asc, b)
            } else {
                ("descending", s.knots_desc, b - na)
            };
            let path = if shared { "static" } else { path };
            if let (Some(a), Some(bb)) = (k.get(j), k.get(j + 1)) {
                poor.push(format!("{path} [{a:.3}, {bb:.3}]: {c}"));
            }
        }
    }
    if !poor.is_empty() {
        out.push(warn(
            "path_coverage",
            format!(
                "knot segments with fewer than {need} samples ({}): their border values are poorly determined (interpolated or extrapolated from neighbours)",
                poor.join("; ")
            ),
        ));
    }

    // Persistent excitation of order (f + p)·m of the regressor.
    let (_, z, _, _) = regressor(ex, s.knots_asc, s.knots_desc, shared);
    let m = z.len();
    let k = s.f + s.p;
    let dim = k * m;
    if dim > 0 && ex.len() > k + 10 {
        let cols = ex.len() - k + 1;
        // Block-Toeplitz Gram from lagged products R_ij(l) = Σ_t z_i(t) z_j(t + l).
        let mut r = vec![vec![vec![0.0; m]; m]; k];
        for (l, rl) in r.iter_mut().enumerate() {
            for (i, row) in rl.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (0..cols).map(|t| z[i][t] * z[j][t + l]).sum::<f64>() / cols as f64;
                }
            }
        }
        let g = DMatrix::from_fn(dim, dim, |a, b| {
            let (ba, ia) = (a / m, a % m);
            let (bb, ib) = (b / m, b % m);
            if bb >= ba {
                r[bb - ba][ia][ib]
            } else {
                r[ba - bb][ib][ia]
            }
        });
        let ev = g.symmetric_eigenvalues();
        let max = ev.max();
        let min = ev.min();
        let rank = ev.iter().filter(|&&v| v > 1e-9 * max).count();
        let well_conditioned = min > 1e-6 * max;
        if !well_conditioned {
            out.push(warn(
                "persistent_excitation",
                format!(
                    "the regressor is not persistently exciting of order (f+p)·m = {dim}: its Hankel Gram has numerical rank {rank} of {dim} ({}); the projection of eq. (11) is ill-conditioned and the model can be poor (shorter horizons or fewer knots help)",
                    if min > 1e-15 * max {
                        format!("condition {:.1e}", max / min)
                    } else {
                        "singular".to_string()
                    }
                ),
            ));
        }
    }

    // Hold for μ0.
    if s.hold > 0 {
        let settled = &y[s.settle.min(s.hold)..s.hold.min(n)];
        if settled.len() >= 20 {
            let h = settled.len() / 2;
            let (a, b) = (&settled[..h], &settled[h..]);
            let lags = 5;
            let diff = mean(a) - mean(b);
            let se = (newey_west_var_of_mean(a, lags) + newey_west_var_of_mean(b, lags)).sqrt();
            let z = diff / se.max(1e-300);
            if 2.0 * normal_sf(z.abs()) < 0.01 {
                out.push(warn(
                    "hold",
                    format!(
                        "the output still moves during the hold (first half − second half = {diff:.4}, z = {z:.1}): μ0 from the hold is biased; a longer hold or settle helps"
                    ),
                ));
            }
        }
    } else if !s.mu0_known {
        out.push(warn(
            "hold",
            "no hold at u_min: μ0 is estimated with the model from the whole record (row-centred Hankel products, μ0 = mean(y) − μ·mean(z)); the paper's method measures it in a hold".into(),
        ));
    }

    // Output saturation and quantisation.
    let sat = saturation(y);
    for (label, level) in [("maximum", sat.ceiling), ("minimum", sat.floor)] {
        if let Some(ext) = level {
            let at = y
                .iter()
                .filter(|&&v| (v - ext).abs() <= sat.tolerance)
                .count();
            out.push(warn(
                "output_saturation",
                format!(
                    "the output sits at its {label} {ext:.4} in {at} samples ({:.1} %): a saturating sensor or an overflow, an output nonlinearity the Hammerstein model does not have",
                    100.0 * at as f64 / n as f64
                ),
            ));
        }
    }
    let mut sorted = y.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    if sorted.len() >= 3 && sorted.len() * 5 < n {
        let step = sorted
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let on_grid = y
            .iter()
            .all(|v| ((v / step) - (v / step).round()).abs() < 1e-6);
        if on_grid {
            out.push(warn(
                "output_quantisation",
                format!(
                    "the output is quantised in steps of {step} ({} distinct values): quantisation noise of RMS {:.3} is added, and it is not white where the output changes slowly",
                    sorted.len(),
                    step / 12f64.sqrt()
                ),
            ));
        }
    }

    // Piecewise-constant input with few levels.
    let mut levels = ex.to_vec();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    if levels.len() <= 40 && levels.len() * 20 < ex.len() {
        out.push(warn(
            "input_levels",
            format!(
                "the input takes only {} distinct values: the nonlinearity is observed at those levels only and interpolated between them, and the dynamics only at the level changes",
                levels.len()
            ),
        ));
    }
    out
}
