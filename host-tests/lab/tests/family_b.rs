//! The second scenario family (`hsid_lab::family_b`): its generator's truths against
//! independent computations, and diagnosis outcomes on a few fixed seeds.

#![allow(clippy::panic)]

use hsid_host::diagnose::{Check, Effect, Validation};
use hsid_host::model;
use hsid_host::validation::checks::feedback::feedback_test;
use hsid_lab::family_b::element::{Borders, Element};
use hsid_lab::family_b::input::InputKind;
use hsid_lab::family_b::noise::{Colour, noise, variance};
use hsid_lab::family_b::plant::{Plant, Section};
use hsid_lab::family_b::rng::Rng;
use hsid_lab::family_b::scenario::HOLD;
use hsid_lab::family_b::{Class, Scenario, generate, run_adjusted, run_one};

/// Every class, seeds 1–4: the realised ratio of the estimation record within 1 dB of the
/// target, the target in 10–40 dB, the declared order (the drawn order cycles through 1–4,
/// plus the integrator), the validation record's noise floor consistent with the ratio.
#[test]
fn generated_records_have_their_drawn_ratio_and_order() {
    for class in Class::ALL {
        let mut orders = Vec::new();
        for seed in 1..=4 {
            let d = generate(&Scenario::new(class, seed));
            let t = &d.truth;
            let target = t.design.snr_db;
            assert!(
                (10.0..=40.0).contains(&target),
                "{class:?} {seed}: {target}"
            );
            assert!(
                (t.snr_realised.0 - target).abs() < 1.0,
                "{class:?} {seed}: realised {:.2} dB, target {target:.2}",
                t.snr_realised.0
            );
            let base = t.design.plant.order();
            orders.push(base);
            let expected = base + usize::from(class == Class::Integrating);
            assert_eq!(t.declared_order, expected, "{class:?} {seed}");
            let Validation::Separate { record, skip } = &d.validation else {
                panic!("a separate validation record")
            };
            assert_eq!((*skip, d.record.len()), (HOLD, HOLD + 3000));
            assert_eq!(record.len(), HOLD + 1500);
            assert!(t.noise_floor > 0.0 && t.innovation_floor <= t.noise_floor * 1.05);
        }
        orders.sort_unstable();
        assert_eq!(orders, [1, 2, 3, 4], "{class:?}");
    }
}

/// The sampled plant against closed forms: a first-order lag is `a = e^{−ts/τ}`,
/// `b = 1 − a`; a complex pair's sampled poles have modulus `e^{−ζω ts}`; a cascade of
/// unit-gain sections has unit static gain; an integrator has a pole at 1.
#[test]
fn sampled_plants_match_closed_forms() {
    let ts = 0.1;
    let lag = Plant {
        sections: vec![Section::Real { tau: 0.5 }],
    }
    .sampled(ts);
    let a = (-ts / 0.5f64).exp();
    assert!((lag.phi[(0, 0)] - a).abs() < 1e-12);
    assert!((lag.gamma[0] - (1.0 - a)).abs() < 1e-12);
    let (omega, zeta) = (4.0, 0.3);
    let plant = Plant {
        sections: vec![Section::Complex { omega, zeta }, Section::Real { tau: 0.3 }],
    };
    let d = plant.sampled(ts);
    let r = (-zeta * omega * ts).exp();
    let moduli = d.pole_moduli();
    assert_eq!(
        moduli.iter().filter(|m| (*m - r).abs() < 1e-9).count(),
        2,
        "{moduli:?}"
    );
    let step = d.simulate(
        &[0.0; 2]
            .iter()
            .chain(&[1.0; 600])
            .copied()
            .collect::<Vec<_>>(),
    );
    assert!((step[step.len() - 1] - 1.0).abs() < 1e-9);
    let int = Plant {
        sections: vec![Section::Real { tau: 0.3 }, Section::Integrator { k: 0.2 }],
    }
    .sampled(ts);
    assert!(int.pole_moduli().iter().any(|m| (m - 1.0).abs() < 1e-12));
}

/// The elements under Table I follow their borders exactly (the two-path model is exact for
/// them), and under an ordinary input the play operator leaves the borders (inner loops).
#[test]
fn elements_follow_their_borders_under_table1_only() {
    let mut rng = Rng::new(7, 0);
    for (kind, sign) in [
        (model::Element::Backlash, -1.0),
        (model::Element::Switch, 1.0),
    ] {
        let b = Borders::random(&mut rng, (-2.0, 2.5), 8, true, sign);
        let u = InputKind::Table1.generate(&mut rng, (-2.0, 2.5), 10, 2000);
        let mut el = Element::new(kind, b.clone(), u[0]);
        let mut last = u[0];
        for &v in &u {
            let w = el.next(v);
            let border = if v > last { b.asc_at(v) } else { b.desc_at(v) };
            if v != last {
                assert!(
                    (w - border).abs() < 1e-12,
                    "{kind:?} at {v}: {w} vs {border}"
                );
            }
            last = v;
        }
    }
    let b = Borders::random(&mut rng, (-2.0, 2.5), 8, true, -1.0);
    let u = InputKind::Smoothed.generate(&mut rng, (-2.0, 2.5), 10, 2000);
    let mut el = Element::new(model::Element::Backlash, b.clone(), u[0]);
    let off = u
        .iter()
        .filter(|&&v| {
            let w = el.next(v);
            w > b.asc_at(v) + 1e-9 && w < b.desc_at(v) - 1e-9
        })
        .count();
    assert!(
        off > 200,
        "the play is inside its borders on {off} of 2010 samples"
    );
}

/// Coloured noise: the AR(1)'s lag-1 autocorrelation is its coefficient, the MA(2)'s is
/// `(c₁ + c₁c₂)/(1 + c₁² + c₂²)`, and both have the variance asked for.
#[test]
fn coloured_noise_has_its_autocorrelation_and_variance() {
    let lag1 = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let num: f64 = v.windows(2).map(|w| (w[0] - m) * (w[1] - m)).sum();
        num / v.iter().map(|x| (x - m) * (x - m)).sum::<f64>()
    };
    let mut rng = Rng::new(3, 9);
    let (c1, c2) = (0.8, 0.4);
    for (colour, rho) in [
        (Colour::Ar1(0.8), 0.8),
        (
            Colour::Ma2(c1, c2),
            (c1 + c1 * c2) / (1.0 + c1 * c1 + c2 * c2),
        ),
        (Colour::White, 0.0),
    ] {
        let n = noise(&mut rng, colour, 0.5, 40_000);
        assert!(
            (lag1(&n.v) - rho).abs() < 0.03,
            "{colour:?}: {}",
            lag1(&n.v)
        );
        assert!(
            (variance(&n.v).sqrt() / 0.5 - 1.0).abs() < 0.06,
            "{colour:?}"
        );
    }
}

/// The closed loop really has feedback: the Granger test of the diagnosis's feedback check,
/// given the true noise-free output and the true noise, fires on the closed-loop records
/// and not on an open-loop record of the same class of plant.
#[test]
fn closed_loop_records_have_feedback_by_the_check() {
    for seed in 1..=3 {
        let d = generate(&Scenario::new(Class::ClosedLoop, seed));
        let u = &d.record.u[HOLD..];
        let y = &d.record.y[HOLD..];
        let clean = clean_output(&d);
        let resid: Vec<f64> = y.iter().zip(&clean).map(|(a, b)| a - b).collect();
        let Some(t) = feedback_test(u, &clean, &resid) else {
            panic!("seed {seed}: the test could not run")
        };
        assert!(t.fires(), "seed {seed}: {t:?}");
    }
    let d = generate(&Scenario::new(Class::Clean, 4));
    let u = &d.record.u[HOLD..];
    let y = &d.record.y[HOLD..];
    let clean = clean_output(&d);
    let resid: Vec<f64> = y.iter().zip(&clean).map(|(a, b)| a - b).collect();
    let Some(t) = feedback_test(u, &clean, &resid) else {
        panic!("the test could not run")
    };
    assert!(!t.fires(), "open loop: {t:?}");
}

/// The noise-free output of a static-element record, simulated again from its input.
fn clean_output(d: &hsid_lab::family_b::Data) -> Vec<f64> {
    let design = &d.truth.design;
    let mut el = Element::new(design.kind, design.borders.clone(), design.range.0);
    el.next(design.range.0);
    let w: Vec<f64> = d.record.u.iter().map(|&v| el.next(v)).collect();
    design.plant.sampled(design.ts).simulate(&w)[HOLD..].to_vec()
}

/// Diagnosis outcomes that hold today on fixed seeds: nothing added on two clean runs (Table
/// I with a backlash, a multisine on a static element), the delay named first, the settling
/// drift of seed 3 named `offset_drift` (a polynomial fitted without the record's last 30 %
/// did not carry it there), `hysteresis` behind a static model (seed 1; and seed 4, a relay
/// whose fit the pole radius keeps scorable), the saturating output named
/// `output_nonlinearity` with the saturation check, the integrating check on an integrating
/// plant, and the outliers of seed 2 (a dozen spikes in the inner block: the kept model's
/// significance is the heavy-tails test's).
#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: confusion over seeds, about 2 min"]
fn diagnosis_names_these_seeds_right() {
    let cases = [
        (Class::Clean, 1),
        (Class::Clean, 2),
        (Class::Delay, 3),
        (Class::Drift, 3),
        (Class::StaticHysteresis, 1),
        (Class::StaticHysteresis, 4),
        (Class::Saturation, 1),
        (Class::Outliers, 2),
        (Class::Integrating, 2),
    ];
    for (class, seed) in cases {
        let o = run_one(&Scenario::new(class, seed));
        assert!(o.right(), "{}", o.line());
        assert!(o.harmful.is_empty(), "{}", o.line());
        if class == Class::Saturation {
            assert_eq!(o.first(), Some(Effect::OutputNonlinearity));
            assert!(o.fired.contains(&Check::OutputSaturation), "{}", o.line());
        }
    }
}

/// The element must carry its own gain, and no extension may gain by a better fit of the same
/// dynamics: on a static plant whose base model fitted without the inner block (subspace
/// poles) simulates it poorly (clean seed 8: order 4, smoothed input), the relay's gain came
/// from its refit of `G` (its borders collapsed onto their mean lost nothing), and a delay
/// gained 46 % there; with the inner fits' poles refined, nothing is added. A backlash behind a
/// static model whose element fit also improves `G` (static_hysteresis seed 6) is still named
/// first.
#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: confusion over seeds, about 30 s"]
fn hysteresis_is_named_only_for_its_memory() {
    let clean = run_one(&Scenario::new(Class::Clean, 8));
    assert!(clean.error.is_none(), "{}", clean.line());
    assert!(clean.named.is_empty(), "{}", clean.line());
    let element = run_one(&Scenario::new(Class::StaticHysteresis, 6));
    assert_eq!(
        element.first(),
        Some(Effect::Hysteresis),
        "{}",
        element.line()
    );
    assert!(element.harmful.is_empty(), "{}", element.line());
}

/// A declared order the record cannot normalise is lowered, with the `order` warning, and the
/// diagnosis goes on: output_curve seed 4 (order 4, sampled slowly, a smoothed input on a
/// static element) has an order-4 estimate whose static gain is within its own error; from
/// order 3 the output curve is named. Seed 1 of the same class (order 1, Table I on a backlash) keeps
/// its order, without the warning.
#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: about 30 s"]
fn a_declared_order_the_record_cannot_normalise_is_lowered() {
    let lowered = run_one(&Scenario::new(Class::OutputCurve, 4));
    assert!(lowered.error.is_none(), "{}", lowered.line());
    assert!(lowered.fired.contains(&Check::Order), "{}", lowered.line());
    assert_eq!(
        lowered.first(),
        Some(Effect::OutputNonlinearity),
        "{}",
        lowered.line()
    );
    let kept = run_one(&Scenario::new(Class::OutputCurve, 1));
    assert!(kept.error.is_none(), "{}", kept.line());
    assert!(!kept.fired.contains(&Check::Order), "{}", kept.line());
}

/// A run with another minimum gain (the sweep of `confusion_b --min-gain`) uses it: extra_pole
/// seed 2 (order 1, multisine) adds the missing state at the default 20 % (it lowers the inner
/// hold-out MSE by 86 %) and nothing when a step must gain 99 %, and each outcome says which
/// minimum gain it ran with.
#[test]
fn a_run_uses_the_minimum_gain_it_is_given() {
    let s = Scenario::new(Class::ExtraPole, 2);
    let default = run_one(&s);
    assert_eq!(default.min_gain, 0.2);
    assert_eq!(
        default.first(),
        Some(Effect::UnmodeledDynamics),
        "{}",
        default.line()
    );
    let strict = run_adjusted(&s, &|o| o.min_gain = 0.99);
    assert_eq!(strict.min_gain, 0.99);
    assert!(strict.error.is_none(), "{}", strict.line());
    assert!(strict.named.is_empty(), "{}", strict.line());
}
