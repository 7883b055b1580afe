//! A small Monte Carlo of the refinement on the paper's example (24 runs per case, the seeds of
//! `hsid paper`); the full 100-run table is `hsid paper --method all`.
//!
//! Bounds and their statistics: with `R = 24` runs a sample standard deviation has a relative
//! standard error of about `1/√(2(R−1)) ≈ 15 %`. The expected values (from the 100-run table)
//! are: PEM pole std ≈ 1.0 × the Cramér–Rao bound and ≈ 0.25–0.3 × PI-MOESP's, reported/empirical
//! std ≈ 1.0–1.25, median border RMS ≈ 0.03 (PI-MOESP: 0.13). Each bound below leaves at least
//! 2.5 standard errors of room.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hsid_host::paper::crb::paper_crb;
use hsid_host::paper::methods::{Method, methods_json, methods_table, run_methods};
use hsid_host::paper::{Case, PaperConfig};

const RUNS: usize = 24;

fn check(case: Case) {
    let cfg = PaperConfig {
        runs: RUNS,
        ..PaperConfig::default()
    };
    let c = run_methods(
        case,
        &cfg,
        &[Method::PiMoesp, Method::PiMoespAls, Method::Pem],
        &|| {},
    )
    .unwrap();
    let get = |m: Method| c.methods.iter().find(|r| r.method == m).unwrap();
    let (pi, als, pem) = (
        get(Method::PiMoesp),
        get(Method::PiMoespAls),
        get(Method::Pem),
    );
    for r in &c.methods {
        assert!(
            r.summary.base.failures.is_empty(),
            "{:?}",
            r.summary.base.failures
        );
        assert_eq!(r.summary.base.order_counts[2], RUNS);
    }
    let norm = |s: [f64; 2]| s[0].hypot(s[1]);
    let crb = c.crb.pole_std_norm();
    println!("{}", methods_table(&cfg, std::slice::from_ref(&c)));
    // The bound is about a quarter of PI-MOESP's spread.
    assert!(crb > 0.0015 && crb < 0.0025, "{crb}");
    // PEM: at the bound, a quarter of PI-MOESP's spread, unbiased.
    let s_pem = norm(pem.summary.base.pole_std);
    let s_pi = norm(pi.summary.base.pole_std);
    assert!(s_pem <= 1.5 * crb, "PEM {s_pem} vs CRB {crb}");
    assert!(
        s_pem >= 0.6 * crb,
        "PEM {s_pem} below the bound {crb}: a bug"
    );
    assert!(s_pem <= 0.45 * s_pi, "PEM {s_pem} vs PI-MOESP {s_pi}");
    assert!((pem.summary.pole_std_over_crb - s_pem / crb).abs() < 1e-12);
    assert!(pem.summary.base.pole_bias < 3.0 * s_pem / (RUNS as f64).sqrt() + 1e-3);
    // Borders: PEM ≈ 0.03, ALS in between, the rank-1 split ≈ 0.13.
    let b = |r: &hsid_host::paper::methods::MethodResult| r.summary.base.border_rms_single_median;
    assert!(b(pem) <= 0.036, "PEM border {}", b(pem));
    assert!(b(als) < 0.8 * b(pi), "ALS {} vs split {}", b(als), b(pi));
    assert!(b(pi) > 0.09, "PI-MOESP border {}", b(pi));
    // Reported standard deviations against the spread.
    let u = pem.summary.uncertainty.clone().unwrap();
    assert_eq!(u.runs, RUNS);
    for v in [u.pole[0], u.pole[1], u.bode_db[1], u.borders[1]] {
        assert!((0.6..=1.6).contains(&v), "{u:?}");
    }
    // The JSON object of the issue.
    let j = methods_json(&c);
    for key in ["pi-moesp", "pi-moesp-als", "pem"] {
        let m = &j[key];
        for field in [
            "pole_std",
            "pole_bias",
            "border_rms_single_median",
            "pole_std_over_crb",
            "seconds_per_identification",
        ] {
            assert!(!m[field].is_null(), "{key}.{field} missing in {m}");
        }
    }
    assert!(j["pem"]["uncertainty"].is_object());
    assert!(j["pi-moesp"].get("uncertainty").is_none());
}

#[test]
fn switch_case_refinement_reaches_the_bound() {
    check(Case::Switch);
}

#[test]
fn backlash_case_refinement_reaches_the_bound() {
    check(Case::Backlash);
}

/// Without a hold: the core's μ0 estimate (a constant channel) and the refinement (μ0 and the
/// initial state as parameters) against the hold's mean.
#[test]
fn mu0_without_the_hold() {
    let with = PaperConfig {
        runs: 12,
        ..PaperConfig::default()
    };
    let without = PaperConfig {
        hold: 0,
        settle: 0,
        ..with.clone()
    };
    let ms = [Method::PiMoesp, Method::Pem];
    let a = run_methods(Case::Backlash, &with, &ms, &|| {}).unwrap();
    let b = run_methods(Case::Backlash, &without, &ms, &|| {}).unwrap();
    let mu0 =
        |c: &hsid_host::paper::methods::CaseMethods, m: usize| c.methods[m].summary.mu0_rms_error;
    for (c, name) in [(&a, "hold"), (&b, "no hold")] {
        println!(
            "{name}: μ0 RMS error PI-MOESP {:.4}, PEM {:.4}",
            mu0(c, 0),
            mu0(c, 1)
        );
    }
    // With the hold both are within a few hundredths (expected ≈ 0.04 and 0.03). Without it
    // the core's estimate (a constant input channel) spreads 3–4 times more (≈ 0.14), while
    // the refinement stays near the hold's accuracy (≈ 0.05): it weighs the constant by the
    // noise model and fits the initial transient. 12 runs: RMS values within ±20 %.
    assert!(mu0(&a, 0) < 0.06 && mu0(&a, 1) < 0.045, "hold");
    assert!(mu0(&b, 0) < 0.2, "no hold: PI-MOESP μ0 RMS {}", mu0(&b, 0));
    assert!(mu0(&b, 1) < 0.07, "no hold: PEM μ0 RMS {}", mu0(&b, 1));
    assert!(mu0(&b, 1) < 0.5 * mu0(&b, 0), "no hold: PEM vs PI-MOESP");
    for c in [&a, &b] {
        assert!(c.methods.iter().all(|m| m.summary.base.failures.is_empty()));
    }
    // Without the hold the refinement still reaches the bound (which includes the initial
    // state).
    assert!(b.methods[1].summary.pole_std_over_crb < 1.6);
    let bound = paper_crb(Case::Backlash, &without, 2, true).unwrap();
    assert!(bound.parameters > a.crb.parameters);
}
