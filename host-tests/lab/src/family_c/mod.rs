//! A third scenario family for the diagnosis's confusion table: servos with the effects real
//! drives have, written apart from the code it tests and from the first two families (its
//! own random source, continuous-time plants integrated by classical Runge–Kutta with events
//! located inside a step, inputs, noise, controller and significance test).
//!
//! Classes ([`Class`]), each in open and closed loop ([`Loop`]): a clean linear servo (motor
//! speed or spring–mass–damper, order 1–3), Coulomb and viscous friction on a stable axis,
//! a two-mass drive with gear play between motor and load, play at a linear servo's input
//! behind a static element, and a position pinned at an end stop or by a saturating sensor.
//! Commands: the paper's Table I, smoothed random levels, a multisine, a slow-clock PRBS; in
//! closed loop a P or PI controller on the noisy output follows a reference of the ordinary
//! kinds. Noise white or AR(1) at 20–40 dB.
//!
//! A scenario is `(class, loop, seed)` ([`Scenario`]); [`generate()`] gives its records, the
//! diagnosis's options and the truth; [`Class::named_right`] says what the diagnosis must do;
//! [`resolvable`] decides apart from the diagnosis whether the true effect can be resolved on
//! the estimation record; [`run::run_all`] and [`table::table`] make the table (example
//! `confusion_c`).

pub mod class;
pub mod closed_loop;
pub mod design;
pub mod dm;
pub mod generate;
pub mod input;
pub mod mass;
pub mod noise;
pub mod resolvable;
pub mod rng;
pub mod run;
pub mod servo;
pub mod table;
pub mod two_mass;

pub use class::{Class, Expect, Loop};
pub use design::{Design, Scenario};
pub use generate::{Data, Truth, generate};
pub use resolvable::{Resolvability, resolvability};
pub use run::{Harm, Outcome, run_all, run_one};
