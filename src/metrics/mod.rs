//! Metrics: how a technique's visibility compares with the reference, pixel by pixel.

mod attribution;
mod classify;
mod timing;

pub use attribution::{Attribution, LightUv, MAX_RADIUS, attribute};
pub use classify::{Counts, Rates, score_hard};
pub use timing::{Stopwatch, median_ms};
