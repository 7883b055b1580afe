//! Dynamics beyond the linear `G`: what their fits share.
//!
//! [`super::diagnose`] proposes one such class, the level-dependent stores
//! ([`super::stores`]), which start from the linear model written as a cascade of two stores
//! ([`HostModel::cascade_forms_with`](crate::identify::HostModel::cascade_forms_with)) and are fitted on the simulation error with the input nonlinearity's
//! output, the target, the skipped samples and the output map held ([`DynamicsFit`]), the border
//! values refitted with them if asked ([`Borders`]). Other classes (a polynomial state term, an
//! internal overflow) are measured on the cascaded tanks benchmark by the example
//! `tanks_dynamics` (`docs/closing-the-loop.md`) and are not proposed.

pub mod cascade;
pub mod error;
pub mod fit_data;

pub use cascade::Cascade;
pub use error::DynamicsError;
pub use fit_data::{Borders, DynamicsFit};
