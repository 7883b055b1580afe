//! The identified model: the linear part `(A, B, C, D)` with `G(1) = 1`, μ0 and the borders
//! `P_a`, `P_d` on their knots; evaluation of the borders and simulation.

use heapless::Vec;

use crate::direction::Direction;
use crate::linalg::Small;
use crate::regressor::Knots;
use crate::scalar::Real;

/// The horizon capacity `H` of [`Identifier`](crate::Identifier), [`Model`] and
/// [`ModelState`] when it is not given: 12, the bound the crate always had, so that
/// `Identifier<f32, M, K>` keeps its meaning. Firmware that knows its `f` gives `H = f` (the
/// small `H × H` matrices of the solve then take no more stack than they must); a desktop
/// tool gives the largest `f` it accepts.
pub const DEFAULT_HORIZON: usize = 12;

/// A Hammerstein model `y(t) = G(q) H[u(t)]` with `H` on the ascending path `P_a` and the
/// descending path `P_d` (eq. 2), both continuous piecewise linear on their knots.
///
/// `G(q) = C (qI − A)⁻¹ B + D` has unit static gain (assumption A.2), which fixes the scale
/// of the borders (Remark 1).
///
/// `H` is the horizon capacity of the [`Identifier`](crate::Identifier) that produced the
/// model: it holds up to `H` singular values and a state of up to `H − 1` entries.
#[derive(Clone, Debug, PartialEq)]
pub struct Model<T, const M: usize, const H: usize = DEFAULT_HORIZON> {
    pub(crate) n: usize,
    pub(crate) a: Small<T, H>,
    pub(crate) b: [T; H],
    pub(crate) c: [T; H],
    pub(crate) d: T,
    pub(crate) dc_state: [T; H],
    pub(crate) mu0: T,
    pub(crate) knots: Knots<T, M>,
    pub(crate) border_asc: Vec<T, M>,
    pub(crate) border_desc: Vec<T, M>,
    pub(crate) f: usize,
    pub(crate) columns: u64,
    pub(crate) sv: [T; H],
    pub(crate) sv_white: [T; H],
}

/// Simulation state of a [`Model`]: the linear state, the direction δ and the previous input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelState<T, const H: usize = DEFAULT_HORIZON> {
    x: [T; H],
    dir: Direction,
    u_prev: T,
}

impl<T: Real, const M: usize, const H: usize> Model<T, M, H> {
    /// Model order `n`.
    pub fn order(&self) -> usize {
        self.n
    }

    /// Entry `(i, j)` of `A` (zero outside `n × n`).
    pub fn a(&self, i: usize, j: usize) -> T {
        if i < self.n && j < self.n {
            self.a[(i, j)]
        } else {
            T::zero()
        }
    }

    /// `B` (length `n`).
    pub fn b(&self) -> &[T] {
        &self.b[..self.n]
    }

    /// `C` (length `n`).
    pub fn c(&self) -> &[T] {
        &self.c[..self.n]
    }

    /// `D`.
    pub fn d(&self) -> T {
        self.d
    }

    /// μ0 = `P_a(u_min)` = `P_d(u_min)`.
    pub fn mu0(&self) -> T {
        self.mu0
    }

    /// The knots (both paths).
    pub fn knots(&self) -> &Knots<T, M> {
        &self.knots
    }

    /// Border values at the knots of a path (`P_a(n_i)` or `P_d(n_i)`, `i = 0 … n_p`).
    pub fn border_values(&self, dir: Direction) -> &[T] {
        match dir {
            Direction::Ascending => &self.border_asc,
            Direction::Descending => &self.border_desc,
        }
    }

    /// The paper's `μ_i` of a path (eq. 3): the slope of the border on segment `i`, written
    /// into `out` (length `n_p`); returns the number written.
    pub fn mu(&self, dir: Direction, out: &mut [T]) -> usize {
        let k = self.knots.path(dir);
        let v = self.border_values(dir);
        let mut n = 0;
        for ((o, kk), vv) in out.iter_mut().zip(k.windows(2)).zip(v.windows(2)) {
            if let ([k0, k1], [v0, v1]) = (kk, vv) {
                *o = (*v1 - *v0) / (*k1 - *k0);
                n += 1;
            }
        }
        n
    }

    /// `P_a(u)` or `P_d(u)`: linear interpolation of the border values (clamped to the
    /// interval's ends outside `[u_min, u_max]`).
    pub fn border(&self, dir: Direction, u: T) -> T {
        let at = self.knots.locate(dir, u);
        let v = self.border_values(dir);
        let s = at.segment as usize;
        match (v.get(s), v.get(s + 1)) {
            (Some(&a), Some(&b)) => a + (b - a) * at.theta,
            _ => self.mu0,
        }
    }

    /// Singular values of `O_f / √j` (eq. 12), descending, `f` of them.
    pub fn singular_values(&self) -> &[T] {
        &self.sv[..self.f]
    }

    /// Noise-whitened singular values used by [`Order::Auto`](crate::Order::Auto).
    pub fn whitened_singular_values(&self) -> &[T] {
        &self.sv_white[..self.f]
    }

    /// Future horizon `f` the model was identified with.
    pub fn horizon(&self) -> usize {
        self.f
    }

    /// Hankel columns `j` used.
    pub fn columns(&self) -> u64 {
        self.columns
    }

    /// Markov parameter `h_k` of `G`: `h_0 = D`, `h_k = C A^{k−1} B`.
    pub fn markov(&self, k: usize) -> T {
        if k == 0 {
            return self.d;
        }
        let mut v = self.b;
        for _ in 1..k {
            v = self.mul_a(&v);
        }
        self.c()
            .iter()
            .zip(&v)
            .fold(T::zero(), |s, (&c, &x)| s + c * x)
    }

    /// Static gain `G(1) = C (I − A)⁻¹ B + D` (1 up to rounding, by construction).
    pub fn static_gain(&self) -> T {
        self.c()
            .iter()
            .zip(&self.dc_state)
            .fold(self.d, |s, (&c, &x)| s + c * x)
    }

    fn mul_a(&self, x: &[T; H]) -> [T; H] {
        let mut y = [T::zero(); H];
        for (i, yi) in y.iter_mut().enumerate().take(self.n) {
            for (j, &xj) in x.iter().enumerate().take(self.n) {
                *yi += self.a[(i, j)] * xj;
            }
        }
        y
    }

    /// A simulation state at rest at `u_min`: the input held at `u_min` long enough for the
    /// output to settle at μ0, as after the identification hold.
    pub fn rest_state(&self) -> ModelState<T, H> {
        let mut x = [T::zero(); H];
        for (xi, &s) in x.iter_mut().zip(&self.dc_state).take(self.n) {
            *xi = s * self.mu0;
        }
        ModelState {
            x,
            dir: Direction::Descending,
            u_prev: self.knots.u_min(),
        }
    }

    /// One simulation step: δ(t) from the input, `H = P_a(u)` or `P_d(u)`, then the linear
    /// part. Returns the simulated output `y(t)`.
    pub fn step(&self, state: &mut ModelState<T, H>, u: T) -> T {
        state.dir = state.dir.next(state.u_prev, u);
        state.u_prev = u;
        let h = self.border(state.dir, u);
        let y = self
            .c()
            .iter()
            .zip(&state.x)
            .fold(self.d * h, |s, (&c, &x)| s + c * x);
        let mut next = self.mul_a(&state.x);
        for (nx, &b) in next.iter_mut().zip(&self.b).take(self.n) {
            *nx += b * h;
        }
        state.x = next;
        y
    }
}
