//! `hsid identify --fit`: whether the element is fitted by simulation error
//! (`hsid_host::workflow::element_fit` decides and fits; `Identified::lines` prints it).

use clap::ValueEnum;
use hsid_host::workflow::ElementFit;

/// What `--fit` fits after the subspace identification.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FitArg {
    /// The simulation fit, with a note, when the input breaks the Table I structure
    /// (backlash and switch: more than one and more than a tenth of the monotone runs start
    /// inside the range); else none.
    Auto,
    /// Keep the identified model (two paths or static).
    None,
    /// The play operator or relay on the borders by simulation-error minimisation.
    Simulation,
}

impl From<FitArg> for ElementFit {
    fn from(f: FitArg) -> Self {
        match f {
            FitArg::Auto => ElementFit::Auto,
            FitArg::None => ElementFit::None,
            FitArg::Simulation => ElementFit::Simulation,
        }
    }
}
