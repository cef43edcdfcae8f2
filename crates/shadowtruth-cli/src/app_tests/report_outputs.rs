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
    // The figures and plots load as they are scrolled to: here every one is loaded at once, so
    // that a broken link fails.
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    assert!(html.contains("<img loading=\"lazy\""), "the plots wait to be scrolled to");
    let page = dir.path().join("index-eager.html");
    std::fs::write(&page, html.replace("loading=\"lazy\" ", "")).unwrap();
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

/// Reads, once the page has loaded in a 1280×800 window, what a reader sees first; then clicks
/// the first point of the first chart and pages the runs table; writes it all into
/// `<pre id="seen">`. Where `openOnly` is set, it only opens the point's run (for a screenshot of
/// the viewer).
const FIRST_SCREEN_DRIVER: &str = r#"<script>
(function () {
  var opening = window.openOnly === true;
  window.addEventListener('load', function () { setTimeout(function () {
    var log = {}, viewer = document.getElementById('viewer');
    var img = document.querySelector('#answer img.answer-img');
    log.image = img ? { top: img.getBoundingClientRect().top, bottom: img.getBoundingClientRect().bottom,
                        width: img.naturalWidth } : null;
    var chart = document.querySelector('#answer svg.cost-chart');
    log.chartTop = chart ? chart.getBoundingClientRect().top : null;
    var table = document.getElementById('runs');
    log.table = { right: table.getBoundingClientRect().right, inner: window.innerWidth,
                  scroll: table.parentNode.scrollWidth, client: table.parentNode.clientWidth };
    var point = document.querySelector('.cost-chart circle[data-run]');
    log.point = point ? Number(point.dataset.run) : null;
    log.hiddenBefore = viewer.hidden;
    if (point) point.dispatchEvent(new MouseEvent('click', { bubbles: true }));
    if (opening) {
      // Headless screenshots are of the page's top: the viewer is moved there.
      document.body.insertBefore(viewer, document.body.firstChild);
      window.scrollTo(0, 0);
      return;
    }
    var data = JSON.parse(document.getElementById('runs-data').textContent);
    log.viewer = { hidden: viewer.hidden, run: Number(viewer.dataset.run),
                   caption: document.getElementById('view-caption').textContent,
                   base: document.getElementById('view-base').getAttribute('src'),
                   want: point ? data[log.point].figures : null };
    var at = document.getElementById('page-at');
    log.pages = [{ page: Number(at.dataset.page), pages: Number(at.dataset.pages), rows: table.tBodies[0].rows.length,
                   first: Number(table.tBodies[0].rows[0].dataset.run) }];
    document.getElementById('page-next').click();
    log.pages.push({ page: Number(at.dataset.page), rows: table.tBodies[0].rows.length,
                     first: Number(table.tBodies[0].rows[0].dataset.run) });
    log.runs = data.length;
    // Compare: pin the opened run as B, open another of the first page as A, slide, and point
    // at a pixel.
    document.getElementById('page-prev').click();
    document.getElementById('view-pin').click();
    var other = Array.prototype.filter.call(document.querySelectorAll('button.view'), function (b) {
      return Number(b.dataset.run) !== log.point;
    })[0];
    other.click();
    document.querySelector('#view-modes button[data-mode=slide]').click();
    var slider = document.getElementById('view-slider'); slider.value = 25; slider.dispatchEvent(new Event('input'));
    var base = document.getElementById('view-base'), over = document.getElementById('view-over');
    var divider = document.getElementById('view-divider');
    setTimeout(function () {
      var r = base.getBoundingClientRect();
      log.compare = { run: Number(viewer.dataset.run), other: Number(other.dataset.run),
                      pinned: Number(viewer.dataset.compare), base: base.getAttribute('src'), over: over.getAttribute('src'),
                      want: { a: data[Number(other.dataset.run)].figures, b: data[log.point].figures },
                      divider: { hidden: divider.hidden, left: divider.style.left, width: base.clientWidth } };
      document.getElementById('view-stage').dispatchEvent(new MouseEvent('mousemove', {
        bubbles: true, clientX: Math.ceil(r.left) + 10, clientY: Math.ceil(r.top) + 20 }));
      setTimeout(function () {
        var p = document.getElementById('view-pixel');
        log.pixel = { text: p.textContent, x: Number(p.dataset.x), y: Number(p.dataset.y), a: p.dataset.a, b: p.dataset.b };
        var pre = document.createElement('pre'); pre.id = 'seen'; pre.textContent = JSON.stringify(log);
        document.body.appendChild(pre);
      }, 1000);
    }, 500);
  }, 200); });
})();
</script>"#;

/// The page as a person sees it at 1280×800: the first screen shows an image and a chart, the
/// runs table fits the window and is paged, and a chart's point opens its own run in the
/// viewer. Screenshots of the first screen and of the opened viewer are kept for people.
#[test]
fn the_first_screen_shows_the_answer_and_a_chart_point_opens_its_run() {
    let browser = required_chromium();
    let dir = tempfile::tempdir().unwrap();
    let mut report = report_of(dir.path(), true);
    // Past one page of runs: copies of the runs under other cameras (their figures are not
    // written, so they have no viewer button and no chart point).
    let runs = report.runs.clone();
    for k in 0..25 {
        report.runs.extend(runs.iter().cloned().map(|mut r| {
            r.camera = format!("copy{k}");
            r
        }));
    }
    assert!(report.runs.len() > 200);
    crate::drawing::write_page(dir.path(), &report).unwrap();
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    let page = dir.path().join("index-seen.html");
    std::fs::write(&page, html.replace("</body>", &format!("{FIRST_SCREEN_DRIVER}</body>"))).unwrap();
    let profile = tempfile::tempdir().unwrap();
    let seen = |extra: &[&str], page: &Path| {
        let mut args = chromium_args(profile.path(), page, extra);
        args.insert(0, "--window-size=1280,800".into());
        Command::new(&browser).args(args).output().expect("chromium runs")
    };
    let out = seen(&["--dump-dom"], &page);
    let dom = String::from_utf8_lossy(&out.stdout);
    let at =
        dom.find("<pre id=\"seen\">").unwrap_or_else(|| panic!("the driver did not finish: {dom:.3000}"));
    let text = dom[at + 15..].split("</pre>").next().unwrap().replace("&quot;", "\"").replace("&amp;", "&");
    let log: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
    let image = &log["image"];
    assert!(image["width"].as_u64().unwrap_or(0) > 0, "the answer's image did not load: {log}");
    assert!(image["top"].as_f64().unwrap() < 800.0, "the first screen shows no image: {log}");
    assert!(log["chartTop"].as_f64().unwrap() < 800.0, "the first screen shows no chart: {log}");
    let table = &log["table"];
    assert!(
        table["scroll"].as_f64() <= table["client"].as_f64()
            && table["right"].as_f64().unwrap() <= table["inner"].as_f64().unwrap(),
        "the runs table does not fit 1280 px: {log}"
    );
    // The point opened its own run.
    assert_eq!(log["hiddenBefore"], true);
    let (viewer, run) = (&log["viewer"], log["point"].as_u64().expect("a chart point with a run"));
    assert_eq!(viewer["hidden"], false);
    assert_eq!(viewer["run"], run);
    assert_eq!(viewer["caption"], viewer["want"]["caption"]);
    assert_eq!(viewer["base"], viewer["want"]["reference"]);
    let r = &report.runs[run as usize];
    assert_eq!(
        viewer["caption"],
        format!("{}/{}/{}: {} at {}² {}", r.scene, r.camera, r.light, r.label, r.resolution, r.depth_format)
    );
    // Paged: 100 rows, then the next 100.
    assert_eq!(log["runs"], report.runs.len());
    let pages = &log["pages"];
    assert_eq!(pages[0]["pages"], report.runs.len().div_ceil(100));
    assert_eq!(
        (&pages[0]["page"], &pages[0]["rows"], &pages[0]["first"]),
        (&1.into(), &100.into(), &0.into())
    );
    assert_eq!(
        (&pages[1]["page"], &pages[1]["rows"], &pages[1]["first"]),
        (&2.into(), &100.into(), &100.into())
    );
    // Two runs compared: B the pinned one, A the one opened after; slid with the divider at 25 %;
    // the pixel under the cursor (zoom 1) read from both error maps.
    let compare = &log["compare"];
    assert_eq!((&compare["run"], &compare["pinned"]), (&compare["other"], &run.into()));
    assert_eq!(compare["base"], compare["want"]["b"]["technique"], "B's shadows under the divider");
    assert_eq!(compare["over"], compare["want"]["a"]["technique"], "A's shadows left of it");
    let divider = &compare["divider"];
    assert_eq!(divider["hidden"], false);
    assert_eq!(divider["left"], format!("{}px", divider["width"].as_f64().unwrap() * 0.25));
    let pixel = &log["pixel"];
    assert_eq!((&pixel["x"], &pixel["y"]), (&10.into(), &20.into()), "{pixel}");
    // The class each error map holds there, read here from the PNGs.
    use crate::drawing::palette::{FALSE_LIT, FALSE_SHADOW, UNCERTAIN};
    for side in ["a", "b"] {
        let map = compare["want"][side]["error"].as_str().unwrap();
        let colour = image::open(dir.path().join(map)).unwrap().into_rgb8().get_pixel(10, 20).0;
        let class = match colour {
            c if c == FALSE_SHADOW => "false shadow",
            c if c == FALSE_LIT => "false lit",
            c if c == UNCERTAIN => "uncertain",
            _ => "agrees with the reference",
        };
        assert_eq!(pixel[side], class, "pixel readout of {side}: {pixel}");
    }
    // Screenshots for people: the first screen, and the viewer opened from a chart point.
    let shots = std::env::temp_dir();
    let opened = dir.path().join("index-opened.html");
    let open_only = format!("<script>var openOnly = true;</script>{FIRST_SCREEN_DRIVER}</body>");
    std::fs::write(&opened, html.replace("</body>", &open_only)).unwrap();
    for (name, page) in [("first-screen", dir.path().join("index.html")), ("viewer", opened)] {
        let shot = shots.join(format!("shadowtruth-page-{name}.png"));
        let _ = std::fs::remove_file(&shot);
        let out = seen(&[&format!("--screenshot={}", shot.display())], &page);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let img = image::open(&shot).expect("a screenshot was saved").into_rgb8();
        assert_eq!((img.width(), img.height()), (1280, 800));
        let distinct: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 50, "the {name} screenshot is nearly blank");
        eprintln!("screenshot of the {name}: {}", shot.display());
    }
}

/// What a plot shows, as read from its SVG: every text that is not a number (title, axis
/// names, legend), and the colour of every series line (width 2) in drawing order.
fn plot_structure(svg: &str) -> serde_json::Value {
    let doc = roxmltree::Document::parse(svg).expect("plotters writes valid SVG");
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(str::trim)
        .filter(|t| !t.is_empty() && t.parse::<f64>().is_err())
        .collect();
    let lines: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke-width") == Some("2"))
        .filter_map(|n| n.attribute("stroke"))
        .collect();
    serde_json::json!({ "texts": texts, "line_colours": lines })
}

/// The stored expectation of one plot of each kind the tool draws (a sweep, error against
/// resolution, cost against error, the frames of a moving view, a `tune` search), in structure:
/// its texts and its series' colours. A change to what the plots say or how they colour it
/// fails here until the expectation is written again (`SHADOWTRUTH_WRITE_PLOT_STRUCTURE=1`) and
/// the difference read.
#[test]
fn each_plot_kind_keeps_its_stored_structure() {
    let dir = tempfile::tempdir().unwrap();
    let report = small_report(dir.path());
    let charts = crate::drawing::plots::charts(&report);
    let mut seen = serde_json::Map::new();
    let mut keep = |kind: &str, charts: &[crate::drawing::plots::Chart]| {
        let svg = crate::drawing::plots::stacked_svg(charts).unwrap();
        seen.insert(kind.to_string(), plot_structure(&svg));
    };
    for kind in ["sweep", "resolution", "cost"] {
        let chart = charts
            .iter()
            .filter(|c| c.stem.starts_with(&format!("{kind}_")))
            .min_by(|a, b| a.stem.cmp(&b.stem))
            .unwrap_or_else(|| panic!("no {kind} plot"));
        keep(kind, std::slice::from_ref(chart));
    }
    let temporal = |label| crate::drawing::frame_plots::tests::temporal_run(label, 512, 6);
    let moving =
        Report { runs: vec![temporal("none"), temporal("constant(bias_depth=0.002)")], ..Report::new() };
    keep("frames", &crate::drawing::frame_plots::frame_plots(&moving)[0].charts);
    keep("tune", std::slice::from_ref(&synthetic_tune_chart()));

    let seen = serde_json::Value::Object(seen);
    let stored = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/app_tests/plot_structure.json");
    if std::env::var_os("SHADOWTRUTH_WRITE_PLOT_STRUCTURE").is_some() {
        std::fs::write(&stored, serde_json::to_string_pretty(&seen).unwrap() + "\n").unwrap();
    }
    let text = std::fs::read_to_string(&stored).unwrap_or_else(|e| panic!("{}: {e}", stored.display()));
    let want: serde_json::Value = serde_json::from_str(&text).unwrap();
    for kind in ["sweep", "resolution", "cost", "frames", "tune"] {
        assert_eq!(seen[kind], want[kind], "the {kind} plot's structure changed");
    }
}

/// The plot of a `tune` search of the constant bias on one synthetic scene: acne (false shadow)
/// falls to zero as the bias grows past 0.01 and a leak (false lit) rises from 0.001.
fn synthetic_tune_chart() -> crate::drawing::plots::Chart {
    use crate::tune::{LogRange, Objective, SuiteAggregate, TuneRequest, tune_with};
    let base = serde_json::json!({ "technique": "constant" }).as_object().unwrap().clone();
    let request = TuneRequest {
        base,
        params: vec![("bias_depth".into(), LogRange { lo: 1e-4, hi: 0.1 })],
        objective: Objective::Total,
        aggregate: SuiteAggregate::Mean,
    };
    let mut shade = |_: usize, spec: &shadowtruth::technique::TechniqueSpec| {
        let bias = spec.parameters()["bias_depth"].as_f64().unwrap();
        let false_shadow = (1000.0 * (0.01 - bias).max(0.0)) as u64;
        let false_lit = (1000.0 * (bias - 0.001).max(0.0)) as u64;
        shadowtruth::metrics::Counts {
            pixels: 1000,
            evaluated: 1000,
            false_shadow,
            false_lit,
            ..Default::default()
        }
    };
    let result = tune_with(&request, &["s".to_string()], &mut shade);
    crate::drawing::tune_chart(&result, &request, 0)
}
