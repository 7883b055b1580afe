//! Measurement noise: white, or AR(1) coloured, at a standard deviation set by a
//! signal-to-noise ratio.

use super::rng::Rng;

/// The noise's colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Colour {
    /// White Gaussian.
    White,
    /// `v(t) = a v(t − 1) + e(t)`, started stationary, `e` scaled so that `v` has the
    /// standard deviation asked.
    Ar1(f64),
}

impl Colour {
    /// `white` or `ar1(0.72)`.
    pub fn name(self) -> String {
        match self {
            Colour::White => "white".into(),
            Colour::Ar1(a) => format!("ar1({a:.2})"),
        }
    }
}

/// `n` samples of noise of standard deviation `sigma`.
pub fn noise(rng: &mut Rng, colour: Colour, sigma: f64, n: usize) -> Vec<f64> {
    match colour {
        Colour::White => (0..n).map(|_| sigma * rng.normal()).collect(),
        Colour::Ar1(a) => {
            let e = sigma * (1.0 - a * a).sqrt();
            let mut v = sigma * rng.normal();
            (0..n)
                .map(|_| {
                    let out = v;
                    v = a * v + e * rng.normal();
                    out
                })
                .collect()
        }
    }
}

/// The standard deviation that puts a noise at `snr_db` below a signal of variance `var`.
pub fn sigma_for(var: f64, snr_db: f64) -> f64 {
    (var / 10f64.powf(snr_db / 10.0)).sqrt()
}

/// Sample variance.
pub fn variance(x: &[f64]) -> f64 {
    let n = x.len().max(1) as f64;
    let m = x.iter().sum::<f64>() / n;
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ar1_noise_has_the_asked_deviation_and_correlation() {
        let v = noise(&mut Rng::new(1, 1), Colour::Ar1(0.8), 0.5, 100_000);
        let var = variance(&v);
        assert!((var.sqrt() - 0.5).abs() < 0.02, "{}", var.sqrt());
        let r1 = v.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / (v.len() - 1) as f64 / var;
        assert!((r1 - 0.8).abs() < 0.02, "{r1}");
        assert!((sigma_for(4.0, 20.0) - 0.2).abs() < 1e-12);
    }
}
