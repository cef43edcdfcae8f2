//! Writes `report.json` as runs finish. The whole report is written atomically when a plan
//! starts and when its last run finishes; in between each finished scene and run is appended to
//! the journal beside it (`shadowtruth::record::journal`), so that the I/O grows with the runs
//! (not with their square) while a killed run leaves the last complete report, never a
//! half-written one, and every finished run on disk for `--resume`.
//!
//! `ReportWriter::create` opens a report folder for `run` and `papers`: the outputs of an earlier
//! run there (`EARLIER_RUN_FILES`, and the figures and plots in `EARLIER_RUN_FOLDERS`) are removed
//! just before the new report.json is first written, so that no figure, plot or CSV row of an
//! earlier run stays beside the new report, while a plan rejected before its first run leaves the
//! earlier report whole. They are removed only from a folder whose report.json is a shadowtruth
//! report, and only the kinds of files this tool writes: whatever else a user keeps there stays.
//!
//! `ReportWriter::resume` reopens an interrupted folder instead (`run --resume`): its finished
//! runs and figures stay, the new runs join them, and the report is kept in schedule order
//! (`schedule_order.rs`).
//!
//! Both first lock the folder (`output_lock.rs`): a folder that another live process is writing
//! is refused before anything in it is removed or written.

use crate::plan::{Event, PlanError, Sink};
use shadowtruth::atomic_file::{remove_stray_temp_files, write_atomic};
use shadowtruth::record::{JOURNAL_FILE, JournalEntry, ScheduleRecord, journal_header, journal_line};
use shadowtruth::record::{Report, RunRecord, SceneRecord};
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Files of an earlier run removed from a report folder (report.json is replaced instead).
const EARLIER_RUN_FILES: [&str; 7] =
    ["report.csv", "index.html", "claims.json", "claims.html", "tune.json", "tune-gate.toml", JOURNAL_FILE];

/// Subfolders of a report folder and the extensions of the files this tool writes into them.
const EARLIER_RUN_FOLDERS: [(&str, &[&str]); 2] = [("figures", &["png"]), ("plots", &["svg", "png"])];

/// The start of the `schema` of every shadowtruth report.
const REPORT_SCHEMA_PREFIX: &str = "shadowtruth/report/";

pub struct ReportWriter {
    path: PathBuf,
    report: Report,
    /// Whether the outputs of an earlier run are still to be removed (before the first write).
    earlier_run_pending: bool,
    /// Whether the plan's schedule is recorded in the report (`run`'s reports).
    tracks_schedule: bool,
    /// The schedule identity the plan must have: that of the report being resumed.
    resumed_identity: Option<String>,
    /// The journal of what finished since report.json was written, while there is any.
    journal: Option<File>,
    /// Runs of the current plan still to finish; report.json is written whole after its last.
    runs_to_finish: usize,
}

impl ReportWriter {
    /// A writer of `dir/report.json` that leaves everything else in `dir` as it is; the file
    /// appears with the first write. `create` is what opens a report folder for a run.
    pub fn new(dir: &Path) -> Self {
        ReportWriter {
            path: dir.join("report.json"),
            report: Report::new(),
            earlier_run_pending: false,
            tracks_schedule: false,
            resumed_identity: None,
            journal: None,
            runs_to_finish: 0,
        }
    }

    /// Reopens `dir`, an interrupted run's folder, to finish `report` (its finished runs): only
    /// the temporary files of killed runs are removed. The plan's schedule must have the
    /// identity of `report`'s, or the plan stops before anything is built.
    pub fn resume(dir: &Path, report: Report) -> std::io::Result<Self> {
        shadowtruth::output_lock::lock_output_folder(dir)?;
        refuse_linked_subfolders(dir)?;
        remove_stray_report_temp_files(dir)?;
        let identity = report.schedule.as_ref().map(|s| s.identity.clone()).unwrap_or_default();
        let mut writer = Self::new(dir);
        (writer.report, writer.tracks_schedule, writer.resumed_identity) = (report, true, Some(identity));
        Ok(writer)
    }

    /// Records the plan's schedule (and `shard`, the share of it run here) in the report, and
    /// writes the report as soon as the plan is known, so that even a shard without views
    /// leaves a report folder.
    pub fn track_schedule(&mut self, shard: Option<shadowtruth::record::ShardRecord>) {
        self.tracks_schedule = true;
        self.report.shard = shard;
    }

    /// Opens `dir` as the report folder of a new run: creates and locks it, removes the temporary
    /// files of killed runs, and returns a writer that removes the outputs of an earlier run just
    /// before it first writes report.json (see the module comment).
    pub fn create(dir: &Path) -> std::io::Result<Self> {
        shadowtruth::output_lock::lock_output_folder(dir)?;
        refuse_linked_subfolders(dir)?;
        remove_stray_report_temp_files(dir)?;
        let mut writer = Self::new(dir);
        writer.earlier_run_pending = true;
        Ok(writer)
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

    /// Replaces the report to be written (`merge` writes a report it assembled).
    pub fn replace_report(&mut self, report: Report) {
        self.report = report;
    }

    pub fn add_scene(&mut self, scene: SceneRecord) -> std::io::Result<()> {
        let resumed = self.resumed_identity.is_some();
        match self.report.scenes.iter_mut().find(|s| resumed && s.name == scene.name) {
            // A resumed run builds the scene again: its record replaces the interrupted one's.
            Some(earlier) => *earlier = scene.clone(),
            None => self.report.scenes.push(scene.clone()),
        }
        self.put_in_order();
        self.journal(&JournalEntry::Scene(scene))
    }

    pub fn add_run(&mut self, run: RunRecord) -> std::io::Result<()> {
        self.report.runs.push(run.clone());
        self.put_in_order();
        self.journal(&JournalEntry::Run(Box::new(run)))?;
        self.runs_to_finish = self.runs_to_finish.saturating_sub(1);
        if self.runs_to_finish == 0 { self.flush() } else { Ok(()) }
    }

    /// Takes the plan's schedule, refusing one that is not the resumed report's.
    fn planned(&mut self, runs: usize, schedule: &ScheduleRecord) -> Result<(), PlanError> {
        self.runs_to_finish = runs;
        if !self.tracks_schedule {
            return Ok(());
        }
        if let Some(identity) = &self.resumed_identity
            && *identity != schedule.identity
        {
            return Err(PlanError::Invalid(format!(
                "{}: schedule.identity: the folder holds a run of another plan, other scenes or other \
                     options ({identity}, this run: {}); run without --resume to replace it, or write to \
                     another folder",
                self.path.display(),
                schedule.identity
            )));
        }
        self.report.schedule = Some(schedule.clone());
        let written = if runs == 0 { self.flush() } else { self.start_journal() };
        written.map_err(|source| PlanError::Io { path: self.path.clone(), source })
    }

    /// Writes the whole report.json; what the journal held is in it, so the journal goes.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.write_report_json()?;
        self.journal = None;
        remove_if_present(&self.dir().join(JOURNAL_FILE))
    }

    /// Writes the whole report.json, then a new journal that extends it.
    fn start_journal(&mut self) -> std::io::Result<()> {
        let written = self.write_report_json()?;
        let path = self.dir().join(JOURNAL_FILE);
        write_atomic(&path, &journal_header(&written))?;
        self.journal = Some(File::options().append(true).open(&path)?);
        Ok(())
    }

    /// Appends `entry` to the journal (started first if there is none), synced before the next
    /// run starts: a finished run is on disk as soon as its record is.
    fn journal(&mut self, entry: &JournalEntry) -> std::io::Result<()> {
        if self.journal.is_none() {
            self.start_journal()?;
        }
        let journal = self.journal.as_mut().expect("started above");
        journal.write_all(&journal_line(entry))?;
        journal.sync_data()
    }

    /// Writes report.json atomically and returns its bytes.
    fn write_report_json(&mut self) -> std::io::Result<Vec<u8>> {
        if self.earlier_run_pending {
            remove_earlier_run_outputs(self.dir())?;
            self.earlier_run_pending = false;
        }
        self.put_in_order();
        let mut text = serde_json::to_vec_pretty(&self.report).map_err(std::io::Error::other)?;
        text.push(b'\n');
        write_atomic(&self.path, &text)?;
        Ok(text)
    }

    /// A resumed report is kept in schedule order (the earlier runs are there from the start).
    fn put_in_order(&mut self) {
        if self.resumed_identity.is_some() {
            super::schedule_order::put_in_schedule_order(&mut self.report);
        }
    }

    /// Writes report.json whole when the journal holds what it lacks.
    fn flush_journaled(&mut self) -> std::io::Result<()> {
        if self.journal.is_some() { self.flush() } else { Ok(()) }
    }

    #[cfg(test)]
    pub fn into_report(mut self) -> Report {
        self.flush_journaled().expect("report.json written");
        std::mem::take(&mut self.report)
    }
}

/// report.json as a sink of a plan's events: each scene and run is added as it finishes.
impl Sink for ReportWriter {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        let written = match event {
            Event::Planned { runs, schedule } => return self.planned(*runs, schedule),
            Event::SceneBuilt(record) => self.add_scene((*record).clone()),
            Event::RunDone { record, .. } => self.add_run((*record).clone()),
            _ => return Ok(()),
        };
        written.map_err(|source| PlanError::Io { path: self.path.clone(), source })
    }
}

/// What finished after the plan's last run (a scene of a resumed run, whose maps were all done)
/// is only in the journal: report.json is written whole once more, as the report it ends with.
impl Drop for ReportWriter {
    fn drop(&mut self) {
        // An error here has no one to go to; the journal then still holds every finished run.
        let _ = self.flush_journaled();
    }
}

/// A report folder's `figures/` and `plots/` must be folders of its own: one that is a link (or
/// anything but a folder) would have the run write, and remove earlier figures, elsewhere.
fn refuse_linked_subfolders(dir: &Path) -> std::io::Result<()> {
    for (folder, _) in EARLIER_RUN_FOLDERS {
        let path = dir.join(folder);
        match std::fs::symlink_metadata(&path) {
            Ok(meta) if !meta.is_dir() => {
                let what = if meta.file_type().is_symlink() { "a symbolic link" } else { "not a folder" };
                return Err(std::io::Error::other(format!(
                    "{} is {what}: a report folder's {folder}/ must be a folder of its own",
                    path.display()
                )));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Removes the temporary files that killed runs left in a report folder, its figures and plots.
pub fn remove_stray_report_temp_files(dir: &Path) -> std::io::Result<()> {
    remove_stray_temp_files(dir)?;
    for (folder, _) in EARLIER_RUN_FOLDERS {
        remove_stray_temp_files(&dir.join(folder))?;
    }
    Ok(())
}

/// Removes what an earlier run wrote into `dir` besides report.json, when `dir` holds a report.
fn remove_earlier_run_outputs(dir: &Path) -> std::io::Result<()> {
    if !holds_a_report(dir) {
        return Ok(());
    }
    for file in EARLIER_RUN_FILES {
        remove_if_present(&dir.join(file))?;
    }
    for (folder, extensions) in EARLIER_RUN_FOLDERS {
        remove_files_with_extensions(&dir.join(folder), extensions)?;
    }
    Ok(())
}

/// Whether `dir/report.json` is a shadowtruth report (of any schema version).
fn holds_a_report(dir: &Path) -> bool {
    #[derive(serde::Deserialize)]
    struct Schema {
        schema: String,
    }
    std::fs::read(dir.join("report.json"))
        .ok()
        .and_then(|bytes| serde_json::from_slice::<Schema>(&bytes).ok())
        .is_some_and(|s| s.schema.starts_with(REPORT_SCHEMA_PREFIX))
}

/// Removes the files of `dir` with one of `extensions`, then `dir` itself if that empties it.
fn remove_files_with_extensions(dir: &Path, extensions: &[&str]) -> std::io::Result<()> {
    // Never through a link: a `figures` that links elsewhere is not this tool's folder.
    if !std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        return Ok(());
    }
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        // The entry's own type: a link named `x.png` is removed as a link, never followed.
        let is_file = entry.file_type()?.is_file();
        if is_file && path.extension().is_some_and(|x| extensions.iter().any(|e| x == *e)) {
            remove_if_present(&path)?;
        }
    }
    let _ = std::fs::remove_dir(dir); // fails, as it should, when the user keeps files there
    Ok(())
}

fn remove_if_present(path: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        result => result,
    }
}
