//! The gate: rules (glob patterns on the runs of a report, an absolute bound on a metric and/or a
//! bound on its regression against a baseline report) → checks and violations. With a baseline,
//! every baseline run is paired with a run of the report or reported missing, so a removed or
//! renamed run cannot let the gate pass unchecked.
//!
//! - `rules.rs` reads rules files (TOML) and matches rules to runs;
//! - `input.rs` reads reports and rejects inconsistent ones ([`CheckedReport`]);
//! - `identity.rs` decides which baseline run is the same run as a run of the report;
//! - `check.rs` evaluates the rules ([`evaluate`], a pure function);
//! - `render.rs` prints the outcome as text and Markdown (JUnit XML is in `exports/junit.rs`);
//! - `fmt_value.rs` is how both the rules and the outcome print a value.
//!
//! Reading files is the only I/O here; the CLI writes the outputs.

mod check;
mod fmt_value;
mod identity;
mod input;
mod render;
mod rules;

pub use check::{BaselineComparison, Check, GateOptions, GateOutcome, evaluate};
pub use input::CheckedReport;
pub use rules::{Metric, RuleSpec, load_rules, parse_rules, rules_toml};

use std::fmt;

/// Bad input: every problem found, each naming its file and field.
#[derive(Clone, Debug, PartialEq)]
pub struct GateError {
    pub problems: Vec<String>,
}

impl GateError {
    fn one(message: String) -> Self {
        GateError { problems: vec![message] }
    }
}

impl fmt::Display for GateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.problems.join("\n"))
    }
}

impl std::error::Error for GateError {}

/// A run of `scene` (camera `main`, light `sun`, 1024² f32, hard reference) with these counts,
/// for the gate's unit tests.
#[cfg(test)]
pub(crate) fn test_run(
    scene: &str,
    technique: &str,
    parameters: serde_json::Value,
    label: &str,
    counts: shadowtruth::metrics::Counts,
) -> shadowtruth::record::RunRecord {
    shadowtruth::record::RunRecord {
        scene: scene.into(),
        camera: "main".into(),
        light: "sun".into(),
        technique: technique.into(),
        parameters: parameters.as_object().cloned().unwrap_or_default(),
        label: label.into(),
        resolution: 1024,
        depth_format: "f32".into(),
        counts,
        rates: counts.rates(),
        timings: shadowtruth::record::Timings::default(),
        layer_memory_bytes: 0,
        reference: Default::default(),
        soft: None,
        pipeline: None,
        cascades: None,
        point_map: None,
        temporal: None,
    }
}
