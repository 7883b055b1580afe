//! Core errors about one sample, as a position in the CSV file the sample came from.

use std::path::Path;

use hsid::Error;
use hsid_host::identify::IdentifyError;

/// A core error about sample `index` (0 = first data row) as a file position: `lines[index]`
/// is the 1-based line of the sample in `data`.
pub fn sample_error(data: &Path, lines: &[usize], e: &IdentifyError) -> String {
    let line = |i: u64| {
        usize::try_from(i)
            .ok()
            .and_then(|i| lines.get(i))
            .map_or_else(|| format!("of sample {i}"), |l| l.to_string())
    };
    match e {
        IdentifyError::Core(Error::NonFinite { index, signal }) => {
            format!(
                "{} line {}: {signal} is NaN or infinite",
                data.display(),
                line(*index)
            )
        }
        IdentifyError::Core(Error::InputOutOfRange { index, value }) => format!(
            "{} line {}: u = {value} lies outside [--umin, --umax]: widen the interval or fix the data",
            data.display(),
            line(*index)
        ),
        IdentifyError::Core(Error::HoldNotAtMin { index, value }) => format!(
            "{} line {}: u = {value} is not --umin but the hold (--hold) is not over: if the input rests at its minimum with a little noise, give --hold-tolerance (the largest |u − u_min| to accept); if the excitation starts here, shorten --hold",
            data.display(),
            line(*index)
        ),
        // The settings, not the data, are wrong: no file position to give.
        IdentifyError::Core(e) if e.concerns_settings() => format!("settings: {e}"),
        other => format!("{}: {other}", data.display()),
    }
}
