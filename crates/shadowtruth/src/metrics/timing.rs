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
pub fn try_timed_median<T, E>(repeats: usize, mut work: impl FnMut() -> Result<T, E>) -> Result<(T, f64), E> {
    let mut samples_ms = Vec::with_capacity(repeats.max(1));
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let sw = Stopwatch::start();
        last = Some(work()?);
        samples_ms.push(sw.ms());
    }
    Ok((last.expect("at least one repeat"), median_ms(&samples_ms)))
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
    fn median_of_an_even_count_is_the_mean_of_the_middle_two() {
        assert_eq!(median_ms(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median_ms(&[5.0, 1.0, 3.0]), 3.0);
        assert_eq!(median_ms(&[]), 0.0);
    }
}
