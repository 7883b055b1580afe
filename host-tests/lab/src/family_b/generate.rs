//! A scenario's records: the estimation and the validation record, the diagnosis's options
//! and the truth (class, declared order, realised ratio, the noise floor of the validation
//! record).

use super::additions::{Additions, clip_level, curve_of};
use super::class::Class;
use super::clean::Clean;
use super::closed_loop;
use super::element::Element;
use super::noise::{Noise, noise, rms, sigma_for, snr_db, variance};
use super::scenario::{Design, ESTIMATION, HOLD, SEGMENTS, Scenario, VALIDATION};
use hsid_host::diagnose::{DiagnoseOptions, Validation};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model;
use hsid_host::model::{Element as ModelElement, Record};

/// What the scenario really is.
#[derive(Clone, Debug, PartialEq)]
pub struct Truth {
    /// The class.
    pub class: Class,
    /// The design drawn from the seed.
    pub design: Design,
    /// The class's additions.
    pub additions: Additions,
    /// The plant's order as declared to the diagnosis (the design's, with the integrator for
    /// the integrating class; the sensor lag is the undeclared pole).
    pub declared_order: usize,
    /// Realised ratio on the estimation and the validation record after their holds, dB.
    pub snr_realised: (f64, f64),
    /// RMS of the noise added over the scored validation samples (spikes not counted).
    pub noise_floor: f64,
    /// RMS of the noise's white innovations over the same samples.
    pub innovation_floor: f64,
}

/// A generated scenario.
#[derive(Clone, Debug)]
pub struct Data {
    /// The estimation record.
    pub record: Record,
    /// The validation record, its hold not scored.
    pub validation: Validation,
    /// The diagnosis's options: uniform knots, the declared order, horizons 12.
    pub options: DiagnoseOptions,
    /// The truth.
    pub truth: Truth,
}

/// Simulates a scenario.
pub fn generate(s: &Scenario) -> Data {
    let design = s.design();
    let add = Additions::draw(s.class, &mut s.rng(1));
    let lens = [(HOLD, ESTIMATION), (HOLD, VALIDATION)];
    let (clean, noises, sigma) = if s.class == Class::ClosedLoop {
        closed_loop::records(s, &design, lens)
    } else {
        open_loop(s, &design, &add, lens)
    };
    let reference = &clean[0].y;
    let curve = curve_of(reference);
    let clip = clip_level(reference);
    let measured = |k: usize| {
        let (c, n) = (&clean[k], &noises[k]);
        let mut spikes = s.rng(10 + k as u64);
        let y: Vec<f64> = (0..c.y.len())
            .map(|t| {
                let y0 = if add.curve { curve(c.y[t]) } else { c.y[t] };
                let mut y = y0 + n.v[t] + add.disturbance(t, sigma);
                if let Some((p, lo, hi)) = add.spikes
                    && spikes.chance(p)
                {
                    let sign = if spikes.chance(0.5) { 1.0 } else { -1.0 };
                    y += sign * spikes.between(lo, hi) * sigma;
                }
                if add.clip { y.min(clip) } else { y }
            })
            .collect();
        Record::from_samples(c.u.iter().copied().zip(y))
    };
    let (record, validation) = (measured(0), measured(1));
    let scored = |x: &[f64]| rms(&x[HOLD.min(x.len())..]);
    let truth = Truth {
        class: s.class,
        declared_order: design.plant.order() + usize::from(add.integrator),
        snr_realised: (
            snr_db(&clean[0].y[HOLD..], &noises[0].v[HOLD..]),
            snr_db(&clean[1].y[HOLD..], &noises[1].v[HOLD..]),
        ),
        noise_floor: scored(&noises[1].v),
        innovation_floor: scored(&noises[1].e),
        additions: add,
        design,
    };
    Data {
        options: options(&truth),
        record,
        validation: Validation::Separate {
            record: validation,
            skip: HOLD,
        },
        truth,
    }
}

/// Input, element, delay and plant for both records, and noise at the design's ratio of the
/// estimation record's noise-free output.
fn open_loop(
    s: &Scenario,
    d: &Design,
    add: &Additions,
    lens: [(usize, usize); 2],
) -> (Vec<Clean>, Vec<Noise>, f64) {
    let plant = add.plant(&d.plant, d.ts).sampled(d.ts);
    let clean: Vec<Clean> = lens
        .iter()
        .enumerate()
        .map(|(k, &(hold, len))| {
            let u = d
                .input
                .generate(&mut s.rng(2 + k as u64), d.range, hold, len);
            let mut el = Element::new(d.kind, d.borders.clone(), u[0]);
            let w: Vec<f64> = u.iter().map(|&v| el.next(v)).collect();
            let y = plant.simulate(&add.delayed(&w));
            Clean { u, y }
        })
        .collect();
    let sigma = sigma_for(variance(&clean[0].y[HOLD..]), d.snr_db);
    let noises = clean
        .iter()
        .enumerate()
        .map(|(k, c)| noise(&mut s.rng(4 + k as u64), d.colour, sigma, c.y.len()))
        .collect();
    (clean, noises, sigma)
}

/// The diagnosis's options for a truth: the element's kind (static for an ordinary input),
/// uniform knots on the range, the declared order, horizons 12, the hold.
pub fn options(t: &Truth) -> DiagnoseOptions {
    let d = &t.design;
    let mut id = IdentifyOptions::uniform(d.range.0, d.range.1, SEGMENTS, HOLD);
    id.order = Some(t.declared_order);
    id.f = 12;
    id.p = 12;
    let kind = match d.kind {
        model::Element::Backlash if t.class != Class::StaticHysteresis => ModelElement::Backlash,
        model::Element::Switch if t.class != Class::StaticHysteresis => ModelElement::Switch,
        _ => ModelElement::Static,
    };
    DiagnoseOptions::new(id, kind)
}
