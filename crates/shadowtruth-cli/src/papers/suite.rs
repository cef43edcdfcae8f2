//! What each paper's experiments (`ehm_fig12.rs`, `ehm_pcf.rs`, `pagot.rs`, `weiskopf.rs`) are
//! given: the report they write the runs of their set-up into (through the plan executor, with
//! their figures), the reference cache, and the plan of a set-up. `run.rs` runs them in turn.

use crate::plan::{Event, Plan, PlanError, Sink, emit, execute};
use shadowtruth::record::RunRecord;
use shadowtruth::technique::TechniqueSpec;
use shadowtruth::trace::ReferenceCache;
use std::path::{Path, PathBuf};

/// How much of the suite to run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PapersOptions {
    /// The paper's set-ups at their resolutions, but a smaller sensitivity grid (one other
    /// set-up per claim), one timing pass and fewer table cells (`pagot.rs`, `ehm_cost.rs`):
    /// for tests.
    pub quick: bool,
}

/// What every paper's experiments write into and read from.
pub(super) struct Suite<'a, 's> {
    /// Holds `papers/*.json`.
    pub scenes_dir: PathBuf,
    /// The report folder.
    pub dir: PathBuf,
    /// The reference cache, or one for this run only: references are traced once per run and
    /// shared by the report's runs and the claims.
    pub cache: &'a ReferenceCache,
    /// Where the set-ups' runs go: the report, its figures, progress.
    pub sinks: &'a mut [&'s mut dyn Sink],
    pub options: PapersOptions,
}

impl Suite<'_, '_> {
    /// Runs the paper's set-up into the report (its records and figures), and returns its
    /// runs' records, so that a claim can name the figures of the runs it judges.
    pub fn report(&mut self, plan: &Plan) -> Result<SetupRuns, PlanError> {
        let mut runs = SetupRuns(Vec::new());
        let mut sinks: Vec<&mut dyn Sink> =
            self.sinks.iter_mut().map(|s| &mut **s as &mut dyn Sink).collect();
        sinks.push(&mut runs);
        execute(plan, Some(self.cache), &mut sinks)?;
        Ok(runs)
    }

    pub fn stage(&mut self, what: &str) -> Result<(), PlanError> {
        emit(self.sinks, &Event::Stage(&format!("papers: {what}")))
    }

    /// `all` in full runs; in quick runs the first (the paper's set-up) and the second only.
    pub fn grid<T>(&self, mut all: Vec<T>) -> Vec<T> {
        if self.options.quick {
            all.truncate(2);
        }
        all
    }

    pub fn scene(&self, file: &str) -> PathBuf {
        self.scenes_dir.join("papers").join(file)
    }
}

/// The records of the runs of a paper's set-up, as the report holds them.
pub(super) struct SetupRuns(Vec<RunRecord>);

impl Sink for SetupRuns {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        if let Event::RunDone { record, .. } = event {
            self.0.push((*record).clone());
        }
        Ok(())
    }
}

impl SetupRuns {
    /// The error map (`figures/<run stem>.error.png`, drawn by the report's figures) of the run
    /// of `technique` on `camera` at `resolution`, if the set-up ran it.
    pub fn error_map(&self, camera: &str, technique: &TechniqueSpec, resolution: u32) -> Option<String> {
        let label = technique.label();
        self.0
            .iter()
            .find(|r| r.camera == camera && r.label == label && r.resolution == resolution)
            .map(|r| format!("figures/{}.error.png", crate::drawing::figures::run_stem(r)))
    }
}

/// A plan of `techniques` × `resolutions` on `cameras` and one light of `scene` (one repeat:
/// the timings that claims read are measured by the claims themselves).
pub(super) fn plan_of(
    scene: &Path,
    cameras: &[&str],
    light: &str,
    techniques: Vec<TechniqueSpec>,
    resolutions: &[u32],
) -> Plan {
    Plan {
        cameras: Some(cameras.iter().map(|c| c.to_string()).collect()),
        lights: Some(vec![light.to_string()]),
        repeats: 1,
        ..Plan::new(vec![scene.to_path_buf()], techniques, resolutions.to_vec())
    }
}
