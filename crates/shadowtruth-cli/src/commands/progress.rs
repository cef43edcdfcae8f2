//! The runs progress bar of `run`, `score`, `tune`'s report and `papers`, fed by the plan's
//! events, with the optional wall-clock time of each stage (`run --timing`).

use crate::plan::{Event, PlanError, Sink};
use indicatif::{ProgressBar, ProgressStyle};
use std::time::Instant;

/// The runs progress bar (hidden when `quiet`), as a sink of the plan's events: its length grows
/// with every plan (the papers suite runs several). With `timing` it also prints each stage's
/// wall-clock time.
pub(super) struct Progress(pub(super) ProgressBar, pub(super) Option<StageClock>);

/// The stage under way and when it (or, before the first, the run) started.
pub(super) struct StageClock {
    stage: String,
    started: Instant,
}

impl StageClock {
    fn new() -> Self {
        StageClock { stage: "loading and checking the scenes".into(), started: Instant::now() }
    }

    /// Prints the stage that ends and starts `next`.
    pub(super) fn next(&mut self, bar: &ProgressBar, next: &str) {
        bar.suspend(|| eprintln!("{:>9.3} s  {}", self.started.elapsed().as_secs_f64(), self.stage));
        *self = StageClock { stage: next.to_string(), started: Instant::now() };
    }
}

impl Progress {
    pub(super) fn timed(quiet: bool, timing: bool) -> Self {
        let mut progress = Progress::new(quiet);
        progress.1 = timing.then(StageClock::new);
        progress
    }

    /// Prints the last stage's time, if timed.
    pub(super) fn finish_timing(&mut self, next: &str) {
        if let Some(clock) = &mut self.1 {
            clock.next(&self.0, next);
        }
    }

    pub(super) fn new(quiet: bool) -> Self {
        let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new(0) };
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} runs, {eta} left  {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        Progress(bar, None)
    }
}

impl Sink for Progress {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        match event {
            Event::Planned { runs, .. } => self.0.inc_length(*runs as u64),
            Event::Stage(s) => {
                self.finish_timing(s);
                self.0.set_message(s.to_string())
            }
            Event::RunDone { .. } => self.0.inc(1),
            _ => {}
        }
        Ok(())
    }
}
