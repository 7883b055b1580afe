//! `hsid identify --stream`: the subspace model of one CSV record read row by row and pushed
//! sample by sample into the core's identifier, in memory that does not grow with the record
//! (one line, the identifier's sums). For records too large to hold whole (10⁸ rows).
//!
//! What needs the whole record is refused rather than dropped: refinement, figures, the HTML
//! report and `--detrend` (clap's conflicts), automatic segment counts and several files
//! (here); the fits, which need a second pass, are not printed.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use hsid_host::identify::{HostModel, IdentifyOptions, identify_stream};
use hsid_host::io::{CsvStream, FileError, IoError, STDIN_NAME, STDIN_PATH};
use hsid_host::refine::knots::SegmentCount;
use hsid_host::units::{UnitsOrigin, units_from_names};
use hsid_host::workflow::element_fit::applies;
use hsid_host::workflow::{ElementFit, IdentifyRequest};

use hsid_host::table1::{RunCounter, end_tolerance};

use super::IdentifyArgs;
use crate::failure::{Failure, outln};

/// Runs `hsid identify --stream`, after refusing what needs the whole record.
pub fn run(a: &IdentifyArgs, request: &IdentifyRequest) -> Result<(), Failure> {
    if request.fit == ElementFit::Simulation {
        return Err(
            "--fit simulation needs the whole record (not --stream): drop one, or give --fit \
             auto or none"
                .to_string()
                .into(),
        );
    }
    if request.integrating {
        return Err(
            "--integrating yes identifies the output's increments, which needs the whole \
             record (not --stream): drop one"
                .to_string()
                .into(),
        );
    }
    let [path] = a.data.as_slice() else {
        return Err(format!(
            "--stream reads one record, {} given: identify them one at a time, or join them \
             into one file",
            a.data.len()
        )
        .into());
    };
    if a.segments == Some(SegmentCount::Auto) {
        return Err(
            "--segments auto refits the whole record: with --stream give a count \
                    (--segments N; default 7, the paper's) or the knots"
                .to_string()
                .into(),
        );
    }
    let opts = request
        .validate(a.hold.hold)
        .map_err(|e| e.message)?
        .options;
    let units = a.units.units()?;
    let ts = a.units.ts()?;
    let names = [
        a.columns.input_column.as_str(),
        a.columns.output_column.as_str(),
    ];
    let csv = a.csv.options();
    let (name, reader) = open(path)?;
    let stream = CsvStream::new(&name, reader, &names, &csv)?;
    let header = stream.units();
    let stated = units_from_names(&name, names, header[0].as_deref(), header[1].as_deref())
        .map_err(|e| e.to_string())?
        .map(|u| (UnitsOrigin::ColumnNames(name.clone()), u));
    let units = a.units.resolve_units(stated)?.or(units);
    let mut runs = RunCounter::new(a.umin, a.umax, end_tolerance(a.umin, a.umax));
    let hold = HoldRows {
        len: opts.hold,
        u_min: a.umin,
        tolerance: a.hold.hold_tolerance.unwrap_or(0.0),
    };
    let model = identify(stream, &name, &opts, hold, (opts.hold, &mut runs))?;
    outln!(
        "streamed {} samples (subspace model, not refined; fits not computed)",
        model.samples
    )?;
    outln!("{}", model.text())?;
    if applies(request) && runs.runs().breaks_table1() {
        outln!(
            "--fit auto: {}; the element's fit needs the whole record, not --stream: not run, the model is the two-path one",
            runs.runs().described(a.umin, a.umax)
        )?;
    }
    if let Some(out) = &a.out.json {
        let mut file = model.to_json(Some(request.element));
        file.sample_time = ts;
        file.units = units;
        file.save(out).map_err(|e| e.to_string())?;
        outln!("wrote {}", out.display())?;
    }
    Ok(())
}

/// The hold as the rows are pushed: an input of its first `len` rows within `tolerance` of
/// `u_min` is pushed as `u_min` (`--hold-tolerance`; one beyond it stops the identifier,
/// [`hsid::Error::HoldNotAtMin`]).
#[derive(Clone, Copy)]
struct HoldRows {
    len: usize,
    u_min: f64,
    tolerance: f64,
}

/// The file, or standard input for `-`, buffered, with the name errors give it.
fn open(path: &Path) -> Result<(std::path::PathBuf, Box<dyn BufRead + Send>), IoError> {
    if path == Path::new(STDIN_PATH) {
        return Ok((
            STDIN_NAME.into(),
            Box::new(BufReader::new(std::io::stdin())),
        ));
    }
    let file = File::open(path).map_err(|e| FileError::read(path, e))?;
    Ok((path.to_path_buf(), Box::new(BufReader::new(file))))
}

/// Pushes the rows of `stream` into the identifier and the inputs from the hold's last
/// sample on (`runs.0 - 1`) into the run counter `runs.1`; the first CSV error stops the
/// record and is the result (never a model of the rows before it). Errors name the file.
fn identify(
    mut stream: CsvStream<Box<dyn BufRead + Send>>,
    name: &Path,
    opts: &IdentifyOptions,
    hold: HoldRows,
    runs: (usize, &mut RunCounter),
) -> Result<HostModel, String> {
    let mut failed: Option<IoError> = None;
    // The first input of the hold off u_min beyond the tolerance (line, value), and the
    // largest deviation of the hold up to it: the record stops there.
    let mut off_hold: Option<(usize, f64)> = None;
    let mut largest = 0.0f64;
    let (from, counter) = runs;
    let mut row = 0usize;
    let mut next = || match stream.next_row() {
        Ok(Some((line, v))) => {
            if row + 1 >= from {
                counter.push(v[0]);
            }
            let in_hold = row < hold.len;
            if in_hold {
                let deviation = (v[0] - hold.u_min).abs();
                largest = largest.max(deviation);
                if !deviation.le(&hold.tolerance) {
                    off_hold = Some((line, v[0]));
                    return None;
                }
            }
            let u = if in_hold { hold.u_min } else { v[0] };
            row += 1;
            Some((u, v[1]))
        }
        Ok(None) => None,
        Err(e) => {
            failed = Some(e);
            None
        }
    };
    let result = identify_stream(&mut next, opts);
    if let Some((line, value)) = off_hold {
        return Err(format!(
            "{} line {line}: u = {value} is not u_min = {} but the hold (--hold {}) is not over \
             (--hold-tolerance {}); the largest deviation in the hold up to it is {largest:.2e}: \
             if the input rests at its minimum with a little noise, give --hold-tolerance (the \
             largest |u − u_min| to accept); if the excitation starts here, shorten --hold",
            name.display(),
            hold.u_min,
            hold.len,
            hold.tolerance
        ));
    }
    match failed {
        Some(e) => Err(e.to_string()),
        None => result.map_err(|e| format!("{}: {e}", name.display())),
    }
}
