//! Friction in the drive: Coulomb, viscous and a constant force acting on the velocity of the
//! model's own output, fitted by simulation error from an identified model.
//!
//! A servo's motor pushes against friction that depends on the sign of the velocity (Coulomb),
//! on its size (viscous) and on neither (an offset: gravity on an incline, a cable). The
//! input element `H` and the linear part `G` of the Hammerstein model see none of it: the
//! residual then depends on the direction the drive moves. The model here closes that loop:
//!
//! ```text
//! w(t) = H[u(t)] − F(v(t)),   F(v) = F_c · tanh(v / v_s) + F_0,   s = G(q) w
//! ```
//!
//! with `v(t)` the velocity the model has at sample `t` before the sample's input acts
//! (`G` strictly proper): for an integrating plant (force → position, [`crate::integrating`])
//! the stable part's output `s(t) = ŷ(t) − ŷ(t − 1)` itself, for any other plant the change
//! of its output `s(t) − s(t − 1)`. The viscous term `F_v v` is linear in the velocity and so
//! is part of `G` (for a rigid body `m v̇ = f − F_v v`, the pole `exp(−F_v T_s / m)`);
//! [`physical`] reads mass and viscous friction from a first-order stable part. The sign is
//! smoothed by `tanh(v / v_s)` with `v_s` fitted: a discrete-time simulation of an exact
//! sign chatters around zero velocity, and `v_s` small against the velocities of the record
//! is the Coulomb law wherever the drive moves (a Stribeck or Dahl term, a friction with its
//! own state, is not part of this model).
//!
//! * [`model`]: the parameters and the simulation (from rest, or from an initial position and
//!   velocity read off the first samples of a record).
//! * [`fit`](mod@fit): the start (an equation-error fit with the friction regressors, and the
//!   identified model with the friction of that fit), then Levenberg–Marquardt on the
//!   simulation error (of the position for an integrating plant).
//! * [`initial`]: the initial position and velocity of an integrating model from the first
//!   samples of a record (the benchmark protocols' "first 20 samples").
//! * [`evidence`]: the residual test that proposes it: does the residual depend on the sign
//!   of the simulated velocity?
//! * [`physical`]: mass, viscous and Coulomb friction and the offset in the input's units.

pub mod evidence;
pub mod file;
pub mod fit;
pub mod initial;
pub mod model;
pub mod physical;

pub use evidence::{VelocitySign, velocity_sign, velocity_sign_arx, velocity_sign_on};
pub use fit::{FrictionError, FrictionFit, FrictionOptions, fit_friction};
pub use model::{Friction, FrictionModel};
pub use model::{Initial, START_SAMPLES};
pub use physical::Physical;
