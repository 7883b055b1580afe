//! The order in which the Schur complement's step walks the columns of the cross block with a
//! cache of a few of them, chosen for the least estimated work.

use super::layout::Layout;

/// How step 2 of [`pi_moesp`](super::pi_moesp) walks the `q` columns of `X = L₁₁⁻¹ G_{Z_f Q}` with a cache of
/// a few of them: panels of `width` columns, each computed once and kept while the Schur
/// complement's rows of the panel are formed, and the columns left of a panel regenerated
/// `stream` at a time next to it. The pairs of columns, and so the result, are the same for
/// every schedule; the work is not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Schedule {
    /// Columns per panel.
    pub(super) width: usize,
    /// Columns regenerated at a time (`width + stream` fit in the cache).
    pub(super) stream: usize,
}

impl Schedule {
    /// The schedule of least estimated work for a cache of `cols` columns: a regenerated
    /// column costs a forward substitution (`(f·m)²/2` multiply-adds), a pass over the lagged
    /// sums about `k²·m²` (`k = f + p` block rows: `k²/2` blocks of about `m²` entries, each
    /// corrected and scattered).
    pub(super) fn choose(lay: Layout, cols: usize) -> Self {
        let q = lay.q();
        let column = (lay.fm() * lay.fm() / 2) as u64;
        let k = (lay.f + lay.p) as u64;
        let pass = k * k * (lay.m * lay.m) as u64;
        let mut best = Self {
            width: 1,
            stream: 1,
        };
        let mut best_cost = u64::MAX;
        let mut last = 0;
        for panels in 1..=q {
            let width = q.div_ceil(panels);
            let Some(stream) = cols.checked_sub(width) else {
                continue;
            };
            if (stream == 0 && width < q) || width == last {
                continue;
            }
            last = width;
            let plan = Self { width, stream };
            let (regenerated, passes) = plan.work(q);
            let cost = (regenerated as u64)
                .saturating_mul(column)
                .saturating_add((passes as u64).saturating_mul(pass));
            if cost < best_cost {
                (best, best_cost) = (plan, cost);
            }
        }
        best
    }

    /// Columns regenerated and passes over the lagged sums for `q` columns.
    pub(super) fn work(self, q: usize) -> (usize, usize) {
        let (mut regenerated, mut passes) = (0, 0);
        for p0 in (0..q).step_by(self.width.max(1)) {
            regenerated += p0;
            passes += 1 + p0.div_ceil(self.stream.max(1));
        }
        (regenerated, passes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's layout with the default workspace: B_f, the two blocks of 32 columns and
    /// the scratch less the raw diagonals hold 83 columns of 140, so two panels of 75 with 8
    /// columns streamed, 75 columns regenerated in 12 passes (the two-block walk regenerated
    /// 320 columns in 16 passes, B_f's included).
    #[test]
    fn schedule_of_the_paper_layout() {
        let lay = Layout::new(14, 10, 10);
        let cols = (lay.bf() + lay.cache() + lay.scratch() - lay.q()) / lay.fm();
        assert_eq!(cols, 83);
        let plan = Schedule::choose(lay, cols);
        assert_eq!(
            plan,
            Schedule {
                width: 75,
                stream: 8
            }
        );
        assert_eq!(plan.work(lay.q()), (75, 12));
    }

    /// Every cache from the smallest (two columns) to more than `q`: the schedule fits it,
    /// streams whenever there is more than one panel, and one panel holds all when it can.
    #[test]
    fn schedule_fits_every_cache() {
        let lay = Layout::new(14, 10, 10);
        let q = lay.q();
        for cols in 2..=q + 10 {
            let plan = Schedule::choose(lay, cols);
            assert!(
                plan.width >= 1 && plan.width + plan.stream <= cols,
                "{cols}: {plan:?}"
            );
            assert!(plan.width >= q || plan.stream >= 1, "{cols}: {plan:?}");
            if cols >= q {
                assert_eq!(plan.work(q), (0, 1), "{cols}: {plan:?}");
            }
        }
    }
}
