//! `diagnose` on closed-loop records with the controller's reference logged: the base model
//! (and every refit) is the closed-loop consistent estimate, whose poles the feedback does
//! not bias, and the feedback warning says so.

#![allow(clippy::unwrap_used)]

use crate::common;

use common::servo_poles::{true_pole, upper_pole};
use hsid_host::closed_loop::{ReferenceError, ServoSpec, simulate_servo};
use hsid_host::diagnose::{
    Check, DiagnoseError, DiagnoseOptions, Diagnosis, Estimator, Validation, diagnose,
};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model::{Element, Record};

const SEEDS: u64 = 10;

fn options(spec: &ServoSpec) -> DiagnoseOptions {
    let mut id = IdentifyOptions::uniform(-3.0, 3.0, spec.knots.len() - 1, spec.hold);
    id.order = Some(2);
    let mut opts = DiagnoseOptions::new(id, Element::Backlash);
    // The base model only (the loop's steps on 20000 samples take minutes per record); the
    // steps refit through the same estimator (the command-line test takes one).
    opts.max_steps = 0;
    opts
}

/// `|mean(p̂ − p)|` of the upper poles, as a complex number.
fn pole_bias(poles: &[(f64, f64)]) -> f64 {
    let (t, n) = (true_pole(), poles.len() as f64);
    let re = poles.iter().map(|p| p.0 - t.0).sum::<f64>() / n;
    let im = poles.iter().map(|p| p.1 - t.1).sum::<f64>() / n;
    re.hypot(im)
}

/// The diagnosis of seed `seed`'s record, with its reference or without, validated on a
/// separate record (another seed).
fn diagnosis(spec: &ServoSpec, seed: u64, with_reference: bool) -> Diagnosis {
    let s = simulate_servo(spec, 100 + seed).unwrap();
    let v = simulate_servo(spec, 1000 + seed).unwrap();
    let record = if with_reference {
        Record::new(s.u, s.y).unwrap().with_reference(s.r).unwrap()
    } else {
        Record::new(s.u, s.y).unwrap()
    };
    let validation = Validation::Separate {
        record: Record::new(v.u, v.y).unwrap(),
        skip: spec.hold,
    };
    diagnose(&record, &validation, &options(spec)).unwrap()
}

fn feedback_message(d: &Diagnosis) -> Option<&str> {
    d.warnings
        .iter()
        .find(|w| w.check == Check::Feedback)
        .map(|w| w.message.as_str())
}

#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: Monte Carlo over seeds, about 4 min"]
fn with_the_reference_the_base_model_is_not_biased_by_the_feedback() {
    let spec = ServoSpec::coloured();
    let (mut open, mut closed, mut closed_final) = (Vec::new(), Vec::new(), Vec::new());
    let (mut fired_open, mut fired_closed) = (0, 0);
    for seed in 0..SEEDS {
        let start = std::time::Instant::now();
        let (o, c) = (diagnosis(&spec, seed, false), diagnosis(&spec, seed, true));
        assert_eq!(o.estimator, Estimator::OpenLoop);
        assert_eq!(c.estimator, Estimator::Reference);
        let steps: Vec<&str> = c.steps.iter().map(|s| s.effect.name()).collect();
        eprintln!(
            "seed {seed} ({:.0} s): open-loop base pole {:?}, reference base pole {:?}, final {:?} after {steps:?}",
            start.elapsed().as_secs_f64(),
            upper_pole(&o.base.hammerstein),
            upper_pole(&c.base.hammerstein),
            upper_pole(&c.model.hammerstein)
        );
        open.push(upper_pole(&o.base.hammerstein));
        closed.push(upper_pole(&c.base.hammerstein));
        closed_final.push(upper_pole(&c.model.hammerstein));
        if let Some(m) = feedback_message(&o) {
            fired_open += 1;
            assert!(m.contains("hsid identify --reference-column NAME"), "{m}");
        }
        if let Some(m) = feedback_message(&c) {
            fired_closed += 1;
            assert!(m.contains("closed-loop-consistent estimate"), "{m}");
            assert!(!m.contains("--reference-column NAME"), "{m}");
        }
    }
    let (bo, bc, bf) = (
        pole_bias(&open),
        pole_bias(&closed),
        pole_bias(&closed_final),
    );
    eprintln!(
        "|mean pole bias| over {SEEDS} seeds: open-loop diagnosis {bo:.4}, with the reference {bc:.4} (final model {bf:.4}); feedback warning: open {fired_open}/{SEEDS}, reference {fired_closed}/{SEEDS}"
    );
    assert!(bc <= 0.01, "reference base model bias {bc}");
    assert!(bc < bo, "reference {bc} not below open loop {bo}");
    assert!(bf <= 0.01, "reference final model bias {bf}");
    assert!(fired_open >= 8 && fired_closed >= 8);
}

#[test]
fn a_bad_reference_is_a_typed_error() {
    let spec = ServoSpec::paper();
    let s = simulate_servo(&spec, 1).unwrap();
    let n = s.u.len();
    let run = |r: Vec<f64>, opts: &DiagnoseOptions| {
        // Set directly: the record's fields are public, so the diagnosis checks them itself.
        let mut record = Record::new(s.u.clone(), s.y.clone()).unwrap();
        record.reference = Some(r);
        diagnose(&record, &Validation::Split(0.7), opts).err()
    };
    let opts = options(&spec);
    let short = run(s.r[..n - 1].to_vec(), &opts);
    assert!(
        matches!(
            short,
            Some(DiagnoseError::Reference(ReferenceError::LengthMismatch { r, .. })) if r == n - 1
        ),
        "{short:?}"
    );
    // Made through `with_reference`, such a record is refused with the same error.
    let refused = Record::new(s.u.clone(), s.y.clone())
        .unwrap()
        .with_reference(s.r[..n - 1].to_vec())
        .map_err(DiagnoseError::from)
        .err();
    assert!(
        matches!(
            refused,
            Some(DiagnoseError::Reference(ReferenceError::LengthMismatch { r, .. })) if r == n - 1
        ),
        "{refused:?}"
    );
    let constant = run(vec![0.5; n], &opts);
    assert!(
        matches!(
            constant,
            Some(DiagnoseError::Reference(ReferenceError::ConstantReference))
        ),
        "{constant:?}"
    );
    let mut nan = s.r.clone();
    nan[7] = f64::NAN;
    let nan = run(nan, &opts);
    assert!(
        matches!(
            nan,
            Some(DiagnoseError::Reference(
                ReferenceError::NonFiniteReference { at: 7 }
            ))
        ),
        "{nan:?}"
    );
    let mut stat = opts.clone();
    stat.nonlinearity = Element::Static;
    let stat = run(s.r.clone(), &stat);
    assert!(
        matches!(
            stat,
            Some(DiagnoseError::Reference(ReferenceError::StaticElement))
        ),
        "{stat:?}"
    );
    assert!(
        stat.unwrap()
            .to_string()
            .contains("not --nonlinearity static")
    );
}
