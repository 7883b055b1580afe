//! The package's exceptions and the mapping from the library's typed errors: `HsidError`, the
//! base, and `DataError` (bad arrays, records, model files, checkpoints), `SettingsError` (bad
//! settings) and `IdentificationError` (the identification itself failed). Each carries the
//! library's message and a `.kind` string naming the error's variant.

use hsid::Error;
use hsid_host::choose::ChooseError;
use hsid_host::diagnose::DiagnoseError;
use hsid_host::fleet::device::checkpoint_kind;
use hsid_host::identify::IdentifyError;
use hsid_host::model_file::ModelFileError;
use hsid_host::progress::Interrupted;
use hsid_host::simulate::SimulateError;
use hsid_host::units::TimeError;
use hsid_host::workflow::{RequestError, WorkflowError};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

pyo3::create_exception!(hsid, HsidError, PyException, "Base of every error of hsid.");
pyo3::create_exception!(
    hsid,
    DataError,
    HsidError,
    "Bad data: arrays, records, model files or checkpoints."
);
pyo3::create_exception!(hsid, SettingsError, HsidError, "Bad settings.");
pyo3::create_exception!(
    hsid,
    IdentificationError,
    HsidError,
    "The identification failed on valid data and settings."
);

/// The exception class of a failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// [`DataError`].
    Data,
    /// [`SettingsError`].
    Settings,
    /// [`IdentificationError`].
    Identification,
}

/// A failure on its way to Python: class, kind and message.
#[derive(Debug)]
pub struct Failure {
    /// The exception class.
    pub class: Class,
    /// The `.kind` of the exception.
    pub kind: &'static str,
    /// The message.
    pub message: String,
}

impl Failure {
    /// A failure of `class` and `kind` saying `message`.
    pub fn new(class: Class, kind: &'static str, message: impl Into<String>) -> Self {
        Self {
            class,
            kind,
            message: message.into(),
        }
    }
}

impl From<Failure> for PyErr {
    fn from(f: Failure) -> Self {
        let err = match f.class {
            Class::Data => DataError::new_err(f.message),
            Class::Settings => SettingsError::new_err(f.message),
            Class::Identification => IdentificationError::new_err(f.message),
        };
        Python::attach(|py| match err.value(py).setattr("kind", f.kind) {
            Ok(()) => err,
            Err(e) => e,
        })
    }
}

/// The class and kind of a core error.
fn core_kind(e: &Error) -> (Class, &'static str) {
    use Class::{Data, Identification, Settings};
    match e {
        Error::InvalidInterval { .. } => (Settings, "invalid_interval"),
        Error::TooFewKnots { .. } => (Settings, "too_few_knots"),
        Error::KnotsNotIncreasing { .. } => (Settings, "knots_not_increasing"),
        Error::KnotEndpoints { .. } => (Settings, "knot_endpoints"),
        Error::SegmentCount { .. } => (Settings, "segment_count"),
        Error::InvalidHorizon { .. } => (Settings, "invalid_horizon"),
        Error::TooFewInstruments { .. } => (Settings, "too_few_instruments"),
        Error::InvalidOrder { .. } => (Settings, "invalid_order"),
        Error::HoldTooShort { .. } => (Settings, "hold_too_short"),
        Error::InvalidMu0 { .. } => (Settings, "invalid_mu0"),
        Error::InvalidForgetting { .. } => (Settings, "invalid_forgetting"),
        Error::Unconfigured => (Settings, "unconfigured"),
        Error::WorkspaceTooSmall { .. } => (Settings, "workspace_too_small"),
        Error::NotShiftStructured { .. } => (Settings, "not_shift_structured"),
        Error::HoldNotAtMin { .. } => (Data, "hold_not_at_min"),
        Error::NonFinite { .. } => (Data, "non_finite"),
        Error::InputOutOfRange { .. } => (Data, "input_out_of_range"),
        Error::TooFewSamples { .. } => (Data, "too_few_samples"),
        Error::NoExcitation { .. } => (Data, "no_excitation"),
        Error::Checkpoint(c) => (Data, checkpoint_kind(*c)),
        Error::RankDeficient { .. } => (Identification, "rank_deficient"),
        Error::Overflow { .. } => (Identification, "overflow"),
        Error::NoConvergence { .. } => (Identification, "no_convergence"),
        Error::NoDynamics => (Identification, "no_dynamics"),
        Error::ZeroStaticGain => (Identification, "zero_static_gain"),
        Error::UnstableModel { .. } => (Identification, "unstable_model"),
        Error::IntegratingModel => (Identification, "integrating_model"),
    }
}

impl From<IdentifyError> for Failure {
    fn from(e: IdentifyError) -> Self {
        let (class, kind) = match &e {
            IdentifyError::Core(c) => core_kind(c),
            IdentifyError::LengthMismatch { .. } => (Class::Data, "length_mismatch"),
            IdentifyError::TooLarge { .. } => (Class::Settings, "too_large"),
        };
        Failure::new(class, kind, e.to_string())
    }
}

impl From<hsid::Error> for Failure {
    fn from(e: hsid::Error) -> Self {
        let (class, kind) = core_kind(&e);
        Failure::new(class, kind, e.to_string())
    }
}

impl From<RequestError> for Failure {
    fn from(e: RequestError) -> Self {
        let class = match e.kind {
            "all_hold" => Class::Data,
            _ => Class::Settings,
        };
        Failure::new(class, e.kind, e.message)
    }
}

impl From<WorkflowError> for Failure {
    fn from(e: WorkflowError) -> Self {
        match e {
            WorkflowError::Request(e) => e.into(),
            WorkflowError::Sample { error, .. } => error.into(),
            WorkflowError::Choose(e) => e.into(),
            e @ WorkflowError::ClosedLoop { .. } => {
                Failure::new(Class::Identification, "closed_loop", e.to_string())
            }
            e @ WorkflowError::ElementFit { .. } => {
                Failure::new(Class::Identification, "element_fit", e.to_string())
            }
            WorkflowError::Interrupted(i) => i.into(),
        }
    }
}

/// A run stopped by its caller: the call that stopped it raises `KeyboardInterrupt` itself
/// ([`crate::interrupt`]), so this reaches Python only from a run stopped another way.
impl From<Interrupted> for Failure {
    fn from(e: Interrupted) -> Self {
        Failure::new(Class::Identification, "interrupted", e.to_string())
    }
}

impl From<ChooseError> for Failure {
    fn from(e: ChooseError) -> Self {
        match e {
            ChooseError::Identify(e) => e.into(),
            e @ ChooseError::Refine(_) => {
                Failure::new(Class::Identification, "refinement_failed", e.to_string())
            }
            e @ ChooseError::NoCandidate => {
                Failure::new(Class::Settings, "no_candidate", e.to_string())
            }
            ChooseError::Interrupted(i) => i.into(),
        }
    }
}

impl From<SimulateError> for Failure {
    fn from(e: SimulateError) -> Self {
        let (class, kind) = match &e {
            SimulateError::Json { .. } => (Class::Settings, "spec_json"),
            SimulateError::Format { .. } => (Class::Settings, "spec_format"),
            SimulateError::OutOfRange { .. } => (Class::Settings, "spec_out_of_range"),
            SimulateError::Missing { .. } => (Class::Settings, "spec_missing"),
            SimulateError::Conflict { .. } => (Class::Settings, "spec_conflict"),
            SimulateError::Knots { .. } => (Class::Settings, "spec_knots"),
            SimulateError::Unstable { .. } => (Class::Settings, "spec_unstable"),
            SimulateError::TransferFunction { .. } => (Class::Settings, "spec_transfer_function"),
            SimulateError::NoNoiseModel => (Class::Settings, "no_noise_model"),
            SimulateError::IncrementsNoiseModel => (Class::Settings, "increments_noise_model"),
            SimulateError::NoNoiseLevel => (Class::Settings, "no_noise_level"),
            SimulateError::InputOutsideModel { .. } => (Class::Data, "input_out_of_range"),
            SimulateError::Time(TimeError::NotIncreasing { .. }) => {
                (Class::Data, "time_not_increasing")
            }
            SimulateError::Time(_) => (Class::Data, "time_column"),
            SimulateError::ConstantOutput => (Class::Data, "constant_output"),
            SimulateError::Io(_) => (Class::Data, "io"),
        };
        Failure::new(class, kind, e.to_string())
    }
}

impl From<ModelFileError> for Failure {
    fn from(e: ModelFileError) -> Self {
        let kind = match &e {
            ModelFileError::File(_) => "model_file_io",
            ModelFileError::TooLarge(_) => "model_file_too_large",
            ModelFileError::Version { .. } => "model_file_version",
            ModelFileError::Json { .. } => "model_file_json",
            ModelFileError::DuplicateKey { .. } => "model_file_duplicate_key",
            ModelFileError::Invalid { .. } => "model_file_invalid",
        };
        Failure::new(Class::Data, kind, e.to_string())
    }
}

impl From<DiagnoseError> for Failure {
    fn from(e: DiagnoseError) -> Self {
        let (class, kind) = match &e {
            DiagnoseError::Identify(i) => return i.clone().into(),
            DiagnoseError::Interrupted(i) => return (*i).into(),
            DiagnoseError::LengthMismatch { .. } => (Class::Data, "length_mismatch"),
            DiagnoseError::TooShort { .. } => (Class::Data, "too_short"),
            DiagnoseError::AllHold { .. } => (Class::Data, "all_hold"),
            DiagnoseError::MaxDelay { .. } => (Class::Settings, "max_delay"),
            DiagnoseError::InputOutOfRange { .. } => (Class::Data, "input_out_of_range"),
            DiagnoseError::KnotNotVisited { .. } => (Class::Data, "knot_not_visited"),
            DiagnoseError::InvalidSplit(_) => (Class::Settings, "invalid_split"),
            DiagnoseError::InvalidHoldout { .. } => (Class::Settings, "invalid_holdout"),
            DiagnoseError::Dynamics(_) => (Class::Identification, "dynamics"),
            DiagnoseError::Reference(_) => (Class::Data, "reference"),
            DiagnoseError::Output(_) => (Class::Identification, "output"),
            DiagnoseError::Setting { .. } => (Class::Settings, "setting"),
        };
        Failure::new(class, kind, e.to_string())
    }
}
