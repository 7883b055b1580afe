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
