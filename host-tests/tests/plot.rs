//! Tests of the SVG figures: well-formed output, nice ticks, missing data, and the paper's three
//! figure kinds on the paper's example system.
//!
//! The sample figures are written to `$TMPDIR/hsid-plot-tests/` so they can be looked at.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;
use std::path::PathBuf;

use hsid_host::paper::figures::{bode_magnitude_plot, border_plot, pole_plot};
use hsid_host::plot::{
    Dash, Figure, LegendPosition, Marker, PlotError, Series, log_ticks, nice_step, nice_ticks,
};

fn out_dir() -> PathBuf {
    let dir = std::env::temp_dir().join("hsid-plot-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small XML well-formedness check: balanced and properly nested tags, quoted attributes,
/// known entities only, one root element `svg`, nothing but whitespace around it.
fn check_well_formed(svg: &str) {
    assert!(svg.starts_with("<svg"), "does not start with <svg");
    let mut stack: Vec<String> = Vec::new();
    let mut roots = 0;
    let mut rest = svg;
    while let Some(lt) = rest.find('<') {
        check_text(&rest[..lt]);
        if stack.is_empty() {
            assert!(
                rest[..lt].trim().is_empty(),
                "text outside the root element"
            );
        }
        let gt = rest[lt..].find('>').expect("unclosed <") + lt;
        let tag = &rest[lt + 1..gt];
        rest = &rest[gt + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().expect("closing tag without opening tag");
            assert_eq!(open, name.trim(), "mismatched closing tag");
            continue;
        }
        assert!(
            !tag.starts_with('!') && !tag.starts_with('?'),
            "unexpected <{tag}>"
        );
        let self_closing = tag.ends_with('/');
        let body = tag.trim_end_matches('/');
        let name_end = body.find(char::is_whitespace).unwrap_or(body.len());
        let name = &body[..name_end];
        assert!(
            !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-'),
            "bad tag name {name:?}"
        );
        check_attributes(&body[name_end..]);
        if stack.is_empty() {
            roots += 1;
            assert_eq!(name, "svg", "root element is not svg");
        }
        if !self_closing {
            stack.push(name.to_string());
        }
    }
    assert!(rest.trim().is_empty(), "text after the root element");
    assert!(stack.is_empty(), "unclosed tags {stack:?}");
    assert_eq!(roots, 1);
}

fn check_attributes(mut s: &str) {
    loop {
        s = s.trim_start();
        if s.is_empty() {
            return;
        }
        let eq = s.find('=').expect("attribute without value");
        let name = s[..eq].trim();
        assert!(
            !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == ':'),
            "bad attribute name {name:?}"
        );
        let after = &s[eq + 1..];
        let quote = after.chars().next().expect("missing attribute value");
        assert!(quote == '"' || quote == '\'', "unquoted attribute {name}");
        let end = after[1..].find(quote).expect("unterminated attribute") + 1;
        let value = &after[1..end];
        assert!(!value.contains('<'), "< in attribute {name}");
        check_text(value);
        s = &after[end + 1..];
    }
}

fn check_text(t: &str) {
    let mut rest = t;
    while let Some(amp) = rest.find('&') {
        let semi = rest[amp..].find(';').expect("unterminated entity") + amp;
        let entity = &rest[amp + 1..semi];
        assert!(
            ["amp", "lt", "gt", "quot", "apos"].contains(&entity),
            "unknown entity &{entity};"
        );
        rest = &rest[semi + 1..];
    }
    assert!(!t.contains('>'), "raw > in text");
}

/// No NaN or infinity may reach the SVG text.
fn check_no_nan(svg: &str) {
    for bad in ["NaN", "nan", "inf"] {
        assert!(!svg.contains(bad), "SVG contains {bad}");
    }
}

/// Numbers of the attribute `attr` of every element `tag`.
fn attr_values(svg: &str, tag: &str, attr: &str) -> Vec<String> {
    let mut out = Vec::new();
    let open = format!("<{tag} ");
    for part in svg.split(&open).skip(1) {
        let body = &part[..part.find('>').unwrap()];
        let key = format!(" {attr}=\"");
        if let Some(p) = body
            .find(&key)
            .or_else(|| body.starts_with(&key[1..]).then_some(0).map(|_| 0))
        {
            let start = if body.starts_with(&key[1..]) && p == 0 {
                key.len() - 1
            } else {
                p + key.len()
            };
            let end = body[start..].find('"').unwrap() + start;
            out.push(body[start..end].to_string());
        }
    }
    out
}

/// Text content of all `<text>` elements (without nested tspans' markup).
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .map(|p| {
            let start = p.find('>').unwrap() + 1;
            let end = p.find("</text>").unwrap();
            let inner = &p[start..end];
            // Drop tspan markup, keep its text.
            let mut s = String::new();
            let mut in_tag = false;
            for c in inner.chars() {
                match c {
                    '<' => in_tag = true,
                    '>' => in_tag = false,
                    c if !in_tag => s.push(c),
                    _ => {}
                }
            }
            s
        })
        .collect()
}

// ----- the paper's example system -------------------------------------------------------------

/// G(q) = q⁻¹ (0.1994 − 0.1804 q⁻¹) / (1 − 1.8858 q⁻¹ + 0.9048 q⁻²), magnitude in dB.
fn paper_bode_db(w: f64) -> f64 {
    // z⁻¹ = e^{-jw}
    let (c1, s1) = (w.cos(), -w.sin());
    let (c2, s2) = ((2.0 * w).cos(), -(2.0 * w).sin());
    // numerator 0.1994 z^-1 - 0.1804 z^-2
    let nr = 0.1994 * c1 - 0.1804 * c2;
    let ni = 0.1994 * s1 - 0.1804 * s2;
    let dr = 1.0 - 1.8858 * c1 + 0.9048 * c2;
    let di = -1.8858 * s1 + 0.9048 * s2;
    20.0 * ((nr * nr + ni * ni).sqrt() / (dr * dr + di * di).sqrt()).log10()
}

fn paper_poles() -> [(f64, f64); 2] {
    let re: f64 = 1.8858 / 2.0;
    let im = (0.9048 - re * re).sqrt();
    [(re, im), (re, -im)]
}

/// Deterministic pseudo-random normal numbers (xorshift + Box–Muller).
struct Noise(u64);
impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform(), self.uniform());
        (-2.0 * a.ln()).sqrt() * (2.0 * PI * b).cos()
    }
}

fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / (n - 1) as f64))
        .collect()
}

fn switch_borders(u: f64) -> (f64, f64) {
    let h0 = 0.5 * (3f64.atan() - 1f64.atan());
    let clamp = |v: f64| {
        if u <= -2.0 {
            -1.0
        } else if u > 2.0 {
            1.0
        } else {
            v
        }
    };
    (clamp((u - 1.0).atan() + h0), clamp((u + 1.0).atan() - h0))
}

// ----- the three figure functions -----------------------------------------------------------

#[test]
fn pole_plot_full_and_zoomed() {
    let truth = paper_poles();
    let mut noise = Noise(42);
    let mut est = Vec::new();
    for _ in 0..100 {
        for &(re, im) in &truth {
            est.push((re + 0.004 * noise.normal(), im + 0.006 * noise.normal()));
        }
    }
    est.push((f64::NAN, 0.1));
    let dir = out_dir();
    let full = dir.join("poles_full.svg");
    pole_plot(
        &full,
        "Switch nonlinearity: eigenvalues of the estimated A",
        &truth,
        &est,
        None,
    )
    .unwrap();
    let zoom = dir.join("poles_zoom.svg");
    pole_plot(
        &zoom,
        "Switch nonlinearity: eigenvalues of the estimated A (zoom)",
        &truth,
        &est,
        Some((0.9, 0.99, -0.18, 0.18)),
    )
    .unwrap();
    for p in [&full, &zoom] {
        let svg = std::fs::read_to_string(p).unwrap();
        check_well_formed(&svg);
        check_no_nan(&svg);
        let t = texts(&svg);
        assert!(t.iter().any(|s| s == "true poles"));
        assert!(t.iter().any(|s| s == "estimated poles"));
        assert!(t.iter().any(|s| s == "Real part"));
    }
    // The full view shows the whole unit circle: ticks at −1 and 1 on the y axis.
    let t = texts(&std::fs::read_to_string(&full).unwrap());
    assert!(t.iter().any(|s| s == "\u{2212}1.0"), "{t:?}");
    assert!(t.iter().any(|s| s == "1.0"), "{t:?}");
}

#[test]
fn pole_plot_without_estimates() {
    let dir = out_dir();
    let p = dir.join("poles_true_only.svg");
    pole_plot(&p, "", &paper_poles(), &[], None).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    assert!(!texts(&svg).iter().any(|s| s == "estimated poles"));
}

#[test]
fn bode_plot_of_the_paper_system() {
    let w = logspace(-3.0, PI.log10(), 400);
    let truth: Vec<f64> = w.iter().map(|&w| paper_bode_db(w)).collect();
    let mut noise = Noise(7);
    let est: Vec<f64> = truth
        .iter()
        .map(|v| v + 0.3 + 0.05 * noise.normal())
        .collect();
    let p = out_dir().join("bode.svg");
    bode_magnitude_plot(
        &p,
        "Switch nonlinearity: Bode magnitude",
        &w,
        &[("true system", &truth), ("estimated (average)", &est)],
    )
    .unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    check_no_nan(&svg);
    let t = texts(&svg);
    // Decade labels 10^-3 .. 10^0 with a typographic minus.
    for label in ["10\u{2212}3", "10\u{2212}2", "10\u{2212}1", "100"] {
        assert!(t.iter().any(|s| s == label), "missing {label}: {t:?}");
    }
    assert!(t.iter().any(|s| s == "Frequency (rad/sample)"));
    assert!(t.iter().any(|s| s == "Magnitude (dB)"));
}

#[test]
fn border_plot_of_the_switch() {
    let u: Vec<f64> = (0..=600).map(|i| -3.0 + 0.01 * i as f64).collect();
    let (pa, pd): (Vec<f64>, Vec<f64>) = u.iter().map(|&u| switch_borders(u)).unzip();
    // A piecewise-linear "estimate" through 8 knots on [-3, 3].
    let knots: Vec<f64> = (0..=7).map(|i| -3.0 + 6.0 * i as f64 / 7.0).collect();
    let interp = |k: &[f64], v: &[f64], x: f64| {
        let i = k.windows(2).position(|w| x <= w[1]).unwrap_or(k.len() - 2);
        let t = (x - k[i]) / (k[i + 1] - k[i]);
        v[i] + t * (v[i + 1] - v[i])
    };
    let ka: Vec<f64> = knots.iter().map(|&x| switch_borders(x).0 + 0.02).collect();
    let kd: Vec<f64> = knots.iter().map(|&x| switch_borders(x).1 - 0.02).collect();
    let ea: Vec<f64> = u.iter().map(|&x| interp(&knots, &ka, x)).collect();
    let ed: Vec<f64> = u.iter().map(|&x| interp(&knots, &kd, x)).collect();
    let p = out_dir().join("border.svg");
    border_plot(
        &p,
        "Switch nonlinearity: H[·] and its average estimate",
        &u,
        &[
            ("true P_a", &pa),
            ("true P_d", &pd),
            ("estimated P_a (average)", &ea),
            ("estimated P_d (average)", &ed),
        ],
    )
    .unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    check_no_nan(&svg);
    let t = texts(&svg);
    for label in ["\u{2212}3", "\u{2212}2", "\u{2212}1", "0", "1", "2", "3"] {
        assert!(
            t.iter().any(|s| s == label),
            "missing x tick {label}: {t:?}"
        );
    }
    assert!(svg.contains("stroke-dasharray"));
}

// ----- ticks --------------------------------------------------------------------------------

fn assert_nice(ticks: &[f64], lo: f64, hi: f64) {
    assert!(ticks.len() >= 2, "too few ticks {ticks:?} for [{lo}, {hi}]");
    let step = ticks[1] - ticks[0];
    let mag = 10f64.powf(step.log10().floor());
    let m = step / mag;
    assert!(
        [1.0, 2.0, 5.0, 10.0].iter().any(|n| (m - n).abs() < 1e-6),
        "step {step} of {ticks:?} is not 1, 2 or 5 × 10^k"
    );
    for (i, t) in ticks.iter().enumerate() {
        assert!(*t >= lo - 1e-12 * hi.abs().max(1.0) && *t <= hi + 1e-12 * hi.abs().max(1.0));
        let k = t / step;
        assert!(
            (k - k.round()).abs() < 1e-6,
            "{t} is not a multiple of {step}"
        );
        // Prints short: no 0.30000000000000004.
        let text = format!("{t}");
        assert!(text.len() <= 12, "{text} does not print short");
        if i > 0 {
            assert!((t - ticks[i - 1] - step).abs() < 1e-9 * step.max(1.0));
        }
    }
}

#[test]
fn ticks_are_nice() {
    let cases = [
        (0.0, 1.0),
        (-3.0, 3.0),
        (-1.05, 1.05),
        (0.1, 0.7),
        (-27.3, 14.2),
        (0.0, 6601.0),
        (1e-6, 7e-6),
        (123456.0, 123470.0),
        (-0.0031, 0.0047),
        (0.9, 0.99),
        (-8.81, 8.81),
        (0.0, 1e9),
    ];
    for (lo, hi) in cases {
        for target in [3, 5, 8, 10] {
            let t = nice_ticks(lo, hi, target);
            assert_nice(&t, lo, hi);
            assert!(
                t.len() <= target + 1,
                "{t:?} has more than {target}+1 ticks"
            );
        }
    }
    assert_eq!(nice_ticks(0.0, 1.0, 5), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    assert_eq!(
        nice_ticks(-3.0, 3.0, 6),
        vec![-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0]
    );
    assert_eq!(
        nice_ticks(0.1, 0.7, 6),
        vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]
    );
    assert_eq!(nice_step(10.0, 4.0), 5.0);
    assert_eq!(nice_step(1.0, 5.0), 0.2);
    assert!(nice_ticks(f64::NAN, 1.0, 5).is_empty());
    assert!(nice_ticks(2.0, 1.0, 5).is_empty());
    assert_eq!(nice_ticks(2.0, 2.0, 5), vec![2.0]);
}

#[test]
fn log_ticks_for_bode_range() {
    let (major, minor) = log_ticks(1e-3, PI, 8.0);
    assert_eq!(major, vec![1e-3, 1e-2, 1e-1, 1.0]);
    assert!(minor.contains(&0.002) && minor.contains(&3.0) && !minor.contains(&4.0));
    let (major, _) = log_ticks(0.5, 3.0, 8.0);
    assert_eq!(major, vec![0.5, 1.0, 2.0]);
    let (major, _) = log_ticks(1e-12, 1e12, 6.0);
    assert!(major.len() <= 7, "{major:?}");
    assert!(log_ticks(0.0, 1.0, 5.0).0.is_empty());
}

#[test]
fn rendered_axis_ticks_are_nice() {
    let x: Vec<f64> = (0..50).map(|i| 0.37 + 0.113 * i as f64).collect();
    let y: Vec<f64> = x.iter().map(|v| 1000.0 * v.sin() - 37.0).collect();
    let svg = Figure::new("t")
        .with(Series::line(&x, &y))
        .to_svg()
        .unwrap();
    let labels: Vec<f64> = texts(&svg)
        .iter()
        .filter_map(|s| s.replace('\u{2212}', "-").parse().ok())
        .collect();
    // x labels first, then y labels.
    let split = labels.windows(2).position(|w| w[1] < w[0]).unwrap() + 1;
    let (xl, yl) = labels.split_at(split);
    assert_nice(xl, 0.0, 6.0);
    assert_nice(yl, -2000.0, 2000.0);
    assert!(xl.len() >= 4 && yl.len() >= 4, "{labels:?}");
}

// ----- missing data and errors --------------------------------------------------------------

#[test]
fn nan_and_infinity_are_skipped() {
    let x = [0.0, 1.0, 2.0, f64::NAN, 4.0, 5.0, 6.0];
    let y = [0.0, 1.0, f64::INFINITY, 3.0, 4.0, f64::NAN, 6.0];
    let mut fig = Figure::new("gaps").x_label("x").y_label("y");
    fig.push(Series::line(&x, &y).label("line"));
    fig.push(Series::scatter(&x, &y, Marker::Circle).label("markers"));
    fig.push(Series::band(&x, &[-1.0; 7], &y).label("band"));
    let svg = fig.to_svg().unwrap();
    check_well_formed(&svg);
    check_no_nan(&svg);
    // The line is broken into sub-paths: (0,1), (4) and (6) → three "M".
    let d = attr_values(&svg, "path", "d");
    let line = d
        .iter()
        .find(|d| d.starts_with('M') && d.contains('L') && !d.contains('Z') && !d.contains('a'))
        .unwrap();
    assert_eq!(line.matches('M').count(), 3, "{line}");
    // Only the two first points of the band are valid together: one polygon.
    let band = d.iter().find(|d| d.ends_with('Z')).unwrap();
    assert_eq!(band.matches('Z').count(), 1, "{band}");
    std::fs::write(out_dir().join("nan.svg"), &svg).unwrap();
}

#[test]
fn all_nan_and_empty_figures_still_render() {
    let nan = [f64::NAN; 3];
    for fig in [
        Figure::new("all missing").with(Series::line(&nan, &nan).label("nothing")),
        Figure::new("empty"),
        Figure::new("log, empty").log_x(true),
        Figure::new("log, non-positive")
            .log_x(true)
            .with(Series::line(&[0.0, -1.0], &[1.0, 2.0])),
        Figure::new("one point").with(Series::scatter(&[3.0], &[3.0], Marker::Dot)),
    ] {
        let svg = fig.to_svg().unwrap();
        check_well_formed(&svg);
        check_no_nan(&svg);
    }
}

#[test]
fn errors() {
    let err = Figure::new("t")
        .with(Series::line(&[1.0, 2.0], &[1.0]).label("bad"))
        .to_svg()
        .unwrap_err();
    assert!(matches!(err, PlotError::LengthMismatch { series: 0, .. }));
    assert_eq!(
        err.to_string(),
        "series 0 (\"bad\"): x has 2 values, y has 1"
    );
    let err = Figure::new("t")
        .with(Series::band(&[1.0, 2.0], &[1.0, 2.0], &[1.0]))
        .to_svg()
        .unwrap_err();
    assert!(matches!(err, PlotError::LengthMismatch { .. }));
    let err = Figure::new("t").x_range(1.0, 1.0).to_svg().unwrap_err();
    assert!(matches!(err, PlotError::InvalidRange { axis: "x", .. }));
    let err = Figure::new("t")
        .log_x(true)
        .x_range(0.0, 1.0)
        .to_svg()
        .unwrap_err();
    assert!(matches!(err, PlotError::InvalidRange { axis: "x", .. }));
    let err = Figure::new("t")
        .y_range(f64::NAN, 1.0)
        .to_svg()
        .unwrap_err();
    assert!(matches!(err, PlotError::InvalidRange { axis: "y", .. }));
    let err = Figure::new("t").size(100, 100).to_svg().unwrap_err();
    assert!(matches!(err, PlotError::InvalidSize { .. }));
    let err = Figure::new("t").save("/nonexistent/dir/f.svg").unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }));
    let err = border_plot("/tmp/never.svg", "t", &[1.0, 2.0], &[("a", &[1.0][..])]).unwrap_err();
    assert!(matches!(err, PlotError::LengthMismatch { .. }));
}

#[test]
fn text_is_escaped() {
    let svg = Figure::new("a < b & \"c\" > 'd'")
        .x_label("<x>")
        .with(Series::line(&[0.0, 1.0], &[0.0, 1.0]).label("y & z"))
        .to_svg()
        .unwrap();
    check_well_formed(&svg);
    assert!(svg.contains("a &lt; b &amp; &quot;c&quot; &gt; &apos;d&apos;"));
    assert!(svg.contains("y &amp; z"));
}

#[test]
fn legend_avoids_the_data() {
    // Data fills the upper right: the legend must go elsewhere.
    let x: Vec<f64> = (0..100).map(|i| i as f64 / 99.0).collect();
    let y: Vec<f64> = x.iter().map(|v| v * v * v * v).collect();
    let svg = Figure::new("legend")
        .with(Series::line(&x, &y).label("x⁴"))
        .with(Series::line(&x, &y.iter().map(|v| v * 0.9).collect::<Vec<_>>()).label("0.9 x⁴"))
        .to_svg()
        .unwrap();
    let rect_x: Vec<f64> = svg
        .split("<rect ")
        .filter(|p| p.contains("rx=\"3\""))
        .map(|p| {
            let s = p.find("x=\"").unwrap() + 3;
            p[s..s + p[s..].find('"').unwrap()].parse().unwrap()
        })
        .collect();
    assert_eq!(rect_x.len(), 1);
    assert!(rect_x[0] < 400.0, "legend at x = {}", rect_x[0]);
    // Hidden legend.
    let svg = Figure::new("no legend")
        .legend(LegendPosition::Hidden)
        .with(Series::line(&x, &y).label("x⁴"))
        .to_svg()
        .unwrap();
    assert!(!svg.contains("rx=\"3\""));
}

#[test]
fn custom_figure_with_every_series_kind() {
    let x: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    let y: Vec<f64> = x.iter().map(|v| (v * 0.8).sin() * v).collect();
    let lo: Vec<f64> = y.iter().zip(&x).map(|(a, v)| a - 0.2 - 0.05 * v).collect();
    let hi: Vec<f64> = y.iter().zip(&x).map(|(a, v)| a + 0.2 + 0.05 * v).collect();
    let mut fig = Figure::new("Every series kind")
        .x_label("time (s)")
        .y_label("output");
    fig.push(Series::band(&x, &lo, &hi).label("±2σ band"));
    fig.push(Series::line(&x, &y).label("mean"));
    fig.push(
        Series::line(&x, &y.iter().map(|v| v * 0.8).collect::<Vec<_>>())
            .label("dashed")
            .dash(Dash::Dashed),
    );
    fig.push(
        Series::line(&x, &y.iter().map(|v| v * 0.6).collect::<Vec<_>>())
            .label("dotted")
            .dash(Dash::Dotted)
            .width(2.5),
    );
    fig.push(
        Series::line(&x, &y.iter().map(|v| v * 0.4).collect::<Vec<_>>())
            .label("dash-dot")
            .dash(Dash::DashDot),
    );
    for (k, m) in [
        Marker::Plus,
        Marker::Cross,
        Marker::Star,
        Marker::Circle,
        Marker::Dot,
    ]
    .into_iter()
    .enumerate()
    {
        let xs: Vec<f64> = (0..5)
            .map(|i| 1.0 + 2.0 * i as f64 + 0.3 * k as f64)
            .collect();
        let ys: Vec<f64> = xs.iter().map(|_| -6.0 + k as f64 * 0.8).collect();
        fig.push(Series::scatter(&xs, &ys, m).label(format!("{m:?}")));
    }
    let p = out_dir().join("kinds.svg");
    fig.save(&p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    check_no_nan(&svg);
    assert_eq!(svg.matches("stroke-dasharray").count(), 6); // 3 lines + 3 legend swatches

    // The same with the legend outside the plot area, to the right.
    let p = out_dir().join("kinds_outside.svg");
    fig.clone()
        .legend(LegendPosition::OutsideRight)
        .save(&p)
        .unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    let legend_x: f64 = svg
        .split("<rect ")
        .find(|p| p.contains("rx=\"3\""))
        .map(|p| {
            let s = p.find("x=\"").unwrap() + 3;
            p[s..s + p[s..].find('"').unwrap()].parse().unwrap()
        })
        .unwrap();
    let clip_w: f64 = attr_values(&svg, "rect", "width")[2].parse().unwrap();
    let clip_x: f64 = attr_values(&svg, "rect", "x")[0].parse().unwrap();
    assert!(legend_x > clip_x + clip_w, "legend at {legend_x}");
}

#[test]
fn log_y_for_singular_values() {
    let idx: Vec<f64> = (1..=7).map(f64::from).collect();
    let sv = [10.0, 5.0, 0.1, 0.05, 0.02, 0.01, 0.0];
    let p = out_dir().join("singular_values.svg");
    Figure::new("Singular values")
        .x_label("index")
        .log_y(true)
        .with(Series::line(&idx, &sv))
        .with(Series::scatter(&idx, &sv, Marker::Dot))
        .save(&p)
        .unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    check_well_formed(&svg);
    check_no_nan(&svg);
    let t = texts(&svg);
    for label in ["10\u{2212}2", "10\u{2212}1", "100", "101"] {
        assert!(t.iter().any(|s| s == label), "missing {label}: {t:?}");
    }
    let err = Figure::new("t")
        .log_y(true)
        .y_range(-1.0, 1.0)
        .to_svg()
        .unwrap_err();
    assert!(matches!(err, PlotError::InvalidRange { axis: "y", .. }));
}
