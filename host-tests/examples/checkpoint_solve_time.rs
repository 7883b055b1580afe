//! Time of the library call that solves a checkpoint, for comparison with the Python call
//! `hsid.solve_checkpoint` on the same bytes (`scripts/python-overhead.py`).
//!
//! ```text
//! cargo run --release -p hsid-host --example checkpoint_solve_time -- DIR [REPS]
//! ```
//!
//! Reads every file of `DIR` (checkpoints, e.g. from `hsid fleet simulate`) into memory, then
//! `REPS` times (default 5) solves all of them one after the other on this thread, each into
//! its model file, the work `hsid.solve_checkpoint` does: [`solve_checkpoint`] and
//! [`HostModel::to_json`](hsid_host::identify::HostModel::to_json). A checkpoint that does not
//! solve costs its failed call, as in Python. Prints one JSON line: the checkpoint count, the
//! failures and the mean time per call of every repetition, in milliseconds.

use hsid_host::model::Element;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use hsid_host::identify::solve_checkpoint;

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(
        args.next()
            .ok_or("usage: checkpoint_solve_time DIR [REPS]")?,
    );
    let reps: usize = match args.next() {
        Some(s) => s.parse().map_err(|_| format!("REPS: not a count: {s}"))?,
        None => 5,
    };
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    paths.sort();
    let blobs: Vec<Vec<u8>> = paths
        .iter()
        .map(|p| std::fs::read(p).map_err(|e| format!("{}: {e}", p.display())))
        .collect::<Result<_, _>>()?;
    if blobs.is_empty() || reps == 0 {
        return Err(format!("{}: no checkpoint, or REPS = 0", dir.display()));
    }
    let mut failed = 0;
    let mut per_call_ms = Vec::with_capacity(reps);
    for _ in 0..reps {
        failed = 0;
        let start = Instant::now();
        for b in &blobs {
            match solve_checkpoint(b) {
                Ok(s) => {
                    let kind = s.shared_knots.then_some(Element::Static);
                    std::hint::black_box(s.model.to_json(kind));
                }
                Err(e) => {
                    std::hint::black_box(e);
                    failed += 1;
                }
            }
        }
        per_call_ms.push(1e3 * start.elapsed().as_secs_f64() / blobs.len() as f64);
    }
    let line = serde_json::json!({
        "checkpoints": blobs.len(),
        "failed": failed,
        "per_call_ms": per_call_ms,
    });
    println!("{line}");
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("checkpoint_solve_time: {e}");
            ExitCode::FAILURE
        }
    }
}
