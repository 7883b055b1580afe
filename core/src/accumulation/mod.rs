//! Streaming accumulation of the block-Hankel products in memory independent of the number of
//! samples.
//!
//! Stack the signals as `w(t) = [z(t); ȳ(t)]`. Block row `a` of the `k = f + p` block-row
//! Hankel matrix holds `w(a), …, w(a + j − 1)`. Each block of its Gram matrix is a lagged sum
//! over a window (`τ = b − a ≥ 0`):
//!
//! ```text
//! G[a, b] = Σ_{t=a}^{a+j−1} w(t) w(t+τ)ᵀ = R_τ − Σ_{t<a} w(t) w(t+τ)ᵀ − Σ_{t≥a+j} w(t) w(t+τ)ᵀ
//! ```
//!
//! with the full-range lagged sums `R_τ = Σ_t w(t) w(t+τ)ᵀ`. The corrections involve only the
//! first `k` and the last `k` samples, so the accumulator keeps `R_0 … R_{k−1}`, the first `k`
//! samples and a ring of the last `k`: `k·(m+1)²` sums plus `2k` samples, whatever the length
//! of the experiment. The type's `M` and `K` are capacities (`m <= M`, `k <= K`): firmware
//! sets them to the exact sizes, a desktop tool to the largest it accepts. The Gram blocks it produces are those of the explicit Hankel matrices,
//! exactly (up to rounding). Samples are stored as their position on the nonlinearity
//! ([`Located`]) and `ȳ`; z(t) is re-expanded on demand, which for the hat basis touches at most
//! two channels. For the hat basis the ring also keeps each sample's two terms of z(t), expanded
//! once when it enters (and rebuilt from the stored samples on restore; checkpoints do not hold
//! them), so one update costs `O(k)` multiply-adds and no expansion per lag.
//!
//! [`Located`]: crate::regressor::Located

mod accumulator;
mod lagged;
mod summation;

pub use accumulator::{Accumulator, RowSums};
pub(crate) use accumulator::{RENORM, checked_forgetting};
pub use lagged::{Entry, Lagged};
pub use summation::{Carries, Compensated, OutputCarry, OutputRounding, Plain, Summation};
