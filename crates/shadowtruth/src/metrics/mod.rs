//! Metrics: how a technique's visibility compares with the reference, pixel by pixel: hard
//! counts and rates, their attribution, soft errors of fractional output, timing.

mod attribution;
mod classify;
mod flicker;
mod soft;
mod timing;

pub use attribution::{Attribution, DEFAULT_ATTRIBUTION_RESOLUTION, LightUv, MAX_RADIUS, attribute};
pub use classify::{Counts, Rates, add_false_counts, falseness, score_hard};
pub use flicker::{FrameDecisions, count_flicker, reference_decisions, technique_decisions};
pub use soft::{SoftErrors, score_soft, thresholded};
pub use timing::{RepeatTimes, Stopwatch, median_ms, timed_median, timed_repeats, try_timed_median};
