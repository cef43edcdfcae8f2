//! `index.html`: one offline page per report folder — the runs table (sortable), the plots, the
//! figures, the settings and the tool version. Only relative links; no network.

use super::Report;
use super::figures::run_stem;
use super::plots::charts;
use std::fmt::Write as _;
use std::path::Path;

/// HTML-escapes text for element content and attribute values.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// Images and links the page shows, relative to the report folder.
#[derive(Clone, Debug, Default)]
pub struct PageAssets {
    /// Plot stems under `plots/` (each has .png and .svg).
    pub plots: Vec<String>,
    /// Figure grids and reference figures, paths under `figures/`, with a caption.
    pub figures: Vec<(String, String)>,
    /// Per run (same order as `report.runs`): its figure paths (technique, error), if written.
    pub run_figures: Vec<Option<(String, String)>>,
}

const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}\
table{border-collapse:collapse;font-size:13px}th,td{border:1px solid #ccc;padding:3px 6px;text-align:right}\
th{background:#eee;cursor:pointer;position:sticky;top:0}td.l,th.l{text-align:left}\
tr:nth-child(even){background:#fafafa}.plots img,.figs img{max-width:100%;border:1px solid #ddd;margin:4px 0}\
.figs figure{display:inline-block;margin:6px;vertical-align:top;max-width:48%}#status{color:#666;font-size:12px}";

/// Sorting by clicking a header; a status line that says how many images loaded (read by tests).
const SCRIPT: &str = r#"
document.querySelectorAll('#runs th').forEach(function (th, col) {
  th.addEventListener('click', function () {
    var body = document.querySelector('#runs tbody');
    var rows = Array.prototype.slice.call(body.rows);
    var dir = th.dataset.dir === 'asc' ? -1 : 1;
    th.dataset.dir = dir === 1 ? 'asc' : 'desc';
    rows.sort(function (a, b) {
      var x = a.cells[col].dataset.v || a.cells[col].textContent, y = b.cells[col].dataset.v || b.cells[col].textContent;
      var nx = parseFloat(x), ny = parseFloat(y);
      if (!isNaN(nx) && !isNaN(ny)) return dir * (nx - ny);
      return dir * x.localeCompare(y);
    });
    rows.forEach(function (r) { body.appendChild(r); });
  });
});
function imagesStatus() {
  var imgs = Array.prototype.slice.call(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  var s = document.getElementById('status');
  s.textContent = 'images loaded: ' + ok + '/' + imgs.length + '; runs: ' + document.querySelectorAll('#runs tbody tr').length;
  s.dataset.loaded = ok; s.dataset.total = imgs.length;
}
window.addEventListener('load', imagesStatus);
"#;

pub fn index_html(report: &Report, assets: &PageAssets) -> String {
    let mut h = String::new();
    page_header(&mut h, report);
    scenes_table(&mut h, report);
    runs_table(&mut h, report, assets);
    figures_section(&mut h, assets);
    plots_section(&mut h, assets);
    let _ = writeln!(h, "<script>{SCRIPT}</script></body></html>");
    h
}

fn page_header(h: &mut String, report: &Report) {
    let _ = write!(
        h,
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>shadowtruth report</title>\
         <style>{STYLE}</style></head><body><h1>shadowtruth report</h1>\
         <p>{} {} · created {} · {} ({} cores) · schema <code>{}</code></p><p id=\"status\">images loading…</p>",
        escape(&report.tool.name),
        escape(&report.tool.version),
        escape(&report.created),
        escape(&report.machine.cpu),
        report.machine.cores,
        escape(&report.schema)
    );
}

fn scenes_table(h: &mut String, report: &Report) {
    h.push_str("<h2>Scenes</h2><table><thead><tr><th class=\"l\">scene</th><th class=\"l\">file</th><th>triangles</th><th>degenerate dropped</th><th>BVH build ms</th></tr></thead><tbody>");
    for s in &report.scenes {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{:.1}</td></tr>",
            escape(&s.name),
            escape(&s.file),
            s.triangles,
            s.dropped_degenerate,
            s.bvh_build_ms
        );
    }
    h.push_str("</tbody></table>");
}

fn runs_table(h: &mut String, report: &Report, assets: &PageAssets) {
    h.push_str("<h2>Runs</h2><p>Rates are fractions of the evaluated pixels; click a header to sort. False shadow: lit in truth, shadowed by the technique; false lit: the reverse. Aliasing: within one shadow-map texel of a true shadow boundary.</p>");
    h.push_str("<table id=\"runs\"><thead><tr>");
    for (name, left) in [
        ("scene", true),
        ("camera", true),
        ("light", true),
        ("technique", true),
        ("resolution", false),
        ("format", true),
        ("evaluated", false),
        ("false shadow", false),
        ("false lit", false),
        ("aliasing", false),
        ("acne", false),
        ("leak", false),
        ("error %", false),
        ("prepare ms", false),
        ("shade ms", false),
        ("ns/pixel", false),
        ("figures", true),
    ] {
        let _ = write!(h, "<th{}>{name}</th>", if left { " class=\"l\"" } else { "" });
    }
    h.push_str("</tr></thead><tbody>");
    for (i, r) in report.runs.iter().enumerate() {
        let c = &r.counts;
        let figs = match assets.run_figures.get(i).and_then(|f| f.as_ref()) {
            Some((t, e)) => {
                format!("<a href=\"{}\">visibility</a> <a href=\"{}\">errors</a>", escape(t), escape(e))
            }
            None => String::new(),
        };
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td>\
             <td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td data-v=\"{}\">{:.3}</td><td>{:.2}</td><td>{:.2}</td><td>{:.1}</td><td class=\"l\">{figs}</td></tr>",
            escape(&r.scene),
            escape(&r.camera),
            escape(&r.light),
            escape(&r.label),
            r.resolution,
            escape(&r.depth_format),
            c.evaluated,
            c.false_shadow,
            c.false_lit,
            c.aliasing,
            c.acne,
            c.leak,
            r.rates.error,
            100.0 * r.rates.error,
            r.timings.prepare,
            r.timings.shade,
            r.timings.ns_per_pixel
        );
    }
    h.push_str("</tbody></table>");
}

fn figures_section(h: &mut String, assets: &PageAssets) {
    if !assets.figures.is_empty() {
        h.push_str("<h2>Figures</h2><div class=\"figs\">");
        for (path, caption) in &assets.figures {
            let _ = write!(
                h,
                "<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{1}</figcaption></figure>",
                escape(path),
                escape(caption)
            );
        }
        h.push_str("</div>");
    }
}

fn plots_section(h: &mut String, assets: &PageAssets) {
    if !assets.plots.is_empty() {
        h.push_str("<h2>Plots</h2><div class=\"plots\">");
        for stem in &assets.plots {
            let _ = write!(
                h,
                "<p><a href=\"plots/{0}.svg\"><img src=\"plots/{0}.png\" alt=\"{0}\"></a></p>",
                escape(stem)
            );
        }
        h.push_str("</div>");
    }
}

/// `index.html`, linking the figures already written under `figures/` and the report's plots.
pub struct PageExport;

impl super::outputs::Export for PageExport {
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()> {
        let assets = page_assets(dir, report);
        crate::atomic_file::write_atomic(&dir.join("index.html"), index_html(report, &assets).as_bytes())
    }
}

/// What the page of the report folder `dir` shows: its grids and reference figures, each run's
/// figures where both were written, and the report's plots.
fn page_assets(dir: &Path, report: &Report) -> PageAssets {
    let mut figures: Vec<(String, String)> = std::fs::read_dir(dir.join("figures"))
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .filter_map(|e| e.file_name().into_string().ok())
                .filter(|n| n.ends_with(".grid.png") || n.ends_with(".reference.png"))
                .map(|n| (format!("figures/{n}"), n.trim_end_matches(".png").replace('.', " ")))
                .collect()
        })
        .unwrap_or_default();
    figures.sort();
    let run_figures = report
        .runs
        .iter()
        .map(|r| {
            let stem = run_stem(r);
            let (t, e) = (format!("figures/{stem}.technique.png"), format!("figures/{stem}.error.png"));
            (dir.join(&t).is_file() && dir.join(&e).is_file()).then_some((t, e))
        })
        .collect();
    let plots = charts(report).into_iter().map(|c| c.stem).collect();
    PageAssets { plots, figures, run_figures }
}
