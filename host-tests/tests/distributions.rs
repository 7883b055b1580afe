//! The distribution functions of the residual tests (`validation::stats`) against values computed
//! independently to 30 digits (mpmath: `erfc`, `erfinv`, the regularised incomplete gamma
//! and a root of it), and their answers outside the domain (no panic).

use hsid_host::validation::stats::{
    chi2_quantile, chi2_sf, normal_quantile, normal_sf, poisson_sf,
};

/// `|got − want| ≤ rel · |want|`.
fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs()
}

#[test]
fn normal_tail_and_quantile_match_reference_values() {
    for (x, want) in [
        (1.96, 0.024_997_895_148_220_436),
        (6.0, 9.865_876_450_376_98e-10),
        (-1.0, 0.841_344_746_068_542_9),
    ] {
        let got = normal_sf(x);
        assert!(
            close(got, want, 1e-9),
            "normal_sf({x}) = {got:e}, want {want:e}"
        );
    }
    for (p, want) in [
        (0.995, 2.575_829_303_548_900_5),
        (1e-6, -4.753_424_308_822_899),
    ] {
        let got = normal_quantile(p);
        assert!(
            close(got, want, 1e-13),
            "normal_quantile({p}) = {got}, want {want}"
        );
    }
}

#[test]
fn chi_square_tail_and_quantile_match_reference_values() {
    for (p, k, want) in [
        (0.99, 20.0, 37.566_234_786_625_05),
        (0.95, 3.0, 7.814_727_903_251_178),
        (0.99, 1.0, 6.634_896_601_021_214),
    ] {
        let got = chi2_quantile(p, k);
        assert!(
            close(got, want, 1e-9),
            "chi2_quantile({p}, {k}) = {got}, want {want}"
        );
    }
    for (x, k, want) in [
        (30.0, 10.0, 8.566_412_107_753_004e-4),
        (200.0, 40.0, 3.764_893_576_001_475e-23),
    ] {
        let got = chi2_sf(x, k);
        assert!(
            close(got, want, 1e-11),
            "chi2_sf({x}, {k}) = {got:e}, want {want:e}"
        );
    }
}

#[test]
fn poisson_tail_keeps_its_relative_accuracy_far_below_one() {
    // P(X ≥ 4) for λ = 1e-4 is 4.2e-18: computed as 1 − Q it would round to 0.
    let got = poisson_sf(4, 1e-4);
    assert!(close(got, 4.166_333_347_221_826e-18, 1e-12), "{got:e}");
    let got = poisson_sf(2, 3.0);
    assert!(close(got, 0.800_851_726_528_544_2, 1e-13), "{got}");
}

#[test]
fn arguments_outside_the_domain_give_limits_or_nan() {
    assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
    assert_eq!(normal_quantile(1.0), f64::INFINITY);
    assert!(normal_quantile(f64::NAN).is_nan());
    assert_eq!(chi2_sf(0.0, 3.0), 1.0);
    assert_eq!(chi2_sf(-1.0, 3.0), 1.0);
    assert_eq!(chi2_sf(f64::INFINITY, 3.0), 0.0);
    assert!(chi2_sf(f64::NAN, 3.0).is_nan());
    assert!(chi2_sf(5.0, 0.0).is_nan());
    assert!(chi2_quantile(1.5, 3.0).is_nan());
    assert!(chi2_quantile(f64::NAN, 3.0).is_nan());
    assert!(chi2_quantile(0.5, -2.0).is_nan());
    assert_eq!(poisson_sf(0, 0.3), 1.0);
    assert_eq!(poisson_sf(3, 0.0), 0.0);
    assert_eq!(poisson_sf(3, f64::INFINITY), 1.0);
    assert!(poisson_sf(3, -1.0).is_nan());
    assert!(poisson_sf(3, f64::NAN).is_nan());
}
