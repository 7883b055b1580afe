//! Long calls that Ctrl-C stops. The work runs on a thread of its own; the calling thread
//! waits for it without the GIL and checks Python's signals every [`POLL`]. On a
//! `KeyboardInterrupt` (Ctrl-C, a Jupyter kernel interrupt) the call raises it at once and
//! tells the work to stop: the work ends at its next stage
//! ([`hsid_host::progress::Reporter::stopped`]) and its result is dropped.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use hsid_host::progress::{Reporter, reporting};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread checks Python's signals.
const POLL: Duration = Duration::from_millis(50);

/// The work's reporter: says nothing, stops when told.
struct Stop(Arc<AtomicBool>);

impl Reporter for Stop {
    fn stage(&self, _: &str) {}

    fn stopped(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Runs `work` on a thread of its own; raises `KeyboardInterrupt` (or what a signal handler
/// raised) within [`POLL`] of a signal, without waiting for the work.
pub fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::sync_channel(1);
    let flag = stop.clone();
    std::thread::Builder::new()
        .name("hsid-work".into())
        .spawn(move || {
            let out = reporting(Arc::new(Stop(flag)), work);
            // The caller may have gone (interrupted): the result is dropped.
            let _ = tx.send(out);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("hsid: cannot start a thread: {e}")))?;
    let mut rx = rx;
    loop {
        // The receiver goes into the closure and back: a shared one is not `Sync`.
        let (got, back) = py.detach(move || (rx.recv_timeout(POLL), rx));
        rx = back;
        match got {
            Ok(out) => return Ok(out),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "hsid: the identification stopped without a result (a panic: please \
                     report it with the data)",
                ));
            }
        }
        if let Err(e) = py.check_signals() {
            stop.store(true, Ordering::Relaxed);
            return Err(e);
        }
    }
}
