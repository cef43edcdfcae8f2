//! Reading a report.json: bounded, schema first, every deserialisation error with its JSON path.

use super::{REPORT_SCHEMA, Report};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The largest report read: a run's record takes a few kilobytes and a plan expands to at most
/// 100 000 runs; a gigabyte holds some 300 000.
pub const MAX_REPORT_BYTES: u64 = 1 << 30;

/// A report that cannot be read: the message names the file (and the JSON path).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct ReportReadError(pub String);

/// Reads a report: a `report.json` file, or a folder holding one. Returns the report and the
/// file it was read from.
pub fn load_report(path: &Path) -> Result<(Report, PathBuf), ReportReadError> {
    let (report, file, _) = load_report_bytes(path).map_err(ReportReadError)?;
    Ok((report, file))
}

/// As [`load_report`], with the bytes read (a journal names the report.json it extends by them).
pub(crate) fn load_report_bytes(path: &Path) -> Result<(Report, PathBuf, Vec<u8>), String> {
    let file = if path.is_dir() { path.join("report.json") } else { path.to_path_buf() };
    let origin = file.display().to_string();
    if !file.exists() {
        return Err(format!("{origin}: no such report"));
    }
    let bytes = crate::input_file::read_named(&file, MAX_REPORT_BYTES)?;
    let text = std::str::from_utf8(&bytes).map_err(|e| format!("{origin}: not UTF-8 text: {e}"))?;
    let report = parse_report(text).map_err(|e| format!("{origin}: {e}"))?;
    Ok((report, file, bytes))
}

/// The schema is checked first, so that a report of another schema says so instead of failing
/// on a field that schema lacks.
fn parse_report(text: &str) -> Result<Report, String> {
    let value: Value = serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
    let expected = format!("expected \"{REPORT_SCHEMA}\"");
    match value.get("schema") {
        Some(Value::String(s)) if s == REPORT_SCHEMA => {}
        Some(other) => return Err(format!("schema: {expected}, got {other}")),
        None if value.is_object() => return Err(format!("schema: missing ({expected})")),
        None => return Err("expected a JSON object (a report)".into()),
    }
    serde_path_to_error::deserialize(value).map_err(|e| format!("{}: {}", e.path(), e.inner()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schema_is_checked_before_the_rest() {
        let report = Report { runs: vec![crate::record::test_run("a")], ..Report::new() };
        let mut v = serde_json::to_value(report).unwrap();
        v["schema"] = "shadowtruth/report/v2".into();
        v["runs"] = "changed in v2".into();
        let e = parse_report(&v.to_string()).unwrap_err();
        assert_eq!(e, "schema: expected \"shadowtruth/report/v1\", got \"shadowtruth/report/v2\"");
        v["schema"] = REPORT_SCHEMA.into();
        v["runs"] = serde_json::json!([serde_json::to_value(crate::record::test_run("a")).unwrap()]);
        v["runs"][0]["counts"]["false_lit"] = (-3).into();
        let e = parse_report(&v.to_string()).unwrap_err();
        assert!(e.starts_with("runs[0].counts.false_lit: invalid value: integer `-3`"), "{e}");
    }
}
