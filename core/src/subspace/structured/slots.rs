//! Where the generator's rows live in the workspace, and how long the workspace is.

use super::super::layout::Layout;

/// The generator's rows (see the [module docs](super)): the bordering identity's row `I_q` in
/// slot `q`, input row `Z_z` (reversed lag order: channel `z mod m`, lag `k − 1 − ⌊z/m⌋`) in
/// slot `m + z`, output row `Ȳ_a` (lag `k − 1 − a`) in slot `m + k·m + a`. `I_q` (`q ≥ m`)
/// takes the slot of `Z_{q−m}`, eliminated before `I_q` can be non-zero. Each slot holds
/// `stride = max(r, f)` scalars: the generator's `r` columns (its rank `2c + 2`, each half
/// padded to a multiple of 4), or `B_f`'s column of `f` once the identity rows are dead.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slots {
    /// Regressor channels.
    pub m: usize,
    /// Future horizon.
    pub f: usize,
    /// Rows of `Z_f`.
    pub fm: usize,
    /// Rows of `[Z_f; Z_p]`.
    pub km: usize,
    /// Channels of `w = [z; ȳ]`, `m + 1`.
    pub c: usize,
    /// Generator columns, `2·pos`.
    pub r: usize,
    /// Columns of signature `+1` (the first `c + 1`, padded with zero columns to a multiple
    /// of 4 for the step's kernel; as many of signature `−1` follow).
    pub pos: usize,
    /// Scalars per slot.
    pub stride: usize,
    /// Block rows `k = f + p`.
    pub k: usize,
}

impl Slots {
    /// The slots for `m` channels and horizons `f`, `p`.
    pub(crate) const fn new(m: usize, f: usize, p: usize) -> Self {
        let c = m + 1;
        let pos = (c + 1).div_ceil(4) * 4;
        let r = 2 * pos;
        Self {
            m,
            f,
            fm: f * m,
            km: (f + p) * m,
            c,
            r,
            pos,
            stride: if r > f { r } else { f },
            k: f + p,
        }
    }

    /// The slots of a layout.
    pub(crate) const fn of(lay: Layout) -> Self {
        Self::new(lay.m, lay.f, lay.p)
    }

    /// Slot of input row `z` (reversed lag order).
    pub(super) const fn z(&self, z: usize) -> usize {
        self.m + z
    }

    /// Slot of output row `a` (reversed lag order).
    pub(super) const fn y(&self, a: usize) -> usize {
        self.m + self.km + a
    }

    /// Slots in all.
    pub(super) const fn len(&self) -> usize {
        self.m + self.km + self.f
    }

    /// Offset of slot `slot` in the workspace.
    pub(crate) const fn off(&self, slot: usize) -> usize {
        slot * self.stride
    }

    /// Scalars of the generator.
    pub(super) const fn generator_len(&self) -> usize {
        self.len() * self.stride
    }

    /// Scalars after the generator: `L₀` (`c × c`) and three vectors of `c` (a row of
    /// `G[:, 𝓕]` and two expanded samples) while the generator is built, one Householder
    /// row (`r`) while it is reduced.
    pub(super) const fn aux_len(&self) -> usize {
        self.c * self.c + 3 * self.c
    }

    /// The channel and lag of input row `z` (reversed lag order).
    pub(super) fn z_row(&self, z: usize) -> (usize, usize) {
        let block = z.checked_div(self.m).unwrap_or(0);
        let ch = z.checked_rem(self.m).unwrap_or(0);
        (ch, self.k.saturating_sub(1 + block))
    }

    /// The slots alive while input row `s` is eliminated: identity rows `I_q`,
    /// `q < min(s + m, f·m)` (only while `Z_f` is eliminated), and the rows from `Z_s` on.
    pub(super) fn active(&self, s: usize) -> [core::ops::Range<usize>; 2] {
        let ident = if s < self.fm {
            0..(s + self.m).min(self.fm)
        } else {
            0..0
        };
        [ident, self.z(s)..self.len()]
    }
}

/// Scalars of the structured solve's workspace for `lay` (PI-MOESP): the generator and its
/// auxiliary vectors, or `B_f` in the identity slots plus the model step's scratch, whichever
/// is longer.
pub(crate) const fn structured_len(lay: Layout) -> usize {
    let sl = Slots::of(lay);
    let solve = sl.generator_len() + sl.aux_len();
    let model = sl.fm * sl.stride + lay.estimate_scratch();
    if solve > model { solve } else { model }
}
