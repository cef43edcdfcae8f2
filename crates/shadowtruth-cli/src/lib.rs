//! The `shadowtruth` command over the `shadowtruth` library: plans and their schedule, reports
//! and figures, the gate, `tune`, the papers suite, shards, scene generators and `view-export`.
//! `src/main.rs` is only a call to [`main`]; [`fuzzing`] holds the entry points of the fuzz
//! targets, so that the same code runs under `cargo fuzz` and over the committed corpus in the
//! tests.

mod commands;
mod decimals;
mod drawing;
mod escape;
mod export;
mod exports;
pub mod fuzzing;
mod gate;
mod generate;
mod option_values;
mod outputs;
mod papers;
mod plan;
mod shards;
mod sinks;
mod tune;
mod view_export;

#[cfg(test)]
mod app_tests;

/// The `shadowtruth` command: parses the arguments, runs the command and returns its exit code
/// (0 success, 1 a gate failed, 2 a usage or input error).
pub fn main() -> std::process::ExitCode {
    commands::main()
}
