//! `hsid diagnose` on measured data (issue 5, part 3), read from `../shared/data/` (never
//! copied into the project): the cascaded tanks benchmark and the DC motor with a dead zone.
//! The numbers checked are those of docs/closing-the-loop.md.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid_host::diagnose::verdict::End;
use hsid_host::diagnose::{
    Check, DiagnoseOptions, Effect, Evidence, Finding, Test, Tried, Validation, diagnose,
};
use hsid_host::identify::IdentifyOptions;
use hsid_host::io::read_columns;
use hsid_host::model::Element;
use hsid_host::model::Record;

const TANKS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/cascaded-tanks/dataBenchmark.csv"
);
const MOTOR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/dc-motor-deadzone/run_minimal.csv"
);

#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: cross-validated search over segment counts on the measured tanks, about 4 min"]
fn cascaded_tanks_level_dependent_stores_chosen_by_cross_validation_reach_the_goal() {
    let c = read_columns(TANKS, &["uEst", "yEst", "uVal", "yVal"]).unwrap();
    let (lo, hi) = c[0]
        .iter()
        .chain(&c[2])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let mut id = IdentifyOptions::uniform(lo, hi, 7, 0);
    id.order = Some(2);
    let mut opts = DiagnoseOptions::new(id, Element::Static);
    opts.select_segments = Some(3..=8);
    let d = diagnose(
        &Record::new(c[0].clone(), c[1].clone()).unwrap(),
        &Validation::Separate {
            record: Record::new(c[2].clone(), c[3].clone()).unwrap(),
            skip: 0,
        },
        &opts,
    )
    .unwrap();
    println!("{}", hsid_host::diagnose::report::text(&d));
    // Better than the best linear approximation of the benchmark (0.75 V).
    assert!(d.before.rmse < 0.70, "base {}", d.before.rmse);
    // The overflow is seen by the data checks, and the missing hold.
    for check in [Check::OutputSaturation, Check::Hold] {
        assert!(d.warnings.iter().any(|w| w.check == check), "{check}");
    }
    // The last 30 % cannot be scored, so the settings are chosen by leave-block-out
    // cross-validation inside the estimation record.
    assert!(d.inner.folds.len() > 1, "{}", d.data_description);
    // The square-root outflows and the overflow of the upper tank, seen by state_dependence,
    // are the first effect added: level-dependent stores, which take the validation error to
    // the goal of 0.45 V or below.
    let first = d.steps.first().expect("an effect is added");
    assert_eq!(first.effect, Effect::StateDependentDynamics);
    assert!(
        first
            .evidence
            .iter()
            .any(|e| matches!(e, Evidence::Test(t) if t.name == Test::StateDependence)),
        "{:?}",
        first.evidence
    );
    let stores = first.model.stores.as_ref().expect("stores");
    // The measured (lower) tank drains slower than linearly in its level, towards a square
    // root.
    assert!(stores.alpha[1] < 1.0, "{stores:?}");
    assert!(first.error_after <= 0.45, "after {}", first.error_after);
    assert!(d.after.rmse <= 0.45, "{} → {}", d.before.rmse, d.after.rmse);
    // What the stores leave is still named.
    assert!(
        d.unexplained
            .contains(&Finding::StateDependenceBeyondStores),
        "{:?}",
        d.unexplained
    );
}

#[test]
fn dc_motor_dead_zone_gains_and_time_constant() {
    let c = read_columns(MOTOR, &["voltage", "rpm"]).unwrap();
    let top = c[0].iter().fold(0.0f64, |a, &v| a.max(v));
    let knots = vec![-top, -8.0, -6.0, -4.0, -2.0, 0.0, 2.0, 4.0, top];
    let mut id = IdentifyOptions::uniform(-top, top, 8, 0);
    id.knots_asc = knots.clone();
    id.knots_desc = knots.clone();
    id.order = Some(1);
    let opts = DiagnoseOptions::new(id, Element::Static);
    let d = diagnose(
        &Record::new(c[0].clone(), c[1].clone()).unwrap(),
        &Validation::Holdout(3900..4500),
        &opts,
    )
    .unwrap();
    println!("{}", hsid_host::diagnose::report::text(&d));
    let m = &d.base.hammerstein;
    let h = |u: f64| m.border_asc_at(u);
    // Dead zone: no speed for |u| <= 2 V.
    for u in [-2.0, -1.0, 0.0, 1.0, 2.0] {
        assert!(h(u).abs() < 3.0, "H({u}) = {}", h(u));
    }
    // Steady speeds (G(1) = 1, so the border is the steady speed) against the known values.
    for (u, known, tol) in [
        (4.0, 74.5, 0.06),
        (top, 228.6, 0.06),
        (-4.0, -88.7, 0.10),
        (-top, -239.9, 0.03),
    ] {
        assert!(
            (h(u) - known).abs() <= tol * known.abs(),
            "H({u}) = {} against {known}",
            h(u)
        );
    }
    // Polarity asymmetry: the negative side is faster at the same voltage.
    assert!(-h(-4.0) > h(4.0) && -h(-top) > h(top));
    // First-order time constant 0.28–0.30 s at 0.01 s sampling.
    let pole = m.poles()[0].0;
    let tau = -0.01 / pole.ln();
    assert!((0.26..=0.32).contains(&tau), "tau {tau}");
    // The held-out 6 V and 8 V levels (interpolated between the 4 V and 8.81 V knots).
    assert!(d.before.rmse < 10.0, "validation RMSE {}", d.before.rmse);
    // The dead time: the ARX test finds the first response at lag 4 (the zero-order hold's
    // sample plus the known 0.03 s = 3 samples of transport delay); the base model responds at
    // lag 0 (direct term), so the input-delay extension shifts the input by 4 samples. The
    // inner hold-out block (mostly the dead zone and one step) has no power for it (MSE +4 %,
    // p = 0.74); scored like the test that found it, over the whole estimation record by
    // cross-validation, it is significantly better and is added.
    assert_eq!(d.dead_time.lag, Some(4), "{:?}", d.dead_time);
    let delay = d
        .steps
        .iter()
        .find(|s| s.effect == Effect::InputDelay)
        .expect("input delay added");
    assert_eq!(delay.model.structure.delay, d.dead_time.extra());
    assert!(delay.inner_p < 0.01 && delay.inner_gain > 0.0, "{delay:?}");
    assert!(delay.error_after < delay.error_before);
    // The play operator on the voltage is added first (its inner hold-out MSE −55 %): it
    // represents part of the coasting down when the drive returns to 0, and lowers the
    // validation error from 8.08 rpm (the input delay alone) to 7.55.
    assert_eq!(d.steps.first().map(|s| s.effect), Some(Effect::Hysteresis));
    assert!(
        (d.after.rmse - 7.553).abs() < 0.005,
        "validation RMSE after {}",
        d.after.rmse
    );
    // One input_delay candidate: the dead-time test's delay replaces the screen's, whose
    // settings stay listed as tried; the dead-time delay was scored on several blocks.
    assert!(
        delay
            .competitors
            .iter()
            .all(|(e, _, _)| *e != Effect::InputDelay),
        "{:?}",
        delay.competitors
    );
    assert!(
        delay.tried.iter().any(|t| matches!(t, Tried::DeadTime { delay, blocks, .. } if *delay == d.dead_time.extra() && *blocks > 1))
            && delay.tried.len() >= 2,
        "{:?}",
        delay.tried
    );
    // The rest of the coast-down (direction dependence beyond the play operator) and the
    // quantisation are reported as found but not in the catalog.
    let found: Vec<&Finding> = d
        .unexplained
        .iter()
        .filter(|u| u.outside_catalog())
        .collect();
    assert!(
        found.contains(&&Finding::DirectionDependenceBeyondElement),
        "{found:?}"
    );
    assert!(found.contains(&&Finding::Quantised), "{found:?}");
    // The verdict names them as found outside the catalog (after the effects added), not as
    // tests no effect explains.
    for f in [
        Finding::DirectionDependenceBeyondElement,
        Finding::Quantised,
    ] {
        assert!(d.verdict.outside.contains(&f), "{:?}", d.verdict);
    }
    assert!(
        d.verdict.added.contains(&Effect::InputDelay)
            && !matches!(
                d.verdict.end,
                End::Unscorable | End::Consistent | End::NotIdentified
            ),
        "{:?}",
        d.verdict
    );
    // Quantisation and the staircase input are reported by the data checks.
    for check in [Check::OutputQuantisation, Check::InputLevels] {
        assert!(d.warnings.iter().any(|w| w.check == check), "{check}");
    }
}
