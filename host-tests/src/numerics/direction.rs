//! The paper's direction signal δ(t) (Section II-B): δ follows the sign of `u(t) − u(t−1)` and
//! keeps its value while `u` does not move, through the core's own [`Direction`].

use hsid::Direction;

/// δ(t) sample by sample: the direction and the previous input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DirectionTracker {
    dir: Direction,
    prev: f64,
}

impl DirectionTracker {
    /// Starts descending (the core's initial direction) with `u_start` as the input before the
    /// first sample.
    pub fn new(u_start: f64) -> Self {
        Self {
            dir: Direction::Descending,
            prev: u_start,
        }
    }

    /// The direction after the input `u`.
    pub fn step(&mut self, u: f64) -> Direction {
        self.dir = self.dir.next(self.prev, u);
        self.prev = u;
        self.dir
    }

    /// The current direction.
    pub fn direction(&self) -> Direction {
        self.dir
    }

    /// The previous input.
    pub fn previous(&self) -> f64 {
        self.prev
    }
}

/// δ(t) of a whole record, starting descending with `u_start` before the first sample.
pub fn directions(u: &[f64], u_start: f64) -> impl Iterator<Item = Direction> + '_ {
    let mut tracker = DirectionTracker::new(u_start);
    u.iter().map(move |&ut| tracker.step(ut))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_sign_of_the_increment_and_holds_when_flat() {
        use Direction::{Ascending as A, Descending as D};
        // From u_start = 0: flat (keeps the initial descending), up, flat (keeps), down, flat.
        let u = [0.0, 1.0, 1.0, 0.5, 0.5, 0.7];
        let got: Vec<Direction> = directions(&u, 0.0).collect();
        assert_eq!(got, [D, A, A, D, D, A]);
        let deltas: Vec<u8> = got.iter().map(|d| d.delta()).collect();
        assert_eq!(deltas, [0, 1, 1, 0, 0, 1]);
    }

    #[test]
    fn the_start_value_decides_the_first_sample() {
        // Below u_start the first sample descends, above it ascends.
        assert_eq!(directions(&[-1.0], 0.0).next(), Some(Direction::Descending));
        assert_eq!(directions(&[1.0], 0.0).next(), Some(Direction::Ascending));
        let mut t = DirectionTracker::new(2.0);
        assert_eq!(t.direction(), Direction::Descending);
        assert_eq!(t.step(3.0), Direction::Ascending);
        assert_eq!(t.step(3.0), Direction::Ascending);
        assert_eq!(t.direction(), Direction::Ascending);
    }
}
