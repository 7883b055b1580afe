//! Random stable plants of orders 1 to 4: real and complex poles, sometimes a zero, unit static
//! gain.

use rand::{Rng, RngExt};

use hsid_host::sim::{Lti, SimError};

/// A random plant and the poles it was built from.
#[derive(Clone, Debug)]
pub struct Plant {
    /// The transfer function (unit static gain, one sample of delay).
    pub lti: Lti,
    /// Its poles `(re, im)`, one entry per pole (a complex pair gives two).
    pub poles: Vec<(f64, f64)>,
    /// Its zero in `z`, when it has one.
    pub zero: Option<f64>,
}

impl Plant {
    /// The order.
    pub fn order(&self) -> usize {
        self.poles.len()
    }

    /// The largest pole modulus.
    pub fn slowest(&self) -> f64 {
        self.poles
            .iter()
            .map(|p| p.0.hypot(p.1))
            .fold(0.0, f64::max)
    }
}

/// Multiplies two polynomials in `q⁻¹`.
fn mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// Draws a plant of order `order` (1 to 4): each real pole in `[0.2, 0.97]`, each complex pair of
/// radius `[0.5, 0.95]` and angle `[0.15, 1.2]` rad; a zero in `[−0.6, 0.7]` with probability
/// 0.4; one sample of delay; unit static gain.
pub fn random_plant<R: Rng + ?Sized>(rng: &mut R, order: usize) -> Result<Plant, SimError> {
    let mut den = vec![1.0];
    let mut poles = Vec::new();
    while poles.len() < order {
        if order - poles.len() >= 2 && rng.random_bool(0.5) {
            let r = rng.random_range(0.5..0.95);
            let th: f64 = rng.random_range(0.15..1.2);
            den = mul(&den, &[1.0, -2.0 * r * th.cos(), r * r]);
            poles.push((r * th.cos(), r * th.sin()));
            poles.push((r * th.cos(), -r * th.sin()));
        } else {
            let p = rng.random_range(0.2..0.97);
            den = mul(&den, &[1.0, -p]);
            poles.push((p, 0.0));
        }
    }
    let zero = rng.random_bool(0.4).then(|| rng.random_range(-0.6..0.7));
    let mut num = match zero {
        Some(z) => vec![0.0, 1.0, -z],
        None => vec![0.0, 1.0],
    };
    let gain = den.iter().sum::<f64>() / num.iter().sum::<f64>();
    num.iter_mut().for_each(|b| *b *= gain);
    Ok(Plant {
        lti: Lti::new(num, den)?,
        poles,
        zero,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use rand_core::SeedableRng;
    use rand_pcg::Pcg64;

    use super::*;

    #[test]
    fn plants_are_stable_with_unit_gain_and_the_poles_they_claim() {
        let mut rng = Pcg64::seed_from_u64(7);
        for order in 1..=4 {
            for _ in 0..20 {
                let p = random_plant(&mut rng, order).unwrap();
                assert_eq!(p.order(), order);
                assert!((p.lti.static_gain() - 1.0).abs() < 1e-9);
                let mut got = p.lti.poles().unwrap();
                let mut want = p.poles.clone();
                let key =
                    |a: &(f64, f64), b: &(f64, f64)| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1));
                got.sort_by(key);
                want.sort_by(key);
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g.0 - w.0).abs() < 1e-6 && (g.1 - w.1).abs() < 1e-6,
                        "{got:?} {want:?}"
                    );
                }
                assert!(p.slowest() < 0.97);
            }
        }
    }
}
