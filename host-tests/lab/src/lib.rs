//! Test benches and research code of `hsid`, kept out of the product's library (`hsid-host`,
//! which the `hsid` command line, the Python package and the fuzz targets link):
//!
//! * [`scenario`] and [`bench`](mod@bench): the first scenario family of the diagnosis (simulated Table I
//!   experiments with one undeclared effect, and two-tank plants for the level-dependent
//!   stores) and its confusion bench (examples `confusion`, `scenario`, `stores_scenarios`);
//! * [`family_b`]: the second scenario family, written apart from the first, and its
//!   confusion table (example `confusion_b`);
//! * [`family_c`]: the third scenario family, servos with the effects real drives have
//!   (friction, play between motor and load, input play, end stops; open and closed loop),
//!   written apart from the first two, with its own resolvability check and table (example
//!   `confusion_c`);
//! * [`generality`]: the generality benchmark on random plants (example `generality`);
//! * [`parallel`]: the families' runs across threads, outcomes in the scenarios' order;
//! * [`displacement`]: PI-MOESP's Schur complements from the lagged sums by the generalised
//!   Schur algorithm, the host reference of the structured onboard solve.

pub mod bench;
pub mod displacement;
pub mod family_b;
pub mod family_c;
pub mod generality;
pub mod parallel;
pub mod scenario;
