//! The family's own random source: xoshiro256** (Blackman and Vigna), its state filled from
//! the seed by a 64-bit mixing function, normals by Marsaglia's polar method. Nothing here is
//! shared with the other families or with the library, so the family's draws depend on its
//! seed alone.

/// A reproducible random stream.
#[derive(Clone, Debug)]
pub struct Rng {
    s: [u64; 4],
    cached: Option<f64>,
}

/// The finaliser of MurmurHash3 on `x + k · golden`: a bijective mix that spreads a counter
/// over all 64 bits.
fn mix(x: u64, k: u64) -> u64 {
    let mut z = x.wrapping_add(k.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 33)).wrapping_mul(0xFF51_AFD7_ED55_8CCD);
    z = (z ^ (z >> 33)).wrapping_mul(0xC4CE_B9FE_1A85_EC53);
    z ^ (z >> 33)
}

impl Rng {
    /// The stream `stream` of `seed`: different streams of one seed are unrelated.
    pub fn new(seed: u64, stream: u64) -> Self {
        let base = mix(seed, 1) ^ mix(stream, 7).rotate_left(17);
        let mut s = [0u64; 4];
        for (i, v) in s.iter_mut().enumerate() {
            *v = mix(base, 11 + i as u64);
        }
        if s.iter().all(|&v| v == 0) {
            s[0] = 1;
        }
        let mut r = Self { s, cached: None };
        for _ in 0..8 {
            r.next_u64();
        }
        r
    }

    /// The next 64 random bits (xoshiro256**).
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let out = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        out
    }

    /// Uniform on `[0, 1)` (53 bits).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform on `[lo, hi)`.
    pub fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Uniform on the open interval `]lo, hi[`.
    pub fn strictly_between(&mut self, lo: f64, hi: f64) -> f64 {
        loop {
            let v = self.between(lo, hi);
            if v > lo && v < hi {
                return v;
            }
        }
    }

    /// Log-uniform on `[lo, hi)` (both positive).
    pub fn log_between(&mut self, lo: f64, hi: f64) -> f64 {
        self.between(lo.ln(), hi.ln()).exp()
    }

    /// An index below `n` (0 for `n = 0`).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            return 0;
        }
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }

    /// One element of a non-empty slice (its first for an empty one is impossible: the
    /// caller passes constants).
    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// Standard normal (Marsaglia's polar method, the second value of a pair kept).
    pub fn normal(&mut self) -> f64 {
        if let Some(v) = self.cached.take() {
            return v;
        }
        loop {
            let a = 2.0 * self.uniform() - 1.0;
            let b = 2.0 * self.uniform() - 1.0;
            let s = a * a + b * b;
            if s > 0.0 && s < 1.0 {
                let f = (-2.0 * s.ln() / s).sqrt();
                self.cached = Some(b * f);
                return a * f;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<u64> = {
            let mut r = Rng::new(3, 1);
            (0..4).map(|_| r.next_u64()).collect()
        };
        let b: Vec<u64> = {
            let mut r = Rng::new(3, 1);
            (0..4).map(|_| r.next_u64()).collect()
        };
        let c: Vec<u64> = {
            let mut r = Rng::new(3, 2);
            (0..4).map(|_| r.next_u64()).collect()
        };
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn moments_of_uniform_and_normal() {
        let mut r = Rng::new(42, 0);
        let n = 200_000;
        let u: Vec<f64> = (0..n).map(|_| r.uniform()).collect();
        let mean = u.iter().sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.005, "{mean}");
        assert!(u.iter().all(|v| (0.0..1.0).contains(v)));
        let z: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        let m = z.iter().sum::<f64>() / n as f64;
        let v = z.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n as f64;
        assert!(m.abs() < 0.01 && (v - 1.0).abs() < 0.015, "{m} {v}");
    }
}
