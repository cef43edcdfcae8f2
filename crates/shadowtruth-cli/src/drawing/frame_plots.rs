//! The per-frame plots of runs over a path (`run --frames`): for each (scene, camera, light,
//! resolution, depth format) with such runs,
//! `plots/frames_<scene>.<camera>.<light>.r<res>.<format>.<digest>.png` and `.svg`, two charts on
//! one frame axis (`plots.rs`'s stacked charts): the error of every frame, one series per
//! technique setting, and the pixels that flickered since the frame before.

use super::plots::{Chart, write_stacked};
use shadowtruth::file_name;
use shadowtruth::record::{Report, RunRecord};
use std::path::Path;

/// The per-frame plot of one (view, resolution, depth format).
#[derive(Clone, Debug)]
pub struct FramePlot {
    /// File stem under `plots/`.
    pub stem: String,
    /// The error per frame, then the flickering pixels per frame.
    pub charts: [Chart; 2],
}

/// The stem under `plots/` of the per-frame plot of a run's (view, resolution, depth format):
/// `frames_<scene>.<camera>.<light>.r<res>.<format>.<digest>`, readable, bounded and one per
/// identity (`src/file_name.rs`).
pub fn frame_plot_stem(run: &RunRecord) -> String {
    let resolution = run.resolution.to_string();
    let parts = [run.scene.as_str(), &run.camera, &run.light, &resolution, &run.depth_format];
    let readable = [&run.scene, &run.camera, &run.light, &format!("r{resolution}"), &run.depth_format]
        .map(|part| file_name::readable(part))
        .join(".");
    file_name::stem_with(&format!("frames_{readable}"), &[&["frames"], &parts[..]].concat())
}

/// The runs over a path of each per-frame plot (indices into `report.runs`), with the plot's
/// stem, in the order of their first runs.
pub fn frame_plot_groups(report: &Report) -> Vec<(String, Vec<usize>)> {
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, run) in report.runs.iter().enumerate().filter(|(_, r)| r.temporal.is_some()) {
        let stem = frame_plot_stem(run);
        match groups.iter_mut().find(|(s, _)| *s == stem) {
            Some((_, runs)) => runs.push(i),
            None => groups.push((stem, vec![i])),
        }
    }
    groups
}

/// Every per-frame plot of the report, in the order of their first runs.
pub fn frame_plots(report: &Report) -> Vec<FramePlot> {
    frame_plot_groups(report).into_iter().map(|(stem, runs)| frame_plot(report, stem, &runs)).collect()
}

/// The plot of the runs `runs` of one (view, resolution, depth format), all over a path.
fn frame_plot(report: &Report, stem: String, runs: &[usize]) -> FramePlot {
    let first = &report.runs[runs[0]];
    let title = format!(
        "{}/{}/{} at {}² ({})",
        first.scene, first.camera, first.light, first.resolution, first.depth_format
    );
    let temporal =
        || runs.iter().filter_map(|&i| Some((&report.runs[i].label, report.runs[i].temporal.as_ref()?)));
    let errors = temporal()
        .map(|(label, t)| {
            let points = t.frame_errors.iter().enumerate();
            (label.clone(), points.map(|(k, &e)| (k as f64, super::plots::percent_on_log_axis(e))).collect())
        })
        .collect();
    // Frame 0 has no frame before it to flicker against.
    let flicker = temporal()
        .map(|(label, t)| {
            let points = t.frame_flicker.iter().enumerate().skip(1);
            (label.clone(), points.map(|(k, &n)| (k as f64, n as f64)).collect())
        })
        .collect();
    let charts = [
        Chart {
            title: format!("{title}: error per frame"),
            x_label: "frame".into(),
            integer_x: true,
            y_label: "error (% of evaluated pixels)".into(),
            series: errors,
            ..Chart::default()
        },
        Chart {
            title: format!("{title}: flickering pixels per frame"),
            x_label: "frame".into(),
            integer_x: true,
            y_label: "pixels flipped since the frame before".into(),
            linear_y: true,
            series: flicker,
            ..Chart::default()
        },
    ];
    FramePlot { stem, charts }
}

/// The per-frame plots under `plots/`.
pub struct FramePlotsExport;

impl crate::export::Export for FramePlotsExport {
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()> {
        use rayon::prelude::*;
        let plots = frame_plots(report);
        if plots.is_empty() {
            return Ok(());
        }
        let plots_dir = dir.join("plots");
        std::fs::create_dir_all(&plots_dir)?;
        plots.par_iter().try_for_each(|p| write_stacked(&plots_dir, &p.stem, &p.charts))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::drawing::plots::tests::line_colours;
    use crate::export::Export;
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::TemporalRecord;

    /// A run over `frames` frames whose error grows by 1 % a frame from 0.
    pub(crate) fn temporal_run(label: &str, resolution: u32, frames: usize) -> RunRecord {
        let counts = Counts { pixels: 100, evaluated: 100, ..Counts::default() };
        let mut r = crate::gate::test_run("s", "none", serde_json::json!({}), label, counts);
        r.resolution = resolution;
        r.temporal = Some(TemporalRecord {
            frames: frames as u32,
            moving: "camera".into(),
            frame_errors: (0..frames).map(|k| 0.01 * k as f64).collect(),
            frame_flicker: (0..frames).map(|k| 3 * k as u64).collect(),
            mean_error: 0.0,
            worst_frame: 0,
            worst_frame_error: 0.0,
            flicker_rate: 0.0,
            flicker_pixels: 0,
            compared_pixels: 100,
        });
        r
    }

    #[test]
    fn one_plot_per_map_with_a_series_per_technique_in_each_chart() {
        let mut single_frame = temporal_run("none", 1024, 1);
        single_frame.temporal = None;
        let runs = vec![
            temporal_run("a", 1024, 6),
            temporal_run("b", 1024, 6),
            temporal_run("c", 1024, 6),
            temporal_run("a", 2048, 6),
            single_frame,
        ];
        let report = Report { runs, ..Report::new() };
        let groups = frame_plot_groups(&report);
        assert_eq!(groups.iter().map(|g| g.1.clone()).collect::<Vec<_>>(), [vec![0, 1, 2], vec![3]]);
        let plots = frame_plots(&report);
        assert!(plots[0].stem.starts_with("frames_s.main.sun.r1024.f32."), "{}", plots[0].stem);
        let [errors, flicker] = &plots[0].charts;
        assert_eq!(errors.series.len(), 3);
        assert_eq!(errors.series[1].1[2], (2.0, 2.0), "frame 2 of b: 2 %");
        assert_eq!(flicker.series[0].1.first(), Some(&(1.0, 3.0)), "frame 0 flickers against nothing");

        let dir = tempfile::tempdir().unwrap();
        FramePlotsExport.write(dir.path(), &report).unwrap();
        let svg = std::fs::read_to_string(dir.path().join(format!("plots/{}.svg", plots[0].stem))).unwrap();
        // Each chart draws every series' line and repeats it in the legend: three colours, each
        // drawn twice in each of the two charts.
        let mut colours = line_colours(&svg);
        assert_eq!(colours.len(), 2 * 2 * 3, "{colours:?}");
        colours.sort();
        colours.dedup();
        assert_eq!(colours.len(), 3);
        assert!(dir.path().join(format!("plots/{}.png", plots[1].stem)).is_file());
    }
}
