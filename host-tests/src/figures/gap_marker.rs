//! The gap drawn on a borders figure: a reversal after a descent at the middle of the input
//! interval. Arriving there on the falling border, at `(u, P_d(u))`, the input must climb by
//! the gap before the rising border reaches that value: the arrow runs level from the falling
//! border to the rising one, `(u + gap, P_d(u))`, and is labelled with the gap and its
//! standard deviation in input units. Its ends are written to `borders-gap.csv`.

use hsid::Direction;

use super::csv::Table;
use super::settings::FigureSettings;
use crate::identify::HostModel;
use crate::plot::Series;
use crate::units::gap_text;

/// The colour of the marker.
const COLOR: &str = "#111111";

/// One reversal with its gap, in the figure's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GapMarker {
    /// The input where the input reverses (after a descent).
    pub(super) u: f64,
    /// The border value there, `P_d(u)`: the level of the arrow.
    pub(super) level: f64,
    /// The gap after a descent at `u` (input units): the rising border takes `level` at
    /// `u + gap`.
    pub(super) gap: f64,
    /// Its standard deviation, when known.
    pub(super) std: Option<f64>,
}

impl GapMarker {
    /// The reversal at the middle of `m`'s input interval, with the standard deviation
    /// `std(u)` of the gap after a descent at `u`; `None` where the gap is not defined, and
    /// for a static element (its two borders one: no gap).
    pub(super) fn at_middle(m: &HostModel, std: impl Fn(f64) -> Option<f64>) -> Option<Self> {
        if m.knots_asc == m.knots_desc && m.border_asc == m.border_desc {
            return None;
        }
        let u = 0.5 * (m.u_min() + m.u_max());
        let gap = m.gap_at(Direction::Descending, u)?;
        Some(GapMarker {
            u,
            level: m.border_desc_at(u),
            gap,
            std: std(u),
        })
    }

    /// The arrow's ends: on the falling border, then on the rising one.
    pub(super) fn ends(&self) -> ((f64, f64), (f64, f64)) {
        ((self.u, self.level), (self.u + self.gap, self.level))
    }

    /// The arrow, labelled `gap 0.192 ± 0.013 V` (the unit from `s`).
    pub(super) fn series(&self, s: &FigureSettings) -> Series {
        let unit = s.units.as_ref().map_or("", |u| u.0.trim());
        let text = format!("gap {} {unit}", gap_text(Some(self.gap), self.std));
        let (from, to) = self.ends();
        Series::arrow(from, to, text.trim_end())
            .color(COLOR)
            .width(1.8)
            .class("gap-marker")
    }

    /// `borders-gap.csv`: the reversal, the input where the rising border takes its value,
    /// the level, the gap and its standard deviation (when known).
    pub(super) fn table(&self, s: &FigureSettings) -> Table {
        let mut t = Table::default();
        t.col(s.input("u reversal"), vec![self.u]);
        t.col(s.input("u + gap"), vec![self.u + self.gap]);
        t.col(s.output("level"), vec![self.level]);
        t.col(s.input("gap"), vec![self.gap]);
        if let Some(sd) = self.std {
            t.col(s.input("sd gap"), vec![sd]);
        }
        t
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::units::gain::tests::first_order;

    #[test]
    fn the_arrow_runs_level_from_the_falling_border_to_the_rising_one() {
        // P_a = 2u − 0.4, P_d = 2u + 0.2 on knots −1, 0, 1: after a descent to 0 (P_d = 0.2)
        // the input climbs to 0.3 before P_a reaches 0.2: the gap is 0.3.
        let k = [-1.0, 0.0, 1.0];
        let m = first_order(
            0.9,
            0.1,
            k.iter().map(|u| 2.0 * u - 0.4).collect(),
            k.iter().map(|u| 2.0 * u + 0.2).collect(),
        );
        let g = GapMarker::at_middle(&m, |_| Some(0.0123)).unwrap();
        let ((u0, y0), (u1, y1)) = g.ends();
        assert_eq!((u0, y0), (0.0, m.border_desc_at(0.0)));
        assert!((y0 - 0.2).abs() < 1e-12 && (u1 - 0.3).abs() < 1e-12 && y1 == y0);
        assert!((m.border_asc_at(u1) - y1).abs() < 1e-12);
        let s = FigureSettings {
            units: Some(("V".into(), "deg".into())),
            ..FigureSettings::default()
        };
        let svg = crate::plot::Figure::new("")
            .with(g.series(&s))
            .to_svg()
            .unwrap();
        assert!(svg.contains("gap 0.300 ± 0.012 V"), "{svg}");
        let data = format!(r#"class="gap-marker" data-from="0 {y0}" data-to="{u1} {y1}""#);
        assert!(svg.contains(&data), "{svg}");
        // A static element has no gap to mark.
        let one = first_order(0.9, 0.1, m.border_asc.clone(), m.border_asc.clone());
        assert_eq!(GapMarker::at_middle(&one, |_| None), None);
    }
}
