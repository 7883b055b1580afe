//! On glibc, `hsid` runs with glibc's mmap threshold fixed (`MALLOC_MMAP_THRESHOLD_`, set by the
//! command running itself again once when it is unset) and keeps a value the user sets. Read
//! from the running process's environment (`/proc/PID/environ`) while it waits on its
//! standard input: the same process the caller started (`exec` keeps its id).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Write as _;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common;

/// The value of `MALLOC_MMAP_THRESHOLD_` in the environment of `hsid simulate --input -` as it
/// waits on its standard input, the caller's environment set by `set` (`None`: removed).
fn threshold_seen(set: Option<&str>) -> Option<String> {
    let plant = common::servo().with_file_name("servo-backlash.json");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hsid"));
    cmd.args(["simulate", "--plant", common::p(&plant), "--input", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    match set {
        Some(v) => cmd.env("MALLOC_MMAP_THRESHOLD_", v),
        None => cmd.env_remove("MALLOC_MMAP_THRESHOLD_"),
    };
    let mut child = cmd.spawn().unwrap();
    let environ = format!("/proc/{}/environ", child.id());
    // The command runs itself again at once; until then its environment is the caller's.
    let start = Instant::now();
    let seen = loop {
        let text = std::fs::read(&environ).unwrap_or_default();
        let value = text
            .split(|&b| b == 0)
            .filter_map(|kv| kv.strip_prefix(b"MALLOC_MMAP_THRESHOLD_="))
            .map(|v| String::from_utf8_lossy(v).into_owned())
            .next();
        if value.is_some() || start.elapsed() > Duration::from_secs(5) {
            break value;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stdin = child.stdin.take().unwrap();
    let input: String = (0..200)
        .map(|t| format!("{}\n", (t as f64 / 20.0).sin()))
        .collect();
    stdin.write_all(format!("u\n{input}").as_bytes()).unwrap();
    drop(stdin);
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    seen
}

#[test]
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn the_command_fixes_the_mmap_threshold_and_keeps_the_users() {
    assert_eq!(threshold_seen(None).as_deref(), Some("262144"));
    assert_eq!(threshold_seen(Some("1048576")).as_deref(), Some("1048576"));
}
