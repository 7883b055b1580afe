//! Desktop side of `hsid`: a simulator of the true systems, a reference implementation written
//! straight from the paper's equations, the desktop identification front end, the paper's
//! Monte Carlo, CSV/JSON I/O, figures, reports and the `hsid` command line.

pub mod diagnose;
pub mod identify;
pub mod io;
pub mod model_file;
pub mod paper;
pub mod plot;
pub mod reference;
pub mod refine;
pub mod report;
pub mod sim;
