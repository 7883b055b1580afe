//! The inputs: the paper's Table I sweep, and two ordinary commands (a smoothed random
//! staircase and a multisine), every one after a hold at `u_min`.

use super::rng::Rng;

/// The input kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// Table I: hold at `u_min`, then random level, `u_max`, random level, `u_min`, repeated
    /// (levels uniform on the open interval).
    Table1,
    /// Random levels held 5–40 samples, smoothed by `1/(1 − 0.85 q⁻¹)` (after the hold).
    Smoothed,
    /// 150 sines at random frequencies in `]0.001, 0.1[` cycles per sample with random
    /// phases, ±2 standard deviations scaled onto the range and clipped there.
    Multisine,
}

impl InputKind {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            InputKind::Table1 => "table1",
            InputKind::Smoothed => "smoothed",
            InputKind::Multisine => "multisine",
        }
    }

    /// `hold` samples at `lo`, then `len` samples of the kind inside `[lo, hi]`.
    pub fn generate(self, rng: &mut Rng, range: (f64, f64), hold: usize, len: usize) -> Vec<f64> {
        let (lo, hi) = range;
        let mut u = vec![lo; hold];
        match self {
            InputKind::Table1 => u.extend((0..len).map(|t| match t % 4 {
                1 => hi,
                3 => lo,
                _ => rng.inside(lo, hi),
            })),
            InputKind::Smoothed => u.extend(smoothed(rng, range, len)),
            InputKind::Multisine => u.extend(multisine(rng, range, len)),
        }
        u
    }
}

fn smoothed(rng: &mut Rng, (lo, hi): (f64, f64), len: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(len);
    let (mut level, mut left, mut s) = (lo, 0usize, lo);
    for _ in 0..len {
        if left == 0 {
            level = rng.between(lo, hi);
            left = 5 + (rng.uniform() * 36.0) as usize;
        }
        left -= 1;
        s = 0.85 * s + 0.15 * level;
        out.push(s.clamp(lo, hi));
    }
    out
}

/// Sines of the multisine: a persistently exciting order of 300, above the `(f + p)·m` of the
/// diagnosis's regressor (24 × 9 = 216).
pub const TONES: usize = 150;

fn multisine(rng: &mut Rng, (lo, hi): (f64, f64), len: usize) -> Vec<f64> {
    let tones: Vec<(f64, f64)> = (0..TONES)
        .map(|_| {
            (
                rng.between(0.001, 0.1),
                rng.between(0.0, 2.0 * std::f64::consts::PI),
            )
        })
        .collect();
    let raw: Vec<f64> = (0..len)
        .map(|t| {
            tones
                .iter()
                .map(|(f, p)| (2.0 * std::f64::consts::PI * f * t as f64 + p).sin())
                .sum()
        })
        .collect();
    // ±2 standard deviations fill the range; the few samples beyond are clipped (about
    // 2 % at each end), so the ends of the range are visited.
    let m = raw.iter().sum::<f64>() / len.max(1) as f64;
    let sd = (raw.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / len.max(1) as f64)
        .sqrt()
        .max(1e-12);
    let (mid, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    raw.iter()
        .map(|v| (mid + half * (v - m) / (2.0 * sd)).clamp(lo, hi))
        .collect()
}
