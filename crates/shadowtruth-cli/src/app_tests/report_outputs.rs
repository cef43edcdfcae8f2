//! A report folder end to end: report.json, report.csv, plots and index.html, and the page
//! opened in a real headless Chromium (Debian's `chromium`), which must load the table and every
//! image. A machine without Chromium fails the browser tests, naming what to install
//! (`bash scripts/test.sh` installs it).

use super::common;

use crate::outputs::write_report_outputs;
use crate::plan::{Plan, execute, parse_plan};
use crate::sinks::ReportWriter;
use shadowtruth::record::{Report, load_report};
use std::path::{Path, PathBuf};
use std::process::Command;

fn small_report(dir: &Path) -> Report {
    report_of(dir, false)
}

/// A small report of plane_box (three techniques, two resolutions), with figures when asked.
fn report_of(dir: &Path, figures: bool) -> Report {
    let text = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "techniques": [
            { "technique": "none" },
            { "technique": "constant", "bias_depth": [0.0005, 0.002, 0.008] },
            { "technique": "slope_scaled", "factor": 2.0, "units": 4.0 }
        ],
        "resolutions": [256, 512], "repeats": 1
    })
    .to_string();
    let mut plan: Plan = parse_plan(&text, Path::new("plan.json")).unwrap();
    plan.scenes = vec![common::repo().join("scenes/plane_box.json")];
    let mut writer = ReportWriter::new(dir);
    let mut figure_sink = crate::sinks::FigureSink::new(&dir.join("figures"), None);
    if figures {
        execute(&plan, None, &mut [&mut writer, &mut figure_sink]).unwrap();
    } else {
        execute(&plan, None, &mut [&mut writer]).unwrap();
    }
    let report = writer.into_report();
    write_report_outputs(dir, &report).unwrap();
    report
}

#[test]
fn csv_has_the_rows_of_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let report = small_report(dir.path());
    let mut csv = csv::Reader::from_path(dir.path().join("report.csv")).unwrap();
    let headers = csv.headers().unwrap().clone();
    let col =
        |name: &str| headers.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), report.runs.len());
    for (row, run) in rows.iter().zip(&report.runs) {
        assert_eq!(row[col("label")], run.label);
        assert_eq!(row[col("counts.false_shadow")].parse::<u64>().unwrap(), run.counts.false_shadow);
        assert_eq!(row[col("counts.aliasing")].parse::<u64>().unwrap(), run.counts.aliasing);
        assert_eq!(row[col("rates.error")].parse::<f64>().unwrap(), run.rates.error);
        assert_eq!(row[col("resolution")].parse::<u32>().unwrap(), run.resolution);
    }
    // Parameters of every technique get their own columns.
    assert!(
        headers.iter().any(|h| h == "parameters.bias_depth")
            && headers.iter().any(|h| h == "parameters.factor")
    );
    // The report command re-renders the same CSV from report.json alone.
    let before = std::fs::read_to_string(dir.path().join("report.csv")).unwrap();
    std::fs::remove_file(dir.path().join("report.csv")).unwrap();
    let (again, _) = load_report(dir.path()).unwrap();
    write_report_outputs(dir.path(), &again).unwrap();
    assert!(std::fs::read_to_string(dir.path().join("report.csv")).unwrap() == before, "report.csv changed");
}

#[test]
fn plots_are_written_as_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    small_report(dir.path());
    let plots: Vec<PathBuf> =
        std::fs::read_dir(dir.path().join("plots")).unwrap().map(|e| e.unwrap().path()).collect();
    let stems = |ext: &str| {
        let mut v: Vec<String> = plots
            .iter()
            .filter(|p| p.extension().is_some_and(|x| x == ext))
            .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(stems("svg"), stems("png"));
    let names = stems("png");
    assert!(names.iter().any(|n| n.starts_with("sweep_") && n.contains("bias_depth")), "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("resolution_")), "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("cost_")), "{names:?}");
    for p in plots.iter().filter(|p| p.extension().is_some_and(|x| x == "png")) {
        let img = image::open(p).unwrap().into_rgb8();
        let distinct: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 10, "{} looks empty", p.display());
    }
    let svg =
        std::fs::read_to_string(plots.iter().find(|p| p.extension().is_some_and(|x| x == "svg")).unwrap())
            .unwrap();
    assert!(svg.contains("<svg") && svg.contains("<text"), "SVG plots carry their text");
}

fn chromium() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    ["chromium", "chromium-browser", "google-chrome"].iter().find_map(|name| {
        std::env::var_os("PATH")
            .and_then(|paths| std::env::split_paths(&paths).map(|d| d.join(name)).find(|p| p.is_file()))
    })
}

/// The browser the tests need: without one they fail, naming what to install.
fn required_chromium() -> PathBuf {
    chromium().expect(
        "no chromium on PATH: install it (`apt-get install chromium`, or `bash scripts/test.sh`, \
         which installs it) or set CHROMIUM",
    )
}

/// Loads `page` in headless Chromium and returns the DOM after its scripts ran.
fn dump_dom(browser: &Path, page: &Path) -> String {
    let profile = tempfile::tempdir().unwrap();
    let out = Command::new(browser)
        .args(chromium_args(profile.path(), page, &["--dump-dom"]))
        .output()
        .expect("chromium runs");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn chromium_args(profile: &Path, page: &Path, extra: &[&str]) -> Vec<String> {
    let mut a: Vec<String> = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--allow-file-access-from-files",
        "--virtual-time-budget=15000",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    a.push(format!("--user-data-dir={}", profile.display()));
    a.extend(extra.iter().map(|s| s.to_string()));
    a.push(format!("file://{}", page.display()));
    a
}

/// Drives the page as a reader would: opens a run in the viewer, flips between the reference,
/// the technique and the error map, slides, zooms, presses a key and filters the table; writes
/// what it saw (image sources, a checksum of each image's pixels) into `<pre id="clicks">`.
const CLICK_DRIVER: &str = r#"<script>
(function () {
  var log = {};
  var base = document.getElementById('view-base'), over = document.getElementById('view-over');
  function checksum(img) {
    var c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
    var g = c.getContext('2d'); g.drawImage(img, 0, 0);
    var d = g.getImageData(0, 0, c.width, c.height).data, h = 0;
    for (var i = 0; i < d.length; i += 4) h = (h * 31 + d[i] * 7 + d[i + 1] * 3 + d[i + 2]) >>> 0;
    return h;
  }
  function seen() {
    var s = { src: base.getAttribute('src'), width: base.naturalWidth, mode: document.getElementById('viewer').dataset.mode };
    try { s.checksum = checksum(base); } catch (e) { s.checksum = 'error: ' + e; }
    return s;
  }
  function click(selector) { document.querySelector(selector).dispatchEvent(new MouseEvent('click', { bubbles: true })); }
  var steps = [
    function () { log.hiddenBefore = document.getElementById('viewer').hidden; document.querySelectorAll('button.view')[1].click(); },
    function () { log.opened = seen(); log.button = document.querySelectorAll('button.view')[1].dataset; click('#view-modes button[data-mode=technique]'); },
    function () { log.technique = seen(); click('#view-modes button[data-mode=error]'); },
    function () { log.error = seen(); click('#view-modes button[data-mode=slide]'); },
    function () {
      var s = document.getElementById('view-slider'); s.value = 30; s.dispatchEvent(new Event('input'));
      log.slide = { base: base.getAttribute('src'), over: over.getAttribute('src'), overHidden: over.hidden, clip: over.style.clipPath };
      var z = document.getElementById('view-zoom'); z.value = '4'; z.dispatchEvent(new Event('change'));
    },
    function () {
      log.zoom = { style: base.style.width, natural: base.naturalWidth };
      document.dispatchEvent(new KeyboardEvent('keydown', { key: '1', bubbles: true }));
      log.key = seen();
      var f = document.querySelector('#filters select[name=resolution]'); f.value = f.options[1].value;
      f.dispatchEvent(new Event('change'));
      log.filter = { value: f.value, shown: Number(document.getElementById('shown').dataset.shown),
                     visible: Array.prototype.filter.call(document.querySelectorAll('#runs tbody tr'), function (r) { return !r.hidden; }).length };
      var pre = document.createElement('pre'); pre.id = 'clicks'; pre.textContent = JSON.stringify(log);
      document.body.appendChild(pre);
    }
  ];
  function run(i) { if (i < steps.length) { steps[i](); setTimeout(function () { run(i + 1); }, 400); } }
  window.addEventListener('load', function () { setTimeout(function () { run(0); }, 100); });
})();
</script>"#;

#[test]
fn the_page_viewer_flips_slides_zooms_and_filters_when_clicked_in_a_real_browser() {
    let browser = required_chromium();
    let dir = tempfile::tempdir().unwrap();
    let report = report_of(dir.path(), true);
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    let page = dir.path().join("index-clicked.html");
    std::fs::write(&page, html.replace("</body>", &format!("{CLICK_DRIVER}</body>"))).unwrap();
    let dom = dump_dom(&browser, &page);
    let at =
        dom.find("<pre id=\"clicks\">").unwrap_or_else(|| panic!("the driver did not finish: {dom:.3000}"));
    let text = dom[at + 17..]
        .split("</pre>")
        .next()
        .unwrap()
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let log: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
    assert_eq!(log["hiddenBefore"], true, "the viewer waits for a run");
    let button = &log["button"];
    let (opened, technique, error) = (&log["opened"], &log["technique"], &log["error"]);
    assert_eq!(opened["src"], button["reference"], "a run opens on its view's reference");
    assert_eq!(technique["src"], button["technique"]);
    assert_eq!(error["src"], button["error"]);
    for (name, s) in [("reference", opened), ("technique", technique), ("error", error)] {
        assert!(s["width"].as_u64().unwrap() > 0, "the {name} image did not load: {s}");
        assert!(s["checksum"].is_u64(), "the {name} image's pixels were not read: {s}");
    }
    // The three images differ: what the reader flips between changes.
    assert_ne!(opened["checksum"], technique["checksum"]);
    assert_ne!(technique["checksum"], error["checksum"]);
    assert_ne!(opened["checksum"], error["checksum"]);
    let slide = &log["slide"];
    assert_eq!(slide["base"], button["reference"]);
    assert_eq!(slide["over"], button["technique"]);
    assert_eq!(slide["overHidden"], false);
    assert_eq!(slide["clip"], "inset(0px 70% 0px 0px)");
    let zoom = &log["zoom"];
    assert_eq!(zoom["style"], format!("{}px", 4 * zoom["natural"].as_u64().unwrap()));
    assert_eq!(log["key"]["mode"], "reference", "key 1 shows the reference");
    assert_eq!(log["key"]["src"], button["reference"]);
    let resolution: u32 = log["filter"]["value"].as_str().unwrap().parse().unwrap();
    let want = report.runs.iter().filter(|r| r.resolution == resolution).count();
    assert!(want > 0 && want < report.runs.len());
    assert_eq!(log["filter"]["shown"], want);
    assert_eq!(log["filter"]["visible"], want);
}

#[test]
fn the_index_page_loads_its_table_and_every_image_in_a_real_browser() {
    let browser = required_chromium();
    let dir = tempfile::tempdir().unwrap();
    let report = small_report(dir.path());
    let page = dir.path().join("index.html");
    let profile = tempfile::tempdir().unwrap();
    let args = |extra: &[&str]| chromium_args(profile.path(), &page, extra);
    let out = Command::new(&browser).args(args(&["--dump-dom"])).output().expect("chromium runs");
    let dom = String::from_utf8_lossy(&out.stdout);
    let attr = |name: &str| -> usize {
        let key = format!("{name}=\"");
        let at = dom.find(&key).unwrap_or_else(|| panic!("no {name} in the page after load: {dom:.2000}"));
        dom[at + key.len()..].split('"').next().unwrap().parse().unwrap()
    };
    let (loaded, total) = (attr("data-loaded"), attr("data-total"));
    assert!(total > 0, "the page shows no image");
    assert_eq!(loaded, total, "{loaded} of {total} images loaded");
    let runs_table = &dom[dom.find("id=\"runs\"").expect("a runs table")..];
    let rows = runs_table.matches("<tr data-scene=\"plane_box\"").count();
    assert_eq!(rows, report.runs.len(), "the runs table has one row per run");
    // A screenshot, kept for people to look at.
    let shot = std::env::temp_dir().join("shadowtruth-index-screenshot.png");
    let _ = std::fs::remove_file(&shot);
    let status = Command::new(&browser)
        .args(args(&[&format!("--screenshot={}", shot.display()), "--window-size=1400,1800"]))
        .output()
        .expect("chromium runs");
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let img = image::open(&shot).expect("a screenshot was saved").into_rgb8();
    assert!(img.width() == 1400 && img.height() == 1800);
    eprintln!("screenshot: {}", shot.display());
}
