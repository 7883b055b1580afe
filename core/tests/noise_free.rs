//! End-to-end checks on noise-free data from the paper's plant: the linear part and the
//! borders come back exactly where the borders are piecewise linear on the knots.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use hsid::{Basis, Direction, Excitation, Identifier, Knots, MuZero, Order, Settings};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// y(t) = G(q) w(t) with the paper's G(q) = q⁻¹(0.1994 − 0.1804 q⁻¹)/(1 − 1.8858 q⁻¹ + 0.9048 q⁻²).
struct Plant {
    w: [f64; 3],
    y: [f64; 2],
}

impl Plant {
    fn step(&mut self, w: f64) -> f64 {
        self.w = [w, self.w[0], self.w[1]];
        let y = 1.8858 * self.y[0] - 0.9048 * self.y[1] + 0.1994 * self.w[1] - 0.1804 * self.w[2];
        self.y = [y, self.y[0]];
        y
    }
}

fn true_poles() -> (f64, f64) {
    let (a1, a2) = (-1.8858f64, 0.9048f64);
    (-a1 / 2.0, (a2 - a1 * a1 / 4.0).sqrt())
}

fn poles<const M: usize>(m: &hsid::Model<f64, M>) -> (f64, f64) {
    assert_eq!(m.order(), 2);
    let tr = m.a(0, 0) + m.a(1, 1);
    let det = m.a(0, 0) * m.a(1, 1) - m.a(0, 1) * m.a(1, 0);
    (tr / 2.0, (det - tr * tr / 4.0).max(0.0).sqrt())
}

/// A switch whose borders are piecewise linear on the knots, so the model class is exact.
fn pwl(x: &[f64], v: &[f64], u: f64) -> f64 {
    for i in 0..x.len() - 1 {
        if u <= x[i + 1] {
            return v[i] + (v[i + 1] - v[i]) * (u - x[i]) / (x[i + 1] - x[i]);
        }
    }
    *v.last().unwrap()
}

fn run(basis: Basis, order: Order) -> hsid::Model<f64, 14> {
    run_with(
        basis,
        order,
        MuZero::Hold {
            len: 400,
            settle: 300,
        },
        1e-6,
    )
}

fn run_with(basis: Basis, order: Order, mu0: MuZero<f64>, tol: f64) -> hsid::Model<f64, 14> {
    let knots = Knots::<f64, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    let xa: Vec<f64> = knots.path(Direction::Ascending).to_vec();
    let va = [-1.0, -0.9, -0.5, 0.2, 0.6, 0.8, 0.95, 1.0];
    let vd = [-1.0, -0.7, -0.1, 0.5, 0.85, 0.95, 1.0, 1.1];
    let hold = mu0.hold_len();
    let mut settings = Settings::new(knots, 10, 10, mu0);
    settings.basis = basis;
    settings.order = order;
    let mut id = Identifier::<f64, 14, 20>::new(settings).unwrap();
    let mut plant = Plant {
        w: [0.0; 3],
        y: [0.0; 2],
    };
    let (mut prev, mut dir_up) = (-3.0, false);
    for u in Excitation::new(-3.0, 3.0, hold, Pcg32::seed_from_u64(7))
        .unwrap()
        .take(hold.max(1) + 4019)
    {
        if u > prev {
            dir_up = true;
        } else if u < prev {
            dir_up = false;
        }
        prev = u;
        let w = if dir_up {
            pwl(&xa, &va, u)
        } else {
            pwl(&xa, &vd, u)
        };
        id.push(u, plant.step(w));
    }
    let mut ws = vec![0.0; id.workspace_len()];
    let model = id.solve(&mut ws).unwrap();
    for (i, (&b, &t)) in model
        .border_values(Direction::Ascending)
        .iter()
        .zip(&va)
        .enumerate()
    {
        assert!((b - t).abs() < tol, "asc knot {i}: {b} vs {t}");
    }
    for (i, (&b, &t)) in model
        .border_values(Direction::Descending)
        .iter()
        .zip(&vd)
        .enumerate()
    {
        assert!((b - t).abs() < tol, "desc knot {i}: {b} vs {t}");
    }
    model
}

#[test]
fn exact_model_class_is_recovered_hat() {
    let m = run(Basis::Hat, Order::Auto);
    let (re, im) = poles(&m);
    let (tre, tim) = true_poles();
    assert!(
        (re - tre).abs() < 1e-7 && (im - tim).abs() < 1e-7,
        "{re} {im}"
    );
    assert!((m.static_gain() - 1.0).abs() < 1e-9);
    assert!((m.markov(1) - 0.1994).abs() < 1e-7, "h1 = {}", m.markov(1));
    assert!(m.d().abs() < 1e-7);
    println!("sv {:?}", m.singular_values());
    println!("white {:?}", m.whitened_singular_values());
}

#[test]
fn ramp_basis_gives_the_same_model() {
    let h = run(Basis::Hat, Order::Fixed(2));
    let r = run(Basis::Ramp, Order::Fixed(2));
    for k in 0..20 {
        assert!((h.markov(k) - r.markov(k)).abs() < 1e-9, "h_{k}");
    }
    for (a, b) in h.singular_values().iter().zip(r.singular_values()) {
        assert!((a - b).abs() < 1e-9 * a.abs().max(1.0));
    }
}

/// Without a hold, μ0 comes from the row-centred identification and the means; the start-up
/// transient of the record (x(0) = 0 while H = μ0) is all that separates it from the truth.
#[test]
fn mu0_estimated_without_hold() {
    let m = run_with(Basis::Hat, Order::Fixed(2), MuZero::Estimate, 2e-3);
    assert!((m.mu0() + 1.0).abs() < 2e-3, "mu0 {}", m.mu0());
    let (re, im) = poles(&m);
    let (tre, tim) = true_poles();
    assert!(
        (re - tre).abs() < 1e-6 && (im - tim).abs() < 1e-6,
        "{re} {im}"
    );
}

/// A static (memoryless) nonlinearity with shared knots, driven by an i.i.d. uniform input
/// (no Table I structure, no hold): the borders and μ0 come back exactly up to the start-up
/// transient.
#[test]
fn static_nonlinearity_with_shared_knots() {
    use rand_core::Rng;
    let x = [-3.0, -1.5, 0.0, 1.5, 3.0];
    let v = [-1.0, -0.8, 0.1, 0.7, 0.9];
    let knots = Knots::<f64, 5>::shared(&x).unwrap();
    assert_eq!(knots.channels(), 4);
    let mut s = Settings::new(knots, 10, 10, MuZero::Estimate);
    s.order = Order::Fixed(2);
    let mut id = Identifier::<f64, 5, 20>::new(s).unwrap();
    let mut plant = Plant {
        w: [0.0; 3],
        y: [0.0; 2],
    };
    let mut rng = Pcg32::seed_from_u64(3);
    for _ in 0..5000 {
        let u = -3.0 + 6.0 * (rng.next_u32() as f64 / 4294967296.0);
        id.push(u, plant.step(pwl(&x, &v, u)));
    }
    let mut ws = vec![0.0; id.workspace_len()];
    let m = id.solve(&mut ws).unwrap();
    for dir in [Direction::Ascending, Direction::Descending] {
        for (b, t) in m.border_values(dir).iter().zip(&v) {
            assert!((b - t).abs() < 2e-3, "{dir}: {b} vs {t}");
        }
    }
    let (re, im) = poles(&m);
    let (tre, tim) = true_poles();
    assert!(
        (re - tre).abs() < 1e-6 && (im - tim).abs() < 1e-6,
        "{re} {im}"
    );
}

/// The solve adapts its Schur-complement block to the workspace it gets: the smallest
/// workspace, the default and a generous one give the same model, bit for bit (every entry of
/// the Schur complement is updated by the same dot product whatever the block width).
#[test]
fn workspace_size_changes_speed_not_result() {
    let knots = Knots::<f64, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    let s = Settings::new(
        knots,
        10,
        10,
        MuZero::Hold {
            len: 100,
            settle: 50,
        },
    );
    let mut id = Identifier::<f64, 14, 20>::new(s).unwrap();
    let mut plant = Plant {
        w: [0.0; 3],
        y: [0.0; 2],
    };
    for u in Excitation::new(-3.0, 3.0, 100, Pcg32::seed_from_u64(11))
        .unwrap()
        .take(2100)
    {
        id.push(u, plant.step((u - 1.0f64).atan()) + 1e-3 * (u * 7.0).sin());
    }
    let solve = |len: usize| {
        let mut ws = vec![0.0; len];
        let m = id.solve(&mut ws).unwrap();
        (0..20).map(|k| m.markov(k).to_bits()).collect::<Vec<_>>()
    };
    let small = solve(id.min_workspace_len());
    assert_eq!(small, solve(id.workspace_len()));
    assert_eq!(
        small,
        solve(hsid::workspace_len_with_block(14, 10, 10, 150))
    );
    let mut ws = vec![0.0; id.min_workspace_len() - 1];
    assert!(matches!(
        id.solve(&mut ws),
        Err(hsid::Error::WorkspaceTooSmall { .. })
    ));
}

/// `Identifier::EMPTY` refuses work until configured, then behaves like `new`.
#[test]
fn empty_identifier_is_configured_in_place() {
    let mut id = Identifier::<f64, 14, 20>::EMPTY;
    id.push(0.0, 0.0);
    assert_eq!(id.fault(), Some(hsid::Error::Unconfigured));
    let knots = Knots::<f64, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    id.reset(Settings::new(knots, 10, 10, MuZero::Known(0.0)))
        .unwrap();
    assert_eq!(id.fault(), None);
    assert_eq!(id.samples(), 0);
}
