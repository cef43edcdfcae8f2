//! The journal of a report being written: the scenes and runs finished since report.json was
//! last written, one JSON line each, appended (and synced) as they finish. report.json itself
//! is rewritten only when a plan starts and ends, so a run of n maps writes O(n) bytes instead
//! of rewriting a growing report after every run; a kill at any moment leaves report.json whole
//! (the last complete report) and every finished run in the journal, folded in on resume.
//!
//! The journal's first line names the report.json it extends by the SHA-256 of its bytes: a
//! kill between writing a new report.json (which holds everything journaled) and starting a new
//! journal leaves a journal of an older report, which is then ignored instead of adding its runs
//! twice. A last line without its newline is an append cut short by the kill, and is ignored.

use super::load::{MAX_REPORT_BYTES, ReportReadError, load_report_bytes};
use super::{Report, RunRecord, SceneRecord};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The journal's name in a report folder, beside report.json.
pub const JOURNAL_FILE: &str = "report.journal";

/// One line of the journal after its header.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JournalEntry {
    Scene(SceneRecord),
    /// Boxed: a run's record is ten times a scene's.
    Run(Box<RunRecord>),
}

/// The journal's first line.
#[derive(Serialize, Deserialize)]
struct JournalHeader {
    extends_sha256: String,
}

/// The header line of a journal that extends the report.json holding `report_json`.
pub fn journal_header(report_json: &[u8]) -> Vec<u8> {
    let header = JournalHeader { extends_sha256: sha256_hex(report_json) };
    json_line(&header)
}

/// The line that journals `entry`.
pub fn journal_line(entry: &JournalEntry) -> Vec<u8> {
    json_line(entry)
}

/// Reads the report of the folder `dir` with what its journal adds (see the module comment).
pub fn load_journaled_report(dir: &Path) -> Result<(Report, PathBuf), ReportReadError> {
    let (mut report, file, bytes) = load_report_bytes(dir).map_err(ReportReadError)?;
    for entry in journal_entries(dir, &bytes).map_err(ReportReadError)? {
        match entry {
            JournalEntry::Scene(scene) => match report.scenes.iter_mut().find(|s| s.name == scene.name) {
                Some(earlier) => *earlier = scene,
                None => report.scenes.push(scene),
            },
            JournalEntry::Run(run) => report.runs.push(*run),
        }
    }
    Ok((report, file))
}

/// The entries of `dir`'s journal when it extends the report.json of `report_json` (none when
/// there is no journal, or one of an older report).
fn journal_entries(dir: &Path, report_json: &[u8]) -> Result<Vec<JournalEntry>, String> {
    let path = dir.join(JOURNAL_FILE);
    if !path.exists() {
        return Ok(Vec::new());
    }
    let bytes = crate::input_file::read_named(&path, MAX_REPORT_BYTES)?;
    let shown = path.display();
    let mut lines = complete_lines(&bytes);
    let Some(header) = lines.next() else { return Ok(Vec::new()) };
    let header: JournalHeader =
        serde_json::from_slice(header).map_err(|e| format!("{shown}: line 1: not a journal header: {e}"))?;
    if header.extends_sha256 != sha256_hex(report_json) {
        return Ok(Vec::new());
    }
    lines
        .enumerate()
        .map(|(i, line)| serde_json::from_slice(line).map_err(|e| format!("{shown}: line {}: {e}", i + 2)))
        .collect()
}

/// The lines of `bytes` that end with a newline (the last one, cut short, is left out).
fn complete_lines(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |end| end + 1);
    bytes[..complete].split_inclusive(|&b| b == b'\n').map(|line| &line[..line.len() - 1])
}

fn json_line(value: &impl Serialize) -> Vec<u8> {
    let mut line = serde_json::to_vec(value).expect("records serialise");
    line.push(b'\n');
    line
}

fn sha256_hex(bytes: &[u8]) -> String {
    crate::scene::hex(&Sha256::digest(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::test_run as run_named;

    fn write_report(dir: &Path, report: &Report) -> Vec<u8> {
        let bytes = serde_json::to_vec_pretty(report).unwrap();
        std::fs::write(dir.join("report.json"), &bytes).unwrap();
        bytes
    }

    fn labels(dir: &Path) -> Vec<String> {
        load_journaled_report(dir).unwrap().0.runs.into_iter().map(|r| r.label).collect()
    }

    #[test]
    fn a_journal_adds_its_runs_and_a_cut_last_line_is_left_out() {
        let dir = tempfile::tempdir().unwrap();
        let mut report = Report::new();
        report.runs.push(run_named("kept"));
        let bytes = write_report(dir.path(), &report);
        let mut journal = journal_header(&bytes);
        journal.extend(journal_line(&JournalEntry::Run(run_named("journaled").into())));
        let cut = journal_line(&JournalEntry::Run(run_named("cut").into()));
        journal.extend(&cut[..cut.len() / 2]);
        std::fs::write(dir.path().join(JOURNAL_FILE), &journal).unwrap();
        assert_eq!(labels(dir.path()), ["kept", "journaled"]);
    }

    #[test]
    fn a_journal_of_an_older_report_is_ignored() {
        let dir = tempfile::tempdir().unwrap();
        let mut report = Report::new();
        let older = write_report(dir.path(), &report);
        let mut journal = journal_header(&older);
        journal.extend(journal_line(&JournalEntry::Run(run_named("folded").into())));
        std::fs::write(dir.path().join(JOURNAL_FILE), &journal).unwrap();
        // Killed after the report holding the journaled run was written, before a new journal.
        report.runs.push(run_named("folded"));
        write_report(dir.path(), &report);
        assert_eq!(labels(dir.path()), ["folded"]);
    }
}
