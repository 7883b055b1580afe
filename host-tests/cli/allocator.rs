//! The allocator's policy for records of a million samples: on glibc, a fixed mmap threshold.
//!
//! glibc serves a request from its heap arenas below a threshold and maps it from the system
//! above it, and it raises that threshold to the size of every mapped block that is freed (up
//! to 32 MiB). After the first record-sized array is freed (the file's text, a simulation),
//! every later one comes from an arena, where a freed block stays resident unless it lies at
//! the arena's top, and each worker thread has an arena of its own. On a 10⁶-sample record
//! the resident size of `hsid identify` was then about twice what it allocated (156 MB for
//! 80 MB). With the threshold fixed (which also turns the raising off) every block above it is
//! mapped and returned to the system when freed: 99 MB.
//!
//! glibc reads the threshold from the environment (`MALLOC_MMAP_THRESHOLD_`) when the process
//! starts, and the project forbids the `unsafe` that `mallopt` would take; so when the variable
//! is not set, the command runs itself again, once, with it set (`exec`: the same process,
//! its arguments, standard streams and signals unchanged). A value the user sets is kept.

/// The threshold in bytes: arrays of a few thousand samples and more are mapped.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const THRESHOLD: &str = "262144";

/// The variable glibc reads.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const VARIABLE: &str = "MALLOC_MMAP_THRESHOLD_";

/// Runs this command again with the threshold set, when it is not; returns only when it is
/// set already, on another platform, or when the command cannot be run again (then it goes
/// on with the allocator's default: the results are the same, the resident size larger).
pub fn tune() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        use std::os::unix::process::CommandExt;
        if std::env::var_os(VARIABLE).is_some() {
            return;
        }
        let Ok(exe) = std::env::current_exe() else {
            return;
        };
        let mut args = std::env::args_os();
        let arg0 = args.next().unwrap_or_else(|| exe.clone().into_os_string());
        // `exec` returns only when it fails.
        let _failed = std::process::Command::new(&exe)
            .arg0(arg0)
            .args(args)
            .env(VARIABLE, THRESHOLD)
            .exec();
    }
}
