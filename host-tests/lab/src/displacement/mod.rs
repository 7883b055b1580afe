//! PI-MOESP's small Schur complements from the lagged sums by the generalised Schur algorithm
//! (T. Kailath, A. H. Sayed, SIAM Review 37, 1995; N. Mastronardi, D. Kressner, V. Sima,
//! P. Van Dooren, S. Van Huffel, J. Comput. Appl. Math. 132, 2001), without forming the Gram or
//! any `f·m × f·m` factor: a host-side reference for an onboard solve in less memory.
//!
//! # What is computed
//!
//! `w(t) = [z(t); ȳ(t)]` has `c = m + 1` channels; the Hankel matrix has `k = f + p` block rows
//! and `j` columns, and `M = [Z_f; Z_p; Ȳ_f]` (`Z_f`: `z` at lags `p … k−1`, `Z_p`: lags
//! `0 … p−1`, `Ȳ_f`: `ȳ` at lags `p … k−1`), `G = M Mᵀ`. [`pi_moesp_blocks`] returns
//! `S_f = S(Ȳ_f | Z_f)`, `S_Φ = S(Ȳ_f | Z_f, Z_p) = L₃₃L₃₃ᵀ`, `L₃₂L₃₂ᵀ` (accumulated from the
//! columns of `L` on `Z_p`, so without the cancellation of `S_f − S_Φ`) and
//! `B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹`, from [`LaggedSums`]: `R_τ` (`τ < k`), the first `k − 1` and
//! the last `k − 1` samples, and `j`.
//!
//! # Displacement structure
//!
//! Order the rows by group and by *reversed* lag: `z` at lags `k−1, k−2, …, 0` (`m` channels per
//! lag: `Z_f` then `Z_p`), then `ȳ` at lags `k−1, …, p`. `F` = diag(block down-shift by `m` on
//! the `z` rows, down-shift by 1 on the `ȳ` rows) maps the row of lag `ℓ + 1` onto that of lag
//! `ℓ`, and for two rows that are not the first of their group
//!
//! ```text
//! G[(i,ℓ),(i',ℓ')] − G[(i,ℓ+1),(i',ℓ'+1)] = w_i(ℓ) w_i'(ℓ') − w_i(ℓ+j) w_i'(ℓ'+j),
//! ```
//!
//! while the first rows `𝓕` (lag `k − 1`, all `c` channels) keep their rows of `G`. So
//!
//! ```text
//! G − F G Fᵀ = u uᵀ − v vᵀ + h₊h₊ᵀ − h₋h₋ᵀ,   u = G[:, 𝓕] L₀⁻ᵀ  (L₀L₀ᵀ = G[𝓕, 𝓕]),
//! v = u with the rows 𝓕 zeroed,   h₊[(i,ℓ)] = w_i(ℓ),   h₋[(i,ℓ)] = w_i(ℓ + j)   (0 on 𝓕):
//! ```
//!
//! the generator `X = [u h₊ | v h₋]` with signature `J = diag(I_{c+1}, −I_{c+1})` has rank
//! `r = 2c + 2`, and needs the entries `G[:, 𝓕]` (each `R_τ` less at most `k − 1` edge
//! products, [`LaggedSums::gram`]) and the edge samples only. The reversed order is what makes
//! `F` strictly lower triangular with `Z_f` first (the algorithm eliminates rows in order; in
//! the forward lag order `Z_p` would come first). The order within `Z_f` and within `Z_p` does
//! not change the Schur complements; the results are put back in the natural order. `Ȳ_p` can be
//! left out because `Ȳ_f` is a leading segment of the `ȳ` rows that `F` maps into itself.
//!
//! # `B_f`: bordering with the identity
//!
//! The algorithm runs on the symmetric bordered matrix `T = [[G, P], [Pᵀ, 0]]`, `P` the identity
//! between the `Z_f` rows and `f·m` extra rows `I_q` (same order, same block shift). After the
//! `Z_f` rows are eliminated, the Schur complement's block between `Ȳ_f` and the `I` rows is
//! `0 − G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹ = −B_f`, read from the generator at that moment together with
//! `S_f`. The displacement of `P` is the single block `e_{Z_0} e_{I_0}ᵀ`, and it costs no rank:
//! the general rule `u = T[:, 𝓕] L₀⁻ᵀ` gives the rows `I_q` (`q < m`) the values `e_qᵀ L₀⁻ᵀ`,
//! and `v` keeps them (the `I` rows are not first rows), so `u uᵀ − v vᵀ` gains exactly
//! `e_{Z_0} e_{I_0}ᵀ` and its transpose. Why this route:
//!
//! * the non-symmetric `[[G_ff, I], [G_Yf, 0]]` needs the two-generator (LU-type) Schur
//!   algorithm — a row and a column generator, no `J`-unitary transformations — for the same
//!   result;
//! * two passes (forward and time-reversed) do not avoid storage: each pass produces the columns
//!   of its own factor in elimination order, while `B_f = L₃₁ L₁₁⁻¹` needs a back substitution
//!   running the other way through the *same* factor (the reversed pass gives `G_ff = U Uᵀ`, `U`
//!   upper triangular, with the same problem for `G_Yf U⁻ᵀ U⁻¹`), so `L₁₁` (`(f·m)²/2`) would
//!   have to be stored;
//! * the bordered form keeps the one-generator `J`-unitary algorithm, gives `S_f` and `B_f` at
//!   the same step, and its extra rows cost at most `m` live rows (next section).
//!
//! # Live rows
//!
//! The `I` part of column `s` of `L` is column `s` of `L₁₁⁻ᵀ`, zero below row `s`, and the
//! shift `F` moves it down one block; so in exact arithmetic the generator's row `I_q` is zero
//! until the step that eliminates `Z_{q−m}`, whose slot it then takes. The generator has
//! `(k + 1)·m + f` rows ([`generator_shape`]): `m` for `I_0 … I_{m−1}`, `k·m` input rows (later
//! `I` rows), `f` output rows. What rounding would put into an `I` row before that step (values
//! that are zero in exact arithmetic) is dropped.
//!
//! # One step
//!
//! For pivot row `Z_s`: a Householder reflection on the `+1` columns and one on the `−1`
//! columns, then one hyperbolic rotation in the mixed form (`y₀ = (x₀ − ρ x_q)/σ`,
//! `y_q = σ x_q − ρ y₀`, `σ = √((1−ρ)(1+ρ))`) leave the pivot row `[δ, 0, …]`; column 0 is then
//! the column of `L` and is replaced by `F` times itself. `|ρ| ≥ 1` (or NaN) is a non-positive
//! pivot ([`DisplacementError::NonPositivePivot`]). After the `f·m` steps of `Z_f`, `S_f` solves
//! `S − F S Fᵀ = X_Y J X_Yᵀ` on the output rows (`F` nilpotent: the recursion
//! `S[a,b] = (X_Y J X_Yᵀ)[a,b] + S[a−1,b−1]`), `−B_f` solves `C − F_Y C F_Iᵀ = X_Y J X_Iᵀ`
//! the same way, and the `I` rows are dropped. The `p·m` steps of `Z_p` add `l_Y l_Yᵀ` to
//! `L₃₂L₃₂ᵀ`; at the end `S_Φ` solves the Stein equation of the remaining output rows. No pivot
//! is taken on `Ȳ_f`, so a singular `S_Φ` (noise-free data) is no failure. A per-channel scaling
//! commutes with `F` and only scales the generator's rows (`L₀`, the reflections and `ρ` follow):
//! with power-of-two scales the results are the same bit for bit (a test checks it), so the
//! solve gains nothing from equilibrating the channels.
//!
//! # Memory and cost
//!
//! Scalars (f32 bytes) for `(m, f, p) = (14, 10, 10)`, `c = 15`, `k = 20`:
//!
//! | item | scalars | f32 bytes |
//! |---|---|---|
//! | generator, `((k+1)m + f) × (2c + 2)` = 304 × 32 | 9,728 | 38,912 |
//! | outputs `B_f` (10 × 140), `S_f`, `S_Φ`, `L₃₂L₃₂ᵀ` (10 × 10 each) | 1,700 | 6,800 |
//! | one Householder vector (`c + 1`) | 16 | 64 |
//! | **peak of this implementation** (the three rows above) | 11,444 | **45,776** |
//! | only while the generator is built: `L₀` (`c × c`) and one row of `G[:, 𝓕]` | 240 | 960 |
//! | input: `R_0 … R_{k−1}` and `2(k−1)` edge samples (held by the accumulator anyway) | 5,070 | 20,280 |
//!
//! For comparison, the packed Gram of `[Z_f; Z_p; Ȳ_f]` (`n = 290`) is 168,780 bytes in f32, the
//! current panelled solve about 130 KB. Without the `I` rows the generator would be
//! `290 × 32`; with them from the start (no slot reuse) `430 × 32` = 55,040 bytes. For the
//! largest horizon `(16, 12, 12)` the generator is `412 × 36` = 59,328 bytes. The work is
//! about `3.8·10⁶` multiply-adds for `(14, 10, 10)` (`≈ (4c + 8)` per live row and step, plus
//! `≈ 10⁵` to build the generator), against `n³/6 ≈ 4.1·10⁶` for the dense Cholesky alone: the
//! gain is memory, not time.
//!
//! # Measured accuracy
//!
//! Relative Frobenius errors against the dense f64 solve (explicit Hankel rows, their Gram,
//! Cholesky and solves) on the tests' record (hats of an AR(1) input, a second-order ARX output
//! with noise; `j` = 1993, 3985, 5981, 7977):
//!
//! | `(m, f, p)` | run | `S_f` | `S_Φ` | `L₃₂L₃₂ᵀ` | `B_f` |
//! |---|---|---|---|---|---|
//! | (3, 4, 4) | f64 | 8.6e-15 | 6.6e-14 | 5.1e-15 | 1.1e-14 |
//! | (6, 8, 8) | f64 | 7.4e-15 | 9.5e-14 | 3.8e-15 | 1.9e-14 |
//! | (14, 10, 10) | f64 | 2.0e-14 | 5.4e-13 | 6.3e-15 | 4.7e-14 |
//! | (16, 12, 12) | f64 | 2.2e-14 | 6.0e-13 | 5.7e-15 | 4.2e-14 |
//! | (3, 4, 4) | f32, sums rounded from f64 | 1.4e-6 | 1.1e-5 | 5.3e-7 | 2.0e-6 |
//! | (6, 8, 8) | f32, sums rounded from f64 | 2.9e-6 | 6.4e-5 | 4.1e-6 | 9.3e-6 |
//! | (14, 10, 10) | f32, sums rounded from f64 | 9.2e-6 | 3.6e-4 | 6.3e-6 | 2.8e-5 |
//! | (16, 12, 12) | f32, sums rounded from f64 | 3.8e-6 | 1.1e-4 | 1.9e-6 | 1.0e-5 |
//! | (3, 4, 4) | f32, sums accumulated in f32 | 3.4e-6 | 7.3e-5 | 1.3e-5 | 6.4e-6 |
//! | (6, 8, 8) | f32, sums accumulated in f32 | 4.2e-6 | 5.0e-5 | 1.3e-6 | 5.3e-6 |
//! | (14, 10, 10) | f32, sums accumulated in f32 | 1.7e-5 | 5.5e-4 | 8.2e-6 | 4.1e-5 |
//! | (16, 12, 12) | f32, sums accumulated in f32 | 1.0e-5 | 3.0e-4 | 2.9e-6 | 1.5e-5 |
//! | (3, 4, 4) | f32 dense solve of the same f32 sums | 4.4e-6 | 2.8e-5 | 2.5e-6 | 3.4e-6 |
//! | (6, 8, 8) | f32 dense solve of the same f32 sums | 4.2e-6 | 5.4e-5 | 7.2e-7 | 5.6e-6 |
//! | (14, 10, 10) | f32 dense solve of the same f32 sums | 6.9e-6 | 2.0e-4 | 8.0e-7 | 8.2e-6 |
//! | (16, 12, 12) | f32 dense solve of the same f32 sums | 1.2e-5 | 3.5e-4 | 5.2e-7 | 4.5e-6 |
//!
//! The f64 errors are at the level of the reference's own rounding (forming the Gram in a
//! different summation order moved them by a factor of up to 3). In f32 the structured solve
//! is within a factor of about 5 of the dense f32 solve of the same sums on `S_f`, `S_Φ` and
//! `B_f` (better on some) and within about 10 on `L₃₂L₃₂ᵀ`; `S_Φ` (the noise part, small
//! against `G`) loses the most in both. The tests assert `1e-9` in f64 and, in f32, `2e-3` on
//! `S_Φ` and `2e-4` on the others (the largest measured values times 3.6 and 4.9).
//!
//! # The port in the core
//!
//! `hsid::Identifier::solve_structured` (`core/src/subspace/structured/`) is this algorithm on
//! fixed storage: `B_f` written over the dead `I` rows (with rows of `max(r, f)` scalars), the
//! accumulator's sums and edge samples as its input, `Rᵀ` of `L₃₂` accumulated by Givens
//! rotations from the `Z_p` steps' columns instead of `L₃₂L₃₂ᵀ`, `S_Φ` factored with the dense
//! solve's rounding floors, each half of the generator's columns padded to a multiple of 4 for
//! its kernel, and no `S_f` (PI-MOESP does not need it). It takes no centring, forgetting or
//! past outputs (`hsid::Error::NotShiftStructured`); PO-MOESP, N4SID and CVA, whose instruments
//! include `Ȳ_p` (a second group of output rows, same construction), are left to the dense
//! solve.

mod sums;
#[cfg(test)]
mod tests;

pub use sums::LaggedSums;

use hsid::Real;
use nalgebra::DMatrix;

/// Why the structured solve stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DisplacementError {
    /// The sizes do not fit together (`m`, `f`, `p` zero, too few samples, lengths of the
    /// lagged sums or of the edge samples).
    Shape,
    /// The Gram of the lag-`k−1` channels (the first rows of the generator) is not positive
    /// definite.
    FirstBlock,
    /// Elimination of input row `step` (in the generator's order) met a non-positive pivot:
    /// the input Hankel rows are (numerically) linearly dependent.
    NonPositivePivot {
        /// The eliminated row, `0 .. (f + p)·m`.
        step: usize,
    },
}

/// The quantities PI-MOESP needs, in the natural order (`Ȳ_f` rows by lag `p … k−1`, `Z_f`
/// columns by lag, then channel).
#[derive(Clone, Debug, PartialEq)]
pub struct Blocks<T: Real> {
    /// `S_f = S(Ȳ_f | Z_f)`, `f × f`.
    pub s_f: DMatrix<T>,
    /// `S_Φ = S(Ȳ_f | Z_f, Z_p) = L₃₃ L₃₃ᵀ`, `f × f`.
    pub s_phi: DMatrix<T>,
    /// `L₃₂ L₃₂ᵀ = S_f − S_Φ`, accumulated from the eliminated `Z_p` columns (no cancellation).
    pub l32_l32t: DMatrix<T>,
    /// `B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹`, `f × f·m`.
    pub b_f: DMatrix<T>,
    /// Generator rank `r = 2c + 2`.
    pub rank: usize,
    /// Scalars of the generator at its largest (`rows · r`).
    pub generator_len: usize,
}

/// Rows and columns of the generator: `(k + 1)·m + f` rows times `r = 2c + 2` columns.
pub fn generator_shape(m: usize, f: usize, p: usize) -> (usize, usize) {
    ((f + p + 1) * m + f, 2 * (m + 1) + 2)
}

/// Where the generator's rows live (see the module docs): the bordering identity's row `I_q`
/// in slot `q`, the input row `Z_z` (reversed lag order) in slot `m + z`, the output row `Ȳ_a`
/// in slot `m + k·m + a`. `I_q` (`q ≥ m`) takes the slot of `Z_{q−m}`, eliminated before `I_q`
/// can be non-zero.
#[derive(Clone, Copy, Debug)]
struct Slots {
    m: usize,
    f: usize,
    fm: usize,
    km: usize,
    /// Generator columns, `2c + 2`.
    r: usize,
    /// Columns of signature `+1` (the first `c + 1`).
    pos: usize,
}

impl Slots {
    fn new(m: usize, f: usize, p: usize) -> Self {
        let c = m + 1;
        Self {
            m,
            f,
            fm: f * m,
            km: (f + p) * m,
            r: 2 * c + 2,
            pos: c + 1,
        }
    }

    fn z(&self, z: usize) -> usize {
        self.m + z
    }

    fn y(&self, a: usize) -> usize {
        self.m + self.km + a
    }

    fn len(&self) -> usize {
        self.m + self.km + self.f
    }

    /// The slots alive while input row `s` is eliminated: identity rows `I_q`,
    /// `q < min(s + m, f·m)` (only while `Z_f` is eliminated), and the rows from `Z_s` on.
    fn active(&self, s: usize) -> [core::ops::Range<usize>; 2] {
        let ident = if s < self.fm {
            0..(s + self.m).min(self.fm)
        } else {
            0..0
        };
        [ident, self.z(s)..self.len()]
    }
}

/// The signature-weighted product `a J bᵀ` of two generator rows.
fn jdot<T: Real>(a: &[T], b: &[T], pos: usize) -> T {
    let (ap, an) = a.split_at(pos.min(a.len()));
    let (bp, bn) = b.split_at(pos.min(b.len()));
    let plus = ap.iter().zip(bp).fold(T::ZERO, |s, (x, y)| s + *x * *y);
    let minus = an.iter().zip(bn).fold(T::ZERO, |s, (x, y)| s + *x * *y);
    plus - minus
}

/// Cholesky factor (lower, row-major, in place) of a small `n × n` matrix; `None` at a
/// non-positive pivot.
fn cholesky_small<T: Real>(a: &mut [T], n: usize) -> Option<()> {
    for i in 0..n {
        for jj in 0..=i {
            let mut s = a[i * n + jj];
            for l in 0..jj {
                s -= a[i * n + l] * a[jj * n + l];
            }
            if i == jj {
                if s.partial_cmp(&T::ZERO) != Some(core::cmp::Ordering::Greater) {
                    return None;
                }
                a[i * n + i] = s.sqrt();
            } else {
                a[i * n + jj] = s / a[jj * n + jj];
            }
        }
        for jj in i + 1..n {
            a[i * n + jj] = T::ZERO;
        }
    }
    Some(())
}

/// `x ← L⁻¹ x` for a lower triangular row-major `n × n` `L`.
fn forward_solve<T: Real>(l: &[T], n: usize, x: &mut [T]) {
    for i in 0..n {
        let mut s = x[i];
        for jj in 0..i {
            s -= l[i * n + jj] * x[jj];
        }
        x[i] = s / l[i * n + i];
    }
}

/// The generator of the bordered Gram `T = [[G, E],[Eᵀ, 0]]` (`E` the identity on the `Z_f`
/// rows) for `T − F T Fᵀ = X J Xᵀ`: `u = T[:, 𝓕] L₀⁻ᵀ`, `h₊`, then `v` (= `u` off the
/// first rows `𝓕`), `h₋` (see the module docs).
fn initial_generator<T: Real>(
    sums: &LaggedSums<T>,
    sl: &Slots,
) -> Result<Vec<T>, DisplacementError> {
    let (c, k, m) = (sums.c(), sums.k(), sums.m);
    let mut l0 = vec![T::ZERO; c * c];
    for a in 0..c {
        for b in 0..c {
            l0[a * c + b] = sums.entry(a, k - 1, b, k - 1);
        }
    }
    cholesky_small(&mut l0, c).ok_or(DisplacementError::FirstBlock)?;
    let mut x = vec![T::ZERO; sl.len() * sl.r];
    let mut t = vec![T::ZERO; c];
    // (slot, channel, lag) of the input and output rows.
    let rows = (0..sl.km)
        .map(|z| (sl.z(z), z % m, k - 1 - z / m))
        .chain((0..sums.f).map(|a| (sl.y(a), m, k - 1 - a)));
    for (slot, ch, lag) in rows {
        for (s, ts) in t.iter_mut().enumerate() {
            *ts = sums.entry(ch, lag, s, k - 1);
        }
        forward_solve(&l0, c, &mut t);
        let row = &mut x[slot * sl.r..(slot + 1) * sl.r];
        let first = lag + 1 == k;
        for (s, &ts) in t.iter().enumerate() {
            row[s] = ts;
            row[sl.pos + s] = if first { T::ZERO } else { ts };
        }
        if !first {
            row[c] = sums.sample(lag, ch);
            row[sl.pos + c] = sums.sample(lag + sums.j, ch);
        }
    }
    // The identity's first block: T[I_q, 𝓕] = e_q, and I_q is not a first row.
    for q in 0..m {
        t.iter_mut().enumerate().for_each(|(s, v)| {
            *v = if s == q { T::ONE } else { T::ZERO };
        });
        forward_solve(&l0, c, &mut t);
        let row = &mut x[q * sl.r..(q + 1) * sl.r];
        for (s, &ts) in t.iter().enumerate() {
            row[s] = ts;
            row[sl.pos + s] = ts;
        }
    }
    Ok(x)
}

/// Applies the Householder reflection that maps the pivot row's entries in `cols` onto their
/// first column to those columns of every active row.
fn householder<T: Real>(
    x: &mut [T],
    sl: &Slots,
    pivot: usize,
    cols: core::ops::Range<usize>,
    active: &[core::ops::Range<usize>; 2],
) {
    let (r, c0) = (sl.r, cols.start);
    let v: Vec<T> = x[pivot * r + cols.start..pivot * r + cols.end].to_vec();
    let norm = v.iter().fold(T::ZERO, |s, a| s + *a * *a).sqrt();
    let Some(&a0) = v.first() else { return };
    if v.iter().skip(1).all(|a| *a == T::ZERO) {
        return;
    }
    let mut v = v;
    let alpha = if a0 >= T::ZERO { -norm } else { norm };
    v[0] = a0 - alpha;
    let beta = T::ONE / (norm * (norm + a0.abs()));
    for slot in active.iter().flat_map(|rg| rg.clone()) {
        let row = &mut x[slot * r + c0..slot * r + c0 + v.len()];
        let d = beta * row.iter().zip(&v).fold(T::ZERO, |s, (a, b)| s + *a * *b);
        for (a, b) in row.iter_mut().zip(&v) {
            *a -= d * *b;
        }
    }
}

/// One step of the generalised Schur algorithm on the pivot row `Z_s`: two Householder
/// reflections (signature `+1` and `−1` columns) and one hyperbolic rotation (in the mixed,
/// stable form) leave a single non-zero, in column 0, which then holds the column of `L`.
fn reduce_pivot<T: Real>(x: &mut [T], sl: &Slots, s: usize) -> Result<(), DisplacementError> {
    let (r, pos, piv) = (sl.r, sl.pos, sl.z(s));
    let active = sl.active(s);
    householder(x, sl, piv, 0..pos, &active);
    householder(x, sl, piv, pos..r, &active);
    let (a, b) = (x[piv * r], x[piv * r + pos]);
    if a.abs().partial_cmp(&b.abs()) != Some(core::cmp::Ordering::Greater) {
        return Err(DisplacementError::NonPositivePivot { step: s });
    }
    let rho = b / a;
    let sc = ((T::ONE - rho) * (T::ONE + rho)).sqrt();
    for slot in active.iter().flat_map(|rg| rg.clone()) {
        let (x0, xq) = (x[slot * r], x[slot * r + pos]);
        let y0 = (x0 - rho * xq) / sc;
        x[slot * r] = y0;
        x[slot * r + pos] = sc * xq - rho * y0;
    }
    Ok(())
}

/// The end of step `s`: column 0 (the column `l` of `L`) becomes `F l` on the rows alive at
/// step `s + 1`. The identity row `I_{s+m}` enters in the pivot's slot.
fn shift_first_column<T: Real>(x: &mut [T], sl: &Slots, s: usize) {
    let (r, m) = (sl.r, sl.m);
    for a in (1..sl.f).rev() {
        x[sl.y(a) * r] = x[sl.y(a - 1) * r];
    }
    x[sl.y(0) * r] = T::ZERO;
    for z in (s + 1..sl.km).rev() {
        x[sl.z(z) * r] = if z >= s + m {
            x[sl.z(z - m) * r]
        } else {
            T::ZERO
        };
    }
    if s >= sl.fm {
        return;
    }
    let alive = (s + 1 + m).min(sl.fm);
    if s + m < sl.fm {
        x[(s + m) * r..(s + m + 1) * r].fill(T::ZERO);
    }
    for q in (m..alive).rev() {
        x[q * r] = x[(q - m) * r];
    }
    for q in 0..m.min(alive) {
        x[q * r] = T::ZERO;
    }
}

/// `S` with `S − F S Fᵀ = X_Y J X_Yᵀ` on the output rows (a Stein equation with a nilpotent
/// shift, solved by its recursion), in the natural order.
fn stein_outputs<T: Real>(x: &[T], sl: &Slots) -> DMatrix<T> {
    let (f, r) = (sl.f, sl.r);
    let row = |a: usize| &x[sl.y(f - 1 - a) * r..(sl.y(f - 1 - a) + 1) * r];
    let mut s = DMatrix::<T>::zeros(f, f);
    for a in (0..f).rev() {
        for b in (0..f).rev() {
            let prev = if a + 1 < f && b + 1 < f {
                s[(a + 1, b + 1)]
            } else {
                T::ZERO
            };
            s[(a, b)] = jdot(row(a), row(b), sl.pos) + prev;
        }
    }
    s
}

/// `B_f` from the block `C = −B_f` of the Schur complement between the output rows and the
/// identity rows: `C − F_Y C F_Iᵀ = X_Y J X_Iᵀ`, in the natural order.
fn stein_regression<T: Real>(x: &[T], sl: &Slots) -> DMatrix<T> {
    let (f, m, r) = (sl.f, sl.m, sl.r);
    let mut b = DMatrix::<T>::zeros(f, sl.fm);
    for a in (0..f).rev() {
        let y = &x[sl.y(f - 1 - a) * r..(sl.y(f - 1 - a) + 1) * r];
        for col in (0..sl.fm).rev() {
            let q = (f - 1 - col / m) * m + col % m;
            let prev = if a + 1 < f && col + m < sl.fm {
                b[(a + 1, col + m)]
            } else {
                T::ZERO
            };
            b[(a, col)] = prev - jdot(y, &x[q * r..(q + 1) * r], sl.pos);
        }
    }
    b
}

/// `S_f`, `S_Φ`, `L₃₂L₃₂ᵀ` and `B_f` of PI-MOESP from the lagged sums by the generalised Schur
/// algorithm on a generator of `(k + 1)·m + f` rows and `2c + 2` columns (see the module docs);
/// the Gram and `L` are never formed.
pub fn pi_moesp_blocks<T: Real>(sums: &LaggedSums<T>) -> Result<Blocks<T>, DisplacementError> {
    if !sums.consistent() {
        return Err(DisplacementError::Shape);
    }
    let sl = Slots::new(sums.m, sums.f, sums.p);
    let mut x = initial_generator(sums, &sl)?;
    let (f, r) = (sl.f, sl.r);
    let mut s_f = DMatrix::<T>::zeros(f, f);
    let mut b_f = DMatrix::<T>::zeros(f, sl.fm);
    let mut l32 = DMatrix::<T>::zeros(f, f);
    for s in 0..sl.km {
        reduce_pivot(&mut x, &sl, s)?;
        if s >= sl.fm {
            for a in 0..f {
                for b in 0..f {
                    let (ya, yb) = (sl.y(f - 1 - a), sl.y(f - 1 - b));
                    l32[(a, b)] += x[ya * r] * x[yb * r];
                }
            }
        }
        shift_first_column(&mut x, &sl, s);
        if s + 1 == sl.fm {
            s_f = stein_outputs(&x, &sl);
            b_f = stein_regression(&x, &sl);
        }
    }
    Ok(Blocks {
        s_f,
        s_phi: stein_outputs(&x, &sl),
        l32_l32t: l32,
        b_f,
        rank: r,
        generator_len: x.len(),
    })
}
