//! A stable start: on the EMPS positioning drive (measured in closed loop, force → position:
//! it integrates), the subspace estimate of the increments' stable part has a pole outside the
//! unit circle. It used to be refused ("a pole of modulus 1.0012 >= 1"); the refinement now
//! starts from the poles reflected inside and gives a stable model, with a note, and the
//! model reported (that one or the linear baseline, whichever simulates the held-out part of
//! the record better) simulates the test record's increments. Read from `../shared/data/` (the benchmark's own
//! files; never copied into the project).

#![allow(clippy::unwrap_used)]

use crate::common;

use common::nrmse;
use hsid_host::io::read_columns;
use hsid_host::model::Record;
use hsid_host::numerics::poly::{spectral_radius, tf_from_ss};
use hsid_host::workflow::{IdentifyRequest, Syntax, identify_record};

use common::{EMPS_TEST as TEST, EMPS_TRAIN as TRAIN};

#[test]
fn emps_increments_get_a_stable_model_from_a_reflected_start() {
    let c = read_columns(TRAIN, &["vir", "qm"]).unwrap();
    let (u, y) = (c[0].clone(), c[1].clone());
    let lo = u.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = u.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut request = IdentifyRequest::new(lo, hi, Syntax::Cli);
    request.integrating = true;
    request.order = Some(2);
    let id = identify_record(&Record::new(u, y).unwrap(), &request).unwrap();
    let lines = id.lines().unwrap();
    // The backlash model's subspace estimate had a pole outside the unit circle (modulus
    // 1.00…) and was refined from the reflected start; the linear baseline beside it
    // simulates the held-out part of the record better and is the model reported.
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("stable start: the subspace model had a pole of modulus 1.")),
        "{lines:#?}"
    );
    assert!(
        lines.iter().any(|l| l.starts_with("linear OE: fit")),
        "{lines:#?}"
    );
    let m = &id.estimate.model;
    let (_, den) = tf_from_ss(&m.a, &m.b, &m.c, m.d);
    assert!(spectral_radius(&den) < 1.0);
    // The test record's increments, simulated from its input (inside the identified interval).
    let t = read_columns(TEST, &["vir", "qm"]).unwrap();
    let uv: Vec<f64> = t[0][1..].iter().map(|v| v.clamp(lo, hi)).collect();
    let dy: Vec<f64> = t[1].windows(2).map(|w| w[1] - w[0]).collect();
    let fit = nrmse(&dy, &m.simulate(&uv));
    eprintln!("test record increments: NRMSE {fit:.4}");
    assert!(fit < 0.35, "NRMSE {fit:.4}");
}
