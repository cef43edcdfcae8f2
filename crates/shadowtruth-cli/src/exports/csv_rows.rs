//! `report.csv`: the rows of report.json, one per run, generated from the same `RunRecord`
//! serialization (nested fields become dotted columns, e.g. `counts.false_shadow`). A run over a
//! path and a run on cascaded shadow maps hold lists (per frame, per cascade) that no cell holds
//! well: their summaries are the [`PATH_COLUMNS`] instead, after every other column so that no
//! column moves when a report has such runs.
//!
//! Names come from untrusted scene and plan files, and a spreadsheet runs a cell that starts with
//! `=`, `+`, `-`, `@`, a tab or a carriage return as a formula: every text cell (and column name)
//! that starts so gets a leading `'`, as OWASP advises against CSV injection. Numbers are written
//! as they are (a negative number is a number, not a formula).

use serde_json::Value;
use shadowtruth::record::{Report, RunRecord};

/// Flattens one record into (column, cell) pairs, in serialization order.
fn flatten(prefix: &str, value: &Value, out: &mut Vec<(String, String)>) {
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                flatten(&key, v, out);
            }
        }
        Value::String(s) => out.push((prefix.to_string(), neutralised(s))),
        Value::Null => out.push((prefix.to_string(), String::new())),
        other => out.push((prefix.to_string(), other.to_string())),
    }
}

/// The first characters that make a spreadsheet take a cell for a formula.
const FORMULA_STARTS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// `text` as a cell that no spreadsheet runs: with a leading `'` when it starts as a formula.
fn neutralised(text: &str) -> String {
    if text.starts_with(FORMULA_STARTS) { format!("'{text}") } else { text.to_string() }
}

/// The last columns, in every report: the summary of `temporal` (empty for a run of one frame)
/// and the number of cascades (empty for a run on one shadow map).
pub const PATH_COLUMNS: [&str; 6] =
    ["mean_error", "worst_frame", "worst_frame_error", "flicker_rate", "flicker_pixels", "cascades"];

/// The record's fields as (column, cell) pairs, less the objects summarised in [`PATH_COLUMNS`].
fn record_cells(run: &RunRecord) -> Vec<(String, String)> {
    let mut value = serde_json::to_value(run).unwrap_or(Value::Null);
    if let Some(fields) = value.as_object_mut() {
        fields.remove("temporal");
        fields.remove("cascades");
    }
    let mut cells = Vec::new();
    flatten("", &value, &mut cells);
    cells
}

/// The cells of [`PATH_COLUMNS`], numbers written as the other columns write them.
fn path_cells(run: &RunRecord) -> [String; 6] {
    let number = |v: Value| v.to_string();
    let [mut mean, mut worst, mut worst_error, mut rate, mut pixels]: [String; 5] = Default::default();
    if let Some(t) = &run.temporal {
        mean = number(t.mean_error.into());
        worst = number(t.worst_frame.into());
        worst_error = number(t.worst_frame_error.into());
        rate = number(t.flicker_rate.into());
        pixels = number(t.flicker_pixels.into());
    }
    let cascades = run.cascades.as_ref().map_or_else(String::new, |c| c.cascades.len().to_string());
    [mean, worst, worst_error, rate, pixels, cascades]
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
    let header = columns.iter().map(|c| neutralised(c));
    w.write_record(header.chain(PATH_COLUMNS.map(String::from)))?;
    for (row, run) in rows.iter().zip(&report.runs) {
        let cells = columns.iter().map(|c| row.iter().find(|(k, _)| k == c).map_or("", |(_, v)| v.as_str()));
        let path = path_cells(run);
        w.write_record(cells.chain(path.iter().map(String::as_str)))?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// `report.csv`.
pub struct CsvExport;

impl crate::export::Export for CsvExport {
    fn write(&self, dir: &std::path::Path, report: &Report) -> std::io::Result<()> {
        let csv = report_csv(report).map_err(std::io::Error::other)?;
        shadowtruth::atomic_file::write_atomic(&dir.join("report.csv"), csv.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::{CascadeCounts, CascadeRecord, CascadesRecord, TemporalRecord};

    fn run(label: &str) -> RunRecord {
        let counts = Counts { pixels: 100, evaluated: 100, false_shadow: 3, ..Counts::default() };
        crate::gate::test_run("s", "none", serde_json::json!({}), label, counts)
    }

    fn temporal() -> TemporalRecord {
        TemporalRecord {
            frames: 3,
            moving: "camera".into(),
            frame_errors: vec![0.01, 0.04, 0.02],
            frame_flicker: vec![0, 5, 2],
            mean_error: 0.07 / 3.0,
            worst_frame: 1,
            worst_frame_error: 0.04,
            flicker_rate: 0.035,
            flicker_pixels: 7,
            compared_pixels: 200,
        }
    }

    fn cascades(count: usize) -> CascadesRecord {
        let cascade = CascadeRecord {
            near: 0.1,
            far: 10.0,
            texel_world: 0.01,
            texel_pixels_at_far: 1.5,
            counts: CascadeCounts::default(),
        };
        CascadesRecord {
            split: "uniform".into(),
            fit: "sphere".into(),
            stabilize: true,
            blend_band: 0.0,
            cascades: vec![cascade; count],
            beyond: CascadeCounts::default(),
        }
    }

    fn table(runs: Vec<RunRecord>) -> Vec<csv::StringRecord> {
        let text = report_csv(&Report { runs, ..Report::new() }).unwrap();
        let mut reader = csv::ReaderBuilder::new().has_headers(false).from_reader(text.as_bytes());
        reader.records().map(Result::unwrap).collect()
    }

    #[test]
    fn text_that_starts_as_a_formula_is_quoted_and_numbers_stay_numbers() {
        let mut r = run("=HYPERLINK(\"x\")");
        r.scene = "+1".into();
        r.camera = "@SUM(A1)".into();
        r.light = "\tsun".into();
        r.parameters.insert("-bias".into(), serde_json::json!(-0.5));
        r.parameters.insert("tag".into(), serde_json::json!("-2"));
        let rows = table(vec![r]);
        let cell = |column: &str| {
            let at = rows[0].iter().position(|c| c == column).unwrap_or_else(|| panic!("{column}"));
            rows[1][at].to_string()
        };
        assert_eq!(cell("label"), "'=HYPERLINK(\"x\")");
        assert_eq!(cell("scene"), "'+1");
        assert_eq!(cell("camera"), "'@SUM(A1)");
        assert_eq!(cell("light"), "'\tsun");
        assert_eq!(cell("parameters.tag"), "'-2");
        assert_eq!(cell("parameters.-bias"), "-0.5");
        assert_eq!(cell("technique"), "none");
    }

    #[test]
    fn path_columns_come_last_and_are_empty_for_other_runs() {
        let plain = table(vec![run("none")]);
        let mut over_path = run("none");
        over_path.temporal = Some(temporal());
        over_path.cascades = Some(cascades(4));
        let rows = table(vec![run("none"), over_path]);
        // The columns of a report without such runs keep their places; the path's come after.
        let header: Vec<&str> = rows[0].iter().collect();
        let before = plain[0].len() - PATH_COLUMNS.len();
        assert_eq!(header, plain[0].iter().collect::<Vec<_>>());
        assert_eq!(header[before..], PATH_COLUMNS);
        assert!(
            !header.iter().any(|c| c.starts_with("temporal") || c.starts_with("cascades.")),
            "{header:?}"
        );
        assert!(rows[1].iter().skip(before).all(str::is_empty), "{:?}", rows[1]);
        let cells: Vec<&str> = rows[2].iter().skip(before).collect();
        assert_eq!(cells, [&serde_json::json!(0.07 / 3.0).to_string(), "1", "0.04", "0.035", "7", "4"]);
        assert_eq!(cells[0].parse::<f64>().unwrap(), 0.07 / 3.0);
    }
}
