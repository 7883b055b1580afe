//! The solve's settings: the weighting ([`Method`]), the order ([`Order`], with
//! [`AUTO_ORDER_MARGIN`] for the automatic one) and the Schur complement's block width
//! ([`SCHUR_BLOCK`]).

/// The subspace weighting (Remark 4): which instruments and which weights enter the SVD that
/// gives `Γ_f`. All four share the accumulation, the Schur complement and the `B`, `D` step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Method {
    /// PI-MOESP, the paper's eq. (11): past inputs as instruments, SVD of `L₃₂`.
    #[default]
    PiMoesp,
    /// PO-MOESP: past inputs and past outputs `[Z_p; Ȳ_p]` as instruments, SVD of `L₃₂`.
    PoMoesp,
    /// N4SID (unit weights): SVD of the oblique projection of `Ȳ_f` along `Z_f` on
    /// `W_p = [Z_p; Ȳ_p]`, i.e. of `L₃₂ L₂₂⁻¹ chol(W_p W_pᵀ)`.
    N4sid,
    /// CVA: PO-MOESP with the left weight `(Ȳ_f Π⊥ Ȳ_fᵀ)^{-1/2}` (canonical correlations);
    /// `Γ_f = L_yy U₁ S₁^½`.
    Cva,
}

impl Method {
    /// Whether past outputs enter the instruments.
    pub const fn past_outputs(self) -> bool {
        !matches!(self, Method::PiMoesp)
    }
}

/// How the model order is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Order {
    /// From the whitened singular values (see the [module docs](super)).
    #[default]
    Auto,
    /// Given by the user (`1 <= n < f`).
    Fixed(usize),
}

/// Margin over the noise-only edge `1 + √(f/(p·m))` that a whitened singular value must clear
/// to count as a state direction in [`Order::Auto`].
pub const AUTO_ORDER_MARGIN: f64 = 1.5;

/// Columns of each of the two column blocks of the workspace. While the Schur complement is
/// formed, the blocks, `B_f`'s place and the scratch together hold panels of
/// `L₁₁⁻¹ G_{Z_f,[Z_p; Ȳ_f]}` (see the solve's `Schedule`) instead of the whole cross Gram.
pub const SCHUR_BLOCK: usize = 32;
