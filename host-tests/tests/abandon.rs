//! `io::abandon`, what the command line's signal thread calls before it exits: it removes the
//! temporary files and staging folders of the outputs in progress, leaves every finished
//! output and every previous file alone, and no output starts or is renamed into place after
//! it. One test in a binary of its own: `abandon` keeps the registry locked until the process
//! ends.
#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use std::fs;
use std::io::Write;
use std::time::Duration;

use common::Scratch;
use hsid_host::io::{AtomicFile, StagedDir, abandon, in_progress, write_atomic};

#[test]
fn abandon_removes_the_outputs_in_progress_and_nothing_else() {
    let dir = Scratch::new("abandon");
    let base = dir.join("");
    fs::write(dir.join("m.json"), "previous").unwrap();
    let mut file = AtomicFile::create(dir.join("m.json")).unwrap();
    file.write_all(b"half of the new model").unwrap();
    file.flush().unwrap();
    let stage = StagedDir::create(dir.join("fig")).unwrap();
    write_atomic(stage.path().join("a.svg"), "new figure").unwrap();
    write_atomic(dir.join("done.json"), "whole").unwrap();
    let names = |d: &std::path::Path| {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&base).len(), 4, "{:?}", names(&base));
    assert_eq!(names(&dir.join("fig")).len(), 1);
    // The model's temporary and the staging folder; the figure inside the folder was
    // committed into it and is gone with it.
    assert_eq!(in_progress(), 2);
    assert_eq!(abandon(), 2);
    assert_eq!(names(&base), ["done.json", "fig", "m.json"]);
    assert_eq!(names(&dir.join("fig")), Vec::<String>::new());
    assert_eq!(fs::read_to_string(dir.join("m.json")).unwrap(), "previous");
    // An output that would start now waits for the exit.
    let late = dir.join("late.json");
    let writer = std::thread::spawn(move || write_atomic(late, "late"));
    std::thread::sleep(Duration::from_millis(300));
    assert!(!writer.is_finished());
    assert!(!dir.join("late.json").exists());
    // Their drops would wait for the registry too.
    std::mem::forget(file);
    std::mem::forget(stage);
}
