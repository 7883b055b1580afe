//! `Identifier::new`, `push`, `solve` and `solve_structured` driven by arbitrary bytes read as
//! settings and samples (at most [`MAX_SAMPLES`]). Settings the core refuses are fine; a model
//! either solve returns must be finite.
#![no_main]

use hsid::{
    Basis, Direction, Forgetting, Identifier, Knots, Method, MuZero, Order, Plain, Real, Settings,
};
use libfuzzer_sys::fuzz_target;

/// A small capacity class (6 channels, 10 block rows, horizon 6), so that one input costs
/// well under a millisecond and long runs reach millions of executions. The accumulated Gram
/// matrix has `K·(M + 1)` rows; at the paper's class (16, 24) one input of 4096 samples took
/// seconds. Settings beyond the capacity are still drawn (and refused by `new`).
const M: usize = 6;
const K: usize = 10;
const H: usize = 6;
/// Samples pushed at most: enough to reach a solve at these horizons, few enough for speed.
const MAX_SAMPLES: usize = 1024;

/// A cursor over the fuzzer's bytes; reads past the end give zeros.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        let (&b, rest) = self.0.split_first().unwrap_or((&0, &[]));
        self.0 = rest;
        b
    }
    fn i16(&mut self) -> i16 {
        i16::from_le_bytes([self.u8(), self.u8()])
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
}

fn knots<T: Real>(b: &mut Bytes<'_>, flags: u8) -> Result<Knots<T, M>, hsid::Error> {
    let (n_asc, n_desc) = (usize::from(b.u8() % 8), usize::from(b.u8() % 8));
    let shared = flags & 1 != 0;
    if flags & 2 != 0 {
        // Raw knots: any values, refused unless they increase.
        let mut read = |n: usize| (0..=n).map(|_| T::of(f64::from(b.f32()))).collect();
        let asc: Vec<T> = read(n_asc);
        if shared {
            return Knots::shared(&asc);
        }
        let desc: Vec<T> = read(n_desc);
        return Knots::new(&asc, &desc);
    }
    let (lo, hi) = (f64::from(b.i16()) / 100.0, f64::from(b.i16()) / 100.0);
    let (lo, hi) = (T::of(lo), T::of(hi));
    if shared {
        let k = Knots::<T, M>::uniform(lo, hi, n_asc, n_asc)?;
        return Knots::shared(k.path(Direction::Ascending));
    }
    Knots::uniform(lo, hi, n_asc, n_desc)
}

fn settings<T: Real>(b: &mut Bytes<'_>) -> Result<Settings<T, M>, hsid::Error> {
    let flags = b.u8();
    let knots = knots::<T>(b, flags)?;
    let (f, p) = (usize::from(b.u8() % 8), usize::from(b.u8() % 10));
    let mu0 = match (flags >> 2) & 3 {
        0 => MuZero::Estimate,
        1 => MuZero::Known(T::of(f64::from(b.f32()))),
        _ => MuZero::Hold {
            len: usize::from(b.u8()),
            settle: usize::from(b.u8()),
        },
    };
    let mut s = Settings::new(knots, f, p, mu0);
    s.basis = if flags & 16 != 0 {
        Basis::Ramp
    } else {
        Basis::Hat
    };
    let choice = b.u8();
    s.method = match choice & 3 {
        0 => Method::PiMoesp,
        1 => Method::PoMoesp,
        2 => Method::N4sid,
        _ => Method::Cva,
    };
    if choice & 4 != 0 {
        s.order = Order::Fixed(usize::from(choice >> 5));
    }
    if flags & 32 != 0 {
        s.forgetting = Forgetting::Exponential {
            lambda: T::of(f64::from(b.f32())),
        };
    }
    Ok(s)
}

fn run<T: Real>(mut b: Bytes<'_>) {
    let Ok(s) = settings::<T>(&mut b) else {
        return;
    };
    let (lo, hi) = (s.knots.u_min().to_f64(), s.knots.u_max().to_f64());
    let Ok(mut id) = Identifier::<T, M, K, Plain, H>::new(s) else {
        return;
    };
    let raw = b.u8() & 1 != 0;
    for _ in 0..MAX_SAMPLES {
        if b.0.is_empty() {
            break;
        }
        let (u, y) = if raw {
            (f64::from(b.f32()), f64::from(b.f32()))
        } else {
            // Mostly inside [u_min, u_max], a little outside at the extremes.
            let t = 0.5 + f64::from(b.i16()) / 60000.0;
            (lo + (hi - lo) * t, f64::from(b.i16()) / 1000.0)
        };
        id.push(T::of(u), T::of(y));
    }
    let mut ws = vec![T::ZERO; id.workspace_len()];
    if let Ok(m) = id.solve(&mut ws) {
        assert_finite(&m);
    }
    let mut ws = vec![T::ZERO; id.structured_workspace_len()];
    if let Ok(m) = id.solve_structured(&mut ws) {
        assert_finite(&m);
    }
}

/// Every number of the model is finite.
fn assert_finite<T: Real>(m: &hsid::Model<T, M, H>) {
    let n = m.order();
    let finite = |v: T| v.to_f64().is_finite();
    assert!(
        (0..n).all(|i| (0..n).all(|j| finite(m.a(i, j)))),
        "A not finite"
    );
    assert!(
        m.b().iter().chain(m.c()).all(|&v| finite(v)),
        "B or C not finite"
    );
    assert!(finite(m.d()) && finite(m.mu0()), "D or mu0 not finite");
}

fuzz_target!(|data: &[u8]| {
    let Some((&scalar, rest)) = data.split_first() else {
        return;
    };
    if scalar & 1 == 0 {
        run::<f64>(Bytes(rest));
    } else {
        run::<f32>(Bytes(rest));
    }
});
