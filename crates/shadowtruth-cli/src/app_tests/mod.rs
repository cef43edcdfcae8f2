//! Tests of the command's own modules (plans, the schedule, reports, figures, the papers
//! suite), which are private to the crate; they share the integration tests' helpers.

#[path = "../../../shadowtruth/tests/common/mod.rs"]
mod common;

mod figures;
mod frames;
mod generate;
mod papers_island;
mod plan_input;
mod plan_sweep;
mod report_outputs;
mod run_report;
mod uncertain_report;
