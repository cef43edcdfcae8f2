//! Wall-clock timing of preparation and shading.

use std::time::Instant;

pub struct Stopwatch(Instant);

impl Stopwatch {
    pub fn start() -> Self {
        Stopwatch(Instant::now())
    }

    pub fn ms(&self) -> f64 {
        self.0.elapsed().as_secs_f64() * 1e3
    }
}

/// The median of a non-empty list of milliseconds (mean of the middle two for an even count).
pub fn median_ms(samples: &[f64]) -> f64 {
    let mut s = samples.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Runs `work` `repeats` times (at least once) and returns the last result with the median of
/// its wall-clock times (ms): the one way every timing of the tool is taken.
pub fn timed_median<T>(repeats: usize, mut work: impl FnMut() -> T) -> (T, f64) {
    match try_timed_median(repeats, || Ok::<T, std::convert::Infallible>(work())) {
        Ok(done) => done,
    }
}

/// [`timed_median`] of fallible work: the first error ends the repeats.
pub fn try_timed_median<T, E>(repeats: usize, work: impl FnMut() -> Result<T, E>) -> Result<(T, f64), E> {
    try_timed_repeats(repeats, work).map(|(last, times)| (last, times.median_ms))
}

/// The wall-clock times of repeats of one piece of work: their median, least and greatest (ms).
/// The range is the noise a comparison of two medians has to clear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepeatTimes {
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
}

/// [`timed_median`] with the range of the repeats' times as well.
pub fn timed_repeats<T>(repeats: usize, mut work: impl FnMut() -> T) -> (T, RepeatTimes) {
    match try_timed_repeats(repeats, || Ok::<T, std::convert::Infallible>(work())) {
        Ok(done) => done,
    }
}

fn try_timed_repeats<T, E>(
    repeats: usize,
    mut work: impl FnMut() -> Result<T, E>,
) -> Result<(T, RepeatTimes), E> {
    let mut samples_ms = Vec::with_capacity(repeats.max(1));
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let sw = Stopwatch::start();
        last = Some(work()?);
        samples_ms.push(sw.ms());
    }
    let times = RepeatTimes {
        median_ms: median_ms(&samples_ms),
        min_ms: samples_ms.iter().copied().fold(f64::INFINITY, f64::min),
        max_ms: samples_ms.iter().copied().fold(0.0, f64::max),
    };
    Ok((last.expect("at least one repeat"), times))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timed_median_runs_at_least_once_and_keeps_the_last_result() {
        let mut runs = 0;
        let (last, ms) = timed_median(0, || {
            runs += 1;
            runs
        });
        assert_eq!((runs, last), (1, 1));
        assert!(ms >= 0.0);
        let mut runs = 0;
        assert_eq!(
            timed_median(5, || {
                runs += 1;
                runs
            })
            .0,
            5
        );
        let failed: Result<((), f64), &str> = try_timed_median(3, || Err("stop"));
        assert_eq!(failed.unwrap_err(), "stop");
    }

    #[test]
    fn repeats_report_their_range_around_the_median() {
        let mut sleep_ms = [1u64, 12, 4].into_iter();
        let ((), t) = timed_repeats(3, || {
            std::thread::sleep(std::time::Duration::from_millis(sleep_ms.next().unwrap()))
        });
        // A sleep lasts at least as asked (a loaded machine only lengthens it).
        assert!(t.min_ms >= 1.0 && t.median_ms >= 4.0 && t.max_ms >= 12.0, "{t:?}");
        assert!(t.min_ms <= t.median_ms && t.median_ms <= t.max_ms, "{t:?}");
    }

    #[test]
    fn median_of_an_even_count_is_the_mean_of_the_middle_two() {
        assert_eq!(median_ms(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median_ms(&[5.0, 1.0, 3.0]), 3.0);
        assert_eq!(median_ms(&[]), 0.0);
    }
}
