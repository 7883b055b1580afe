//! Knots where the record has samples, when the user gives none.
//!
//! The paper's experiment (Table I) sweeps both paths over the whole interval, so uniform knots
//! on `[u_min, u_max]` each see many samples. An ordinary record does not: a band-limited or
//! quantised input thins out at the ends of its range, and a path (ascending or descending,
//! the direction δ(t) of the paper) may never visit a part of it. A knot whose basis function
//! no sample of its path reaches cannot be estimated, and one that few samples reach is
//! estimated from those few.
//!
//! So, per path, a segment `(k_{j−1}, k_j]` of the uniform knots with fewer than
//! [`MIN_SEGMENT_SAMPLES`] samples of that path is merged into its neighbour with fewer
//! samples (the knot between them removed), the sparsest first, until every segment has
//! that many or one segment is left. The ends `u_min`, `u_max` stay, so the model keeps the
//! user's interval. A static element has one path: all samples count. Knots the user gives are
//! never moved.

use hsid::Direction;

/// The samples of its path a segment needs to keep its own knot.
pub const MIN_SEGMENT_SAMPLES: usize = 10;

/// The knots of both paths after merging, and what was merged.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotSupport {
    /// Ascending path's knots (the only ones for a static element).
    pub asc: Vec<f64>,
    /// Descending path's knots.
    pub desc: Vec<f64>,
    /// Segments per path before merging.
    pub segments: usize,
    /// Segments removed on the ascending path (on the one path, for a static element).
    pub merged_asc: usize,
    /// Segments removed on the descending path.
    pub merged_desc: usize,
    /// Whether the element has two paths.
    pub two_path: bool,
}

impl KnotSupport {
    /// Whether any segment was merged.
    pub fn merged(&self) -> bool {
        self.merged_asc + self.merged_desc > 0
    }

    /// One line for a report.
    pub fn report(&self) -> String {
        let path = |name: &str, knots: &[f64]| {
            format!(
                "{name} {} segment{}",
                knots.len() - 1,
                if knots.len() == 2 { "" } else { "s" }
            )
        };
        let paths = match self.two_path {
            true => format!(
                "{}, {}",
                path("ascending path", &self.asc),
                path("descending path", &self.desc)
            ),
            false => path("one path", &self.asc),
        };
        format!(
            "knots from the data: of {} uniform segments, those with fewer than \
             {MIN_SEGMENT_SAMPLES} samples of their path were merged into a neighbour: {paths}",
            self.segments
        )
    }
}

/// The segment of `knots` holding `u`: `j` for `k_j < u ≤ k_{j+1}`; `None` at or below the
/// first knot (the μ0 point) and above the last.
fn segment_of(knots: &[f64], u: f64) -> Option<usize> {
    let (first, last) = (*knots.first()?, *knots.last()?);
    if !(u > first && u <= last) {
        return None;
    }
    Some(knots.partition_point(|&k| k < u).saturating_sub(1))
}

/// Merges the segments of `knots` with fewer than `min` of the samples `counts` (one count per
/// segment) into a neighbour, the sparsest first; the ends stay.
fn merge(knots: &[f64], counts: &[usize], min: usize) -> Vec<f64> {
    let mut knots = knots.to_vec();
    let mut counts = counts.to_vec();
    while counts.len() > 1 {
        let Some((j, &c)) = counts.iter().enumerate().min_by_key(|&(_, &c)| c) else {
            break;
        };
        if c >= min {
            break;
        }
        // The neighbour with fewer samples takes the segment (the right one on a tie).
        let right = j + 1 < counts.len() && (j == 0 || counts[j + 1] <= counts[j - 1]);
        let (keep, gone) = if right { (j, j + 1) } else { (j - 1, j) };
        counts[keep] += counts[gone];
        counts.remove(gone);
        // The knot between segments `keep` and `gone` is knot `keep + 1`.
        knots.remove(keep + 1);
    }
    knots
}

/// The knots of `asc` and `desc` (the same uniform knots, or two sets) merged where the
/// samples of `u` after `hold` do not support them; `two_path` false counts every sample on
/// the one path of `asc`.
pub fn supported_knots(
    u: &[f64],
    hold: usize,
    asc: &[f64],
    desc: &[f64],
    two_path: bool,
) -> KnotSupport {
    let segments = asc.len().saturating_sub(1);
    let mut count_asc = vec![0usize; segments];
    let mut count_desc = vec![0usize; desc.len().saturating_sub(1)];
    let mut dir = Direction::default();
    let mut prev = None;
    for (t, &v) in u.iter().enumerate() {
        if let Some(p) = prev {
            dir = dir.next(p, v);
        }
        prev = Some(v);
        if t < hold {
            continue;
        }
        let (knots, counts) = match (two_path, dir) {
            (false, _) | (true, Direction::Ascending) => (asc, &mut count_asc),
            (true, Direction::Descending) => (desc, &mut count_desc),
        };
        if let Some(c) = segment_of(knots, v).and_then(|j| counts.get_mut(j)) {
            *c += 1;
        }
    }
    let new_asc = merge(asc, &count_asc, MIN_SEGMENT_SAMPLES);
    let new_desc = match two_path {
        true => merge(desc, &count_desc, MIN_SEGMENT_SAMPLES),
        false => new_asc.clone(),
    };
    KnotSupport {
        merged_asc: asc.len() - new_asc.len(),
        merged_desc: match two_path {
            true => desc.len() - new_desc.len(),
            false => 0,
        },
        asc: new_asc,
        desc: new_desc,
        segments,
        two_path,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_found_by_their_upper_knot() {
        let k = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(segment_of(&k, 0.0), None);
        assert_eq!(segment_of(&k, 0.5), Some(0));
        assert_eq!(segment_of(&k, 1.0), Some(0));
        assert_eq!(segment_of(&k, 1.0001), Some(1));
        assert_eq!(segment_of(&k, 3.0), Some(2));
        assert_eq!(segment_of(&k, 3.5), None);
    }

    #[test]
    fn a_sparse_segment_joins_its_sparser_neighbour_and_the_ends_stay() {
        let k = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(merge(&k, &[50, 3, 40, 60], 10), vec![0.0, 1.0, 3.0, 4.0]);
        assert_eq!(merge(&k, &[50, 3, 60, 40], 10), vec![0.0, 2.0, 3.0, 4.0]);
        // An empty end segment merges inward; its end knot stays.
        assert_eq!(merge(&k, &[50, 40, 60, 0], 10), vec![0.0, 1.0, 2.0, 4.0]);
        // Two sparse neighbours merge with each other first, and stop once supported.
        assert_eq!(merge(&k, &[50, 6, 5, 60], 10), vec![0.0, 1.0, 3.0, 4.0]);
        // Nothing anywhere: one segment.
        assert_eq!(merge(&k, &[0, 0, 0, 0], 10), vec![0.0, 4.0]);
        assert_eq!(merge(&k, &[10, 10, 10, 10], 10), k.to_vec());
    }

    #[test]
    fn each_path_counts_its_own_samples() {
        // Up from 0 to 4 in steps of 0.01 (ascending, 400 samples over 4 segments), then down
        // only to 2 (descending samples in segments 2 and 3 only: 1 and 0 never visited).
        let mut u: Vec<f64> = (0..=400).map(|i| i as f64 * 0.01).collect();
        u.extend((1..=200).map(|i| 4.0 - i as f64 * 0.01));
        let k = [0.0, 1.0, 2.0, 3.0, 4.0];
        let s = supported_knots(&u, 0, &k, &k, true);
        assert_eq!(s.asc, k.to_vec());
        assert_eq!(s.desc, vec![0.0, 3.0, 4.0]);
        assert_eq!((s.merged_asc, s.merged_desc), (0, 2));
        assert!(s.merged());
        assert!(
            s.report()
                .contains("ascending path 4 segments, descending path 2 segments")
        );
        // One path: every sample counts, nothing merged.
        let s = supported_knots(&u, 0, &k, &k, false);
        assert_eq!((s.asc.clone(), s.desc.clone()), (k.to_vec(), k.to_vec()));
        assert!(!s.merged());
        // The hold's samples do not count: holding at 3.5 supports nothing.
        let held = vec![3.5; 100];
        let s = supported_knots(&held, 100, &k, &k, false);
        assert_eq!(s.asc, vec![0.0, 4.0]);
    }
}
