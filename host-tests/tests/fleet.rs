//! A small simulated fleet, every device with one damaged checkpoint: each damage is reported
//! with its typed kind on its device, the batch completes, and the result does not depend on
//! the number of threads.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use hsid_host::fleet::simulate::{Damage, FleetSpec, file_name};
use hsid_host::fleet::solve::{FleetError, FleetSettings, solve_dir, solve_one};
use hsid_host::fleet::write::write_fleet;

fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hsid-fleet-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn damaged_checkpoints_cost_their_device_only() {
    let root = fresh_dir("damage");
    let states = root.join("states");
    let spec = FleetSpec {
        samples: 1000,
        damage_every: 1,
        ..FleetSpec::standard(8, 4)
    };
    let truths = write_fleet(&spec, &states, &root.join("truth.csv"), Some(2)).unwrap();
    // An entry that cannot be read: a link to nowhere.
    #[cfg(unix)]
    std::os::unix::fs::symlink(root.join("nowhere"), states.join("zz-broken.bin")).unwrap();

    // The fleet's settings from a device's intact checkpoint.
    let t0 = &truths[0];
    let intact = (0..spec.weeks)
        .find(|w| t0.damaged.map(|d| d.0) != Some(*w))
        .unwrap();
    let reference = std::fs::read(states.join(file_name(0, intact))).unwrap();
    let fleet = FleetSettings::of(&solve_one("ref", &reference, None).outcome.unwrap());

    let one = solve_dir(&states, Some(&fleet), Some(1)).unwrap();
    let two = solve_dir(&states, Some(&fleet), Some(2)).unwrap();
    assert_eq!(one, two);
    assert_eq!(
        one.len(),
        spec.devices * spec.weeks + usize::from(cfg!(unix))
    );
    let mut seen = Vec::new();
    for t in &truths {
        let (week, damage) = t.damaged.unwrap();
        let id = file_name(t.index, week);
        let r = one.iter().find(|r| r.device == id).unwrap();
        let kind = r.outcome.as_ref().err().map(|e| e.kind());
        let expected = match damage {
            Damage::Truncated => "checkpoint_truncated",
            Damage::Corrupted => "checkpoint_checksum",
            Damage::ForeignSettings => "foreign_settings",
            Damage::NotACheckpoint => "not_a_checkpoint",
            Damage::None => unreachable!(),
        };
        assert_eq!(kind, Some(expected), "{id}");
        seen.push(expected);
    }
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), 4, "every kind of damage occurs");
    if cfg!(unix) {
        let broken = one.last().unwrap();
        assert_eq!(broken.device, "zz-broken.bin");
        assert_eq!(
            broken.outcome.as_ref().err().map(|e| e.kind()),
            Some("unreadable")
        );
        let line = broken.to_json();
        assert_eq!(line["error"]["kind"], "unreadable");
    }
    // Intact checkpoints of the fleet's settings solve (or fail in the identification only).
    let intact_ok = one.iter().filter(|r| r.outcome.is_ok()).count();
    assert!(
        intact_ok >= spec.devices * (spec.weeks - 1) * 3 / 4,
        "{intact_ok} models"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn zero_threads_and_a_missing_directory_stop_the_batch_with_a_typed_error() {
    let missing = fresh_dir("missing");
    assert!(matches!(
        solve_dir(&missing, None, Some(1)),
        Err(FleetError::Directory { .. })
    ));
    std::fs::create_dir_all(&missing).unwrap();
    assert!(matches!(
        solve_dir(&missing, None, Some(0)),
        Err(FleetError::ZeroThreads)
    ));
    assert_eq!(solve_dir(&missing, None, Some(1)).unwrap(), vec![]);
    std::fs::remove_dir_all(&missing).unwrap();
}

#[test]
fn a_file_larger_than_any_checkpoint_is_refused_unread() {
    use hsid_host::fleet::solve::MAX_CHECKPOINT_BYTES;
    let dir = fresh_dir("large");
    std::fs::create_dir_all(&dir).unwrap();
    // A sparse file one byte over the limit: refused by its size, not read.
    let big = std::fs::File::create(dir.join("big.bin")).unwrap();
    big.set_len(MAX_CHECKPOINT_BYTES as u64 + 1).unwrap();
    std::fs::write(dir.join("small.bin"), b"not a checkpoint").unwrap();
    let r = solve_dir(&dir, None, Some(1)).unwrap();
    let kinds: Vec<_> = r
        .iter()
        .map(|r| {
            (
                r.device.as_str(),
                r.outcome.as_ref().err().map(|e| e.kind()),
            )
        })
        .collect();
    assert_eq!(
        kinds,
        [
            ("big.bin", Some("file_too_large")),
            ("small.bin", Some("not_a_checkpoint"))
        ]
    );
    let message = r[0].outcome.as_ref().unwrap_err().to_string();
    assert!(
        message.contains(&format!("{} bytes", MAX_CHECKPOINT_BYTES + 1)),
        "{message}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn results_come_in_the_listing_order_across_chunks_and_a_failing_output_stops_the_batch() {
    use hsid_host::fleet::solve::solve_dir_each;
    let dir = fresh_dir("chunks");
    std::fs::create_dir_all(&dir).unwrap();
    // More files than one chunk of two threads holds (2 × 64).
    let n = 300;
    for i in 0..n {
        std::fs::write(dir.join(format!("d{i:04}.bin")), format!("device {i}")).unwrap();
    }
    let mut seen = Vec::new();
    let count = solve_dir_each(&dir, None, Some(2), &mut |r| {
        assert_eq!(
            r.outcome.as_ref().err().map(|e| e.kind()),
            Some("not_a_checkpoint")
        );
        seen.push(r.device);
        Ok(())
    })
    .unwrap();
    assert_eq!((count.devices, count.failed), (n, n));
    let expected: Vec<String> = (0..n).map(|i| format!("d{i:04}.bin")).collect();
    assert_eq!(seen, expected);

    let mut written = 0;
    let stopped = solve_dir_each(&dir, None, Some(2), &mut |_| {
        written += 1;
        if written == 5 {
            Err(std::io::Error::other("disk full"))
        } else {
            Ok(())
        }
    });
    assert!(
        matches!(&stopped, Err(FleetError::Output(e)) if e.contains("disk full")),
        "{stopped:?}"
    );
    assert_eq!(written, 5);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_cli_writes_one_line_per_device_and_no_file_when_the_batch_cannot_start() {
    use std::process::Command;
    let root = fresh_dir("cli");
    let states = root.join("states");
    std::fs::create_dir_all(&states).unwrap();
    std::fs::write(states.join("a.bin"), b"junk").unwrap();
    std::fs::write(states.join("b.bin"), b"more junk").unwrap();
    let out = root.join("models.jsonl");
    let run = |states: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_hsid"))
            .args(["fleet", "--threads", "2", "--states"])
            .arg(states)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    let ok = run(&states);
    assert!(ok.status.success(), "{ok:?}");
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["device"], "a.bin");
    assert_eq!(lines[1]["error"]["kind"], "not_a_checkpoint");
    assert!(String::from_utf8_lossy(&ok.stdout).contains("2 devices: 0 models, 2 errors"));

    std::fs::remove_file(&out).unwrap();
    let missing = run(&root.join("nowhere"));
    assert!(!missing.status.success());
    let err = String::from_utf8_lossy(&missing.stderr);
    assert!(
        err.contains("nowhere") && err.contains("cannot list"),
        "{err}"
    );
    assert!(
        !out.exists(),
        "a batch that could not start wrote {}",
        out.display()
    );
    std::fs::remove_dir_all(&root).unwrap();
}
