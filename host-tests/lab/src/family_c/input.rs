//! The commands: the paper's Table I excitation and three ordinary ones (smoothed random
//! levels, a multisine, a slow-clock PRBS), each after a hold at `u_min`. The ordinary
//! commands' time scales follow the servo's dominant time constant in samples.

use super::rng::Rng;

/// The command's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// Table I: from `u_min`, a random level in `]u_min, u_max[`, `u_max`, a random level,
    /// `u_min`, and again; each level held [`Design::level_hold`](super::design::Design)
    /// samples (1 in the paper), so every monotone run starts at an end of the range.
    Table1,
    /// Random levels, uniform on the range, held ½–3 dominant time constants, smoothed by a
    /// first-order filter of 0.3 of it.
    Levels,
    /// 30 sines at log-spaced frequencies from 0.1 to 3 over 2π dominant time constants, random
    /// phases, ±2.5 standard deviations scaled onto the range and clipped there.
    Multisine,
    /// A maximum-length binary sequence (10-bit register) between `u_min` and `u_max`, its
    /// clock ½–2 dominant time constants.
    Prbs,
}

impl InputKind {
    /// Every kind.
    pub const ALL: [InputKind; 4] = [
        InputKind::Table1,
        InputKind::Levels,
        InputKind::Multisine,
        InputKind::Prbs,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            InputKind::Table1 => "table1",
            InputKind::Levels => "levels",
            InputKind::Multisine => "multisine",
            InputKind::Prbs => "prbs",
        }
    }

    /// `hold` samples at `lo`, then `len` samples of the kind on `[lo, hi]`; `tau` is the
    /// servo's dominant time constant in samples, `level_hold` the samples of each Table I
    /// level.
    pub fn generate(
        self,
        rng: &mut Rng,
        (lo, hi): (f64, f64),
        hold: usize,
        len: usize,
        tau: f64,
        level_hold: usize,
    ) -> Vec<f64> {
        let mut u = vec![lo; hold];
        let tau = tau.max(1.0);
        match self {
            InputKind::Table1 => u.extend(table1(rng, (lo, hi), len, level_hold.max(1))),
            InputKind::Levels => u.extend(levels(rng, (lo, hi), len, tau)),
            InputKind::Multisine => u.extend(multisine(rng, (lo, hi), len, tau)),
            InputKind::Prbs => u.extend(prbs(rng, (lo, hi), len, tau)),
        }
        u
    }
}

/// Table I with each level held `m` samples.
fn table1(rng: &mut Rng, (lo, hi): (f64, f64), len: usize, m: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(len);
    let mut level = lo;
    for t in 0..len {
        if t % m == 0 {
            level = match (t / m) % 4 {
                1 => hi,
                3 => lo,
                _ => rng.strictly_between(lo, hi),
            };
        }
        out.push(level);
    }
    out
}

fn levels(rng: &mut Rng, (lo, hi): (f64, f64), len: usize, tau: f64) -> Vec<f64> {
    let a = (-1.0 / (0.3 * tau).max(0.5)).exp();
    let (mut level, mut left, mut s) = (lo, 0usize, lo);
    (0..len)
        .map(|_| {
            if left == 0 {
                level = rng.between(lo, hi);
                left = rng.between(0.5 * tau, 3.0 * tau).round().max(3.0) as usize;
            }
            left -= 1;
            s = a * s + (1.0 - a) * level;
            s.clamp(lo, hi)
        })
        .collect()
}

fn multisine(rng: &mut Rng, (lo, hi): (f64, f64), len: usize, tau: f64) -> Vec<f64> {
    const SINES: usize = 30;
    let (f_lo, f_hi) = (
        0.1 / (2.0 * std::f64::consts::PI * tau),
        3.0 / (2.0 * std::f64::consts::PI * tau),
    );
    let f_hi = f_hi.min(0.4);
    let comps: Vec<(f64, f64)> = (0..SINES)
        .map(|i| {
            let f = f_lo * (f_hi / f_lo).powf(i as f64 / (SINES - 1) as f64);
            (f, rng.between(0.0, 2.0 * std::f64::consts::PI))
        })
        .collect();
    let raw: Vec<f64> = (0..len)
        .map(|t| {
            comps
                .iter()
                .map(|(f, p)| (2.0 * std::f64::consts::PI * f * t as f64 + p).sin())
                .sum()
        })
        .collect();
    let sd = (SINES as f64 / 2.0).sqrt();
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    raw.iter()
        .map(|v| (mid + half * v / (2.5 * sd)).clamp(lo, hi))
        .collect()
}

fn prbs(rng: &mut Rng, (lo, hi): (f64, f64), len: usize, tau: f64) -> Vec<f64> {
    let clock = rng.between(0.5 * tau, 2.0 * tau).round().max(2.0) as usize;
    // x¹⁰ + x⁷ + 1: period 1023.
    let mut reg: u16 = 1 + (rng.next_u64() % 1023) as u16;
    let mut bit = 0u16;
    (0..len)
        .map(|t| {
            if t % clock == 0 {
                bit = ((reg >> 9) ^ (reg >> 6)) & 1;
                reg = ((reg << 1) | bit) & 0x3FF;
            }
            if bit == 1 { hi } else { lo }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table I: the hold at `u_min`, then per cycle a level strictly inside, `u_max`, a level
    /// strictly inside, `u_min`, each held `m` samples.
    #[test]
    fn table1_levels_follow_the_papers_cycle() {
        for m in [1, 3] {
            let mut rng = Rng::new(5, 0);
            let (lo, hi) = (-2.0, 1.5);
            let u = InputKind::Table1.generate(&mut rng, (lo, hi), 10, 400, 8.0, m);
            assert_eq!(u.len(), 410);
            assert!(u[..10].iter().all(|&v| v == lo));
            for (t, &v) in u[10..].iter().enumerate() {
                match (t / m) % 4 {
                    1 => assert_eq!(v, hi),
                    3 => assert_eq!(v, lo),
                    _ => assert!(v > lo && v < hi, "{t}: {v}"),
                }
                if t % m != 0 {
                    assert_eq!(v, u[10 + t - 1]);
                }
            }
            // Every rise starts at u_min and every fall at u_max (the paper's paths).
            for t in 10..u.len() - 1 {
                if u[t + 1] > u[t] && u[t] != lo {
                    // A rise from an inner level only to u_max, right after u_min.
                    assert_eq!(u[t + 1], hi, "{t}");
                }
            }
        }
    }

    #[test]
    fn ordinary_inputs_stay_in_the_range_and_prbs_has_two_levels() {
        let (lo, hi) = (-1.0, 2.0);
        for kind in [InputKind::Levels, InputKind::Multisine, InputKind::Prbs] {
            let mut rng = Rng::new(9, 1);
            let u = kind.generate(&mut rng, (lo, hi), 20, 3000, 12.0, 1);
            assert!(u.iter().all(|&v| (lo..=hi).contains(&v)), "{}", kind.name());
            let spread = u.iter().cloned().fold(f64::MIN, f64::max)
                - u.iter().cloned().fold(f64::MAX, f64::min);
            assert!(spread > 0.7 * (hi - lo), "{} {spread}", kind.name());
        }
        let u = InputKind::Prbs.generate(&mut Rng::new(2, 2), (lo, hi), 0, 2000, 6.0, 1);
        assert!(u.iter().all(|&v| v == lo || v == hi));
        assert!(u.iter().filter(|&&v| v == hi).count() > 600);
    }
}
