//! The figures of a model (`hsid_host::figures`, `identify --out`, `validate --out`) on a
//! simulated record with known truth: every SVG parses as XML and holds its series, every CSV
//! has its columns and rows, and the plotted numbers agree with the model computed
//! independently (static gain, poles, autocorrelation at lag 0, the Bode band against the
//! analytic delta method, the measured border points against the true loop).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use hsid_host::model::Element;
use std::path::Path;

use common::{Scratch, classes, has, hsid, identify, p};
use hsid_host::choose::{self, Best, Choices, ModelStage, Segments, best_model};
use hsid_host::figures::{
    FigureError, FigureSettings, RecordView, TrueBorders, UncertaintySource, write_figures,
};
use hsid_host::identify::{HostModel, IdentifyOptions};
use hsid_host::io::read_columns;
use hsid_host::refine::uncertainty::{bode_db_std, border_std};
use hsid_host::sim::{
    Lti, TruePaths, paper_backlash, paper_plant, simulate, table1_excitation, with_hold,
};
use nalgebra::{DMatrix, DVector};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

const HOLD: usize = 300;
const SAMPLES: usize = 3300;
const TS: f64 = 0.01;

/// The paper's backlash and plant at 20 dB of white noise: `(u, y, true paths)`.
fn record() -> (Vec<f64>, Vec<f64>, TruePaths) {
    let mut rng = Pcg32::seed_from_u64(13);
    let ex = table1_excitation(SAMPLES - HOLD, -3.0, 3.0, &mut rng).unwrap();
    let u = with_hold(HOLD, -3.0, &ex);
    let mut nl = paper_backlash();
    let paths = nl.true_paths(-3.0, 3.0);
    let white = Lti::new(vec![1.0], vec![1.0]).unwrap();
    let s = simulate(
        &u,
        &mut nl,
        &paper_plant(),
        &white,
        Some(20.0),
        HOLD..SAMPLES,
        &mut rng,
    )
    .unwrap();
    (u, s.y, paths)
}

fn refined(u: &[f64], y: &[f64]) -> Best {
    let mut opts = IdentifyOptions::uniform(-3.0, 3.0, 7, HOLD);
    opts.order = Some(2);
    let choices = Choices {
        segments: Segments::Given,
        horizons: choose::Horizons::Given,
        estimator: ModelStage::Refined,
        ..Choices::default()
    };
    best_model(u, y, &opts, &choices).unwrap()
}

fn columns(path: &Path, names: &[&str]) -> Vec<Vec<f64>> {
    read_columns(path, names).unwrap_or_else(|e| panic!("{e}"))
}

fn static_gain(m: &HostModel) -> f64 {
    let n = m.order;
    let x = (DMatrix::identity(n, n) - &m.a)
        .lu()
        .solve(&DVector::from_column_slice(&m.b))
        .unwrap();
    DVector::from_column_slice(&m.c).dot(&x) + m.d
}

#[test]
fn refined_model_figures_hold_the_model_and_its_uncertainty() {
    let (u, y, paths) = record();
    let best = refined(&u, &y);
    let fit = best.fit.as_ref().unwrap();
    let m = &fit.model;
    let grid: Vec<f64> = (0..=60).map(|i| -3.0 + 0.1 * i as f64).collect();
    let settings = FigureSettings {
        ts: Some(TS),
        units: Some(("V".into(), "deg".into())),
        truth: Some(TrueBorders {
            u: grid.clone(),
            asc: grid.iter().map(|&v| paths.asc(v)).collect(),
            desc: grid.iter().map(|&v| paths.desc(v)).collect(),
        }),
    };
    let dir = Scratch::new("figures-refined");
    let out = dir.join("figs");
    let record = RecordView {
        u: &u,
        y: &y,
        skip: HOLD,
    };
    let written = write_figures(
        &out,
        m,
        &record,
        Some(UncertaintySource::Refined(fit)),
        &settings,
    )
    .unwrap();
    assert!(written.notes.is_empty(), "{:?}", written.notes);
    // 18 and the gap marker's borders-gap.csv and borders-detail.svg.
    assert_eq!(written.files.len(), 20, "{:?}", written.files);
    let f = |name: &str| out.join(name);

    // Borders: the model's, the bands, the truth, the partial residuals.
    has(
        &f("borders.svg"),
        &[
            "border-asc",
            "border-desc",
            "band-asc",
            "band-desc",
            "true-asc",
            "true-desc",
            "points-asc",
            "points-desc",
            "gap-marker",
        ],
    );
    let b = columns(
        &f("borders.csv"),
        &[
            "u [V]",
            "P_a [deg]",
            "P_d [deg]",
            "P_a - 2sd [deg]",
            "P_a + 2sd [deg]",
            "P_d - 2sd [deg]",
            "P_d + 2sd [deg]",
        ],
    );
    assert_eq!(b[0].len(), 401 + 6, "the grid and the 6 interior knots");
    for (i, &v) in b[0].iter().enumerate() {
        assert_eq!(b[1][i], m.border_asc_at(v));
        assert_eq!(b[2][i], m.border_desc_at(v));
    }
    // At the knots the band is ±2 of the knot's standard deviation.
    let (sa, _) = border_std(fit);
    let k = b[0].iter().position(|&v| v == m.knots_asc[3]).unwrap();
    assert!(((b[4][k] - b[3][k]) / 4.0 - sa[3]).abs() < 1e-12);
    // The measured points scatter around the true loop (the refined G has G(1) = 1 and so has
    // the paper's plant, so both are on the same scale).
    let pts = columns(
        &f("borders-points.csv"),
        &[
            "u [V]",
            "h_measured [deg]",
            "direction (+1 rising, -1 falling)",
        ],
    );
    let n_pts = pts[0].len();
    assert!(
        n_pts > SAMPLES - HOLD - 100 && n_pts <= SAMPLES - HOLD,
        "{n_pts}"
    );
    let mut dev: Vec<f64> = (0..n_pts)
        .map(|i| {
            let t = if pts[2][i] > 0.0 {
                paths.asc(pts[0][i])
            } else {
                paths.desc(pts[0][i])
            };
            (pts[1][i] - t).abs()
        })
        .collect();
    dev.sort_by(f64::total_cmp);
    let median = dev[n_pts / 2];
    assert!(
        median < 0.1,
        "median distance of the points to the true loop {median}"
    );
    let t = columns(
        &f("borders-true.csv"),
        &["u [V]", "true P_a [deg]", "true P_d [deg]"],
    );
    assert_eq!(t[0].len(), 61);

    // Bode: the first row is ω = 0, the static gain; frequencies in Hz up to Nyquist.
    has(&f("bode-magnitude.svg"), &["magnitude", "band"]);
    has(&f("bode-phase.svg"), &["phase", "band"]);
    let bode = columns(
        &f("bode.csv"),
        &[
            "f_Hz",
            "|G| [dB]",
            "phase [deg]",
            "|G| [dB] - 2sd",
            "|G| [dB] + 2sd",
            "phase [deg] - 2sd",
            "phase [deg] + 2sd",
        ],
    );
    assert_eq!(bode[0].len(), 301);
    assert_eq!(bode[0][0], 0.0);
    assert!((bode[0][300] - 0.5 / TS).abs() < 1e-9);
    let g1 = static_gain(m);
    assert!(
        (bode[1][0] - 20.0 * g1.abs().log10()).abs() < 1e-9,
        "{} vs {g1}",
        bode[1][0]
    );
    // The band's half width is 2σ of the analytic delta method (the figure differentiates
    // numerically).
    let w: Vec<f64> = bode[0]
        .iter()
        .map(|f| 2.0 * std::f64::consts::PI * f * TS)
        .collect();
    let analytic = bode_db_std(fit, &w);
    for i in (1..301).step_by(20) {
        let sd = (bode[4][i] - bode[3][i]) / 4.0;
        let (db, sd_a) = analytic[i];
        assert!(
            (db - bode[1][i]).abs() < 1e-9,
            "row {i}: {db} vs {}",
            bode[1][i]
        );
        assert!(
            (sd - sd_a).abs() <= 1e-4 * sd_a + 1e-12,
            "row {i}: {sd} vs {sd_a}"
        );
        assert!(bode[6][i] > bode[5][i], "row {i}: no phase band");
    }

    // Poles: the model's, with their ellipses.
    has(&f("poles.svg"), &["unit-circle", "ellipse", "poles"]);
    has(&f("poles-zoom-1.svg"), &["ellipse", "poles"]);
    let pc = columns(
        &f("poles.csv"),
        &["re", "im", "sd re", "sd im", "cov re im"],
    );
    let poles = m.poles();
    assert_eq!(pc[0].len(), poles.len());
    for (i, (re, im)) in poles.iter().enumerate() {
        assert_eq!((pc[0][i], pc[1][i]), (*re, *im));
        assert!(pc[2][i] > 0.0 && pc[3][i] > 0.0);
    }
    let e = columns(
        &f("poles-ellipses.csv"),
        &["pole (0-based row of poles.csv)", "re", "im"],
    );
    assert_eq!(e[0].len(), 181 * poles.len());

    // Output and residual over time in seconds.
    has(&f("output.svg"), &["measured", "simulated"]);
    has(&f("output-detail.svg"), &["measured", "simulated"]);
    let sim = m.simulate(&u);
    let o = columns(
        &f("output.csv"),
        &["t_s", "y measured [deg]", "y simulated [deg]"],
    );
    assert_eq!(o[0].len(), SAMPLES);
    assert_eq!((o[0][7], o[1][7], o[2][7]), (7.0 * TS, y[7], sim[7]));
    has(&f("residual.svg"), &["residual"]);
    let r = columns(&f("residual.csv"), &["t_s", "residual [deg]"]);
    assert_eq!(r[1].len(), SAMPLES - HOLD);
    assert_eq!(r[1][5], y[HOLD + 5] - sim[HOLD + 5]);
    has(
        &f("residual-acf.svg"),
        &["acf", "acf-stems", "bounds", "bound-upper", "bound-lower"],
    );
    let acf = columns(
        &f("residual-acf.csv"),
        &["lag [s]", "acf", "bound 1.96/sqrt(N)"],
    );
    assert_eq!(acf[1].len(), 51);
    assert_eq!(acf[1][0], 1.0);
    assert!((acf[2][0] - 1.96 / ((SAMPLES - HOLD) as f64).sqrt()).abs() < 1e-15);
    // Lag 1 by hand.
    let mean = r[1].iter().sum::<f64>() / r[1].len() as f64;
    let c = |k: usize| {
        (0..r[1].len() - k)
            .map(|t| (r[1][t] - mean) * (r[1][t + k] - mean))
            .sum::<f64>()
    };
    assert!((acf[1][1] - c(1) / c(0)).abs() < 1e-12);
}

#[test]
fn a_model_file_gives_bands_of_borders_and_poles_but_not_of_the_bode_plot() {
    let (u, y, _) = record();
    let best = refined(&u, &y);
    let fit = best.fit.as_ref().unwrap();
    let mut file = fit.model.to_json(Some(Element::Backlash));
    let (asc, desc) = border_std(fit);
    file.std = Some(hsid_host::model_file::ModelStd {
        poles: file.poles.iter().map(|_| [0.01, 0.02]).collect(),
        mu0: asc[0],
        border_asc: asc,
        border_desc: desc,
        mean_gap: None,
    });
    let dir = Scratch::new("figures-stored");
    let record = RecordView {
        u: &u,
        y: &y,
        skip: HOLD,
    };
    let unc = UncertaintySource::from_file(&file);
    let written = write_figures(
        &dir.join("f"),
        &HostModel::from_json(&file),
        &record,
        unc,
        &FigureSettings::default(),
    )
    .unwrap();
    assert_eq!(written.notes.len(), 1, "{:?}", written.notes);
    assert!(written.notes[0].contains("covariance"));
    let found = classes(&dir.join("f/bode-magnitude.svg"));
    assert!(!found.contains("band"), "{found:?}");
    has(&dir.join("f/borders.svg"), &["band-asc", "band-desc"]);
    // Axis-aligned ellipses with the stored standard deviations: semi-axes 0.02 and 0.04.
    let e = columns(
        &dir.join("f/poles-ellipses.csv"),
        &["pole (0-based row of poles.csv)", "re", "im"],
    );
    let (re0, im0) = (file.poles[0][0], file.poles[0][1]);
    let max_re = e[1][..181]
        .iter()
        .map(|v| (v - re0).abs())
        .fold(0.0, f64::max);
    let max_im = e[2][..181]
        .iter()
        .map(|v| (v - im0).abs())
        .fold(0.0, f64::max);
    assert!(
        (max_re - 0.02).abs() < 1e-9 && (max_im - 0.04).abs() < 1e-6,
        "{max_re} {max_im}"
    );
    // Without units and sample time: samples and rad/sample.
    columns(&dir.join("f/bode.csv"), &["w_rad_per_sample", "|G| [dB]"]);
    columns(&dir.join("f/output.csv"), &["t_samples", "y measured"]);
}

#[test]
fn bad_settings_and_unwritable_directories_are_errors() {
    let (u, y, _) = record();
    let m = refined(&u, &y).model;
    let dir = Scratch::new("figures-errors");
    let file = dir.write("plain.txt", "not a directory");
    let record = RecordView {
        u: &u,
        y: &y,
        skip: HOLD,
    };
    let s = FigureSettings::default();
    match write_figures(&file.join("sub"), &m, &record, None, &s) {
        Err(e @ FigureError::CreateDir { .. }) => {
            assert!(
                e.to_string().contains("cannot create the figure directory"),
                "{e}"
            );
        }
        other => panic!("{other:?}"),
    }
    let bad = FigureSettings {
        ts: Some(-0.1),
        ..FigureSettings::default()
    };
    assert!(matches!(
        write_figures(&dir.join("a"), &m, &record, None, &bad),
        Err(FigureError::InvalidSampleTime(_))
    ));
    let short = RecordView {
        u: &u,
        y: &y[1..],
        skip: 0,
    };
    assert!(matches!(
        write_figures(&dir.join("b"), &m, &short, None, &s),
        Err(FigureError::InvalidRecord { .. })
    ));
}

#[test]
fn identify_and_validate_write_figures_with_out() {
    let (u, y, _) = record();
    let dir = Scratch::new("figures-cli");
    let data = dir.write_uy("data.csv", &u, &y);
    let model = dir.join("model.json");
    let out = dir.join("id");
    let run = identify(
        &data,
        &[
            "--order",
            "2",
            "--segments",
            "7",
            "--json",
            p(&model),
            "--out",
            p(&out),
        ],
    )
    .success();
    assert!(run.stdout.contains("figure files"), "{}", run.stdout);
    for name in [
        "borders",
        "bode-magnitude",
        "bode-phase",
        "poles",
        "output",
        "residual",
        "residual-acf",
    ] {
        classes(&out.join(format!("{name}.svg")));
    }
    has(&out.join("bode-magnitude.svg"), &["band"]);
    let vout = dir.join("val");
    hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "300",
        "--out",
        p(&vout),
    ])
    .success();
    has(&vout.join("residual-acf.svg"), &["acf"]);
    has(&vout.join("poles.svg"), &["ellipse"]);
    let blocked = dir.write("blocked", "a file");
    let bad = blocked.join("figs");
    hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--out",
        p(&bad),
    ])
    .clean_error(&["cannot create the figure directory"]);
}
