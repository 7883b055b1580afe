//! One verdict on the data: the persistent-excitation check measures the exact Hankel Gram
//! (its rank is bounded by an input's period, a fact independent of the code), passes the
//! tour's record at the horizons `identify` chose itself, and the terminal of `identify` and
//! `diagnose` and the HTML page say the same.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{Scratch, hsid, p, servo, servo_args};
use hsid_host::identify::IdentifyOptions;
use hsid_host::io::read_columns;
use hsid_host::model::Element;
use hsid_host::validation::{Check, Warning, data_checks};

/// The servo record's `(u, y)`.
fn servo_record() -> (Vec<f64>, Vec<f64>) {
    let mut cols = read_columns(servo(), &["u", "y"]).unwrap();
    let y = cols.pop().unwrap();
    (cols.pop().unwrap(), y)
}

/// The tour's structure: 7 uniform segments per path on [-1, 1], hold 300, `f = p = h`.
fn options(h: usize) -> IdentifyOptions {
    let mut opts = IdentifyOptions::uniform(-1.0, 1.0, 7, 300);
    (opts.f, opts.p) = (h, h);
    opts
}

fn excitation(warnings: &[Warning]) -> Option<&Warning> {
    warnings
        .iter()
        .find(|w| w.check == Check::PersistentExcitation)
}

/// The number after `key` in `text`.
fn number(text: &str, key: &str) -> usize {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {text}"));
    let rest = &text[at + key.len()..];
    let end = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    rest[..end].parse().unwrap()
}

/// An input that repeats every `P` samples after the hold has stacked regressors
/// `φ(t + P) = φ(t)` from its second sample on (the first one's direction comes from before
/// the repetition): its Hankel Gram has rank at most `P + 1`, below the `(f + p)·m = 560` rows
/// of `f = p = 20` with 14 channels. The check fires and reports a rank within that bound.
#[test]
fn a_periodic_input_is_not_persistently_exciting_beyond_its_period() {
    const P: usize = 150;
    let (u, y) = servo_record();
    let mut periodic = u[..300].to_vec();
    while periodic.len() < u.len() {
        let at = 300 + (periodic.len() - 300) % P;
        periodic.push(u[at]);
    }
    let warnings = data_checks(&periodic, &y, &options(20), Element::Backlash);
    let w = excitation(&warnings).expect("the check fires on a periodic input");
    assert!(
        w.message.contains("of order (f+p)·m = 560"),
        "{}",
        w.message
    );
    let rank = number(&w.message, "numerical rank ");
    assert!(
        rank <= P + 1,
        "rank {rank} above the period {P} + 1: {}",
        w.message
    );
    assert!(rank > P / 2, "rank {rank}: {}", w.message);
    // The same record, not repeated, excites every direction at those horizons.
    let warnings = data_checks(&u, &y, &options(20), Element::Backlash);
    assert!(excitation(&warnings).is_none(), "{warnings:?}");
}

/// The horizons `identify` chooses on the tour's record (`f = p = 39`, 1,092 rows) pass the
/// check: the model there is at the noise floor (`quick_start`), so a warning would be false.
#[test]
fn the_tours_chosen_horizons_pass_the_excitation_check() {
    let (u, y) = servo_record();
    let warnings = data_checks(&u, &y, &options(39), Element::Backlash);
    assert!(excitation(&warnings).is_none(), "{warnings:?}");
}

/// `identify` prints the data checks the page shows, and `diagnose` prints them in the same
/// words.
#[test]
fn identify_diagnose_and_the_page_give_one_verdict() {
    let dir = Scratch::new("one-verdict");
    let html = dir.join("servo.html");
    let out = hsid(&servo_args(
        "identify",
        &["--ts", "0.01", "--html", p(&html)],
    ))
    .success();
    let line = out
        .stdout
        .lines()
        .find(|l| l.starts_with("data checks: "))
        .unwrap_or_else(|| panic!("no data checks line:\n{}", out.stdout));
    assert!(
        line.starts_with("data checks: all 7 passed, the data meet the method's assumptions"),
        "{line}"
    );
    assert!(line.contains("persistent_excitation"), "{line}");
    let page = std::fs::read_to_string(&html).unwrap();
    let row = page
        .lines()
        .find(|l| l.contains("data: persistent_excitation"))
        .expect("the page has the excitation row");
    assert!(
        row.contains("<td>no</td>") && row.contains("passed"),
        "{row}"
    );
    assert!(
        !page.contains("class=\"fired\"><td>data: "),
        "a data check fired"
    );

    let diagnosed = hsid(&servo_args("diagnose", &["--ts", "0.01"])).success();
    let line = diagnosed
        .stdout
        .lines()
        .find(|l| l.starts_with("data checks: "))
        .unwrap_or_else(|| panic!("no data checks line:\n{}", diagnosed.stdout));
    // diagnose runs two more checks (feedback, integrating), in the same words.
    assert!(
        line.starts_with("data checks: all 9 passed, the data meet the method's assumptions")
            || line.contains(" of 9 passed"),
        "{line}"
    );
}
