//! What `hsid identify` checks and reads before it identifies: the request (flags that
//! contradict each other or cannot describe a record) and the records, their junctions
//! checked.

use hsid_host::workflow::{ElementFit, IdentifyRequest};

use super::IdentifyArgs;
use super::records::Records;
use crate::failure::Failure;

/// Refuses flags that contradict each other or cannot describe a record: the library's
/// request check, and `--stream`'s own limits.
pub fn refuse_bad_flags(a: &IdentifyArgs, request: &IdentifyRequest) -> Result<(), Failure> {
    let hold = match request.integrating {
        true => a.hold.hold.saturating_sub(1),
        false => a.hold.hold,
    };
    request.validate(hold).map_err(|e| e.message)?;
    if request.fit == ElementFit::Simulation && a.stream {
        return Err(
            "--fit simulation needs the whole record (not --stream) and a plant without an \
             integrator (not --integrating): drop those, or give --fit auto or none"
                .to_string()
                .into(),
        );
    }
    Ok(())
}

/// The records, read and their junctions checked (once the flags are found consistent by
/// [`refuse_bad_flags`]).
pub fn read_records(a: &IdentifyArgs) -> Result<Records, Failure> {
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
