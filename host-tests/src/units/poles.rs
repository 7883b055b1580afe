//! Continuous-time equivalents of discrete poles, `s = ln(z)/ts`, with first-order (delta
//! method) standard deviations from the covariance of the pole's real and imaginary parts.
//!
//! Without a sample time, `ts = 1`: time constants are in samples, frequencies in rad/sample.

use serde::Serialize;

/// A value with its standard deviation when known.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ValueStd {
    /// The value.
    pub value: f64,
    /// Its standard deviation (first order), when the model was refined.
    pub std: Option<f64>,
}

/// What a discrete pole means in continuous time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Mode {
    /// A real pole in (0, 1): a first-order decay of time constant `tau = −ts/ln z`.
    Real {
        /// Time constant (s, or samples without a sample time).
        tau: ValueStd,
    },
    /// A complex pair (reported once, for the pole with positive imaginary part).
    Complex {
        /// Natural frequency `|s|` in rad/s (rad/sample without a sample time).
        wn: ValueStd,
        /// Damping `ζ = −Re(s)/|s|`.
        zeta: ValueStd,
    },
    /// A real pole at or below zero: no continuous-time equivalent (a delay, or an
    /// oscillation at the Nyquist frequency).
    NoEquivalent,
    /// A pole on or outside the unit circle: not a decaying mode.
    NotDecaying,
}

/// One discrete pole and its continuous-time reading.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContinuousPole {
    /// The discrete pole `(re, im)`.
    pub z: (f64, f64),
    /// Its meaning in continuous time.
    pub mode: Mode,
}

/// The continuous-time reading of pole `z` at sample time `ts`; `cov` is the covariance of
/// `(re z, im z)` when known. `None` for the lower member of a complex pair.
pub(crate) fn continuous_pole(
    z: (f64, f64),
    cov: Option<[[f64; 2]; 2]>,
    ts: f64,
) -> Option<ContinuousPole> {
    let (x, y) = z;
    let r2 = x * x + y * y;
    let mode = if y < 0.0 {
        return None;
    } else if r2 >= 1.0 {
        Mode::NotDecaying
    } else if y == 0.0 && x <= 0.0 {
        Mode::NoEquivalent
    } else if y == 0.0 {
        // τ = −ts/ln x, dτ/dx = ts/(x ln²x).
        let l = x.ln();
        let tau = -ts / l;
        let d = ts / (x * l * l);
        Mode::Real {
            tau: ValueStd {
                value: tau,
                std: cov.map(|c| (d * d * c[0][0]).max(0.0).sqrt()),
            },
        }
    } else {
        complex(x, y, r2, cov, ts)
    };
    Some(ContinuousPole { z, mode })
}

/// Natural frequency and damping of the pair at `x + jy`, `r2 = x² + y²`.
fn complex(x: f64, y: f64, r2: f64, cov: Option<[[f64; 2]; 2]>, ts: f64) -> Mode {
    // s = σ + jω = (ln r + j atan2(y, x)) / ts.
    let sigma = 0.5 * r2.ln() / ts;
    let omega = y.atan2(x) / ts;
    let wn = sigma.hypot(omega);
    let zeta = -sigma / wn;
    // ∂(σ, ω)/∂(x, y).
    let ds = [x / r2 / ts, y / r2 / ts];
    let dw = [-y / r2 / ts, x / r2 / ts];
    // ∂wn/∂(σ, ω) = (σ, ω)/wn; ∂ζ/∂(σ, ω) = (−ω², σω)/wn³.
    let w3 = wn * wn * wn;
    let grad = |a: f64, b: f64| [a * ds[0] + b * dw[0], a * ds[1] + b * dw[1]];
    let g_wn = grad(sigma / wn, omega / wn);
    let g_zeta = grad(-omega * omega / w3, sigma * omega / w3);
    let var = |g: [f64; 2], c: [[f64; 2]; 2]| {
        (g[0] * g[0] * c[0][0] + 2.0 * g[0] * g[1] * c[0][1] + g[1] * g[1] * c[1][1])
            .max(0.0)
            .sqrt()
    };
    Mode::Complex {
        wn: ValueStd {
            value: wn,
            std: cov.map(|c| var(g_wn, c)),
        },
        zeta: ValueStd {
            value: zeta,
            std: cov.map(|c| var(g_zeta, c)),
        },
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_real_pole_gives_its_time_constant() {
        // z = e^{−ts/τ} with τ = 0.05 s, ts = 0.01 s: z = e^{−0.2} = 0.818731.
        let z = (-0.2f64).exp();
        let p = continuous_pole((z, 0.0), Some([[1e-6, 0.0], [0.0, 0.0]]), 0.01).unwrap();
        let Mode::Real { tau } = p.mode else {
            panic!("{p:?}")
        };
        assert!((tau.value - 0.05).abs() < 1e-12, "{tau:?}");
        // dτ/dz = ts/(z ln²z) = 0.01/(0.818731 · 0.04) = 0.305347; σ_z = 1e-3.
        assert!((tau.std.unwrap() - 0.305_347e-3).abs() < 1e-8, "{tau:?}");
    }

    #[test]
    fn a_complex_pair_gives_the_plants_wn_and_zeta() {
        // wn = 2π·1.5 rad/s, ζ = 0.3, ts = 0.01: z = exp((−ζ wn + j wn √(1−ζ²)) ts).
        let (wn, zeta, ts) = (2.0 * PI * 1.5, 0.3, 0.01);
        let r = (-zeta * wn * ts).exp();
        let th = wn * (1.0f64 - zeta * zeta).sqrt() * ts;
        let z = (r * th.cos(), r * th.sin());
        let p = continuous_pole(z, None, ts).unwrap();
        let Mode::Complex { wn: w, zeta: d } = p.mode else {
            panic!("{p:?}")
        };
        assert!((w.value - wn).abs() < 1e-9 && (d.value - zeta).abs() < 1e-12);
        assert_eq!((w.std, d.std), (None, None));
        assert_eq!(continuous_pole((z.0, -z.1), None, ts), None);
    }

    #[test]
    fn the_delta_method_matches_finite_differences() {
        let (x, y, ts) = (0.9, 0.2, 0.01);
        let (sx, sy, rho) = (1e-3, 2e-3, 0.3);
        let cov = [[sx * sx, rho * sx * sy], [rho * sx * sy, sy * sy]];
        let at = |x: f64, y: f64| match continuous_pole((x, y), None, ts).unwrap().mode {
            Mode::Complex { wn, zeta } => (wn.value, zeta.value),
            m => panic!("{m:?}"),
        };
        let h = 1e-7;
        let gx = (
            (at(x + h, y).0 - at(x - h, y).0) / (2.0 * h),
            (at(x + h, y).1 - at(x - h, y).1) / (2.0 * h),
        );
        let gy = (
            (at(x, y + h).0 - at(x, y - h).0) / (2.0 * h),
            (at(x, y + h).1 - at(x, y - h).1) / (2.0 * h),
        );
        let sd = |a: f64, b: f64| {
            (a * a * cov[0][0] + 2.0 * a * b * cov[0][1] + b * b * cov[1][1]).sqrt()
        };
        let Mode::Complex { wn, zeta } = continuous_pole((x, y), Some(cov), ts).unwrap().mode
        else {
            panic!()
        };
        assert!((wn.std.unwrap() / sd(gx.0, gy.0) - 1.0).abs() < 1e-5);
        assert!((zeta.std.unwrap() / sd(gx.1, gy.1) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn poles_without_an_equivalent_are_named() {
        let mode = |z| continuous_pole(z, None, 1.0).unwrap().mode;
        assert_eq!(mode((-0.5, 0.0)), Mode::NoEquivalent);
        assert_eq!(mode((0.0, 0.0)), Mode::NoEquivalent);
        assert_eq!(mode((1.0, 0.0)), Mode::NotDecaying);
    }
}
