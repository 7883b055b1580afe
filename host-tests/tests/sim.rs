//! Tests of the simulator: hysteretic elements, transfer functions, excitation and noise level.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid_host::sim::{
    Backlash, Lti, Nonlinearity, PAPER_U_MAX, PAPER_U_MIN, Switch, paper_backlash,
    paper_noise_model, paper_plant, paper_switch, paper_switch_h0, simulate, table1_excitation,
    variance, with_hold,
};
use rand::SeedableRng;
use rand_pcg::Pcg64;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn play_operator_flat_parts_and_reversal() {
    // Straight borders: H_a(u) = u - 1, H_d(u) = u + 1 (a play of half-width 1).
    let mut b = Backlash::from_fns(|u| u - 1.0, |u| u + 1.0);
    // Initial output 0 lies inside [H_a(0), H_d(0)] = [-1, 1]: stays.
    assert_eq!(b.step(0.0), 0.0);
    // Rising inside the play: flat until H_a catches up.
    assert_eq!(b.step(0.5), 0.0);
    assert_eq!(b.step(1.0), 0.0);
    // Now on the ascending border.
    assert_eq!(b.step(2.0), 1.0);
    assert_eq!(b.step(3.0), 2.0);
    // Reversal: flat part of width 2 before the descending border.
    assert_eq!(b.step(2.5), 2.0);
    assert_eq!(b.step(1.0), 2.0);
    assert_eq!(b.step(0.5), 1.5);
    assert_eq!(b.step(-1.0), 0.0);
    // Reversal again.
    assert_eq!(b.step(0.0), 0.0);
    assert_eq!(b.step(1.5), 0.5);
    // Reset returns to the initial output.
    b.reset();
    assert_eq!(b.output(), 0.0);
    assert_eq!(b.step(5.0), 4.0);
}

#[test]
fn play_operator_initial_output_is_clamped() {
    let mut b = Backlash::from_fns(|u| u - 1.0, |u| u + 1.0).with_initial_output(10.0);
    assert_eq!(b.step(0.0), 1.0);
    let mut b = paper_backlash();
    // Default w = 0 clamped into [atan(-4), atan(-2)] at u = -3.
    assert!(close(b.step(-3.0), (-2.0_f64).atan(), 1e-15));
}

#[test]
fn switch_branch_logic() {
    let mut s = Switch::from_fns(|u| 10.0 + u, |u| -10.0 + u);
    // First sample: no previous input, initial branch descending.
    assert_eq!(s.step(0.0), -10.0);
    assert!(!s.is_ascending());
    // Equal: keep descending.
    assert_eq!(s.step(0.0), -10.0);
    // Rise: ascending.
    assert_eq!(s.step(1.0), 11.0);
    assert!(s.is_ascending());
    // Equal: keep ascending.
    assert_eq!(s.step(1.0), 11.0);
    // Fall: descending.
    assert_eq!(s.step(0.5), -9.5);
    assert_eq!(s.step(0.5), -9.5);
    // Rise again.
    assert_eq!(s.step(0.6), 10.6);
    s.reset();
    assert!(!s.is_ascending());
    assert_eq!(s.step(3.0), -7.0);
}

#[test]
fn paper_switch_borders() {
    let s = paper_switch();
    let h0 = paper_switch_h0();
    assert!(close(h0, 0.5 * (3f64.atan() - 1f64.atan()), 0.0));
    assert_eq!(s.h_a(-3.0), -1.0);
    assert_eq!(s.h_d(-3.0), -1.0);
    assert_eq!(s.h_a(-2.0), -1.0);
    assert_eq!(s.h_a(-1.5), (-2.5f64).atan() + h0);
    assert_eq!(s.h_d(2.0), 3.0f64.atan() - h0);
    assert_eq!(s.h_d(2.0 + 1e-12), 1.0);
    assert_eq!(s.h_a(2.5), 1.0);
    assert_eq!(s.h_d(0.0), 1.0f64.atan() - h0);
    // Assumption A.1.
    assert_eq!(s.h_a(PAPER_U_MIN), s.h_d(PAPER_U_MIN));
}

#[test]
fn paper_backlash_true_paths() {
    let b = paper_backlash();
    let paths = b.true_paths(PAPER_U_MIN, PAPER_U_MAX);
    // Flat part of the ascending path up to u = -1 (where atan(u - 1) = atan(-2)).
    assert!(close(paths.asc(-3.0), (-2.0f64).atan(), 1e-15));
    assert!(close(paths.asc(-1.5), (-2.0f64).atan(), 1e-15));
    assert!(close(paths.asc(0.0), (-1.0f64).atan(), 1e-15));
    assert!(close(paths.asc(3.0), 2.0f64.atan(), 1e-15));
    // Flat part of the descending path down to u = 1.
    assert!(close(paths.desc(3.0), 2.0f64.atan(), 1e-15));
    assert!(close(paths.desc(1.5), 2.0f64.atan(), 1e-15));
    assert!(close(paths.desc(0.0), 1.0f64.atan(), 1e-15));
    assert!(close(paths.desc(-3.0), (-2.0f64).atan(), 1e-15));
}

/// Under the Table I excitation (after a hold at u_min), the elements follow P_a while the
/// input rises or holds after rising, and P_d otherwise.
#[test]
fn elements_follow_true_paths_under_table1() {
    let mut rng = Pcg64::seed_from_u64(7);
    let exc = table1_excitation(2001, PAPER_U_MIN, PAPER_U_MAX, &mut rng).unwrap();
    let u = with_hold(20, PAPER_U_MIN, &exc);
    let backlash = paper_backlash();
    let switch = paper_switch();
    let cases: Vec<(Box<dyn Nonlinearity>, _)> = vec![
        (
            Box::new(backlash.clone()),
            backlash.true_paths(PAPER_U_MIN, PAPER_U_MAX),
        ),
        (
            Box::new(switch.clone()),
            switch.true_paths(PAPER_U_MIN, PAPER_U_MAX),
        ),
    ];
    for (mut nl, paths) in cases {
        let mut prev = PAPER_U_MIN;
        let mut asc = false;
        for &ut in &u {
            if ut > prev {
                asc = true;
            } else if ut < prev {
                asc = false;
            }
            prev = ut;
            let want = if asc { paths.asc(ut) } else { paths.desc(ut) };
            assert!(close(nl.step(ut), want, 1e-15), "u = {ut}, asc = {asc}");
        }
    }
}

#[test]
fn table1_excitation_structure() {
    let mut rng = Pcg64::seed_from_u64(1);
    let u = table1_excitation(4001, -3.0, 3.0, &mut rng).unwrap();
    assert_eq!(u.len(), 4001);
    assert_eq!(u[0], -3.0);
    for t in 1..u.len() {
        match (t - 1) % 4 {
            0 => assert!(u[t] > -3.0 && u[t] < 3.0 && u[t] > u[t - 1]),
            1 => assert_eq!(u[t], 3.0),
            2 => assert!(u[t] > -3.0 && u[t] < 3.0 && u[t] < u[t - 1]),
            _ => assert_eq!(u[t], -3.0),
        }
    }
    assert!(table1_excitation(10, 1.0, 1.0, &mut rng).is_err());
    let h = with_hold(3, -3.0, &u[..2]);
    assert_eq!(h, vec![-3.0, -3.0, -3.0, -3.0, u[1]]);
}

#[test]
fn paper_plant_gain_and_poles() {
    let g = paper_plant();
    let want = (0.1994 - 0.1804) / (1.0 - 1.8858 + 0.9048);
    assert!(close(g.static_gain(), want, 1e-12));
    assert!(close(want, 1.0, 0.05));
    let poles = g.poles().unwrap();
    assert_eq!(poles.len(), 2);
    // Exact roots of z^2 - 1.8858 z + 0.9048.
    let re: f64 = 1.8858 / 2.0;
    let im = (0.9048 - re * re).sqrt();
    assert!(close(poles[0].0, re, 1e-12) && close(poles[0].1, im, 1e-12));
    assert!(close(poles[1].0, re, 1e-12) && close(poles[1].1, -im, 1e-12));
    assert!(close(re, 0.9429, 1e-4) && close(im, 0.1255, 1e-4));
    // Frequency response at w = 0 is the static gain; impulse response has one delay.
    let (r0, i0) = g.freq_response(0.0);
    assert!(close(r0, want, 1e-12) && close(i0, 0.0, 1e-12));
    let h = g.impulse_response(3);
    assert_eq!(h[0], 0.0);
    assert!(close(h[1], 0.1994, 1e-15));
    assert!(close(h[2], -0.1804 + 1.8858 * 0.1994, 1e-15));
}

#[test]
fn frequency_response_and_energy_of_first_order() {
    // G = 1 / (1 - 0.5 q^-1): energy 1 / (1 - 0.25); G(e^{jπ}) = 1 / 1.5.
    let g = Lti::new(vec![1.0], vec![1.0, -0.5]).unwrap();
    assert!(close(g.impulse_energy(), 1.0 / 0.75, 1e-12));
    let (re, im) = g.freq_response(std::f64::consts::PI);
    assert!(close(re, 1.0 / 1.5, 1e-12) && close(im, 0.0, 1e-12));
    // At w = π/2: 1 / (1 + 0.5 j) = (1 - 0.5 j) / 1.25.
    let (re, im) = g.freq_response(std::f64::consts::FRAC_PI_2);
    assert!(close(re, 0.8, 1e-12) && close(im, -0.4, 1e-12));
    // Paper noise model energy: (1 + 0.5 q^-1)/(1 - 0.85 q^-1):
    // h0 = 1, h_k = 1.35 * 0.85^(k-1): energy = 1 + 1.35^2 / (1 - 0.85^2).
    let gv = paper_noise_model();
    assert!(close(
        gv.impulse_energy(),
        1.0 + 1.35f64.powi(2) / (1.0 - 0.85f64.powi(2)),
        1e-10
    ));
    // Normalisation by a[0].
    let g2 = Lti::new(vec![2.0], vec![2.0, -1.0]).unwrap();
    assert_eq!(g2.num(), &[1.0]);
    assert_eq!(g2.den(), &[1.0, -0.5]);
    assert!(Lti::new(vec![1.0], vec![0.0, 1.0]).is_err());
    assert!(Lti::new(vec![], vec![1.0]).is_err());
    assert!(Lti::new(vec![1.0], vec![]).is_err());
}

#[test]
fn lti_step_reset_and_filter_agree() {
    let mut g = paper_plant();
    let x: Vec<f64> = (0..50).map(|t| ((t * 7) % 5) as f64 - 2.0).collect();
    let y1: Vec<f64> = x.iter().map(|&v| g.step(v)).collect();
    g.reset();
    let y2: Vec<f64> = x.iter().map(|&v| g.step(v)).collect();
    assert_eq!(y1, y2);
    assert_eq!(y1, g.filter(&x));
}

#[test]
fn noise_free_simulation() {
    let mut rng = Pcg64::seed_from_u64(3);
    let exc = table1_excitation(400, -3.0, 3.0, &mut rng).unwrap();
    let u = with_hold(300, -3.0, &exc);
    let mut nl = paper_switch();
    let s = simulate(
        &u,
        &mut nl,
        &paper_plant(),
        &paper_noise_model(),
        None,
        0..0,
        &mut rng,
    )
    .unwrap();
    assert_eq!(s.y, s.y_clean);
    assert_eq!(s.e_std, 0.0);
    assert!(s.v.iter().all(|&v| v == 0.0));
    // Settled hold output is G(1) H(u_min) = G(1) * (-1).
    assert!(close(s.y[299], -paper_plant().static_gain(), 1e-5));
}

#[test]
fn realised_snr_is_10_db() {
    let mut rng = Pcg64::seed_from_u64(11);
    let hold = 300;
    let exc = table1_excitation(200_000, -3.0, 3.0, &mut rng).unwrap();
    let u = with_hold(hold, -3.0, &exc);
    let mut nl = paper_backlash();
    let s = simulate(
        &u,
        &mut nl,
        &paper_plant(),
        &paper_noise_model(),
        Some(10.0),
        hold..u.len(),
        &mut rng,
    )
    .unwrap();
    let snr = variance(&s.y_clean[hold..]) / variance(&s.v[hold..]);
    assert!(close(snr, 10.0, 0.3), "realised SNR ratio {snr}");
    assert!(s.e_std > 0.0);
    // Errors.
    assert!(
        simulate(
            &u,
            &mut nl,
            &paper_plant(),
            &paper_noise_model(),
            Some(10.0),
            5..5,
            &mut rng
        )
        .is_err()
    );
    assert!(
        simulate(
            &u,
            &mut nl,
            &paper_plant(),
            &paper_noise_model(),
            Some(f64::NAN),
            0..10,
            &mut rng
        )
        .is_err()
    );
}
