//! The layout of the Gram of `[Z_f; Z_p; Ȳ_p; Ȳ_f]`: its dimensions for `m` channels and
//! horizons `f`, `p`, the block width of the Schur complement, and where each lagged channel
//! sits among the rows.

use super::settings::{Method, SCHUR_BLOCK};

/// Layout of the solve workspace for `m` channels and horizons `f`, `p`:
/// `[L₁₁ (packed f·m) | S (packed p·m + f) | B_f (f × f·m) | two column blocks | scratch]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub m: usize,
    pub f: usize,
    pub p: usize,
    /// Columns per block of the Schur complement (at least 1, at most `q`).
    pub block: usize,
    /// The weighting; decides whether `Ȳ_p` rows are part of the instruments.
    pub method: Method,
}

impl Layout {
    /// Rows of `Φ = [Z_f; Z_p]`.
    pub const fn d(&self) -> usize {
        (self.f + self.p) * self.m
    }
    /// Rows of `Z_f`.
    pub const fn fm(&self) -> usize {
        self.f * self.m
    }
    /// Rows of `[Z_p; Ȳ_f]`, the block that stays after `Z_f` is eliminated.
    pub const fn q(&self) -> usize {
        self.w() + self.f
    }
    /// Rows of the instruments `W_p`: `Z_p`, and `Ȳ_p` for the methods that use past outputs.
    pub const fn w(&self) -> usize {
        self.p * self.m + self.py()
    }
    /// Rows of `Ȳ_p` in the instruments (0 for PI-MOESP).
    pub const fn py(&self) -> usize {
        if self.method.past_outputs() {
            self.p
        } else {
            0
        }
    }
    /// A layout with the default block width ([`SCHUR_BLOCK`], or `q` if smaller).
    pub const fn new(m: usize, f: usize, p: usize) -> Self {
        Self::with_block(m, f, p, SCHUR_BLOCK)
    }
    /// A layout with the given block width, clamped to `1 ..= q`.
    pub const fn with_block(m: usize, f: usize, p: usize, block: usize) -> Self {
        Self::for_method(m, f, p, block, Method::PiMoesp)
    }
    /// A layout for a weighting, with the given block width clamped to `1 ..= q`.
    pub const fn for_method(m: usize, f: usize, p: usize, block: usize, method: Method) -> Self {
        let mut lay = Self {
            m,
            f,
            p,
            block: 1,
            method,
        };
        let q = lay.q();
        let b = if block > q { q } else { block };
        lay.block = if b == 0 { 1 } else { b };
        lay
    }
    /// The widest block that fits in `len` scalars, if any.
    pub fn fitting(self, len: usize) -> Option<Self> {
        let fixed = self.total() - self.cache();
        let per = 2 * self.fm();
        let b = len.checked_sub(fixed)? / per.max(1);
        (b >= 1).then(|| Self::for_method(self.m, self.f, self.p, b, self.method))
    }
    /// Columns per block of the Schur complement.
    pub const fn block(&self) -> usize {
        self.block
    }
    /// Row of channel `c` of block row `a` of `z` in `[Z_f; Z_p; Ȳ_f]`.
    #[inline]
    pub fn z_row(&self, a: usize, c: usize) -> usize {
        if a >= self.p {
            (a - self.p) * self.m + c
        } else {
            self.f * self.m + a * self.m + c
        }
    }
    /// Row of `ȳ` in block row `a` in `[Z_f; Z_p; Ȳ_p; Ȳ_f]`, if it is used.
    #[inline]
    pub fn y_row(&self, a: usize) -> Option<usize> {
        let base = self.fm() + self.p * self.m;
        if a >= self.p {
            Some(base + self.py() + (a - self.p))
        } else if self.py() > 0 {
            Some(base + a)
        } else {
            None
        }
    }
}
