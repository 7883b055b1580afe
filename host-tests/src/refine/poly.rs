//! Polynomials in `q⁻¹` and the state-space ↔ transfer-function maps the refinement needs.
//!
//! A monic polynomial `p = [1, p₁, …, p_n]` stands for `1 + p₁ q⁻¹ + … + p_n q⁻ⁿ`; its roots
//! are those of `zⁿ + p₁ zⁿ⁻¹ + … + p_n` (the poles of `1/p`).

use nalgebra::{Complex, DMatrix};

use super::RefineError;
use crate::sim::eigenvalues;

/// Characteristic polynomial `det(zI − A)` as `[1, p₁, …, p_n]` (Faddeev–LeVerrier).
pub fn char_poly(a: &DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut coef = vec![1.0; n + 1];
    let mut m = DMatrix::<f64>::zeros(n, n);
    let eye = DMatrix::<f64>::identity(n, n);
    for k in 1..=n {
        m = a * &m + &eye * coef[k - 1];
        let am = a * &m;
        coef[k] = -am.trace() / k as f64;
    }
    coef
}

/// `G(q) = C (qI − A)⁻¹ B + D` as `(num, den)`: `den = det(qI − A)` in `q⁻¹` (monic) and
/// `num = [b₀, …, b_n]`, from the Markov parameters.
pub fn tf_from_ss(a: &DMatrix<f64>, b: &[f64], c: &[f64], d: f64) -> (Vec<f64>, Vec<f64>) {
    let n = a.nrows();
    let den = char_poly(a);
    // Markov parameters h_0 = D, h_k = C A^{k−1} B.
    let mut h = vec![d];
    let mut x = nalgebra::DVector::from_column_slice(b);
    for _ in 0..n {
        h.push(c.iter().zip(x.iter()).map(|(ci, xi)| ci * xi).sum());
        x = a * x;
    }
    let num = (0..=n)
        .map(|k| (0..=k).map(|i| den[i] * h[k - i]).sum())
        .collect();
    (num, den)
}

/// Observer canonical form of `num/den` (`den` monic, both of length `n + 1`):
/// `A = [−p | I; −p_n 0]`, `B_i = b_i − p_i b₀`, `C = e₁`, `D = b₀`.
pub fn observer_form(num: &[f64], den: &[f64]) -> (DMatrix<f64>, Vec<f64>, Vec<f64>, f64) {
    let n = den.len().saturating_sub(1);
    let b0 = num.first().copied().unwrap_or(0.0);
    let mut a = DMatrix::zeros(n, n);
    for i in 0..n {
        a[(i, 0)] = -den[i + 1];
        if i + 1 < n {
            a[(i, i + 1)] = 1.0;
        }
    }
    let b = (0..n)
        .map(|i| num.get(i + 1).copied().unwrap_or(0.0) - den[i + 1] * b0)
        .collect();
    let mut c = vec![0.0; n];
    if let Some(c0) = c.first_mut() {
        *c0 = 1.0;
    }
    (a, b, c, b0)
}

/// Roots of a monic polynomial as `(re, im)`, sorted as [`eigenvalues`].
pub fn roots(p: &[f64]) -> Option<Vec<(f64, f64)>> {
    let n = p.len().saturating_sub(1);
    if n == 0 {
        return Some(Vec::new());
    }
    let mut m = DMatrix::<f64>::zeros(n, n);
    for k in 0..n {
        m[(0, k)] = -p[k + 1];
    }
    for k in 1..n {
        m[(k, k - 1)] = 1.0;
    }
    eigenvalues(m)
}

/// Largest root modulus (0 for a constant polynomial, infinity if the roots cannot be found).
pub fn spectral_radius(p: &[f64]) -> f64 {
    match roots(p) {
        Some(r) => r.iter().map(|(a, b)| a.hypot(*b)).fold(0.0, f64::max),
        None => f64::INFINITY,
    }
}

/// Whether every root lies strictly inside the circle of radius `r`.
pub fn is_stable(p: &[f64], r: f64) -> bool {
    spectral_radius(p) < r
}

/// Monic polynomial with the given roots (complex ones in conjugate pairs).
pub fn from_roots(r: &[(f64, f64)]) -> Vec<f64> {
    let mut c = vec![Complex::new(1.0, 0.0)];
    for &(re, im) in r {
        let z = Complex::new(re, im);
        let mut next = vec![Complex::new(0.0, 0.0); c.len() + 1];
        for (k, ck) in c.iter().enumerate() {
            next[k] += ck;
            next[k + 1] -= ck * z;
        }
        c = next;
    }
    c.iter().map(|v| v.re).collect()
}

/// The polynomial with every root of modulus above `r_max` moved inside: `z → 1/z̄`, then
/// clamped to `r_max`. Used to make a fitted noise numerator minimum phase (the spectral
/// factor keeps the spectrum's shape).
pub fn stabilise(p: &[f64], r_max: f64) -> Result<Vec<f64>, RefineError> {
    let r = roots(p).ok_or(RefineError::Singular("roots of a noise polynomial"))?;
    if r.iter().all(|(a, b)| a.hypot(*b) < r_max) {
        return Ok(p.to_vec());
    }
    let moved: Vec<(f64, f64)> = r
        .iter()
        .map(|&(a, b)| {
            let m = a.hypot(b);
            if m >= 1.0 {
                let inv = 1.0 / (m * m);
                (a * inv, b * inv)
            } else {
                (a, b)
            }
        })
        .map(|(a, b)| {
            let m = a.hypot(b);
            if m >= r_max {
                (a * r_max / m, b * r_max / m)
            } else {
                (a, b)
            }
        })
        .collect();
    Ok(from_roots(&moved))
}

/// `p(z) = zⁿ + p₁ zⁿ⁻¹ + … + p_n` at a complex `z`.
pub fn eval_z(p: &[f64], z: Complex<f64>) -> Complex<f64> {
    p.iter().fold(Complex::new(0.0, 0.0), |acc, &c| {
        acc * z + Complex::new(c, 0.0)
    })
}

/// `p(q⁻¹)` at `q = e^{jw}`: `Σ_k p_k e^{−jwk}`.
pub fn eval_w(p: &[f64], w: f64) -> Complex<f64> {
    p.iter()
        .enumerate()
        .fold(Complex::new(0.0, 0.0), |acc, (k, &c)| {
            let ph = -w * k as f64;
            acc + Complex::new(c * ph.cos(), c * ph.sin())
        })
}

/// Derivatives of a simple root `z` of the monic `p` with respect to `p₁ … p_n`:
/// `∂z/∂p_i = −z^{n−i} / p'(z)`.
pub fn root_sensitivity(p: &[f64], z: Complex<f64>) -> Vec<Complex<f64>> {
    let n = p.len().saturating_sub(1);
    // p'(z) = Σ_{k<n} (n − k) p_k z^{n−k−1}
    let mut dp = Complex::new(0.0, 0.0);
    for (k, &c) in p.iter().enumerate().take(n) {
        dp += Complex::new(c * (n - k) as f64, 0.0) * z.powu((n - k - 1) as u32);
    }
    (1..=n).map(|i| -z.powu((n - i) as u32) / dp).collect()
}
