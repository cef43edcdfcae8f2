//! `report.csv`: the rows of report.json, one per run, generated from the same `RunRecord`
//! serialization (nested fields become dotted columns, e.g. `counts.false_shadow`).

use super::{Report, RunRecord};
use serde_json::Value;

/// Flattens one record into (column, cell) pairs, in serialization order.
fn flatten(prefix: &str, value: &Value, out: &mut Vec<(String, String)>) {
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                flatten(&key, v, out);
            }
        }
        Value::String(s) => out.push((prefix.to_string(), s.clone())),
        Value::Null => out.push((prefix.to_string(), String::new())),
        other => out.push((prefix.to_string(), other.to_string())),
    }
}

fn record_cells(run: &RunRecord) -> Vec<(String, String)> {
    let mut cells = Vec::new();
    flatten("", &serde_json::to_value(run).unwrap_or(Value::Null), &mut cells);
    cells
}

/// The CSV text: a header with every column that any run has (parameters differ between
/// techniques), then one row per run; empty cells where a run lacks a column.
pub fn report_csv(report: &Report) -> Result<String, csv::Error> {
    let rows: Vec<Vec<(String, String)>> = report.runs.iter().map(record_cells).collect();
    let mut columns: Vec<String> = Vec::new();
    for row in &rows {
        for (k, _) in row {
            if !columns.contains(k) {
                columns.push(k.clone());
            }
        }
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&columns)?;
    for row in &rows {
        let cells: Vec<&str> = columns
            .iter()
            .map(|c| row.iter().find(|(k, _)| k == c).map_or("", |(_, v)| v.as_str()))
            .collect();
        w.write_record(&cells)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// `report.csv`.
pub struct CsvExport;

impl super::outputs::Export for CsvExport {
    fn write(&self, dir: &std::path::Path, report: &Report) -> std::io::Result<()> {
        let csv = report_csv(report).map_err(std::io::Error::other)?;
        crate::atomic_file::write_atomic(&dir.join("report.csv"), csv.as_bytes())
    }
}
