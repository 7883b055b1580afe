//! Ctrl-C and SIGTERM: the command stops at once, removes the outputs it has in progress
//! (their temporary files and staging folders, [`hsid_host::io::abandon`]) and exits with 128
//! plus the signal's number — 130 for SIGINT, 143 for SIGTERM — as a shell expects. An output
//! already renamed into place before the signal is whole; none is left half written, and a
//! file the run would have replaced keeps its previous content.

use std::io::Write;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Starts the thread that waits for SIGINT and SIGTERM.
pub fn install() -> std::io::Result<()> {
    let mut signals = Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("hsid-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                stop(signal);
            }
        })?;
    Ok(())
}

/// Removes the outputs in progress, says why the command stopped and exits.
fn stop(signal: i32) -> ! {
    hsid_host::io::abandon();
    let name = match signal {
        SIGINT => "SIGINT (Ctrl-C)",
        SIGTERM => "SIGTERM",
        _ => "a signal",
    };
    let _ = writeln!(
        std::io::stderr(),
        "hsid: stopped by {name}; outputs written before it are whole, none is left half written"
    );
    std::process::exit(128 + signal)
}
