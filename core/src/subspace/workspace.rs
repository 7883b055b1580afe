//! The solve workspace: the sizes of its regions and of the scratch of each step, its total
//! (what [`workspace_len`] reports), and its carving into the regions.

use super::layout::Layout;
use super::settings::Method;
use crate::error::Error;
use crate::linalg::packed_len;

impl Layout {
    /// Packed `L₁₁`.
    pub const fn lff(&self) -> usize {
        packed_len(self.fm())
    }
    /// Packed Schur complement, then its Cholesky factor.
    pub const fn schur(&self) -> usize {
        packed_len(self.q())
    }
    /// Packed Gram of the instruments `W_p` (N4SID only).
    pub const fn wgram(&self) -> usize {
        if matches!(self.method, Method::N4sid) {
            packed_len(self.w())
        } else {
            0
        }
    }
    /// Length of `B_f = L₃₁ L₁₁⁻¹` (`f × f·m`).
    pub const fn bf(&self) -> usize {
        self.f * self.fm()
    }
    /// Two column blocks of `L₁₁⁻¹ G_{f,·}`.
    pub const fn cache(&self) -> usize {
        2 * self.block() * self.fm()
    }
    /// Scratch of the projection's QR of `L₃₂ᵀ` (`w × f`): the matrix, then `f` reflector
    /// scalars.
    pub const fn qr_parts(&self) -> (usize, usize) {
        (self.w() * self.f, self.f)
    }
    /// Scratch of `U₂` for order `n`: `Γ_f` (`f × n`), `n` reflector scalars, a vector of `f`.
    pub const fn u2_parts(&self, n: usize) -> (usize, usize, usize) {
        (self.f * n, n, self.f)
    }
    /// Scratch of the shift invariance for order `n`: `Γ_under`, `Γ_over` (`(f−1) × n` each),
    /// `n` reflector scalars.
    pub const fn shift_parts(&self, n: usize) -> (usize, usize, usize) {
        let g = (self.f - 1) * n;
        (g, g, n)
    }
    /// Scratch of the `[D; B]` least squares for order `n`: the `f(f−n) × (n+1)` matrix, the
    /// `f(f−n) × m` right-hand sides (then the solution), `n + 1` reflector scalars.
    pub const fn bd_parts(&self, n: usize) -> (usize, usize, usize) {
        let rows = self.f * (self.f - n);
        (rows * (n + 1), rows * self.m, n + 1)
    }
    /// Scratch of the rank-1 split of the `(n+1) × m` solution, placed after the
    /// [`bd_parts`](Self::bd_parts) (whose solution it reads): a copy of the matrix (or its
    /// transpose), `min(n+1, m)` reflector scalars and a vector of `max(n+1, m)`.
    pub const fn split_len(&self, n: usize) -> usize {
        let r = n + 1;
        let (lo, hi) = if r < self.m { (r, self.m) } else { (self.m, r) };
        r * self.m + lo + hi
    }
    /// Scratch of γ for order `n`: `I − A` (`n × n`), the right-hand side and `n` reflector
    /// scalars.
    pub const fn gain_parts(&self, n: usize) -> (usize, usize, usize) {
        (n * n, n, n)
    }
    /// Scratch for the QR/least-squares steps: the projection's QR or the model's steps
    /// ([`estimate_scratch`](Self::estimate_scratch)), whichever is longer.
    pub const fn scratch(&self) -> usize {
        let (x, tau) = self.qr_parts();
        let est = self.estimate_scratch();
        if x + tau > est { x + tau } else { est }
    }
    /// Scratch of the model's steps: the largest of the step sizes above over every order
    /// `1 <= n < f` (the slicing in the solve uses the same functions).
    pub const fn estimate_scratch(&self) -> usize {
        let mut need = 0;
        let mut n = 1;
        while n < self.f {
            let (a, b, c) = self.u2_parts(n);
            let u2 = a + b + c;
            let (a, b, c) = self.shift_parts(n);
            let shift = a + b + c;
            let (a, b, c) = self.bd_parts(n);
            let bd = a + b + c + self.split_len(n);
            let (a, b, c) = self.gain_parts(n);
            let gain = a + b + c;
            let mut step = u2;
            if shift > step {
                step = shift;
            }
            if bd > step {
                step = bd;
            }
            if gain > step {
                step = gain;
            }
            if step > need {
                need = step;
            }
            n += 1;
        }
        need
    }
    /// Whole workspace.
    pub const fn total(&self) -> usize {
        self.lff() + self.schur() + self.wgram() + self.bf() + self.cache() + self.scratch()
    }
    /// The workspace `ws` split into `[L₁₁, S, W_p Gram, B_f, column blocks, scratch]` (the
    /// scratch is the rest); [`Error::WorkspaceTooSmall`] if `ws` is shorter than
    /// [`total`](Self::total).
    pub fn carve<'a, T>(&self, ws: &'a mut [T]) -> Result<[&'a mut [T]; 6], Error> {
        let err = too_small(*self, ws.len());
        let [lff, schur, wgram, rest] = self.carve_front(ws)?;
        let (bf, rest) = rest.split_at_mut_checked(self.bf()).ok_or(err)?;
        let (cache, scratch) = rest.split_at_mut_checked(self.cache()).ok_or(err)?;
        if scratch.len() < self.scratch() {
            return Err(err);
        }
        Ok([lff, schur, wgram, bf, cache, scratch])
    }
    /// The workspace `ws` split into `[L₁₁, S, W_p Gram, the rest]`, the rest at least as long
    /// as `B_f`, the column blocks and the scratch together (which [`carve`](Self::carve)
    /// separates; the Schur complement's step uses them as one cache while they are idle).
    pub fn carve_front<'a, T>(&self, ws: &'a mut [T]) -> Result<[&'a mut [T]; 4], Error> {
        let err = too_small(*self, ws.len());
        let (lff, rest) = ws.split_at_mut_checked(self.lff()).ok_or(err)?;
        let (schur, rest) = rest.split_at_mut_checked(self.schur()).ok_or(err)?;
        let (wgram, rest) = rest.split_at_mut_checked(self.wgram()).ok_or(err)?;
        if rest.len() < self.bf() + self.cache() + self.scratch() {
            return Err(err);
        }
        Ok([lff, schur, wgram, rest])
    }
}

/// The error for a workspace of `have` scalars that is shorter than `lay` needs.
pub(crate) fn too_small(lay: Layout, have: usize) -> Error {
    Error::WorkspaceTooSmall {
        need: lay.total(),
        have,
    }
}

/// Scalars the solve workspace needs for `m` channels and horizons `f`, `p` with the default
/// block width [`SCHUR_BLOCK`](super::SCHUR_BLOCK): size a static array with it, e.g.
/// `[0.0f32; hsid::workspace_len(14, 10, 10)]`.
///
/// The solve adapts to the workspace it is given: less (down to
/// [`workspace_len_with_block`]`(m, f, p, 1)`) saves memory and costs passes over the lagged
/// sums, more (up to block `p·m + f`) saves time.
pub const fn workspace_len(m: usize, f: usize, p: usize) -> usize {
    Layout::new(m, f, p).total()
}

/// Scalars the solve workspace needs with a Schur-complement block of `block` columns.
pub const fn workspace_len_with_block(m: usize, f: usize, p: usize, block: usize) -> usize {
    Layout::with_block(m, f, p, block).total()
}
