//! Tests of the example's model classes against plants of their class.

use hsid_host::diagnose::dynamics::{Borders, DynamicsFit};
use hsid_host::numerics::rms_error;

use crate::error::ClassError;
use crate::fixtures::{levels, model};
use crate::overflow::{Overflow, fit_overflow};
use crate::poly::{StatePoly, monomials, simulate, unique_steady_states};
use crate::poly_fit::fit;

/// The plant of the polynomial class: the test's linear model plus a quadratic term in
/// its first state.
fn quadratic_plant(h: &[f64]) -> Vec<f64> {
    let mut x = [0.0f64; 2];
    h.iter()
        .map(|&hi| {
            let y = x[0] + 0.5 * x[1];
            x = [
                0.9 * x[0] + 0.05 * x[1] + 0.1 * hi - 0.15 * x[0] * x[0],
                0.8 * x[1] + 0.2 * hi,
            ];
            y
        })
        .collect()
}

/// Noise-free data, every sample fitted, the initial state held at zero.
fn exact<'a>(
    h: &'a [f64],
    y: &'a [f64],
    skip: &'a [bool],
    iterations: usize,
    borders: Option<Borders<'a>>,
) -> DynamicsFit<'a> {
    DynamicsFit {
        h,
        y,
        skip,
        map: None,
        fit_x0: false,
        radius_limit: 0.999,
        iterations,
        borders,
    }
}

type Outcome = Result<(), Box<dyn std::error::Error>>;

#[test]
fn polynomial_term_fits_a_plant_of_its_class() -> Outcome {
    // The plant: the linear model plus a quadratic term in its first state. Started from
    // the linear model, the fit must explain what the linear model misses.
    let lin = model([[0.9, 0.05], [0.0, 0.8]], [0.1, 0.2], [1.0, 0.5], 0.0);
    let h = levels(1500, 7);
    let y = quadratic_plant(&h);
    let skip = vec![false; h.len()];
    let data = exact(&h, &y, &skip, 50, None);
    let before = rms_error(&lin.linear_response(&h, &[0.0, 0.0]), &y);
    let (m, poly, x0) = fit(&lin, &[0.0, 0.0], 2, &data)?;
    let after = rms_error(
        &simulate(&m, Some(&poly), &h, &x0).ok_or("not simulated")?,
        &y,
    );
    // On another input of the same range (not fitted).
    let h2 = levels(1500, 99);
    let y2 = quadratic_plant(&h2);
    let before2 = rms_error(&lin.linear_response(&h2, &[0.0, 0.0]), &y2);
    let after2 = rms_error(
        &simulate(&m, Some(&poly), &h2, &x0).ok_or("not simulated")?,
        &y2,
    );
    assert!(after < 0.02 * before, "fitted: {before:.3e} → {after:.3e}");
    assert!(
        after2 < 0.05 * before2,
        "new input: {before2:.3e} → {after2:.3e}"
    );
    Ok(())
}

#[test]
fn borders_refitted_with_the_polynomial() -> Outcome {
    // The plant's element is h = u² on [0, 1] (static); the starting model holds the
    // identity border. With the borders held the fit cannot reach the plant; refitted
    // with the polynomial the error must at least halve.
    let mut lin = model([[0.9, 0.05], [0.0, 0.8]], [0.1, 0.2], [1.0, 0.5], 0.0);
    lin.knots_asc = (0..=8).map(|k| f64::from(k) / 8.0).collect();
    lin.knots_desc = lin.knots_asc.clone();
    lin.border_asc = lin.knots_asc.clone();
    lin.border_desc = lin.knots_asc.clone();
    let u = levels(2000, 5);
    let h_true: Vec<f64> = u.iter().map(|v| v * v).collect();
    let y = quadratic_plant(&h_true);
    let skip = vec![false; u.len()];
    let h_start = lin.nonlinearity_output(&u);
    let fit_with = |borders: Option<Borders>| {
        fit(
            &lin,
            &[0.0, 0.0],
            2,
            &exact(&h_start, &y, &skip, 60, borders),
        )
    };
    let (m0, p0, x0) = fit_with(None)?;
    let held = rms_error(&simulate(&m0, Some(&p0), &h_start, &x0).ok_or("held")?, &y);
    let (m1, p1, x1) = fit_with(Some(Borders {
        u: &u,
        shared: true,
    }))?;
    let h1 = m1.nonlinearity_output(&u);
    let refit = rms_error(&simulate(&m1, Some(&p1), &h1, &x1).ok_or("refit")?, &y);
    assert_eq!(
        m1.border_asc, m1.border_desc,
        "a shared border stays shared"
    );
    assert!(
        refit < 0.5 * held,
        "borders held {held:.3e}, refitted {refit:.3e}"
    );
    Ok(())
}

#[test]
fn two_steady_states_are_found() -> Outcome {
    // x₁⁺ = 1.5 x₁ − 0.5 x₁³ + 0.1 h settles near −1 or +1 for small h depending on where
    // it starts; x₂ follows x₁. An input that visits both wells must expose it.
    let m = model([[1.5, 0.0], [0.5, 0.5]], [0.1, 0.0], [1.0, 0.0], 0.0);
    let monomials = monomials(3, 3);
    let k = monomials.len();
    let cube = monomials
        .iter()
        .position(|e| e.as_slice() == [3, 0, 0])
        .ok_or("x₁³ monomial")?;
    let mut e = vec![0.0; 2 * k];
    e[cube] = -0.5;
    let poly = StatePoly {
        degree: 3,
        center: vec![0.0; 3],
        scale: vec![1.0; 3],
        low: vec![-10.0; 3],
        high: vec![10.0; 3],
        monomials,
        e,
    };
    let h: Vec<f64> = (0..400)
        .map(|t| if (t / 100) % 2 == 0 { 2.0 } else { -2.0 })
        .collect();
    assert!(matches!(
        unique_steady_states(&m, &poly, &h, &[0.0, 0.0]),
        Err(ClassError::Multistable { .. })
    ));
    // Without the cubic term (and a stable A) there is one steady state per level.
    let mut stable = m.clone();
    stable.a[(0, 0)] = 0.5;
    let linear = StatePoly {
        e: vec![0.0; 2 * k],
        ..poly
    };
    unique_steady_states(&stable, &linear, &h, &[0.0, 0.0])?;
    Ok(())
}

#[test]
fn overflow_fit_finds_the_level_and_the_spill() -> Outcome {
    // A cascade whose first store overflows at 3 with 60 % of the excess reaching the
    // second; the start is the same cascade without the overflow (a linear model).
    let truth = Overflow {
        p1: 0.9,
        p2: 0.85,
        c1: 0.0,
        c2: 0.2,
        d: 0.0,
        level: 3.0,
        spill: 0.6,
        x0: [0.0, 0.0],
    };
    let lin = model([[0.9, 0.0], [1.0, 0.85]], [1.0, 0.0], [0.0, 0.2], 0.0);
    let h: Vec<f64> = levels(2000, 3).iter().map(|v| 0.5 * v).collect();
    let y = truth.simulate(&h).ok_or("not simulated")?;
    let (_, peak) = truth.first_store_range(&h);
    assert!(
        peak > 3.5,
        "the test input must make the store overflow (peak {peak})"
    );
    let skip = vec![false; h.len()];
    let data = exact(&h, &y, &skip, 100, None);
    let o = fit_overflow(&lin, &[0.0, 0.0], &data)?;
    let after = rms_error(&o.simulate(&h).ok_or("not simulated")?, &y);
    assert!((o.level - 3.0).abs() < 1e-3, "{o:?}");
    assert!((o.spill - 0.6).abs() < 1e-3, "{o:?}");
    assert!(after < 1e-6, "{after:e}");
    // Complex poles are refused with what the class needs.
    let osc = model([[0.9, -0.3], [0.3, 0.9]], [1.0, 0.0], [0.0, 1.0], 0.0);
    assert!(matches!(
        fit_overflow(&osc, &[0.0, 0.0], &data),
        Err(ClassError::NotTwoRealPoles { .. })
    ));
    Ok(())
}

#[test]
fn monomials_leave_out_pure_input_powers() {
    // Two states and h, degree 2: x1², x1x2, x1h, x2², x2h (h² left out).
    assert_eq!(monomials(3, 2).len(), 5);
    // Degree 3 adds the 10 cubic monomials but h³: 9.
    assert_eq!(monomials(3, 3).len(), 14);
    // One state: x², xh; cubic x³, x²h, xh².
    assert_eq!(monomials(2, 2).len(), 2);
    assert_eq!(monomials(2, 3).len(), 5);
    assert!(monomials(3, 3).iter().all(|m| m[0] + m[1] > 0));
}
