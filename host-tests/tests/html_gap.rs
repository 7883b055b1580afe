//! The gap on the `hsid identify --html` page of the README's servo with `--true-plant`: the
//! gap table holds the cells `identify` prints, the true gap of the plant specification
//! beside them and the identified gaps near it by their standard deviations; the borders
//! figure (`--out` and inline) draws the gap marker with its ends on the two borders.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{Scratch, hsid, p};
use hsid::Direction;
use hsid_host::identify::HostModel;
use hsid_host::model_file::ModelFile;
use scraper::{ElementRef, Html, Selector};

struct Tour {
    _dir: Scratch,
    stdout: String,
    html: String,
    borders_svg: String,
    gap_csv: String,
    model: HostModel,
    /// The gap of the plant specification's element.
    true_gap: f64,
}

/// The README's tour command, once for every test.
fn tour() -> &'static Tour {
    static T: OnceLock<Tour> = OnceLock::new();
    T.get_or_init(|| {
        let dir = Scratch::new("html-gap");
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data");
        let (data, spec) = (root.join("servo.csv"), root.join("servo-backlash.json"));
        let (json, out, page) = (dir.join("m.json"), dir.join("out"), dir.join("r.html"));
        let fixed = "identify --umin -1 --umax 1 --ts 0.01 --input-unit V --output-unit deg";
        let mut args: Vec<&str> = fixed.split(' ').collect();
        args.extend(["--data", p(&data), "--json", p(&json), "--out", p(&out)]);
        args.extend(["--true-plant", p(&spec), "--html", p(&page)]);
        let run = hsid(&args).success();
        let spec: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&spec).unwrap()).unwrap();
        let read = |name: &str| std::fs::read_to_string(out.join(name)).unwrap();
        Tour {
            stdout: run.stdout,
            html: std::fs::read_to_string(&page).unwrap(),
            borders_svg: read("borders.svg"),
            gap_csv: read("borders-gap.csv"),
            model: HostModel::from_json(&ModelFile::load(&json).unwrap()),
            true_gap: spec["element"]["gap"].as_f64().unwrap(),
            _dir: dir,
        }
    })
}

fn sel(s: &str) -> Selector {
    Selector::parse(s).unwrap()
}

fn text(e: ElementRef<'_>) -> String {
    e.text().collect::<String>()
}

/// `v ± s` or `v`: the value and the standard deviation.
fn pm(cell: &str) -> (f64, Option<f64>) {
    match cell.split_once(" ± ") {
        Some((v, s)) => (v.parse().unwrap(), Some(s.parse().unwrap())),
        None => (cell.parse().unwrap(), None),
    }
}

/// Half a unit of the last decimal `cell`'s value is printed with.
fn half_unit(cell: &str) -> f64 {
    let v = cell.split(' ').next().unwrap();
    let decimals = v.split('.').nth(1).map_or(0, str::len) as i32;
    0.5 * 10f64.powi(-decimals)
}

/// The header and rows of the page's gap table (the table whose header names the true gap).
fn gap_table(doc: &Html) -> (Vec<String>, Vec<Vec<String>>) {
    let table = doc
        .select(&sel("section#headline table"))
        .find(|t| t.select(&sel("th")).any(|h| text(h) == "true gap [V]"))
        .expect("a gap table with the true gap");
    let header = table.select(&sel("th")).map(text).collect();
    let rows = table
        .select(&sel("tr"))
        .skip(1)
        .map(|tr| tr.select(&sel("td")).map(text).collect())
        .collect();
    (header, rows)
}

#[test]
fn the_gap_table_holds_the_printed_gaps_and_the_true_gap() {
    let t = tour();
    let doc = Html::parse_document(&t.html);
    let (header, rows) = gap_table(&doc);
    assert_eq!(
        header,
        [
            "u [V]",
            "gap after a descent [V]",
            "gap after an ascent [V]",
            "true gap [V]",
            "loop height [deg]"
        ]
    );
    // The printed lines, `gap at u = U V: D after a descent, A after an ascent (V); loop
    // height H deg`, are the table's rows cell by cell.
    let printed: Vec<Vec<String>> = t
        .stdout
        .lines()
        .filter_map(|l| l.strip_prefix("gap at u = "))
        .map(|l| {
            let (u, rest) = l.split_once(" V: ").unwrap();
            let (d, rest) = rest.split_once(" after a descent, ").unwrap();
            let (a, rest) = rest
                .split_once(" after an ascent (V); loop height ")
                .unwrap();
            let h = rest.strip_suffix(" deg").unwrap();
            [u, d, a, h].map(str::to_string).to_vec()
        })
        .collect();
    assert_eq!(printed.len(), 5, "{}", t.stdout);
    assert_eq!(rows.len(), printed.len() + 1);
    for (row, line) in rows.iter().zip(&printed) {
        assert_eq!([&row[..3], &row[4..]].concat(), *line);
    }
    let m = &t.model;
    for row in &rows[..5] {
        let u: f64 = row[0].parse().unwrap();
        for (cell, dir) in [
            (&row[1], Direction::Descending),
            (&row[2], Direction::Ascending),
        ] {
            // The model file's gap, rounded to its standard deviation.
            let (g, s) = pm(cell);
            let want = m.gap_at(dir, u).unwrap();
            assert!((g - want).abs() <= half_unit(cell), "{cell} against {want}");
            let s = s.unwrap_or_else(|| panic!("no ± in {cell}"));
            assert!(s > 0.002 && s < 0.03, "{cell}");
            // Near the plant's gap by its standard deviation (3σ at each of the ten).
            assert!(
                (g - t.true_gap).abs() < 3.0 * s,
                "{cell} against {}",
                t.true_gap
            );
        }
        // The plant's backlash has the same gap everywhere, in both directions.
        assert_eq!(row[3], format!("{:.5}", t.true_gap), "{row:?}");
    }
    // The mean row: the mean gap within one standard deviation of the true gap, beside it.
    let mean = &rows[5];
    assert_eq!(mean[0], "mean of both directions");
    let (g, s) = pm(&mean[1]);
    let s = s.unwrap();
    assert!(
        (g - t.true_gap).abs() < s,
        "{} against {}",
        mean[1],
        t.true_gap
    );
    assert_eq!(mean[3], format!("{:.5}", t.true_gap));
    assert!(t.stdout.contains(&format!("mean gap {} V\n", mean[1])));
    // And in the facts, after the mean gap.
    let facts: Vec<(String, String)> = doc
        .select(&sel("table.facts tr"))
        .map(|tr| {
            (
                text(tr.select(&sel("th")).next().unwrap()),
                text(tr.select(&sel("td")).next().unwrap()),
            )
        })
        .collect();
    let i = facts
        .iter()
        .position(|f| f.0 == "mean gap (between the borders)")
        .unwrap();
    assert_eq!(facts[i].1, format!("{} V", mean[1]));
    assert_eq!(
        facts[i + 1],
        (
            "true mean gap (--true-plant)".to_string(),
            format!("{:.5} V", t.true_gap)
        )
    );
}

/// The `x y` pairs of a path's `M`/`L` commands, in order.
fn path_points(d: &str) -> Vec<(f64, f64)> {
    d.split(['M', 'L', 'Z'])
        .filter(|s| !s.is_empty())
        .map(|s| {
            let (x, y) = s.trim().split_once(' ').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// The `d` of the element with class `class`.
fn path_of<'a>(svg: &'a str, class: &str) -> &'a str {
    let at = svg
        .find(&format!("class=\"{class}\" d=\""))
        .unwrap_or_else(|| panic!("no {class}"));
    let rest = &svg[at + class.len() + 12..];
    &rest[..rest.find('"').unwrap()]
}

/// The polyline's y at `x` (linear between its points).
fn y_at(line: &[(f64, f64)], x: f64) -> f64 {
    let w = line
        .windows(2)
        .find(|w| (w[0].0.min(w[1].0)..=w[0].0.max(w[1].0)).contains(&x))
        .unwrap_or_else(|| panic!("x = {x} off the line"));
    let (a, b) = (w[0], w[1]);
    a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
}

#[test]
fn the_borders_figure_marks_the_gap_between_the_two_borders() {
    let t = tour();
    let svg = &t.borders_svg;
    let m = &t.model;
    // The marker's ends in data coordinates: the reversal at the middle of [−1, 1] on P_d,
    // and where P_a takes the same value.
    let at = svg.find("<g class=\"gap-marker\"").expect("a gap marker");
    let g = &svg[at..at + svg[at..].find("</g>").unwrap()];
    let attr = |name: &str| -> (f64, f64) {
        let v = g.split(&format!("{name}=\"")).nth(1).unwrap();
        let v = &v[..v.find('"').unwrap()];
        let (x, y) = v.split_once(' ').unwrap();
        (x.parse().unwrap(), y.parse().unwrap())
    };
    let (from, to) = (attr("data-from"), attr("data-to"));
    assert_eq!(from.0, 0.0);
    assert_eq!(from.1, m.border_desc_at(0.0));
    assert_eq!(to.1, from.1);
    assert!((m.border_asc_at(to.0) - to.1).abs() < 1e-9, "{to:?}");
    let gap = m.gap_at(Direction::Descending, 0.0).unwrap();
    assert!((to.0 - from.0 - gap).abs() < 1e-12);
    // Its label: the table's gap after a descent at u = 0, with the unit.
    let doc = Html::parse_document(&t.html);
    let (_, rows) = gap_table(&doc);
    let middle = rows.iter().find(|r| r[0] == "0.00000").unwrap();
    assert!(g.contains(&format!(">gap {} V</text>", middle[1])), "{g}");
    // borders-gap.csv: the same numbers.
    let values: Vec<f64> = t
        .gap_csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(values[..4], [from.0, to.0, from.1, to.0 - from.0]);
    // Drawn: the arrow's tips (the first points of the heads' sub-paths) lie on the drawn
    // borders, in px: the first on P_d, the second on P_a, level with each other.
    let heads = g.split("<path d=\"").nth(2).unwrap();
    let tips: Vec<(f64, f64)> = heads[..heads.find('"').unwrap()]
        .split('Z')
        .filter(|s| !s.is_empty())
        .map(|s| path_points(s)[0])
        .collect();
    assert_eq!(tips.len(), 2);
    let desc = path_points(path_of(svg, "border-desc"));
    let asc = path_points(path_of(svg, "border-asc"));
    assert!((y_at(&desc, tips[0].0) - tips[0].1).abs() < 0.5, "{tips:?}");
    assert!((y_at(&asc, tips[1].0) - tips[1].1).abs() < 0.5, "{tips:?}");
    assert_eq!(tips[0].1, tips[1].1);
    // The gap is about 0.2 of the 2 V wide axis: tens of px, not a sliver.
    assert!(tips[1].0 - tips[0].0 > 40.0, "{tips:?}");
    // The page inlines the same figure, and the detail around the marker.
    assert!(t.html.contains(&g[..g.find('>').unwrap()]));
    assert!(t.html.contains("The identified loop around the gap"));
}
