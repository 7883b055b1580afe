//! Polynomials in `q⁻¹` and the state-space ↔ transfer-function maps (observer form).
//!
//! A monic polynomial `p = [1, p₁, …, p_n]` stands for `1 + p₁ q⁻¹ + … + p_n q⁻ⁿ`; its roots
//! are those of `zⁿ + p₁ zⁿ⁻¹ + … + p_n` (the poles of `1/p`).

use nalgebra::{Complex, DMatrix};

/// Eigenvalues of a real square matrix as `(re, im)`, sorted by decreasing real part then
/// decreasing imaginary part; `None` if the Schur iteration does not converge.
pub fn eigenvalues(m: DMatrix<f64>) -> Option<Vec<(f64, f64)>> {
    if m.nrows() == 0 {
        return Some(Vec::new());
    }
    let schur = nalgebra::Schur::try_new(m, f64::EPSILON, 10_000)?;
    let mut ev: Vec<(f64, f64)> = schur
        .complex_eigenvalues()
        .iter()
        .map(|c| (c.re, c.im))
        .collect();
    ev.sort_by(|x, y| y.0.total_cmp(&x.0).then(y.1.total_cmp(&x.1)));
    Some(ev)
}

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

/// The observer canonical `A` of the monic `zⁿ + p₁ zⁿ⁻¹ + … + p_n`, given `p₁ … p_n`: first
/// column `−p`, ones on the superdiagonal.
pub fn observer_a(p: &[f64]) -> DMatrix<f64> {
    let n = p.len();
    DMatrix::from_fn(n, n, |i, j| {
        if j == 0 {
            -p[i]
        } else if j == i + 1 {
            1.0
        } else {
            0.0
        }
    })
}

/// Observer canonical form of `num/den` (`den` monic, both of length `n + 1`):
/// `A = [−p | I; −p_n 0]` ([`observer_a`]), `B_i = b_i − p_i b₀`, `C = e₁`, `D = b₀`.
pub fn observer_form(num: &[f64], den: &[f64]) -> (DMatrix<f64>, Vec<f64>, Vec<f64>, f64) {
    let n = den.len().saturating_sub(1);
    let b0 = num.first().copied().unwrap_or(0.0);
    let a = observer_a(den.get(1..).unwrap_or(&[]));
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

/// Monic polynomial `[1, p₁, …, p_n]` with the given roots, in real arithmetic: a real root
/// (`|im| ≤ 10⁻¹²`) as the factor `z − re`, a complex one and the next root, its conjugate
/// (as [`roots`] and [`eigenvalues`] sort them), as the quadratic `z² − 2 re z + re² + im²`.
/// Real roots give the exact products of their factors, with no imaginary rounding left over.
pub fn from_roots(r: &[(f64, f64)]) -> Vec<f64> {
    let mul = |p: &[f64], f: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; p.len() + f.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in f.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    };
    let mut p = vec![1.0];
    let mut i = 0;
    while i < r.len() {
        let (re, im) = r[i];
        if im.abs() > 1e-12 && i + 1 < r.len() {
            p = mul(&p, &[1.0, -2.0 * re, re * re + im * im]);
            i += 2;
        } else {
            p = mul(&p, &[1.0, -re]);
            i += 1;
        }
    }
    p
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

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-10
    }

    #[test]
    fn roots_of_a_known_polynomial_and_back() {
        // (z − 0.5)(z² − 1.6 z + 0.89): roots 0.5 and 0.8 ± 0.5j.
        let p = [1.0, -2.1, 1.69, -0.445];
        let r = roots(&p).unwrap_or_default();
        assert_eq!(r.len(), 3);
        assert!(close(r[0].0, 0.8) && close(r[0].1, 0.5), "{r:?}");
        assert!(close(r[1].0, 0.8) && close(r[1].1, -0.5), "{r:?}");
        assert!(close(r[2].0, 0.5) && close(r[2].1, 0.0), "{r:?}");
        let back = from_roots(&r);
        assert!(back.iter().zip(p).all(|(a, b)| close(*a, b)), "{back:?}");
        assert!(close(spectral_radius(&p), 0.89f64.sqrt()));
        assert!(is_stable(&p, 1.0) && !is_stable(&p, 0.9));
    }

    #[test]
    fn real_roots_multiply_exactly() {
        // (z − 0.5)(z − 0.25)(z + 0.125) = z³ − 0.625 z² + 0.03125 z + 0.015625, every
        // coefficient a binary fraction: the real factors give it without rounding.
        let p = from_roots(&[(0.5, 0.0), (0.25, 0.0), (-0.125, 0.0)]);
        assert_eq!(p, vec![1.0, -0.625, 0.03125, 0.015625]);
        // A conjugate pair as one real quadratic: (z² − 1.6 z + 0.89).
        let q = from_roots(&[(0.8, 0.5), (0.8, -0.5)]);
        assert_eq!(q, vec![1.0, -1.6, 0.8 * 0.8 + 0.5 * 0.5]);
    }

    #[test]
    fn observer_form_round_trips_through_the_characteristic_polynomial() {
        // G = (0.5 + 0.2 q⁻¹ − 0.1 q⁻²) / (1 − 1.2 q⁻¹ + 0.5 q⁻²).
        let (num, den) = ([0.5, 0.2, -0.1], [1.0, -1.2, 0.5]);
        let (a, b, c, d) = observer_form(&num, &den);
        let cp = char_poly(&a);
        assert!(cp.iter().zip(den).all(|(x, y)| close(*x, y)), "{cp:?}");
        let (n2, d2) = tf_from_ss(&a, &b, &c, d);
        assert!(n2.iter().zip(num).all(|(x, y)| close(*x, y)), "{n2:?}");
        assert!(d2.iter().zip(den).all(|(x, y)| close(*x, y)), "{d2:?}");
        // The frequency response at ω = 0 is the static gain 0.6 / 0.3 = 2.
        let g0 = eval_w(&num, 0.0) / eval_w(&den, 0.0);
        assert!(close(g0.re, 2.0) && close(g0.im, 0.0), "{g0}");
    }

    #[test]
    fn eigenvalues_are_sorted_and_empty_for_an_empty_matrix() {
        let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -0.25, 1.0]);
        // z² − z + 0.25: a double root at 0.5.
        let ev = eigenvalues(m).unwrap_or_default();
        assert!(
            ev.iter()
                .all(|(re, im)| (re - 0.5).abs() < 1e-6 && im.abs() < 1e-6),
            "{ev:?}"
        );
        assert_eq!(eigenvalues(DMatrix::zeros(0, 0)), Some(Vec::new()));
    }
}
