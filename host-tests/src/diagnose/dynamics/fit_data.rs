//! What a fit of the dynamics beyond the linear `G` holds fixed and what it fits to.

use crate::diagnose::output_map::OutputMap;
use crate::identify::HostModel;

/// What the fit holds fixed and what it fits to.
pub struct DynamicsFit<'a> {
    /// Output of the input nonlinearity (delay included).
    pub h: &'a [f64],
    /// Target of the linear part's output through the output map: the measured output minus
    /// the additive terms.
    pub y: &'a [f64],
    /// Samples left out of the error (outliers).
    pub skip: &'a [bool],
    /// Output map, held (`None`: identity).
    pub map: Option<&'a OutputMap>,
    /// Whether the initial state is fitted too.
    pub fit_x0: bool,
    /// Largest spectral radius of `A` allowed.
    pub radius_limit: f64,
    /// Iterations of Levenberg–Marquardt.
    pub iterations: usize,
    /// Refit the border values too (`None`: held, `h` as given).
    pub borders: Option<Borders<'a>>,
}

/// The input whose border values are refitted with the dynamics.
#[derive(Clone, Copy, Debug)]
pub struct Borders<'a> {
    /// Input (delay included), the record `h` came from.
    pub u: &'a [f64],
    /// One border for both directions (static nonlinearity).
    pub shared: bool,
}

impl DynamicsFit<'_> {
    /// The fit on the first `n` samples (all of them when there are fewer).
    pub fn prefix(&self, n: usize) -> DynamicsFit<'_> {
        let cut = |s: usize| n.min(s);
        DynamicsFit {
            h: &self.h[..cut(self.h.len())],
            y: &self.y[..cut(self.y.len())],
            skip: &self.skip[..cut(self.skip.len())],
            map: self.map,
            fit_x0: self.fit_x0,
            radius_limit: self.radius_limit,
            iterations: self.iterations,
            borders: self.borders.map(|b| Borders {
                u: &b.u[..cut(b.u.len())],
                shared: b.shared,
            }),
        }
    }

    /// The error the fit minimises for a linear part's output `lin`: the target minus
    /// `g(lin)`, the skipped samples left out; `None` if it is not finite.
    pub fn residual(&self, lin: &[f64]) -> Option<Vec<f64>> {
        let r: Vec<f64> = lin
            .iter()
            .zip(self.y)
            .zip(self.skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| y - self.map.map_or(*l, |g| g.eval(*l)))
            .collect();
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    /// The input nonlinearity's output for a model whose border values may be refitted:
    /// recomputed from [`Borders::u`] if they are (`None` if they are held: `h` as given).
    pub fn refitted_h(&self, m: &HostModel) -> Option<Vec<f64>> {
        self.borders.map(|b| m.nonlinearity_output(b.u))
    }
}

impl Borders<'_> {
    /// Appends a model's border values to `θ`: the ascending ones, then unless shared the
    /// descending ones.
    pub fn pack(&self, m: &HostModel, theta: &mut Vec<f64>) {
        theta.extend_from_slice(&m.border_asc);
        if !self.shared {
            theta.extend_from_slice(&m.border_desc);
        }
    }

    /// Reads the border values [`Borders::pack`] appended back into a model (a shared border
    /// is copied to both directions).
    pub fn unpack(&self, values: &mut impl Iterator<Item = f64>, m: &mut HostModel) {
        for v in m.border_asc.iter_mut() {
            *v = values.next().unwrap_or(*v);
        }
        if self.shared {
            m.border_desc.clone_from(&m.border_asc);
        } else {
            for v in m.border_desc.iter_mut() {
                *v = values.next().unwrap_or(*v);
            }
        }
    }
}
