#![doc = include_str!("../../README.md")]
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod accumulation;
pub mod checkpoint;
pub mod direction;
pub mod error;
pub mod estimation;
pub mod excitation;
pub mod hold;
pub mod identifier;
mod linalg;
pub mod model;
pub mod play;
pub mod regressor;
pub mod scalar;
pub mod store;
pub mod subspace;

pub use accumulation::{
    Accumulator, Carries, Compensated, Entry, Lagged, OutputCarry, OutputRounding, Plain, RowSums,
    Summation,
};
pub use checkpoint::{
    CHECKPOINT_VERSION, checkpoint_capacity, compensated_checkpoint_capacity, crc32,
};
pub use direction::Direction;
pub use error::{CheckpointError, Error, KnotEnd, ShiftBreak, Signal, Stage};
pub use estimation::Poles;
pub use excitation::Excitation;
pub use hold::{HoldMean, MuZero};
pub use identifier::{Forgetting, Identifier, Settings};
pub use model::{DEFAULT_HORIZON, Model, ModelState};
pub use regressor::{Basis, Knots, Located};
pub use scalar::Real;
pub use subspace::{
    AUTO_ORDER_MARGIN, Method, Order, SCHUR_BLOCK, structured_workspace_len, workspace_len,
    workspace_len_with_block,
};
