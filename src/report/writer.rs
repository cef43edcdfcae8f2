//! Writes `report.json` as runs finish: the whole report is rewritten atomically after each
//! run, so a killed run leaves the last complete report, never a half-written one.

use super::{Report, RunRecord, SceneRecord};
use crate::atomic_file::write_atomic;
use std::path::{Path, PathBuf};

pub struct ReportWriter {
    path: PathBuf,
    report: Report,
}

impl ReportWriter {
    /// A writer of `dir/report.json`; the file appears with the first write.
    pub fn new(dir: &Path) -> Self {
        ReportWriter { path: dir.join("report.json"), report: Report::new() }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The report folder.
    pub fn dir(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new("."))
    }

    pub fn report(&self) -> &Report {
        &self.report
    }

    pub fn add_scene(&mut self, scene: SceneRecord) -> std::io::Result<()> {
        self.report.scenes.push(scene);
        self.flush()
    }

    pub fn add_run(&mut self, run: RunRecord) -> std::io::Result<()> {
        self.report.runs.push(run);
        self.flush()
    }

    pub fn flush(&self) -> std::io::Result<()> {
        let mut text = serde_json::to_string_pretty(&self.report).map_err(std::io::Error::other)?;
        text.push('\n');
        write_atomic(&self.path, text.as_bytes())
    }

    pub fn into_report(self) -> Report {
        self.report
    }
}
