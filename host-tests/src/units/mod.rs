//! The sample time and units of a record, and the identified model read in them.
//!
//! * [`time`]: the sample time from `--ts`, a time column, a model file or a plant
//!   specification, checked positive, uniform and consistent between its sources.
//! * [`poles`]: each discrete pole's continuous-time equivalent `s = ln(z)/ts` (time constant,
//!   natural frequency and damping), with first-order standard deviations.
//! * [`gain`]: the static gains and the −3 dB bandwidth of the linear part.
//! * [`gap`]: the backlash gap (play) and the loop height of a two-path element as functions of
//!   u, by the definitions of the firmware's `Model::gap_at` and `Model::loop_height`.
//! * [`dead_band`]: the widest flat interval of a static element's border.
//! * [`header`]: a record's header comments (`# key = value`), where both are stated.
//! * [`stated`]: the units from the flags, a model file, a plant specification, a record's
//!   header comments or its column names (`u [V]`), checked to agree.
//! * [`report`]: all of it as one [`UnitReport`], printed by `identify` and `validate`.
//!
//! Without a sample time the same numbers are given per sample (time constants in samples,
//! frequencies in rad/sample), and labelled so.

pub mod dead_band;
pub mod gain;
pub mod gap;
pub mod header;
pub mod poles;
pub mod report;
pub mod stated;
pub mod time;

pub use header::{HeaderComment, header_comments};
pub use report::{GapAt, UnitReport, gap_text};
pub use stated::{
    UnitCharError, UnitsError, UnitsOrigin, check_unit_text, resolve_units, units_from_comments,
    units_from_names,
};
pub use time::{
    Jitter, Origin, TimeError, TimeUnit, checked_ts, is_time_name, resolve_ts, time_unit_of,
    ts_from_column, ts_from_comments,
};
