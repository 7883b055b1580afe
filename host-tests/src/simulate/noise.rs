//! Output noise `v = F(q) e`, `e` white Gaussian from a seeded generator, at a level given as
//! an SNR met exactly on the record or as the standard deviation of `e`.

use rand_core::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg32;

use super::error::SimulateError;
use super::plant::transfer;
use super::spec::{ColourSpec, NoiseSpec};
use crate::sim::{Lti, variance};

/// How loud the noise is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Level {
    /// `var(y_clean) / var(v) = 10^(dB/10)` over the whole record, exactly.
    SnrDb(f64),
    /// Standard deviation of the white `e` that drives the colour filter.
    Std(f64),
}

/// A noise source: colour filter, level and seed.
#[derive(Clone, Debug, PartialEq)]
pub struct Noise {
    /// The colour filter `F(q)` (`1` for white noise).
    pub filter: Lti,
    /// The level.
    pub level: Level,
    /// Seed of the PCG32 generator.
    pub seed: u64,
}

/// The noise of the given record: `v` and the standard deviation of `e` it used.
pub fn output_noise(y_clean: &[f64], noise: &Noise) -> Result<(Vec<f64>, f64), SimulateError> {
    let mut rng = Pcg32::seed_from_u64(noise.seed);
    let e: Vec<f64> = (0..y_clean.len())
        .map(|_| StandardNormal.sample(&mut rng))
        .collect();
    let v = noise.filter.filter(&e);
    let std = match noise.level {
        Level::Std(s) => s,
        Level::SnrDb(db) => {
            let (vy, vv) = (variance(y_clean), variance(&v));
            if !(vy.is_finite() && vy > 0.0) {
                return Err(SimulateError::ConstantOutput);
            }
            (vy / 10f64.powf(db / 10.0) / vv).sqrt()
        }
    };
    Ok((v.iter().map(|x| x * std).collect(), std))
}

/// Checks a level: an SNR finite, a standard deviation finite and `>= 0`; `field` names it.
pub fn level(l: Level, field: &str) -> Result<Level, SimulateError> {
    let (v, ok, must) = match l {
        Level::SnrDb(v) => (v, v.is_finite(), "finite"),
        Level::Std(v) => (v, v.is_finite() && v >= 0.0, "finite and >= 0"),
    };
    if ok {
        Ok(l)
    } else {
        Err(SimulateError::OutOfRange {
            field: field.to_string(),
            value: v,
            must,
        })
    }
}

/// White noise's filter, `F = 1`.
pub fn white() -> Lti {
    #[allow(clippy::unwrap_used)] // constant, valid coefficients
    Lti::new(vec![1.0], vec![1.0]).unwrap()
}

/// The noise of a plant specification.
pub(crate) fn from_spec(n: &NoiseSpec) -> Result<Noise, SimulateError> {
    let level_of = match (n.snr_db, n.std) {
        (Some(db), None) => level(Level::SnrDb(db), "noise.snr_db")?,
        (None, Some(s)) => level(Level::Std(s), "noise.std")?,
        (Some(_), Some(_)) => {
            return Err(SimulateError::Conflict {
                field: "noise.std".into(),
                why: "give the level once, as snr_db or std".into(),
            });
        }
        (None, None) => {
            return Err(SimulateError::Missing {
                field: "noise.snr_db".into(),
                why: "noise needs a level, snr_db (dB) or std; leave out \"noise\" for none",
            });
        }
    };
    let filter = match &n.colour {
        None | Some(ColourSpec::Named(_)) => white(),
        Some(ColourSpec::Filter(t)) => transfer(t.num.clone(), t.den.clone(), "noise.colour")?,
    };
    Ok(Noise {
        filter,
        level: level_of,
        seed: n.seed.unwrap_or(1),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn the_snr_holds_exactly_on_the_record() {
        let y: Vec<f64> = (0..500).map(|t| (0.05 * t as f64).sin()).collect();
        let noise = Noise {
            filter: Lti::new(vec![1.0, 0.5], vec![1.0, -0.85]).unwrap(),
            level: Level::SnrDb(20.0),
            seed: 3,
        };
        let (v, _) = output_noise(&y, &noise).unwrap();
        let snr = 10.0 * (variance(&y) / variance(&v)).log10();
        assert!((snr - 20.0).abs() < 1e-9, "{snr}");
    }
}
