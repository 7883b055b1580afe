//! `hsid identify --html`: the page parses as HTML without errors, refers to nothing outside
//! itself, escapes the names it shows, holds the model's numbers in its headline, and renders
//! in headless Chromium (when installed) without console errors and with figures of non-zero
//! size.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::{Scratch, hsid, p};
use hsid_host::identify::HostModel;
use hsid_host::model_file::ModelFile;
use hsid_host::units::unit_report;
use scraper::{Html, Selector};

/// A name with markup and an ampersand, for the data file and the input unit.
const NASTY: &str = "servo <script>x=1 & co";

struct Report {
    _dir: Scratch,
    html: String,
    data: PathBuf,
    model: PathBuf,
    svg_files: usize,
}

/// One identify run on the example servo (copied under a name with markup), shared by the
/// tests.
fn report() -> &'static Report {
    static R: OnceLock<Report> = OnceLock::new();
    R.get_or_init(|| {
        let dir = Scratch::new("html");
        let text = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/servo.csv"),
        )
        .unwrap();
        let data = dir.write(&format!("{NASTY}.csv"), &text);
        let (model, page, out) = (dir.join("m.json"), dir.join("r.html"), dir.join("figs"));
        let unit = format!("V{NASTY}");
        let fixed =
            "identify --umin -1 --umax 1 --ts 0.01 --output-unit deg --segments 7 --order 2";
        let mut args: Vec<&str> = fixed.split(' ').collect();
        args.extend([
            "--data",
            p(&data),
            "--input-unit",
            &unit,
            "--json",
            p(&model),
        ]);
        args.extend(["--out", p(&out), "--html", p(&page)]);
        hsid(&args).success();
        let svg_files = std::fs::read_dir(&out)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .path()
                    .extension()
                    .is_some_and(|x| x == "svg")
            })
            .count();
        Report {
            html: std::fs::read_to_string(&page).unwrap(),
            _dir: dir,
            data,
            model,
            svg_files,
        }
    })
}

fn sel(s: &str) -> Selector {
    Selector::parse(s).unwrap()
}

fn text(e: scraper::ElementRef<'_>) -> String {
    e.text().collect::<String>()
}

#[test]
fn the_page_parses_without_errors_and_refers_to_nothing_outside() {
    let r = report();
    let doc = Html::parse_document(&r.html);
    assert!(doc.errors.is_empty(), "parse errors: {:?}", doc.errors);
    for bad in [
        "script", "link", "img", "iframe", "object", "embed", "base", "form",
    ] {
        assert!(doc.select(&sel(bad)).next().is_none(), "a <{bad}> element");
    }
    for e in doc.select(&sel("*")) {
        for (name, value) in e.value().attrs() {
            let local = name.rsplit(':').next().unwrap();
            if ["src", "href", "srcset", "action", "data", "poster"].contains(&local) {
                assert!(
                    value.starts_with('#'),
                    "{name}=\"{value}\" on <{}>",
                    e.value().name()
                );
            }
            assert!(!local.starts_with("on"), "event handler {name}");
        }
    }
    let lower = r.html.to_lowercase();
    for needle in ["http:", "https:", "ftp:", "file:", "@import", "javascript:"] {
        assert!(!lower.contains(needle), "the page holds {needle}");
    }
    let urls: Vec<&str> = lower.split("url(").skip(1).collect();
    assert!(
        urls.iter().all(|u| u.starts_with('#')),
        "a url() to outside"
    );
    // Every clip-path refers to an id defined once in the page.
    let ids: Vec<&str> = doc
        .select(&sel("[id]"))
        .map(|e| e.value().id().unwrap())
        .collect();
    let mut unique = ids.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), ids.len(), "duplicate ids");
    for u in &urls {
        let id = &u[1..u.find(')').unwrap()];
        assert!(ids.contains(&id), "url(#{id}) without its element");
    }
}

#[test]
fn user_strings_are_escaped() {
    let r = report();
    assert!(!r.html.contains("<script"), "raw <script> in the page");
    assert!(r.html.contains("servo &lt;script&gt;x=1 &amp; co"));
    let doc = Html::parse_document(&r.html);
    let title = text(doc.select(&sel("h1")).next().unwrap());
    assert!(title.contains(NASTY), "{title}");
    let gap = fact(&doc, "mean gap (play)");
    assert!(gap.ends_with(&format!(" V{NASTY}")), "{gap}");
}

/// The value of the headline fact labelled `label`.
fn fact(doc: &Html, label: &str) -> String {
    doc.select(&sel("table.facts tr"))
        .find(|tr| text(tr.select(&sel("th")).next().unwrap()) == label)
        .map(|tr| text(tr.select(&sel("td")).next().unwrap()))
        .unwrap_or_else(|| panic!("no fact {label}"))
}

#[test]
fn the_sections_hold_the_models_numbers() {
    let r = report();
    let doc = Html::parse_document(&r.html);
    let order: Vec<String> = doc
        .select(&sel("section"))
        .map(|s| s.value().id().unwrap().to_string())
        .collect();
    assert_eq!(order, ["headline", "figures", "checks", "reproduce"]);
    // The gap in the headline is the model file's, read by the library.
    let file = ModelFile::load(&r.model).unwrap();
    let m = HostModel::from_json(&file);
    let want = unit_report(&m, Some(0.01), None, None, true)
        .mean_gap
        .unwrap();
    let gap = fact(&doc, "mean gap (play)");
    let shown: f64 = gap.split(' ').next().unwrap().parse().unwrap();
    assert!((shown - want).abs() <= 5e-6, "{gap} against {want}");
    // The servo's truth: a play of 0.2 V, 3 Hz, damping 0.4.
    assert!((shown - 0.2).abs() < 0.02, "{gap}");
    let pole = doc
        .select(&sel("table.facts th"))
        .map(text)
        .find(|t| t.starts_with("pole "))
        .unwrap();
    let wn = fact(&doc, &pole);
    let hz: f64 = wn
        .split(" = ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((hz - 3.0).abs() < 0.05, "{wn}");
    let lead = text(doc.select(&sel("p.lead")).nth(1).unwrap());
    assert!(
        lead.starts_with("Simulation fit on 6000 samples") && lead.contains(" %"),
        "{lead}"
    );
    // One inline figure per SVG file of --out, each with a caption.
    let figures = doc.select(&sel("figure")).count();
    assert_eq!(figures, r.svg_files);
    assert_eq!(doc.select(&sel("figure > svg[viewBox]")).count(), figures);
    assert_eq!(doc.select(&sel("figure > figcaption")).count(), figures);
    // Seven data checks and ten residual tests, the tests with p-values in [0, 1].
    let rows: Vec<Vec<String>> = doc
        .select(&sel("table.checks tr"))
        .skip(1)
        .map(|tr| tr.select(&sel("td")).map(text).collect())
        .collect();
    assert_eq!(
        rows.iter().filter(|r| r[0].starts_with("data: ")).count(),
        7
    );
    let tests: Vec<&Vec<String>> = rows
        .iter()
        .filter(|r| !r[0].starts_with("data: "))
        .collect();
    assert_eq!(tests.len(), 10);
    for t in tests {
        let pv: f64 = t[3].parse().unwrap();
        assert!((0.0..=1.0).contains(&pv), "{t:?}");
        assert_eq!(t[4] == "yes", pv < 0.01, "{t:?}");
    }
    // The command as run, and the input's size.
    let cmd = text(doc.select(&sel("pre.command")).next().unwrap());
    assert!(
        cmd.contains(" identify --umin -1 ") && cmd.contains(NASTY),
        "{cmd}"
    );
    let size = std::fs::metadata(&r.data).unwrap().len().to_string();
    let inputs: Vec<String> = doc.select(&sel("table.inputs td")).map(text).collect();
    assert_eq!(inputs, [r.data.display().to_string(), size]);
}

const CHROMIUM: &str = "/usr/bin/chromium";

/// Headless Chromium on `page` with extra `args`: (stdout, stderr).
fn chromium(page: &Path, args: &[&str]) -> (String, String) {
    let profile = Scratch::new("chromium-profile");
    let out = Command::new(CHROMIUM)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--window-size=1200,3000",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.join("p").display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The console messages Chromium logged.
fn console(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.contains(":CONSOLE")).collect()
}

/// Writes the page's figure sizes into the DOM, for `--dump-dom` (a test copy only: the page
/// itself holds no script).
const PROBE: &str = "<script>var s=[];document.querySelectorAll('figure svg').forEach(\
function(e){var r=e.getBoundingClientRect();s.push(Math.round(r.width)+'x'+Math.round(r.height));});\
var p=document.createElement('pre');p.id='probe';p.textContent=s.join(' ');\
document.body.appendChild(p);</script>";

#[test]
fn chromium_renders_the_page_without_console_errors_and_with_sized_figures() {
    if !Path::new(CHROMIUM).exists() {
        println!("SKIPPED: {CHROMIUM} is absent (apt-get install -y chromium); not rendered");
        return;
    }
    let r = report();
    let dir = Scratch::new("browser");
    let page = dir.write("page.html", &r.html);
    let shot = dir.join("shot.png");
    let (_, err) = chromium(&page, &[&format!("--screenshot={}", shot.display())]);
    assert_eq!(console(&err), Vec::<&str>::new(), "console messages");
    let png = std::fs::read(&shot).unwrap();
    assert!(
        png.len() > 10_000 && png.starts_with(b"\x89PNG"),
        "{} bytes",
        png.len()
    );
    // Figure sizes, measured by the probe in a test copy.
    let probed = dir.write(
        "probed.html",
        &r.html.replace("</body>", &format!("{PROBE}</body>")),
    );
    let (dom, _) = chromium(&probed, &["--dump-dom"]);
    let doc = Html::parse_document(&dom);
    let sizes = text(doc.select(&sel("pre#probe")).next().expect("the probe ran"));
    let sizes: Vec<(f64, f64)> = sizes
        .split(' ')
        .map(|s| {
            let (w, h) = s.split_once('x').unwrap();
            (w.parse().unwrap(), h.parse().unwrap())
        })
        .collect();
    assert_eq!(sizes.len(), r.svg_files);
    for (w, h) in sizes {
        assert!(w >= 400.0 && h >= 200.0, "a figure rendered {w}x{h}");
    }
    // The console check can fail: an error logged by a test copy is seen.
    let bad = dir.write(
        "bad.html",
        &r.html.replace(
            "</body>",
            "<script>console.error('probe error')</script></body>",
        ),
    );
    let (_, err) = chromium(
        &bad,
        &[&format!("--screenshot={}", dir.join("b.png").display())],
    );
    assert!(
        console(&err).iter().any(|l| l.contains("probe error")),
        "{err}"
    );
}
