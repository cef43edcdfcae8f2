//! The page's "Over the path" section (`html.rs`): for runs over a path (`run --frames`), their
//! error over the frames and their flicker, then per (view, resolution, depth format) the
//! per-frame plot (`frame_plots.rs`) and each run's animated error map (`frame_movie.rs`) and
//! flicker heat map (`flicker_map.rs`). Images are linked only where their files were written.

use super::figures::run_stem;
use super::flicker_map::flicker_file_name;
use super::frame_movie::movie_file_name;
use super::frame_plots::frame_plot_groups;
use crate::escape::escape_html as escape;
use shadowtruth::record::Report;
use shadowtruth::record::{RunRecord, TemporalRecord};
use std::fmt::Write as _;
use std::path::Path;

/// The files of the section, relative to the report folder.
#[derive(Clone, Debug, Default)]
pub struct PathAssets {
    /// Per run (as `report.runs`): its animated error map and its heat map, where written.
    pub figures: Vec<(Option<String>, Option<String>)>,
    /// Per-frame plots written under `plots/` (stems).
    pub plots: Vec<String>,
}

/// What the report folder `dir` holds for the section.
pub fn path_assets(dir: &Path, report: &Report) -> PathAssets {
    let written = |path: String| dir.join(&path).is_file().then_some(path);
    let figures = report
        .runs
        .iter()
        .map(|r| match r.temporal {
            Some(_) => {
                let stem = run_stem(r);
                (
                    written(format!("figures/{}", movie_file_name(&stem))),
                    written(format!("figures/{}", flicker_file_name(&stem))),
                )
            }
            None => (None, None),
        })
        .collect();
    let plots = frame_plot_groups(report)
        .into_iter()
        .map(|(stem, _)| stem)
        .filter(|stem| dir.join(format!("plots/{stem}.png")).is_file())
        .collect();
    PathAssets { figures, plots }
}

/// The section, when the report has runs over a path.
pub fn path_section(h: &mut String, report: &Report, assets: &PathAssets) {
    let groups = frame_plot_groups(report);
    if groups.is_empty() {
        return;
    }
    h.push_str(
        "<h2>Over the path</h2><p>Runs scored at every frame of a camera or light path. Error: the share of \
         evaluated pixels wrong in a frame, averaged over the frames, and the worst frame (frames count from 0). \
         Flicker: surface points whose shadow flips between consecutive frames, as a share of the points compared \
         and as a count. Each run's error map is animated over the frames; its heat map colours each pixel by \
         how often it flickered (yellow: rarely, red: most often).</p>",
    );
    path_table(h, report, groups.iter().flat_map(|(_, runs)| runs.iter().copied()));
    for (stem, runs) in &groups {
        path_group(h, report, assets, stem, runs);
    }
}

/// One row per run over a path.
fn path_table(h: &mut String, report: &Report, runs: impl Iterator<Item = usize>) {
    h.push_str("<table id=\"path-runs\"><thead><tr>");
    for (name, left) in [
        ("scene / camera / light", true),
        ("technique", true),
        ("resolution", false),
        ("format", true),
        ("frames", false),
        ("moving", true),
        ("mean error %", false),
        ("worst frame", false),
        ("worst frame error %", false),
        ("flicker rate %", false),
        ("flickering pixels", false),
    ] {
        let _ = write!(h, "<th{}>{name}</th>", if left { " class=\"l\"" } else { "" });
    }
    h.push_str("</tr></thead><tbody>");
    for r in runs.map(|i| &report.runs[i]) {
        let Some(t) = &r.temporal else { continue };
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td><td>{}</td>\
             <td class=\"l\">{}</td><td>{:.3}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{}</td></tr>",
            escape(&view_name(r)),
            escape(&r.label),
            r.resolution,
            escape(&r.depth_format),
            t.frames,
            escape(&t.moving),
            100.0 * t.mean_error,
            t.worst_frame,
            100.0 * t.worst_frame_error,
            100.0 * t.flicker_rate,
            flicker_count(t)
        );
    }
    h.push_str("</tbody></table>");
}

/// `flicker_pixels of compared_pixels`.
fn flicker_count(t: &TemporalRecord) -> String {
    format!("{} of {}", t.flicker_pixels, t.compared_pixels)
}

fn view_name(r: &RunRecord) -> String {
    format!("{}/{}/{}", r.scene, r.camera, r.light)
}

/// One (view, resolution, depth format): its per-frame plot and its runs' animations and heat
/// maps.
fn path_group(h: &mut String, report: &Report, assets: &PathAssets, stem: &str, runs: &[usize]) {
    let first = &report.runs[runs[0]];
    let _ = write!(
        h,
        "<h3>{} at {}² ({})</h3>",
        escape(&view_name(first)),
        first.resolution,
        escape(&first.depth_format)
    );
    if assets.plots.iter().any(|p| p == stem) {
        let _ = write!(
            h,
            "<div class=\"plots\"><p><a href=\"plots/{0}.svg\"><img src=\"plots/{0}.png\" alt=\"{0}\"></a></p></div>",
            escape(stem)
        );
    }
    h.push_str("<div class=\"figs\">");
    for &i in runs {
        let Some((movie, heat)) = assets.figures.get(i) else { continue };
        if movie.is_none() && heat.is_none() {
            continue;
        }
        let label = escape(&report.runs[i].label);
        h.push_str("<figure>");
        for (path, what) in [(movie, "error map over the frames"), (heat, "flicker heat map")] {
            if let Some(path) = path {
                let _ =
                    write!(h, "<a href=\"{0}\"><img src=\"{0}\" alt=\"{label}: {what}\"></a>", escape(path));
            }
        }
        let _ = write!(h, "<figcaption>{label}</figcaption></figure>");
    }
    h.push_str("</div>");
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;

    fn run(label: &str, temporal: bool) -> RunRecord {
        let counts = Counts { pixels: 100, evaluated: 100, ..Counts::default() };
        let mut r = crate::gate::test_run("s", "none", serde_json::json!({}), label, counts);
        r.temporal = temporal.then(|| TemporalRecord {
            frames: 4,
            moving: "light".into(),
            frame_errors: vec![0.01, 0.02, 0.0125, 0.01],
            frame_flicker: vec![0, 3, 1, 0],
            mean_error: 0.0125,
            worst_frame: 1,
            worst_frame_error: 0.02,
            flicker_rate: 0.0133,
            flicker_pixels: 4,
            compared_pixels: 300,
        });
        r
    }

    #[test]
    fn the_section_lists_runs_over_a_path_and_links_what_was_written() {
        let report = Report { runs: vec![run("still", false), run("a<b", true)], ..Report::new() };
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("figures")).unwrap();
        let movie = format!("figures/{}", movie_file_name(&run_stem(&report.runs[1])));
        std::fs::write(dir.path().join(&movie), b"").unwrap();
        let assets = path_assets(dir.path(), &report);
        assert_eq!(assets.figures[1], (Some(movie.clone()), None), "no heat map was written");
        assert!(assets.plots.is_empty());
        let mut h = String::new();
        path_section(&mut h, &report, &assets);
        assert!(h.starts_with("<h2>Over the path</h2>"));
        assert_eq!(h.matches("<tr><td").count(), 1, "only the run over a path: {h}");
        assert!(h.contains("<td>1.250</td><td>1</td><td>2.000</td><td>1.330</td><td>4 of 300</td>"), "{h}");
        assert!(
            h.contains(&format!("<img src=\"{movie}\" alt=\"a&lt;b: error map over the frames\">")),
            "{h}"
        );
        assert!(!h.contains("flicker.png") && !h.contains("plots/"), "{h}");
        let mut none = String::new();
        path_section(&mut none, &Report { runs: vec![run("still", false)], ..Report::new() }, &assets);
        assert!(none.is_empty());
    }
}
