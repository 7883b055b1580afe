//! The refinement module against the simulator's truth: polynomials and filters, the hat
//! regressors, the analytic Jacobian, the noise model and innovation form, Remark 5's
//! alternating least squares, the prediction-error refinement (exact on noise-free data,
//! typed errors), the uncertainty against the bound, the bound itself and the knot count.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hsid_host::identify::{HostModel, IdentifyOptions, identify, interpolate};
use hsid_host::paper::crb::paper_crb;
use hsid_host::paper::{
    Case, Experiment, PaperConfig, case_system, derive_seed, experiment, options,
};
use hsid_host::refine::RefineError;
use hsid_host::refine::Unstable;
use hsid_host::refine::bilinear::split;
use hsid_host::refine::knots::{Criterion, SegmentCount, select_segments};
use hsid_host::refine::pem::{
    BURN_IN, Feedthrough, PemInitialState, PemOptions, PemProblem, PemStructure, feedthrough_std,
    minimise, refine,
};
use hsid_host::refine::poly::{
    char_poly, from_roots, observer_form, root_sensitivity, roots, spectral_radius, stabilise,
    tf_from_ss,
};
use hsid_host::refine::signal::{HatRegressors, filter};
use hsid_host::refine::stochastic::{
    InnovationForm, NoiseModel, NoiseOrder, estimate_noise, fit_noise, hannan_rissanen,
};
use hsid_host::refine::uncertainty::{bode_db_std, border_std, upper_pole};
use hsid_host::sim::{Lti, Switch, paper_noise_model, paper_plant, simulate};
use nalgebra::{Complex, DMatrix};
use rand_core::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg32;

const TRUE_POLE: (f64, f64) = (0.9429, 0.125_457_522_691_945_96);

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// A paper experiment whose element is the piecewise-linear interpolant of the true paths at
/// the Monte Carlo's knots, so that the model structure contains the truth exactly.
fn pwl_experiment(cfg: &PaperConfig, run: u64, snr: Option<f64>) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let opts = options(cfg);
    let (_, paths, plant, noise) = case_system(Case::Switch);
    let k = opts.knots_asc.clone();
    let va: Vec<f64> = k.iter().map(|&u| paths.asc(u)).collect();
    let vd: Vec<f64> = k.iter().map(|&u| paths.desc(u)).collect();
    let n = cfg.hold + cfg.j + cfg.f + cfg.p - 1;
    let rng = Pcg32::seed_from_u64(derive_seed(cfg.seed, 7, run, 1));
    let u: Vec<f64> = hsid::Excitation::new(cfg.u_min, cfg.u_max, cfg.hold, rng)
        .unwrap()
        .take(n)
        .collect();
    let (k1, k2, a2, d2) = (k.clone(), k.clone(), va.clone(), vd.clone());
    let mut nl = Switch::from_fns(
        move |x| interpolate(&k1, &a2, x),
        move |x| interpolate(&k2, &d2, x),
    );
    let mut nrng = Pcg32::seed_from_u64(derive_seed(cfg.seed, 7, run, 2));
    let sim = simulate(&u, &mut nl, &plant, &noise, snr, cfg.hold..n, &mut nrng).unwrap();
    let mut beta = vec![va[0]];
    beta.extend(&va[1..]);
    beta.extend(&vd[1..]);
    (u, sim.y, beta)
}

fn run0() -> &'static Experiment {
    static E: std::sync::OnceLock<Experiment> = std::sync::OnceLock::new();
    E.get_or_init(|| experiment(Case::Switch, &PaperConfig::default(), 0).unwrap())
}

// ---------------------------------------------------------------------------------------------
// Polynomials and filters
// ---------------------------------------------------------------------------------------------

#[test]
fn transfer_function_round_trip_of_the_paper_plant() {
    let g = paper_plant();
    let (a, b, c, d) = observer_form(g.num(), g.den());
    assert_eq!(char_poly(&a).len(), 3);
    for (x, y) in char_poly(&a).iter().zip(g.den()) {
        assert!(close(*x, *y, 1e-14), "{x} vs {y}");
    }
    let (num, den) = tf_from_ss(&a, &b, &c, d);
    for (x, y) in num.iter().zip(g.num()).chain(den.iter().zip(g.den())) {
        assert!(close(*x, *y, 1e-14), "{x} vs {y}");
    }
    // A similarity transform does not change the transfer function.
    let t = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, -0.5, 3.0]);
    let ti = t.clone().try_inverse().unwrap();
    let a2 = &t * &a * &ti;
    let b2: Vec<f64> = (&t * nalgebra::DVector::from_column_slice(&b))
        .iter()
        .copied()
        .collect();
    let c2: Vec<f64> = (nalgebra::RowDVector::from_row_slice(&c) * &ti)
        .iter()
        .copied()
        .collect();
    let (num2, den2) = tf_from_ss(&a2, &b2, &c2, d);
    for (x, y) in num2.iter().zip(g.num()).chain(den2.iter().zip(g.den())) {
        assert!(close(*x, *y, 1e-12), "{x} vs {y}");
    }
    // The filter is the simulator's difference equation.
    let x: Vec<f64> = (0..200).map(|t| ((t * 7919) % 13) as f64 - 6.0).collect();
    for (p, q) in filter(g.num(), g.den(), &x).iter().zip(g.filter(&x)) {
        assert!(close(*p, q, 1e-12));
    }
}

#[test]
fn roots_their_sensitivity_and_stabilisation() {
    let den = paper_plant().den().to_vec();
    let r = roots(&den).unwrap();
    let up = r
        .iter()
        .copied()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert!(close(up.0, TRUE_POLE.0, 1e-12) && close(up.1, TRUE_POLE.1, 1e-12));
    // ∂z/∂f_i against central differences.
    let s = root_sensitivity(&den, Complex::new(up.0, up.1));
    for i in 1..den.len() {
        let h = 1e-7;
        let mut dp = den.clone();
        dp[i] += h;
        let mut dm = den.clone();
        dm[i] -= h;
        let zp = roots(&dp)
            .unwrap()
            .into_iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        let zm = roots(&dm)
            .unwrap()
            .into_iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        let fd = Complex::new((zp.0 - zm.0) / (2.0 * h), (zp.1 - zm.1) / (2.0 * h));
        assert!(
            (fd - s[i - 1]).norm() < 1e-5 * (1.0 + fd.norm()),
            "{fd} vs {}",
            s[i - 1]
        );
    }
    // A root outside the unit circle is reflected inside.
    let p = from_roots(&[(2.0, 0.0), (0.5, 0.0)]);
    assert!(spectral_radius(&p) > 1.9);
    let q = stabilise(&p, 0.99).unwrap();
    let rq = roots(&q).unwrap();
    assert!(rq.iter().any(|z| close(z.0, 0.5, 1e-12)), "{rq:?}");
    assert!(spectral_radius(&q) < 0.99);
}

#[test]
fn hat_regressors_reproduce_the_piecewise_linear_borders() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let (u, _, beta) = pwl_experiment(&cfg, 0, None);
    let hat = HatRegressors::new(&u, &opts.knots_asc, &opts.knots_desc).unwrap();
    assert_eq!(hat.channels(), 15);
    let h = hat.output(&beta);
    // The simulator's element output, recomputed from the same paths.
    let (_, paths, _, _) = case_system(Case::Switch);
    let k = &opts.knots_asc;
    let va: Vec<f64> = k.iter().map(|&x| paths.asc(x)).collect();
    let vd: Vec<f64> = k.iter().map(|&x| paths.desc(x)).collect();
    let mut el = Switch::from_fns(
        {
            let (k, v) = (k.clone(), va.clone());
            move |x| interpolate(&k, &v, x)
        },
        {
            let (k, v) = (k.clone(), vd.clone());
            move |x| interpolate(&k, &v, x)
        },
    );
    use hsid_host::sim::Nonlinearity;
    for (t, &ut) in u.iter().enumerate() {
        let truth = el.step(ut);
        assert!(close(h[t], truth, 1e-12), "t = {t}: {} vs {truth}", h[t]);
    }
    let (a, d) = hat.borders_from_beta(&beta);
    assert_eq!(a, va);
    assert_eq!(d, vd);
    // A static nonlinearity shares one border.
    let s = HatRegressors::shared(&u, k).unwrap();
    assert_eq!(s.channels(), 8);
    assert!(HatRegressors::new(&[5.0], k, k).is_err());
}

// ---------------------------------------------------------------------------------------------
// The prediction-error problem
// ---------------------------------------------------------------------------------------------

fn structure(nv: usize, initial: PemInitialState, feedthrough: bool) -> PemStructure {
    PemStructure {
        n: 2,
        nv,
        initial,
        start: 150,
        feedthrough,
        shared: false,
        burn: BURN_IN,
    }
}

/// θ of the true system (PWL borders) in a problem's layout.
fn true_theta(p: &PemProblem, beta: &[f64]) -> Vec<f64> {
    let l = p.layout();
    let mut th = vec![0.0; l.len()];
    th[l.f()].copy_from_slice(&paper_plant().den()[1..]);
    for (k, i) in l.b().enumerate() {
        th[i] = paper_plant().num()[k + 1];
    }
    th[l.beta()].copy_from_slice(beta);
    if l.nv == 1 {
        th[l.nd().start] = paper_noise_model().den()[1];
        th[l.nc().start] = paper_noise_model().num()[1];
    }
    th
}

/// The paper's record as a prediction-error problem of order 2 with an ARMA(2) noise model,
/// with a feed-through and the plant at rest, and without either (the initial state estimated,
/// its coefficients at 0.3): `(feed-through, problem, θ)`.
fn jacobian_cases() -> Vec<(bool, PemProblem<'static>, Vec<f64>)> {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let e = run0();
    let init = identify(&e.u, &e.y, &opts).unwrap();
    let noise = NoiseModel {
        c: vec![1.0, 0.4, 0.1],
        d: vec![1.0, -0.8, 0.05],
        sigma2: 1.0,
    };
    [
        (true, PemInitialState::Rest),
        (false, PemInitialState::Estimate),
    ]
    .into_iter()
    .map(|(ft, ini)| {
        let p = PemProblem::new(
            &e.u,
            &e.y,
            &opts.knots_asc,
            &opts.knots_desc,
            structure(2, ini, ft),
        )
        .unwrap();
        let mut th = p.theta_from(&init, &noise).unwrap();
        for i in p.layout().iota() {
            th[i] = 0.3;
        }
        (ft, p, th)
    })
    .collect()
}

#[test]
fn analytic_jacobian_matches_finite_differences() {
    for (ft, p, th) in jacobian_cases() {
        let jac = p.jacobian(&th);
        assert_eq!(jac.nrows(), p.samples());
        for j in 0..th.len() {
            let h = 1e-6 * (1.0 + th[j].abs());
            let mut tp = th.clone();
            tp[j] += h;
            let mut tm = th.clone();
            tm[j] -= h;
            let (ep, em) = (p.errors(&tp), p.errors(&tm));
            let (mut num, mut den) = (0.0, 0.0);
            for t in 0..ep.len() {
                let fd = (ep[t] - em[t]) / (2.0 * h);
                num += (fd - jac[(t, j)]).powi(2);
                den += fd * fd;
            }
            let rel = (num / den.max(1e-300)).sqrt();
            assert!(
                rel < 1e-6,
                "column {j} (feed-through {ft}): relative error {rel}"
            );
        }
    }
}

/// The normal equations accumulated sample by sample (what the refinement uses) are those of
/// the Jacobian matrix: `JᵀJ`, `Jᵀε` and `Jᵀr` for another residual, to rounding.
#[test]
fn accumulated_normal_equations_are_those_of_the_jacobian() {
    for (ft, p, th) in jacobian_cases() {
        let jac = p.jacobian(&th);
        let ev = p.evaluate(&th);
        let eps = nalgebra::DVector::from_column_slice(&ev.eps);
        assert_eq!(ev.eps, p.errors(&th));
        let close = |a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>, what: &str| {
            let rel = (a - b).norm() / b.norm();
            assert!(
                rel < 1e-12,
                "{what} (feed-through {ft}): relative error {rel}"
            );
        };
        close(&ev.jtj, &jac.tr_mul(&jac), "JᵀJ");
        close(
            &nalgebra::DMatrix::from_column_slice(ev.jtr.len(), 1, ev.jtr.as_slice()),
            &nalgebra::DMatrix::from_column_slice(eps.len(), 1, eps.as_slice())
                .tr_mul(&jac)
                .transpose(),
            "Jᵀε",
        );
        let r: Vec<f64> = (0..ev.eps.len()).map(|t| (t as f64 * 0.37).sin()).collect();
        let other = p.evaluate_against(&th, Some(&r));
        let rv = nalgebra::DVector::from_column_slice(&r);
        let want = jac.tr_mul(&rv);
        let rel = (&other.jtr - &want).norm() / want.norm();
        assert!(rel < 1e-12, "Jᵀr (feed-through {ft}): relative error {rel}");
    }
}

#[test]
fn refinement_is_exact_on_noise_free_data_of_the_model_class() {
    let cfg = PaperConfig {
        order: Some(2),
        ..PaperConfig::default()
    };
    let opts = options(&cfg);
    let (u, y, beta) = pwl_experiment(&cfg, 1, None);
    let init = identify(&u, &y, &opts).unwrap();
    let fit = refine(
        &u,
        &y,
        &init,
        &PemOptions {
            noise_order: NoiseOrder::Fixed(0),
            feedthrough: Feedthrough::Zero,
            ..PemOptions::for_identify(&opts)
        },
    )
    .unwrap();
    let p = upper_pole(&fit).unwrap().pole;
    assert!(
        close(p.0, TRUE_POLE.0, 1e-7) && close(p.1, TRUE_POLE.1, 1e-7),
        "{p:?}"
    );
    // The simulated plant starts from zero, not at rest: 150 samples of settling leave
    // 0.951¹⁵⁰ ≈ 5·10⁻⁴ of the step, which the rest assumption reads as 4·10⁻⁵ of μ0.
    let got = HatRegressors::new(&u, &opts.knots_asc, &opts.knots_desc)
        .unwrap()
        .beta_of(fit.model.mu0, &fit.model.border_asc, &fit.model.border_desc);
    for (a, b) in got.iter().zip(&beta) {
        assert!(close(*a, *b, 1e-4), "{a} vs {b}");
    }
    assert!(fit.mse < 1e-8, "mse {}", fit.mse);
}

#[test]
fn minimiser_finds_the_same_optimum_from_the_truth_and_from_the_subspace_model() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let (u, y, beta) = pwl_experiment(&cfg, 2, Some(10.0));
    let init = identify(&u, &y, &opts).unwrap();
    let po = PemOptions {
        noise_order: NoiseOrder::Fixed(1),
        feedthrough: Feedthrough::Zero,
        ..PemOptions::for_identify(&opts)
    };
    let fit = refine(&u, &y, &init, &po).unwrap();
    let p = PemProblem::new(
        &u,
        &y,
        &opts.knots_asc,
        &opts.knots_desc,
        structure(1, PemInitialState::Rest, false),
    )
    .unwrap();
    let (th, ev, _) = minimise(&p, true_theta(&p, &beta), 200, 1e-12).unwrap();
    assert!(
        close(ev.cost, fit.cost, 1e-8 * fit.cost),
        "{} vs {}",
        ev.cost,
        fit.cost
    );
    for (a, b) in th.iter().zip(&fit.theta) {
        assert!(close(*a, *b, 1e-4 * (1.0 + b.abs())), "{a} vs {b}");
    }
}

#[test]
fn typed_errors_for_bad_starts_and_bad_data() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let e = run0();
    let init = identify(&e.u, &e.y, &opts).unwrap();
    // An unstable starting plant.
    let mut bad = init.clone();
    bad.a = DMatrix::from_row_slice(2, 2, &[1.2, 0.0, 0.0, 0.5]);
    let err = refine(&e.u, &e.y, &bad, &PemOptions::for_identify(&opts)).unwrap_err();
    assert!(
        matches!(err, RefineError::UnstablePredictor { which: Unstable::Plant, radius } if close(radius, 1.2, 1e-9)),
        "{err:?}"
    );
    assert!(err.to_string().contains("unstable predictor"), "{err}");
    // An unstable predictor (noise numerator) given to the minimiser.
    let p = PemProblem::new(
        &e.u,
        &e.y,
        &opts.knots_asc,
        &opts.knots_desc,
        structure(1, PemInitialState::Rest, true),
    )
    .unwrap();
    let noise = NoiseModel {
        c: vec![1.0, 1.5],
        d: vec![1.0, -0.85],
        sigma2: 1.0,
    };
    let th = p.theta_from(&init, &noise).unwrap();
    assert!(matches!(
        minimise(&p, th.clone(), 50, 1e-10),
        Err(RefineError::UnstablePredictor {
            which: Unstable::Noise,
            ..
        })
    ));
    // The iteration limit.
    let noise = NoiseModel {
        c: vec![1.0, 0.0],
        d: vec![1.0, 0.0],
        sigma2: 1.0,
    };
    let th = p.theta_from(&init, &noise).unwrap();
    assert!(matches!(
        minimise(&p, th, 1, 1e-300),
        Err(RefineError::NoConvergence { iterations: 1, .. })
    ));
    // `refine` keeps the last iterate at the limit and says so; its cost is below the start's.
    let short = PemOptions {
        max_iter: 1,
        noise_order: NoiseOrder::Fixed(0),
        feedthrough: Feedthrough::Zero,
        ..PemOptions::for_identify(&opts)
    };
    let stopped = refine(&e.u, &e.y, &init, &short).unwrap();
    assert_eq!(stopped.iterations, 1);
    let decrease = stopped.unconverged.unwrap();
    assert!(
        decrease > 0.0 && stopped.cost < stopped.initial_cost,
        "{decrease}"
    );
    let converged = refine(
        &e.u,
        &e.y,
        &init,
        &PemOptions {
            max_iter: 100,
            ..short
        },
    )
    .unwrap();
    assert_eq!(converged.unconverged, None);
    assert!(converged.cost <= stopped.cost);
    // Data errors.
    assert!(matches!(
        refine(&e.u[..100], &e.y, &init, &PemOptions::default()),
        Err(RefineError::LengthMismatch { .. })
    ));
    assert!(matches!(
        refine(&e.u[..150], &e.y[..150], &init, &PemOptions::default()),
        Err(RefineError::TooFewSamples { .. })
    ));
    let mut y = e.y.clone();
    y[1000] = f64::NAN;
    assert!(matches!(
        refine(&e.u, &y, &init, &PemOptions::for_identify(&opts)),
        Err(RefineError::NonFinite)
    ));
}

#[test]
fn refinement_of_one_run_is_near_the_truth_with_a_calibrated_uncertainty() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let e = run0();
    let init = identify(&e.u, &e.y, &opts).unwrap();
    let fit = refine(&e.u, &e.y, &init, &PemOptions::for_identify(&opts)).unwrap();
    // The noise model found is the true ARMA(1, 1) (0.5, −0.85), within 5 of its std.
    assert_eq!(fit.noise.order(), 1, "{:?}", fit.noise_bic);
    let l = fit.layout;
    let sd = |i: usize| fit.covariance[(i, i)].sqrt();
    assert!(
        close(fit.noise.c[1], 0.5, 5.0 * sd(l.nc().start)),
        "{:?}",
        fit.noise
    );
    assert!(
        close(fit.noise.d[1], -0.85, 5.0 * sd(l.nd().start)),
        "{:?}",
        fit.noise
    );
    // The true plant has no feed-through: D is dropped.
    assert!(!fit.layout.feedthrough);
    assert_eq!(feedthrough_std(&fit), (0.0, 0.0));
    // The pole within 4 reported standard deviations, which are near the bound (0.0013,
    // 0.0015).
    let up = upper_pole(&fit).unwrap();
    assert!(close(up.pole.0, TRUE_POLE.0, 4.0 * up.std.0), "{up:?}");
    assert!(close(up.pole.1, TRUE_POLE.1, 4.0 * up.std.1), "{up:?}");
    assert!(up.std.0 > 0.0008 && up.std.0 < 0.002, "{up:?}");
    assert!(up.std.1 > 0.0009 && up.std.1 < 0.0022, "{up:?}");
    // Bode magnitude and borders: std positive, the true values within 4 std almost
    // everywhere.
    let w: Vec<f64> = (1..40).map(|i| 0.08 * i as f64).collect();
    let g = paper_plant();
    let bode = bode_db_std(&fit, &w);
    let outside = w
        .iter()
        .zip(&bode)
        .filter(|(x, (db, s))| {
            let (re, im) = g.freq_response(**x);
            (10.0 * (re * re + im * im).log10() - db).abs() > 4.0 * s
        })
        .count();
    assert!(
        outside <= 2,
        "{outside} of {} Bode points outside 4σ",
        w.len()
    );
    let (sa, sdd) = border_std(&fit);
    assert_eq!(sa.len(), 8);
    assert!(
        sa.iter().chain(&sdd).all(|s| *s > 0.005 && *s < 0.06),
        "{sa:?} {sdd:?}"
    );
    // The innovation form predicts one step ahead with the innovation variance.
    let inn = fit.innovation_form();
    assert_eq!(inn.order(), 3);
    let pred = inn.predict(&e.u, &e.y);
    let mse = e.y[400..]
        .iter()
        .zip(&pred[400..])
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        / (e.y.len() - 400) as f64;
    assert!(
        close(mse, fit.noise.sigma2, 0.1 * fit.noise.sigma2),
        "{mse} vs {}",
        fit.noise.sigma2
    );
    // … far better than simulating.
    let sim = inn.simulate(&e.u);
    let sim_mse = e.y[400..]
        .iter()
        .zip(&sim[400..])
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        / (e.y.len() - 400) as f64;
    assert!(sim_mse > 5.0 * mse, "{sim_mse} vs {mse}");
}

// ---------------------------------------------------------------------------------------------
// Remark 6: the noise model of a subspace model
// ---------------------------------------------------------------------------------------------

#[test]
fn hannan_rissanen_recovers_an_arma_model() {
    let g = Lti::new(vec![1.0, 0.5], vec![1.0, -0.85]).unwrap();
    let mut rng = Pcg32::seed_from_u64(11);
    let e: Vec<f64> = (0..20_000)
        .map(|_| {
            let n: f64 = StandardNormal.sample(&mut rng);
            0.1 * n
        })
        .collect();
    let v = g.filter(&e);
    let m = hannan_rissanen(&v, 1).unwrap();
    assert!(
        close(m.c[1], 0.5, 0.05) && close(m.d[1], -0.85, 0.02),
        "{m:?}"
    );
    assert!(close(m.sigma2, 0.01, 0.0005), "{m:?}");
    let f = fit_noise(&v, NoiseOrder::Auto { max: 3 }).unwrap();
    assert_eq!(f.model.order(), 1, "{:?}", f.bic);
    // The whitened noise is white.
    let w = m.whiten(&v);
    let r1 = w[100..].windows(2).map(|p| p[0] * p[1]).sum::<f64>()
        / w[100..].iter().map(|x| x * x).sum::<f64>();
    assert!(r1.abs() < 0.03, "lag-1 correlation {r1}");
}

#[test]
fn remark6_noise_model_of_the_subspace_model_and_its_predictor() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let e = run0();
    let m = identify(&e.u, &e.y, &opts).unwrap();
    let nf = estimate_noise(&m, &e.u, &e.y, cfg.settle, NoiseOrder::default()).unwrap();
    assert!(nf.model.order() >= 1, "{:?}", nf.bic);
    let inn = InnovationForm::new(&m, &nf.model);
    assert_eq!(inn.k.len(), inn.order());
    assert_eq!(&inn.k[..2], &[0.0, 0.0]);
    // The predictor is the filter ŷ = y − (D/C)(y − ŷ_sim).
    let pred = inn.predict(&e.u, &e.y);
    let sim = m.simulate(&e.u);
    let raw: Vec<f64> = e.y.iter().zip(&sim).map(|(a, b)| a - b).collect();
    let eps = nf.model.whiten(&raw);
    for t in 0..e.y.len() {
        assert!(close(pred[t], e.y[t] - eps[t], 1e-9), "t = {t}");
    }
    // Prediction beats simulation by a wide margin (10 dB SNR, coloured noise).
    let mse = |a: &[f64]| {
        e.y[400..]
            .iter()
            .zip(&a[400..])
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
    };
    assert!(mse(&pred) < 0.5 * mse(&sim));
    // Noise-free data: the predictor of a white noise model is the simulation.
    let white = InnovationForm::new(&m, &NoiseModel::white(1.0));
    let p2 = white.predict(&e.u, &e.y);
    for (a, b) in p2.iter().zip(&sim) {
        assert!(close(*a, *b, 1e-12));
    }
}

// ---------------------------------------------------------------------------------------------
// Remark 5: B and μ separately
// ---------------------------------------------------------------------------------------------

#[test]
fn remark5_alternating_least_squares_is_exact_without_noise_and_beats_the_split_with_it() {
    // Noise free, the automatic order can count the settling of the hold as a third mode
    // (a pole at 1): fix the order.
    let cfg = PaperConfig {
        order: Some(2),
        ..PaperConfig::default()
    };
    let opts = options(&cfg);
    let (u, y, beta) = pwl_experiment(&cfg, 3, None);
    let m = identify(&u, &y, &opts).unwrap();
    let als = split(&m, &u, &y, cfg.hold, 200, false).unwrap();
    // μ0 is the hold's mean, 4·10⁻⁵ off (the plant settles from zero during the hold).
    let got = HatRegressors::new(&u, &opts.knots_asc, &opts.knots_desc)
        .unwrap()
        .beta_of(als.model.mu0, &als.model.border_asc, &als.model.border_desc);
    for (a, b) in got.iter().zip(&beta) {
        assert!(close(*a, *b, 1e-4), "{a} vs {b}");
    }
    assert!(als.mse < 1e-8, "{}", als.mse);
    // With noise, on a few runs: the border error drops (PI-MOESP's split: ≈0.13 RMS).
    let grid: Vec<f64> = (0..=600).map(|i| -3.0 + 0.01 * i as f64).collect();
    let (_, paths, _, _) = case_system(Case::Switch);
    let err = |m: &HostModel| {
        let s: f64 = grid
            .iter()
            .map(|&x| {
                (m.border_asc_at(x) - paths.asc(x)).powi(2)
                    + (m.border_desc_at(x) - paths.desc(x)).powi(2)
            })
            .sum();
        (s / (2.0 * grid.len() as f64)).sqrt()
    };
    let (mut e1, mut e2) = (0.0, 0.0);
    for r in 0..4 {
        let e = experiment(Case::Switch, &cfg, r).unwrap();
        let m = identify(&e.u, &e.y, &opts).unwrap();
        let als = split(&m, &e.u, &e.y, cfg.hold, 200, false).unwrap();
        // A and C are kept, G(1) = 1.
        assert_eq!(als.model.a, m.a);
        assert_eq!(als.model.c, m.c);
        let x = (DMatrix::identity(2, 2) - &m.a)
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(&als.model.b))
            .unwrap();
        assert!(close(
            m.c[0] * x[0] + m.c[1] * x[1] + als.model.d,
            1.0,
            1e-12
        ));
        e1 += err(&m) / 4.0;
        e2 += err(&als.model) / 4.0;
    }
    assert!(e2 < 0.75 * e1, "ALS border RMS {e2} vs rank-1 split {e1}");
}

// ---------------------------------------------------------------------------------------------
// The bound
// ---------------------------------------------------------------------------------------------

#[test]
fn cramer_rao_bound_of_the_paper_example() {
    let cfg = PaperConfig::default();
    let b = paper_crb(Case::Switch, &cfg, 3, true).unwrap();
    assert_eq!(b.parameters, 21);
    assert!(close(b.pole.pole.0, TRUE_POLE.0, 1e-12) && close(b.pole.pole.1, TRUE_POLE.1, 1e-12));
    // ≈ (0.0013, 0.0015): a quarter of PI-MOESP's spread (0.0058, 0.0048).
    assert!(
        b.pole.std.0 > 0.0011 && b.pole.std.0 < 0.0015,
        "{:?}",
        b.pole
    );
    assert!(
        b.pole.std.1 > 0.0013 && b.pole.std.1 < 0.0017,
        "{:?}",
        b.pole
    );
    assert!(close(b.sigma2, 1.45e-3, 0.1e-3), "{}", b.sigma2);
    // Four times the data halves the bound.
    let long = paper_crb(
        Case::Switch,
        &PaperConfig {
            j: 16_000,
            ..cfg.clone()
        },
        1,
        true,
    )
    .unwrap();
    let ratio = long.pole_std_norm() / b.pole_std_norm();
    assert!(ratio > 0.45 && ratio < 0.56, "{ratio}");
    // Without a feed-through the bound is about the same (the true D is 0).
    let strict = paper_crb(Case::Switch, &cfg, 3, false).unwrap();
    assert!(close(
        strict.pole_std_norm(),
        b.pole_std_norm(),
        0.05 * b.pole_std_norm()
    ));
    // Without a hold the initial state is estimated (and the true one is zero).
    let nohold = paper_crb(
        Case::Backlash,
        &PaperConfig {
            hold: 0,
            settle: 0,
            ..cfg
        },
        2,
        true,
    )
    .unwrap();
    assert!(
        nohold.parameters == 23 && nohold.pole_std_norm() < 0.0025,
        "{nohold:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// The knot count
// ---------------------------------------------------------------------------------------------

#[test]
fn knot_count_from_the_data() {
    let cfg = PaperConfig::default();
    let opts = options(&cfg);
    let e = run0();
    let c = select_segments(&e.u, &e.y, &opts, 3..=9, Criterion::Bic).unwrap();
    assert!((5..=8).contains(&c.segments), "{c:?}");
    assert_eq!(c.scores.len(), 7);
    assert!(
        c.report()
            .contains(&format!("segments per path: {}", c.segments))
    );
    // Far too few knots are always worse: the approximation error dominates.
    let s3 = c.scores.iter().find(|(s, _)| *s == 3).unwrap().1;
    let best = c
        .scores
        .iter()
        .map(|(_, v)| *v)
        .fold(f64::INFINITY, f64::min);
    assert!(s3 > best + 100.0, "{c:?}");
    // AIC's lighter penalty never picks fewer knots than BIC on the same scores.
    let a = select_segments(&e.u, &e.y, &opts, 3..=9, Criterion::Aic).unwrap();
    assert!(a.segments >= c.segments, "{a:?} {c:?}");
    assert_eq!("auto".parse::<SegmentCount>(), Ok(SegmentCount::Auto));
    assert_eq!("7".parse::<SegmentCount>(), Ok(SegmentCount::Fixed(7)));
    assert!("seven".parse::<SegmentCount>().is_err());
}

#[test]
fn refinement_without_a_hold_estimates_mu0_and_the_initial_state() {
    let cfg = PaperConfig {
        hold: 0,
        settle: 0,
        ..PaperConfig::default()
    };
    let opts: IdentifyOptions = options(&cfg);
    assert_eq!(opts.hold, 0);
    let e = experiment(Case::Backlash, &cfg, 0).unwrap();
    let init = identify(&e.u, &e.y, &opts).unwrap();
    let po = PemOptions::for_identify(&opts);
    assert_eq!(po.initial, PemInitialState::Estimate);
    let fit = refine(&e.u, &e.y, &init, &po).unwrap();
    let up = upper_pole(&fit).unwrap();
    assert!(close(up.pole.0, TRUE_POLE.0, 4.0 * up.std.0), "{up:?}");
    assert!(close(up.pole.1, TRUE_POLE.1, 4.0 * up.std.1), "{up:?}");
    let (_, paths, _, _) = case_system(Case::Backlash);
    let mu0 = paths.asc(-3.0);
    let (sa, _) = border_std(&fit);
    assert!(
        close(fit.model.mu0, mu0, 4.0 * sa[0]),
        "{} vs {mu0}",
        fit.model.mu0
    );
}
