//! The model file's parts of a [`Best`](super::Best): the noise model in the file's form and,
//! when refined, the standard deviations of its poles, μ0 and borders (the identify workflow,
//! `crate::workflow`, writes the whole file).

use crate::model_file::{ModelStd, NoiseFile};
use crate::refine::NoiseModel;
use crate::refine::pem::PemFit;
use crate::refine::uncertainty::{border_covariance, border_std, fit_poles};

/// The noise model in the model file's form.
pub fn noise_file(n: &NoiseModel) -> NoiseFile {
    NoiseFile {
        c: n.c.clone(),
        d: n.d.clone(),
        sigma2: n.sigma2,
    }
}

/// Standard deviations of a refined model (with its mean gap's, from the borders' whole
/// covariance), and the covariance of each pole's `(re, im)`: each pole of the model paired
/// with the nearest root of the refined denominator.
pub fn model_std(fit: &PemFit) -> (ModelStd, Vec<[[f64; 2]; 2]>) {
    let roots = fit_poles(fit);
    let nearest: Vec<_> = fit
        .model
        .poles()
        .into_iter()
        .map(|(re, im)| {
            roots.iter().min_by(|a, b| {
                let d = |p: (f64, f64)| (p.0 - re).hypot(p.1 - im);
                d(a.pole).total_cmp(&d(b.pole))
            })
        })
        .collect();
    let poles = nearest
        .iter()
        .map(|r| r.map_or([f64::NAN; 2], |r| [r.std.0, r.std.1]))
        .collect();
    let cov = nearest
        .iter()
        .map(|r| r.map_or([[f64::NAN; 2]; 2], |r| r.cov))
        .collect();
    let (asc, desc) = border_std(fit);
    // A static element's borders are one: it has no gap.
    let mean_gap = (!fit.layout.shared)
        .then(|| fit.model.mean_gap_std(&border_covariance(fit)))
        .flatten();
    let std = ModelStd {
        poles,
        mu0: asc.first().copied().unwrap_or(f64::NAN),
        border_asc: asc,
        border_desc: desc,
        mean_gap,
    };
    (std, cov)
}
