//! Desktop side of `hsid`: a simulator of the true systems, a reference implementation written
//! straight from the paper's equations, the desktop identification front end, the paper's
//! Monte Carlo, CSV I/O, the model file, figures and reports. The `hsid` command line is the
//! package's binary (`cli/`), built on this library; the library knows no command line.

pub mod choose;
pub mod closed_loop;
pub mod diagnose;
pub mod figures;
pub mod fleet;
pub mod friction;
pub mod hold;
pub mod html;
pub mod hysteresis;
pub mod identify;
pub mod integrating;
pub mod io;
pub mod model;
pub mod model_file;
pub mod numerics;
pub mod paper;
pub mod plot;
pub mod progress;
pub mod reference;
pub mod refine;
pub mod report;
pub mod sandwich;
pub mod sim;
pub mod simulate;
pub mod table1;
pub mod units;
pub mod validation;
pub mod workflow;
