//! Output noise at a signal-to-noise ratio: white, AR(1) or MA(2), driven by Gaussian
//! innovations whose variance gives the process the variance the ratio asks for.

use super::rng::Rng;

/// The noise's colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Colour {
    /// White.
    White,
    /// `v(t) = a v(t−1) + e(t)`.
    Ar1(f64),
    /// `v(t) = e(t) + c₁ e(t−1) + c₂ e(t−2)`.
    Ma2(f64, f64),
}

impl Colour {
    /// Variance of the process for unit innovation variance.
    pub fn gain(self) -> f64 {
        match self {
            Colour::White => 1.0,
            Colour::Ar1(a) => 1.0 / (1.0 - a * a),
            Colour::Ma2(c1, c2) => 1.0 + c1 * c1 + c2 * c2,
        }
    }

    /// Short name.
    pub fn name(self) -> String {
        match self {
            Colour::White => "white".into(),
            Colour::Ar1(a) => format!("ar1({a:.2})"),
            Colour::Ma2(c1, c2) => format!("ma2({c1:.2},{c2:.2})"),
        }
    }
}

/// A noise sequence and the innovations that drive it.
#[derive(Clone, Debug, PartialEq)]
pub struct Noise {
    /// The noise added to the output.
    pub v: Vec<f64>,
    /// The white innovations (equal to `v` for white noise).
    pub e: Vec<f64>,
}

/// `len` samples of noise of process standard deviation `sigma` (in theory, not rescaled to
/// the realisation).
pub fn noise(rng: &mut Rng, colour: Colour, sigma: f64, len: usize) -> Noise {
    let se = sigma / colour.gain().sqrt();
    let e: Vec<f64> = (0..len).map(|_| se * rng.normal()).collect();
    let mut v = Vec::with_capacity(len);
    // The AR(1) starts in its stationary distribution.
    let mut last = match colour {
        Colour::Ar1(_) => sigma * rng.normal(),
        _ => 0.0,
    };
    for t in 0..len {
        let x = match colour {
            Colour::White => e[t],
            Colour::Ar1(a) => a * last + e[t],
            Colour::Ma2(c1, c2) => {
                let at = |k: usize| t.checked_sub(k).map_or(0.0, |i| e[i]);
                e[t] + c1 * at(1) + c2 * at(2)
            }
        };
        last = x;
        v.push(x);
    }
    Noise { v, e }
}

/// The noise standard deviation for `snr_db` against a signal of variance `signal_var`.
pub fn sigma_for(signal_var: f64, snr_db: f64) -> f64 {
    (signal_var / 10f64.powf(snr_db / 10.0)).sqrt()
}

/// Sample variance.
pub fn variance(x: &[f64]) -> f64 {
    let n = x.len().max(1) as f64;
    let m = x.iter().sum::<f64>() / n;
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n
}

/// Root mean square.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// The realised ratio `10 log₁₀(var signal / var noise)`, dB.
pub fn snr_db(signal: &[f64], noise: &[f64]) -> f64 {
    10.0 * (variance(signal) / variance(noise)).log10()
}
