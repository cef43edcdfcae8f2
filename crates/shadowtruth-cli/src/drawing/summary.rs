//! What a person asks of a report first, per scene (or per group of scenes): each setting's
//! error over the scene's views, the best setting of each technique family at each resolution,
//! and the settings no other beats on both error and cost (the Pareto set). The terminal table
//! and the page's summary read it.

use super::pareto::{CostPoint, pareto_front};
use shadowtruth::record::{Report, RunRecord};

/// One setting (label, resolution, depth format) over the views of a scene or group.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingSummary {
    pub label: String,
    /// The technique family: the technique's name.
    pub technique: String,
    pub resolution: u32,
    pub depth_format: String,
    /// Rates over every scored pixel of the views (not a mean of the views' rates).
    pub false_shadow: f64,
    pub false_lit: f64,
    pub error: f64,
    /// Shading cost, the mean over the views of their medians.
    pub ns_per_pixel: f64,
    /// The means over the views of the least and greatest cost of the repeats.
    pub ns_per_pixel_range: [f64; 2],
    /// Whether the cost was measured here in every view (not another renderer's buffer).
    pub cost_measured: bool,
    pub views: usize,
}

impl SettingSummary {
    /// The cost as read: "12.3 (11.8–13.0)" ns/pixel, median and range of the repeats; "—"
    /// where it was not measured here.
    pub fn cost_text(&self) -> String {
        let [lo, hi] = self.ns_per_pixel_range;
        match (self.cost_measured, lo < hi) {
            (false, _) => "—".into(),
            (true, true) => format!("{:.1} ({lo:.1}–{hi:.1})", self.ns_per_pixel),
            (true, false) => format!("{:.1}", self.ns_per_pixel),
        }
    }

    fn cost_point(&self) -> CostPoint {
        CostPoint {
            cost: self.ns_per_pixel,
            cost_range: self.ns_per_pixel_range,
            error: self.error,
            measured: self.cost_measured,
        }
    }
}

/// The settings of one scene or group, in report order.
#[derive(Clone, Debug)]
pub struct GroupSummary {
    pub name: String,
    pub settings: Vec<SettingSummary>,
}

impl GroupSummary {
    /// The resolutions present, ascending.
    pub fn resolutions(&self) -> Vec<u32> {
        let mut r: Vec<u32> = self.settings.iter().map(|s| s.resolution).collect();
        r.sort_unstable();
        r.dedup();
        r
    }

    /// The best setting of each technique family at `resolution` (least error, then least cost),
    /// families in report order.
    pub fn best_per_family(&self, resolution: u32) -> Vec<&SettingSummary> {
        let mut best: Vec<&SettingSummary> = Vec::new();
        for s in self.settings.iter().filter(|s| s.resolution == resolution) {
            match best.iter_mut().find(|b| b.technique == s.technique) {
                Some(b) if (s.error, s.ns_per_pixel) < (b.error, b.ns_per_pixel) => *b = s,
                Some(_) => {}
                None => best.push(s),
            }
        }
        best
    }

    /// The settings at `resolution` that no other beats on error and cost beyond the cost's
    /// noise (pareto.rs), by cost.
    pub fn pareto(&self, resolution: u32) -> Vec<&SettingSummary> {
        let at: Vec<&SettingSummary> = self.settings.iter().filter(|s| s.resolution == resolution).collect();
        let points: Vec<CostPoint> = at.iter().map(|s| s.cost_point()).collect();
        pareto_front(&points).into_iter().map(|i| at[i]).collect()
    }
}

/// Groups of the report: each scene, or with `group` the scenes mapped to one name together.
pub fn summaries(report: &Report, group: impl Fn(&RunRecord) -> String) -> Vec<GroupSummary> {
    let mut groups: Vec<(String, Vec<&RunRecord>)> = Vec::new();
    for r in &report.runs {
        let name = group(r);
        match groups.iter_mut().find(|(n, _)| *n == name) {
            Some((_, runs)) => runs.push(r),
            None => groups.push((name, vec![r])),
        }
    }
    groups.into_iter().map(|(name, runs)| GroupSummary { name, settings: settings(&runs) }).collect()
}

/// The scene's own name: one group per scene.
pub fn per_scene(run: &RunRecord) -> String {
    run.scene.clone()
}

/// The run's view, `scene/camera/light`: one group per view.
pub fn per_view(run: &RunRecord) -> String {
    format!("{}/{}/{}", run.scene, run.camera, run.light)
}

/// The runs summed per (label, resolution, depth format), in first-seen order.
fn settings(runs: &[&RunRecord]) -> Vec<SettingSummary> {
    type Key<'a> = (&'a str, u32, &'a str);
    let mut keys: Vec<Key> = Vec::new();
    for r in runs {
        let key = (r.label.as_str(), r.resolution, r.depth_format.as_str());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(label, resolution, format)| {
            let of: Vec<&&RunRecord> = runs
                .iter()
                .filter(|r| {
                    (r.label.as_str(), r.resolution, r.depth_format.as_str()) == (label, resolution, format)
                })
                .collect();
            let scored = of.iter().map(|r| r.counts.scored()).sum::<u64>().max(1) as f64;
            let false_shadow = of.iter().map(|r| r.counts.false_shadow).sum::<u64>() as f64 / scored;
            let false_lit = of.iter().map(|r| r.counts.false_lit).sum::<u64>() as f64 / scored;
            let mean = |f: &dyn Fn(&RunRecord) -> f64| of.iter().map(|r| f(r)).sum::<f64>() / of.len() as f64;
            SettingSummary {
                label: label.to_string(),
                technique: of[0].technique.clone(),
                resolution,
                depth_format: format.to_string(),
                false_shadow,
                false_lit,
                error: false_shadow + false_lit,
                ns_per_pixel: mean(&|r| r.timings.ns_per_pixel),
                ns_per_pixel_range: [
                    mean(&|r| r.timings.cost_range()[0]),
                    mean(&|r| r.timings.cost_range()[1]),
                ],
                cost_measured: of.iter().all(|r| r.timings.cost_measured()),
                views: of.len(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;

    fn run(
        scene: &str,
        technique: &str,
        label: &str,
        resolution: u32,
        fs: u64,
        fl: u64,
        ns: f64,
    ) -> RunRecord {
        let mut r = crate::gate::test_run(
            scene,
            technique,
            serde_json::json!({}),
            label,
            Counts { evaluated: 1000, false_shadow: fs, false_lit: fl, ..Counts::default() },
        );
        r.resolution = resolution;
        // Timed here, with no spread: the front is the classic one.
        (r.timings.shade, r.timings.ns_per_pixel) = (ns * 1e-3, ns);
        r
    }

    fn report(runs: Vec<RunRecord>) -> Report {
        Report { runs, ..Report::new() }
    }

    #[test]
    fn a_scene_sums_its_views_and_names_the_best_of_each_family_and_the_pareto_set() {
        let mut second_view = run("a", "constant", "constant(b=1)", 512, 30, 0, 10.0);
        second_view.light = "other".into();
        let r = report(vec![
            run("a", "constant", "constant(b=1)", 512, 10, 0, 20.0),
            second_view,
            run("a", "constant", "constant(b=2)", 512, 5, 5, 12.0),
            run("a", "pcf", "pcf(size=3)", 512, 1, 1, 50.0),
            run("a", "pcf", "pcf(size=5)", 512, 1, 1, 80.0),
            run("b", "pcf", "pcf(size=3)", 512, 100, 0, 50.0),
        ]);
        let groups = summaries(&r, per_scene);
        assert_eq!(groups.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(), ["a", "b"]);
        let a = &groups[0];
        // constant(b=1): 40 false shadows over 2000 pixels, cost the mean of 20 and 10.
        assert_eq!(a.settings[0].error, 0.02);
        assert_eq!(a.settings[0].ns_per_pixel, 15.0);
        assert_eq!(a.settings[0].views, 2);
        let best: Vec<&str> = a.best_per_family(512).iter().map(|s| s.label.as_str()).collect();
        assert_eq!(best, ["constant(b=2)", "pcf(size=3)"]);
        let front: Vec<&str> = a.pareto(512).iter().map(|s| s.label.as_str()).collect();
        assert_eq!(front, ["constant(b=2)", "pcf(size=3)"]);
        let together = summaries(&r, |_| "all".into());
        assert_eq!(together.len(), 1);
        assert_eq!(together[0].settings.iter().find(|s| s.label == "pcf(size=3)").unwrap().views, 2);
    }
}
