//! The tables `run` prints when it ends: per scene (or per group of scenes, or the whole suite)
//! the false shadow / false lit of every setting at every resolution, then the best setting of
//! each technique family and the Pareto set at the highest resolution.

use crate::drawing::palette::{FALSE_LIT, FALSE_SHADOW, terminal_colour};
use crate::drawing::summary::{GroupSummary, SettingSummary, per_scene, per_view, summaries};
use shadowtruth::record::{Report, RunRecord};
use std::path::Path;

/// How the runs are split into tables.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum TableLayout {
    /// One table per scene (its cameras and lights pooled).
    #[default]
    PerScene,
    /// One table per view (scene, camera and light).
    PerView,
    /// One table per folder of scene files (`scenes/`, `scenes/papers/`, …).
    Grouped,
    /// One table over every scene.
    Suite,
}

pub(super) fn print_tables(report: &Report, layout: TableLayout) {
    let key = |run: &RunRecord| match layout {
        TableLayout::PerScene => per_scene(run),
        TableLayout::PerView => per_view(run),
        TableLayout::Grouped => scene_folder(report, &run.scene),
        TableLayout::Suite => "all scenes".into(),
    };
    let groups = summaries(report, key);
    if !groups.is_empty() {
        // anstream leaves the colour out where stdout is no terminal or NO_COLOR is set.
        anstream::println!(
            "\nshd/lit %: {} / {}, of the evaluated pixels of the views a table pools (named under \
             its title)",
            coloured(FALSE_SHADOW, "false shadow %"),
            coloured(FALSE_LIT, "false lit %")
        );
    }
    for g in &groups {
        print_group(g, &views_of(report, &g.name, key));
    }
    if let Some(line) = uncertain_line(report) {
        println!("{line}");
    }
}

/// The views whose reference cannot decide some pixels beyond doubt, with how many (left out of
/// every rate above); None when every view's reference decides every pixel.
fn uncertain_line(report: &Report) -> Option<String> {
    let mut views: Vec<(String, u64)> = Vec::new();
    for r in report.runs.iter().filter(|r| r.counts.uncertain > 0) {
        let view = format!("{}/{}/{}", r.scene, r.camera, r.light);
        if !views.iter().any(|(v, _)| *v == view) {
            // A run over frames sums its frames' counts: the count shown is the run's.
            views.push((view, r.counts.uncertain));
        }
    }
    if views.is_empty() {
        return None;
    }
    let list: Vec<String> = views.iter().map(|(v, n)| format!("{v} {n}")).collect();
    Some(format!("reference uncertain (pixels left out of every score): {}", list.join(", ")))
}

/// The views (scene/camera/light) of the runs `key` puts in group `group`, in the
/// report's order.
fn views_of(report: &Report, group: &str, key: impl Fn(&RunRecord) -> String) -> Vec<String> {
    let mut views: Vec<String> = Vec::new();
    for r in report.runs.iter().filter(|r| key(r) == group) {
        let view = format!("{}/{}/{}", r.scene, r.camera, r.light);
        if !views.contains(&view) {
            views.push(view);
        }
    }
    views
}

/// The folder of a scene's file, as the report records it.
fn scene_folder(report: &Report, scene: &str) -> String {
    report
        .scenes
        .iter()
        .find(|s| s.name == scene)
        .and_then(|s| Path::new(&s.file).parent().map(|p| p.display().to_string()))
        .filter(|p| !p.is_empty())
        .unwrap_or_else(|| ".".into())
}

fn row_name(s: &SettingSummary) -> String {
    if s.depth_format == "f32" { s.label.clone() } else { format!("{} [{}]", s.label, s.depth_format) }
}

/// `text` in the terminal's nearest colour to `rgb`.
fn coloured(rgb: [u8; 3], text: &str) -> String {
    let style = anstyle::Style::new().fg_color(Some(anstyle::Ansi256Color(terminal_colour(rgb)).into()));
    format!("{style}{text}{style:#}")
}

/// False shadow / false lit (fractions) in % in the colour code, right-aligned in `width`
/// characters (the colour's escapes take no room on screen).
fn rate_cell(false_shadow: f64, false_lit: f64, width: usize) -> String {
    let (shadow, lit) = (format!("{:.2}", 100.0 * false_shadow), format!("{:.2}", 100.0 * false_lit));
    let pad = width.saturating_sub(shadow.len() + 1 + lit.len());
    format!("{}{}/{}", " ".repeat(pad), coloured(FALSE_SHADOW, &shadow), coloured(FALSE_LIT, &lit))
}

fn print_group(g: &GroupSummary, views: &[String]) {
    let resolutions = g.resolutions();
    let mut unique: Vec<String> = Vec::new();
    for row in g.settings.iter().map(row_name) {
        if !unique.contains(&row) {
            unique.push(row);
        }
    }
    let width = unique.iter().map(|r| r.len()).max().unwrap_or(9).max(9);
    println!("\n{}", g.name);
    match views {
        [one] => println!("view {one}"),
        _ => println!("pools the pixels of {} views: {}", views.len(), views.join(", ")),
    }
    print!("{:width$}", "technique");
    for res in &resolutions {
        print!("  {:>15}", format!("{res}² shd/lit %"));
    }
    println!();
    for row in &unique {
        print!("{row:width$}");
        for res in &resolutions {
            match g.settings.iter().find(|s| s.resolution == *res && row_name(s) == *row) {
                Some(s) => anstream::print!("  {}", rate_cell(s.false_shadow, s.false_lit, 15)),
                None => print!("  {:>15}", "-"),
            }
        }
        println!();
    }
    let Some(&top) = resolutions.last() else { return };
    println!(
        "best of each technique at {top}² (error %, CPU shading ns/pixel: median (range) of the repeats):"
    );
    for s in g.best_per_family(top) {
        println!("  {:<14} {:<width$} {:>8.3}  {}", s.technique, row_name(s), 100.0 * s.error, s.cost_text());
    }
    let front: Vec<String> = g.pareto(top).iter().map(|s| row_name(s)).collect();
    println!(
        "Pareto set at {top}² (none better in error and no costlier beyond the timing noise), by cost: {}",
        front.join(", ")
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;

    #[test]
    fn the_views_with_uncertain_pixels_are_listed_once() {
        let run = |scene: &str, label: &str, uncertain: u64| {
            let counts = Counts { pixels: 10, evaluated: 10 - uncertain, uncertain, ..Counts::default() };
            crate::gate::test_run(scene, "none", serde_json::json!({}), label, counts)
        };
        let mut report = Report { runs: vec![run("a", "x", 0), run("b", "x", 0)], ..Report::default() };
        assert_eq!(uncertain_line(&report), None);
        report.runs = vec![run("a", "x", 0), run("rocks", "x", 3), run("rocks", "y", 3), run("spot", "x", 1)];
        let line = uncertain_line(&report).expect("two views have uncertain pixels");
        assert!(line.ends_with(": rocks/main/sun 3, spot/main/sun 1"), "{line}");
    }

    #[test]
    fn a_cell_is_aligned_as_its_plain_text_and_coloured_in_the_code() {
        let cell = rate_cell(0.0123, 0.5, 15);
        assert_eq!(anstream::adapter::strip_str(&cell).to_string(), format!("{:>15}", "1.23/50.00"));
        // xterm's 256 colours: 166 vermillion (false shadow), 25 blue (false lit).
        assert!(cell.contains("\x1b[38;5;166m1.23\x1b[0m/\x1b[38;5;25m50.00"), "{cell:?}");
    }

    #[test]
    fn a_table_names_the_views_it_pools() {
        let run = |scene: &str, light: &str| {
            let mut r = crate::gate::test_run(scene, "none", serde_json::json!({}), "x", Counts::default());
            r.light = light.into();
            r
        };
        let report = Report {
            runs: vec![run("a", "sun"), run("a", "lamp"), run("a", "sun"), run("b", "sun")],
            ..Report::default()
        };
        assert_eq!(views_of(&report, "a", per_scene), ["a/main/sun", "a/main/lamp"]);
        assert_eq!(views_of(&report, "all", |_| "all".to_string()).len(), 3);
        assert_eq!(views_of(&report, "a/main/lamp", per_view), ["a/main/lamp"]);
    }
}
