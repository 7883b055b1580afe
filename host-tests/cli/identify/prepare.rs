//! What `hsid identify` checks and reads before it identifies: the request (flags that
//! contradict each other or cannot describe a record) and the records, their junctions
//! checked.

use hsid_host::workflow::IdentifyRequest;

use super::IdentifyArgs;
use super::records::Records;
use crate::failure::Failure;

/// Refuses flags that contradict each other or cannot describe a record (the library's
/// request check), before a file is opened.
fn refuse_bad_flags(a: &IdentifyArgs, request: &IdentifyRequest) -> Result<(), Failure> {
    let hold = match request.integrating {
        true => a.hold.hold.saturating_sub(1),
        false => a.hold.hold,
    };
    request.validate(hold).map_err(|e| e.message)?;
    Ok(())
}

/// The records of a whole-record run, read and their junctions checked, once the flags are
/// found consistent (`--stream` checks its own, [`super::stream::run`]).
pub fn read_records(a: &IdentifyArgs, request: &IdentifyRequest) -> Result<Records, Failure> {
    refuse_bad_flags(a, request)?;
    let reference = a.reference_column.as_deref();
    Ok(Records::read_joined(
        &a.data,
        &a.columns,
        reference,
        &a.csv,
        &a.units,
        (a.umin, a.hold.settle()),
    )?)
}
