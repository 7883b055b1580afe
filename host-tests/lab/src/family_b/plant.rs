//! The linear plants: continuous-time cascades of first- and second-order sections (real and
//! complex poles, each of unit static gain) and an optional integrator, sampled with a
//! zero-order hold at the scenario's sample time.

use nalgebra::{DMatrix, DVector};

/// One section of the cascade, in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Section {
    /// `1/(τ s + 1)`: a real pole at `−1/τ`.
    Real {
        /// Time constant, s.
        tau: f64,
    },
    /// `ω²/(s² + 2ζω s + ω²)`: a complex pair for `ζ < 1`.
    Complex {
        /// Natural frequency, rad/s.
        omega: f64,
        /// Damping ratio.
        zeta: f64,
    },
    /// `k/s`: an integrator (the plant then has no static gain).
    Integrator {
        /// Gain, 1/s.
        k: f64,
    },
}

impl Section {
    /// States the section adds.
    pub fn order(self) -> usize {
        match self {
            Section::Complex { .. } => 2,
            _ => 1,
        }
    }
}

/// A continuous plant: sections in series, the first fed by the element's output.
#[derive(Clone, Debug, PartialEq)]
pub struct Plant {
    /// The sections, input side first.
    pub sections: Vec<Section>,
}

impl Plant {
    /// State dimension (the plant's true order).
    pub fn order(&self) -> usize {
        self.sections.iter().map(|s| s.order()).sum()
    }

    /// Whether a section integrates.
    pub fn integrates(&self) -> bool {
        self.sections
            .iter()
            .any(|s| matches!(s, Section::Integrator { .. }))
    }

    /// The continuous state-space `(A, B, C)`; the output is the last section's output.
    pub fn continuous(&self) -> (DMatrix<f64>, DVector<f64>, DVector<f64>) {
        let n = self.order();
        let mut a = DMatrix::zeros(n, n);
        let mut b = DVector::zeros(n);
        // Where the input of the next section comes from: the element, or a state.
        let mut feed: Option<usize> = None;
        let mut i = 0;
        for s in &self.sections {
            // Adds `gain × (section input)` to row `row`.
            let mut drive = |a: &mut DMatrix<f64>, row: usize, gain: f64| match feed {
                Some(j) => a[(row, j)] += gain,
                None => b[row] += gain,
            };
            match *s {
                Section::Real { tau } => {
                    a[(i, i)] = -1.0 / tau;
                    drive(&mut a, i, 1.0 / tau);
                }
                Section::Integrator { k } => drive(&mut a, i, k),
                Section::Complex { omega, zeta } => {
                    a[(i, i + 1)] = 1.0;
                    a[(i + 1, i)] = -omega * omega;
                    a[(i + 1, i + 1)] = -2.0 * zeta * omega;
                    drive(&mut a, i + 1, omega * omega);
                }
            }
            feed = Some(i);
            i += s.order();
        }
        let mut c = DVector::zeros(n);
        if let Some(j) = feed {
            c[j] = 1.0;
        }
        (a, b, c)
    }

    /// The plant sampled with a zero-order hold every `ts` seconds.
    pub fn sampled(&self, ts: f64) -> Discrete {
        let (a, b, c) = self.continuous();
        let n = a.nrows();
        // exp([[A, B], [0, 0]] ts) = [[Φ, Γ], [0, 1]].
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n)).copy_from(&(a * ts));
        m.view_mut((0, n), (n, 1)).copy_from(&(b * ts));
        let e = expm(&m);
        Discrete {
            phi: e.view((0, 0), (n, n)).into_owned(),
            gamma: e.view((0, n), (n, 1)).column(0).into_owned(),
            c,
        }
    }
}

/// The matrix exponential by scaling and squaring with a Taylor series (small matrices).
pub fn expm(m: &DMatrix<f64>) -> DMatrix<f64> {
    let norm = m.abs().row_sum().max();
    let mut s = 0;
    while norm / f64::powi(2.0, s) > 0.25 {
        s += 1;
    }
    let x = m / f64::powi(2.0, s);
    let n = m.nrows();
    let mut sum = DMatrix::identity(n, n);
    let mut term = DMatrix::identity(n, n);
    for k in 1..=20 {
        term = &term * &x / k as f64;
        sum += &term;
    }
    for _ in 0..s {
        sum = &sum * &sum;
    }
    sum
}

/// A sampled plant `x(t+1) = Φ x(t) + Γ w(t)`, `y(t) = C x(t)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Discrete {
    /// `Φ`.
    pub phi: DMatrix<f64>,
    /// `Γ`.
    pub gamma: DVector<f64>,
    /// `C`.
    pub c: DVector<f64>,
}

impl Discrete {
    /// The state at rest under a constant input `w0` (zero when the plant integrates).
    pub fn rest(&self, w0: f64) -> DVector<f64> {
        let n = self.phi.nrows();
        let m = DMatrix::identity(n, n) - &self.phi;
        m.lu()
            .solve(&(&self.gamma * w0))
            .filter(|x| x.iter().all(|v| v.is_finite() && v.abs() < 1e6))
            .unwrap_or_else(|| DVector::zeros(n))
    }

    /// One step: returns `y(t) = C x(t)` and advances the state with `w(t)`.
    pub fn step(&self, x: &mut DVector<f64>, w: f64) -> f64 {
        let y = self.c.dot(x);
        *x = &self.phi * &*x + &self.gamma * w;
        y
    }

    /// The output for an input sequence, from rest at `w[0]`.
    pub fn simulate(&self, w: &[f64]) -> Vec<f64> {
        let mut x = self.rest(w.first().copied().unwrap_or(0.0));
        w.iter().map(|&v| self.step(&mut x, v)).collect()
    }

    /// Moduli of the eigenvalues of `Φ` (the sampled poles).
    pub fn pole_moduli(&self) -> Vec<f64> {
        self.phi
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .collect()
    }
}
